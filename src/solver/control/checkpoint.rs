//! Checkpoints of accepted states: everything a run carries from one increment to the next
//! (the converged `State` and the crossing check's memory), so that a run can go on from any
//! accepted increment exactly as it would have from there, as the app does to branch a history.
//! [`Solver::checkpoint`] takes one and [`Solver::restore`] goes on from one.

use crate::solver::acceptance::CrossingMemory;
use crate::solver::state::State;

/// An accepted state to go on from (`Solver::checkpoint`, `Solver::restore`).
#[derive(Clone, Debug)]
pub struct Checkpoint {
    pub(super) state: State,
    pub(super) crossing: CrossingMemory,
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

    /// The load factor at this state (the first load group's).
    pub fn load_factor(&self) -> f64 {
        self.state.load_factors[0]
    }

    /// The load factors at this state, one per load group.
    pub fn load_factors(&self) -> &[f64] {
        &self.state.load_factors
    }

    /// The steps of the load path completed at this state.
    pub fn path_step(&self) -> usize {
        self.state.path_step
    }

    /// Bytes held (an estimate, for memory budgets).
    pub fn bytes(&self) -> usize {
        let s = &self.state;
        let arc = s.arc.last.as_ref().map_or(0, Vec::len);
        (s.d.len() + s.residue.len() + s.prescribed.len() + s.load_factors.len() + arc) * 8
            + s.contacts.beams.active.len() * 32
            + self.crossing.bytes()
            + std::mem::size_of::<Checkpoint>()
    }
}
