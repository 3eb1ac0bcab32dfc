//! Branching and Undo on the app: driving a prescribed dof from the viewed increment (the
//! later increments set aside), setting a whole run aside before a change of scene or setting,
//! and bringing back what was set aside last, with the worker going on from its end.

use crate::worker::Command;

use super::branches::{end_checkpoint, events_after, SetAside, UNDO_DEPTH};
use super::retention::HISTORY_BUDGET;
use super::state::TsmApp;

impl TsmApp {
    /// Drive prescribed dof `index` to `value` (a slider or the handle). With an earlier
    /// increment viewed, the run goes on from there and the later increments are set aside.
    pub(crate) fn drive(&mut self, index: usize, value: f64) {
        if self.selected < self.last() {
            self.branch();
        }
        if let Some(t) = self.targets.get_mut(index) {
            *t = value;
        }
        self.targeting = true;
        self.send(Command::SetTarget { index, value });
    }

    /// Go on from the viewed increment: the later ones are set aside for Undo.
    pub(crate) fn branch(&mut self) {
        let k = self.selected.min(self.last());
        let Some(c) = self.history.checkpoint(k) else {
            self.status = format!(
                "increment {} has no state to go on from yet",
                self.history[k].increment
            );
            return;
        };
        if self.busy {
            self.worker.send(Command::Cancel);
        }
        let at = self.history[k].increment;
        let mut tail = self.history.split_off(k + 1);
        tail.trim_to_checkpoint();
        let events = events_after(&mut self.events, at);
        self.set_aside(SetAside::Branch { tail, events });
        self.branch_points.push(at);
        self.restore(c);
        self.status = format!("going on from increment {at}; Ctrl+Z brings back the old path");
    }

    /// Let the worker go on from `c`, skipping what it still sends of earlier work.
    pub(crate) fn restore(&mut self, c: std::sync::Arc<crate::solver::Checkpoint>) {
        self.targets = c.prescribed().to_vec();
        self.worker.send(Command::Restore(c));
        self.stale = true;
        self.live.clear();
        self.pinned = None;
    }

    /// Set the run aside before a change of scene or setting (or Reset) replaces it; nothing
    /// to set aside before its first increment.
    pub(crate) fn set_aside_run(&mut self) {
        self.error = None;
        let Some(l) = &self.loaded else { return };
        if self.last() == 0 {
            return;
        }
        if self.busy {
            self.worker.send(Command::Cancel);
        }
        let run = SetAside::Run {
            scene: Box::new(l.scene.clone()),
            history: std::mem::take(&mut self.history),
            events: std::mem::take(&mut self.events),
            selected: self.selected,
            name: self.scene_name.clone(),
            branches: std::mem::take(&mut self.branch_points),
        };
        self.set_aside(run);
        self.stale = true;
    }

    /// Keep `s` for Undo, within `UNDO_DEPTH` entries and one history budget in all.
    fn set_aside(&mut self, s: SetAside) {
        self.undo.push(s);
        while self.undo.len() > UNDO_DEPTH
            || (self.undo.len() > 1
                && self.undo.iter().map(SetAside::bytes).sum::<usize>() > HISTORY_BUDGET)
        {
            self.undo.remove(0);
        }
    }

    /// Bring back what was set aside last (Ctrl+Z): the history as it was, and the worker
    /// going on from its end.
    pub(crate) fn undo(&mut self) {
        let Some(s) = self.undo.pop() else {
            self.status = "nothing to undo".into();
            return;
        };
        if self.busy {
            self.worker.send(Command::Cancel);
        }
        self.playing = false;
        self.status = format!("brought back {}", s.describe());
        match s {
            SetAside::Branch { .. } => self.take_back(s),
            SetAside::Run {
                ref scene,
                ref name,
                ..
            } => {
                self.scene_name = name.clone();
                self.worker.send(Command::LoadScene(scene.clone()));
                self.stale = true;
                self.restoring = Some(s);
            }
        }
    }

    /// Put a set-aside history back in place (a whole run once its scene is loaded).
    pub(crate) fn take_back(&mut self, s: SetAside) {
        match s {
            SetAside::Branch { tail, events } => {
                let from = self.history.get(tail.at - 1).map_or(0, |r| r.increment);
                events_after(&mut self.events, from);
                self.events.extend(events);
                self.history.rejoin(tail);
                self.branch_points.pop();
                self.selected = self.last();
            }
            SetAside::Run {
                history,
                events,
                selected,
                branches,
                ..
            } => {
                self.history = history;
                self.events = events;
                self.selected = selected.min(self.last());
                self.branch_points = branches;
            }
        }
        if let Some(l) = &self.loaded {
            let c = end_checkpoint(&self.history, &l.checkpoint);
            self.restore(c);
        }
    }
}
