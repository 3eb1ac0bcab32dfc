//! The run history: every increment record and event of a run, as written by `solve --json`
//! and the GUI's export, with the model's topology (`topology.rs`) so that it describes itself.
//! The schema is documented in `docs/history-format.md`.

pub mod output;
pub mod topology;

use std::path::Path;

use serde::{Deserialize, Serialize};

use crate::solver::report::Flow;
use crate::solver::{
    Event, Formulation, IncrementRecord, IterationRecord, Model, Observer, SolverParams,
};
pub use output::{output_problem, write_atomic, TempFile};
pub use topology::{Topology, FORMAT_VERSION};

/// A whole run.
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
pub struct History {
    /// The version of the format (`FORMAT_VERSION` when written by this program; 1 where
    /// absent, for histories that carry no topology).
    #[serde(default = "version_one")]
    pub format_version: u32,
    /// Scene name.
    pub scene: String,
    /// Element formulation used.
    pub formulation: Option<Formulation>,
    /// Solver parameters used.
    pub params: Option<SolverParams>,
    /// User ids of the nodes, in the order of [`IncrementRecord::nodes`].
    pub node_ids: Vec<u32>,
    /// The model's topology (absent from version 1 histories).
    #[serde(default)]
    pub topology: Option<Topology>,
    /// Kept every how many accepted increments (`solve --every N`), the last one always kept;
    /// absent: every one. A thinned history cannot tell what happened between the increments
    /// it keeps (a node may pass through a body and back), and `check` says so.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub every: Option<usize>,
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

/// The version of a history that names none.
fn version_one() -> u32 {
    1
}

impl History {
    /// An empty history of a run of `model`: the format version, the node ids and the
    /// topology filled in.
    pub fn of_model(
        scene: &str,
        model: &Model,
        formulation: Option<Formulation>,
        params: Option<SolverParams>,
    ) -> History {
        History {
            format_version: FORMAT_VERSION,
            scene: scene.to_string(),
            formulation,
            params,
            node_ids: model.nodes.iter().map(|n| n.id).collect(),
            topology: Some(Topology::of(model)),
            ..History::default()
        }
    }

    /// Write as pretty JSON, atomically (temporary file, then rename).
    pub fn write_json(&self, path: &Path) -> std::io::Result<()> {
        let text = serde_json::to_string_pretty(self).map_err(std::io::Error::other)?;
        write_atomic(path, text.as_bytes())
    }
}

/// A history written as the run goes, so that a run of any length holds no increment in
/// memory: the header, then every increment as it is accepted, and the events and the error
/// when the run ends (`finish`). The file is a temporary one beside the target until then
/// (`TempFile`), and is removed if the writer is dropped unfinished. The JSON is `History`'s.
pub struct HistoryWriter {
    out: std::io::BufWriter<TempFile>,
    increments: usize,
    /// Keep every how many accepted increments (1: all), how many were accepted, and the last
    /// one not kept (written at the end, so that the history ends where the run did).
    every: usize,
    accepted: usize,
    held: Option<IncrementRecord>,
    events: Vec<Event>,
    /// Bytes written so far, and the most the history may take.
    bytes: u64,
    limit: u64,
}

/// The most a history file may take unless asked otherwise (`solve --max-output`): 1 GiB.
pub const DEFAULT_MAX_OUTPUT: u64 = 1 << 30;

impl HistoryWriter {
    /// Start writing `header` (its increments, events and error are left out) to `path`, in
    /// at most `limit` bytes, keeping every `header.every`-th accepted increment (and the
    /// last); refuses what `output_problem` refuses.
    pub fn create(path: &Path, header: &History, limit: u64) -> std::io::Result<HistoryWriter> {
        use std::io::Write;
        let every = header.every.unwrap_or(1).max(1);
        let mut writer = HistoryWriter {
            out: std::io::BufWriter::new(TempFile::create(path)?),
            increments: 0,
            every,
            accepted: 0,
            held: None,
            events: Vec::new(),
            bytes: 0,
            limit,
        };
        let thinned = if every > 1 {
            format!("\"every\":{every},")
        } else {
            String::new()
        };
        write!(
            writer.out,
            "{{\"format_version\":{},\"scene\":{},\"formulation\":{},\"params\":{},\"node_ids\":{},\"topology\":{},{thinned}\"increments\":[",
            header.format_version,
            json(&header.scene),
            json(&header.formulation),
            json(&header.params),
            json(&header.node_ids),
            json(&header.topology)
        )?;
        Ok(writer)
    }

    /// Take one accepted increment: written if it is one to keep, else held until the next
    /// (the last is written by `finish`); an error once the history would take more than its
    /// limit.
    pub fn increment(&mut self, r: &IncrementRecord) -> std::io::Result<()> {
        self.accepted += 1;
        if !self.accepted.is_multiple_of(self.every) {
            self.held = Some(r.clone());
            return Ok(());
        }
        self.held = None;
        self.write_increment(r)
    }

    /// Write one increment record.
    fn write_increment(&mut self, r: &IncrementRecord) -> std::io::Result<()> {
        use std::io::Write;
        let text = serde_json::to_vec(r).map_err(std::io::Error::other)?;
        self.bytes += text.len() as u64 + 1;
        if self.bytes > self.limit {
            return Err(std::io::Error::other(format!(
                "the history would take more than {} bytes at increment {} (--max-output)",
                self.limit, r.increment
            )));
        }
        if self.increments > 0 {
            self.out.write_all(b",")?;
        }
        self.out.write_all(&text)?;
        self.increments += 1;
        Ok(())
    }

    /// Keep an event for the end of the file.
    pub fn event(&mut self, e: &Event) {
        self.events.push(e.clone());
    }

    /// Write the events and `error`, and move the file into place.
    pub fn finish(mut self, error: Option<String>) -> std::io::Result<()> {
        use std::io::Write;
        if let Some(last) = self.held.take() {
            self.write_increment(&last)?;
        }
        let events = serde_json::to_string(&self.events).map_err(std::io::Error::other)?;
        let error = serde_json::to_string(&error).map_err(std::io::Error::other)?;
        write!(self.out, "],\"events\":{events},\"error\":{error}}}")?;
        let tmp = self.out.into_inner().map_err(|e| e.into_error())?;
        tmp.commit()
    }
}

/// The JSON text of a header field (`null` where it cannot be written).
fn json<T: Serialize>(v: &T) -> String {
    serde_json::to_string(v).unwrap_or_else(|_| "null".into())
}
