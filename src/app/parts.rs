//! The parts of the app's state, each with one owner: the study (scene, history, drive, runs
//! set aside), the playback, what the user looks at, the files, the notices and the window's
//! run-time state; and the actions a panel asks of the app beyond the parts it is given
//! (`TsmApp::apply` applies them once the panels have drawn).

use crate::figure::Diagram;
use crate::solver::{Event, IncrementRecord, IterationRecord};
use crate::worker::{Command, Failure, Loaded};

use super::branches::SetAside;
use super::display::{Angles, Picked, TableView};
use super::files::dialog::{Dialogs, Purpose};
use super::files::scenes::Recent;
use super::files::screenshot::{Layout, Shot};
use super::frame_log::FrameLog;
use super::retention::KeptHistory;
use super::view::{Drag, View};

/// What is being solved and what it produced: the scene, the converged states and events,
/// the drive's targets, and the runs set aside for Undo and Redo.
#[derive(Default)]
pub struct Study {
    /// Name the current scene was opened by (built-in name or path).
    pub(crate) scene_name: String,
    pub(crate) loaded: Option<Box<Loaded>>,
    /// Converged states; `history[0]` is the undeformed state.
    pub(crate) history: KeptHistory,
    pub(crate) events: Vec<Event>,
    /// Iterations of the increment being solved.
    pub(crate) live: Vec<IterationRecord>,
    /// Whether the worker is solving.
    pub(crate) busy: bool,
    /// Target value of every prescribed dof (what the sliders and the handle show).
    pub(crate) targets: Vec<f64>,
    /// Whether the targets are being driven (a slider or handle held).
    pub(crate) targeting: bool,
    /// Steps to run once the scene is loaded.
    pub(crate) run_steps: Option<usize>,
    /// Histories set aside (a branch's later increments, a run before a change), newest last.
    pub(crate) undo: Vec<SetAside>,
    /// Histories Undo replaced, newest last (cleared by a new branch or change).
    pub(crate) redo: Vec<SetAside>,
    /// The increments the shown history branched at (marked on the timeline).
    pub(crate) branch_points: Vec<usize>,
    /// Messages of work set aside are still coming: skip them until the worker says it is
    /// loaded or restored (or fails).
    pub(crate) stale: bool,
    /// A run brought back by Undo, taken up when its scene is loaded again.
    pub(crate) restoring: Option<SetAside>,
    /// Counts the scenes loaded: what the viewport's cached geometry belongs to.
    pub(crate) generation: u64,
}

impl Study {
    /// Index of the last converged state.
    pub fn last(&self) -> usize {
        self.history.len().saturating_sub(1)
    }

    /// "K increments accepted at the round-off floor (worst residual 4.1e-6)" and "M states on
    /// the way of a snap, not in equilibrium" when the history has any: the states that are not
    /// in equilibrium to the tolerance.
    pub fn marked_summary(&self) -> Option<String> {
        use crate::solver::IncrementStatus;
        let at_floor: Vec<f64> = (self.history.iter())
            .filter(|r| matches!(r.status, IncrementStatus::RoundOff { .. }))
            .map(|r| r.relative_residual)
            .collect();
        let worst = at_floor.iter().copied().fold(0.0f64, f64::max);
        let snapping = (self.history.iter())
            .filter(|r| matches!(r.status, IncrementStatus::Snapping { .. }))
            .count();
        let mut parts = Vec::new();
        if !at_floor.is_empty() {
            parts.push(format!(
                "{} increments accepted at the round-off floor (worst residual {worst:.1e})",
                at_floor.len()
            ));
        }
        if snapping > 0 {
            parts.push(format!(
                "{snapping} states on the way of a snap, not in equilibrium"
            ));
        }
        (!parts.is_empty()).then(|| parts.join("; "))
    }

    /// The state at index `selected` (the last one past the end), if a scene is loaded.
    pub fn record(&self, selected: usize) -> Option<&IncrementRecord> {
        self.history.get(selected.min(self.last()))
    }
}

/// The timeline's playback: the increment viewed and whether it advances by itself.
#[derive(Default)]
pub struct Playback {
    pub(crate) selected: usize,
    pub(crate) playing: bool,
    /// When playback last advanced (s, egui's clock).
    pub(crate) last_play: f64,
}

impl Playback {
    /// View state `k`; the replay stops.
    pub fn view(&mut self, k: usize) {
        self.selected = k;
        self.playing = false;
    }

    /// View the previous state (of `last` + 1).
    pub fn previous(&mut self, last: usize) {
        self.view(self.selected.min(last).saturating_sub(1));
    }

    /// View the next state; false at the last one (`last`), where the next is to be solved.
    pub fn next(&mut self, last: usize) -> bool {
        self.playing = false;
        if self.selected < last {
            self.selected += 1;
            true
        } else {
            false
        }
    }

    /// Start the replay (from the start when at the end, `last`) or pause it; `now` is egui's
    /// clock.
    pub fn toggle(&mut self, last: usize, now: f64) {
        self.playing = !self.playing;
        if self.playing && self.selected >= last {
            self.selected = 0;
        }
        self.last_play = now;
    }

    /// Advance the replay once `now` is a frame's time (50 ms) past the last advance; it stops
    /// at the last state (`last`). Returns whether it is still playing.
    pub fn advance(&mut self, last: usize, now: f64) -> bool {
        if self.playing && now - self.last_play >= 0.05 {
            self.last_play = now;
            if self.selected < last {
                self.selected += 1;
            } else {
                self.playing = false;
            }
        }
        self.playing
    }
}

/// What the user looks at and how: the camera, the diagram, the picked node or element, the
/// plots' and the table's choices.
pub struct Look {
    pub(crate) camera: View,
    /// Fit the camera to the model at the next frame.
    pub(crate) fit_pending: bool,
    /// A prescribed dof's handle being dragged.
    pub(crate) drag: Option<Drag>,
    /// The handle under the pointer.
    pub(crate) hover_handle: Option<usize>,
    /// The force diagram drawn along the beams, if any.
    pub(crate) diagram: Option<Diagram>,
    /// How rotations are shown.
    pub(crate) angles: Angles,
    /// The node or element clicked in the viewport, shown in the details panel.
    pub(crate) pinned: Option<Picked>,
    /// The dof of the selected node the response plot is drawn against (a node without a
    /// rotation: v in place of phi).
    pub(crate) plot_dof: crate::solver::Dof,
    /// Whether the convergence plot shows every increment (else the one viewed).
    pub(crate) plot_all: bool,
    /// The table window's choices.
    pub(crate) table: TableView,
    /// Whether the shortcuts window is open.
    pub(crate) show_shortcuts: bool,
}

/// Files: the dialog in progress, the scene files opened last, where exports go.
pub struct Files {
    /// The path typed into File > Open.
    pub(crate) open_path: String,
    /// The stem of the exports' file names.
    pub(crate) export_stem: String,
    /// The file dialog in progress.
    pub(crate) dialogs: Dialogs,
    /// The scene files opened last.
    pub(crate) recent: Recent,
    /// The size of the view's PNG export (px).
    pub(crate) png_size: [u32; 2],
}

/// What the app tells the user: the status line and the error panel.
#[derive(Default)]
pub struct Notices {
    pub(crate) status: String,
    pub(crate) error: Option<Failure>,
    /// Whether the error panel is shown (it opens with each new error).
    pub(crate) show_error: bool,
}

/// The window's run-time state, never saved: whether the beams go through wgpu, where the
/// last frame drew its parts, the screenshot run, the frame log, and whether settings persist.
pub struct Frame {
    pub(crate) gpu: bool,
    /// Where this frame drew the viewport and the convergence plot (for the screenshot sidecar).
    pub(crate) layout: Layout,
    pub(crate) shot: Option<Shot>,
    pub(crate) frame_log: Option<FrameLog>,
    /// Whether the settings are saved (not for a screenshot run).
    pub(crate) persist: bool,
}

/// What a panel asks of the app beyond the parts it was given, applied by the window once the
/// panels have drawn, in the order asked.
#[derive(Debug)]
pub enum Action {
    /// Send a command to the worker (a run, a step or a target marks the app busy).
    Send(Command),
    /// Change a setting of the scene (formulation, stretch correction): the run so far is set
    /// aside for Undo, then the command sent.
    Change(Command),
    /// Back to increment 0, the run set aside for Undo.
    Reset,
    /// Bring back what was set aside last (Ctrl+Z).
    Undo,
    /// Bring back what Undo replaced (Ctrl+Y).
    Redo,
    /// Drive prescribed dof `index` to `value` from the viewed increment.
    Drive {
        /// The prescribed dof (its place in the scene's list).
        index: usize,
        /// Its target value.
        value: f64,
    },
    /// Go on from the viewed increment, the later ones set aside.
    Branch,
    /// A handle let go with the run at its target: follow the converged states again.
    FollowRun,
    /// Open a scene by path or built-in name.
    Open(String),
    /// Show an error in the error panel.
    Fail(Failure),
    /// Write an export under the name in "Export as".
    Export(Export),
    /// Make the run shown the scene's load path.
    KeepDrive,
    /// Show a file dialog.
    Dialog(Purpose),
}

/// What an export writes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Export {
    /// The history as JSON.
    Json,
    /// The history as CSV, with the picked node's displacements.
    Csv,
    /// The history as JSON, then (if that was written) as CSV.
    History,
    /// The viewed increment as SVG.
    Svg,
    /// The viewed increment as a PNG of the chosen size.
    Png,
    /// The whole window as it is drawn.
    Window,
}
