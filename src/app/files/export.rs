//! Exports: the run history as JSON (the `solve --json` schema) and CSV (one row per
//! increment, units in the headers), and PNG screenshots. Files are written atomically.

use std::fmt::Write as _;
use std::path::Path;

use egui::ColorImage;

use crate::history::{write_atomic, History};
use crate::solver::{Event, IncrementRecord, IncrementStatus};
use crate::worker::Loaded;

/// The history of the current run in the `History` schema (increment 0 left out); `every`:
/// the app kept every how many of the run's records ([`History::every`]).
pub fn history(
    loaded: &Loaded,
    records: &[IncrementRecord],
    every: usize,
    events: &[Event],
    error: Option<&str>,
) -> History {
    let model = &loaded.scene.model;
    History {
        increments: records
            .iter()
            .filter(|r| r.increment > 0)
            .cloned()
            .collect(),
        events: events.to_vec(),
        error: error.map(str::to_string),
        every: (every > 1).then_some(every),
        ..History::of_model(
            &loaded.scene.file.name,
            model,
            Some(model.formulation),
            Some(loaded.scene.params),
        )
    }
}

/// One CSV row per increment: number, prescribed values, load factor, iterations, residual,
/// status (converged or roundoff), cut-backs, active contacts, every reaction, the contact force
/// on every contact candidate node (0 when it touches nothing), the friction force on every
/// candidate of a frictional pair (along its element's chord), and the displacements of the
/// nodes in `nodes` (indices). Each header names its unit in brackets, in the scene's units.
pub fn csv(loaded: &Loaded, records: &[IncrementRecord], nodes: &[usize]) -> String {
    let model = &loaded.scene.model;
    let units = loaded.scene.file.units;
    let mut out = String::from("increment");
    for (l, p) in loaded.prescribed_labels.iter().zip(&model.prescribed) {
        let _ = write!(out, ",{} [{}]", l.replace(' ', "_"), units.of_dof(p.dof));
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
        let unit = if d == "phi" {
            units.moment()
        } else {
            units.force().to_string()
        };
        let _ = write!(out, ",R_node_{n}_{d} [{unit}]");
    }
    let mut candidates: Vec<u32> = (model.contacts.iter())
        .flat_map(|c| c.nodes.iter().map(|&n| model.nodes[n].id))
        .collect();
    candidates.sort_unstable();
    candidates.dedup();
    for id in &candidates {
        let _ = write!(out, ",Yc_node_{id} [{}]", units.force());
    }
    let mut frictional: Vec<u32> = (model.contacts.iter().filter(|c| c.mu > 0.0))
        .flat_map(|c| c.nodes.iter().map(|&n| model.nodes[n].id))
        .collect();
    frictional.sort_unstable();
    frictional.dedup();
    for id in &frictional {
        let _ = write!(out, ",T_node_{id} [{}]", units.force());
    }
    for &n in nodes {
        let id = model.nodes[n].id;
        let len = units.length();
        let _ = write!(out, ",u_node_{id} [{len}],v_node_{id} [{len}]");
        if model.nodes[n].rotation {
            let _ = write!(out, ",phi_node_{id} [rad]");
        }
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
                IncrementStatus::Snapping { .. } => "snapping",
            },
            r.cutbacks,
            r.contacts.len() + r.obstacle_contacts.len()
        );
        for (n, d) in &reactions {
            let v = r
                .reactions
                .iter()
                .find(|x| x.node == *n && &x.dof == d)
                .map_or(f64::NAN, |x| x.value);
            let _ = write!(out, ",{v:.12e}");
        }
        for id in &candidates {
            let yc: f64 = (r.contacts.iter())
                .filter(|c| c.node == *id)
                .map(|c| c.force)
                .sum();
            let _ = write!(out, ",{yc:.12e}");
        }
        for id in &frictional {
            let t: f64 = (r.contacts.iter())
                .filter(|c| c.node == *id)
                .map(|c| c.tangential)
                .sum();
            let _ = write!(out, ",{t:.12e}");
        }
        for &n in nodes {
            let (p, node) = (r.nodes[n], &model.nodes[n]);
            let _ = write!(out, ",{:.12e},{:.12e}", p[0] - node.x, p[1] - node.y);
            if node.rotation {
                let _ = write!(out, ",{:.12e}", p[2]);
            }
        }
        out.push('\n');
    }
    out
}

/// Write the CSV export, with the displacements of the nodes `nodes` (indices).
pub fn write_csv(
    path: &Path,
    loaded: &Loaded,
    records: &[IncrementRecord],
    nodes: &[usize],
) -> std::io::Result<()> {
    write_atomic(path, csv(loaded, records, nodes).as_bytes())
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
