//! The panels around the viewport, each taking the parts of the app state it shows (never
//! the whole app mutably) and asking for anything beyond them with an action
//! (`crate::app::parts::Action`), which the window applies once the panels have drawn
//! (`TsmApp::apply`): the toolbar and the prescribed-dof sliders (`controls.rs`), its menus
//! (`menus.rs`), the error panel (`errors.rs`), the details of the selected state
//! (`details.rs`), the convergence and response plots (`plots.rs`), the timeline
//! (`timeline.rs`), the keyboard shortcuts with their window (`shortcuts.rs`) and the sortable
//! table (`table.rs`); and their layout round the viewport (`lay_out`). A new panel is a file
//! here, its `mod` line and its place in `lay_out`.

pub mod controls;
pub mod details;
pub mod errors;
pub mod menus;
pub mod plots;
pub mod shortcuts;
pub mod table;
pub mod timeline;

use crate::app::canvas::viewport;
use crate::app::state::TsmApp;

/// Lay the panels out round the viewport, each with the parts of the app it shows (the app
/// itself goes to none of them), after the keys; `gpu` draws the beams through wgpu.
pub(crate) fn lay_out(app: &mut TsmApp, ui: &mut egui::Ui, gpu: Option<&egui_wgpu::RenderState>) {
    let ctx = &ui.ctx().clone();
    shortcuts::handle(
        &app.study,
        &mut app.playback,
        &mut app.look,
        &mut app.actions,
        ctx,
    );
    egui::Panel::top("toolbar").show(ui, |ui| {
        controls::toolbar(
            &app.study,
            &mut app.look,
            &mut app.files,
            &app.notices,
            &mut app.actions,
            ui,
        )
    });
    errors::panel(&mut app.notices, ui);
    egui::Panel::bottom("timeline")
        .resizable(true)
        .default_size(300.0)
        .min_size(200.0)
        .show(ui, |ui| {
            timeline::show(&app.study, &mut app.playback, &mut app.actions, ui);
            ui.separator();
            plots::show(
                &app.study,
                app.playback.selected,
                &mut app.look,
                &mut app.frame.layout,
                ui,
            );
        });
    egui::Panel::right("details")
        .resizable(true)
        .default_size(330.0)
        .show(ui, |ui| {
            egui::ScrollArea::vertical().show(ui, |ui| {
                controls::sliders(&app.study, app.playback.selected, &mut app.actions, ui);
                ui.separator();
                details::show(&app.study, app.playback.selected, &app.look, ui);
            });
        });
    egui::CentralPanel::no_frame().show(ui, |ui| {
        viewport::show(
            &app.study,
            app.playback.selected,
            &mut app.look,
            &mut app.frame.layout,
            &app.notices,
            &mut app.actions,
            ui,
            gpu,
        )
    });
    shortcuts::window(&mut app.look, ctx);
    menus::drop_hint(ctx);
    table::window(&app.study, app.playback.selected, &mut app.look, ctx);
}

#[cfg(test)]
mod tests {
    /// The convergence plot's decade marks all lie within the range shown (a mark below its
    /// foot would be labelled outside the frame), one every power of two decades, 1e-8 among
    /// them: from 1e-12.3 to 1e3.5, every second decade from 1e-12 to 1e2.
    #[test]
    fn decade_marks_lie_within_the_range_shown() {
        let input = egui_plot::GridInput {
            bounds: (-12.3, 3.5),
            base_step_size: 0.1,
        };
        let marks: Vec<f64> = super::plots::decades(input)
            .iter()
            .map(|m| m.value)
            .collect();
        let expected: Vec<f64> = (0..8).map(|k| -12.0 + 2.0 * k as f64).collect();
        assert_eq!(marks, expected);
    }
}
