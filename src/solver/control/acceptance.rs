//! The solver's side of the acceptance check: a converged attempt is checked before it is
//! committed (equilibrium status, then the geometric tests and the friction law, read from the
//! forces and stick points the attempt left), and a refused or failed attempt
//! becomes a cut-back reason or, once the cut-backs are spent, a typed `SolveError`.

use super::solver::Solver;
use crate::solver::acceptance::{
    feature_through, friction_law, inside_obstacle, out_of_range, rim_overlap, spun,
    FrictionRecord, MAX_STRAIN_STEP, MAX_TURN_STEP,
};
use crate::solver::newton::{AttemptError, Converged};
use crate::solver::report::{ContactChange, Event, IncrementStatus, NodeState, SolveError};

impl Solver {
    /// The acceptance check (`acceptance`) of a converged attempt, before it is committed: its
    /// equilibrium status from the residual of its final assembly, no element turned or
    /// strained beyond the step range, no node inside an obstacle, every frictional contact
    /// within the friction law, and no node through a body it is not in contact with. Returns
    /// the status and the node states.
    pub(crate) fn acceptance(
        &self,
        c: &Converged,
    ) -> Result<(IncrementStatus, Vec<NodeState>), AttemptError> {
        let p = &self.structure.params;
        let status = match c.equilibrium_residual {
            // A snap's step: in equilibrium or not, by its residual without the viscous force.
            Some(residual) if residual <= p.tolerance => IncrementStatus::Converged,
            // A step Newton took to the round-off floor (above the tolerance) is in equilibrium
            // at that floor where the viscous force adds no more than round-off: its residual
            // without it within twice the residual it was taken to.
            Some(residual)
                if c.relative_residual > p.tolerance && residual <= 2.0 * c.relative_residual =>
            {
                IncrementStatus::of(residual, p.tolerance, p.roundoff_bound)
                    .unwrap_or(IncrementStatus::Snapping { residual })
            }
            Some(residual) => IncrementStatus::Snapping { residual },
            None => {
                let rel =
                    (c.assembled.unbalanced_norm2.sqrt() / c.reference).max(c.relative_residual);
                IncrementStatus::of(rel, p.tolerance, p.roundoff_bound).ok_or(
                    AttemptError::AtFloor {
                        residual: rel,
                        floor: c.roundoff_floor,
                    },
                )?
            }
        };
        let states = self.structure.node_states(&c.d);
        let before = self.structure.node_states(&self.state.d);
        if let Some(x) = out_of_range(
            &self.structure.model,
            &self.structure.elements,
            &before,
            &states,
        ) {
            return Err(AttemptError::OutOfRange(x));
        }
        if let Some((node, turn)) = spun(&self.structure.model, &before, &states) {
            return Err(AttemptError::Spun(node, turn));
        }
        let tol = self.structure.obstacle_tolerance();
        if let Some(x) = inside_obstacle(
            &self.structure.model,
            self.structure.origin,
            (&before, &states),
            tol,
        ) {
            return Err(AttemptError::InsideObstacle(x));
        }
        if let Some(x) = feature_through(
            &self.structure.model,
            self.structure.origin,
            (&before, &states),
        ) {
            return Err(AttemptError::FeatureThrough(x));
        }
        if let Some(x) = friction_law(&self.friction_records(c)) {
            return Err(AttemptError::FrictionLaw(x));
        }
        let active = c.contacts.pairs();
        if let Some(x) = self.crossing.find(&self.structure.model, &states, &active) {
            return Err(AttemptError::Crossed(x));
        }
        let window = |n, b| self.structure.self_window_of(n, b);
        let touching: Vec<(usize, usize, usize)> = (c.contacts.beams.active.iter())
            .map(|a| (a.node, a.body, a.beam))
            .collect();
        let overlap = (self.structure.stands_off)
            .then(|| {
                rim_overlap(
                    &self.structure.model,
                    &self.structure.candidates,
                    window,
                    &states,
                    &touching,
                )
            })
            .flatten();
        match overlap {
            Some(x) => Err(AttemptError::Overlap(x)),
            None => Ok((status, states)),
        }
    }

    /// The frictional contacts of a converged attempt as the friction law's check reads them:
    /// pressure, friction force along the body, and the stick points before and after (none
    /// before for a contact that began in the increment); after, with the rim's roll of the
    /// increment put back: a rim that rolls without slipping moves its stick point with it.
    fn friction_records(&self, c: &Converged) -> Vec<FrictionRecord> {
        let tractions = &c.assembled.elements.contact_friction;
        let began = |node: usize, body: usize| {
            c.events.iter().any(|e| {
                matches!(e, Event::Contact(x) if x.change == ContactChange::Activated
                    && x.node == self.structure.model.nodes[node].id
                    && x.body == self.structure.model.bodies[body].name)
            })
        };
        (c.contacts.beams.active.iter().enumerate())
            .filter_map(|(k, a)| {
                let stick = a.stick?;
                let t = tractions.get(k).copied().flatten()?;
                let [si, sj] = self.structure.body_length_at[a.beam];
                let before = (self.state.contacts.beams.active.iter())
                    .find(|b| b.node == a.node && b.body == a.body && !began(a.node, a.body))
                    .and_then(|b| b.stick);
                Some(FrictionRecord {
                    node: a.node,
                    body: a.body,
                    obstacle: false,
                    mu: *self.structure.friction.get(&(a.node, a.body))?,
                    pressure: t.normal,
                    tangential: t.tangential * (sj - si).signum(),
                    stick_before: before.map(|b| b.at),
                    stick_after: stick.at + t.rolled,
                    period: 0.0,
                    scale: t.rolled.abs(),
                })
            })
            .chain(self.obstacle_friction_records(c))
            .collect()
    }

    /// `friction_records` of the nodes resting on obstacles: the friction force along the
    /// obstacle's tangent (its places grow that way).
    fn obstacle_friction_records(&self, c: &Converged) -> Vec<FrictionRecord> {
        let tractions = &c.assembled.elements.obstacle_friction;
        let before = &self.state.contacts.obstacles.links;
        (c.contacts.obstacles.links.iter().enumerate())
            .filter_map(|(k, link)| {
                let grip = link.grip.filter(|_| link.active)?;
                let t = tractions.get(k).copied().flatten()?;
                let anew = c.contacts.obstacles.touched.contains(&k);
                let was = before.get(k).and_then(|b| b.grip).filter(|_| !anew);
                Some(FrictionRecord {
                    node: link.node,
                    body: link.obstacle,
                    obstacle: true,
                    mu: grip.mu,
                    pressure: t.normal,
                    tangential: t.tangential,
                    stick_before: was.map(|b| b.stick),
                    stick_after: grip.stick + t.rolled,
                    period: grip.period.unwrap_or(0.0),
                    scale: t.rolled.abs(),
                })
            })
            .collect()
    }

    /// The text of a failed attempt, for cut-back events.
    pub(crate) fn failure_reason(&self, e: &AttemptError) -> String {
        e.describe(&self.structure.model, self.structure.params.roundoff_bound)
    }

    /// The error of increment `increment` when its last attempt failed with `e` after
    /// `cutbacks` cut-backs.
    pub(crate) fn give_up(&self, increment: usize, cutbacks: usize, e: AttemptError) -> SolveError {
        match e {
            AttemptError::Stopped => SolveError::Stopped,
            AttemptError::AtFloor { residual, floor } => SolveError::RoundOffFloor {
                increment,
                cutbacks,
                residual,
                floor,
                bound: self.structure.params.roundoff_bound,
            },
            AttemptError::Crossed(x) | AttemptError::Overlap(x) => SolveError::Crossing {
                increment,
                cutbacks,
                node: self.structure.model.nodes[x.node].id,
                body: self.structure.model.bodies[x.body].name.clone(),
                element: self.structure.model.element_place(x.element),
                depth: x.depth,
            },
            AttemptError::InsideObstacle(x) => SolveError::ObstacleCrossing {
                increment,
                cutbacks,
                node: self.structure.model.nodes[x.node].id,
                obstacle: self.structure.model.obstacles[x.obstacle].name.clone(),
                depth: x.depth,
            },
            AttemptError::FeatureThrough(x) => {
                let body = self.structure.model.beams[x.element].body;
                SolveError::ObstacleThrough {
                    increment,
                    cutbacks,
                    obstacle: self.structure.model.obstacles[x.obstacle].name.clone(),
                    body: self.structure.model.bodies[body].name.clone(),
                    element: self.structure.model.element_place(x.element),
                    depth: x.depth,
                }
            }
            AttemptError::FrictionLaw(x) => SolveError::FrictionLaw {
                increment,
                cutbacks,
                node: self.structure.model.nodes[x.node].id,
                body: x.surface(&self.structure.model),
                ratio: x.ratio,
                slipped: x.slipped,
            },
            AttemptError::OutOfRange(x) => {
                let body = self.structure.model.beams[x.element].body;
                SolveError::OutOfRange {
                    increment,
                    cutbacks,
                    body: self.structure.model.bodies[body].name.clone(),
                    element: self.structure.model.element_place(x.element),
                    turn: x.turn,
                    strain: x.strain,
                    max_turn: MAX_TURN_STEP,
                    max_strain: MAX_STRAIN_STEP,
                }
            }
            other => SolveError::NoConvergence {
                increment,
                cutbacks,
                reason: self.failure_reason(&other),
            },
        }
    }
}
