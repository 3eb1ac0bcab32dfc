//! The interactive visualiser (feature `gui`): `run` opens the eframe window on a scene, or
//! renders a screenshot and exits. The app state lives in `state.rs`, in the parts of `parts.rs` (the camera in `view.rs`),
//! the window that lays out the panels in `window.rs`, the panels in `panels/`, the viewport
//! and what it draws in `canvas/`, files and exports in `files/`; the history it holds in
//! `retention.rs`, `branches.rs` (what is set aside) and `undo.rs` (branching and Undo); `frame_log.rs`
//! serves them.

pub mod branches;
pub mod canvas;
pub mod display;
pub mod files;
pub mod frame_log;
pub mod panels;
pub mod parts;
pub mod retention;
pub mod state;
pub mod undo;
pub mod view;
pub mod window;

use std::sync::atomic::{AtomicI32, Ordering};
use std::sync::Arc;

pub use state::TsmApp;
pub use window::Startup;

/// Open the visualiser as `startup` asks: on its scene (a path or built-in name; default: the
/// last one used, else the first built-in), solving its steps first, with its diagram, and with
/// a screenshot, saving the PNG after the steps and exiting. Returns the process exit code.
pub fn run(startup: Startup) -> i32 {
    let exit = Arc::new(AtomicI32::new(0));
    let shot = startup.screenshot.is_some();
    let startup = Startup {
        exit: Some(exit.clone()),
        ..startup
    };
    let options = eframe::NativeOptions {
        viewport: egui::ViewportBuilder::default()
            .with_title("tsm-contact")
            .with_inner_size([1500.0, 940.0])
            .with_min_inner_size([800.0, 600.0]),
        multisampling: 0,
        depth_buffer: 0,
        persist_window: !shot,
        ..Default::default()
    };
    match eframe::run_native(
        "tsm-contact",
        options,
        Box::new(move |cc| Ok(Box::new(TsmApp::new(cc, startup)))),
    ) {
        Ok(()) => exit.load(Ordering::SeqCst),
        Err(e) => {
            eprintln!("error: cannot open the window: {e}");
            1
        }
    }
}
