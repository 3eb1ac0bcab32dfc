//! Increment control: the `Solver` of a run (`solver.rs`), displacement and load control with
//! cut-backs (`increments.rs`), arc-length control (`arc_length.rs`), the acceptance check
//! before a commit and the typed errors of a run that gives up (`acceptance.rs`), and the
//! commit of an accepted attempt into the converged state and its record (`commit.rs`), checkpoints of accepted states to go on from (`checkpoint.rs`), and the snap of a
//! structure past a limit point of its drive (`snap.rs`).

mod acceptance;
mod arc_length;
mod checkpoint;
mod commit;
mod increments;
mod snap;
mod solver;

pub use checkpoint::Checkpoint;
pub use solver::Solver;
