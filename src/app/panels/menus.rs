//! The menus of the toolbar: File (Open with the native dialog, recent files, the built-in
//! scenes, a typed path, Keep the drive as a path, Save scene as), Export (the history as JSON
//! and CSV, the viewed increment as SVG and as a PNG of a chosen size, the window as a picture,
//! under the name in "Export as", which "..." picks with a dialog) and Help (the shortcuts);
//! and the hint shown while files are dragged over the window. What they choose is asked for
//! as actions: `TsmApp::apply` opens, writes (confirming with the full path or saying why it
//! failed) and shows the dialogs, whose answers `TsmApp::answers` takes.

use egui::containers::menu::{MenuButton, MenuConfig};

use crate::app::files::dialog::Purpose;
use crate::app::parts::{Action, Export, Files, Look, Study};

/// The three menus: what they choose is asked for as actions (`TsmApp::apply` opens, writes
/// and shows the dialogs).
pub fn menus(
    study: &Study,
    look: &mut Look,
    files: &mut Files,
    actions: &mut Vec<Action>,
    ui: &mut egui::Ui,
) {
    file_menu(study, files, actions, ui);
    let stay = MenuConfig::new().close_behavior(egui::PopupCloseBehavior::CloseOnClickOutside);
    MenuButton::new("Export")
        .config(stay)
        .ui(ui, |ui| export_menu(files, actions, ui));
    ui.menu_button("Help", |ui| {
        if ui.button("Shortcuts (?)").clicked() {
            look.show_shortcuts = true;
        }
    });
}

/// The File menu.
fn file_menu(study: &Study, files: &mut Files, actions: &mut Vec<Action>, ui: &mut egui::Ui) {
    ui.menu_button("File", |ui| {
        if ui.button("Open... (Ctrl+O)").clicked() {
            actions.push(Action::Dialog(Purpose::OpenScene));
        }
        ui.menu_button("Open recent", |ui| {
            let recent = files.recent.files().to_vec();
            if recent.is_empty() {
                ui.label("no scene files opened yet");
            }
            for p in recent {
                if ui.button(p.display().to_string()).clicked() {
                    actions.push(Action::Open(p.to_string_lossy().into_owned()));
                }
            }
        });
        ui.menu_button("Built-in scenes", |ui| {
            for (file, _) in crate::scene::builtin::BUILTIN {
                let name = file.trim_end_matches(".ron");
                if ui.selectable_label(study.scene_name == name, name).clicked() {
                    actions.push(Action::Open(name.to_string()));
                }
            }
        });
        ui.horizontal(|ui| {
            let name = ui.label("path");
            ui.add(
                egui::TextEdit::singleline(&mut files.open_path)
                    .hint_text("scene.ron")
                    .desired_width(180.0),
            )
            .labelled_by(name.id);
            if ui.button("Open path").clicked() && !files.open_path.trim().is_empty() {
                actions.push(Action::Open(files.open_path.trim().to_string()));
            }
        });
        ui.separator();
        if ui
            .add_enabled(study.last() > 0, egui::Button::new("Keep the drive as a path"))
            .on_hover_text(
                "make the run shown (steps, drags, reversals) the scene's stages, so that the saved \
                 scene replays it",
            )
            .clicked()
        {
            actions.push(Action::KeepDrive);
        }
        if ui.button("Save scene as...").clicked() {
            actions.push(Action::Dialog(Purpose::SaveScene));
        }
    });
}

/// The Export menu.
fn export_menu(files: &mut Files, actions: &mut Vec<Action>, ui: &mut egui::Ui) {
    ui.horizontal(|ui| {
        let name = ui.label("Export as");
        ui.add(
            egui::TextEdit::singleline(&mut files.export_stem)
                .hint_text("folder/name, no extension")
                .desired_width(200.0),
        )
        .labelled_by(name.id);
        if ui
            .button("...")
            .on_hover_text("pick the folder and name")
            .clicked()
        {
            actions.push(Action::Dialog(Purpose::ExportStem));
        }
    });
    ui.separator();
    if ui
        .button("Export JSON")
        .on_hover_text("the history (Ctrl+E)")
        .clicked()
    {
        actions.push(Action::Export(Export::Json));
    }
    if ui
        .button("Export CSV")
        .on_hover_text("one row an increment; with a node selected, its displacements too (Ctrl+E)")
        .clicked()
    {
        actions.push(Action::Export(Export::Csv));
    }
    if ui
        .button("Export SVG")
        .on_hover_text("the viewed increment, for papers: beams as paths")
        .clicked()
    {
        actions.push(Action::Export(Export::Svg));
    }
    ui.horizontal(|ui| {
        if ui
            .button("Export PNG")
            .on_hover_text("the viewed increment alone, at this size (Ctrl+S)")
            .clicked()
        {
            actions.push(Action::Export(Export::Png));
        }
        let w = ui.label("width");
        ui.add(egui::DragValue::new(&mut files.png_size[0]).range(16..=16384))
            .labelled_by(w.id);
        let h = ui.label("height");
        ui.add(egui::DragValue::new(&mut files.png_size[1]).range(16..=16384))
            .labelled_by(h.id);
    });
    if ui
        .button("Save window image")
        .on_hover_text("the whole window as it is drawn, panels included")
        .clicked()
    {
        actions.push(Action::Export(Export::Window));
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
