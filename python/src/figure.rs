//! `figure`: a state of a run drawn as the CLI's `figure` draws it, a PNG of any size or an SVG
//! by the file's extension: the scene's undeformed state (increment 0), a recorded increment of
//! a history, or the state after solving a number of steps.

use std::path::PathBuf;
use std::sync::Arc;

use pyo3::exceptions::{PyKeyError, PyOSError, PyValueError};
use pyo3::prelude::*;
use tsm_contact::figure::{raster, svg, Diagram};
use tsm_contact::solver::Silent;
use tsm_contact::worker::{initial_record, Loaded};

use crate::history::PyHistory;
use crate::PyScene;

/// Draw `scene` to `path` (.png or .svg): increment `increment` of `history` if given (0: the
/// undeformed state), else the state after `steps` steps (default: the scene's). `diagram`:
/// "N", "V" or "M" draws that force diagram; `size` is a PNG's (width, height) in pixels.
#[pyfunction]
#[pyo3(signature = (scene, path, history = None, increment = None, steps = None, diagram = None, size = (1600, 1000)))]
#[allow(clippy::too_many_arguments)]
pub fn figure(
    py: Python<'_>,
    scene: &PyScene,
    path: PathBuf,
    history: Option<&PyHistory>,
    increment: Option<usize>,
    steps: Option<usize>,
    diagram: Option<&str>,
    size: (u32, u32),
) -> PyResult<()> {
    let ext = path.extension().and_then(|e| e.to_str()).unwrap_or("");
    if !matches!(ext, "png" | "svg") {
        return Err(PyValueError::new_err(format!(
            "{}: a figure is written as .png or .svg",
            path.display()
        )));
    }
    if !(16..=16384).contains(&size.0) || !(16..=16384).contains(&size.1) {
        return Err(PyValueError::new_err(format!(
            "size {size:?}: each side from 16 to 16384 pixels"
        )));
    }
    let diagram = match diagram.map(|d| d.to_ascii_uppercase()) {
        None => None,
        Some(d) if d == "N" => Some(Diagram::Axial),
        Some(d) if d == "V" => Some(Diagram::Shear),
        Some(d) if d == "M" => Some(Diagram::Moment),
        Some(d) => {
            return Err(PyValueError::new_err(format!(
                "diagram {d:?}: N (axial), V (shear) or M (moment)"
            )))
        }
    };
    let sc = &scene.scene;
    let mut solver = sc
        .solver()
        .map_err(|e| crate::SolveError::new_err(format!("{}: {e}", sc.file.name)))?;
    let initial = initial_record(&solver);
    let record = match (history, increment) {
        (Some(h), k) => {
            let h = &h.history;
            if h.node_ids.len() != sc.model.nodes.len() {
                return Err(PyValueError::new_err(format!(
                    "the history has {} nodes and scene {:?} {}: not a run of this scene",
                    h.node_ids.len(),
                    sc.file.name,
                    sc.model.nodes.len()
                )));
            }
            match k {
                Some(0) => initial.clone(),
                Some(k) => {
                    (h.increments.iter().find(|r| r.increment == k).cloned()).ok_or_else(|| {
                        PyKeyError::new_err(format!("the history has no increment {k}"))
                    })?
                }
                None => h
                    .increments
                    .last()
                    .cloned()
                    .unwrap_or_else(|| initial.clone()),
            }
        }
        (None, _) => {
            let steps = steps.unwrap_or(sc.steps);
            let name = sc.file.name.clone();
            py.detach(|| {
                let mut last = initial.clone();
                for _ in 0..steps {
                    let recs = solver
                        .step(&mut Silent)
                        .map_err(|e| format!("{name}: {e}"))?;
                    if let Some(r) = recs.into_iter().last() {
                        last = r;
                    }
                }
                Ok::<_, String>(last)
            })
            .map_err(PyValueError::new_err)?
        }
    };
    let loaded = Loaded {
        checkpoint: Arc::new(solver.checkpoint()),
        initial,
        elements: solver.elements().to_vec(),
        prescribed_labels: Vec::new(),
        scene: sc.clone(),
    };
    let written = if ext == "png" {
        raster::write_png(&path, &loaded, &record, diagram, [size.0, size.1])
    } else {
        svg::write_svg(&path, &loaded, &record, diagram)
            .map_err(|e| format!("cannot write {}: {e}", path.display()))
    };
    written.map_err(PyOSError::new_err)
}
