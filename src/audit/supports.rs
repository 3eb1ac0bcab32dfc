//! The held dofs of an accepted state: every support where the model holds it (no
//! displacement from rest), every prescribed dof at the value its record gives, and every
//! node that moves with a pilot (a moving polyline's corner) displaced as its pilot is. A state
//! whose prescribed node stayed behind while its record says it moved is in equilibrium from
//! its own forces, so only this check tells it apart.

use std::collections::HashMap;

use super::geometry::dof_place;
use super::Finding;
use crate::history::Topology;
use crate::solver::IncrementRecord;

/// How far a held dof may be from where it is held: this fraction of the model's size (m, at
/// least 1) or of a radian, beyond the round-off of the recorded positions. The solver moves a
/// held dof by exactly its increments, up to the round-off of their sum, orders of magnitude
/// below.
const SLACK: f64 = 1e-9;

/// How far held dof `dof` may be from `target`: `SLACK` of the model's `size` (m, at least 1,
/// or of `target` where larger) and the round-off `roundoff` of a recorded position, or
/// `SLACK` of a radian (or of `target`) for a rotation.
fn allowed(dof: &str, target: f64, (size, roundoff): (f64, f64)) -> f64 {
    if dof == "phi" {
        SLACK * target.abs().max(1.0)
    } else {
        SLACK * size.max(target.abs()).max(1.0) + roundoff
    }
}

/// The offset of dof `dof` ("u", "v" or "phi") of the node at `slot` in `r` from rest.
fn displacement(r: &IncrementRecord, slot: usize, rest: [f64; 2], dof: &str) -> Option<f64> {
    let k = dof_place(dof)?;
    let at_rest = rest.get(k).copied().unwrap_or(0.0);
    Some(r.nodes.get(slot)?[k] - at_rest)
}

/// Every held dof of `r` off where it is held by more than `SLACK` of `size` (m) and the
/// round-off of a recorded position, `roundoff` (m; a model far from the origin records its
/// positions no finer): a support displaced, or a prescribed dof away from its recorded
/// value. Nothing where the topology does not list the prescribed dofs in the order of the
/// record's values (a history written before it did).
pub fn out_of_place(
    topology: &Topology,
    slot: &HashMap<u32, usize>,
    rest: &HashMap<u32, [f64; 2]>,
    r: &IncrementRecord,
    (size, roundoff): (f64, f64),
) -> Vec<Finding> {
    if topology.prescribed.len() != r.prescribed.len() {
        return Vec::new();
    }
    let mut found = with_their_pilots(topology, slot, rest, r, (size, roundoff));
    for (node, dof) in &topology.held {
        let (Some(&s), Some(&at_rest)) = (slot.get(node), rest.get(node)) else {
            continue;
        };
        let Some(value) = displacement(r, s, at_rest, dof) else {
            continue;
        };
        let prescribed = (topology.prescribed.iter())
            .position(|(n, d)| n == node && d == dof)
            .map(|k| r.prescribed[k]);
        let (target, what) = match prescribed {
            Some(p) => (p, "its prescribed value"),
            None => (0.0, "its support (no displacement)"),
        };
        let off = value - target;
        if off.abs() > allowed(dof, target, (size, roundoff)) {
            found.push(Finding {
                increment: r.increment,
                node: Some(*node),
                body: None,
                element: None,
                what: format!(
                    "node {node}'s {dof} is {value:.9e}, {off:.3e} off {what} {target:.9e}"
                ),
            });
        }
    }
    found
}

/// Every node of `r` that moves with a pilot (`TopologyNode::moves_with`) whose u or v is off
/// its pilot's by more than `SLACK` of `size` (m) and the round-off `roundoff`.
fn with_their_pilots(
    topology: &Topology,
    slot: &HashMap<u32, usize>,
    rest: &HashMap<u32, [f64; 2]>,
    r: &IncrementRecord,
    (size, roundoff): (f64, f64),
) -> Vec<Finding> {
    let mut found = Vec::new();
    for n in &topology.nodes {
        let Some(pilot) = n.moves_with else { continue };
        let (Some(&s), Some(&sp), Some(&rp)) =
            (slot.get(&n.id), slot.get(&pilot), rest.get(&pilot))
        else {
            continue;
        };
        for dof in ["u", "v"] {
            let (Some(own), Some(its)) = (
                displacement(r, s, [n.x, n.y], dof),
                displacement(r, sp, rp, dof),
            ) else {
                continue;
            };
            let off = own - its;
            if off.abs() > allowed(dof, its, (size, roundoff)) {
                found.push(Finding {
                    increment: r.increment,
                    node: Some(n.id),
                    body: None,
                    element: None,
                    what: format!(
                        "node {}'s {dof} is {own:.9e}, {off:.3e} off its pilot {pilot}'s {dof}, {its:.9e}",
                        n.id
                    ),
                });
            }
        }
    }
    found
}
