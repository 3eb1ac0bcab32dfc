//! Rims: no candidate node that stands off the beams' axes (its radius, its own beams' half
//! thickness and the half thickness of the body's elements, as the topology gives them) lies nearer
//! an element's axis than that distance, unless the record has it in contact with that element or a
//! neighbour. The element's shape between its nodes is bounded by its chord and a bulge from its
//! end rotations against the chord (a quarter of the length a radian, as a cubic with those end
//! slopes stays within) plus the sag of its distributed load: a node is found only where it
//! overlaps whatever the shape. Past a free end of a body that an obstacle carried by the node
//! touches, the end's corner is left to the obstacle check (the end node touches it). A node
//! with a reach (a solid arc's centre) is judged only where its way to the element lies within
//! its angles.

use std::collections::HashMap;

use super::finding::Finding;
use super::geometry::Chains;
use super::sides::within_angles;
use crate::history::Topology;
use crate::solver::IncrementRecord;

/// Overlaps below this fraction of the element length (beyond the positions' round-off) are
/// touching.
const TOUCH: f64 = 1e-9;

/// The deflection bound of an element from its chord per radian of end rotation, in element
/// lengths (a cubic with end slopes a and b stays within (|a| + |b|) l / 4 of its chord).
const BULGE_PER_RADIAN: f64 = 0.25;

/// The first node of a candidate pair in record `r` that overlaps an element of its body it
/// is not in contact with, with `sag` the load sag of each element.
pub fn overlapping(
    topology: &Topology,
    chains: &Chains,
    r: &IncrementRecord,
    sag: &dyn Fn(usize) -> f64,
) -> Option<Finding> {
    let clearance: HashMap<u32, f64> = (topology.nodes.iter())
        .filter(|n| n.clearance != 0.0)
        .map(|n| (n.id, n.clearance))
        .collect();
    let reaches: HashMap<u32, [f64; 2]> = (topology.nodes.iter())
        .filter_map(|n| Some((n.id, n.reach?)))
        .collect();
    let thick = topology.elements.iter().any(|e| e.thickness != 0.0);
    if clearance.is_empty() && !thick {
        return None;
    }
    let body_of: HashMap<&str, usize> = (topology.bodies.iter().enumerate())
        .map(|(b, body)| (body.name.as_str(), b))
        .collect();
    for pair in &topology.candidates {
        let (Some(&b), Some(&slot)) =
            (body_of.get(pair.body.as_str()), chains.slot.get(&pair.node))
        else {
            continue;
        };
        // The elements it rests on: it may touch the body's other elements only by going
        // through them.
        let on: Vec<usize> = (r.contacts.iter())
            .filter(|c| c.node == pair.node && topology.elements[c.element].body == b)
            .filter_map(|c| chains.elements[b].iter().position(|&e| e == c.element))
            .collect();
        let own = own_window(topology, chains, b, slot);
        let c = r.nodes[slot];
        let pin = clearance.get(&pair.node).copied().unwrap_or(0.0);
        for (place, &e) in chains.elements[b].iter().enumerate() {
            let el = &topology.elements[e];
            let reach = pin + 0.5 * el.thickness;
            let skip = own.is_some_and(|(lo, hi)| (lo..=hi).contains(&place));
            // Where it rests, and the neighbours, which its contact spring lets it sink into
            // at their shared node.
            let resting = on.iter().any(|&p| p.abs_diff(place) <= 1);
            if reach == 0.0 || skip || resting {
                continue;
            }
            let (a, z) = (r.nodes[chains.slot[&el.i]], r.nodes[chains.slot[&el.j]]);
            let u = [z[0] - a[0], z[1] - a[1]];
            let l = u[0].hypot(u[1]);
            let v = [c[0] - a[0], c[1] - a[1]];
            let s = (v[0] * u[0] + v[1] * u[1]) / (l * l);
            // Past a free end of the body (the first or last place of an open chain) that
            // an obstacle carried by the node touches, the end's corner is the obstacle
            // check's: the end node touches the obstacle there.
            let last = chains.elements[b].len() - 1;
            let ring = chains.nodes[b].first() == chains.nodes[b].last();
            let obstacle_holds = |end: u32| {
                (topology.obstacles.iter())
                    .any(|o| o.pilot == Some(pair.node) && o.nodes.contains(&end))
            };
            // The way from the node to the element's nearest point.
            let (dist, way) = if s < 0.0 {
                if place == 0 && !ring && obstacle_holds(el.i) {
                    continue;
                }
                (v[0].hypot(v[1]), [-v[0], -v[1]])
            } else if s > 1.0 {
                if place == last && !ring && obstacle_holds(el.j) {
                    continue;
                }
                ((c[0] - z[0]).hypot(c[1] - z[1]), [z[0] - c[0], z[1] - c[1]])
            } else {
                let h = (u[0] * v[1] - u[1] * v[0]) / l;
                (h.abs(), [h.signum() * u[1], -h.signum() * u[0]])
            };
            // A node with a reach (a solid arc's centre) touches only within its angles.
            if (reaches.get(&pair.node)).is_some_and(|&[from, to]| !within_angles(way, from, to)) {
                continue;
            }
            let chord = u[1].atan2(u[0]);
            let turn = |phi: f64| {
                let t = phi + chains.angle0[e] - chord;
                (t + std::f64::consts::PI).rem_euclid(std::f64::consts::TAU) - std::f64::consts::PI
            };
            let bulge = BULGE_PER_RADIAN * l * (turn(a[2]).abs() + turn(z[2]).abs()) + sag(e);
            let overlap = reach - dist - bulge;
            if overlap > TOUCH * l + chains.roundoff {
                return Some(Finding {
                    increment: r.increment,
                    node: Some(pair.node),
                    body: Some(pair.body.clone()),
                    element: Some(e),
                    what: format!(
                        "node {} is {overlap:.3e} m within its contact distance ({reach:.3e} m) of element {} of {} without touching it",
                        pair.node,
                        place + 1,
                        pair.body
                    ),
                });
            }
        }
    }
    None
}

/// The places along body `b` that the node in `slot` never touches when it is one of the
/// body's own nodes: its own elements and `Topology::self_window` more on either side.
fn own_window(
    topology: &Topology,
    chains: &Chains,
    b: usize,
    slot: usize,
) -> Option<(usize, usize)> {
    let k = chains.nodes[b].iter().position(|&s| s == slot)?;
    let w = topology.self_window;
    Some((k.saturating_sub(1 + w), k + w))
}
