//! Force diagrams along the deformed beams: the axial force N, the shear V or the bending
//! moment M of each element, drawn off its chord (positive to the chord's left), scaled so that
//! the largest value spans `REACH` points, with that extreme labelled; and the colour map of
//! the bending moment shared by the strips and the legend.

use egui::{Color32, FontId, Pos2, Shape, Stroke, Vec2};

use crate::figure::{value_at, Diagram};
use crate::solver::{IncrementRecord, Model};

/// Screen points the largest value of a diagram spans.
const REACH: f32 = 45.0;

/// Samples per element (the moment and shear jump at contact points inside an element).
const SAMPLES: usize = 16;

/// The extreme of `diagram` over the structure: (value, element, fraction along it).
pub fn extreme(model: &Model, r: &IncrementRecord, diagram: Diagram) -> Option<(f64, usize, f64)> {
    let mut best: Option<(f64, usize, f64)> = None;
    for e in 0..model.beams.len() {
        for k in 0..=SAMPLES {
            let x = k as f64 / SAMPLES as f64;
            let v = value_at(model, r, diagram, e, x);
            if best.is_none_or(|b| v.abs() > b.0.abs()) {
                best = Some((v, e, x));
            }
        }
    }
    best
}

/// Draw `diagram` for record `r`; `s` maps world to screen. Returns nothing to draw when every
/// value is zero.
pub fn paint(
    p: &egui::Painter,
    model: &Model,
    r: &IncrementRecord,
    diagram: Diagram,
    unit: &str,
    s: &dyn Fn([f64; 2]) -> Pos2,
) {
    let Some((peak, pe, px)) = extreme(model, r, diagram) else {
        return;
    };
    if peak == 0.0 || !peak.is_finite() {
        return;
    }
    let scale = REACH / peak.abs() as f32;
    let (pos_fill, neg_fill) = (
        Color32::from_rgba_unmultiplied(214, 39, 40, 60),
        Color32::from_rgba_unmultiplied(31, 119, 220, 60),
    );
    let mut label_at = None;
    for (e, beam) in model.beams.iter().enumerate() {
        let (a, b) = (r.nodes[beam.i], r.nodes[beam.j]);
        let (sa, sb) = (s([a[0], a[1]]), s([b[0], b[1]]));
        let along = sb - sa;
        if along.length() < 1e-6 {
            continue;
        }
        // The chord's left on screen (y down): the world normal turned with the chord.
        let normal = Vec2::new(along.y, -along.x).normalized();
        let point = |x: f64| sa + along * x as f32;
        let off = |x: f64| normal * (value_at(model, r, diagram, e, x) as f32 * scale);
        let mut outline = Vec::with_capacity(SAMPLES + 1);
        for k in 0..SAMPLES {
            let (x0, x1) = (k as f64 / SAMPLES as f64, (k + 1) as f64 / SAMPLES as f64);
            let mid = value_at(model, r, diagram, e, 0.5 * (x0 + x1));
            let fill = if mid >= 0.0 { pos_fill } else { neg_fill };
            let (o0, o1) = (off(x0), off(x1));
            // A quad of (nearly) no area is left out: its anti-aliased edges would have no
            // direction, and egui draws them as long slivers.
            if o0.length() + o1.length() > 0.5 {
                let quad = vec![point(x0), point(x1), point(x1) + o1, point(x0) + o0];
                p.add(Shape::convex_polygon(quad, fill, Stroke::NONE));
            }
            outline.push(point(x0) + off(x0));
        }
        outline.push(point(1.0) + off(1.0));
        p.add(Shape::line(
            outline,
            Stroke::new(1.2, Color32::from_gray(60)),
        ));
        if e == pe {
            label_at = Some(point(px) + off(px));
        }
    }
    if let Some(at) = label_at {
        p.text(
            at + Vec2::new(6.0, -6.0),
            egui::Align2::LEFT_BOTTOM,
            format!(
                "{} = {} {unit}",
                diagram.letter(),
                crate::app::display::num(peak)
            ),
            FontId::proportional(13.0),
            Color32::from_gray(20),
        );
    }
}

/// Colour of moment `m` on a diverging scale: blue (negative), slate (zero), red (positive).
pub fn moment_color(m: f64, mmax: f64) -> Color32 {
    let t = (m / mmax.max(1e-30)).clamp(-1.0, 1.0) as f32;
    let zero = [70.0, 78.0, 92.0];
    let end = if t >= 0.0 {
        [214.0, 39.0, 40.0]
    } else {
        [31.0, 119.0, 220.0]
    };
    let a = t.abs().sqrt();
    let c: Vec<u8> = (0..3)
        .map(|i| (zero[i] + (end[i] - zero[i]) * a).round() as u8)
        .collect();
    Color32::from_rgb(c[0], c[1], c[2])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn colour_map_ends_and_middle() {
        assert_eq!(moment_color(0.0, 1.0), Color32::from_rgb(70, 78, 92));
        assert_eq!(moment_color(2.0, 1.0), Color32::from_rgb(214, 39, 40));
        assert_eq!(moment_color(-1.0, 1.0), Color32::from_rgb(31, 119, 220));
    }
}
