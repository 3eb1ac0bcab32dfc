//! Why a Newton attempt failed, as a type: each failure the increment control can answer
//! (a smaller increment, a slide-off, a located error) is told apart by its variant.

use crate::solver::acceptance::{
    Crossing, FeatureCrossing, FrictionViolation, ObstacleCrossing, OutOfRange, MAX_SPIN_STEP,
    MAX_STRAIN_STEP, MAX_TURN_STEP,
};
use crate::solver::contact::ContactSet;
use crate::solver::model::Model;
use crate::solver::report::{ContactChange, Event};

/// Why an attempt failed.
#[derive(Clone, Debug, PartialEq)]
pub enum AttemptError {
    /// The residual grew past `SolverParams::divergence`.
    Diverged {
        /// Iteration (of the attempt).
        iteration: usize,
        /// Relative residual there.
        residual: f64,
    },
    /// A pass used up `SolverParams::max_iterations`.
    NoConvergence {
        /// The iteration limit.
        iterations: usize,
        /// Relative residual reached.
        residual: f64,
        /// Round-off floor estimate there.
        floor: f64,
    },
    /// The residual is not finite.
    NonFinite {
        /// Iteration (of the attempt).
        iteration: usize,
    },
    /// A pivot of the tangent vanished.
    Singular {
        /// The dof of that pivot ("node N u").
        dof: String,
    },
    /// Too many contact state changes in one increment.
    Chattering {
        /// Changes counted.
        changes: usize,
        /// The contact that changed most often, where one did.
        most: Option<Chatter>,
    },
    /// A node was found deeper through a body than `SolverParams::max_penetration` before its
    /// contact was detected.
    TooDeep {
        /// Node index.
        node: usize,
        /// Body index.
        body: usize,
        /// Depth, in element lengths.
        depth: f64,
    },
    /// A node was found deeper inside a rigid obstacle than `SolverParams::max_penetration`
    /// lengths of its elements before its contact was made.
    ObstacleTooDeep {
        /// Node index.
        node: usize,
        /// Obstacle index.
        obstacle: usize,
        /// Depth (m).
        depth: f64,
    },
    /// The multipliers of the obstacle contacts were updated in too many passes without
    /// closing every gap to the tolerance.
    GapsOpen {
        /// Passes that updated them.
        updates: usize,
        /// Node index of the widest gap at the last pass.
        node: usize,
        /// Its obstacle's index.
        obstacle: usize,
        /// The gap (m; negative: inside).
        gap: f64,
    },
    /// The acceptance check found a node inside a rigid obstacle.
    InsideObstacle(ObstacleCrossing),
    /// The acceptance check found an obstacle's feature through an element between its nodes.
    FeatureThrough(FeatureCrossing),
    /// The acceptance check found a contact breaking the friction law.
    FrictionLaw(FrictionViolation),
    /// Arc length: the reference load does no work on the free dofs.
    NoLoadPath,
    /// Arc length: the constraint has no real root.
    NoArcRoot {
        /// Iteration (of the attempt).
        iteration: usize,
    },
    /// Newton stalled at the round-off floor above `SolverParams::roundoff_bound`.
    AtFloor {
        /// Relative residual reached.
        residual: f64,
        /// Round-off floor estimate there.
        floor: f64,
    },
    /// The acceptance check found a node through a body it is not in contact with.
    Crossed(Crossing),
    /// The acceptance check found a node that stands off the axes (a radius, a thickness)
    /// within its contact distance of an element it is not in contact with (depth in
    /// element lengths).
    Overlap(Crossing),
    /// The acceptance check found an element outside the range of its theory.
    OutOfRange(OutOfRange),
    /// The acceptance check found a node turned by a half turn or more within the increment:
    /// (node index, its turn in rad).
    Spun(usize, f64),
    /// The observer asked to stop.
    Stopped,
}

impl AttemptError {
    /// Whether the attempt found no acceptable state near the last one for want of an
    /// equilibrium there (Newton diverged, stalled, cycled through contact sets, or reached a
    /// state far from the path: turned, strained, or with a node deep through a body or an
    /// obstacle however short the step), rather than a state refused for what it is (a
    /// crossing, a feature through a body, a node inside an obstacle, the friction law, gaps
    /// held open): where no step finds one, the structure snaps (`control/snap.rs`).
    pub fn finds_no_state(&self) -> bool {
        matches!(
            self,
            AttemptError::Diverged { .. }
                | AttemptError::NoConvergence { .. }
                | AttemptError::NonFinite { .. }
                | AttemptError::Singular { .. }
                | AttemptError::Chattering { .. }
                | AttemptError::AtFloor { .. }
                | AttemptError::OutOfRange(_)
                | AttemptError::Spun(..)
                | AttemptError::TooDeep { .. }
                | AttemptError::ObstacleTooDeep { .. }
        )
    }

    /// The failure in words, with nodes and bodies named from `model`; `bound` is
    /// `SolverParams::roundoff_bound`.
    pub fn describe(&self, model: &Model, bound: f64) -> String {
        match self {
            AttemptError::Diverged {
                iteration,
                residual,
            } => format!("diverged at iteration {iteration}: relative residual {residual:.3e}"),
            AttemptError::NoConvergence {
                iterations,
                residual,
                floor,
            } => format!(
                "no convergence in {iterations} iterations: relative residual {residual:.3e} (round-off floor {floor:.1e})"
            ),
            AttemptError::NonFinite { iteration } => {
                format!("non-finite residual at iteration {iteration}")
            }
            AttemptError::Singular { dof } => format!("singular tangent at {dof}"),
            AttemptError::Chattering { changes, most } => {
                let text = format!("{changes} contact state changes in one increment (chattering)");
                match most {
                    Some(c) => format!("{text}, {c}"),
                    None => text,
                }
            }
            AttemptError::TooDeep { node, body, depth } => format!(
                "{} went {depth:.2} element lengths through {} before contact was detected",
                model.node_label(*node),
                model.bodies[*body].name
            ),
            AttemptError::ObstacleTooDeep {
                node,
                obstacle,
                depth,
            } => format!(
                "{} went {depth:.2e} m into obstacle {} before contact was made",
                model.node_label(*node),
                model.obstacles[*obstacle].name
            ),
            AttemptError::GapsOpen {
                updates,
                node,
                obstacle,
                gap,
            } => format!(
                "{} stays {:.2e} m {} obstacle {} after {updates} updates of the multipliers (a support or a prescribed displacement may hold it there)",
                model.node_label(*node),
                gap.abs(),
                if *gap < 0.0 { "inside" } else { "clear of, yet pressing on," },
                model.obstacles[*obstacle].name
            ),
            AttemptError::InsideObstacle(x) => format!(
                "{} ends inside obstacle {}, or passed through it, {:.2e} m deep",
                model.node_label(x.node),
                model.obstacles[x.obstacle].name,
                x.depth
            ),
            AttemptError::FeatureThrough(x) => format!(
                "obstacle {} passed through {} between its nodes, {:.2e} m",
                model.obstacles[x.obstacle].name,
                model.element_label(x.element),
                x.depth
            ),
            AttemptError::FrictionLaw(x) => format!(
                "{} on {} breaks the friction law: friction force {:.6} times mu N, stick point moved {:.2e} m",
                model.node_label(x.node),
                x.surface(model),
                x.ratio,
                x.slipped
            ),
            AttemptError::NoLoadPath => {
                "arc length: the reference load does no work on the free dofs".into()
            }
            AttemptError::NoArcRoot { iteration } => {
                format!("arc length: no real root at iteration {iteration}")
            }
            AttemptError::AtFloor { residual, floor } => format!(
                "Newton stalls at relative residual {residual:.3e} (round-off floor {floor:.1e}), above the bound {bound:.0e}"
            ),
            AttemptError::Overlap(x) => format!(
                "{} ends within its contact distance ({:.3e} m) of {} without touching it ({:.2e} element lengths)",
                model.node_label(x.node),
                model.contact_distance(x.node, x.element),
                model.element_label(x.element),
                x.depth
            ),
            AttemptError::Crossed(x) => format!(
                "{} passes through {} ({:.2e} element lengths beyond it)",
                model.node_label(x.node),
                model.element_label(x.element),
                x.depth
            ),
            AttemptError::OutOfRange(x) => format!(
                "{} turns by {:.2} rad against its chord and changes its strain by {:.1e} in one increment (limits {MAX_TURN_STEP} rad, {MAX_STRAIN_STEP}): a state far from the path",
                model.element_label(x.element),
                x.turn,
                x.strain
            ),
            AttemptError::Spun(node, turn) => format!(
                "{} turns by {turn:.2} rad in one increment (limit {:.2} rad, a half turn): a state far from the path",
                model.node_label(*node),
                MAX_SPIN_STEP
            ),
            AttemptError::Stopped => "stopped by the caller".into(),
        }
    }
}

/// The contact that changes state most often in a chattering attempt: where the contact
/// passes cycle.
#[derive(Clone, Debug, PartialEq)]
pub struct Chatter {
    /// User id of its node.
    pub node: u32,
    /// The surface: "cantilever element 30" or "obstacle floor".
    pub surface: String,
    /// Its changes in the attempt.
    pub changes: usize,
    /// The kinds of change it went through, in the order first seen.
    pub kinds: Vec<ContactChange>,
}

impl Chatter {
    /// The contact of `events` (an attempt's) with the most changes; ties go to the one seen
    /// first. Element indices are named from `model`.
    pub fn most_changed(events: &[Event], model: &Model) -> Option<Chatter> {
        let mut all: Vec<Chatter> = Vec::new();
        for e in events {
            let (node, surface, kind) = match e {
                Event::Contact(c) => (c.node, model.element_label(c.element), c.change),
                Event::Obstacle(o) => (o.node, format!("obstacle {}", o.obstacle), o.change),
                _ => continue,
            };
            match all
                .iter_mut()
                .find(|c| c.node == node && c.surface == surface)
            {
                Some(c) => {
                    c.changes += 1;
                    if !c.kinds.contains(&kind) {
                        c.kinds.push(kind);
                    }
                }
                None => all.push(Chatter {
                    node,
                    surface,
                    changes: 1,
                    kinds: vec![kind],
                }),
            }
        }
        let most = all.iter().map(|c| c.changes).max()?;
        all.into_iter().find(|c| c.changes == most)
    }
}

impl std::fmt::Display for Chatter {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let kinds: Vec<&str> = self.kinds.iter().map(|k| k.verb()).collect();
        write!(
            f,
            "{} of them by node {} on {} ({})",
            self.changes,
            self.node,
            self.surface,
            kinds.join(", ")
        )
    }
}

/// The converged outcome of one attempt, before it is committed.
pub struct Converged {
    /// Displacements.
    pub d: Vec<f64>,
    /// Their rounding residues (`State::residue`).
    pub residue: Vec<f64>,
    /// Load factors, one per load group (the target's, or the one arc length found).
    pub load_factors: Vec<f64>,
    /// Contact state.
    pub contacts: ContactSet,
    /// Final assembly at the converged state.
    pub assembled: crate::solver::assembly::Assembled,
    /// Total iterations.
    pub iterations: usize,
    /// Iterations to an 8-order drop of the unbalanced force.
    pub iterations_8_orders: Option<usize>,
    /// Relative residual at convergence.
    pub relative_residual: f64,
    /// Reference force.
    pub reference: f64,
    /// Round-off floor estimate of the relative residual.
    pub roundoff_floor: f64,
    /// A snap's pseudo-time step: the relative residual of the state's equilibrium, the
    /// viscous force left out (`None`: an attempt without one, in equilibrium).
    pub equilibrium_residual: Option<f64>,
    /// Iteration records.
    pub residuals: Vec<crate::solver::report::IterationRecord>,
    /// Contact events.
    pub events: Vec<crate::solver::report::Event>,
    /// Largest penetration through a body, in element lengths (see `IncrementRecord`).
    pub max_penetration: f64,
}
