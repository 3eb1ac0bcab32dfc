//! The acceptance check every increment passes before it is committed, independent of the
//! contact bookkeeping that produced it:
//!
//! - **Equilibrium**: the relative residual is within the tolerance (`IncrementStatus::
//!   Converged`), or, where Newton stalled at the round-off floor, within
//!   `SolverParams::roundoff_bound` (`IncrementStatus::RoundOff`). Anything else is refused
//!   (`IncrementStatus::of`).
//! - **Geometry** (`CrossingCheck`, `crossing.rs`): no contact-candidate node passed through an
//!   element of a candidate body it is not in contact with, tested on node positions and
//!   rotations alone; `chord.rs` holds the swept chord, `grid.rs` the grid of the long bodies;
//!   and no candidate node inside a rigid obstacle beyond the obstacle tolerance
//!   (`obstacle.rs`), nor an obstacle's convex feature through an element between its nodes
//!   (`feature.rs`), nor a node that stands off the axes (a pin's radius, the beams'
//!   thicknesses) within its contact distance of a body it is not in contact with
//!   (`rim.rs`).
//! - **Friction** (`friction.rs`): no friction force beyond mu times the pressure, and exactly
//!   that, against the slip, where a contact slipped.

mod chord;
mod crossing;
mod feature;
mod friction;
mod grid;
mod obstacle;
mod range;
mod rim;

pub use crossing::{Crossing, CrossingCheck, CrossingMemory};
pub use feature::{feature_through, FeatureCrossing};
pub use friction::{friction_law, FrictionRecord, FrictionViolation, FRICTION_LAW_TOLERANCE};
pub use obstacle::{inside_obstacle, ObstacleCrossing};
pub use range::{
    most_bent, out_of_range, spun, OutOfRange, MAX_SPIN_STEP, MAX_STRAIN_STEP, MAX_TURN_STEP,
};
pub use rim::rim_overlap;
