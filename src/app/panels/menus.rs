//! The menus of the toolbar and what they do: File (Open with the native dialog, recent
//! files, the built-in scenes, a typed path, Keep the drive as a path, Save scene as), Export (the history as JSON and
//! CSV, the viewed increment as SVG and as a PNG of a chosen size, the window as a picture,
//! under the name in "Export as", which "..." picks with a dialog) and Help (the shortcuts).
//! Also the answers of the dialogs, and files dragged over and dropped on the window. Every write confirms with
//! its full path or says why it failed.

use std::path::{Path, PathBuf};

use egui::containers::menu::{MenuButton, MenuConfig};

use crate::app::display::Picked;
use crate::app::files::dialog::{Answer, Purpose};
use crate::app::files::export;
use crate::app::files::scenes::{dropped_scene, is_file, save_scene};
use crate::app::files::screenshot::Shot;
use crate::app::state::TsmApp;
use crate::figure::{raster, svg};

/// The three menus.
pub fn menus(app: &mut TsmApp, ui: &mut egui::Ui) {
    file_menu(app, ui);
    let stay = MenuConfig::new().close_behavior(egui::PopupCloseBehavior::CloseOnClickOutside);
    MenuButton::new("Export")
        .config(stay)
        .ui(ui, |ui| export_menu(app, ui));
    ui.menu_button("Help", |ui| {
        if ui.button("Shortcuts (?)").clicked() {
            app.look.show_shortcuts = true;
        }
    });
}

/// The File menu.
fn file_menu(app: &mut TsmApp, ui: &mut egui::Ui) {
    ui.menu_button("File", |ui| {
        if ui.button("Open... (Ctrl+O)").clicked() {
            open_dialog(app, ui.ctx());
        }
        ui.menu_button("Open recent", |ui| {
            let recent = app.files.recent.files().to_vec();
            if recent.is_empty() {
                ui.label("no scene files opened yet");
            }
            for p in recent {
                if ui.button(p.display().to_string()).clicked() {
                    app.open(&p.to_string_lossy());
                }
            }
        });
        ui.menu_button("Built-in scenes", |ui| {
            for (file, _) in crate::scene::builtin::BUILTIN {
                let name = file.trim_end_matches(".ron");
                if ui.selectable_label(app.session.scene_name == name, name).clicked() {
                    app.open(name);
                }
            }
        });
        ui.horizontal(|ui| {
            let name = ui.label("path");
            ui.add(
                egui::TextEdit::singleline(&mut app.files.open_path)
                    .hint_text("scene.ron")
                    .desired_width(180.0),
            )
            .labelled_by(name.id);
            if ui.button("Open path").clicked() && !app.files.open_path.trim().is_empty() {
                let p = app.files.open_path.trim().to_string();
                app.open(&p);
            }
        });
        ui.separator();
        if ui
            .add_enabled(app.last() > 0, egui::Button::new("Keep the drive as a path"))
            .on_hover_text(
                "make the run shown (steps, drags, reversals) the scene's stages, so that the saved \
                 scene replays it",
            )
            .clicked()
        {
            keep_drive(app);
        }
        if ui.button("Save scene as...").clicked() {
            let folder = folder_of(&app.session.scene_name);
            app.files.dialogs
                .show(Purpose::SaveScene, folder, ui.ctx().clone());
        }
    });
}

/// The folder of a scene file's name (none for a built-in scene).
fn folder_of(name: &str) -> Option<PathBuf> {
    is_file(name)
        .then(|| Path::new(name).parent().map(Path::to_path_buf))
        .flatten()
}

/// Show the Open dialog (Ctrl+O).
pub fn open_dialog(app: &mut TsmApp, ctx: &egui::Context) {
    let folder = folder_of(&app.session.scene_name);
    app.files
        .dialogs
        .show(Purpose::OpenScene, folder, ctx.clone());
}

/// The Export menu.
fn export_menu(app: &mut TsmApp, ui: &mut egui::Ui) {
    ui.horizontal(|ui| {
        let name = ui.label("Export as");
        ui.add(
            egui::TextEdit::singleline(&mut app.files.export_stem)
                .hint_text("folder/name, no extension")
                .desired_width(200.0),
        )
        .labelled_by(name.id);
        if ui
            .button("...")
            .on_hover_text("pick the folder and name")
            .clicked()
        {
            let folder = Path::new(&app.files.export_stem)
                .parent()
                .map(Path::to_path_buf);
            app.files
                .dialogs
                .show(Purpose::ExportStem, folder, ui.ctx().clone());
        }
    });
    ui.separator();
    if ui
        .button("Export JSON")
        .on_hover_text("the history (Ctrl+E)")
        .clicked()
    {
        export_json(app);
    }
    if ui
        .button("Export CSV")
        .on_hover_text("one row an increment; with a node selected, its displacements too (Ctrl+E)")
        .clicked()
    {
        export_csv(app);
    }
    if ui
        .button("Export SVG")
        .on_hover_text("the viewed increment, for papers: beams as paths")
        .clicked()
    {
        export_svg(app);
    }
    ui.horizontal(|ui| {
        if ui
            .button("Export PNG")
            .on_hover_text("the viewed increment alone, at this size (Ctrl+S)")
            .clicked()
        {
            export_png(app);
        }
        let w = ui.label("width");
        ui.add(egui::DragValue::new(&mut app.files.png_size[0]).range(16..=16384))
            .labelled_by(w.id);
        let h = ui.label("height");
        ui.add(egui::DragValue::new(&mut app.files.png_size[1]).range(16..=16384))
            .labelled_by(h.id);
    });
    if ui
        .button("Save window image")
        .on_hover_text("the whole window as it is drawn, panels included")
        .clicked()
        && app.frame.shot.is_none()
    {
        let path = with_ext(&app.files.export_stem, "window.png");
        app.notices.status = format!("saving {}", path.display());
        app.frame.shot = Some(Shot::new(path, None, false));
    }
}

/// `stem` with extension `ext`.
fn with_ext(stem: &str, ext: &str) -> PathBuf {
    PathBuf::from(format!("{}.{ext}", stem.trim()))
}

/// Say what a write did: its full path, or why it failed.
pub fn confirm(app: &mut TsmApp, what: Result<PathBuf, String>) {
    match what {
        Ok(p) => {
            let full = std::fs::canonicalize(&p).unwrap_or(p);
            app.notices.status = format!("wrote {}", full.display());
        }
        Err(e) => app.set_error(format!("export failed: {e}")),
    }
}

/// Export the history as JSON.
pub fn export_json(app: &mut TsmApp) {
    let Some(loaded) = &app.session.loaded else {
        return;
    };
    let path = with_ext(&app.files.export_stem, "json");
    let h = export::history(
        loaded,
        &app.session.history,
        app.session.history.stride(),
        &app.session.events,
        app.error().as_deref(),
    );
    let done = h.write_json(&path).map(|_| path).map_err(|e| e.to_string());
    confirm(app, done);
}

/// Export the history as CSV (with the selected node's displacements).
pub fn export_csv(app: &mut TsmApp) {
    let Some(loaded) = &app.session.loaded else {
        return;
    };
    let picked: Vec<usize> = match app.look.pinned {
        Some(Picked::Node(n)) => vec![n],
        _ => Vec::new(),
    };
    let path = with_ext(&app.files.export_stem, "csv");
    let done = export::write_csv(&path, loaded, &app.session.history, &picked)
        .map(|_| path)
        .map_err(|e| e.to_string());
    confirm(app, done);
}

/// Export the viewed increment as SVG.
pub fn export_svg(app: &mut TsmApp) {
    let (Some(loaded), Some(r)) = (&app.session.loaded, app.record()) else {
        return;
    };
    let path = with_ext(&app.files.export_stem, "svg");
    let done = svg::write_svg(&path, loaded, r, app.look.diagram)
        .map(|_| path)
        .map_err(|e| e.to_string());
    confirm(app, done);
}

/// Export the viewed increment as a PNG of the chosen size (Ctrl+S).
pub fn export_png(app: &mut TsmApp) {
    let (Some(loaded), Some(r)) = (&app.session.loaded, app.record()) else {
        return;
    };
    let path = with_ext(&app.files.export_stem, "png");
    let done =
        raster::write_png(&path, loaded, r, app.look.diagram, app.files.png_size).map(|_| path);
    confirm(app, done);
}

/// Act on a closed dialog's answer and on a file dropped on the window.
pub fn answers(app: &mut TsmApp, ctx: &egui::Context) {
    match app.files.dialogs.poll() {
        Some((purpose, Answer::Chosen(path))) => match purpose {
            Purpose::OpenScene => app.open(&path.to_string_lossy()),
            Purpose::SaveScene => save_scene_as(app, &path),
            Purpose::ExportStem => {
                app.files.export_stem = path.with_extension("").to_string_lossy().into_owned();
                app.notices.status = format!("exports go to {}.*", app.files.export_stem);
            }
        },
        Some((_, Answer::Unavailable)) => {
            app.notices.status = "no file dialog can be shown on this desktop (it needs a desktop \
                          portal or zenity): type the path under File > path, or in Export as"
                .into();
        }
        Some((_, Answer::Cancelled)) | None => {}
    }
    match dropped_scene(ctx) {
        Some(Ok(path)) => app.open(&path.to_string_lossy()),
        Some(Err(why)) => app.set_error(why),
        None => {}
    }
}

/// While files are dragged over the window: say that a dropped scene opens.
pub fn drop_hint(ctx: &egui::Context) {
    if ctx.input(|i| i.raw.hovered_files.is_empty()) {
        return;
    }
    let layer = egui::LayerId::new(egui::Order::Foreground, egui::Id::unique("drop hint"));
    let painter = ctx.layer_painter(layer);
    let rect = ctx.content_rect();
    painter.rect_filled(rect, 0.0, egui::Color32::from_black_alpha(120));
    painter.text(
        rect.center(),
        egui::Align2::CENTER_CENTER,
        "drop a .ron scene file to open it",
        egui::FontId::proportional(22.0),
        egui::Color32::WHITE,
    );
}

/// Keep the run shown as the scene's load path (`scene::kept::kept_path`): the loaded scene
/// becomes the scene with those stages, which "Save scene as" then writes and which replays the
/// run headless. Refused, with the reason shown, where the history kept in memory is not every
/// increment of the run or the scene cannot take the path.
pub fn keep_drive(app: &mut TsmApp) {
    let Some(loaded) = &app.session.loaded else {
        return;
    };
    if app.session.history.dropped() > 0 {
        app.set_error(
            "the run is longer than the history kept in memory: only whole runs can be kept as a \
             path (export the history instead)"
                .to_string(),
        );
        return;
    }
    let scene = &loaded.scene;
    let mut file = scene.file.clone();
    file.formulation = scene.model.formulation;
    file.control.stretch_correction = scene.params.stretch_correction;
    let records = app.session.history.get(1..).unwrap_or_default();
    let kept = crate::scene::kept::kept_path(&file, &scene.model, records)
        .and_then(|f| crate::scene::from_scene_file(f, &file.name).map_err(|e| e.to_string()));
    match kept {
        Ok(kept) => {
            let steps = kept.steps;
            if let Some(l) = &mut app.session.loaded {
                l.scene = kept;
            }
            app.notices.status = format!(
                "the run is kept as the scene's path ({steps} steps): Save scene as... writes it"
            );
        }
        Err(e) => app.set_error(format!("cannot keep the drive as a path: {e}")),
    }
}

/// Save the scene as solved to `path` (the dialog's answer, or a test's path).
pub fn save_scene_as(app: &mut TsmApp, path: &Path) {
    let Some(loaded) = &app.session.loaded else {
        return;
    };
    let done = save_scene(path, &loaded.scene).map(|_| path.to_path_buf());
    let ok = done.is_ok();
    confirm(app, done);
    if ok {
        app.files.recent.opened(path);
    }
}
