//! The window: creating the app (worker, start-up scene, stored view) and the `eframe::App`
//! implementation that drains the worker each frame and lays out the panels (toolbar,
//! timeline and plots, sliders and details, viewport), and saves what persists.

use super::canvas::{beams_gpu, viewport};
use super::display::Angles;
use super::files::scenes::{startup_scene, Recent};
use super::files::screenshot::{Layout, Shot};
use super::frame_log::FrameLog;
use super::panels::{controls, details, errors, menus, plots, shortcuts, table, timeline};
use super::retention::KeptHistory;
use super::state::{Startup, TsmApp};
use super::view::View;
use crate::worker::Worker;

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
        let stored_scene: Option<String> = if persist {
            (startup.remembered.clone())
                .or_else(|| cc.storage.and_then(|s| eframe::get_value(s, KEY_SCENE)))
        } else {
            None
        };
        let stored_view: Option<View> = if persist {
            cc.storage.and_then(|s| eframe::get_value(s, KEY_VIEW))
        } else {
            None
        };
        let recent: Recent = if persist {
            cc.storage
                .and_then(|s| eframe::get_value(s, KEY_RECENT))
                .unwrap_or_default()
        } else {
            Recent::default()
        };
        let default = crate::scene::builtin::BUILTIN[0].0.trim_end_matches(".ron");
        let (name, why) = startup_scene(startup.scene.clone(), stored_scene.clone(), default);
        let keep_view = stored_view.is_some() && stored_scene.as_deref() == Some(name.as_str());
        let mut app = TsmApp {
            worker,
            scene_name: name.clone(),
            loaded: None,
            history: KeptHistory::default(),
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
            diagram: startup.diagram,
            angles: Angles::default(),
            pinned: None,
            generation: 0,
            show_shortcuts: false,
            plot_dof: crate::solver::Dof::V,
            table: Default::default(),
            undo: Vec::new(),
            redo: Vec::new(),
            branch_points: Vec::new(),
            stale: false,
            restoring: None,
            dialogs: Default::default(),
            recent,
            png_size: [1600, 1000],
            show_error: false,
        };
        app.open(&name);
        if let Some(why) = why {
            app.set_error(why);
        }
        if !keep_view {
            app.fit_pending = true;
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
        shortcuts::handle(self, &ctx);
        menus::answers(self, &ctx);
        egui::Panel::top("toolbar").show(ui, |ui| controls::toolbar(self, ui));
        errors::panel(self, ui);
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
        shortcuts::window(self, &ctx);
        menus::drop_hint(&ctx);
        table::window(self, &ctx);
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
            eframe::set_value(storage, KEY_RECENT, &self.recent);
        }
    }
}
