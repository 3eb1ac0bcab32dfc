//! The error panel under the toolbar: the last error in full (scene file, line and field, or
//! increment, node and element, as the message names them), in a scrolling area whose text can
//! be selected, with Copy and Close. A solver's stop is headed with the increment it stopped
//! in (from the solver's typed error); the states before it stay on the timeline. A new error
//! opens the panel again.

use crate::app::parts::Notices;

/// The tallest the panel grows before its text scrolls (points).
const MAX_HEIGHT: f32 = 160.0;

/// Show the panel while there is an error to show.
pub fn panel(notices: &mut Notices, ui: &mut egui::Ui) {
    let Some(failure) = notices.error.clone().filter(|_| notices.show_error) else {
        return;
    };
    let e = failure.to_string();
    let heading = match failure.increment() {
        Some(k) => format!("The solver stopped in increment {k}"),
        None => "Error".to_string(),
    };
    egui::Panel::top("error").show(ui, |ui| {
        ui.horizontal(|ui| {
            ui.label(
                egui::RichText::new(heading)
                    .strong()
                    .color(ui.visuals().error_fg_color),
            );
            if ui
                .button("Copy")
                .on_hover_text("copy the whole message")
                .clicked()
            {
                ui.ctx().copy_text(e.clone());
                notices.status = "error message copied".into();
            }
            if ui.button("Close").clicked() {
                notices.show_error = false;
            }
        });
        egui::ScrollArea::vertical()
            .max_height(MAX_HEIGHT)
            .auto_shrink([false, true])
            .show(ui, |ui| {
                ui.add(
                    egui::Label::new(egui::RichText::new(&e).monospace())
                        .wrap()
                        .selectable(true),
                );
            });
    });
}
