//! What goes over the worker's channels: the commands it takes and the messages it streams
//! back.

use crate::scene::Scene;
use crate::solver::element::beam::BeamElement;
use crate::solver::Solver;
use std::sync::Arc;

use crate::solver::{
    Checkpoint, Event, Formulation, IncrementRecord, IterationRecord, SolveError, StretchCorrection,
};

/// Why a run or a load could not go on, as the app shows it: the solver's typed error (its
/// increment, node and body), or words.
#[derive(Clone, Debug, PartialEq)]
pub enum Failure {
    /// The solver stopped.
    Solve(SolveError),
    /// A scene or file that could not be read, loaded or written, or a caught panic.
    Other(String),
}

impl Failure {
    /// The increment the solver stopped in, where it names one.
    pub fn increment(&self) -> Option<usize> {
        match self {
            Failure::Solve(e) => e.increment(),
            Failure::Other(_) => None,
        }
    }
}

impl std::fmt::Display for Failure {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Failure::Solve(e) => e.fmt(f),
            Failure::Other(s) => f.write_str(s),
        }
    }
}

impl From<String> for Failure {
    fn from(s: String) -> Failure {
        Failure::Other(s)
    }
}

/// Capacity of the worker's outgoing message channel.
pub const CHANNEL_CAPACITY: usize = 1024;

/// A request to the worker. Commands are handled in order; a command that arrives while the
/// worker is solving interrupts the current Newton attempt unless it is `Run`, `RunSteps`,
/// `Step` or `Pause` (those wait for the current increment to converge).
#[derive(Debug)]
pub enum Command {
    /// Replace the scene and start from its undeformed state.
    LoadScene(Box<Scene>),
    /// Solve the scene's remaining steps (up to [`Scene::steps`] steps in all).
    Run,
    /// Solve this many more steps.
    RunSteps(usize),
    /// Stop after the increment being solved.
    Pause,
    /// Solve one more step.
    Step,
    /// March prescribed dof `index` from the current equilibrium to `value`, in increments no
    /// larger than that dof's `|per_step|`. A newer target replaces the old one at once.
    SetTarget {
        /// Index into `Model::prescribed`.
        index: usize,
        /// Target value (m or rad).
        value: f64,
    },
    /// Reload the scene with this element formulation.
    SetFormulation(Formulation),
    /// Reload the scene with this stretch-correction mode (`SolverParams::stretch_correction`).
    SetStretchCorrection(StretchCorrection),
    /// Back to the undeformed state of the current scene.
    Reset,
    /// Go on from an accepted state of the current scene (a branch of its history, or the end
    /// of one set aside); answered by [`Message::Restored`].
    Restore(Arc<Checkpoint>),
    /// Abandon the current work at once (the last converged state is kept).
    Cancel,
    /// End the thread.
    Shutdown,
}

/// The state right after a scene (re)load.
#[derive(Clone, Debug)]
pub struct Loaded {
    /// The scene as solved (its model carries the formulation in use).
    pub scene: Scene,
    /// The element evaluators, needed by `solver::element::shape::element_curve`.
    pub elements: Vec<BeamElement>,
    /// The undeformed state as increment 0 (no forces, no contacts).
    pub initial: IncrementRecord,
    /// "node N v"-style label of every prescribed dof.
    pub prescribed_labels: Vec<String>,
    /// The undeformed state to go on from ([`Command::Restore`]).
    pub checkpoint: Arc<Checkpoint>,
}

impl Loaded {
    /// `scene` with `solver`, a fresh solver of it (at the undeformed state, which becomes
    /// increment 0 and the checkpoint to go back to).
    pub fn new(scene: Scene, solver: &Solver) -> Loaded {
        Loaded {
            checkpoint: Arc::new(solver.checkpoint()),
            initial: super::targets::initial_record(solver),
            elements: solver.structure.elements().to_vec(),
            prescribed_labels: (scene.model.prescribed.iter())
                .map(|p| scene.model.dof_label(p.node, p.dof.offset()))
                .collect(),
            scene,
        }
    }
}

/// What the worker reports.
#[derive(Clone, Debug)]
pub enum Message {
    /// A Newton iteration (may be dropped when the channel is full).
    Iteration(IterationRecord),
    /// A converged increment.
    Increment(Box<IncrementRecord>),
    /// The state after a converged increment, to go on from later ([`Command::Restore`]); sent
    /// after the increment's record.
    Checkpoint(Arc<Checkpoint>),
    /// The worker went back to the accepted state of this increment ([`Command::Restore`]):
    /// what it sends from now on continues from there.
    Restored(usize),
    /// A cut-back or contact event.
    Event(Event),
    /// A solver error, a scene that did not load or a caught panic; the worker stays usable.
    Error(Failure),
    /// A scene was (re)loaded.
    Loaded(Box<Loaded>),
    /// The worker started solving.
    Busy,
    /// The worker has nothing left to do.
    Idle,
}

/// Called after the worker sends messages (e.g. `egui::Context::request_repaint`).
pub type Repaint = Box<dyn Fn() + Send>;
