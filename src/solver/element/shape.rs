//! Deformed shapes for drawing and checks: each element's own deflected curve in its chord
//! frame (exact for the element force equation, through its contact points), sampled from a
//! converged increment record.

use super::beam::BeamElement;
use super::contact_element::deflection;
use crate::solver::model::Model;
use crate::solver::report::IncrementRecord;

/// Contact fractions are clamped like the stiffness does.
const XI_MIN: f64 = 1e-6;

/// Points along beam element `e` in the state of `record`: `samples + 1` points from node i to
/// node j, each at chord position x (0..1) plus the element's deflection there.
pub fn element_curve(
    model: &Model,
    elements: &[BeamElement],
    record: &IncrementRecord,
    e: usize,
    samples: usize,
) -> Vec<[f64; 2]> {
    let beam = &model.beams[e];
    let (pi, pj) = (record.nodes[beam.i], record.nodes[beam.j]);
    let (dx, dy) = (pj[0] - pi[0], pj[1] - pi[1]);
    let l = dx.hypot(dy);
    let (c, s) = (dx / l, dy / l);
    let f = record.element_forces[e];
    let mut bending = vec![f[1], f[2]];
    let mut xis = Vec::new();
    for ct in record.contacts.iter().filter(|ct| ct.element == e) {
        bending.push(ct.force);
        xis.push(ct.xi.clamp(XI_MIN, 1.0 - XI_MIN));
    }
    let samples = samples.max(1);
    (0..=samples)
        .map(|k| {
            let x = k as f64 / samples as f64;
            let w = if k == 0 || k == samples {
                0.0
            } else {
                deflection(&elements[e], &bending, &xis, x)
            };
            [pi[0] + x * l * c - w * s, pi[1] + x * l * s + w * c]
        })
        .collect()
}
