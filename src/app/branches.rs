//! What a branch or a change sets aside. A drive moved while an earlier increment is viewed
//! goes on from that increment, and the later ones are set aside; a changed setting or another
//! scene starts again from increment 0, and the old run is set aside whole. Undo (Ctrl+Z)
//! brings back what was set aside last, exactly as it was, and sets aside what it replaces for
//! Redo (Ctrl+Y); `undo.rs` does it.

use crate::scene::Scene;
use crate::solver::{Checkpoint, Event};

use super::retention::{KeptHistory, Tail};
use std::sync::Arc;

/// How many set-aside histories Undo can bring back.
pub const UNDO_DEPTH: usize = 16;

/// A history set aside, to bring back with Undo.
#[derive(Debug)]
pub enum SetAside {
    /// The increments after a branch point (`tail.at - 1` is the kept record branched from).
    Branch {
        /// The records set aside.
        tail: Tail,
        /// Their events.
        events: Vec<Event>,
        /// Whether they are the branch (brought back by Redo) rather than the path it left.
        branched: bool,
    },
    /// A whole run, before a change of scene or setting.
    Run {
        /// The scene (with the settings) it was solved with.
        scene: Box<Scene>,
        /// Its history.
        history: KeptHistory,
        /// Its events.
        events: Vec<Event>,
        /// The increment viewed.
        selected: usize,
        /// The name the scene was opened by.
        name: String,
        /// Its branch points.
        branches: Vec<usize>,
    },
}

impl SetAside {
    /// The bytes its records take.
    pub fn bytes(&self) -> usize {
        match self {
            SetAside::Branch { tail, .. } => tail.bytes(),
            SetAside::Run { history, .. } => history.bytes(),
        }
    }

    /// What Undo brings back, in words ("increments 21 to 40").
    pub fn describe(&self) -> String {
        match self {
            SetAside::Branch { tail, .. } => {
                match (tail.records().first(), tail.records().last()) {
                    (Some(a), Some(b)) => format!("increments {} to {}", a.increment, b.increment),
                    _ => "the increments after the branch point".into(),
                }
            }
            SetAside::Run { history, name, .. } => format!(
                "the run of {} to increment {}",
                short_name(name),
                history.last().map_or(0, |r| r.increment)
            ),
        }
    }
}

/// The file name of a scene path without `.ron` (or the built-in name).
pub fn short_name(name: &str) -> String {
    let base = std::path::Path::new(name)
        .file_name()
        .map_or(name.into(), |f| f.to_string_lossy().to_string());
    base.trim_end_matches(".ron").to_string()
}

/// Split `events` into those up to increment `last` (kept) and the later ones (returned).
pub fn events_after(events: &mut Vec<Event>, last: usize) -> Vec<Event> {
    let at = events.partition_point(|e| e.increment() <= last);
    events.split_off(at)
}

/// The checkpoint to go on from after the last record of `history` (the undeformed state's,
/// `initial`, if none other was sent).
pub fn end_checkpoint(history: &KeptHistory, initial: &Arc<Checkpoint>) -> Arc<Checkpoint> {
    (0..history.len())
        .rev()
        .find_map(|k| history.checkpoint(k))
        .unwrap_or_else(|| initial.clone())
}
