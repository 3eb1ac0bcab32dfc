//! The timeline: a slider over the converged increments ("Increment") and the buttons
//! "Step back", "Step" (next stored increment, or one more solved step at the end), "Play" /
//! "Pause" (replay), "Run" (solve the scene's remaining steps) and "Reset".

use crate::worker::Command;

use super::state::TsmApp;

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
        if ui.add_enabled(loaded, egui::Button::new("Reset")).clicked() {
            app.playing = false;
            app.targeting = false;
            app.worker.send(Command::Reset);
        }
    });
}
