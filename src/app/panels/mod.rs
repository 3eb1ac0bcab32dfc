//! The panels around the viewport, each taking the app state it shows: the toolbar and the
//! prescribed-dof sliders (`controls.rs`), the details of the selected state (`details.rs`),
//! the convergence and response plots (`plots.rs`) and the timeline (`timeline.rs`).

pub mod controls;
pub mod details;
pub mod plots;
pub mod timeline;
