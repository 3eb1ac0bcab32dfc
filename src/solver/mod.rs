//! The Tangent Stiffness Method solver for plane frames with node-to-beam contact. Knows no
//! file format, thread or screen.
//!
//! The folders follow the method: `element/` (the TSM beam and the contact element),
//! `linear/` (the band solve), `assembly/` (dofs, ordering, unbalanced force and tangent),
//! `contact/` (the contact set and its life cycle), `newton/` (one Newton iteration for every
//! increment control), `acceptance/` (the check every increment passes before it is
//! committed) and `control/` (the `Solver`: increment control and cut-backs). `model/` (with
//! the obstacles' curves), `load_path.rs`, `params.rs`, `report.rs` and `errors.rs` (what a run stops with) are the
//! vocabulary they share; `structure.rs` and `state.rs` the prepared model and the converged
//! state; `rigid_modes.rs` tells a mechanism's free rigid motions, and `index_map.rs` is the
//! small map the contact code keys by node and body.

pub mod acceptance;
pub mod assembly;
pub mod contact;
pub mod control;
pub mod element;
pub mod errors;
pub mod index_map;
pub mod linear;
pub mod load_path;
pub mod model;
pub mod newton;
pub mod params;
pub mod report;
pub mod rigid_modes;
pub mod state;
pub mod structure;

pub use acceptance::{Crossing, CrossingCheck};
pub use control::{Checkpoint, Solver};
pub use load_path::{LoadPath, PathPoint, Stage, StageMotion};
pub use model::{
    Beam, Body, ContactPair, DistributedLoad, Dof, Formulation, Load, Model, Node, Obstacle,
    Prescribed, Section, Shape, Support,
};
pub use params::{SolverParams, StretchCorrection};
pub use report::{
    ContactChange, Event, Flow, Friction, IncrementRecord, IncrementStatus, IterationRecord,
    NodeState, Observer, ObstacleEvent, ObstacleState, Silent, SolveError,
};
pub use structure::Structure;
