//! What the solver reports: a record per Newton iteration, a record per converged increment,
//! contact and control events, typed errors, and the observer trait through which a caller
//! (CLI, worker thread, test) receives them and can ask the run to stop.

use serde::{Deserialize, Serialize};

use super::model::Model;

/// A node's position and rotation at one state: x, y, phi.
pub type NodeState = [f64; 3];

/// How an accepted increment met the equilibrium test.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum IncrementStatus {
    /// The relative residual is within the tolerance.
    #[default]
    Converged,
    /// Newton stalled at the round-off floor of the residual, above the tolerance but within
    /// `SolverParams::roundoff_bound`.
    #[serde(rename = "roundoff")]
    RoundOff {
        /// Relative residual reached over the tolerance (> 1).
        ratio: f64,
    },
}

impl IncrementStatus {
    /// The status of a relative residual `rel` under `tolerance` and the round-off `bound`, or
    /// None where it is not acceptable at all.
    pub fn of(rel: f64, tolerance: f64, bound: f64) -> Option<IncrementStatus> {
        if rel <= tolerance {
            Some(IncrementStatus::Converged)
        } else if rel <= bound.max(tolerance) {
            Some(IncrementStatus::RoundOff {
                ratio: rel / tolerance,
            })
        } else {
            None
        }
    }
}

/// One Newton iteration.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct IterationRecord {
    /// Increment number this iteration belongs to (1-based, counting converged increments).
    pub increment: usize,
    /// Iteration number within the increment attempt (1-based).
    pub iteration: usize,
    /// Euclidean norm of the unbalanced force over the free dofs after this iteration (N).
    pub residual: f64,
    /// `residual / reference` (the convergence measure).
    pub relative_residual: f64,
    /// Reference force the residual is measured against (N).
    pub reference: f64,
    /// Norm of the displacement correction of this iteration.
    pub step_norm: f64,
    /// Number of active contacts during this iteration.
    pub active_contacts: usize,
}

/// Something that happened during a run.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum Event {
    /// The increment was halved after a failed attempt.
    CutBack {
        /// Increment number being attempted.
        increment: usize,
        /// Why the attempt failed.
        reason: String,
        /// Fraction of the requested step now attempted.
        fraction: f64,
    },
    /// A contact changed state.
    Contact(ContactEvent),
    /// The stretch correction (`StretchCorrection::AfterCutBack`) is on from this increment's
    /// next attempt to the end of the run.
    StretchCorrectionOn {
        /// Increment number being attempted.
        increment: usize,
    },
}

/// Kinds of contact state change.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum ContactChange {
    /// A node crossed a beam and the contact element was switched on.
    Activated,
    /// The contact point left its element and moved to the neighbouring element.
    Transferred,
    /// The contact force turned tensile.
    Released,
    /// The node slid off a free end of the beam.
    SlidOff,
}

impl ContactChange {
    /// The change as the verb of an event line ("node 7 touches bar element 3").
    pub fn verb(self) -> &'static str {
        match self {
            ContactChange::Activated => "touches",
            ContactChange::Transferred => "moves onto",
            ContactChange::Released => "releases from",
            ContactChange::SlidOff => "slides off",
        }
    }
}

impl Event {
    /// The number of the increment it happened in.
    pub fn increment(&self) -> usize {
        match self {
            Event::CutBack { increment, .. } | Event::StretchCorrectionOn { increment } => {
                *increment
            }
            Event::Contact(c) => c.increment,
        }
    }

    /// The event in one line, its element named by `model` (`Model::element_label`): what the
    /// CLI prints and the app lists.
    pub fn describe(&self, model: &Model) -> String {
        match self {
            Event::CutBack {
                increment,
                reason,
                fraction,
            } => format!(
                "cut-back in increment {increment}: {reason}; now trying {fraction} of the step"
            ),
            Event::StretchCorrectionOn { increment } => format!(
                "stretch correction on from increment {increment} (the run's first cut-back)"
            ),
            // Only a release carries a force: the tensile one that let go.
            Event::Contact(c) if c.change == ContactChange::Released => format!(
                "node {} {} {} (li/l = {:.4}, Yc = {:+.4e}) at iteration {}",
                c.node,
                c.change.verb(),
                model.element_label(c.element),
                c.xi,
                c.force,
                c.iteration
            ),
            Event::Contact(c) => format!(
                "node {} {} {} (li/l = {:.4}) at iteration {}",
                c.node,
                c.change.verb(),
                model.element_label(c.element),
                c.xi,
                c.iteration
            ),
        }
    }
}

/// A contact event with where and when it happened.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ContactEvent {
    /// What happened.
    pub change: ContactChange,
    /// Increment number.
    pub increment: usize,
    /// Iteration within the increment (0 = between converged passes).
    pub iteration: usize,
    /// User id of the contact node.
    pub node: u32,
    /// Element index (0-based) the contact is on after the change (before, for releases).
    pub element: usize,
    /// Name of the body the element belongs to.
    pub body: String,
    /// li/l at the change.
    pub xi: f64,
    /// Contact force Yc at a release (N): the force that let go; 0 for the other changes.
    pub force: f64,
}

/// An active contact in a converged state.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ContactState {
    /// User id of the contact node.
    pub node: u32,
    /// Element index (0-based, over every beam of the model; for indexing `element_forces`).
    pub element: usize,
    /// The element's place in its body (from 1): the numbering the scene, the app and the
    /// messages use ("body element 3").
    #[serde(default)]
    pub place: usize,
    /// Body name.
    pub body: String,
    /// li/l.
    pub xi: f64,
    /// Contact force Yc in the element's chord frame (N).
    pub force: f64,
    /// Compressive contact pressure (N): positive when the bodies push on each other.
    pub pressure: f64,
}

/// A reaction at a supported or prescribed dof.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Reaction {
    /// User node id.
    pub node: u32,
    /// "u", "v" or "phi".
    pub dof: String,
    /// Reaction force or moment (N or N m).
    pub value: f64,
}

/// One converged increment.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct IncrementRecord {
    /// Increment number (1-based).
    pub increment: usize,
    /// Values of the prescribed displacements after this increment.
    pub prescribed: Vec<f64>,
    /// Load factor after this increment.
    pub load_factor: f64,
    /// Newton iterations used (all passes of the active set together).
    pub iterations: usize,
    /// Iterations needed to reduce the unbalanced force by 8 orders of magnitude from its value
    /// at the start of the increment (None if never reached).
    pub iterations_8_orders: Option<usize>,
    /// Relative residual at convergence.
    pub relative_residual: f64,
    /// Reference force of the convergence test (N).
    pub reference: f64,
    /// Estimated round-off floor of the relative residual.
    pub roundoff_floor: f64,
    /// How the increment met the equilibrium test: within the tolerance, or at the round-off
    /// floor within `SolverParams::roundoff_bound` (with the ratio reached over the tolerance).
    #[serde(default)]
    pub status: IncrementStatus,
    /// Cut-backs taken before this increment converged.
    pub cutbacks: usize,
    /// Residual history of every iteration.
    pub residuals: Vec<IterationRecord>,
    /// Node positions (x, y) and rotations, in node order.
    pub nodes: Vec<[f64; 3]>,
    /// (N, Mi, Mj) for every beam element.
    pub element_forces: Vec<[f64; 3]>,
    /// Reactions at supported and prescribed dofs.
    pub reactions: Vec<Reaction>,
    /// Active contacts.
    pub contacts: Vec<ContactState>,
    /// Largest penetration of an inactive candidate node through a body's deformed shape, in
    /// element lengths, measured against the sides at the previous converged state (0 if none).
    pub max_penetration: f64,
    /// Contact events of this increment.
    pub events: Vec<Event>,
    /// Wall time of this increment, cut-back attempts included (s).
    pub seconds: f64,
}

/// An observer's answer: go on or stop the run.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Flow {
    /// Keep going.
    Continue,
    /// Stop as soon as possible (the last converged state is kept).
    Stop,
}

/// Receives the solver's records as they happen.
pub trait Observer {
    /// After each Newton iteration.
    fn iteration(&mut self, _record: &IterationRecord) -> Flow {
        Flow::Continue
    }
    /// After each converged increment.
    fn increment(&mut self, _record: &IncrementRecord) -> Flow {
        Flow::Continue
    }
    /// On every event.
    fn event(&mut self, _event: &Event) {}
}

/// An observer that ignores everything.
pub struct Silent;
impl Observer for Silent {}

/// Why a run could not continue.
#[derive(Clone, Debug, PartialEq, thiserror::Error, Serialize, Deserialize)]
pub enum SolveError {
    /// Newton failed even after the allowed cut-backs.
    #[error(
        "increment {increment}: no convergence after {cutbacks} cut-backs (last attempt: {reason})"
    )]
    NoConvergence {
        /// Increment number.
        increment: usize,
        /// Cut-backs tried.
        cutbacks: usize,
        /// Why the last attempt failed.
        reason: String,
    },
    /// Newton stalled at the round-off floor with a relative residual above
    /// `SolverParams::roundoff_bound`, even after the allowed cut-backs.
    #[error(
        "increment {increment}: Newton stalls at relative residual {residual:.3e} (round-off floor {floor:.1e}), above the bound {bound:.0e} for acceptance at round-off, after {cutbacks} cut-backs"
    )]
    RoundOffFloor {
        /// Increment number.
        increment: usize,
        /// Cut-backs tried.
        cutbacks: usize,
        /// Relative residual reached.
        residual: f64,
        /// Round-off floor estimate there.
        floor: f64,
        /// The bound it exceeds.
        bound: f64,
    },
    /// A node passes through a body it is not in contact with in every attempt, even after the
    /// allowed cut-backs (the acceptance check's geometric test).
    #[error(
        "increment {increment}: node {node} passes through {body} element {element} ({depth:.2e} element lengths beyond it) after {cutbacks} cut-backs"
    )]
    Crossing {
        /// Increment number.
        increment: usize,
        /// Cut-backs tried.
        cutbacks: usize,
        /// User id of the node.
        node: u32,
        /// Name of the body.
        body: String,
        /// The place in its body (from 1) of the element the node ends beyond.
        element: usize,
        /// How far beyond, in element lengths.
        depth: f64,
    },
    /// Every attempt converges to a state where an element has turned against its chord, or
    /// changed its strain, by more than one increment may take (`acceptance::MAX_TURN_STEP`,
    /// `acceptance::MAX_STRAIN_STEP`), even after the allowed cut-backs: the equilibrium Newton
    /// finds lies far from the path.
    #[error(
        "increment {increment}: {body} element {element} turns by {turn:.2} rad against its chord and changes its strain by {strain:.1e} within the increment after {cutbacks} cut-backs (limits {max_turn} rad and {max_strain}): the equilibrium found lies far from the path"
    )]
    OutOfRange {
        /// Increment number.
        increment: usize,
        /// Cut-backs tried.
        cutbacks: usize,
        /// Name of the body.
        body: String,
        /// The place in its body (from 1) of the element.
        element: usize,
        /// The larger change of its end rotations against its chord (rad).
        turn: f64,
        /// The change of its axial strain.
        strain: f64,
        /// The limit of the rotation change (rad).
        max_turn: f64,
        /// The limit of the strain change.
        max_strain: f64,
    },
    /// A contact candidate node starts on a body's line with the neighbouring nodes of its own
    /// beam not all clear on one side of it: which side it is on cannot be told.
    #[error(
        "node {node} starts on {body} with its own beam's neighbouring nodes not all on one side of it: move it off the line or its neighbours to one side"
    )]
    AmbiguousSide {
        /// User id of the node.
        node: u32,
        /// Name of the body.
        body: String,
    },
    /// The tangent is singular: the structure is a mechanism at these dofs.
    #[error("the structure is a mechanism: {}", mechanism_text(dofs, *complete, bodies))]
    Mechanism {
        /// Free dofs as "node N u/v/phi".
        dofs: Vec<String>,
        /// Whether `dofs` is every dof of the null space (small models, and rigid motions the
        /// supports leave free), or only the first that a factorisation finds without
        /// stiffness (inner mechanisms of large ones).
        complete: bool,
        /// The bodies (`body "NAME"`) and lone nodes (`node N`) those dofs belong to.
        bodies: Vec<String>,
    },
    /// A part of the structure (bodies joined by beams, or a lone node) can move rigidly: its
    /// supports and prescribed displacements do not stop all its rigid motions.
    #[error(
        "the structure is a mechanism: {} can move rigidly ({motions} rigid motion{} not stopped; {}): support it further",
        listed(parts, "parts"),
        if *motions == 1 { "" } else { "s" },
        held_text(held)
    )]
    RigidMotion {
        /// The bodies (`body "NAME"`) and lone nodes (`node N`) that can move.
        parts: Vec<String>,
        /// How many rigid motions their held dofs leave free, over all of them.
        motions: usize,
        /// Their held dofs, as "node N u/v/phi".
        held: Vec<String>,
    },
    /// The observer asked the run to stop.
    #[error("stopped by the caller")]
    Stopped,
    /// The request does not fit the model (e.g. arc-length control without loads).
    #[error("invalid request: {reason}")]
    Invalid {
        /// What is wrong.
        reason: String,
    },
}

/// Items in words: all of them up to eight, else how many `what` and the first eight.
fn listed(items: &[String], what: &str) -> String {
    match items.len() {
        n if n <= 8 => items.join(", "),
        n => format!("{n} {what}, among them {},", items[..8].join(", ")),
    }
}

/// The held dofs of the parts that can move, in words.
fn held_text(held: &[String]) -> String {
    match held.len() {
        0 => "nothing holds them".into(),
        _ => format!("held only at {}", listed(held, "dofs")),
    }
}

/// The dofs of a mechanism in words: how many, the bodies they belong to, the first few, and
/// whether that is all of them.
pub fn mechanism_text(dofs: &[String], complete: bool, bodies: &[String]) -> String {
    const SHOWN: usize = 8;
    let first = dofs[..dofs.len().min(SHOWN)].join(", ");
    let owners = match bodies.len() {
        0 => String::new(),
        n if n <= SHOWN => format!(" (in {})", bodies.join(", ")),
        n => format!(
            " (in {n} bodies and nodes, among them {})",
            bodies[..SHOWN].join(", ")
        ),
    };
    match (complete, dofs.len()) {
        (false, _) => format!(
            "the free dof {first}{owners} has no stiffness (the first found; there may be more)"
        ),
        (true, 1) => format!("the free dof {first}{owners} has no stiffness"),
        (true, n) if n <= SHOWN => {
            format!("these {n} free dofs{owners} have no stiffness: {first}")
        }
        (true, n) => format!("{n} free dofs{owners} have no stiffness, among them {first}"),
    }
}
