//! The toolbar (the menus of `menus.rs`, the element formulation, the stretch correction, Fit,
//! the force diagram, the angle unit, the table, the status line) and the sliders that drive
//! each prescribed dof (an `Action::Drive`: from the viewed increment).

use crate::solver::{Formulation, StretchCorrection};
use crate::worker::Command;

use super::menus;
use crate::app::display::Angles;
use crate::app::parts::{Action, Files, Look, Notices, Study};
use crate::figure::Diagram;

/// The stretch-correction mode of Newton's updates (`StretchCorrection`): a change reloads
/// the scene, as the formulation toggle does.
fn stretch_correction(mode: StretchCorrection, actions: &mut Vec<Action>, ui: &mut egui::Ui) {
    let label = |m| match m {
        StretchCorrection::Never => "never",
        StretchCorrection::WhereNeeded => "where needed",
        StretchCorrection::AfterCutBack => "after a cut-back",
        StretchCorrection::Always => "always",
    };
    egui::ComboBox::from_label("Stretch correction")
        .selected_text(label(mode))
        .show_ui(ui, |ui| {
            for m in [
                StretchCorrection::Never,
                StretchCorrection::WhereNeeded,
                StretchCorrection::AfterCutBack,
                StretchCorrection::Always,
            ] {
                if ui.selectable_label(mode == m, label(m)).clicked() && mode != m {
                    actions.push(Action::Change(Command::SetStretchCorrection(m)));
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
fn diagram_and_angles(look: &mut Look, ui: &mut egui::Ui) {
    let name = |d: Option<Diagram>| d.map_or("none", |d| d.letter());
    egui::ComboBox::from_label("Diagram")
        .selected_text(name(look.diagram))
        .show_ui(ui, |ui| {
            for d in std::iter::once(None).chain(Diagram::ALL.map(Some)) {
                ui.selectable_value(&mut look.diagram, d, name(d));
            }
        })
        .response
        .on_hover_text("axial force N, shear V or bending moment M along the deformed beams");
    let deg = look.angles == Angles::Degrees;
    if ui
        .selectable_label(deg, "deg")
        .on_hover_text("show rotations in degrees")
        .clicked()
    {
        look.angles = if deg {
            Angles::Radians
        } else {
            Angles::Degrees
        };
    }
}

/// The top bar: the menus, then widgets of fixed width (they keep their place whatever the
/// scene and the state), then the status line.
pub fn toolbar(
    study: &Study,
    look: &mut Look,
    files: &mut Files,
    notices: &Notices,
    actions: &mut Vec<Action>,
    ui: &mut egui::Ui,
) {
    ui.horizontal_wrapped(|ui| {
        menus::menus(study, look, files, actions, ui);
        ui.separator();
        ui.add_enabled_ui(study.loaded.is_some(), |ui| {
            ui.label("Element:");
            let (f, mode) = study.loaded.as_ref().map_or(
                (Formulation::Timoshenko, StretchCorrection::default()),
                |l| (l.scene.model.formulation, l.scene.params.stretch_correction),
            );
            for value in Formulation::ALL {
                let label = value.name();
                let hint =
                    "solve again from increment 0 with this element; Undo brings the run back";
                if ui
                    .selectable_label(f == value, label)
                    .on_hover_text(hint)
                    .clicked()
                    && f != value
                {
                    actions.push(Action::Change(Command::SetFormulation(value)));
                }
            }
            stretch_correction(mode, actions, ui);
        });
        ui.separator();
        if ui
            .button("Fit")
            .on_hover_text("fit the structure to the view (F)")
            .clicked()
        {
            look.fit_pending = true;
        }
        diagram_and_angles(look, ui);
        if ui
            .selectable_label(look.table.open, "Table")
            .on_hover_text("nodes, elements, contacts and reactions of the viewed increment")
            .clicked()
        {
            look.table.open = !look.table.open;
        }
        ui.separator();
        status(study, notices, ui);
    });
}

/// A spinner-sized slot, there or not, and one elided line (the whole text on hover; errors in
/// full in the error panel): the bar, and the viewport under it, keep their layout when the
/// solver starts and stops or a long message comes (else the beams and the handle under the
/// pointer would jump).
fn status(study: &Study, notices: &Notices, ui: &mut egui::Ui) {
    let side = ui.spacing().interact_size.y;
    let (slot, _) = ui.allocate_exact_size(egui::vec2(side, side), egui::Sense::hover());
    let line = if study.busy {
        egui::Spinner::new().paint_at(ui, slot);
        egui::RichText::new("solving...")
    } else {
        match (&notices.error, study.marked_summary()) {
            (Some(_), _) if notices.show_error => {
                egui::RichText::new("error: see the panel below").color(ui.visuals().error_fg_color)
            }
            // The panel closed: the message in the line (whole on hover).
            (Some(e), _) => egui::RichText::new(e.to_string()).color(ui.visuals().error_fg_color),
            (None, Some(s)) => egui::RichText::new(format!("{}; {s}", notices.status))
                .color(super::plots::ROUNDOFF),
            (None, None) => egui::RichText::new(&notices.status),
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
}

/// One slider per prescribed dof ("node 34 v"), driving its target.
pub fn sliders(study: &Study, selected: usize, actions: &mut Vec<Action>, ui: &mut egui::Ui) {
    let Some(l) = &study.loaded else { return };
    ui.heading("Drive");
    let model = &l.scene.model;
    if model.prescribed.is_empty() {
        let lambda = study.record(selected).map_or(0.0, |r| r.load_factor);
        let control = if l.scene.params.arc_length.is_some() {
            "arc-length control: each step solved is one arc"
        } else if model.path.is_some() {
            "stages: Next or Run solves the path's steps"
        } else {
            "load control: Next or Run solves steps"
        };
        if model.load_groups.len() > 1 {
            ui.label(format!(
                "{} load groups ({control})",
                model.load_groups.len()
            ));
        } else {
            ui.label(format!("load factor {lambda:.4} ({control})"));
        }
        return;
    }
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
        let Some(&t) = study.targets.get(k) else {
            continue;
        };
        let mut v = t;
        let r = ui.add(
            egui::Slider::new(&mut v, lo..=hi)
                .text(label)
                .custom_formatter(|x, _| format!("{x:.4}")),
        );
        // Only a real move counts (the slider may round or clamp a value it is merely shown).
        if r.changed() && (v - t).abs() > 1e-9 * (hi - lo) {
            actions.push(Action::Drive { index: k, value: v });
        }
    }
    // One row of button height either way, so the details below do not jump.
    ui.horizontal(|ui| {
        ui.set_min_height(ui.spacing().interact_size.y);
        if study.busy {
            ui.label("solving: Stop under the view, or Esc, ends it");
        } else {
            ui.label(format!(
                "increments of at most {:.4} {step_unit}",
                first_step.abs()
            ));
        }
    });
}
