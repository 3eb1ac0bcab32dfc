//! The keyboard: Space runs or stops, Left and Right step through the increments (Right at the
//! last one solves one more step), Home and End go to the first and last, Esc stops the
//! solver, F fits the view (in `canvas::viewport`), Ctrl+Z brings back what was set aside and
//! Ctrl+Y (or Ctrl+Shift+Z) what Undo replaced,
//! Ctrl+O opens a scene, Ctrl+S saves the view's PNG, Ctrl+E exports the history, and ? lists
//! them all in a window. Keys act only while no text field has the keyboard.

use egui::Key;

use crate::app::files::dialog::Purpose;
use crate::app::parts::{Action, Export, Look, Playback, Study};
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
pub fn handle(
    study: &Study,
    playback: &mut Playback,
    look: &mut Look,
    actions: &mut Vec<Action>,
    ctx: &egui::Context,
) {
    if ctx.egui_wants_keyboard_input() {
        return;
    }
    let command = |k: Key| ctx.input_mut(|i| i.consume_key(egui::Modifiers::COMMAND, k));
    let shifted = egui::Modifiers::COMMAND | egui::Modifiers::SHIFT;
    if ctx.input_mut(|i| i.consume_key(shifted, Key::Z)) || command(Key::Y) {
        actions.push(Action::Redo);
    }
    if command(Key::Z) {
        actions.push(Action::Undo);
    }
    if command(Key::O) {
        actions.push(Action::Dialog(Purpose::OpenScene));
    }
    if command(Key::S) {
        actions.push(Action::Export(Export::Png));
    }
    if command(Key::E) {
        actions.push(Action::Export(Export::History));
    }
    if study.loaded.is_none() {
        return;
    }
    let pressed = |k: Key| ctx.input(|i| i.key_pressed(k));
    let last = study.last();
    if pressed(Key::Space) {
        if study.busy {
            actions.push(Action::Send(Command::Cancel));
        } else {
            playback.view(last);
            actions.push(Action::Send(Command::Run));
        }
    }
    if pressed(Key::Escape) && study.busy {
        actions.push(Action::Send(Command::Cancel));
    }
    if pressed(Key::ArrowLeft) {
        playback.previous(last);
    }
    if pressed(Key::ArrowRight) && !playback.next(last) && !study.busy {
        actions.push(Action::Send(Command::Step));
    }
    if pressed(Key::Home) {
        playback.view(0);
    }
    if pressed(Key::End) {
        playback.view(last);
    }
    if pressed(Key::Questionmark) || pressed(Key::Slash) && ctx.input(|i| i.modifiers.shift) {
        look.show_shortcuts = !look.show_shortcuts;
    }
}

/// The window that lists the shortcuts, while it is open.
pub fn window(look: &mut Look, ctx: &egui::Context) {
    let mut open = look.show_shortcuts;
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
    look.show_shortcuts = open;
}
