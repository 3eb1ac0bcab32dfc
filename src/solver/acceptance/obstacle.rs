//! The obstacle half of the acceptance check (`inside_obstacle`): no candidate node ends
//! inside a rigid obstacle by more than the obstacle tolerance, whether it is in contact or
//! not, nor passed through one on its way from a clear place to a clear place. It works on node positions alone and finds the side of a polyline by counting where a
//! ray crosses it (not by the nearest point, as the contact code does), so that neither a bug
//! in the active set nor one in the gap can hide itself.

use crate::solver::model::{Model, Shape};
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
        let scale = shape_scale(&ob.shape, t1);
        for &n in &ob.nodes {
            let x = [after[n][0] - t1[0], after[n][1] - t1[1]];
            let x0 = [before[n][0] - t0[0], before[n][1] - t0[1]];
            let slack = 64.0 * f64::EPSILON * (scale + x[0].abs().max(x[1].abs()));
            let end = depth_inside(&ob.shape, x);
            // A node touching at either end may have slid along the obstacle, its straight
            // path a chord through it: only a path between two clear ends is looked at.
            let clear = |p: [f64; 2]| clearance(&ob.shape, p) > tol + slack;
            let depth = if clear(x0) && clear(x) {
                end.max(depth_on_path(&ob.shape, x0, x))
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

/// How far outside the shape point `x` lies (m; 0 or less where it is inside or on it): the
/// distance to the curve on the free side (an arc's nodes outside its angles are clear).
fn clearance(shape: &Shape, x: [f64; 2]) -> f64 {
    match shape {
        Shape::Arc {
            centre, from, to, ..
        } if !within_angles(*centre, *from, *to, x) => f64::INFINITY,
        Shape::Line { .. } | Shape::Circle { .. } | Shape::Arc { .. } => -depth_inside(shape, x),
        Shape::Polyline { points } => {
            if polyline_depth(points, x) > 0.0 {
                return 0.0;
            }
            (points.windows(2))
                .map(|w| segment_distance(w[0], w[1], x))
                .fold(f64::INFINITY, f64::min)
        }
    }
}

/// The distance from point `x` to the segment from `a` to `b`.
fn segment_distance(a: [f64; 2], b: [f64; 2], x: [f64; 2]) -> f64 {
    let ab = sub(b, a);
    let len2 = ab[0] * ab[0] + ab[1] * ab[1];
    let t = (((x[0] - a[0]) * ab[0] + (x[1] - a[1]) * ab[1]) / len2).clamp(0.0, 1.0);
    (x[0] - a[0] - t * ab[0]).hypot(x[1] - a[1] - t * ab[1])
}

/// Points along a path at which a polyline's depth is looked at (`depth_on_path`).
const PATH_SAMPLES: usize = 32;

/// How deep inside the shape the straight path from `a` to `b` runs: about a circle or an
/// arc, the radius less the path's distance from the centre where the nearest point lies
/// within the path (and, for an arc, within its angles); for a polyline, the deepest of points
/// along the path; a line's solid side is a half-plane, which a straight path between free ends
/// cannot enter.
fn depth_on_path(shape: &Shape, a: [f64; 2], b: [f64; 2]) -> f64 {
    match shape {
        Shape::Line { .. } => 0.0,
        Shape::Circle { hollow: true, .. } | Shape::Arc { hollow: true, .. } => 0.0,
        Shape::Circle { centre, .. } | Shape::Arc { centre, .. } => {
            let ab = sub(b, a);
            let len2 = ab[0] * ab[0] + ab[1] * ab[1];
            if len2 == 0.0 {
                return 0.0;
            }
            let t =
                (((centre[0] - a[0]) * ab[0] + (centre[1] - a[1]) * ab[1]) / len2).clamp(0.0, 1.0);
            depth_inside(shape, [a[0] + t * ab[0], a[1] + t * ab[1]])
        }
        Shape::Polyline { .. } => (1..PATH_SAMPLES)
            .map(|k| {
                let t = k as f64 / PATH_SAMPLES as f64;
                depth_inside(shape, [a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])])
            })
            .fold(0.0, f64::max),
    }
}

/// The largest coordinate of the shape, moved by `t` (m).
fn shape_scale(shape: &Shape, t: [f64; 2]) -> f64 {
    let big = |p: &[f64; 2]| (p[0] + t[0]).abs().max((p[1] + t[1]).abs());
    match shape {
        Shape::Line { from, to } => big(from).max(big(to)),
        Shape::Polyline { points } => points.iter().map(big).fold(0.0, f64::max),
        Shape::Circle { centre, radius, .. } | Shape::Arc { centre, radius, .. } => {
            big(centre) + radius
        }
    }
    .max(f64::MIN_POSITIVE)
}

fn sub(a: [f64; 2], b: [f64; 2]) -> [f64; 2] {
    [a[0] - b[0], a[1] - b[1]]
}

fn cross(a: [f64; 2], b: [f64; 2]) -> f64 {
    a[0] * b[1] - a[1] * b[0]
}

/// How far inside the shape point `x` lies (m; 0 or less where it is free).
fn depth_inside(shape: &Shape, x: [f64; 2]) -> f64 {
    match shape {
        Shape::Line { from, to } => {
            let t = sub(*to, *from);
            -cross(t, sub(x, *from)) / t[0].hypot(t[1])
        }
        Shape::Circle {
            centre,
            radius,
            hollow,
        } => radial_depth(*centre, *radius, *hollow, x),
        Shape::Arc {
            centre,
            radius,
            from,
            to,
            hollow,
        } => {
            if within_angles(*centre, *from, *to, x) {
                radial_depth(*centre, *radius, *hollow, x)
            } else {
                0.0
            }
        }
        Shape::Polyline { points } => polyline_depth(points, x),
    }
}

/// Whether point `x`'s polar angle about `centre` lies from `from` counter-clockwise to `to`.
fn within_angles(centre: [f64; 2], from: f64, to: f64, x: [f64; 2]) -> bool {
    let r = sub(x, centre);
    let tau = std::f64::consts::TAU;
    (r[1].atan2(r[0]) - from).rem_euclid(tau) <= (to - from).rem_euclid(tau)
}

/// How far inside a disk (or outside a hole) point `x` lies.
fn radial_depth(centre: [f64; 2], radius: f64, hollow: bool, x: [f64; 2]) -> f64 {
    let rho = (x[0] - centre[0]).hypot(x[1] - centre[1]);
    if hollow {
        rho - radius
    } else {
        radius - rho
    }
}

/// How far inside a polyline (continued along its end segments) point `x` lies: its distance
/// to the curve where a ray from it towards the free side's far field crosses the curve an
/// odd number of times, else 0.
fn polyline_depth(points: &[[f64; 2]], x: [f64; 2]) -> f64 {
    let m = points.len();
    let unit = |v: [f64; 2]| {
        let l = v[0].hypot(v[1]);
        [v[0] / l, v[1] / l]
    };
    let first = unit(sub(points[1], points[0]));
    let last = unit(sub(points[m - 1], points[m - 2]));
    // Far away the curve is its two end rays: outward along -first and along last. The free
    // side's far field lies counter-clockwise from `last` to `-first`; the ray goes down its
    // middle (turned a little off it, so that it does not run along a piece).
    let a0 = last[1].atan2(last[0]);
    let sweep = ((-first[1]).atan2(-first[0]) - a0).rem_euclid(std::f64::consts::TAU);
    let sweep = if sweep == 0.0 {
        std::f64::consts::TAU
    } else {
        sweep
    };
    let a = a0 + 0.5 * sweep + 1e-3;
    let v = [a.cos(), a.sin()];
    // The pieces: the segments, then the end rays (as segments long enough to reach past x).
    let span = points
        .iter()
        .map(|p| (p[0] - x[0]).hypot(p[1] - x[1]))
        .fold(0.0, f64::max);
    let reach = 4.0 * span + 1.0;
    let mut pieces: Vec<([f64; 2], [f64; 2])> = points.windows(2).map(|w| (w[0], w[1])).collect();
    let p0 = points[0];
    pieces.push(([p0[0] - reach * first[0], p0[1] - reach * first[1]], p0));
    let pm = points[m - 1];
    pieces.push((pm, [pm[0] + reach * last[0], pm[1] + reach * last[1]]));
    let mut crossings = 0;
    let mut distance = f64::MAX;
    for &(a, b) in &pieces {
        let ab = sub(b, a);
        let len2 = ab[0] * ab[0] + ab[1] * ab[1];
        let t = ((x[0] - a[0]) * ab[0] + (x[1] - a[1]) * ab[1]) / len2;
        let t = t.clamp(0.0, 1.0);
        distance = distance.min((x[0] - a[0] - t * ab[0]).hypot(x[1] - a[1] - t * ab[1]));
        // The ray x + s v (s > 0) meets the piece a + u ab (0 <= u < 1).
        let den = cross(v, ab);
        if den != 0.0 {
            let ax = sub(a, x);
            let s = cross(ax, ab) / den;
            let u = cross(ax, v) / den;
            if s > 0.0 && (0.0..1.0).contains(&u) {
                crossings += 1;
            }
        }
    }
    if crossings % 2 == 1 {
        distance
    } else {
        0.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The ray count agrees with the sides drawn by hand: a step (free above-left), points on
    /// both sides of every piece and past both ends.
    #[test]
    fn the_ray_count_tells_the_sides_of_a_polyline() {
        let step = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [2.0, 1.0]];
        let inside = [([1.2, 0.9], 0.1), ([5.0, 0.5], 0.5), ([-3.0, -0.25], 0.25)];
        for (x, depth) in inside {
            let got = polyline_depth(&step, x);
            assert!((got - depth).abs() < 1e-12, "{x:?}: {got}");
        }
        for x in [
            [0.8, 0.5],
            [0.5, 0.1],
            [-4.0, 0.3],
            [1.5, 1.2],
            [9.0, 3.0],
            [0.9, 1.1],
        ] {
            assert_eq!(polyline_depth(&step, x), 0.0, "{x:?}");
        }
    }
}
