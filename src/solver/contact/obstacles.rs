//! Contacts of nodes with rigid obstacles at a converged pass (`ContactSet::obstacle_pass`):
//! a candidate node found inside an obstacle by more than `Structure::obstacle_tolerance`
//! becomes a contact (within it, the node is as good as touching, and its force would be
//! round-off: no contact is made that the next pass would let go); a contact whose normal force
//! turns tensile, or whose node leaves the obstacle's reach, lets go; and the multiplier of a
//! contact whose gap is still open either way by more than `Structure::obstacle_tolerance`
//! takes the force it carries (the augmented Lagrangian update), so that the next pass closes
//! the gap further. The gap at an accepted state is within the tolerance: exact geometry, no
//! penetration beyond it.

use super::set::{ContactSet, ContactView};
use crate::solver::assembly::{obstacle_gap, Assembled, ObstacleLink};
use crate::solver::report::{ContactChange, Event, ObstacleEvent, ObstacleState};

/// What a converged pass did to the obstacle contacts.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ObstaclePass {
    /// Contacts made or let go (active-set changes).
    pub changes: usize,
    /// Multipliers updated (the same active set, another pass to close its gaps).
    pub updated: usize,
}

impl ContactSet {
    /// At a converged pass at displacements `d` with assembly `asm` (made with these obstacle
    /// contacts): releases, activations and multiplier updates, with their events.
    pub fn obstacle_pass(
        &mut self,
        cv: &ContactView<'_>,
        d: &[f64],
        asm: &Assembled,
        increment: usize,
        iteration: usize,
        events: &mut Vec<Event>,
    ) -> ObstaclePass {
        let mut pass = ObstaclePass::default();
        if cv.obstacle_candidates.is_empty() {
            return pass;
        }
        let m = &cv.model;
        let tol = cv.obstacle_tolerance();
        let event = |link: &ObstacleLink, change, force| {
            Event::Obstacle(ObstacleEvent {
                change,
                increment,
                iteration,
                node: m.nodes[link.node].id,
                obstacle: m.obstacles[link.obstacle].name.clone(),
                force,
            })
        };
        let forces = &asm.elements.obstacle_forces;
        let mut kept = Vec::with_capacity(self.obstacle.len());
        for (k, link) in self.obstacle.iter().enumerate() {
            let f = forces[k];
            match obstacle_gap(m, &cv.dofs, d, link.node, link.obstacle) {
                Some(gap) if f >= 0.0 => {
                    let mut link = *link;
                    if gap.g.abs() > tol {
                        link.multiplier = f;
                        pass.updated += 1;
                    }
                    kept.push(link);
                }
                _ => {
                    events.push(event(link, ContactChange::Released, f));
                    pass.changes += 1;
                }
            }
        }
        self.obstacle = kept;
        for &(n, o) in &cv.obstacle_candidates {
            if self.obstacle.iter().any(|l| l.node == n && l.obstacle == o) {
                continue;
            }
            let Some(gap) = obstacle_gap(m, &cv.dofs, d, n, o) else {
                continue;
            };
            if gap.g < -tol {
                let link = ObstacleLink {
                    node: n,
                    obstacle: o,
                    multiplier: 0.0,
                };
                events.push(event(&link, ContactChange::Activated, 0.0));
                self.obstacle.push(link);
                pass.changes += 1;
                let reach = cv.params.max_penetration * node_length(cv, n);
                if -gap.g > reach && self.obstacle_too_deep.is_none() {
                    self.obstacle_too_deep = Some((n, o, -gap.g));
                }
            }
        }
        self.multiplier_updates += pass.updated;
        pass
    }

    /// Report states of the obstacle contacts from a converged assembly at displacements `d`.
    pub fn obstacle_states(
        &self,
        cv: &ContactView<'_>,
        d: &[f64],
        asm: &Assembled,
    ) -> Vec<ObstacleState> {
        let m = &cv.model;
        let o = cv.origin;
        (self.obstacle.iter().zip(&asm.elements.obstacle_forces))
            .filter_map(|(link, &force)| {
                let gap = obstacle_gap(m, &cv.dofs, d, link.node, link.obstacle)?;
                Some(ObstacleState {
                    node: m.nodes[link.node].id,
                    obstacle: m.obstacles[link.obstacle].name.clone(),
                    force,
                    gap: gap.g,
                    point: [gap.point[0] + o[0], gap.point[1] + o[1]],
                    normal: gap.n,
                })
            })
            .collect()
    }
}

/// The length a node's penetration is measured in: the mean length of its elements (the
/// model's size for a node with none).
fn node_length(cv: &ContactView<'_>, n: usize) -> f64 {
    let beams = &cv.node_beams[n];
    if beams.is_empty() {
        return cv.size;
    }
    beams.iter().map(|&e| cv.model.beam_length(e)).sum::<f64>() / beams.len() as f64
}
