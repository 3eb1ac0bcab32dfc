//! Obstacle features between nodes: no convex feature of a rigid obstacle (the centre of a
//! circle or arc that nodes stay out of, a corner of a polyline that juts into the free side)
//! passes through a beam element of a body whose nodes may touch the obstacle. The node tests
//! see nodes only, and a small roller or peg fits between two nodes: a feature that projects
//! onto an element's chord at both ends of the increment and changes side of it went through
//! the element. A drum that a chord cuts by its sag keeps its centre on one side.

use super::obstacle::pilot_offset;
use crate::solver::model::Model;
use crate::solver::report::NodeState;

/// A feature of an obstacle found through an element.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FeatureCrossing {
    /// Obstacle index.
    pub obstacle: usize,
    /// Beam element index.
    pub element: usize,
    /// How far beyond the element's chord the feature ends (m).
    pub depth: f64,
}

/// Gaps below this fraction of the element length (plus the positions' round-off) are on the
/// chord: they tell no side.
const ON_CHORD: f64 = 1e-9;

/// The first feature of an obstacle of `model` that passed through an element between node
/// states `before` and `after` (scene coordinates; `origin` is where the model's own
/// coordinates are measured from, as for `inside_obstacle`).
pub fn feature_through(
    model: &Model,
    origin: [f64; 2],
    (before, after): (&[NodeState], &[NodeState]),
) -> Option<FeatureCrossing> {
    for (o, ob) in model.obstacles.iter().enumerate() {
        // Features that touch elements are contact nodes, kept out by the crossing check.
        let points = ob.shape.convex_features();
        if points.is_empty() || ob.touches_elements {
            continue;
        }
        let (t0, t1) = (
            pilot_offset(model, ob.pilot, origin, before),
            pilot_offset(model, ob.pilot, origin, after),
        );
        // The bodies with a node that may touch the obstacle (its nodes are ascending).
        let mut touching = vec![false; model.bodies.len()];
        for beam in &model.beams {
            let candidate = |n: usize| ob.nodes.binary_search(&n).is_ok();
            touching[beam.body] |= candidate(beam.i) || candidate(beam.j);
        }
        for (e, beam) in model.beams.iter().enumerate() {
            if !touching[beam.body] {
                continue;
            }
            for &f in &points {
                let side = |s: &[NodeState], t: [f64; 2]| {
                    let (a, b) = (s[beam.i], s[beam.j]);
                    let p = [f[0] + t[0], f[1] + t[1]];
                    let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
                    let l = dx.hypot(dy);
                    let along = ((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / (l * l);
                    let off = (dx * (p[1] - a[1]) - dy * (p[0] - a[0])) / l;
                    let scale = a[0].abs().max(a[1].abs()).max(p[0].abs()).max(p[1].abs());
                    let tol = ON_CHORD * l + 64.0 * f64::EPSILON * scale;
                    ((0.0..=1.0).contains(&along), off, tol)
                };
                let (in0, off0, tol0) = side(before, t0);
                let (in1, off1, tol1) = side(after, t1);
                if in0 && in1 && off0.abs() > tol0 && off1.abs() > tol1 && off0 * off1 < 0.0 {
                    return Some(FeatureCrossing {
                        obstacle: o,
                        element: e,
                        depth: off1.abs(),
                    });
                }
            }
        }
    }
    None
}
