//! The window: how the app starts (`Startup`), creating it (worker, start-up scene, the saved
//! settings) and the `eframe::App` implementation that, each frame, drains the worker, lays
//! out the panels (`panels::lay_out`), applies what they asked for, and saves what persists.

use super::canvas::beams_gpu;
use super::display::Angles;
use super::files::scenes::{startup_scene, Recent};
use super::files::screenshot::{Layout, Shot};
use super::frame_log::FrameLog;
use super::panels;
use std::path::PathBuf;
use std::sync::atomic::AtomicI32;
use std::sync::Arc;

use super::parts::{Files, Frame, Look, Notices, Playback, Study};
use super::state::TsmApp;
use super::view::View;
use crate::figure::Diagram;
use crate::worker::Worker;

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

/// Storage keys.
const KEY_SCENE: &str = "tsm_scene";
const KEY_VIEW: &str = "tsm_view";
const KEY_RECENT: &str = "tsm_recent";

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
            && cc.wgpu_render_state.as_ref().is_some_and(beams_gpu::init);
        let persist = startup.screenshot.is_none();
        let saved = if persist {
            Saved::load(cc.storage, startup.remembered.clone())
        } else {
            Saved::default()
        };
        let default = crate::scene::builtin::BUILTIN[0].0.trim_end_matches(".ron");
        let (name, why) = startup_scene(startup.scene.clone(), saved.scene.clone(), default);
        let keep_view = saved.camera.is_some() && saved.scene.as_deref() == Some(name.as_str());
        let mut app = TsmApp {
            worker,
            study: Study {
                scene_name: name.clone(),
                run_steps: startup.steps.filter(|&k| k > 0),
                ..Study::default()
            },
            playback: Playback::default(),
            look: Look {
                camera: saved.camera.unwrap_or_default(),
                fit_pending: !keep_view,
                drag: None,
                hover_handle: None,
                diagram: startup.diagram,
                angles: Angles::default(),
                pinned: None,
                plot_dof: crate::solver::Dof::V,
                plot_all: true,
                table: Default::default(),
                show_shortcuts: false,
            },
            files: Files {
                open_path: String::new(),
                export_stem: "tsm-history".into(),
                dialogs: Default::default(),
                recent: saved.recent,
                png_size: [1600, 1000],
            },
            notices: Notices::default(),
            frame: Frame {
                gpu,
                layout: Layout::default(),
                shot: startup
                    .screenshot
                    .map(|p| Shot::new(p, startup.exit.clone(), true)),
                frame_log: FrameLog::from_env(),
                persist,
            },
            actions: Vec::new(),
        };
        app.open(&name);
        if let Some(why) = why {
            app.set_error(why);
        }
        if !keep_view {
            app.look.fit_pending = true;
        }
        app
    }
}

impl eframe::App for TsmApp {
    fn ui(&mut self, ui: &mut egui::Ui, frame: &mut eframe::Frame) {
        let t0 = std::time::Instant::now();
        self.drain();
        let ctx = ui.ctx().clone();
        self.play(&ctx);
        let gpu = if self.frame.gpu {
            frame.wgpu_render_state().cloned()
        } else {
            None
        };
        self.answers(&ctx);
        panels::lay_out(self, ui, gpu.as_ref());
        self.apply(&ctx);
        if let Some(shot) = &mut self.frame.shot {
            shot.frame(&ctx, &self.frame.layout);
            if shot.finished() {
                self.frame.shot = None;
            }
        }
        let increments = self.last();
        if let Some(log) = &mut self.frame.frame_log {
            log.frame(t0.elapsed(), self.study.busy, increments);
            // Keep drawing so that idle frames are measured too.
            ctx.request_repaint();
        }
    }

    fn persist_egui_memory(&self) -> bool {
        self.frame.persist
    }

    fn save(&mut self, storage: &mut dyn eframe::Storage) {
        if self.frame.persist {
            Saved {
                scene: Some(self.study.scene_name.clone()),
                camera: Some(self.look.camera),
                recent: self.files.recent.clone(),
            }
            .store(storage);
        }
    }
}

/// The settings kept from one run of the app to the next (eframe's storage): the scene last
/// open, its camera and the recent files. Everything else is run-time state.
#[derive(Default)]
struct Saved {
    scene: Option<String>,
    camera: Option<View>,
    recent: Recent,
}

impl Saved {
    /// The settings in `storage`, the scene `remembered` (if given) in place of the stored one.
    fn load(storage: Option<&dyn eframe::Storage>, remembered: Option<String>) -> Saved {
        Saved {
            scene: remembered.or_else(|| storage.and_then(|s| eframe::get_value(s, KEY_SCENE))),
            camera: storage.and_then(|s| eframe::get_value(s, KEY_VIEW)),
            recent: (storage.and_then(|s| eframe::get_value(s, KEY_RECENT))).unwrap_or_default(),
        }
    }

    /// Keep these settings in `storage`.
    fn store(&self, storage: &mut dyn eframe::Storage) {
        if let Some(scene) = &self.scene {
            eframe::set_value(storage, KEY_SCENE, scene);
        }
        if let Some(camera) = &self.camera {
            eframe::set_value(storage, KEY_VIEW, camera);
        }
        eframe::set_value(storage, KEY_RECENT, &self.recent);
    }
}
