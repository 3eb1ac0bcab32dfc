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

/// The visualiser.
pub struct TsmApp {
    pub(crate) worker: Worker,
    /// Name the current scene was opened by (built-in name or path).
    pub(crate) scene_name: String,
    pub(crate) loaded: Option<Box<Loaded>>,
    /// Converged states; `history[0]` is the undeformed state.
    pub(crate) history: KeptHistory,
    pub(crate) events: Vec<Event>,
    /// Iterations of the increment being solved.
    pub(crate) live: Vec<IterationRecord>,
    pub(crate) selected: usize,
    pub(crate) busy: bool,
    pub(crate) playing: bool,
    pub(crate) last_play: f64,
    pub(crate) view: View,
    pub(crate) fit_pending: bool,
    /// Target value of every prescribed dof (what the sliders and the handle show).
    pub(crate) targets: Vec<f64>,
    pub(crate) targeting: bool,
    pub(crate) plot_all: bool,
    pub(crate) status: String,
    pub(crate) error: Option<Failure>,
    pub(crate) open_path: String,
    pub(crate) export_stem: String,
    pub(crate) gpu: bool,
    pub(crate) shot: Option<Shot>,
    /// Where this frame drew the viewport and the convergence plot (for the screenshot sidecar).
    pub(crate) layout: Layout,
    pub(crate) run_steps: Option<usize>,
    pub(crate) drag: Option<Drag>,
    pub(crate) hover_handle: Option<usize>,
    pub(crate) frame_log: Option<FrameLog>,
    pub(crate) persist: bool,
    /// The force diagram drawn along the beams, if any.
    pub(crate) diagram: Option<Diagram>,
    /// How rotations are shown.
    pub(crate) angles: Angles,
    /// The node or element clicked in the viewport, shown in the details panel.
    pub(crate) pinned: Option<Picked>,
    /// Counts the scenes loaded: what the viewport's cached geometry belongs to.
    pub(crate) generation: u64,
    /// Whether the shortcuts window is open.
    pub(crate) show_shortcuts: bool,
    /// The dof of the selected node the response plot is drawn against (a node without a
    /// rotation: v in place of phi).
    pub(crate) plot_dof: crate::solver::Dof,
    /// The table window's choices.
    pub(crate) table: TableView,
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
    /// The file dialog in progress.
    pub(crate) dialogs: Dialogs,
    /// The scene files opened last.
    pub(crate) recent: Recent,
    /// The size of the view's PNG export (px).
    pub(crate) png_size: [u32; 2],
    /// Whether the error panel is shown (it opens with each new error).
    pub(crate) show_error: bool,
}

impl TsmApp {
    /// Load a scene by path or built-in name and hand it to the worker (the run so far set
    /// aside for Undo). A scene that cannot be loaded leaves the current one in place, and its
    /// located error is shown.
    pub fn open(&mut self, name: &str) {
        match crate::scene::builtin::open(name).map_err(|e| e.to_string()) {
            Ok(scene) => {
                self.set_aside_run();
                self.scene_name = name.to_string();
                if is_file(name) {
                    self.recent.opened(std::path::Path::new(name));
                }
                self.error = None;
                self.status = format!("loading {}", scene.file.name);
                self.worker.send(Command::LoadScene(Box::new(scene)));
            }
            Err(e) => {
                if let Some(shot) = &mut self.shot {
                    shot.fail(&e);
                }
                self.set_error(e);
            }
        }
    }

    /// Show `e` in the error panel.
    pub(crate) fn set_error(&mut self, e: impl Into<Failure>) {
        self.error = Some(e.into());
        self.show_error = true;
    }

    /// The error shown, if any, in words.
    pub fn error(&self) -> Option<String> {
        self.error.as_ref().map(|e| e.to_string())
    }

    /// The status line's text.
    pub fn status(&self) -> &str {
        &self.status
    }

    /// The converged states held: the undeformed state, then the increments.
    pub fn history(&self) -> &[IncrementRecord] {
        &self.history
    }

    /// The events of the history held.
    pub fn events(&self) -> &[Event] {
        &self.events
    }

    /// The name the current scene was opened by (a path or a built-in name).
    pub fn scene_name(&self) -> &str {
        &self.scene_name
    }

    /// The scene files opened last, newest first (File > Open recent).
    pub fn recent_files(&self) -> &[std::path::PathBuf] {
        self.recent.files()
    }

    /// Whether a file dialog is open.
    pub fn dialog_open(&self) -> bool {
        self.dialogs.open()
    }

    /// How many file dialogs the app has shown.
    pub fn dialogs_shown(&self) -> usize {
        self.dialogs.shown()
    }

    /// Send a command to the worker (and note that work was requested).
    pub(crate) fn send(&mut self, c: Command) {
        if matches!(
            c,
            Command::Run | Command::RunSteps(_) | Command::Step | Command::SetTarget { .. }
        ) {
            self.busy = true;
        }
        self.worker.send(c);
    }

    /// Index of the last converged state.
    pub(crate) fn last(&self) -> usize {
        self.history.len().saturating_sub(1)
    }

    /// The selected state, if a scene is loaded.
    pub(crate) fn record(&self) -> Option<&IncrementRecord> {
        self.history.get(self.selected.min(self.last()))
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
        let rect = self.layout.viewport?;
        let model = &self.loaded.as_ref()?.scene.model;
        let n = model.nodes.iter().position(|x| x.id == id)?;
        let p = self.record()?.nodes.get(n)?;
        Some((rect, self.view.to_screen(rect, [p[0], p[1]])))
    }

    /// Whether the beams go through the wgpu callback (else the egui-painter fallback).
    pub fn uses_gpu(&self) -> bool {
        self.gpu
    }

    /// "K increments accepted at the round-off floor (worst 4.1e-6)" when the history has any
    /// (they are in equilibrium only to that residual, not to the tolerance).
    pub(crate) fn roundoff_summary(&self) -> Option<String> {
        let at_floor: Vec<f64> = (self.history.iter())
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
            if self.stale
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
                Message::Checkpoint(c) => self.history.attach(c),
                Message::Restored(_) => self.stale = false,
                Message::Loaded(l) => {
                    self.stale = false;
                    self.history.reset(l.initial.clone());
                    self.history.attach(l.checkpoint.clone());
                    self.branch_points.clear();
                    self.targets = l.initial.prescribed.clone();
                    self.status = format!(
                        "{} elements ({:?})",
                        l.scene.model.beams.len(),
                        l.scene.model.formulation
                    );
                    self.loaded = Some(l);
                    // A scene opened in the app is fitted to the viewport.
                    self.fit_pending = true;
                    self.pinned = None;
                    self.generation += 1;
                    self.events.clear();
                    self.live.clear();
                    self.selected = 0;
                    if let Some(k) = self.run_steps.take() {
                        self.send(Command::RunSteps(k));
                    }
                    if let Some(run) = self.restoring.take() {
                        let _ = self.take_back(run);
                    }
                    if let Some(shot) = &mut self.shot {
                        shot.loaded(self.busy);
                    }
                }
                Message::Increment(r) => {
                    let follow = self.selected >= self.last();
                    if !self.targeting {
                        self.targets = r.prescribed.clone();
                    }
                    let shown = self.history.get(self.selected).map(|h| h.increment);
                    if self.history.push(*r) {
                        self.status = format!(
                            "{} earlier increments dropped from memory to stay within {} MiB",
                            self.history.dropped(),
                            HISTORY_BUDGET >> 20
                        );
                        if let Some(inc) = shown {
                            self.selected = self.history.at_or_before(inc);
                        }
                    }
                    self.live.clear();
                    if follow {
                        self.selected = self.last();
                    }
                }
                Message::Iteration(r) => self.live.push(r),
                Message::Event(e) => self.events.push(e),
                Message::Error(e) => {
                    self.stale = false;
                    if let Some(shot) = &mut self.shot {
                        shot.record_failure(&e.to_string());
                    }
                    self.set_error(e);
                    self.live.clear();
                }
                Message::Busy => {
                    self.busy = true;
                    if let Some(shot) = &mut self.shot {
                        shot.started();
                    }
                }
                Message::Idle => {
                    self.busy = false;
                    // Iterations of an abandoned attempt.
                    self.live.clear();
                    if self.targeting && self.drag.is_none() {
                        self.targeting = false;
                        if let Some(r) = self.history.last() {
                            self.targets = r.prescribed.clone();
                        }
                    }
                    if let Some(shot) = &mut self.shot {
                        if shot.idle() {
                            self.selected = self.last();
                            self.fit_pending = true;
                        }
                    }
                }
            }
        }
    }

    /// Advance the playback of the timeline.
    pub(crate) fn play(&mut self, ctx: &egui::Context) {
        if !self.playing {
            return;
        }
        let now = ctx.input(|i| i.time);
        if now - self.last_play >= 0.05 {
            self.last_play = now;
            if self.selected < self.last() {
                self.selected += 1;
            } else {
                self.playing = false;
            }
        }
        ctx.request_repaint_after(std::time::Duration::from_millis(16));
    }
}
