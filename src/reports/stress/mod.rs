//! The stability suite: hard cases run for both element formulations, each summarised as one
//! row (converged or not, increments, iterations, cut-backs, transfers, the contact point
//! closest to an element end, and an error against an independent reference where there is
//! one). `tsm-contact stress` prints the table and writes `docs/stress.md`; the tests in
//! `tests/solver/stability.rs` check the numbers. `run.rs` runs one case, `cases.rs` holds them,
//! `suite.rs` runs them all and writes the table.

mod cases;
mod run;
mod suite;

pub use cases::*;
pub use run::{first_peak, run, Path, Run, StressRow};
pub use suite::{markdown, suite};
