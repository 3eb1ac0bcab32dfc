//! The solver's own physics: elements, linear algebra, Newton, rigid motion, stability, convergence, checkpoints and Example 3.1.
//! One test binary; each module is one subject (`cargo test --release --test solver -- MODULE::`).

#[path = "../common/mod.rs"]
mod common;

mod checkpoints;
mod distributed_loads;
mod elements;
mod example_3_1;
mod linear;
mod newton;
mod rigid_motion;
mod solver_core;
mod stability;
mod step_range;
mod stretch_correction;
mod work_precision;
