//! `TsmApp`: the visualiser's state (the worker handle, the converged history, the selection,
//! the camera, the targets of the prescribed dofs), draining the worker's messages each frame
//! without blocking, persistence, and the `eframe::App` implementation that lays out the panels.

use std::path::PathBuf;
use std::sync::atomic::{AtomicI32, Ordering};
use std::sync::Arc;

use crate::scene::Scene;
use crate::solver::{Event, IncrementRecord, IterationRecord};
use crate::worker::{Command, Loaded, Message, Worker};

use super::screenshot::{Layout, Phase, Shot};
use super::view::View;
use super::{controls, details, frame_log::FrameLog, plots, timeline, viewport};

/// Storage keys.
const KEY_SCENE: &str = "tsm_scene";
const KEY_VIEW: &str = "tsm_view";

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
    pub(crate) history: Vec<IncrementRecord>,
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
    pub(crate) error: Option<String>,
    pub(crate) open_path: String,
    pub(crate) export_stem: String,
    pub(crate) gpu: bool,
    pub(crate) shot: Option<Shot>,
    /// Where this frame drew the viewport and the convergence plot (for the screenshot sidecar).
    pub(crate) layout: Layout,
    pub(crate) run_steps: Option<usize>,
    pub(crate) drag: Option<viewport::Drag>,
    pub(crate) hover_handle: Option<usize>,
    frame_log: Option<FrameLog>,
    persist: bool,
}

/// Load a scene from a path if it exists, else a built-in by name.
pub fn load_scene(name: &str) -> Result<Scene, String> {
    let path = std::path::Path::new(name);
    if path.exists() {
        return crate::scene::load_file(path).map_err(|e| e.to_string());
    }
    match crate::scene::builtin::builtin(name) {
        Some(r) => r.map_err(|e| e.to_string()),
        None => Err(format!(
            "{name}: no such file and no built-in scene of that name"
        )),
    }
}

impl TsmApp {
    /// Create the app, start the worker and load the start-up scene.
    pub fn new(cc: &eframe::CreationContext<'_>, startup: Startup) -> TsmApp {
        cc.egui_ctx.set_theme(egui::Theme::Light);
        let ctx = cc.egui_ctx.clone();
        // At most one repaint per display frame however fast the worker reports.
        let worker = Worker::spawn(Some(Box::new(move || {
            ctx.request_repaint_after(std::time::Duration::from_millis(15))
        })));
        let gpu = !startup.no_gpu
            && std::env::var_os("TSM_NO_GPU").is_none()
            && cc
                .wgpu_render_state
                .as_ref()
                .is_some_and(super::beams_gpu::init);
        let persist = startup.screenshot.is_none();
        let stored_scene: Option<String> = if persist {
            cc.storage.and_then(|s| eframe::get_value(s, KEY_SCENE))
        } else {
            None
        };
        let stored_view: Option<View> = if persist {
            cc.storage.and_then(|s| eframe::get_value(s, KEY_VIEW))
        } else {
            None
        };
        let default = crate::scene::builtin::BUILTIN[0]
            .0
            .trim_end_matches(".ron")
            .to_string();
        let name = startup
            .scene
            .clone()
            .or(stored_scene.clone())
            .unwrap_or(default);
        let keep_view = stored_view.is_some() && stored_scene.as_deref() == Some(name.as_str());
        let mut app = TsmApp {
            worker,
            scene_name: name.clone(),
            loaded: None,
            history: Vec::new(),
            events: Vec::new(),
            live: Vec::new(),
            selected: 0,
            busy: false,
            playing: false,
            last_play: 0.0,
            view: stored_view.unwrap_or_default(),
            fit_pending: !keep_view,
            targets: Vec::new(),
            targeting: false,
            plot_all: true,
            status: String::new(),
            error: None,
            open_path: String::new(),
            export_stem: "tsm-history".into(),
            gpu,
            shot: startup
                .screenshot
                .map(|p| Shot::new(p, startup.exit.clone(), true)),
            layout: Layout::default(),
            run_steps: startup.steps.filter(|&k| k > 0),
            drag: None,
            hover_handle: None,
            frame_log: FrameLog::from_env(),
            persist,
        };
        app.open(&name);
        if !keep_view {
            app.fit_pending = true;
        }
        app
    }

    /// Load a scene by path or built-in name and hand it to the worker.
    pub(crate) fn open(&mut self, name: &str) {
        match load_scene(name) {
            Ok(scene) => {
                self.scene_name = name.to_string();
                self.error = None;
                self.status = format!("loading {}", scene.file.name);
                self.worker.send(Command::LoadScene(Box::new(scene)));
            }
            Err(e) => {
                self.error = Some(e);
                if let Some(shot) = &mut self.shot {
                    shot.phase = Phase::Settle(3);
                }
            }
        }
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
    fn drain(&mut self) {
        while let Some(m) = self.worker.try_recv() {
            match m {
                Message::Loaded(l) => {
                    self.history = vec![l.initial.clone()];
                    self.targets = l.initial.prescribed.clone();
                    self.status = format!(
                        "{} elements ({:?})",
                        l.scene.model.beams.len(),
                        l.scene.model.formulation
                    );
                    self.loaded = Some(l);
                    self.events.clear();
                    self.live.clear();
                    self.selected = 0;
                    self.error = None;
                    if let Some(k) = self.run_steps.take() {
                        self.send(Command::RunSteps(k));
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
                    self.history.push(*r);
                    self.live.clear();
                    if follow {
                        self.selected = self.last();
                    }
                }
                Message::Iteration(r) => self.live.push(r),
                Message::Event(e) => self.events.push(e),
                Message::Error(e) => {
                    self.error = Some(e);
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
    fn play(&mut self, ctx: &egui::Context) {
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

impl eframe::App for TsmApp {
    fn ui(&mut self, ui: &mut egui::Ui, frame: &mut eframe::Frame) {
        let t0 = std::time::Instant::now();
        self.drain();
        let ctx = ui.ctx().clone();
        self.play(&ctx);
        egui::Panel::top("toolbar").show(ui, |ui| controls::toolbar(self, ui));
        egui::Panel::bottom("timeline")
            .resizable(true)
            .default_size(300.0)
            .min_size(200.0)
            .show(ui, |ui| {
                timeline::show(self, ui);
                ui.separator();
                plots::show(self, ui);
            });
        egui::Panel::right("details")
            .resizable(true)
            .default_size(330.0)
            .show(ui, |ui| {
                egui::ScrollArea::vertical().show(ui, |ui| {
                    controls::sliders(self, ui);
                    ui.separator();
                    details::show(self, ui);
                });
            });
        let gpu = if self.gpu {
            frame.wgpu_render_state().cloned()
        } else {
            None
        };
        egui::CentralPanel::no_frame().show(ui, |ui| viewport::show(self, ui, gpu.as_ref()));
        if let Some(shot) = &mut self.shot {
            shot.frame(&ctx, &self.layout);
            if shot.finished() {
                self.shot = None;
            }
        }
        let increments = self.last();
        if let Some(log) = &mut self.frame_log {
            log.frame(t0.elapsed(), self.busy, increments);
            // Keep drawing so that idle frames are measured too.
            ctx.request_repaint();
        }
    }

    fn persist_egui_memory(&self) -> bool {
        self.persist
    }

    fn save(&mut self, storage: &mut dyn eframe::Storage) {
        if self.persist {
            eframe::set_value(storage, KEY_SCENE, &self.scene_name);
            eframe::set_value(storage, KEY_VIEW, &self.view);
        }
    }
}

/// Exit code holder for the screenshot run.
pub(crate) fn set_exit(exit: &Option<Arc<AtomicI32>>, code: i32) {
    if let Some(e) = exit {
        e.store(code, Ordering::SeqCst);
    }
}
