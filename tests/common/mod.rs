//! Helpers shared by the integration tests: a reproducible random sequence, and the oracle's
//! audit of a run's records (`tsm_contact::audit`, which shares no code with the solver).

use tsm_contact::audit::{audit, Finding, Run};
use tsm_contact::history::Topology;
use tsm_contact::scene::Scene;
use tsm_contact::solver::IncrementRecord;

/// The oracle's findings on `records` of `scene`, which follow one another from the
/// undeformed state.
#[allow(dead_code)]
pub fn findings(scene: &Scene, records: &[IncrementRecord]) -> Vec<Finding> {
    let topology = Topology::of(&scene.model);
    let ids: Vec<u32> = scene.model.nodes.iter().map(|n| n.id).collect();
    let run = Run {
        topology: &topology,
        node_ids: &ids,
        params: &scene.params,
    };
    audit(&run, None, records)
}

/// The oracle on `records` of `scene` (`findings`): panics naming every finding (a node
/// through a body, a group out of balance, a node inside an obstacle, a contact beyond the
/// friction law, a status its residual does not earn).
#[allow(dead_code)]
pub fn assert_audited(scene: &Scene, records: &[IncrementRecord]) {
    let found = findings(scene, records);
    assert!(
        found.is_empty(),
        "{} finding(s):\n{}",
        found.len(),
        found
            .iter()
            .map(|f| f.to_string())
            .collect::<Vec<_>>()
            .join("\n")
    );
}

/// A small deterministic pseudo-random sequence (xorshift) in [-1, 1), so failures are
/// reproducible.
#[allow(dead_code)]
pub struct Rng(pub u64);

#[allow(dead_code)]
impl Rng {
    /// Next value in [-1, 1).
    pub fn next(&mut self) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    }
}

/// Collect a worker's messages until `Idle` arrives after the work started (`Busy`), or time
/// runs out: the increments and the errors.
#[allow(dead_code)]
pub fn until_idle(
    w: &tsm_contact::worker::Worker,
    limit: std::time::Duration,
) -> (Vec<IncrementRecord>, Vec<String>) {
    use tsm_contact::worker::Message;
    let t0 = std::time::Instant::now();
    let (mut incs, mut errors, mut busy) = (Vec::new(), Vec::new(), false);
    while t0.elapsed() < limit {
        match w.recv_timeout(std::time::Duration::from_millis(50)) {
            Some(Message::Increment(r)) => incs.push(*r),
            Some(Message::Error(e)) => errors.push(e.to_string()),
            Some(Message::Busy) => busy = true,
            Some(Message::Idle) if busy => return (incs, errors),
            _ => {}
        }
    }
    panic!(
        "worker did not become idle within {limit:?} ({} increments so far)",
        incs.len()
    );
}
