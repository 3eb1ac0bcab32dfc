//! Exports: the run history as JSON (the `solve --json` schema) and CSV (one row per
//! increment), and PNG screenshots. Files are written atomically.

use std::fmt::Write as _;
use std::path::Path;

use egui::ColorImage;

use crate::history::{write_atomic, History};
use crate::solver::{Event, IncrementRecord, IncrementStatus};
use crate::worker::Loaded;

/// The history of the current run in the `History` schema (increment 0 left out).
pub fn history(
    loaded: &Loaded,
    records: &[IncrementRecord],
    events: &[Event],
    error: Option<&str>,
) -> History {
    History {
        scene: loaded.scene.file.name.clone(),
        formulation: Some(loaded.scene.model.formulation),
        params: Some(loaded.scene.params),
        node_ids: loaded.scene.model.nodes.iter().map(|n| n.id).collect(),
        increments: records
            .iter()
            .filter(|r| r.increment > 0)
            .cloned()
            .collect(),
        events: events.to_vec(),
        error: error.map(str::to_string),
    }
}

/// One CSV row per increment: number, prescribed values, load factor, iterations, residual,
/// status (converged or roundoff), cut-backs, active contacts, then every reaction.
pub fn csv(loaded: &Loaded, records: &[IncrementRecord]) -> String {
    let mut out = String::from("increment");
    for l in &loaded.prescribed_labels {
        let _ = write!(out, ",{}", l.replace(' ', "_"));
    }
    out.push_str(",load_factor,iterations,relative_residual,status,cutbacks,active_contacts");
    let reactions: Vec<(u32, String)> = records
        .iter()
        .rev()
        .find(|r| !r.reactions.is_empty())
        .map(|r| {
            r.reactions
                .iter()
                .map(|x| (x.node, x.dof.clone()))
                .collect()
        })
        .unwrap_or_default();
    for (n, d) in &reactions {
        let _ = write!(out, ",R_node_{n}_{d}");
    }
    out.push('\n');
    for r in records.iter().filter(|r| r.increment > 0) {
        let _ = write!(out, "{}", r.increment);
        for v in &r.prescribed {
            let _ = write!(out, ",{v:.12e}");
        }
        let _ = write!(
            out,
            ",{:.12e},{},{:.6e},{},{},{}",
            r.load_factor,
            r.iterations,
            r.relative_residual,
            match r.status {
                IncrementStatus::Converged => "converged",
                IncrementStatus::RoundOff { .. } => "roundoff",
            },
            r.cutbacks,
            r.contacts.len()
        );
        for (n, d) in &reactions {
            let v = r
                .reactions
                .iter()
                .find(|x| x.node == *n && &x.dof == d)
                .map_or(f64::NAN, |x| x.value);
            let _ = write!(out, ",{v:.12e}");
        }
        out.push('\n');
    }
    out
}

/// Write the CSV export.
pub fn write_csv(path: &Path, loaded: &Loaded, records: &[IncrementRecord]) -> std::io::Result<()> {
    write_atomic(path, csv(loaded, records).as_bytes())
}

/// Save a screenshot as PNG.
pub fn save_png(path: &Path, img: &ColorImage) -> Result<(), String> {
    let [w, h] = img.size;
    let bytes: Vec<u8> = img
        .pixels
        .iter()
        .flat_map(|c| c.to_srgba_unmultiplied())
        .collect();
    let buf = image::RgbaImage::from_raw(w as u32, h as u32, bytes).ok_or("bad image size")?;
    let mut png = Vec::new();
    buf.write_to(&mut std::io::Cursor::new(&mut png), image::ImageFormat::Png)
        .map_err(|e| e.to_string())?;
    write_atomic(path, &png).map_err(|e| e.to_string())
}
