//! The run history: every increment record and event of a run, as written by `solve --json`
//! and the GUI's export. The schema is documented in `docs/history-format.md`.

use serde::{Deserialize, Serialize};

use crate::solver::report::Flow;
use crate::solver::{Event, Formulation, IncrementRecord, IterationRecord, Observer, SolverParams};

/// A whole run.
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
pub struct History {
    /// Scene name.
    pub scene: String,
    /// Element formulation used.
    pub formulation: Option<Formulation>,
    /// Solver parameters used.
    pub params: Option<SolverParams>,
    /// User ids of the nodes, in the order of `IncrementRecord::nodes`.
    pub node_ids: Vec<u32>,
    /// Converged increments, in order.
    pub increments: Vec<IncrementRecord>,
    /// Every event in order (cut-backs and contact changes).
    pub events: Vec<Event>,
    /// Why the run stopped early, if it did.
    pub error: Option<String>,
}

impl Observer for History {
    fn iteration(&mut self, _r: &IterationRecord) -> Flow {
        Flow::Continue
    }
    fn increment(&mut self, r: &IncrementRecord) -> Flow {
        self.increments.push(r.clone());
        Flow::Continue
    }
    fn event(&mut self, e: &Event) {
        self.events.push(e.clone());
    }
}

impl History {
    /// Write as pretty JSON, atomically (temporary file, then rename).
    pub fn write_json(&self, path: &std::path::Path) -> std::io::Result<()> {
        let text = serde_json::to_string_pretty(self).map_err(std::io::Error::other)?;
        write_atomic(path, text.as_bytes())
    }
}

/// Write a file atomically: a temporary file beside it, then a rename.
pub fn write_atomic(path: &std::path::Path, bytes: &[u8]) -> std::io::Result<()> {
    let mut tmp = path.as_os_str().to_owned();
    tmp.push(".tmp");
    let tmp = std::path::PathBuf::from(tmp);
    std::fs::write(&tmp, bytes)?;
    std::fs::rename(&tmp, path)
}
