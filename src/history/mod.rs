//! The run history: every increment record and event of a run, as written by `solve --json`
//! and the GUI's export, with the model's topology (`topology.rs`) so that it describes itself.
//! The schema is documented in `docs/history-format.md`.

pub mod topology;

use std::path::Path;

use serde::{Deserialize, Serialize};

use crate::solver::report::Flow;
use crate::solver::{
    Event, Formulation, IncrementRecord, IterationRecord, Model, Observer, SolverParams,
};
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
    /// User ids of the nodes, in the order of `IncrementRecord::nodes`.
    pub node_ids: Vec<u32>,
    /// The model's topology (absent from version 1 histories).
    #[serde(default)]
    pub topology: Option<Topology>,
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

/// Why `path` may not be written as an output, if it may not: it is (or links to) one of
/// `inputs`, is a symbolic link (refused rather than followed or replaced), is not a regular
/// file (a folder, a FIFO, a device), or its folder does not exist. Checked before a run, so that
/// a long solve does not end in "cannot write".
pub fn output_problem(path: &Path, inputs: &[&Path]) -> Option<String> {
    if let Ok(meta) = std::fs::symlink_metadata(path) {
        if meta.file_type().is_symlink() {
            return Some("it is a symbolic link: name the file itself".into());
        }
        if !meta.is_file() {
            return Some("it is not a regular file (a folder, a FIFO or a device)".into());
        }
        let same = |input: &Path| match (std::fs::canonicalize(path), std::fs::canonicalize(input))
        {
            (Ok(a), Ok(b)) => a == b,
            _ => false,
        };
        if inputs.iter().any(|i| same(i)) {
            return Some("it is the input scene, which writing there would overwrite".into());
        }
    }
    let folder = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    };
    if !folder.is_dir() {
        return Some(format!("its folder {} does not exist", folder.display()));
    }
    None
}

/// Write a file atomically: a temporary file beside it, then a rename. Refuses what
/// `output_problem` refuses; on any failure the temporary file is removed.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    if let Some(why) = output_problem(path, &[]) {
        return Err(std::io::Error::other(why));
    }
    let mut tmp = path.as_os_str().to_owned();
    tmp.push(".tmp");
    let tmp = std::path::PathBuf::from(tmp);
    let written = std::fs::write(&tmp, bytes).and_then(|()| std::fs::rename(&tmp, path));
    if written.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    written
}

/// A history written as the run goes, so that a run of any length holds no increment in
/// memory: the header, then every increment as it is accepted, and the events and the error
/// when the run ends (`finish`). The file is a temporary one beside the target until then, and
/// is removed if the writer is dropped unfinished. The JSON is `History`'s.
pub struct HistoryWriter {
    out: std::io::BufWriter<std::fs::File>,
    tmp: std::path::PathBuf,
    path: std::path::PathBuf,
    increments: usize,
    events: Vec<Event>,
    finished: bool,
}

impl HistoryWriter {
    /// Start writing `header` (its increments, events and error are left out) to `path`;
    /// refuses what `output_problem` refuses.
    pub fn create(path: &Path, header: &History) -> std::io::Result<HistoryWriter> {
        use std::io::Write;
        if let Some(why) = output_problem(path, &[]) {
            return Err(std::io::Error::other(why));
        }
        let mut tmp = path.as_os_str().to_owned();
        tmp.push(".tmp");
        let tmp = std::path::PathBuf::from(tmp);
        let file = std::fs::File::create(&tmp)?;
        let mut writer = HistoryWriter {
            out: std::io::BufWriter::new(file),
            tmp,
            path: path.to_path_buf(),
            increments: 0,
            events: Vec::new(),
            finished: false,
        };
        write!(
            writer.out,
            "{{\"format_version\":{},\"scene\":{},\"formulation\":{},\"params\":{},\"node_ids\":{},\"topology\":{},\"increments\":[",
            header.format_version,
            json(&header.scene),
            json(&header.formulation),
            json(&header.params),
            json(&header.node_ids),
            json(&header.topology)
        )?;
        Ok(writer)
    }

    /// Write one accepted increment.
    pub fn increment(&mut self, r: &IncrementRecord) -> std::io::Result<()> {
        use std::io::Write;
        if self.increments > 0 {
            self.out.write_all(b",")?;
        }
        serde_json::to_writer(&mut self.out, r).map_err(std::io::Error::other)?;
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
        let events = serde_json::to_string(&self.events).map_err(std::io::Error::other)?;
        let error = serde_json::to_string(&error).map_err(std::io::Error::other)?;
        write!(self.out, "],\"events\":{events},\"error\":{error}}}")?;
        self.out.flush()?;
        std::fs::rename(&self.tmp, &self.path)?;
        self.finished = true;
        Ok(())
    }
}

impl Drop for HistoryWriter {
    fn drop(&mut self) {
        if !self.finished {
            let _ = std::fs::remove_file(&self.tmp);
        }
    }
}

/// The JSON text of a header field (`null` where it cannot be written).
fn json<T: Serialize>(v: &T) -> String {
    serde_json::to_string(v).unwrap_or_else(|_| "null".into())
}
