//! `TsmApp`: the worker and the app's state in parts (`parts.rs`); draining the worker's
//! messages each frame without blocking, the playback's clock, and applying what the panels
//! asked for (`apply`: runs, Undo, opening scenes, exports, the dialogs' answers). The panels
//! read and change the parts they are given; `window.rs` lays them out.

use std::path::{Path, PathBuf};

use crate::solver::{Event, IncrementRecord};
use crate::worker::{Command, Failure, Message, Worker};

use super::display::Picked;
use super::files::dialog::{Answer, Purpose};
use super::files::export;
use super::files::scenes::{dropped_scene, is_file, save_scene};
use super::files::screenshot::Shot;
use super::parts::{Action, Export, Files, Frame, Look, Notices, Playback, Study};
use super::retention::HISTORY_BUDGET;
use crate::figure::{raster, svg};

/// The visualiser: the worker and the app's state in parts, each with one owner. The panels
/// read the parts they show and change the parts they drive.
pub struct TsmApp {
    pub(crate) worker: Worker,
    /// The scene, the history held, the drive's targets and the runs set aside.
    pub(crate) study: Study,
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
    /// What the panels asked for this frame (`apply`).
    pub(crate) actions: Vec<Action>,
}

impl TsmApp {
    /// Load a scene by path or built-in name and hand it to the worker (the run so far set
    /// aside for Undo). A scene that cannot be loaded leaves the current one in place, and its
    /// located error is shown.
    pub fn open(&mut self, name: &str) {
        match crate::scene::builtin::open(name).map_err(|e| e.to_string()) {
            Ok(scene) => {
                self.set_aside_run();
                self.study.scene_name = name.to_string();
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
        &self.study.history
    }

    /// The events of the history held.
    pub fn events(&self) -> &[Event] {
        &self.study.events
    }

    /// The name the current scene was opened by (a path or a built-in name).
    pub fn scene_name(&self) -> &str {
        &self.study.scene_name
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
            self.study.busy = true;
        }
        self.worker.send(c);
    }

    /// Index of the last converged state.
    pub(crate) fn last(&self) -> usize {
        self.study.last()
    }

    /// The selected state, if a scene is loaded.
    pub(crate) fn record(&self) -> Option<&IncrementRecord> {
        self.study.record(self.playback.selected)
    }

    /// Apply what the panels asked for this frame, in order.
    pub(crate) fn apply(&mut self, ctx: &egui::Context) {
        for a in std::mem::take(&mut self.actions) {
            match a {
                Action::Send(c) => self.send(c),
                Action::Change(c) => {
                    self.set_aside_run();
                    self.send(c);
                }
                Action::Reset => {
                    self.playback.playing = false;
                    self.study.targeting = false;
                    self.set_aside_run();
                    self.worker.send(Command::Reset);
                }
                Action::Undo => self.undo(),
                Action::Redo => self.redo(),
                Action::Drive { index, value } => self.drive(index, value),
                Action::Branch => self.branch(),
                Action::FollowRun => self.study.targeting = false,
                Action::Open(name) => self.open(&name),
                Action::Fail(e) => self.set_error(e),
                Action::Export(Export::History) => {
                    if self.export(Export::Json) {
                        self.export(Export::Csv);
                    }
                }
                Action::Export(what) => {
                    self.export(what);
                }
                Action::KeepDrive => self.keep_drive(),
                Action::Dialog(purpose) => {
                    let folder = match purpose {
                        Purpose::ExportStem => Path::new(&self.files.export_stem)
                            .parent()
                            .map(Path::to_path_buf),
                        _ => folder_of(&self.study.scene_name),
                    };
                    self.files.dialogs.show(purpose, folder, ctx.clone());
                }
            }
        }
    }

    /// Write export `what` under the name in "Export as" and say what it did: its full path,
    /// or why it failed. Returns whether it wrote.
    fn export(&mut self, what: Export) -> bool {
        let stem = self.files.export_stem.trim().to_string();
        let path = |ext: &str| PathBuf::from(format!("{stem}.{ext}"));
        if what == Export::Window {
            if self.frame.shot.is_none() {
                let p = path("window.png");
                self.notices.status = format!("saving {}", p.display());
                self.frame.shot = Some(Shot::new(p, None, false));
            }
            return true;
        }
        let Some(loaded) = &self.study.loaded else {
            return false;
        };
        let record = self.record();
        let diagram = self.look.diagram;
        let done = match (what, record) {
            (Export::Json, _) => {
                let h = export::history(
                    loaded,
                    &self.study.history,
                    self.study.history.stride(),
                    &self.study.events,
                    self.error().as_deref(),
                );
                let p = path("json");
                h.write_json(&p).map(|_| p).map_err(|e| e.to_string())
            }
            (Export::Csv, _) => {
                let picked: Vec<usize> = match self.look.pinned {
                    Some(Picked::Node(n)) => vec![n],
                    _ => Vec::new(),
                };
                let p = path("csv");
                export::write_csv(&p, loaded, &self.study.history, &picked)
                    .map(|_| p)
                    .map_err(|e| e.to_string())
            }
            (Export::Svg, Some(r)) => {
                let p = path("svg");
                (svg::write_svg(&p, loaded, r, diagram).map(|_| p)).map_err(|e| e.to_string())
            }
            (Export::Png, Some(r)) => {
                let p = path("png");
                raster::write_png(&p, loaded, r, diagram, self.files.png_size).map(|_| p)
            }
            _ => return false,
        };
        let wrote = done.is_ok();
        self.confirm(done);
        wrote
    }

    /// Say what a write did: its full path, or why it failed.
    fn confirm(&mut self, what: Result<PathBuf, String>) {
        match what {
            Ok(p) => {
                let full = std::fs::canonicalize(&p).unwrap_or(p);
                self.notices.status = format!("wrote {}", full.display());
            }
            Err(e) => self.set_error(format!("export failed: {e}")),
        }
    }

    /// Keep the run shown as the scene's load path (`scene::kept::kept_path`): the loaded
    /// scene becomes the scene with those stages, which "Save scene as" then writes and which
    /// replays the run headless. Refused, with the reason shown, where the history kept in
    /// memory is not every increment of the run or the scene cannot take the path.
    fn keep_drive(&mut self) {
        let Some(loaded) = &self.study.loaded else {
            return;
        };
        if self.study.history.dropped() > 0 {
            self.set_error(
                "the run is longer than the history kept in memory: only whole runs can be kept \
                 as a path (export the history instead)"
                    .to_string(),
            );
            return;
        }
        let scene = &loaded.scene;
        let mut file = scene.file.clone();
        file.formulation = scene.model.formulation;
        file.control.stretch_correction = scene.params.stretch_correction;
        let records = self.study.history.get(1..).unwrap_or_default();
        let kept = crate::scene::kept::kept_path(&file, &scene.model, records)
            .and_then(|f| crate::scene::from_scene_file(f, &file.name).map_err(|e| e.to_string()));
        match kept {
            Ok(kept) => {
                let steps = kept.steps;
                if let Some(l) = &mut self.study.loaded {
                    l.scene = kept;
                }
                self.notices.status = format!(
                    "the run is kept as the scene's path ({steps} steps): Save scene as... writes it"
                );
            }
            Err(e) => self.set_error(format!("cannot keep the drive as a path: {e}")),
        }
    }

    /// Act on a closed dialog's answer and on a file dropped on the window.
    pub(crate) fn answers(&mut self, ctx: &egui::Context) {
        match self.files.dialogs.poll() {
            Some((purpose, Answer::Chosen(path))) => match purpose {
                Purpose::OpenScene => self.open(&path.to_string_lossy()),
                Purpose::SaveScene => self.save_scene_as(&path),
                Purpose::ExportStem => {
                    self.files.export_stem = path.with_extension("").to_string_lossy().into_owned();
                    self.notices.status = format!("exports go to {}.*", self.files.export_stem);
                }
            },
            Some((_, Answer::Unavailable)) => {
                self.notices.status = "no file dialog can be shown on this desktop (it needs a \
                                       desktop portal or zenity): type the path under File > \
                                       path, or in Export as"
                    .into();
            }
            Some((_, Answer::Cancelled)) | None => {}
        }
        match dropped_scene(ctx) {
            Some(Ok(path)) => self.open(&path.to_string_lossy()),
            Some(Err(why)) => self.set_error(why),
            None => {}
        }
    }

    /// Save the scene as solved to `path` (the dialog's answer, or a script's path), the drive
    /// kept as its path if it was.
    pub fn save_scene_as(&mut self, path: &Path) {
        let Some(loaded) = &self.study.loaded else {
            return;
        };
        let done = save_scene(path, &loaded.scene).map(|_| path.to_path_buf());
        let ok = done.is_ok();
        self.confirm(done);
        if ok {
            self.files.recent.opened(path);
        }
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
        let model = &self.study.loaded.as_ref()?.scene.model;
        let n = model.nodes.iter().position(|x| x.id == id)?;
        let p = self.record()?.nodes.get(n)?;
        Some((rect, self.look.camera.to_screen(rect, [p[0], p[1]])))
    }

    /// Whether the beams go through the wgpu callback (else the egui-painter fallback).
    pub fn uses_gpu(&self) -> bool {
        self.frame.gpu
    }

    /// Apply every waiting worker message. Never blocks.
    pub(crate) fn drain(&mut self) {
        while let Some(m) = self.worker.try_recv() {
            if self.study.stale
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
                Message::Checkpoint(c) => self.study.history.attach(c),
                Message::Restored(_) => self.study.stale = false,
                Message::Loaded(l) => {
                    self.study.stale = false;
                    self.study.history.reset(l.initial.clone());
                    self.study.history.attach(l.checkpoint.clone());
                    self.study.branch_points.clear();
                    self.study.targets = l.initial.prescribed.clone();
                    self.notices.status = format!(
                        "{} elements ({:?})",
                        l.scene.model.beams.len(),
                        l.scene.model.formulation
                    );
                    self.study.loaded = Some(l);
                    // A scene opened in the app is fitted to the viewport.
                    self.look.fit_pending = true;
                    self.look.pinned = None;
                    self.study.generation += 1;
                    self.study.events.clear();
                    self.study.live.clear();
                    self.playback.selected = 0;
                    if let Some(k) = self.study.run_steps.take() {
                        self.send(Command::RunSteps(k));
                    }
                    if let Some(run) = self.study.restoring.take() {
                        let _ = self.take_back(run);
                    }
                    if let Some(shot) = &mut self.frame.shot {
                        shot.loaded(self.study.busy);
                    }
                }
                Message::Increment(r) => {
                    let follow = self.playback.selected >= self.last();
                    if !self.study.targeting {
                        self.study.targets = r.prescribed.clone();
                    }
                    let shown = self
                        .study
                        .history
                        .get(self.playback.selected)
                        .map(|h| h.increment);
                    if self.study.history.push(*r) {
                        self.notices.status = format!(
                            "{} earlier increments dropped from memory to stay within {} MiB",
                            self.study.history.dropped(),
                            HISTORY_BUDGET >> 20
                        );
                        if let Some(inc) = shown {
                            self.playback.selected = self.study.history.at_or_before(inc);
                        }
                    }
                    self.study.live.clear();
                    if follow {
                        self.playback.selected = self.last();
                    }
                }
                Message::Iteration(r) => self.study.live.push(r),
                Message::Event(e) => self.study.events.push(e),
                Message::Error(e) => {
                    self.study.stale = false;
                    if let Some(shot) = &mut self.frame.shot {
                        shot.record_failure(&e.to_string());
                    }
                    self.set_error(e);
                    self.study.live.clear();
                }
                Message::Busy => {
                    self.study.busy = true;
                    if let Some(shot) = &mut self.frame.shot {
                        shot.started();
                    }
                }
                Message::Idle => {
                    self.study.busy = false;
                    // Iterations of an abandoned attempt.
                    self.study.live.clear();
                    if self.study.targeting && self.look.drag.is_none() {
                        self.study.targeting = false;
                        if let Some(r) = self.study.history.last() {
                            self.study.targets = r.prescribed.clone();
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
        let last = self.last();
        if self.playback.advance(last, ctx.input(|i| i.time)) {
            ctx.request_repaint_after(std::time::Duration::from_millis(16));
        }
    }
}

/// The folder of a scene file's name (none for a built-in scene).
fn folder_of(name: &str) -> Option<PathBuf> {
    is_file(name)
        .then(|| Path::new(name).parent().map(Path::to_path_buf))
        .flatten()
}
