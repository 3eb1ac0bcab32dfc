//! What the campaign counts of a run: the Newton iterations of every increment number over
//! all its attempts, and the states accepted (`Count`, an `Observer`); and the quantiles of
//! the counts.

use std::collections::BTreeMap;

use crate::solver::{Event, Flow, IncrementRecord, IterationRecord, Observer};

/// Counts the Newton iterations of each increment number, every attempt included, and keeps
/// every accepted increment as it is accepted: a step that stops part way has accepted states
/// of its own, and the audit reads them too.
#[derive(Default)]
pub(super) struct Count {
    /// Newton iterations (solves) of each increment number, over all its attempts.
    pub(super) per_increment: BTreeMap<usize, usize>,
    /// The iteration number of the last record seen of each increment: an attempt numbers its
    /// iterations from 1 and records a residual again at the same number after a contact
    /// change, so a number below the last starts a new attempt.
    last: BTreeMap<usize, usize>,
    pub(super) accepted: Vec<IncrementRecord>,
}

impl Count {
    /// The Newton iterations of each of `records`, its failed attempts included (its own count
    /// where none was seen).
    pub(super) fn iterations_of(&self, records: &[IncrementRecord]) -> Vec<usize> {
        (records.iter())
            .map(|r| (self.per_increment.get(&r.increment).copied()).unwrap_or(r.iterations))
            .collect()
    }
}

impl Observer for Count {
    fn iteration(&mut self, r: &IterationRecord) -> Flow {
        let last = self.last.insert(r.increment, r.iteration).unwrap_or(0);
        let solves = if r.iteration < last {
            r.iteration
        } else {
            r.iteration - last
        };
        *self.per_increment.entry(r.increment).or_default() += solves;
        Flow::Continue
    }

    fn event(&mut self, e: &Event) {
        // A cut-back starts a new attempt, numbered from 1 again.
        if let Event::CutBack { increment, .. } = e {
            self.last.remove(increment);
        }
    }

    fn increment(&mut self, r: &IncrementRecord) -> Flow {
        self.accepted.push(r.clone());
        Flow::Continue
    }
}

/// The `q`-quantile (0 to 1) of sorted `v` (0 for none).
fn quantile(v: &[usize], q: f64) -> usize {
    match v.len() {
        0 => 0,
        n => v[((q * (n - 1) as f64).round() as usize).min(n - 1)],
    }
}

/// The median, 99th percentile and largest of counts `v` (0 for none), as the report gives
/// them.
pub(super) fn spread(mut v: Vec<usize>) -> (usize, usize, usize) {
    v.sort_unstable();
    let largest = v.last().copied().unwrap_or(0);
    (quantile(&v, 0.5), quantile(&v, 0.99), largest)
}
