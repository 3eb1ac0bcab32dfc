//! The timeline: a slider over the converged increments ("Increment") and the buttons
//! "Step back", "Step" (next stored increment, or one more solved step at the end), "Play" /
//! "Pause" (replay), "Run" (solve the scene's remaining steps), "Stop" (any run) and "Reset". Increments accepted
//! at the round-off floor are ticked under the slider.

use crate::worker::Command;

use crate::app::state::TsmApp;

/// Show the timeline row.
pub fn show(app: &mut TsmApp, ui: &mut egui::Ui) {
    ui.horizontal(|ui| {
        let last = app.last();
        let mut sel = app.selected.min(last);
        ui.spacing_mut().slider_width = (ui.available_width() - 520.0).max(120.0);
        let r = ui.add(
            egui::Slider::new(&mut sel, 0..=last)
                .text("Increment")
                .integer(),
        );
        if r.changed() {
            app.selected = sel;
            app.playing = false;
        }
        roundoff_ticks(app, ui, r.rect, last);
        let loaded = app.loaded.is_some();
        if ui
            .add_enabled(app.selected > 0, egui::Button::new("Step back"))
            .clicked()
        {
            app.selected -= 1;
            app.playing = false;
        }
        if ui.add_enabled(loaded, egui::Button::new("Step")).clicked() {
            app.playing = false;
            if app.selected < last {
                app.selected += 1;
            } else {
                app.send(Command::Step);
            }
        }
        let play = if app.playing { "Pause" } else { "Play" };
        if ui.add_enabled(last > 0, egui::Button::new(play)).clicked() {
            app.playing = !app.playing;
            if app.playing && app.selected >= last {
                app.selected = 0;
            }
            app.last_play = ui.input(|i| i.time);
        }
        if ui
            .add_enabled(loaded && !app.busy, egui::Button::new("Run"))
            .clicked()
        {
            app.selected = last;
            app.send(Command::Run);
        }
        // One Stop for every kind of run: displacement, load and arc-length control.
        if ui
            .add_enabled(app.busy, egui::Button::new("Stop"))
            .on_hover_text("stop the solver; the accepted increments stay (Esc)")
            .clicked()
        {
            app.send(Command::Cancel);
        }
        if ui.add_enabled(loaded, egui::Button::new("Reset")).clicked() {
            app.playing = false;
            app.targeting = false;
            app.worker.send(Command::Reset);
        }
    });
}

/// A tick under the slider at every increment accepted at the round-off floor (the colour of
/// their markers in the convergence plot), so that they are seen before they are selected.
fn roundoff_ticks(app: &TsmApp, ui: &egui::Ui, rect: egui::Rect, last: usize) {
    if last == 0 {
        return;
    }
    // The slider's track: its rect less the value text on the right.
    let track = ui.spacing().slider_width;
    let (x0, y) = (rect.left() + 6.0, rect.bottom() - 1.0);
    let span = (track - 12.0).max(1.0);
    let painter = ui.painter();
    for (k, r) in app.history.iter().enumerate() {
        if matches!(r.status, crate::solver::IncrementStatus::RoundOff { .. }) {
            let x = x0 + span * k as f32 / last as f32;
            painter.line_segment(
                [egui::pos2(x, y - 4.0), egui::pos2(x, y + 1.0)],
                egui::Stroke::new(2.0, super::plots::ROUNDOFF),
            );
        }
    }
}
