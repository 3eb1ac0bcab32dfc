//! The panels around the viewport, each taking the app state it shows: the toolbar and the
//! prescribed-dof sliders (`controls.rs`), the details of the selected state (`details.rs`),
//! the convergence and response plots (`plots.rs`), the timeline (`timeline.rs`) and the
//! keyboard shortcuts with their window (`shortcuts.rs`).

pub mod controls;
pub mod details;
pub mod plots;
pub mod shortcuts;
pub mod timeline;
