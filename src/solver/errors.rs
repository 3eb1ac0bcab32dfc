//! Why a run could not continue: the typed, located errors a run gives up with, and their
//! messages.

use serde::{Deserialize, Serialize};

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
    /// A node ends inside a rigid obstacle, or passes through one, in every attempt, even after
    /// the allowed cut-backs (the acceptance check's test of the obstacles).
    #[error(
        "increment {increment}: node {node} ends inside obstacle {obstacle}, or passes through it, {depth:.2e} m deep, after {cutbacks} cut-backs"
    )]
    ObstacleCrossing {
        /// Increment number.
        increment: usize,
        /// Cut-backs tried.
        cutbacks: usize,
        /// User id of the node.
        node: u32,
        /// Name of the obstacle.
        obstacle: String,
        /// How far inside (m): at its end, or the deepest of its path.
        depth: f64,
    },
    /// An obstacle's convex feature (a circle's centre, a polyline's jutting corner) passes
    /// through a beam element between its nodes in every attempt, even after the allowed
    /// cut-backs (the nodes alone cannot hold a small roller or peg).
    #[error(
        "increment {increment}: obstacle {obstacle} passes through {body} element {element} between its nodes, {depth:.2e} m, after {cutbacks} cut-backs"
    )]
    ObstacleThrough {
        /// Increment number.
        increment: usize,
        /// Cut-backs tried.
        cutbacks: usize,
        /// Name of the obstacle.
        obstacle: String,
        /// Name of the body.
        body: String,
        /// The place in its body (from 1) of the element.
        element: usize,
        /// How far beyond the element's chord (m).
        depth: f64,
    },
    /// Every attempt converges to a state where a frictional contact breaks the friction law
    /// (a friction force beyond mu times its pressure, or a slip not resisted by mu times its
    /// pressure), even after the allowed cut-backs.
    #[error(
        "increment {increment}: node {node} on body {body} breaks the friction law (friction force {ratio:.6} times mu N, stick point moved {slipped:.2e} m) after {cutbacks} cut-backs"
    )]
    FrictionLaw {
        /// Increment number.
        increment: usize,
        /// Cut-backs tried.
        cutbacks: usize,
        /// User id of the node.
        node: u32,
        /// Name of the body.
        body: String,
        /// |T| / (mu N).
        ratio: f64,
        /// How far the stick point moved in the increment (m).
        slipped: f64,
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
    /// A snap (no step of the drive finds an equilibrium near the last one) whose every step
    /// bends an element beyond what the element's theory follows: the shape the structure
    /// moves to needs more elements than the body has.
    #[error(
        "increment {increment}: the structure snaps from increment {snap_from}, and every step of the snap bends {body} element {element} by {turn:.2} rad against its chord (a snap's limit: {limit} rad) after {cutbacks} cut-backs: the shape it moves to needs a finer mesh of {body}"
    )]
    MeshTooCoarse {
        /// Increment number.
        increment: usize,
        /// Cut-backs tried before the snap.
        cutbacks: usize,
        /// The increment the snap started at.
        snap_from: usize,
        /// Name of the body.
        body: String,
        /// The place in its body (from 1) of the element.
        element: usize,
        /// Its end rotation against its chord in the snap's softest step (rad).
        turn: f64,
        /// The most a snap's element may turn against its chord (rad).
        limit: f64,
    },
    /// A contact candidate node starts on a body's line with the neighbouring nodes of its own
    /// beam not all clear on one side of it: which side it is on cannot be told.
    #[error(
        "node {node} starts on {body} with its own beam's neighbouring nodes not all on one side of it: move it off the line or its neighbours to one side, or give the contact a side (side: Left or Right)"
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

impl SolveError {
    /// The increment the run stopped in, where the error names one.
    pub fn increment(&self) -> Option<usize> {
        match self {
            SolveError::NoConvergence { increment, .. }
            | SolveError::RoundOffFloor { increment, .. }
            | SolveError::Crossing { increment, .. }
            | SolveError::ObstacleCrossing { increment, .. }
            | SolveError::ObstacleThrough { increment, .. }
            | SolveError::FrictionLaw { increment, .. }
            | SolveError::OutOfRange { increment, .. } => Some(*increment),
            _ => None,
        }
    }
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
