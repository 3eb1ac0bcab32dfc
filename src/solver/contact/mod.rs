//! Node-to-beam contact: the contact set and its life cycle (activation, transfer to the
//! neighbouring element, release, slide-off), worked on a narrow view of the solver
//! (`ContactView`: the structure and the last converged state).
//!
//! `broad_phase.rs` culls node-body pairs and elements; `probe.rs` finds where a node lies
//! relative to a body's deformed shape; `sides.rs` remembers sides and detects crossings;
//! `transfer.rs` moves contacts between elements and off free ends; `active_set.rs` decides
//! activation and release at a converged pass; `obstacles/` the contacts with rigid
//! obstacles; `friction.rs` the stick points of frictional contacts; `cycle.rs` the guard
//! against cycling that each of those stages keeps for an attempt.

mod active_set;
mod broad_phase;
mod cycle;
mod friction;
mod obstacles;
mod probe;
mod set;
mod sides;
mod transfer;

pub use probe::Probe;
pub use set::{ActiveContact, ContactSet, ContactView, Stick};
