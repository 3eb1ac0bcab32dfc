//! What the app reads and writes: scene files (the native dialogs on a thread of their own,
//! recent files, dropped files, the remembered scene at start-up: `scenes.rs`, `dialog.rs`),
//! exports of the history (`export.rs`) and pictures of the window (`screenshot.rs`).

pub mod dialog;
pub mod export;
pub mod scenes;
pub mod screenshot;
