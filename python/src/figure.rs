//! `figure`: a state of a run drawn as the CLI's `figure` draws it, a PNG of any size or an SVG
//! by the file's extension: the scene's undeformed state (increment 0), a recorded increment of
//! a history, or the state after solving a number of steps.

use std::path::PathBuf;

use pyo3::exceptions::{PyKeyError, PyOSError, PyValueError};
use pyo3::prelude::*;
use tsm_contact::figure::state::solved;
use tsm_contact::figure::{raster, svg, Diagram};
use tsm_contact::scene::Scene;
use tsm_contact::solver::SolveError;
use tsm_contact::worker::Loaded;

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
    let (loaded, record) = match history {
        Some(h) => {
            let h = &h.history;
            if h.node_ids.len() != sc.model.nodes.len() {
                return Err(PyValueError::new_err(format!(
                    "the history has {} nodes and scene {:?} {}: not a run of this scene",
                    h.node_ids.len(),
                    sc.file.name,
                    sc.model.nodes.len()
                )));
            }
            let solver = sc.solver().map_err(|e| solve_error(sc, e))?;
            let loaded = Loaded::new(sc.clone(), &solver);
            let record = match increment {
                Some(0) => loaded.initial.clone(),
                Some(k) => {
                    (h.increments.iter().find(|r| r.increment == k).cloned()).ok_or_else(|| {
                        PyKeyError::new_err(format!("the history has no increment {k}"))
                    })?
                }
                None => (h.increments.last().cloned()).unwrap_or_else(|| loaded.initial.clone()),
            };
            (loaded, record)
        }
        None => {
            let steps = steps.unwrap_or(sc.steps);
            py.detach(|| solved(sc.clone(), steps))
                .map_err(|e| solve_error(sc, e))?
        }
    };
    let written = if ext == "png" {
        raster::write_png(&path, &loaded, &record, diagram, [size.0, size.1])
    } else {
        svg::write_svg(&path, &loaded, &record, diagram)
            .map_err(|e| format!("cannot write {}: {e}", path.display()))
    };
    written.map_err(PyOSError::new_err)
}

/// A solver that cannot start on `scene`, or a step that fails, as a Python `SolveError`.
fn solve_error(scene: &Scene, e: SolveError) -> PyErr {
    crate::SolveError::new_err(format!("{}: {e}", scene.file.name))
}
