//! The app: its panels and keys under egui_kittest, results, snapshots, the worker thread and a screenshot of a real window.
//! One test binary; each module is one subject (`cargo test --release --test app -- MODULE::`).

#[path = "../common/mod.rs"]
mod common;
#[cfg(feature = "gui")]
#[path = "../gui_support/mod.rs"]
mod gui_support;

mod gui;
mod gui_keys;
mod gui_results;
mod gui_snapshots;
mod gui_work;
mod screenshot;
mod worker;
