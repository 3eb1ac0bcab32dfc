//! The viewed state as SVG, for papers: each body's deformed curve as one path (the curve the
//! viewport draws), pins as circles, y up, written atomically.

use std::fmt::Write as _;
use std::path::Path;

use super::shapes::deformed_bodies;
use crate::history::write_atomic;
use crate::solver::IncrementRecord;
use crate::worker::Loaded;

/// The viewed state `r` as SVG, for papers: one path per body through its deformed curve (the
/// same curve the viewport draws), pins as circles, in the scene's units with y up, fitted to
/// `width` pixels.
pub fn svg(loaded: &Loaded, r: &IncrementRecord, width: f64) -> String {
    let model = &loaded.scene.model;
    let curves = deformed_bodies(model, &loaded.elements, r);
    let points = curves.iter().flat_map(|c| c.points.iter());
    let (mut lo, mut hi) = ([f64::MAX; 2], [f64::MIN; 2]);
    for p in points
        .clone()
        .chain(r.nodes.iter().map(|n| &n[..2]).map(|n| {
            // Pins are drawn too: their positions count.
            let a: &[f64; 2] = n.try_into().expect("two coordinates");
            a
        }))
    {
        for k in 0..2 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    let span = (hi[0] - lo[0]).max(hi[1] - lo[1]).max(1e-300);
    let margin = 0.05 * span;
    let scale = width / (hi[0] - lo[0] + 2.0 * margin).max(1e-300);
    let height = (hi[1] - lo[1] + 2.0 * margin) * scale;
    let x = |v: f64| (v - lo[0] + margin) * scale;
    let y = |v: f64| (hi[1] + margin - v) * scale;
    let mut out = format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{width:.0}\" height=\"{height:.0}\" viewBox=\"0 0 {width:.3} {height:.3}\">\n<!-- {}, increment {}, lengths in {} -->\n",
        loaded.scene.file.name.replace("--", "-"),
        r.increment,
        loaded.scene.file.units.length()
    );
    for c in &curves {
        let d: Vec<String> = (c.points.iter().enumerate())
            .map(|(k, p)| {
                format!(
                    "{}{:.3} {:.3}",
                    if k == 0 { "M" } else { "L" },
                    x(p[0]),
                    y(p[1])
                )
            })
            .collect();
        let _ = writeln!(
            out,
            "<path id=\"{}\" d=\"{}\" fill=\"none\" stroke=\"black\" stroke-width=\"2\"/>",
            xml_escape(&model.bodies[c.body].name),
            d.join(" ")
        );
    }
    for (n, node) in model.nodes.iter().enumerate().filter(|(_, n)| !n.rotation) {
        let _ = writeln!(
            out,
            "<circle id=\"node {}\" cx=\"{:.3}\" cy=\"{:.3}\" r=\"4\" fill=\"white\" stroke=\"black\"/>",
            node.id,
            x(r.nodes[n][0]),
            y(r.nodes[n][1])
        );
    }
    out.push_str("</svg>\n");
    out
}

/// `text` with the XML special characters escaped.
fn xml_escape(text: &str) -> String {
    text.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// Write the SVG export of record `r`.
pub fn write_svg(path: &Path, loaded: &Loaded, r: &IncrementRecord) -> std::io::Result<()> {
    write_atomic(path, svg(loaded, r, 1200.0).as_bytes())
}
