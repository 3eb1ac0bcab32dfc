//! tsm-contact: Tangent Stiffness Method solver for large-displacement contact of plane frames,
//! with the scene format, the run history, a worker thread and (feature `gui`) an interactive
//! visualiser.

#![warn(missing_docs)]
#[cfg(feature = "gui")]
pub mod app;
pub mod contact_scaling;
pub mod history;
pub mod interactive;
pub mod pin_elastica;
pub mod plain_chain;
pub mod scaling;
pub mod scene;
pub mod solver;
pub mod stress;
#[cfg(test)]
mod test_support;
pub mod work_precision;
pub mod worker;
