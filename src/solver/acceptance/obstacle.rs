//! The obstacle half of the acceptance check (`inside_obstacle`): no candidate node ends
//! inside a rigid obstacle by more than the obstacle tolerance, whether it is in contact or
//! not, nor passed through one on its way from a clear place to a clear place. It works on
//! node positions alone and measures depths with the shape's ray count ([`Shape::depth_inside`](crate::solver::model::Shape::depth_inside):
//! not the nearest point, as the contact code does), so that neither a bug in the active set
//! nor one in the gap can hide itself.

use crate::solver::model::Model;
use crate::solver::report::NodeState;

/// A node found inside an obstacle.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ObstacleCrossing {
    /// Node index.
    pub node: usize,
    /// Obstacle index.
    pub obstacle: usize,
    /// How far inside (m).
    pub depth: f64,
}

/// The first candidate (node, obstacle) pair of `model` whose node ends more than `tol` inside
/// the obstacle at node states `after`, or passed through it since `before` (the path of the
/// node relative to the obstacle, a straight segment, runs inside it deeper than `tol` between
/// two free ends: a node that jumped across a small roller in one increment). States are in the
/// scene's coordinates; `origin` is where the model's own coordinates are measured from; each
/// obstacle moves with its pilot node.
pub fn inside_obstacle(
    model: &Model,
    origin: [f64; 2],
    (before, after): (&[NodeState], &[NodeState]),
    tol: f64,
) -> Option<ObstacleCrossing> {
    for (o, ob) in model.obstacles.iter().enumerate() {
        let (t0, t1) = (
            pilot_offset(model, ob.pilot, origin, before),
            pilot_offset(model, ob.pilot, origin, after),
        );
        // Beyond the tolerance by more than the round-off of the positions and the shape's
        // coordinates (64 units of the largest), which the contact code's gap and this
        // check's depth may each be off by.
        let scale = ob.shape.scale(t1);
        for &n in &ob.nodes {
            let x = [after[n][0] - t1[0], after[n][1] - t1[1]];
            let x0 = [before[n][0] - t0[0], before[n][1] - t0[1]];
            let slack = 64.0 * f64::EPSILON * (scale + x[0].abs().max(x[1].abs()));
            let end = ob.shape.depth_inside(x);
            // A node touching at either end may have slid along the obstacle, its straight
            // path a chord through it: only a path between two clear ends is looked at.
            let clear = |p: [f64; 2]| ob.shape.clearance(p) > tol + slack;
            let depth = if clear(x0) && clear(x) {
                end.max(ob.shape.depth_on_path(x0, x))
            } else {
                end
            };
            if depth > tol + slack {
                return Some(ObstacleCrossing {
                    node: n,
                    obstacle: o,
                    depth,
                });
            }
        }
    }
    None
}

/// How far an obstacle has moved in state `states`: its pilot node's displacement, or
/// `origin` for an obstacle without one.
pub(super) fn pilot_offset(
    model: &Model,
    pilot: Option<usize>,
    origin: [f64; 2],
    states: &[NodeState],
) -> [f64; 2] {
    match pilot {
        Some(p) => [
            states[p][0] - model.nodes[p].x,
            states[p][1] - model.nodes[p].y,
        ],
        None => origin,
    }
}
