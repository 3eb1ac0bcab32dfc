//! The rim half of the acceptance check (`rim_overlap`): no candidate node that stands off the
//! beams' axes (a pin with a radius, beams with a thickness: `Model::contact_distance`) ends nearer
//! the axis of an element it is not in contact with than its contact distance. It works on node
//! positions and rotations alone: the element's shape is bounded by its chord and the bulge its end
//! rotations allow (`Chord::bulge`), so a node is refused only where it overlaps whatever the shape
//! between the nodes. Past a free end of a body that an obstacle carried by the node touches, the
//! end's corner is left to the obstacle check: the end node's contact with the obstacle holds it
//! there. A node whose contacts hold only in some directions (a solid arc's centre,
//! `Node::reach`) is judged only where the way to the element lies within them.

use super::chord::Chord;
use super::crossing::Crossing;
use crate::solver::model::Model;
use crate::solver::report::NodeState;

/// Overlaps below this fraction of the element length, or below `ROUNDOFF_ULPS` round-off
/// units of the coordinates, are touching.
const TOUCH: f64 = 1e-9;

/// Round-off units of the largest coordinate that a distance may be off by.
const ROUNDOFF_ULPS: f64 = 64.0;

/// The first candidate pair of `pairs` (node, body) whose node ends within its contact
/// distance of an element of the body it is not in contact with (`active`: node, body and
/// element of every contact) at node states `after`, beyond the element's bulge: the node and
/// element, and the overlap in element lengths. A node in contact with a body is judged
/// against the body's elements beyond the one it rests on and its neighbours too: it touches
/// one place of it.
/// `window` gives the elements of its own body a node never touches (its self-contact window,
/// by place along the body).
pub fn rim_overlap(
    model: &Model,
    pairs: &[(usize, usize)],
    window: impl Fn(usize, usize) -> Option<(usize, usize)>,
    after: &[NodeState],
    active: &[(usize, usize, usize)],
) -> Option<Crossing> {
    for &(n, b) in pairs {
        // The place along the body of the element it rests on, if it does.
        let els = &model.bodies[b].elements;
        let touched = (active.iter().find(|a| a.0 == n && a.1 == b))
            .and_then(|a| els.iter().position(|&e| e == a.2));
        let c = [after[n][0], after[n][1]];
        let own = window(n, b);
        for (place, &e) in model.bodies[b].elements.iter().enumerate() {
            let r = model.contact_distance(n, e);
            let skip = own.is_some_and(|(lo, hi)| (lo..=hi).contains(&place));
            // Where it rests, and the neighbours, which its contact spring lets it sink into
            // at their shared node.
            let resting = touched.is_some_and(|t| t.abs_diff(place) <= 1);
            if r == 0.0 || skip || resting {
                continue;
            }
            let (p, q) = (
                model.position(model.beams[e].i),
                model.position(model.beams[e].j),
            );
            let angle0 = (q[1] - p[1]).atan2(q[0] - p[0]);
            let chord = Chord::at(model, angle0, e, after);
            let (s, h) = chord.locate(c);
            let end = |k: usize| {
                let x = after[if k == 0 {
                    model.beams[e].i
                } else {
                    model.beams[e].j
                }];
                (c[0] - x[0]).hypot(c[1] - x[1])
            };
            // Beyond an end of the element, the end node's corner; at a free end of the body
            // that an obstacle carried by the node touches, its node contact holds the corner
            // (and the obstacle check judges it).
            let held_by_node_contact = |k: usize| {
                let x = [model.beams[e].i, model.beams[e].j][k];
                let along = |f: &usize| model.beams[*f].i == x || model.beams[*f].j == x;
                let free = model.bodies[b].elements.iter().filter(|f| along(f)).count() < 2;
                free && (model.obstacles.iter())
                    .any(|o| o.pilot == Some(n) && o.nodes.binary_search(&x).is_ok())
            };
            let dist = match s {
                s if s < 0.0 && held_by_node_contact(0) => continue,
                s if s > 1.0 && held_by_node_contact(1) => continue,
                s if s < 0.0 => end(0),
                s if s > 1.0 => end(1),
                _ => h.abs(),
            };
            // A node that touches only in some directions (a solid arc's centre) overlaps
            // nothing where the way to the element's nearest point lies outside them.
            let toward = |k: usize| {
                let x = after[[model.beams[e].i, model.beams[e].j][k]];
                [x[0] - c[0], x[1] - c[1]]
            };
            let within = match (s, model.nodes[n].reach) {
                (_, None) => true,
                (s, Some(r)) if s < 0.0 => r.holds(toward(0)),
                (s, Some(r)) if s > 1.0 => r.holds(toward(1)),
                _ => chord.within_reach(model, n, h.signum()),
            };
            if !within {
                continue;
            }
            let scale = c[0]
                .abs()
                .max(c[1].abs())
                .max(chord.p[0].abs().max(chord.p[1].abs()));
            let slack = TOUCH * chord.l + ROUNDOFF_ULPS * f64::EPSILON * scale;
            let depth = r - dist - chord.bulge();
            if depth > slack {
                return Some(Crossing {
                    node: n,
                    body: b,
                    element: e,
                    depth: depth / chord.l,
                });
            }
        }
    }
    None
}
