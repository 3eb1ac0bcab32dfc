//! The Tangent Stiffness Method solver for plane frames with node-to-beam contact.
//! Knows nothing of scenes files or the GUI.

pub mod acceptance;
pub mod active_set;
pub mod angle;
pub mod arc_length;
pub mod assembly;
pub mod beam;
#[cfg(target_arch = "x86_64")]
pub mod beam_lanes;
pub mod broad_phase;
pub mod contact;
pub mod contact_element;
pub mod control;
pub mod dual;
mod ldlt;
pub mod linear;
pub mod loads;
pub mod model;
pub mod newton;
pub mod params;
mod rcm;
pub mod reduce;
pub mod report;
pub mod shape;
mod simd;
mod twisted;

pub use acceptance::{Crossing, CrossingCheck, IncrementStatus, NodeState};
pub use control::Solver;
pub use model::{
    Beam, Body, ContactPair, Dof, Formulation, Load, Model, Node, Prescribed, Section, Support,
};
pub use params::{SolverParams, StretchCorrection};
pub use report::{
    ContactChange, Event, Flow, IncrementRecord, IterationRecord, Observer, Silent, SolveError,
};
