//! `History`: a whole run (the CLI's `solve --json` format) and its arrays for numpy: node
//! states `[increments, nodes, 3]`, the driven values and residuals by increment, and the
//! contacts, obstacle contacts and reactions as flat tables with an increment column. Numbers
//! cross as little-endian f64 bytes with a shape (`numpy.frombuffer` reads them without a
//! copy). `check` is the independent audit of a history (`tsm_contact::audit`).

use std::path::PathBuf;

use pyo3::exceptions::{PyKeyError, PyOSError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyBytes, PyDict};
use tsm_contact::audit::audit_history;
use tsm_contact::history::History;
use tsm_contact::solver::IncrementStatus;

/// A run: the scene's name, node ids and topology, every accepted increment and event, and
/// the error it stopped on (None: it completed).
#[pyclass(module = "tsm_contact._native", name = "History", frozen)]
pub struct PyHistory {
    pub(crate) history: History,
}

/// `values` as little-endian f64 bytes.
fn bytes_of(py: Python<'_>, values: &[f64]) -> Py<PyBytes> {
    let raw: Vec<u8> = values.iter().flat_map(|v| v.to_le_bytes()).collect();
    PyBytes::new(py, &raw).unbind()
}

/// A column of a table: floats as bytes, text as a list.
enum Column {
    Numbers(Vec<f64>),
    Text(Vec<String>),
}

#[pymethods]
impl PyHistory {
    /// A history from the JSON text `solve --json` writes.
    #[staticmethod]
    fn from_json(text: &str) -> PyResult<PyHistory> {
        serde_json::from_str(text)
            .map(|history| PyHistory { history })
            .map_err(|e| PyValueError::new_err(format!("not a history: {e}")))
    }

    /// The history file at `path` (JSON, as `solve --json` writes it).
    #[staticmethod]
    fn load(path: PathBuf) -> PyResult<PyHistory> {
        let text = std::fs::read_to_string(&path)
            .map_err(|e| PyOSError::new_err(format!("cannot read {}: {e}", path.display())))?;
        serde_json::from_str(&text)
            .map(|history| PyHistory { history })
            .map_err(|e| PyValueError::new_err(format!("{}: not a history: {e}", path.display())))
    }

    /// The history as JSON text, as `solve --json` writes it.
    fn to_json(&self) -> PyResult<String> {
        serde_json::to_string_pretty(&self.history)
            .map_err(|e| PyValueError::new_err(e.to_string()))
    }

    /// Write the history to `path` as JSON, atomically (a temporary file, then a rename).
    fn save(&self, path: PathBuf) -> PyResult<()> {
        self.history
            .write_json(&path)
            .map_err(|e| PyOSError::new_err(format!("cannot write {}: {e}", path.display())))
    }

    /// The scene's name.
    #[getter]
    fn scene(&self) -> String {
        self.history.scene.clone()
    }

    /// Why the run stopped early (None: it made every step it was asked for).
    #[getter]
    fn error(&self) -> Option<String> {
        self.history.error.clone()
    }

    /// User ids of the nodes, in the order of `positions`.
    #[getter]
    fn node_ids(&self) -> Vec<u32> {
        self.history.node_ids.clone()
    }

    /// How each increment met the equilibrium test: "converged", "roundoff" (accepted at the
    /// round-off floor of the residual), or "snapping" (a state on the way of a snap, not in
    /// equilibrium).
    #[getter]
    fn statuses(&self) -> Vec<&'static str> {
        (self.history.increments.iter())
            .map(|r| match r.status {
                IncrementStatus::Converged => "converged",
                IncrementStatus::RoundOff { .. } => "roundoff",
                IncrementStatus::Snapping { .. } => "snapping",
            })
            .collect()
    }

    /// The number of accepted increments.
    fn __len__(&self) -> usize {
        self.history.increments.len()
    }

    /// Record `k` (0-based) as JSON text.
    fn record_json(&self, k: usize) -> PyResult<String> {
        let r = (self.history.increments.get(k))
            .ok_or_else(|| PyKeyError::new_err(format!("no record {k}")))?;
        serde_json::to_string(r).map_err(|e| PyValueError::new_err(e.to_string()))
    }

    /// The events (cut-backs and contact changes) as JSON text.
    fn events_json(&self) -> PyResult<String> {
        serde_json::to_string(&self.history.events)
            .map_err(|e| PyValueError::new_err(e.to_string()))
    }

    /// Array `name` as (bytes, shape): "positions" [increments, nodes, 3] (x, y, rotation),
    /// "prescribed" [increments, prescribed dofs], "load_factor", "increment", "iterations",
    /// "cutbacks", "relative_residual" [increments].
    fn array(&self, py: Python<'_>, name: &str) -> PyResult<(Py<PyBytes>, Vec<usize>)> {
        let incs = &self.history.increments;
        let n = incs.len();
        let per = |f: &dyn Fn(&tsm_contact::solver::IncrementRecord) -> f64| {
            (
                bytes_of(py, &incs.iter().map(f).collect::<Vec<_>>()),
                vec![n],
            )
        };
        Ok(match name {
            "positions" => {
                let nodes = self.history.node_ids.len();
                let v: Vec<f64> = (incs.iter())
                    .flat_map(|r| r.nodes.iter().flat_map(|s| s.iter().copied()))
                    .collect();
                if v.len() != n * nodes * 3 {
                    return Err(PyValueError::new_err(
                        "records differ in their number of nodes",
                    ));
                }
                (bytes_of(py, &v), vec![n, nodes, 3])
            }
            "prescribed" => {
                let k = incs.first().map_or(0, |r| r.prescribed.len());
                if incs.iter().any(|r| r.prescribed.len() != k) {
                    return Err(PyValueError::new_err(
                        "records differ in their prescribed dofs",
                    ));
                }
                let v: Vec<f64> = incs
                    .iter()
                    .flat_map(|r| r.prescribed.iter().copied())
                    .collect();
                (bytes_of(py, &v), vec![n, k])
            }
            "load_factor" => per(&|r| r.load_factor),
            "increment" => per(&|r| r.increment as f64),
            "iterations" => per(&|r| r.iterations as f64),
            "cutbacks" => per(&|r| r.cutbacks as f64),
            "relative_residual" => per(&|r| r.relative_residual),
            _ => return Err(PyKeyError::new_err(format!("no array named {name:?}"))),
        })
    }

    /// Table `name` ("contacts", "obstacle_contacts" or "reactions") as a dict of columns:
    /// numbers as (bytes, length), text as lists; every table has an "increment" column.
    fn table<'py>(&self, py: Python<'py>, name: &str) -> PyResult<Bound<'py, PyDict>> {
        let cols = self.columns(name)?;
        let out = PyDict::new(py);
        for (key, col) in cols {
            match col {
                Column::Numbers(v) => out.set_item(key, (bytes_of(py, &v), v.len()))?,
                Column::Text(v) => out.set_item(key, v)?,
            }
        }
        Ok(out)
    }
}

impl PyHistory {
    /// The columns of table `name`.
    fn columns(&self, name: &str) -> PyResult<Vec<(&'static str, Column)>> {
        let incs = &self.history.increments;
        let num = |f: &dyn Fn(usize) -> Vec<f64>| -> Column {
            Column::Numbers(incs.iter().enumerate().flat_map(|(k, _)| f(k)).collect())
        };
        let text = |f: &dyn Fn(usize) -> Vec<String>| -> Column {
            Column::Text(incs.iter().enumerate().flat_map(|(k, _)| f(k)).collect())
        };
        Ok(match name {
            "contacts" => {
                let cs = |k: usize| &incs[k].contacts;
                let each = |g: &dyn Fn(&tsm_contact::solver::report::ContactState) -> f64| {
                    num(&|k| cs(k).iter().map(g).collect())
                };
                vec![
                    (
                        "increment",
                        num(&|k| vec![incs[k].increment as f64; cs(k).len()]),
                    ),
                    ("node", each(&|c| f64::from(c.node))),
                    ("element", each(&|c| c.element as f64)),
                    ("place", each(&|c| c.place as f64)),
                    (
                        "body",
                        text(&|k| cs(k).iter().map(|c| c.body.clone()).collect()),
                    ),
                    ("xi", each(&|c| c.xi)),
                    ("force", each(&|c| c.force)),
                    ("pressure", each(&|c| c.pressure)),
                    ("tangential", each(&|c| c.tangential)),
                ]
            }
            "obstacle_contacts" => {
                let cs = |k: usize| &incs[k].obstacle_contacts;
                let each = |g: &dyn Fn(&tsm_contact::solver::ObstacleState) -> f64| {
                    num(&|k| cs(k).iter().map(g).collect())
                };
                vec![
                    (
                        "increment",
                        num(&|k| vec![incs[k].increment as f64; cs(k).len()]),
                    ),
                    ("node", each(&|c| f64::from(c.node))),
                    (
                        "obstacle",
                        text(&|k| cs(k).iter().map(|c| c.obstacle.clone()).collect()),
                    ),
                    ("force", each(&|c| c.force)),
                    ("gap", each(&|c| c.gap)),
                    ("x", each(&|c| c.point[0])),
                    ("y", each(&|c| c.point[1])),
                    ("tangential", each(&|c| c.tangential)),
                ]
            }
            "reactions" => {
                let rs = |k: usize| &incs[k].reactions;
                vec![
                    (
                        "increment",
                        num(&|k| vec![incs[k].increment as f64; rs(k).len()]),
                    ),
                    (
                        "node",
                        num(&|k| rs(k).iter().map(|r| f64::from(r.node)).collect()),
                    ),
                    (
                        "dof",
                        text(&|k| rs(k).iter().map(|r| r.dof.clone()).collect()),
                    ),
                    ("value", num(&|k| rs(k).iter().map(|r| r.value).collect())),
                ]
            }
            _ => return Err(PyKeyError::new_err(format!("no table named {name:?}"))),
        })
    }
}

/// A finding as Python sees it: (increment, node or None, body or None, the sentence).
type FindingRow = (usize, Option<u32>, Option<String>, String);

/// The independent audit of `history` (code that shares nothing with the solver's own
/// checks): every finding as (increment, node or None, body or None, text). An empty list: it
/// found nothing wrong.
#[pyfunction]
pub fn check(py: Python<'_>, history: &PyHistory) -> PyResult<Vec<FindingRow>> {
    let found = py
        .detach(|| audit_history(&history.history, None))
        .map_err(PyValueError::new_err)?;
    Ok(found
        .into_iter()
        .map(|f| (f.increment, f.node, f.body.clone(), f.to_string()))
        .collect())
}
