//! Newton-Raphson for one increment attempt, the same iteration for every increment control:
//! `attempt.rs` runs it, on what `iteration.rs` gives it to read; `constraint.rs` closes the equations (prescribed displacements and
//! load factor, or an arc length); `convergence.rs` tells convergence, stall and failure;
//! `stretch.rs` corrects the chords of an update and `contact_gap.rs` its contact nodes'
//! offsets from their chords; `viscous.rs` damps the
//! pseudo-time steps of a snap; `failure.rs` types what goes wrong;
//! `workspace.rs` holds the scratch space the attempts share.

mod attempt;
mod constraint;
mod contact_gap;
mod convergence;
mod failure;
mod iteration;
mod stretch;
#[cfg(test)]
mod tests;
mod viscous;
mod workspace;

pub use constraint::Constraint;
pub use failure::{AttemptError, Converged};
pub use iteration::Newton;
pub use viscous::Viscous;
pub use workspace::Workspace;
