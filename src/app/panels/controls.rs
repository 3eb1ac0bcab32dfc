//! The toolbar (scene picker, "Open..." path, formulation toggle, fit, force diagram, angle
//! unit, exports, screenshot, status) and the sliders that drive each prescribed dof through `Command::SetTarget`.

use crate::solver::{Formulation, StretchCorrection};
use crate::worker::Command;

use crate::app::canvas::svg;
use crate::app::display::Diagram;
use crate::app::display::{Angles, Picked};
use crate::app::export;
use crate::app::screenshot::Shot;
use crate::app::state::TsmApp;

/// The stretch-correction mode of Newton's updates (`StretchCorrection`): a change reloads
/// the scene, as the formulation toggle does.
fn stretch_correction(app: &mut TsmApp, mode: StretchCorrection, ui: &mut egui::Ui) {
    let label = |m| match m {
        StretchCorrection::Never => "never",
        StretchCorrection::AfterCutBack => "after a cut-back",
        StretchCorrection::Always => "always",
    };
    egui::ComboBox::from_label("Stretch correction")
        .selected_text(label(mode))
        .show_ui(ui, |ui| {
            for m in [
                StretchCorrection::Never,
                StretchCorrection::AfterCutBack,
                StretchCorrection::Always,
            ] {
                if ui.selectable_label(mode == m, label(m)).clicked() && mode != m {
                    app.send(Command::SetStretchCorrection(m));
                }
            }
        })
        .response
        .on_hover_text(
            "Take the chords' second-order stretch out of Newton's updates: fewer iterations \
             and cut-backs on fine meshes of stiff beams in large rotation; one more solve \
             an iteration",
        );
}

/// The force diagram drawn along the beams (none, N, V or M), and the unit rotations are shown
/// in.
fn diagram_and_angles(app: &mut TsmApp, ui: &mut egui::Ui) {
    let name = |d: Option<Diagram>| d.map_or("none", |d| d.letter());
    egui::ComboBox::from_label("Diagram")
        .selected_text(name(app.diagram))
        .show_ui(ui, |ui| {
            for d in std::iter::once(None).chain(Diagram::ALL.map(Some)) {
                ui.selectable_value(&mut app.diagram, d, name(d));
            }
        })
        .response
        .on_hover_text("axial force N, shear V or bending moment M along the deformed beams");
    let deg = app.angles == Angles::Degrees;
    if ui
        .selectable_label(deg, "deg")
        .on_hover_text("show rotations in degrees")
        .clicked()
    {
        app.angles = if deg {
            Angles::Radians
        } else {
            Angles::Degrees
        };
    }
}

/// The top bar.
pub fn toolbar(app: &mut TsmApp, ui: &mut egui::Ui) {
    ui.horizontal_wrapped(|ui| {
        let current = app.scene_name.clone();
        egui::ComboBox::from_label("Scene")
            .selected_text(short(&current))
            .show_ui(ui, |ui| {
                for (file, _) in crate::scene::builtin::BUILTIN {
                    let name = file.trim_end_matches(".ron");
                    if ui.selectable_label(current == name, name).clicked() {
                        app.open(name);
                    }
                }
            });
        let name = ui.label("file");
        ui.add(
            egui::TextEdit::singleline(&mut app.open_path)
                .hint_text("scene.ron path")
                .desired_width(150.0),
        )
        .labelled_by(name.id);
        if ui.button("Open...").clicked() && !app.open_path.trim().is_empty() {
            let p = app.open_path.trim().to_string();
            app.open(&p);
        }
        ui.separator();
        if let Some(l) = &app.loaded {
            ui.label("Element:");
            let f = l.scene.model.formulation;
            let mode = l.scene.params.stretch_correction;
            for (label, value) in [
                ("Timoshenko", Formulation::Timoshenko),
                ("Bernoulli-Euler", Formulation::BernoulliEuler),
            ] {
                if ui.selectable_label(f == value, label).clicked() && f != value {
                    app.send(Command::SetFormulation(value));
                }
            }
            stretch_correction(app, mode, ui);
        }
        ui.separator();
        if ui
            .button("Fit")
            .on_hover_text("fit the structure to the view (F)")
            .clicked()
        {
            app.fit_pending = true;
        }
        diagram_and_angles(app, ui);
        if ui
            .selectable_label(app.table.open, "Table")
            .on_hover_text("nodes, elements, contacts and reactions of the viewed increment")
            .clicked()
        {
            app.table.open = !app.table.open;
        }
        ui.separator();
        let name = ui.label("Export as");
        ui.add(
            egui::TextEdit::singleline(&mut app.export_stem)
                .hint_text("export file stem")
                .desired_width(110.0),
        )
        .labelled_by(name.id);
        exports(app, ui);
        ui.separator();
        // A spinner-sized slot, there or not, and one elided line (the whole text on hover): the
        // bar, and the viewport under it, keep their layout when the solver starts and stops
        // or a long message comes (else the beams and the handle under the pointer would jump).
        let side = ui.spacing().interact_size.y;
        let (slot, _) = ui.allocate_exact_size(egui::vec2(side, side), egui::Sense::hover());
        let line = if app.busy {
            egui::Spinner::new().paint_at(ui, slot);
            egui::RichText::new("solving...")
        } else {
            match (&app.error, app.roundoff_summary()) {
                (Some(e), _) => egui::RichText::new(e).color(ui.visuals().error_fg_color),
                (None, Some(s)) => egui::RichText::new(format!("{}; {s}", app.status))
                    .color(super::plots::ROUNDOFF),
                (None, None) => egui::RichText::new(&app.status),
            }
        };
        // The rest of the row (a row of its own when little is left), whatever the text.
        // (A wrapping row reports its whole width as available: measure what is left of it.)
        let width = ui.max_rect().right() - ui.cursor().left() - ui.spacing().item_spacing.x;
        let width = if width < 120.0 { 300.0 } else { width };
        let row = egui::Layout::left_to_right(egui::Align::Center);
        ui.allocate_ui_with_layout(egui::vec2(width, side), row, |ui| {
            ui.set_min_width(width);
            ui.add(egui::Label::new(line).truncate());
        });
    });
}

/// Export buttons.
fn exports(app: &mut TsmApp, ui: &mut egui::Ui) {
    let stem = app.export_stem.trim().to_string();
    let Some(loaded) = &app.loaded else { return };
    let mut note = None;
    if ui.button("Export JSON").clicked() {
        let path = std::path::PathBuf::from(format!("{stem}.json"));
        let h = export::history(loaded, &app.history, &app.events, app.error.as_deref());
        note = Some(h.write_json(&path).map(|_| path));
    }
    let picked: Vec<usize> = match app.pinned {
        Some(Picked::Node(n)) => vec![n],
        _ => Vec::new(),
    };
    if ui
        .button("Export CSV")
        .on_hover_text("every increment; with a node selected, its displacements too")
        .clicked()
    {
        let path = std::path::PathBuf::from(format!("{stem}.csv"));
        note = Some(export::write_csv(&path, loaded, &app.history, &picked).map(|_| path));
    }
    if ui
        .button("Export SVG")
        .on_hover_text("the viewed increment's beams, for papers")
        .clicked()
    {
        if let Some(r) = app.record() {
            let path = std::path::PathBuf::from(format!("{stem}.svg"));
            note = Some(svg::write_svg(&path, loaded, r).map(|_| path));
        }
    }
    if ui.button("Save PNG").clicked() && app.shot.is_none() {
        app.shot = Some(Shot::new(format!("{stem}.png").into(), None, false));
        app.status = format!("saving {stem}.png");
    }
    match note {
        Some(Ok(p)) => {
            let full = std::fs::canonicalize(&p).unwrap_or(p);
            app.status = format!("wrote {}", full.display());
        }
        Some(Err(e)) => app.error = Some(format!("export failed: {e}")),
        None => {}
    }
}

/// Last path component without `.ron`.
fn short(name: &str) -> String {
    let base = std::path::Path::new(name)
        .file_name()
        .map_or(name.into(), |f| f.to_string_lossy().to_string());
    base.trim_end_matches(".ron").to_string()
}

/// One slider per prescribed dof ("node 34 v"), driving its target.
pub fn sliders(app: &mut TsmApp, ui: &mut egui::Ui) {
    let Some(l) = &app.loaded else { return };
    ui.heading("Drive");
    let model = &l.scene.model;
    if model.prescribed.is_empty() {
        let lambda = app.record().map_or(0.0, |r| r.load_factor);
        let control = if l.scene.params.arc_length.is_some() {
            "arc-length control: each Step is one arc"
        } else {
            "load control; use Step / Run"
        };
        ui.label(format!("load factor {lambda:.4} ({control})"));
        return;
    }
    let mut sends = Vec::new();
    let first_step = model.prescribed[0].per_step;
    let step_unit = l.scene.file.units.of_dof(model.prescribed[0].dof);
    for (k, p) in model.prescribed.iter().enumerate() {
        let total = p.per_step * l.scene.steps as f64;
        let span = if total != 0.0 { total * 1.25 } else { 1.0 };
        let (lo, hi) = (
            span.min(0.0).min(-span.abs() * 0.1),
            span.max(0.0).max(span.abs() * 0.1),
        );
        let label = l.prescribed_labels.get(k).cloned().unwrap_or_default();
        let Some(t) = app.targets.get_mut(k) else {
            continue;
        };
        let mut v = *t;
        let r = ui.add(
            egui::Slider::new(&mut v, lo..=hi)
                .text(label)
                .custom_formatter(|x, _| format!("{x:.4}")),
        );
        // Only a real move counts (the slider may round or clamp a value it is merely shown).
        if r.changed() && (v - *t).abs() > 1e-9 * (hi - lo) {
            *t = v;
            sends.push((k, v));
        }
    }
    for (index, value) in sends {
        app.targeting = true;
        app.send(Command::SetTarget { index, value });
    }
    // One row of button height either way, so the details below do not jump.
    ui.horizontal(|ui| {
        ui.set_min_height(ui.spacing().interact_size.y);
        if app.busy {
            ui.label("solving: Stop under the view, or Esc, ends it");
        } else {
            ui.label(format!(
                "increments of at most {:.4} {step_unit}",
                first_step.abs()
            ));
        }
    });
}
