//! The viewed state as SVG, for papers: the figure of `drawing.rs` with each body's deformed
//! curve as one `<path>` named after the body, the ghost and the diagram as `<polyline>`s, pins
//! and contact nodes as circles, in the scene's units with y up, written atomically.

use std::fmt::Write as _;
use std::path::Path;

use super::drawing::{figure, Diagram, Kind};
use crate::history::write_atomic;
use crate::solver::IncrementRecord;
use crate::worker::Loaded;

/// The viewed state `r` as SVG `width` pixels across, with `diagram` if given.
pub fn svg(loaded: &Loaded, r: &IncrementRecord, diagram: Option<Diagram>, width: f64) -> String {
    let f = figure(loaded, r, diagram);
    let frame = f.frame(width, 0.0);
    let [w, h] = frame.size;
    let mut out = format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{w:.0}\" height=\"{h:.0}\" viewBox=\"0 0 {w:.3} {h:.3}\">\n<!-- {}, increment {}, lengths in {} -->\n",
        loaded.scene.file.name.replace("--", "-"),
        r.increment,
        loaded.scene.file.units.length()
    );
    for line in &f.lines {
        let pts: Vec<String> = (line.points.iter())
            .map(|p| {
                let [x, y] = frame.px(*p);
                format!("{x:.3} {y:.3}")
            })
            .collect();
        let ([r, g, b], width) = line.kind.style();
        let stroke = format!("fill=\"none\" stroke=\"rgb({r},{g},{b})\" stroke-width=\"{width}\"");
        let _ = match line.kind {
            Kind::Body => writeln!(
                out,
                "<path id=\"{}\" d=\"M{}\" {stroke}/>",
                xml_escape(&line.name),
                pts.join(" L")
            ),
            Kind::Ghost | Kind::Diagram | Kind::Obstacle | Kind::Face => writeln!(
                out,
                "<polyline class=\"{}\" points=\"{}\" {stroke}/>",
                match line.kind {
                    Kind::Ghost => "undeformed",
                    Kind::Obstacle => "obstacle",
                    Kind::Face => "face",
                    _ => "diagram",
                },
                pts.join(" ")
            ),
        };
    }
    for d in &f.dots {
        let [x, y] = frame.px(d.at);
        let (fill, stroke) = if d.contact {
            ("rgb(210,40,40)", "rgb(120,0,0)")
        } else {
            ("white", "black")
        };
        let _ = writeln!(
            out,
            "<circle id=\"{} node {}\" cx=\"{x:.3}\" cy=\"{y:.3}\" r=\"4\" fill=\"{fill}\" stroke=\"{stroke}\"/>",
            if d.contact { "contact" } else { "pin" },
            d.node
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
pub fn write_svg(
    path: &Path,
    loaded: &Loaded,
    r: &IncrementRecord,
    diagram: Option<Diagram>,
) -> std::io::Result<()> {
    write_atomic(path, svg(loaded, r, diagram, 1200.0).as_bytes())
}
