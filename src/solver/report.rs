//! What the solver reports: a record per Newton iteration, a record per converged increment,
//! contact and control events, typed errors, and the observer trait through which a caller
//! (CLI, worker thread, test) receives them and can ask the run to stop.

use serde::{Deserialize, Serialize};

pub use super::errors::{mechanism_text, SolveError};
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
    /// A state on the way of a snap (`Event::Snaps`): the structure moves from the last state
    /// that had an equilibrium to the next stable one along a damped path, and this state is
    /// in equilibrium with the viscous force of that path, not without it. It has no
    /// equilibrium to check; its sides, contacts and supports are checked as every state's.
    Snapping {
        /// The relative residual of its equilibrium, the viscous force left out.
        residual: f64,
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
    /// A contact with a rigid obstacle began or ended.
    Obstacle(ObstacleEvent),
    /// The stretch correction (`StretchCorrection::AfterCutBack`, `WhereNeeded`) is on for every
    /// update from this increment's
    /// next attempt to the end of the run.
    StretchCorrectionOn {
        /// Increment number being attempted.
        increment: usize,
    },
    /// No step of the drive, however short, finds an equilibrium near the last one (a limit
    /// point of the drive, or a contact let go with nothing to hold the structure there): the
    /// drive is held and the structure moves to the next stable state along a damped path, its
    /// states marked [`IncrementStatus::Snapping`] up to the first in equilibrium.
    Snaps {
        /// Increment number of the first state of the snap.
        increment: usize,
        /// Why the last attempt failed.
        reason: String,
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
    /// A frictional contact began to slip: its friction force reached mu times its pressure.
    Slips,
    /// A slipping frictional contact stuck again.
    Sticks,
}

impl ContactChange {
    /// The change as the verb of an event line ("node 7 touches bar element 3").
    pub fn verb(self) -> &'static str {
        match self {
            ContactChange::Activated => "touches",
            ContactChange::Transferred => "moves onto",
            ContactChange::Released => "releases from",
            ContactChange::SlidOff => "slides off",
            ContactChange::Slips => "slips on",
            ContactChange::Sticks => "sticks on",
        }
    }
}

impl Event {
    /// The number of the increment it happened in.
    pub fn increment(&self) -> usize {
        match self {
            Event::CutBack { increment, .. }
            | Event::StretchCorrectionOn { increment }
            | Event::Snaps { increment, .. } => *increment,
            Event::Contact(c) => c.increment,
            Event::Obstacle(o) => o.increment,
        }
    }

    /// The event in one line, its element named by `model` ([`Model::element_label`]): what the
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
                "stretch correction on for every update from increment {increment} (the run's first cut-back)"
            ),
            Event::Snaps { increment, reason } => format!(
                "the structure snaps from increment {increment}: no step finds an equilibrium near the last one ({reason}); the drive is held while it moves to the next stable state along a damped path (states marked snapping)"
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
            // A change between stick and slip carries the friction force.
            Event::Contact(c)
                if matches!(c.change, ContactChange::Slips | ContactChange::Sticks) =>
            {
                format!(
                    "node {} {} {} (li/l = {:.4}, T = {:+.4e}) at iteration {}",
                    c.node,
                    c.change.verb(),
                    model.element_label(c.element),
                    c.xi,
                    c.force,
                    c.iteration
                )
            }
            Event::Contact(c) => format!(
                "node {} {} {} (li/l = {:.4}) at iteration {}",
                c.node,
                c.change.verb(),
                model.element_label(c.element),
                c.xi,
                c.iteration
            ),
            Event::Obstacle(o)
                if matches!(o.change, ContactChange::Slips | ContactChange::Sticks) =>
            {
                format!(
                    "node {} {} obstacle {} (T = {:+.4e}) at iteration {}",
                    o.node,
                    o.change.verb(),
                    o.obstacle,
                    o.force,
                    o.iteration
                )
            }
            Event::Obstacle(o) => format!(
                "node {} {} obstacle {} at iteration {}",
                o.node,
                o.change.verb(),
                o.obstacle,
                o.iteration
            ),
        }
    }
}

/// A node touching or leaving a rigid obstacle, and when.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ObstacleEvent {
    /// What happened: `Activated`, `Released`, `Slips` or `Sticks`.
    pub change: ContactChange,
    /// Increment number.
    pub increment: usize,
    /// Iteration within the increment.
    pub iteration: usize,
    /// User id of the node.
    pub node: u32,
    /// Name of the obstacle.
    pub obstacle: String,
    /// The normal force at the pass where the contact was let go (N; negative: it pulled, by
    /// as much as the penalty makes of the gap opening there, which says that it let go, not
    /// what it carried), 0 at an activation; the friction force along the obstacle where it
    /// began to slip or stuck again.
    pub force: f64,
}

/// A node resting on a rigid obstacle at a converged state.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ObstacleState {
    /// User id of the node.
    pub node: u32,
    /// Name of the obstacle.
    pub obstacle: String,
    /// The normal force pushing the node off the obstacle (N, positive in compression).
    pub force: f64,
    /// The gap (m): positive clear of the obstacle, negative inside it (within
    /// `SolverParams::obstacle_gap` of the model's size at an accepted state).
    pub gap: f64,
    /// The point of the obstacle it touches, in the scene's coordinates (m): where the node's
    /// face touches, and where the contact's force acts.
    pub point: [f64; 2],
    /// The unit normal there, pointing to the free side.
    pub normal: [f64; 2],
    /// The friction force on the node along the obstacle's tangent (`normal[1]`, `-normal[0]`)
    /// (N); 0 where the obstacle is frictionless.
    #[serde(default)]
    pub tangential: f64,
    /// Whether the node sticks or slips.
    #[serde(default)]
    pub friction: Friction,
    /// The stick point: a place along the obstacle (`Shape::place`, m), moving with a rim
    /// that rolls; `None` where frictionless.
    #[serde(default)]
    pub stick: Option<f64>,
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
    /// The friction force on the contact node along the element's chord, from its end i to
    /// its end j (N); 0 where the contact is frictionless.
    #[serde(default)]
    pub tangential: f64,
    /// The angle (rad, counter-clockwise) from the chord's normal to the beam's surface normal
    /// at the contact point, along which the frictionless force acts (`SolverParams::
    /// surface_normal`): the node takes Yc tan(turn) along the chord besides -Yc along the
    /// normal. 0 with the chord normal, and where a history does not name it.
    #[serde(default)]
    pub turn: f64,
    /// Whether the contact sticks or slips.
    #[serde(default)]
    pub friction: Friction,
    /// The stick point: the length along the body (undeformed, from its first node) of the
    /// material point the node is held to (m); `None` where the contact is frictionless.
    #[serde(default)]
    pub stick: Option<f64>,
    /// Where the contact presses on the beam's axis, for a node that stands off it (a radius,
    /// a thickness: the force acts on the beam there); `None`: at the node itself.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub point: Option<[f64; 2]>,
}

/// The frictional state of a contact.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub enum Friction {
    /// No friction between the node and the body.
    #[default]
    Frictionless,
    /// The node is held to its stick point: its friction force is below mu times the pressure.
    Sticking,
    /// The node slides along the body with a friction force of mu times the pressure,
    /// against the slip.
    Slipping,
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
    /// Load factor after this increment: the first load group's where the model has several
    /// (`load_factors`).
    pub load_factor: f64,
    /// Every load group's factor after this increment, in the order of the model's load
    /// groups; empty where the model has one load factor.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub load_factors: Vec<f64>,
    /// The stage of the load path this increment belongs to (index into the path's stages);
    /// none where the scene has no stages, or for an increment a drag made off the path.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub stage: Option<usize>,
    /// Whether this increment is part of a step that was cut back and goes on toward its
    /// target (not the step's last increment).
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub partial: bool,
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
    /// Nodes resting on rigid obstacles.
    #[serde(default)]
    pub obstacle_contacts: Vec<ObstacleState>,
    /// Largest penetration of an inactive candidate node through a body's deformed shape, in
    /// element lengths, measured against the sides at the previous converged state (0 if none).
    pub max_penetration: f64,
    /// Contact events of this increment.
    pub events: Vec<Event>,
    /// Wall time of this increment, cut-back attempts included (s).
    pub seconds: f64,
}

impl IncrementRecord {
    /// The sum of the reactions at dof `dof` ("u", "v" or "phi") of the nodes with ids `ids`:
    /// with [`Model::moving_with`], the force a driven node carries, its obstacle's included
    /// (N, or N m).
    pub fn held_force(&self, ids: &[u32], dof: &str) -> f64 {
        (self.reactions.iter())
            .filter(|r| r.dof == dof && ids.contains(&r.node))
            .map(|r| r.value)
            .sum()
    }
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
