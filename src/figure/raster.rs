//! The figure rasterised: drawn with tiny-skia into an image of any size, white behind, lines
//! as wide as in a 1200 px figure in proportion, and written as a PNG atomically.

use std::path::Path;

use super::drawing::{figure, Diagram, Figure};
use crate::history::write_atomic;
use crate::solver::IncrementRecord;
use crate::worker::Loaded;

/// The figure drawn into an RGBA image of `width` x `height` pixels, white behind.
pub fn raster(f: &Figure, width: u32, height: u32) -> Result<tiny_skia::Pixmap, String> {
    use tiny_skia::{Color, FillRule, Paint, PathBuilder, Pixmap, Stroke, Transform};
    let mut pm = Pixmap::new(width, height)
        .ok_or_else(|| format!("cannot draw an image of {width} x {height} pixels"))?;
    pm.fill(Color::WHITE);
    let frame = f.frame(f64::from(width), f64::from(height));
    // Lines as wide as in a 1200 px figure, in proportion.
    let grow = (f64::from(width.max(height)) / 1200.0).max(0.5);
    let paint = |rgb: [u8; 3]| {
        let mut p = Paint::default();
        p.set_color_rgba8(rgb[0], rgb[1], rgb[2], 255);
        p.anti_alias = true;
        p
    };
    for line in &f.lines {
        let mut pb = PathBuilder::new();
        for (k, p) in line.points.iter().enumerate() {
            let [x, y] = frame.px(*p);
            if k == 0 {
                pb.move_to(x as f32, y as f32);
            } else {
                pb.line_to(x as f32, y as f32);
            }
        }
        let Some(path) = pb.finish() else { continue };
        let (rgb, w) = line.kind.style();
        let stroke = Stroke {
            width: (w * grow) as f32,
            ..Stroke::default()
        };
        pm.stroke_path(&path, &paint(rgb), &stroke, Transform::identity(), None);
    }
    for d in &f.dots {
        let [x, y] = frame.px(d.at);
        let radius = (4.0 * grow) as f32;
        let Some(circle) = PathBuilder::from_circle(x as f32, y as f32, radius) else {
            continue;
        };
        let (fill, edge) = if d.contact {
            ([210, 40, 40], [120, 0, 0])
        } else {
            ([255, 255, 255], [0, 0, 0])
        };
        let id = Transform::identity();
        pm.fill_path(&circle, &paint(fill), FillRule::Winding, id, None);
        let stroke = Stroke {
            width: grow as f32,
            ..Stroke::default()
        };
        pm.stroke_path(&circle, &paint(edge), &stroke, id, None);
    }
    Ok(pm)
}

/// Write the figure of record `r` as a PNG of `width` x `height` pixels.
pub fn write_png(
    path: &Path,
    loaded: &Loaded,
    r: &IncrementRecord,
    diagram: Option<Diagram>,
    size: [u32; 2],
) -> Result<(), String> {
    let pm = raster(&figure(loaded, r, diagram), size[0], size[1])?;
    let png = pm
        .encode_png()
        .map_err(|e| format!("cannot encode {}: {e}", path.display()))?;
    write_atomic(path, &png).map_err(|e| format!("cannot write {}: {e}", path.display()))
}
