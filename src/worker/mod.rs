//! The solver worker thread ("tsm-solver"): owns the `Solver`, takes commands over a channel
//! (load, run, step, drive a prescribed dof to a target, change formulation, reset, cancel)
//! and streams iterations, increments, events and errors back over a bounded channel. Newer
//! commands interrupt stale work through the observer; solver panics are caught and reported.
//! No GUI dependency: the app, the tests and any other front end use it the same way.

mod handle;
mod messages;
mod relay;
mod targets;
mod thread;

pub use handle::Worker;
pub use messages::{Command, Failure, Loaded, Message, Repaint, CHANNEL_CAPACITY};
pub use targets::{initial_record, next_target};
