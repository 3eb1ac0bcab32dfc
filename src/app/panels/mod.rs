//! The panels around the viewport, each taking the app state it shows: the toolbar and the
//! prescribed-dof sliders (`controls.rs`), its menus (`menus.rs`), the error panel
//! (`errors.rs`), the details of the selected state (`details.rs`),
//! the convergence and response plots (`plots.rs`), the timeline (`timeline.rs`), the
//! keyboard shortcuts with their window (`shortcuts.rs`) and the sortable table (`table.rs`).

pub mod controls;
pub mod details;
pub mod errors;
pub mod menus;
pub mod plots;
pub mod shortcuts;
pub mod table;
pub mod timeline;
