//! What the figure and the viewport draw, in world coordinates: each body's smooth deformed
//! curve (through `solver::element::shape::element_curve`) with the bending moment at every
//! sample, the undeformed chords, the faces of bodies with a thickness, and the outlines of
//! the rigid obstacles where their pilots have moved them.

use crate::solver::element::beam::BeamElement;
use crate::solver::{IncrementRecord, Model};

/// Samples per element along the deformed curve.
pub const SAMPLES: usize = 8;

/// A body's deformed centre line with the bending moment at each point.
#[derive(Clone, Debug, Default)]
pub struct BodyCurve {
    /// Index of the body in [`Model::bodies`].
    pub body: usize,
    /// Points (m).
    pub points: Vec<[f64; 2]>,
    /// Bending moment at each point (N m).
    pub moments: Vec<f64>,
}

/// Bending moment at fraction `x` along element `e` of a simply supported beam carrying the end
/// moments (Mi, Mj), the element's contact forces and its distributed loads (sign convention
/// of the element force equation: `Mi` at end i, `-Mj` at end j).
pub fn moment_at(model: &Model, record: &IncrementRecord, e: usize, x: f64) -> f64 {
    let f = record.element_forces.get(e).copied().unwrap_or([0.0; 3]);
    let l = model.beam_length(e);
    let mut m = f[1] * (1.0 - x) - f[2] * x;
    for c in record.contacts.iter().filter(|c| c.element == e) {
        let a = c.xi.clamp(0.0, 1.0);
        m += c.force * l * if x <= a { (1.0 - a) * x } else { a * (1.0 - x) };
    }
    if let Some([pi, pj]) = transverse_load(model, record, e) {
        m += l * l * ((2.0 * pi + pj) / 6.0 * x - pi * x * x / 2.0 - (pj - pi) * x.powi(3) / 6.0);
    }
    m
}

/// The distributed loads on element `e` across its chord at the viewed state, per length at
/// ends i and j, positive on the side a positive element force Y acts on (`SIDE`); `None`
/// without distributed loads.
pub fn transverse_load(model: &Model, record: &IncrementRecord, e: usize) -> Option<[f64; 2]> {
    let on = model.distributed_on(e);
    if on.is_empty() {
        return None;
    }
    let (_, n, l) = chord_frame(model, record, e)?;
    // A follower load is per current length: on the undeformed length the moment formula
    // uses, (l / l0)^2 times as much.
    let stretch = (l / model.beam_length(e).max(1e-300)).powi(2);
    let mut p = [0.0; 2];
    for d in on {
        for (end, q) in p.iter_mut().zip(&d.q) {
            let across = if d.follower {
                q[1] * stretch
            } else {
                q[0] * n[0] + q[1] * n[1]
            };
            *end += record.load_factor * SIDE * across;
        }
    }
    Some(p)
}

/// The current chord of element `e` in record `r`: its unit direction t (from end i to end j),
/// its unit normal n (t turned +90 degrees) and its length.
pub fn chord_frame(
    model: &Model,
    r: &IncrementRecord,
    e: usize,
) -> Option<([f64; 2], [f64; 2], f64)> {
    let b = model.beams.get(e)?;
    let (a, c) = (r.nodes.get(b.i)?, r.nodes.get(b.j)?);
    let (dx, dy) = (c[0] - a[0], c[1] - a[1]);
    let l = dx.hypot(dy).max(1e-300);
    Some(([dx / l, dy / l], [-dy / l, dx / l], l))
}

/// The side of the chord a positive element force Y acts on (+1: the normal turned +90 degrees
/// from the chord i -> j).
const SIDE: f64 = 1.0;

/// Deformed curves of every body (elements chained in body order; a gap starts a new curve).
pub fn deformed_bodies(
    model: &Model,
    elements: &[BeamElement],
    record: &IncrementRecord,
) -> Vec<BodyCurve> {
    let mut out = Vec::new();
    for (b, body) in model.bodies.iter().enumerate() {
        let mut cur = BodyCurve {
            body: b,
            ..BodyCurve::default()
        };
        let mut last_node = None;
        for &e in &body.elements {
            if e >= model.beams.len() || e >= elements.len() {
                continue;
            }
            let beam = &model.beams[e];
            if last_node.is_some() && last_node != Some(beam.i) && !cur.points.is_empty() {
                out.push(std::mem::replace(
                    &mut cur,
                    BodyCurve {
                        body: b,
                        ..BodyCurve::default()
                    },
                ));
            }
            let pts =
                crate::solver::element::shape::element_curve(model, elements, record, e, SAMPLES);
            let skip = usize::from(!cur.points.is_empty());
            for (k, p) in pts.iter().enumerate().skip(skip) {
                cur.points.push(*p);
                cur.moments
                    .push(moment_at(model, record, e, k as f64 / SAMPLES as f64));
            }
            last_node = Some(beam.j);
        }
        if !cur.points.is_empty() {
            out.push(cur);
        }
    }
    out
}

/// The faces of a body of thickness `2 half` about its deformed curve `points`: for each point,
/// the points `half` either side along the curve's normal there (empty for a line).
pub fn faces(points: &[[f64; 2]], half: f64) -> Vec<[[f64; 2]; 2]> {
    if half <= 0.0 || points.len() < 2 {
        return Vec::new();
    }
    let last = points.len() - 1;
    (0..=last)
        .map(|k| {
            let (a, b) = (points[k.saturating_sub(1)], points[(k + 1).min(last)]);
            let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
            let l = dx.hypot(dy).max(f64::MIN_POSITIVE);
            let n = [-dy / l * half, dx / l * half];
            let p = points[k];
            [[p[0] + n[0], p[1] + n[1]], [p[0] - n[0], p[1] - n[1]]]
        })
        .collect()
}

/// Half the thickness of body `b`: of its thickest element (0: a line).
pub fn half_thickness(model: &Model, b: usize) -> f64 {
    (model.bodies[b].elements.iter())
        .map(|&e| 0.5 * model.beams[e].section.thickness)
        .fold(0.0, f64::max)
}

/// Undeformed chords of every body, as polylines through the initial node positions.
pub fn undeformed_bodies(model: &Model) -> Vec<Vec<[f64; 2]>> {
    let mut out = Vec::new();
    for body in &model.bodies {
        let mut line: Vec<[f64; 2]> = Vec::new();
        let mut last_node = None;
        for &e in &body.elements {
            let Some(beam) = model.beams.get(e) else {
                continue;
            };
            if last_node != Some(beam.i) {
                if line.len() > 1 {
                    out.push(std::mem::take(&mut line));
                }
                line.clear();
                line.push(model.position(beam.i));
            }
            line.push(model.position(beam.j));
            last_node = Some(beam.j);
        }
        if line.len() > 1 {
            out.push(line);
        }
    }
    out
}

/// Largest |M| over the curves (at least a tiny positive number).
pub fn max_moment(curves: &[BodyCurve]) -> f64 {
    curves
        .iter()
        .flat_map(|c| c.moments.iter())
        .fold(1e-30, |a, m| a.max(m.abs()))
}

/// The outline of every obstacle at record `r` (moved by its pilot's displacement), each a
/// polyline in world coordinates: lines and the ends of polylines drawn `reach` beyond the
/// model's bounding box at rest, circles and arcs as fine polygons.
pub fn obstacle_outlines(model: &Model, r: &IncrementRecord) -> Vec<Vec<[f64; 2]>> {
    let (lo, hi) = model.bounds();
    let reach = (hi[0] - lo[0]).max(hi[1] - lo[1]).max(1e-9);
    let centre = [0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1])];
    let mut out = Vec::new();
    for ob in &model.obstacles {
        let t = ob.pilot.map_or([0.0, 0.0], |p| {
            let at = r.nodes.get(p).copied().unwrap_or([0.0; 3]);
            [at[0] - model.nodes[p].x, at[1] - model.nodes[p].y]
        });
        out.push(ob.shape.translated(t).outline(centre, reach));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The faces of a quarter circle of radius 1 drawn 0.1 thick are the circles of radius
    /// 0.95 and 1.05 (to the chord's sag, 3e-4 at 64 pieces); a line has none.
    #[test]
    fn the_faces_of_an_arc_are_the_arcs_half_the_thickness_either_side() {
        let n = 64;
        let arc: Vec<[f64; 2]> = (0..=n)
            .map(|k| {
                let t = std::f64::consts::FRAC_PI_2 * k as f64 / n as f64;
                [t.cos(), t.sin()]
            })
            .collect();
        let sides = faces(&arc, 0.05);
        assert_eq!(sides.len(), arc.len());
        for [a, b] in sides {
            let (ra, rb) = (a[0].hypot(a[1]), b[0].hypot(b[1]));
            let (outer, inner) = if ra > rb { (ra, rb) } else { (rb, ra) };
            assert!(
                (outer - 1.05).abs() < 3e-4 && (inner - 0.95).abs() < 3e-4,
                "{outer} {inner}"
            );
        }
        assert!(faces(&arc, 0.0).is_empty());
    }
}
