//! How much of a run's history the app holds in memory: every increment record until they
//! take `HISTORY_BUDGET` bytes, then every second one (then every fourth, ...), evenly over the
//! run, always with the undeformed state and the latest. A run of any length then fits; `solve --json` and the
//! history export of the kept records are the places for every increment.

use std::ops::Deref;
use std::sync::Arc;

use crate::solver::{Checkpoint, IncrementRecord};

/// The memory the app gives the increment records of one run.
pub const HISTORY_BUDGET: usize = 512 << 20;

/// The converged states the app shows: `[0]` is the undeformed state, then the increments kept.
#[derive(Clone, Debug)]
pub struct KeptHistory {
    records: Vec<IncrementRecord>,
    /// The place of each kept record in the run (0: the undeformed state).
    places: Vec<usize>,
    /// The state to go on from after each kept record, once the worker sent it.
    checkpoints: Vec<Option<Arc<Checkpoint>>>,
    bytes: usize,
    budget: usize,
    /// Records kept: those whose place is a multiple of this, and the latest.
    stride: usize,
    /// Records seen over the run.
    seen: usize,
}

impl Deref for KeptHistory {
    type Target = [IncrementRecord];

    fn deref(&self) -> &[IncrementRecord] {
        &self.records
    }
}

impl Default for KeptHistory {
    fn default() -> Self {
        KeptHistory::with_budget(HISTORY_BUDGET)
    }
}

impl KeptHistory {
    /// An empty history held to `budget` bytes.
    pub fn with_budget(budget: usize) -> KeptHistory {
        KeptHistory {
            records: Vec::new(),
            places: Vec::new(),
            checkpoints: Vec::new(),
            bytes: 0,
            budget,
            stride: 1,
            seen: 0,
        }
    }

    /// Start again from the undeformed state `initial`.
    pub fn reset(&mut self, initial: IncrementRecord) {
        *self = KeptHistory::with_budget(self.budget);
        self.push(initial);
    }

    /// Add the latest record. The one before it stays only if its place is a multiple of the
    /// stride; past the budget the stride doubles and the records off it are dropped. Returns
    /// whether the stride doubled.
    pub fn push(&mut self, r: IncrementRecord) -> bool {
        if let Some(&place) = self.places.last() {
            if place % self.stride != 0 {
                self.places.pop();
                let dropped = self.records.pop().expect("a record per place");
                self.bytes -= record_bytes(&dropped);
                let c = self.checkpoints.pop().expect("a checkpoint slot per place");
                self.bytes -= c.map_or(0, |c| c.bytes());
            }
        }
        self.bytes += record_bytes(&r);
        self.records.push(r);
        self.checkpoints.push(None);
        self.places.push(self.seen);
        self.seen += 1;
        if self.bytes <= self.budget || self.records.len() < 3 {
            return false;
        }
        self.stride *= 2;
        let (stride, last) = (self.stride, self.seen - 1);
        let keep: Vec<bool> = (self.places.iter())
            .map(|&p| p % stride == 0 || p == last)
            .collect();
        let mut k = 0;
        self.records.retain(|_| {
            k += 1;
            keep[k - 1]
        });
        let mut k = 0;
        self.checkpoints.retain(|_| {
            k += 1;
            keep[k - 1]
        });
        self.places.retain(|&p| p % stride == 0 || p == last);
        self.count_bytes();
        true
    }

    fn count_bytes(&mut self) {
        self.bytes = bytes_of(&self.records, &self.checkpoints);
    }

    /// Keep `c` as the state to go on from after the kept record of its increment (dropped if
    /// that record is not kept).
    pub fn attach(&mut self, c: Arc<Checkpoint>) {
        let at = self
            .records
            .iter()
            .rposition(|r| r.increment == c.increment());
        if let Some(k) = at {
            self.bytes += c.bytes();
            if let Some(old) = self.checkpoints[k].replace(c) {
                self.bytes -= old.bytes();
            }
        }
    }

    /// The state to go on from after kept record `k`, if the worker sent it.
    pub fn checkpoint(&self, k: usize) -> Option<Arc<Checkpoint>> {
        self.checkpoints.get(k).cloned().flatten()
    }

    /// Set aside the kept records after the first `len` (the run goes on from record
    /// `len - 1`); `rejoin` puts them back.
    pub fn split_off(&mut self, len: usize) -> Tail {
        let len = len.clamp(1, self.records.len().max(1));
        let tail = Tail {
            at: len,
            records: self.records.split_off(len),
            places: self.places.split_off(len),
            checkpoints: self.checkpoints.split_off(len),
            stride: self.stride,
            seen: self.seen,
        };
        self.seen = self.places.last().map_or(0, |p| p + 1);
        self.count_bytes();
        tail
    }

    /// Put a set-aside tail back in place of the records after its split point, and return
    /// those (the branch it replaces) as a tail in turn.
    pub fn rejoin(&mut self, tail: Tail) -> Tail {
        let replaced = self.split_off(tail.at);
        self.records.extend(tail.records);
        self.places.extend(tail.places);
        self.checkpoints.extend(tail.checkpoints);
        self.stride = tail.stride;
        self.seen = tail.seen;
        self.count_bytes();
        replaced
    }

    /// The bytes the kept records and their checkpoints take.
    pub fn bytes(&self) -> usize {
        self.bytes
    }

    /// Every how many records of the run one is kept (1: all of them so far).
    pub fn stride(&self) -> usize {
        self.stride
    }

    /// Records dropped over the run to stay within the budget.
    pub fn dropped(&self) -> usize {
        self.seen - self.records.len()
    }

    /// The index of the last kept record whose increment is at most `increment`.
    pub fn at_or_before(&self, increment: usize) -> usize {
        self.records
            .partition_point(|r| r.increment <= increment)
            .saturating_sub(1)
    }
}

/// Kept records set aside from a history ([`KeptHistory::split_off`]), with what the history
/// needs to take them back.
#[derive(Clone, Debug)]
pub struct Tail {
    /// How many records came before them.
    pub at: usize,
    records: Vec<IncrementRecord>,
    places: Vec<usize>,
    checkpoints: Vec<Option<Arc<Checkpoint>>>,
    stride: usize,
    seen: usize,
}

impl Tail {
    /// The records set aside.
    pub fn records(&self) -> &[IncrementRecord] {
        &self.records
    }

    /// The bytes the records and their checkpoints take.
    pub fn bytes(&self) -> usize {
        bytes_of(&self.records, &self.checkpoints)
    }

    /// Drop the records at the end that have no checkpoint yet (the worker had not sent it when
    /// they were set aside): a run brought back goes on from the end of what it shows.
    pub fn trim_to_checkpoint(&mut self) {
        while self.checkpoints.last().is_some_and(Option::is_none) {
            self.checkpoints.pop();
            self.records.pop();
            self.places.pop();
        }
    }
}

/// The memory records and their checkpoints take.
fn bytes_of(records: &[IncrementRecord], checkpoints: &[Option<Arc<Checkpoint>>]) -> usize {
    records.iter().map(record_bytes).sum::<usize>()
        + (checkpoints.iter().flatten())
            .map(|c| c.bytes())
            .sum::<usize>()
}

/// The memory a record takes (its vectors' contents; the residual records included).
pub fn record_bytes(r: &IncrementRecord) -> usize {
    use std::mem::size_of_val;
    size_of_val(r)
        + size_of_val(r.nodes.as_slice())
        + size_of_val(r.element_forces.as_slice())
        + size_of_val(r.prescribed.as_slice())
        + size_of_val(r.residuals.as_slice())
        + size_of_val(r.reactions.as_slice())
        + size_of_val(r.contacts.as_slice())
        + size_of_val(r.events.as_slice())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn record(increment: usize, nodes: usize) -> IncrementRecord {
        IncrementRecord {
            increment,
            prescribed: Vec::new(),
            load_factor: 0.0,
            load_factors: Vec::new(),
            stage: None,
            partial: false,
            iterations: 1,
            iterations_8_orders: None,
            relative_residual: 0.0,
            reference: 1.0,
            roundoff_floor: 0.0,
            status: Default::default(),
            cutbacks: 0,
            residuals: Vec::new(),
            nodes: vec![[0.0; 3]; nodes],
            element_forces: Vec::new(),
            reactions: Vec::new(),
            contacts: Vec::new(),
            obstacle_contacts: Vec::new(),
            max_penetration: 0.0,
            events: Vec::new(),
            seconds: 0.0,
        }
    }

    /// A run of 10,000 records of about 2.6 kB each (100 nodes) held to 64 kB: the kept
    /// records stay within the budget plus one record, the undeformed state and the latest are
    /// kept, the kept increments are evenly spread over the whole run (every gap but the last
    /// the same), and the dropped count adds up.
    #[test]
    fn a_long_run_is_thinned_to_the_budget_keeping_its_ends() {
        let size = record_bytes(&record(0, 100));
        let mut h = KeptHistory::with_budget(64 << 10);
        h.reset(record(0, 100));
        for k in 1..=10_000 {
            h.push(record(k, 100));
            assert!(h.iter().map(record_bytes).sum::<usize>() <= (64 << 10) + size);
        }
        assert_eq!(h[0].increment, 0);
        assert_eq!(h.last().unwrap().increment, 10_000);
        assert_eq!(h.len() + h.dropped(), 10_001);
        let gaps: Vec<usize> = h[..h.len() - 1]
            .windows(2)
            .map(|w| w[1].increment - w[0].increment)
            .collect();
        let (lo, hi) = (gaps.iter().min().unwrap(), gaps.iter().max().unwrap());
        assert!(*lo > 0 && hi == lo, "gaps from {lo} to {hi}");
        assert!(h.len() > 10, "{} kept", h.len());
        assert_eq!(
            h.at_or_before(5_000),
            h.partition_point(|r| r.increment <= 5_000) - 1
        );
    }
}
