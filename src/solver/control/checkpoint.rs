//! Checkpoints of accepted states: everything a run carries from one increment to the next
//! (the converged `State` and the crossing check's memory), so that a run can go on from any
//! accepted increment exactly as it would have from there, as the app does to branch a history.

use crate::solver::acceptance::CrossingMemory;
use crate::solver::state::State;

use super::solver::Solver;

/// An accepted state to go on from (`Solver::checkpoint`, `Solver::restore`).
#[derive(Clone, Debug)]
pub struct Checkpoint {
    state: State,
    crossing: CrossingMemory,
}

impl Checkpoint {
    /// The number of the increment it was taken after (0: the undeformed state).
    pub fn increment(&self) -> usize {
        self.state.increment
    }

    /// The prescribed values at this state.
    pub fn prescribed(&self) -> &[f64] {
        &self.state.prescribed
    }

    /// The load factor at this state.
    pub fn load_factor(&self) -> f64 {
        self.state.load_factor
    }

    /// Bytes held (an estimate, for memory budgets).
    pub fn bytes(&self) -> usize {
        let s = &self.state;
        let arc = s.arc.last.as_ref().map_or(0, Vec::len);
        (s.d.len() + s.prescribed.len() + arc) * 8
            + s.contacts.active.len() * 32
            + self.crossing.bytes()
            + std::mem::size_of::<Checkpoint>()
    }
}

impl Solver {
    /// The accepted state as it is now.
    pub fn checkpoint(&self) -> Checkpoint {
        Checkpoint {
            state: self.state.clone(),
            crossing: self.crossing.memory(),
        }
    }

    /// Go on from `checkpoint` (taken from this solver, or one built from the same model and
    /// parameters): the next increment is solved exactly as it was after the checkpoint.
    pub fn restore(&mut self, checkpoint: &Checkpoint) {
        self.state = checkpoint.state.clone();
        if !self.crossing.is_empty() {
            self.crossing.restore(&checkpoint.crossing);
        }
        // The kept assembly belongs to another state of the same number, perhaps.
        self.work.converged_assembly.0.borrow_mut().take();
    }

    /// Keep a checkpoint of every accepted increment from now on (or stop keeping them), for
    /// `take_checkpoints`.
    pub fn keep_checkpoints(&mut self, on: bool) {
        self.kept = on.then(Vec::new);
    }

    /// The checkpoints kept since the last call, oldest first.
    pub fn take_checkpoints(&mut self) -> Vec<Checkpoint> {
        self.kept.as_mut().map(std::mem::take).unwrap_or_default()
    }

    /// Keep a checkpoint of the state just accepted, if asked to (`keep_checkpoints`).
    pub(crate) fn keep_checkpoint(&mut self) {
        if self.kept.is_some() {
            let c = self.checkpoint();
            self.kept.as_mut().expect("kept").push(c);
        }
    }
}
