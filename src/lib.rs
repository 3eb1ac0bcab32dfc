//! tsm-contact: Tangent Stiffness Method solver for large-displacement contact of plane frames,
//! with the scene format, the run history, a worker thread, (feature `figures`) the figure of a
//! state as PNG or SVG, (feature `reports`) the reports that measure the solver and (feature
//! `gui`) an interactive visualiser. The arrows point one
//! way: app -> worker -> solver, scene -> solver, reports -> solver; `tests/inputs/architecture.rs`
//! checks them.

#![warn(missing_docs)]
#[cfg(feature = "gui")]
pub mod app;
pub mod audit;
#[cfg(feature = "figures")]
pub mod figure;
pub mod history;
#[cfg(feature = "reports")]
pub mod reports;
pub mod scene;
pub mod solver;
#[cfg(test)]
mod test_support;
pub mod worker;
