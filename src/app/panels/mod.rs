//! The panels around the viewport, each taking the parts of the app state it shows (never
//! the whole app mutably) and asking for anything beyond them with an action
//! (`crate::app::parts::Action`), which the window applies once the panels have drawn
//! (`TsmApp::apply`): the toolbar and the prescribed-dof sliders (`controls.rs`), its menus
//! (`menus.rs`), the error panel (`errors.rs`), the details of the selected state
//! (`details.rs`), the convergence and response plots (`plots.rs`), the timeline
//! (`timeline.rs`), the keyboard shortcuts with their window (`shortcuts.rs`) and the sortable
//! table (`table.rs`). A new panel is a file here, its `mod` line, and its place in
//! `window.rs`.

pub mod controls;
pub mod details;
pub mod errors;
pub mod menus;
pub mod plots;
pub mod shortcuts;
pub mod table;
pub mod timeline;
