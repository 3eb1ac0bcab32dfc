//! Branching, Undo and Redo on the app: driving a prescribed dof from the viewed increment (the
//! later increments set aside), setting a whole run aside before a change of scene or setting,
//! bringing back what was set aside last (Undo) with the worker going on from its end, and
//! what Undo replaced (Redo).

use crate::worker::Command;

use super::branches::{end_checkpoint, events_after, SetAside, UNDO_DEPTH};
use super::retention::HISTORY_BUDGET;
use super::state::TsmApp;

impl TsmApp {
    /// Drive prescribed dof `index` to `value` (a slider or the handle). With an earlier
    /// increment viewed, the run goes on from there and the later increments are set aside.
    pub(crate) fn drive(&mut self, index: usize, value: f64) {
        if self.playback.selected < self.last() {
            self.branch();
        }
        if let Some(t) = self.study.targets.get_mut(index) {
            *t = value;
        }
        self.study.targeting = true;
        self.send(Command::SetTarget { index, value });
    }

    /// Go on from the viewed increment: the later ones are set aside for Undo.
    pub(crate) fn branch(&mut self) {
        let k = self.playback.selected.min(self.last());
        let Some(c) = self.study.history.checkpoint(k) else {
            self.notices.status = format!(
                "increment {} has no state to go on from yet",
                self.study.history[k].increment
            );
            return;
        };
        if self.study.busy {
            self.worker.send(Command::Cancel);
        }
        let at = self.study.history[k].increment;
        let mut tail = self.study.history.split_off(k + 1);
        tail.trim_to_checkpoint();
        let events = events_after(&mut self.study.events, at);
        self.set_aside(SetAside::Branch {
            tail,
            events,
            branched: false,
        });
        self.study.branch_points.push(at);
        self.restore(c);
        self.notices.status =
            format!("going on from increment {at}; Ctrl+Z brings back the old path");
    }

    /// Let the worker go on from `c`, skipping what it still sends of earlier work.
    pub(crate) fn restore(&mut self, c: std::sync::Arc<crate::solver::Checkpoint>) {
        self.study.targets = c.prescribed().to_vec();
        self.worker.send(Command::Restore(c));
        self.study.stale = true;
        self.study.live.clear();
        self.look.pinned = None;
    }

    /// Set the run aside before a change of scene or setting (or Reset) replaces it; nothing
    /// to set aside before its first increment.
    pub(crate) fn set_aside_run(&mut self) {
        self.notices.error = None;
        if self.last() == 0 {
            return;
        }
        if let Some(run) = self.take_run() {
            self.set_aside(run);
        }
    }

    /// The current run, taken out of the app to be set aside (the worker's messages of it
    /// skipped from now on).
    fn take_run(&mut self) -> Option<SetAside> {
        let l = self.study.loaded.as_ref()?;
        if self.study.busy {
            self.worker.send(Command::Cancel);
        }
        self.study.stale = true;
        Some(SetAside::Run {
            scene: Box::new(l.scene.clone()),
            history: std::mem::take(&mut self.study.history),
            events: std::mem::take(&mut self.study.events),
            selected: self.playback.selected,
            name: self.study.scene_name.clone(),
            branches: std::mem::take(&mut self.study.branch_points),
        })
    }

    /// Keep `s` for Undo (a new branch or change: nothing is left to redo).
    fn set_aside(&mut self, s: SetAside) {
        self.study.redo.clear();
        keep(&mut self.study.undo, s);
    }

    /// Bring back what was set aside last (Ctrl+Z): the history as it was, and the worker
    /// going on from its end; what it replaces is kept for Redo.
    pub(crate) fn undo(&mut self) {
        self.swap(true);
    }

    /// Bring back what Undo replaced (Ctrl+Y), keeping what it replaces for Undo.
    pub(crate) fn redo(&mut self) {
        self.swap(false);
    }

    /// Bring back the newest entry of the undo (`undo`) or the redo stack, and keep what it
    /// replaces on the other.
    fn swap(&mut self, undo: bool) {
        let from = if undo {
            &mut self.study.undo
        } else {
            &mut self.study.redo
        };
        let Some(s) = from.pop() else {
            self.notices.status = format!("nothing to {}", if undo { "undo" } else { "redo" });
            return;
        };
        if self.study.busy {
            self.worker.send(Command::Cancel);
        }
        self.playback.playing = false;
        self.notices.status = format!("brought back {}", s.describe());
        let replaced = match s {
            SetAside::Branch { .. } => self.take_back(s),
            SetAside::Run {
                ref scene,
                ref name,
                ..
            } => {
                let current = self.take_run();
                self.study.scene_name = name.clone();
                self.worker.send(Command::LoadScene(scene.clone()));
                self.study.stale = true;
                self.study.restoring = Some(s);
                current
            }
        };
        if let Some(r) = replaced {
            keep(
                if undo {
                    &mut self.study.redo
                } else {
                    &mut self.study.undo
                },
                r,
            );
        }
    }

    /// Put a set-aside history back in place (a whole run once its scene is loaded), and
    /// return what a branch's increments replace.
    pub(crate) fn take_back(&mut self, s: SetAside) -> Option<SetAside> {
        let replaced = match s {
            SetAside::Branch {
                tail,
                events,
                branched,
            } => {
                let at = tail.at;
                let from = self.study.history.get(at - 1).map_or(0, |r| r.increment);
                let old_events = events_after(&mut self.study.events, from);
                self.study.events.extend(events);
                let mut old = self.study.history.rejoin(tail);
                old.trim_to_checkpoint();
                if branched {
                    self.study.branch_points.push(from);
                } else {
                    self.study.branch_points.pop();
                }
                self.playback.selected = self.last();
                Some(SetAside::Branch {
                    tail: old,
                    events: old_events,
                    branched: !branched,
                })
            }
            SetAside::Run {
                history,
                events,
                selected,
                branches,
                ..
            } => {
                self.study.history = history;
                self.study.events = events;
                self.playback.selected = selected.min(self.last());
                self.study.branch_points = branches;
                None
            }
        };
        if let Some(l) = &self.study.loaded {
            let c = end_checkpoint(&self.study.history, &l.checkpoint);
            self.restore(c);
        }
        replaced
    }
}

/// Push `s` on an undo or redo stack, within `UNDO_DEPTH` entries and one history budget in
/// all (the oldest go first).
fn keep(stack: &mut Vec<SetAside>, s: SetAside) {
    stack.push(s);
    while stack.len() > UNDO_DEPTH
        || (stack.len() > 1 && stack.iter().map(SetAside::bytes).sum::<usize>() > HISTORY_BUDGET)
    {
        stack.remove(0);
    }
}
