//! The one guard against cycling that every contact stage (beam contacts, obstacle contacts,
//! friction modes) keeps for an attempt: the states its converged passes have reached, and,
//! once one comes back, the switch to one change a pass (Murty's least-index rule: on a
//! linear complementarity problem with a P-matrix, one violation at a time cannot cycle).

use std::collections::HashSet;
use std::hash::Hash;

/// The states `K` a stage's passes have reached within an attempt.
#[derive(Clone, Debug)]
pub(crate) struct CycleGuard<K> {
    seen: HashSet<K>,
    one_at_a_time: bool,
}

impl<K> Default for CycleGuard<K> {
    fn default() -> Self {
        CycleGuard {
            seen: HashSet::new(),
            one_at_a_time: false,
        }
    }
}

impl<K: Eq + Hash> CycleGuard<K> {
    /// Forget the passes of a previous attempt.
    pub(crate) fn clear(&mut self) {
        self.seen.clear();
        self.one_at_a_time = false;
    }

    /// Record the state a pass that changed something has reached: a state met before within
    /// the attempt means the passes cycle, and from then on each makes one change.
    pub(crate) fn reached(&mut self, state: K) {
        if !self.seen.insert(state) {
            self.one_at_a_time = true;
        }
    }

    /// Whether the passes make one change each (a state came back within the attempt).
    pub(crate) fn one_at_a_time(&self) -> bool {
        self.one_at_a_time
    }
}
