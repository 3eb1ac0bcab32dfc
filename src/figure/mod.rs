//! The state of a run as a figure for papers, without a window: what is drawn (`drawing.rs`:
//! the rigid obstacles, the undeformed shape as a grey ghost, each body's deformed curve and
//! faces, a force diagram, pins and contact nodes, in world coordinates), the geometry it is
//! drawn from, shared with the app's viewport (`geometry.rs`), the PNG at any size
//! (`raster.rs`), the SVG (`svg.rs`), and the state drawn for a scene solved some steps
//! (`state.rs`).

pub mod drawing;
pub mod geometry;
pub mod raster;
pub mod state;
pub mod svg;

pub use drawing::{figure, value_at, Diagram, Figure};
