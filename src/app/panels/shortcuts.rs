//! The keyboard: Space runs or stops, Left and Right step through the increments (Right at the
//! last one solves one more step), Home and End go to the first and last, Esc stops the
//! solver, F fits the view (in `canvas::viewport`), Ctrl+Z brings back what was set aside and
//! Ctrl+Y (or Ctrl+Shift+Z) what Undo replaced,
//! Ctrl+O opens a scene, Ctrl+S saves the view's PNG, Ctrl+E exports the history, and ? lists
//! them all in a window. Keys act only while no text field has the keyboard.

use egui::Key;

use super::menus;
use crate::app::state::TsmApp;
use crate::worker::Command;

/// Every shortcut and what it does, as the help window lists them.
pub const SHORTCUTS: [(&str, &str); 12] = [
    ("Space", "run the remaining steps, or stop the solver"),
    (
        "Left / Right",
        "previous / next increment (at the last one: solve one more step)",
    ),
    ("Home / End", "first / last increment"),
    ("Esc", "stop the solver (the accepted increments stay)"),
    ("F", "fit the view"),
    ("double-click", "fit the view"),
    (
        "Ctrl+Z",
        "undo: bring back the increments a branch, a change of scene or setting, or Reset set aside",
    ),
    ("Ctrl+Y", "redo: bring back what Undo replaced (also Ctrl+Shift+Z)"),
    ("Ctrl+O", "open a scene file"),
    ("Ctrl+S", "save the viewed increment as a PNG (Export menu: name and size)"),
    ("Ctrl+E", "export the history as JSON and CSV (Export menu: name)"),
    ("?", "show or hide this list"),
];

/// Act on the keys pressed this frame.
pub fn handle(app: &mut TsmApp, ctx: &egui::Context) {
    if ctx.egui_wants_keyboard_input() {
        return;
    }
    let command = |k: Key| ctx.input_mut(|i| i.consume_key(egui::Modifiers::COMMAND, k));
    let shifted = egui::Modifiers::COMMAND | egui::Modifiers::SHIFT;
    if ctx.input_mut(|i| i.consume_key(shifted, Key::Z)) || command(Key::Y) {
        app.redo();
    }
    if command(Key::Z) {
        app.undo();
    }
    if command(Key::O) {
        menus::open_dialog(app, ctx);
    }
    if command(Key::S) {
        menus::export_png(app);
    }
    if command(Key::E) {
        menus::export_json(app);
        if app.notices.error.is_none() {
            menus::export_csv(app);
        }
    }
    if app.session.loaded.is_none() {
        return;
    }
    let pressed = |k: Key| ctx.input(|i| i.key_pressed(k));
    let last = app.last();
    if pressed(Key::Space) {
        if app.session.busy {
            app.send(Command::Cancel);
        } else {
            app.playback.selected = last;
            app.send(Command::Run);
        }
    }
    if pressed(Key::Escape) && app.session.busy {
        app.send(Command::Cancel);
    }
    if pressed(Key::ArrowLeft) {
        app.playback.selected = app.playback.selected.min(last).saturating_sub(1);
        app.playback.playing = false;
    }
    if pressed(Key::ArrowRight) {
        app.playback.playing = false;
        if app.playback.selected < last {
            app.playback.selected += 1;
        } else if !app.session.busy {
            app.send(Command::Step);
        }
    }
    if pressed(Key::Home) {
        app.playback.selected = 0;
        app.playback.playing = false;
    }
    if pressed(Key::End) {
        app.playback.selected = last;
        app.playback.playing = false;
    }
    if pressed(Key::Questionmark) || pressed(Key::Slash) && ctx.input(|i| i.modifiers.shift) {
        app.look.show_shortcuts = !app.look.show_shortcuts;
    }
}

/// The window that lists the shortcuts, while it is open.
pub fn window(app: &mut TsmApp, ctx: &egui::Context) {
    let mut open = app.look.show_shortcuts;
    egui::Window::new("Shortcuts")
        .open(&mut open)
        .collapsible(false)
        .resizable(false)
        .show(ctx, |ui| {
            egui::Grid::new("shortcuts").striped(true).show(ui, |ui| {
                for (key, what) in SHORTCUTS {
                    ui.label(egui::RichText::new(key).strong());
                    ui.label(what);
                    ui.end_row();
                }
            });
        });
    app.look.show_shortcuts = open;
}
