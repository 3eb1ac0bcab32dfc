//! The timeline: a slider over the converged increments ("Increment") and the buttons
//! "Previous", "Next" (the next increment; at the last one, one more scene step solved), "Play" /
//! "Pause" (replay), "Run" (solve the scene's remaining steps), "Stop" (any run), "Reset" and
//! "Undo" (bring back what a branch, a change or Reset set aside), "Redo" (what Undo replaced).
//! Increments accepted at the round-off floor, and the states of a snap, are ticked under the
//! slider, branch points marked
//! over it; along a load path, a line across the slider where each stage begins (the details
//! panel names the selected increment's stage).

use crate::app::parts::{Action, Playback, Study};
use crate::worker::Command;

/// Show the timeline row: the playback is its own; runs, steps, Reset, Undo and Redo are
/// asked for as actions.
pub fn show(study: &Study, playback: &mut Playback, actions: &mut Vec<Action>, ui: &mut egui::Ui) {
    ui.horizontal(|ui| {
        let last = study.last();
        let mut sel = playback.selected.min(last);
        ui.spacing_mut().slider_width = (ui.available_width() - 580.0).max(120.0);
        let r = ui.add(
            egui::Slider::new(&mut sel, 0..=last)
                .text("Increment")
                .integer(),
        );
        if r.changed() {
            playback.view(sel);
        }
        marked_ticks(study, ui, r.rect, last);
        branch_marks(study, ui, r.rect, last);
        stage_marks(study, ui, r.rect, last);
        let loaded = study.loaded.is_some();
        if ui
            .add_enabled(playback.selected > 0, egui::Button::new("Previous"))
            .on_hover_text("the previous increment (Left)")
            .clicked()
        {
            playback.previous(last);
        }
        if ui
            .add_enabled(loaded, egui::Button::new("Next"))
            .on_hover_text(
                "the next increment; at the last one, solve one more step of the scene (Right)",
            )
            .clicked()
            && !playback.next(last)
        {
            actions.push(Action::Send(Command::Step));
        }
        let play = if playback.playing { "Pause" } else { "Play" };
        if ui.add_enabled(last > 0, egui::Button::new(play)).clicked() {
            playback.toggle(last, ui.input(|i| i.time));
        }
        if ui
            .add_enabled(loaded && !study.busy, egui::Button::new("Run"))
            .clicked()
        {
            playback.view(last);
            actions.push(Action::Send(Command::Run));
        }
        // One Stop for every kind of run: displacement, load and arc-length control.
        if ui
            .add_enabled(study.busy, egui::Button::new("Stop"))
            .on_hover_text("stop the solver; the accepted increments stay (Esc)")
            .clicked()
        {
            actions.push(Action::Send(Command::Cancel));
        }
        if ui
            .add_enabled(loaded, egui::Button::new("Reset"))
            .on_hover_text("back to increment 0; Undo brings the run back")
            .clicked()
        {
            actions.push(Action::Reset);
        }
        if set_aside_button(ui, "Undo", study.undo.last(), "Ctrl+Z") {
            actions.push(Action::Undo);
        }
        if set_aside_button(ui, "Redo", study.redo.last(), "Ctrl+Y") {
            actions.push(Action::Redo);
        }
    });
}

/// The colour of stage boundaries and names.
pub const STAGE: egui::Color32 = egui::Color32::from_rgb(150, 90, 20);

/// A line across the slider at every increment that begins a stage of the load path.
fn stage_marks(study: &Study, ui: &egui::Ui, rect: egui::Rect, last: usize) {
    if last == 0 {
        return;
    }
    let track = ui.spacing().slider_width;
    let x0 = rect.left() + 6.0;
    let span = (track - 12.0).max(1.0);
    let painter = ui.painter();
    let mut before = None;
    for (k, r) in study.history.iter().enumerate().skip(1) {
        if r.stage.is_some() && r.stage != before {
            // The boundary lies between the last increment of one stage and the first of the
            // next.
            let x = x0 + span * (k as f32 - 0.5) / last as f32;
            painter.line_segment(
                [egui::pos2(x, rect.top()), egui::pos2(x, rect.bottom())],
                egui::Stroke::new(1.5, STAGE),
            );
        }
        before = r.stage;
    }
}

/// The Undo or Redo button: enabled when there is something to bring back, which its hover
/// text names. Returns whether it was clicked.
fn set_aside_button(
    ui: &mut egui::Ui,
    label: &str,
    next: Option<&crate::app::branches::SetAside>,
    key: &str,
) -> bool {
    let hint = match next {
        Some(s) => format!("bring back {} ({key})", s.describe()),
        None => format!("nothing to bring back ({key})"),
    };
    ui.add_enabled(next.is_some(), egui::Button::new(label))
        .on_hover_text(hint)
        .clicked()
}

/// A triangle over the slider at every increment the shown history branched at.
fn branch_marks(study: &Study, ui: &egui::Ui, rect: egui::Rect, last: usize) {
    if last == 0 {
        return;
    }
    let track = ui.spacing().slider_width;
    let (x0, y) = (rect.left() + 6.0, rect.top() + 1.0);
    let span = (track - 12.0).max(1.0);
    let painter = ui.painter();
    for &inc in &study.branch_points {
        let k = study.history.at_or_before(inc);
        let x = x0 + span * k as f32 / last as f32;
        painter.add(egui::Shape::convex_polygon(
            vec![
                egui::pos2(x - 4.0, y - 3.0),
                egui::pos2(x + 4.0, y - 3.0),
                egui::pos2(x, y + 3.0),
            ],
            BRANCH,
            egui::Stroke::NONE,
        ));
    }
}

/// The colour of branch points.
pub const BRANCH: egui::Color32 = egui::Color32::from_rgb(40, 120, 200);

/// A tick under the slider at every increment accepted at the round-off floor (the colour of
/// their markers in the convergence plot) and every state on the way of a snap (not in
/// equilibrium), so that they are seen before they are selected.
fn marked_ticks(study: &Study, ui: &egui::Ui, rect: egui::Rect, last: usize) {
    if last == 0 {
        return;
    }
    // The slider's track: its rect less the value text on the right.
    let track = ui.spacing().slider_width;
    let (x0, y) = (rect.left() + 6.0, rect.bottom() - 1.0);
    let span = (track - 12.0).max(1.0);
    let painter = ui.painter();
    for (k, r) in study.history.iter().enumerate() {
        let colour = match r.status {
            crate::solver::IncrementStatus::Converged => continue,
            crate::solver::IncrementStatus::RoundOff { .. } => super::plots::ROUNDOFF,
            crate::solver::IncrementStatus::Snapping { .. } => super::plots::SNAPPING,
        };
        let x = x0 + span * k as f32 / last as f32;
        painter.line_segment(
            [egui::pos2(x, y - 4.0), egui::pos2(x, y + 1.0)],
            egui::Stroke::new(2.0, colour),
        );
    }
}
