//! Obstacles: no candidate node is inside a rigid obstacle beyond the accepted gap. The
//! obstacle's curve at a state is its rest curve moved by its pilot's displacement; the signed
//! distance to it, and the convex features the sides check follows between nodes, are worked
//! out here from each shape's own definition (the audit's geometry of every shape).

use std::collections::HashMap;

use crate::history::topology::Topology;
use crate::solver::Shape;

/// Round-off units of the coordinates that a distance from an obstacle may be off by.
const ROUNDOFF_ULPS: f64 = 64.0;

/// The size of the coordinates of `shape` (m): its largest coordinate, plus its radius.
fn shape_scale(shape: &Shape) -> f64 {
    let big = |p: &[f64; 2]| p[0].abs().max(p[1].abs());
    match shape {
        Shape::Line { from, to } => big(from).max(big(to)),
        Shape::Polyline { points } => points.iter().map(big).fold(0.0, f64::max),
        Shape::Circle { centre, radius, .. } | Shape::Arc { centre, radius, .. } => {
            big(centre) + radius
        }
    }
}

/// The angles (rad, counter-clockwise from the first to the second) within which an
/// obstacle's convex features are kept out of the bodies: an arc's centre only within the
/// arc; `None`, every direction.
pub fn feature_reach(shape: &Shape) -> Option<[f64; 2]> {
    match shape {
        Shape::Arc { from, to, .. } => Some([*from, *to]),
        _ => None,
    }
}

/// The convex features of `shape` at rest, which fit between two nodes: the centre of a disk
/// (a circle or an arc nodes stay out of), and each corner of a polyline where it turns right
/// (juts into the free side).
pub fn convex_features(shape: &Shape) -> Vec<[f64; 2]> {
    match shape {
        Shape::Circle {
            centre,
            hollow: false,
            ..
        }
        | Shape::Arc {
            centre,
            hollow: false,
            ..
        } => vec![*centre],
        Shape::Polyline { points } => (points.windows(3))
            .filter(|w| {
                let turn = (w[1][0] - w[0][0]) * (w[2][1] - w[1][1])
                    - (w[1][1] - w[0][1]) * (w[2][0] - w[1][0]);
                turn < 0.0
            })
            .map(|w| w[1])
            .collect(),
        _ => Vec::new(),
    }
}

/// The signed distance (m) of point `p` from `shape`: positive on the free side, negative
/// inside; None where an arc does not reach the point (its polar angle is outside the arc).
pub fn signed_distance(shape: &Shape, p: [f64; 2]) -> Option<f64> {
    match shape {
        Shape::Line { from, to } => {
            let (dx, dy) = (to[0] - from[0], to[1] - from[1]);
            Some((dx * (p[1] - from[1]) - dy * (p[0] - from[0])) / dx.hypot(dy))
        }
        Shape::Polyline { points } => polyline(points, p),
        Shape::Circle {
            centre,
            radius,
            hollow,
        } => {
            let r = (p[0] - centre[0]).hypot(p[1] - centre[1]);
            Some(if *hollow { radius - r } else { r - radius })
        }
        Shape::Arc {
            centre,
            radius,
            from,
            to,
            hollow,
        } => {
            let angle = (p[1] - centre[1]).atan2(p[0] - centre[0]);
            let span = (to - from).rem_euclid(std::f64::consts::TAU);
            let at = (angle - from).rem_euclid(std::f64::consts::TAU);
            if at > span {
                return None;
            }
            let r = (p[0] - centre[0]).hypot(p[1] - centre[1]);
            Some(if *hollow { radius - r } else { r - radius })
        }
    }
}

/// The signed distance from a polyline continued beyond its ends, free to the left: the
/// distance to the closest piece, its sign from that piece, or at a corner from the corner's
/// two pieces (inside where the point is on the solid side of both at a convex corner, of
/// either at a concave one).
fn polyline(points: &[[f64; 2]], p: [f64; 2]) -> Option<f64> {
    let last = points.len().checked_sub(2)?;
    let side = |a: [f64; 2], b: [f64; 2]| {
        let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
        (dx * (p[1] - a[1]) - dy * (p[0] - a[0])) / dx.hypot(dy)
    };
    let mut best: Option<(f64, usize, f64)> = None;
    for k in 0..=last {
        let (a, b) = (points[k], points[k + 1]);
        let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
        let t = ((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / (dx * dx + dy * dy);
        let lo = if k == 0 { f64::NEG_INFINITY } else { 0.0 };
        let hi = if k == last { f64::INFINITY } else { 1.0 };
        let t = t.clamp(lo, hi);
        let d = (p[0] - a[0] - t * dx).hypot(p[1] - a[1] - t * dy);
        if best.is_none_or(|bb| d < bb.0) {
            best = Some((d, k, t));
        }
    }
    let (d, k, t) = best?;
    let (a, b) = (points[k], points[k + 1]);
    let corner = if t <= 0.0 && k > 0 {
        Some(k)
    } else if t >= 1.0 && k < last {
        Some(k + 1)
    } else {
        None
    };
    let Some(c) = corner else {
        return Some(d.copysign(side(a, b)));
    };
    let (u, v, w) = (points[c - 1], points[c], points[c + 1]);
    let (s1, s2) = (side(u, v), side(v, w));
    let turn = (v[0] - u[0]) * (w[1] - v[1]) - (v[1] - u[1]) * (w[0] - v[0]);
    // A left turn bends the free side in (concave for the free side): inside if beyond either.
    let inside = if turn > 0.0 {
        s1 < 0.0 || s2 < 0.0
    } else {
        s1 < 0.0 && s2 < 0.0
    };
    Some(if inside { -d } else { d })
}

/// The deepest candidate node inside an obstacle in state `s` (its face, at its clearance
/// from the node), deeper than `tol` (m):
/// (node id, obstacle name, depth).
pub fn deepest_inside(
    topology: &Topology,
    slot: &HashMap<u32, usize>,
    rest: &HashMap<u32, [f64; 2]>,
    s: &[[f64; 3]],
    tol: f64,
) -> Option<(u32, String, f64)> {
    let clearance: HashMap<u32, f64> = (topology.nodes.iter())
        .filter(|n| n.clearance != 0.0)
        .map(|n| (n.id, n.clearance))
        .collect();
    let mut worst: Option<(u32, String, f64)> = None;
    for o in &topology.obstacles {
        let by = o.pilot.map_or([0.0, 0.0], |p| {
            let (now, was) = (s[slot[&p]], rest[&p]);
            [now[0] - was[0], now[1] - was[1]]
        });
        let shape = o.shape.translated(by);
        let scale = shape_scale(&shape);
        for &n in &o.nodes {
            let p = s[slot[&n]];
            let Some(centre) = signed_distance(&shape, [p[0], p[1]]) else {
                continue;
            };
            // The node's face: its clearance nearer the obstacle than the node.
            let g = centre - clearance.get(&n).copied().unwrap_or(0.0);
            // Beyond the round-off of the positions and the shape's coordinates too.
            let slack = ROUNDOFF_ULPS * f64::EPSILON * (scale + p[0].abs().max(p[1].abs()));
            if -g > tol + slack && worst.as_ref().is_none_or(|w| -g > w.2) {
                worst = Some((n, o.name.clone(), -g));
            }
        }
    }
    worst
}
