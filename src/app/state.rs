//! `TsmApp`: the visualiser's state (the worker handle, the converged history, the selection,
//! the camera, the targets of the prescribed dofs) and draining the worker's messages each
//! frame without blocking. The panels read and change it; `window.rs` lays them out.

use std::path::PathBuf;
use std::sync::atomic::AtomicI32;
use std::sync::Arc;

use crate::solver::{Event, IncrementRecord, IterationRecord};
use crate::worker::{Command, Failure, Loaded, Message, Worker};

use super::branches::SetAside;
use super::display::{Angles, Picked, TableView};
use super::frame_log::FrameLog;
use crate::figure::Diagram;

use super::files::dialog::Dialogs;
use super::files::scenes::{is_file, Recent};
use super::files::screenshot::{Layout, Shot};
use super::retention::{KeptHistory, HISTORY_BUDGET};
use super::view::{Drag, View};

/// How the app starts.
#[derive(Clone, Debug, Default)]
pub struct Startup {
    /// Scene file or built-in name (default: the persisted one, else the first built-in).
    pub scene: Option<String>,
    /// Steps to solve right after loading.
    pub steps: Option<usize>,
    /// Render this PNG after the steps and close.
    pub screenshot: Option<PathBuf>,
    /// Exit code written by the screenshot run (0 = saved).
    pub exit: Option<Arc<AtomicI32>>,
    /// Draw the beams with the egui painter even when wgpu is available (also `TSM_NO_GPU`).
    pub no_gpu: bool,
    /// The force diagram to draw along the beams.
    pub diagram: Option<Diagram>,
    /// The scene remembered from the last time the app ran (default: the one eframe stored).
    pub remembered: Option<String>,
}

impl Startup {
    /// Start on a scene.
    pub fn scene(name: &str) -> Startup {
        Startup {
            scene: Some(name.into()),
            ..Startup::default()
        }
    }
}

/// The visualiser: the worker and the app's state in parts, each with one owner. The panels
/// read the parts they show and change the parts they drive.
pub struct TsmApp {
    pub(crate) worker: Worker,
    /// The scene, the history held, the drive's targets and the runs set aside.
    pub(crate) session: Session,
    /// The timeline's playback and the increment viewed.
    pub(crate) playback: Playback,
    /// What the user looks at and how.
    pub(crate) look: Look,
    /// Dialogs, recent files and exports.
    pub(crate) files: Files,
    /// The status line and the error panel.
    pub(crate) notices: Notices,
    /// The window's run-time state (drawing path, layout, screenshot run, frame log).
    pub(crate) frame: Frame,
}

/// What is being solved and what it produced: the scene, the converged states and events,
/// the drive's targets, and the runs set aside for Undo and Redo.
#[derive(Default)]
pub(crate) struct Session {
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

/// The timeline's playback: the increment viewed and whether it advances by itself.
#[derive(Default)]
pub(crate) struct Playback {
    pub(crate) selected: usize,
    pub(crate) playing: bool,
    /// When playback last advanced (s, egui's clock).
    pub(crate) last_play: f64,
}

/// What the user looks at and how: the camera, the diagram, the picked node or element, the
/// plots' and the table's choices.
pub(crate) struct Look {
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
pub(crate) struct Files {
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
pub(crate) struct Notices {
    pub(crate) status: String,
    pub(crate) error: Option<Failure>,
    /// Whether the error panel is shown (it opens with each new error).
    pub(crate) show_error: bool,
}

/// The window's run-time state, never saved: whether the beams go through wgpu, where the
/// last frame drew its parts, the screenshot run, the frame log, and whether settings persist.
pub(crate) struct Frame {
    pub(crate) gpu: bool,
    /// Where this frame drew the viewport and the convergence plot (for the screenshot sidecar).
    pub(crate) layout: Layout,
    pub(crate) shot: Option<Shot>,
    pub(crate) frame_log: Option<FrameLog>,
    /// Whether the settings are saved (not for a screenshot run).
    pub(crate) persist: bool,
}

impl TsmApp {
    /// Load a scene by path or built-in name and hand it to the worker (the run so far set
    /// aside for Undo). A scene that cannot be loaded leaves the current one in place, and its
    /// located error is shown.
    pub fn open(&mut self, name: &str) {
        match crate::scene::builtin::open(name).map_err(|e| e.to_string()) {
            Ok(scene) => {
                self.set_aside_run();
                self.session.scene_name = name.to_string();
                if is_file(name) {
                    self.files.recent.opened(std::path::Path::new(name));
                }
                self.notices.error = None;
                self.notices.status = format!("loading {}", scene.file.name);
                self.worker.send(Command::LoadScene(Box::new(scene)));
            }
            Err(e) => {
                if let Some(shot) = &mut self.frame.shot {
                    shot.fail(&e);
                }
                self.set_error(e);
            }
        }
    }

    /// Show `e` in the error panel.
    pub(crate) fn set_error(&mut self, e: impl Into<Failure>) {
        self.notices.error = Some(e.into());
        self.notices.show_error = true;
    }

    /// The error shown, if any, in words.
    pub fn error(&self) -> Option<String> {
        self.notices.error.as_ref().map(|e| e.to_string())
    }

    /// The status line's text.
    pub fn status(&self) -> &str {
        &self.notices.status
    }

    /// The converged states held: the undeformed state, then the increments.
    pub fn history(&self) -> &[IncrementRecord] {
        &self.session.history
    }

    /// The events of the history held.
    pub fn events(&self) -> &[Event] {
        &self.session.events
    }

    /// The name the current scene was opened by (a path or a built-in name).
    pub fn scene_name(&self) -> &str {
        &self.session.scene_name
    }

    /// The scene files opened last, newest first (File > Open recent).
    pub fn recent_files(&self) -> &[std::path::PathBuf] {
        self.files.recent.files()
    }

    /// Whether a file dialog is open.
    pub fn dialog_open(&self) -> bool {
        self.files.dialogs.open()
    }

    /// How many file dialogs the app has shown.
    pub fn dialogs_shown(&self) -> usize {
        self.files.dialogs.shown()
    }

    /// Send a command to the worker (and note that work was requested).
    pub(crate) fn send(&mut self, c: Command) {
        if matches!(
            c,
            Command::Run | Command::RunSteps(_) | Command::Step | Command::SetTarget { .. }
        ) {
            self.session.busy = true;
        }
        self.worker.send(c);
    }

    /// Index of the last converged state.
    pub(crate) fn last(&self) -> usize {
        self.session.history.len().saturating_sub(1)
    }

    /// The selected state, if a scene is loaded.
    pub(crate) fn record(&self) -> Option<&IncrementRecord> {
        self.session
            .history
            .get(self.playback.selected.min(self.last()))
    }

    /// Number of converged increments so far.
    pub fn increments(&self) -> usize {
        self.last()
    }

    /// Send a command to the worker as the ui would (for scripted runs and tests).
    pub fn worker_command(&mut self, c: Command) {
        self.send(c);
    }

    /// The viewport drawn in the last frame, and where node `id` of the viewed increment lies
    /// in it (screen points), if a scene is loaded and has that node.
    pub fn node_on_screen(&self, id: u32) -> Option<(egui::Rect, egui::Pos2)> {
        let rect = self.frame.layout.viewport?;
        let model = &self.session.loaded.as_ref()?.scene.model;
        let n = model.nodes.iter().position(|x| x.id == id)?;
        let p = self.record()?.nodes.get(n)?;
        Some((rect, self.look.camera.to_screen(rect, [p[0], p[1]])))
    }

    /// Whether the beams go through the wgpu callback (else the egui-painter fallback).
    pub fn uses_gpu(&self) -> bool {
        self.frame.gpu
    }

    /// "K increments accepted at the round-off floor (worst 4.1e-6)" when the history has any
    /// (they are in equilibrium only to that residual, not to the tolerance).
    pub(crate) fn roundoff_summary(&self) -> Option<String> {
        let at_floor: Vec<f64> = (self.session.history.iter())
            .filter(|r| matches!(r.status, crate::solver::IncrementStatus::RoundOff { .. }))
            .map(|r| r.relative_residual)
            .collect();
        let worst = at_floor.iter().copied().fold(0.0f64, f64::max);
        (!at_floor.is_empty()).then(|| {
            format!(
                "{} increments accepted at the round-off floor (worst residual {worst:.1e})",
                at_floor.len()
            )
        })
    }

    /// Apply every waiting worker message. Never blocks.
    pub(crate) fn drain(&mut self) {
        while let Some(m) = self.worker.try_recv() {
            if self.session.stale
                && matches!(
                    m,
                    Message::Increment(_)
                        | Message::Checkpoint(_)
                        | Message::Iteration(_)
                        | Message::Event(_)
                )
            {
                continue;
            }
            match m {
                Message::Checkpoint(c) => self.session.history.attach(c),
                Message::Restored(_) => self.session.stale = false,
                Message::Loaded(l) => {
                    self.session.stale = false;
                    self.session.history.reset(l.initial.clone());
                    self.session.history.attach(l.checkpoint.clone());
                    self.session.branch_points.clear();
                    self.session.targets = l.initial.prescribed.clone();
                    self.notices.status = format!(
                        "{} elements ({:?})",
                        l.scene.model.beams.len(),
                        l.scene.model.formulation
                    );
                    self.session.loaded = Some(l);
                    // A scene opened in the app is fitted to the viewport.
                    self.look.fit_pending = true;
                    self.look.pinned = None;
                    self.session.generation += 1;
                    self.session.events.clear();
                    self.session.live.clear();
                    self.playback.selected = 0;
                    if let Some(k) = self.session.run_steps.take() {
                        self.send(Command::RunSteps(k));
                    }
                    if let Some(run) = self.session.restoring.take() {
                        let _ = self.take_back(run);
                    }
                    if let Some(shot) = &mut self.frame.shot {
                        shot.loaded(self.session.busy);
                    }
                }
                Message::Increment(r) => {
                    let follow = self.playback.selected >= self.last();
                    if !self.session.targeting {
                        self.session.targets = r.prescribed.clone();
                    }
                    let shown = self
                        .session
                        .history
                        .get(self.playback.selected)
                        .map(|h| h.increment);
                    if self.session.history.push(*r) {
                        self.notices.status = format!(
                            "{} earlier increments dropped from memory to stay within {} MiB",
                            self.session.history.dropped(),
                            HISTORY_BUDGET >> 20
                        );
                        if let Some(inc) = shown {
                            self.playback.selected = self.session.history.at_or_before(inc);
                        }
                    }
                    self.session.live.clear();
                    if follow {
                        self.playback.selected = self.last();
                    }
                }
                Message::Iteration(r) => self.session.live.push(r),
                Message::Event(e) => self.session.events.push(e),
                Message::Error(e) => {
                    self.session.stale = false;
                    if let Some(shot) = &mut self.frame.shot {
                        shot.record_failure(&e.to_string());
                    }
                    self.set_error(e);
                    self.session.live.clear();
                }
                Message::Busy => {
                    self.session.busy = true;
                    if let Some(shot) = &mut self.frame.shot {
                        shot.started();
                    }
                }
                Message::Idle => {
                    self.session.busy = false;
                    // Iterations of an abandoned attempt.
                    self.session.live.clear();
                    if self.session.targeting && self.look.drag.is_none() {
                        self.session.targeting = false;
                        if let Some(r) = self.session.history.last() {
                            self.session.targets = r.prescribed.clone();
                        }
                    }
                    if let Some(shot) = &mut self.frame.shot {
                        if shot.idle() {
                            self.playback.selected = self.last();
                            self.look.fit_pending = true;
                        }
                    }
                }
            }
        }
    }

    /// Advance the playback of the timeline.
    pub(crate) fn play(&mut self, ctx: &egui::Context) {
        if !self.playback.playing {
            return;
        }
        let now = ctx.input(|i| i.time);
        if now - self.playback.last_play >= 0.05 {
            self.playback.last_play = now;
            if self.playback.selected < self.last() {
                self.playback.selected += 1;
            } else {
                self.playback.playing = false;
            }
        }
        ctx.request_repaint_after(std::time::Duration::from_millis(16));
    }
}
