//! `figure`: a scene's state after some steps drawn as a figure for papers, without a window
//! (`tsm_contact::figure`): a PNG of the chosen size or an SVG, by the extension of the file.

use std::path::Path;

use super::args::DiagramArg;
use tsm_contact::figure::state::solved;
use tsm_contact::figure::{raster, svg};
use tsm_contact::scene::builtin::open;

/// Solve `steps` steps of `scene` (default: the scene's) and write the last state to `out`;
/// returns the exit code (1 with the reason on stderr when the scene, the size, the solve or
/// the write fails).
pub fn run(
    scene: &str,
    steps: Option<usize>,
    diagram: Option<DiagramArg>,
    out: &Path,
    size: &str,
) -> i32 {
    match draw(scene, steps, diagram, out, size) {
        Ok(()) => {
            out!("wrote {}", out.display());
            0
        }
        Err(e) => {
            eprintln!("error: {e}");
            1
        }
    }
}

fn draw(
    name: &str,
    steps: Option<usize>,
    diagram: Option<DiagramArg>,
    out: &Path,
    size: &str,
) -> Result<(), String> {
    let size = parse_size(size)?;
    let ext = out.extension().and_then(|e| e.to_str()).unwrap_or("");
    if !matches!(ext, "png" | "svg") {
        return Err(format!(
            "{}: the figure is written as .png or .svg",
            out.display()
        ));
    }
    let scene = open(name).map_err(|e| e.to_string())?;
    let steps = steps.unwrap_or(scene.steps);
    let (loaded, last) = solved(scene, steps).map_err(|e| format!("{name}: {e}"))?;
    let diagram = diagram.map(DiagramArg::diagram);
    if ext == "png" {
        raster::write_png(out, &loaded, &last, diagram, size)
    } else {
        svg::write_svg(out, &loaded, &last, diagram)
            .map_err(|e| format!("cannot write {}: {e}", out.display()))
    }
}

/// "1600x1000" as [1600, 1000], each from 16 to 16384.
fn parse_size(size: &str) -> Result<[u32; 2], String> {
    let bad = || format!("--size {size}: write it as WIDTHxHEIGHT in pixels, each 16 to 16384");
    let (w, h) = size.split_once(['x', 'X']).ok_or_else(bad)?;
    let w: u32 = w.trim().parse().map_err(|_| bad())?;
    let h: u32 = h.trim().parse().map_err(|_| bad())?;
    if !(16..=16384).contains(&w) || !(16..=16384).contains(&h) {
        return Err(bad());
    }
    Ok([w, h])
}
