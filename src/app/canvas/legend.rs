//! The viewport's keys, drawn over it with egui: the colour legend of the bending moment and a
//! scale bar.

use egui::{Align2, Color32, FontId, Pos2, Rect, Shape, Stroke, Vec2};

use super::diagrams::moment_color;
use super::overlays::INK;
use crate::app::display::num;
use crate::scene::units::Units;

/// Colour legend of the bending moment.
pub(crate) fn legend(p: &egui::Painter, rect: Rect, mmax: f64, units: Units) {
    let o = rect.left_top() + Vec2::new(14.0, 14.0);
    let (w, h) = (180.0, 12.0);
    let bg = Rect::from_min_size(o - Vec2::new(8.0, 6.0), Vec2::new(w + 16.0, 62.0));
    p.rect_filled(bg, 4.0, Color32::from_white_alpha(220));
    p.text(
        o,
        Align2::LEFT_TOP,
        format!("bending moment M ({})", units.moment()),
        FontId::proportional(12.0),
        INK,
    );
    let bar = o + Vec2::new(0.0, 18.0);
    let mut mesh = egui::Mesh::default();
    let steps = 32;
    for k in 0..=steps {
        let t = k as f32 / steps as f32;
        let c = moment_color((2.0 * f64::from(t) - 1.0) * mmax, mmax);
        mesh.colored_vertex(bar + Vec2::new(t * w, 0.0), c);
        mesh.colored_vertex(bar + Vec2::new(t * w, h), c);
        if k > 0 {
            let i = 2 * k as u32;
            mesh.add_triangle(i - 2, i - 1, i);
            mesh.add_triangle(i - 1, i + 1, i);
        }
    }
    p.add(Shape::mesh(mesh));
    let f = FontId::proportional(11.0);
    let y = bar.y + h + 3.0;
    // Stress-free: `max_moment`'s floor is no scale to print.
    let end = if mmax > 1e-20 { num(mmax) } else { "0".into() };
    p.text(
        Pos2::new(bar.x, y),
        Align2::LEFT_TOP,
        if mmax > 1e-20 {
            format!("-{end}")
        } else {
            end.clone()
        },
        f.clone(),
        INK,
    );
    p.text(
        Pos2::new(bar.x + w / 2.0, y),
        Align2::CENTER_TOP,
        "0",
        f.clone(),
        INK,
    );
    p.text(Pos2::new(bar.x + w, y), Align2::RIGHT_TOP, end, f, INK);
}

/// A scale bar of a round length near 100 points.
pub(crate) fn scale_bar(p: &egui::Painter, rect: Rect, scale: f64, units: Units) {
    let raw = 100.0 / scale;
    let pow = 10f64.powf(raw.log10().floor());
    let len = [1.0, 2.0, 5.0, 10.0]
        .iter()
        .map(|m| m * pow)
        .rfind(|l| *l <= raw)
        .unwrap_or(pow);
    let px = (len * scale) as f32;
    let o = rect.left_bottom() + Vec2::new(16.0, -16.0);
    let s = Stroke::new(2.0, INK);
    p.line_segment([o, o + Vec2::new(px, 0.0)], s);
    p.line_segment([o, o - Vec2::new(0.0, 5.0)], s);
    p.line_segment([o + Vec2::new(px, 0.0), o + Vec2::new(px, -5.0)], s);
    p.text(
        o + Vec2::new(px / 2.0, -6.0),
        Align2::CENTER_BOTTOM,
        format!("{len} {}", units.length()),
        FontId::proportional(11.0),
        INK,
    );
}
