//! Contacts of nodes with rigid obstacles. Every candidate (node, obstacle) pair carries a
//! multiplier and whether it is in contact in the current pass ([`ContactSet::obstacle`]). Within
//! a Newton pass the contacts are fixed; at a converged pass ([`ContactSet::obstacle_pass`])
//! contacts whose force `multiplier - penalty g` turned tensile let go and nodes found inside
//! an obstacle by more than [`Structure::obstacle_tolerance`] touch it; once the contacts hold,
//! the multiplier of every contact whose gap is still open either way by more than the
//! tolerance takes the force it carries (the augmented Lagrangian update), and the next pass
//! closes the gap further. On frictionless obstacles the changes are first predicted for the
//! whole set from the linearised problem (`prediction.rs`), with the forces the contacts will
//! carry. Should a set of contacts come back within an attempt, each pass
//! makes one change, the least (node, obstacle) pair first, which cannot cycle. At the
//! accepted pass ([`ContactSet::obstacle_settle`]) the contacts are compared with the last
//! accepted ones: the nodes that touched and let go are the events, not the passes between.

mod prediction;

use super::set::{ContactSet, ContactView};
use crate::solver::assembly::{Assembled, ObstacleLink, Ordering};
use crate::solver::linear::BandMatrix;
use crate::solver::report::{ContactChange, Event, Friction, ObstacleEvent, ObstacleState};

impl ContactSet {
    /// The candidate pairs of the structure at rest, each with its multiplier, and whether it
    /// rests on its obstacle: a node within the obstacle tolerance of it (a strip lying on a
    /// table) starts in contact, its multiplier taking up a gap of round-off so that it presses
    /// from the start.
    pub(crate) fn obstacles_at_rest(&mut self, cv: &ContactView<'_>) {
        let (k, tol) = (
            cv.structure.obstacle_penalty,
            cv.structure.obstacle_tolerance(),
        );
        self.obstacles.links.clear();
        self.obstacles.resting.clear();
        for &(node, obstacle) in &cv.structure.obstacle_candidates {
            let gap = cv.obstacle_gap(cv.d, node, obstacle);
            let resting = gap.is_some_and(|g| g.g.abs() <= tol);
            let multiplier = gap.filter(|_| resting).map_or(0.0, |g| k * g.g.max(0.0));
            let grip = resting
                .then(|| Self::obstacle_grip_at(cv, cv.d, node, obstacle))
                .flatten();
            self.obstacles.links.push(ObstacleLink {
                node,
                obstacle,
                multiplier,
                active: resting,
                grip,
            });
            self.obstacles.resting.push(resting);
        }
    }

    /// The nodes resting on obstacles at the last accepted state and the directions their
    /// obstacles hold them in there (what holds a body up before it is loaded): the unit
    /// normal, and the tangent too where the obstacle has friction (the node sticks).
    pub(crate) fn resting_normals(&self, cv: &ContactView<'_>) -> Vec<(usize, [f64; 2])> {
        (self.obstacles.links.iter().zip(&self.obstacles.resting))
            .filter(|(_, &r)| r)
            .filter_map(|(l, _)| {
                let gap = cv.obstacle_gap(cv.d, l.node, l.obstacle)?;
                let n = gap.n;
                let tangent = l.grip.map(|_| (l.node, [n[1], -n[0]]));
                Some(std::iter::once((l.node, n)).chain(tangent))
            })
            .flatten()
            .collect()
    }

    /// Whether `node` is the end of a body that an obstacle touching elements (its pilot in
    /// contact with the body) slid off in this attempt: the body's end springs onto the
    /// obstacle there, and its node touches it at once, however deep it is found.
    fn handed_over(&self, cv: &ContactView<'_>, node: usize, obstacle: usize) -> bool {
        let m = &cv.structure.model;
        let Some(pilot) = m.obstacles[obstacle]
            .pilot
            .filter(|_| m.obstacles[obstacle].touches_elements)
        else {
            return false;
        };
        (cv.structure.node_beams[node].iter())
            .any(|&e| self.beams.slid_off.contains(&(pilot, m.beams[e].body)))
    }

    /// At a converged pass at displacements `d` with assembly `asm` (made with these
    /// contacts): releases and activations, else the augmented Lagrangian update. Returns the
    /// contacts made or let go, and the multipliers moved (both 0: every gap is closed). A node
    /// that did not rest on its obstacle at the last accepted state and is found deeper inside
    /// it than `max_penetration` lengths of its elements makes the attempt fail
    /// (`obstacle_too_deep`): the increment is cut back so that the touch is caught where it
    /// happens.
    pub fn obstacle_pass(
        &mut self,
        cv: &ContactView<'_>,
        d: &[f64],
        asm: &Assembled,
        tangent: Option<(&BandMatrix, &Ordering)>,
    ) -> (usize, usize) {
        if let Some(changed) = tangent.and_then(|t| self.predicted_changes(cv, d, asm, t)) {
            return (changed, 0);
        }
        let changed = self.obstacle_changes(cv, d, asm, false);
        if changed > 0 {
            return (changed, 0);
        }
        let tol = cv.structure.obstacle_tolerance();
        let forces = &asm.elements.obstacle_forces;
        let mut updated = 0;
        self.obstacles.widest_gap = None;
        for (k, link) in self.obstacles.links.iter_mut().enumerate() {
            if !link.active {
                continue;
            }
            let Some(gap) = cv.obstacle_gap(d, link.node, link.obstacle) else {
                continue;
            };
            if gap.g.abs() > tol {
                link.multiplier = forces[k];
                updated += 1;
                if self
                    .obstacles
                    .widest_gap
                    .is_none_or(|w| gap.g.abs() > w.2.abs())
                {
                    self.obstacles.widest_gap = Some((link.node, link.obstacle, gap.g));
                }
            }
        }
        self.obstacles.multiplier_updates += usize::from(updated > 0);
        (0, updated)
    }

    /// The releases and activations of `obstacle_pass` at displacements `d` with assembly
    /// `asm`: contacts whose force turned tensile let go, nodes inside by more than the
    /// tolerance touch (all at once, or the least pair alone once a set came back). Returns how
    /// many changed. `releases_only`: only the contacts that turned tensile let go (a state on
    /// the way to convergence, where the gaps of free nodes are not judged).
    pub(crate) fn obstacle_changes(
        &mut self,
        cv: &ContactView<'_>,
        d: &[f64],
        asm: &Assembled,
        releases_only: bool,
    ) -> usize {
        let tol = cv.structure.obstacle_tolerance();
        let forces = &asm.elements.obstacle_forces;
        // The violations, in the order of the pairs: (pair, activate).
        let mut violations = Vec::new();
        for (k, link) in self.obstacles.links.iter().enumerate() {
            if link.active {
                if forces[k] < 0.0 {
                    violations.push((k, false));
                }
                continue;
            }
            if releases_only {
                continue;
            }
            let Some(gap) = cv.obstacle_gap(d, link.node, link.obstacle) else {
                continue;
            };
            if gap.g < -tol {
                violations.push((k, true));
                let reach = cv.structure.params.max_penetration * node_length(cv, link.node);
                if !self.obstacles.resting[k]
                    && -gap.g > reach
                    && self.obstacles.too_deep.is_none()
                    && !self.handed_over(cv, link.node, link.obstacle)
                {
                    self.obstacles.too_deep = Some((link.node, link.obstacle, -gap.g));
                }
            }
        }
        if !violations.is_empty() {
            if self.obstacles.guard.one_at_a_time() {
                violations.truncate(1);
            }
            for &(k, activate) in &violations {
                let (node, obstacle) = (
                    self.obstacles.links[k].node,
                    self.obstacles.links[k].obstacle,
                );
                let grip = activate
                    .then(|| Self::obstacle_grip_at(cv, d, node, obstacle))
                    .flatten();
                let link = &mut self.obstacles.links[k];
                link.active = activate;
                link.multiplier = 0.0;
                link.grip = grip;
                if activate {
                    self.obstacles.touched.push(k);
                }
                if !activate {
                    self.obstacles.let_go.insert(k, forces[k]);
                }
            }
            let set: Vec<bool> = self.obstacles.links.iter().map(|l| l.active).collect();
            self.obstacles.guard.reached(set);
        }
        violations.len()
    }

    /// At the accepted pass: which nodes rest on their obstacles now, and the
    /// events of those that touched (`Activated`) or let go (`Released`) since the last accepted
    /// state.
    pub fn obstacle_settle(
        &mut self,
        cv: &ContactView<'_>,
        increment: usize,
        iteration: usize,
        events: &mut Vec<Event>,
    ) {
        let m = &cv.structure.model;
        for (k, link) in self.obstacles.links.iter().enumerate() {
            let now = link.active;
            if now == self.obstacles.resting[k] {
                continue;
            }
            // A release carries the tensile force it was let go with.
            let (change, force) = if now {
                (ContactChange::Activated, 0.0)
            } else {
                let f = self.obstacles.let_go.get(&k).copied().unwrap_or(0.0);
                (ContactChange::Released, f.max(-f64::MAX))
            };
            events.push(Event::Obstacle(ObstacleEvent {
                change,
                increment,
                iteration,
                node: m.nodes[link.node].id,
                obstacle: m.obstacles[link.obstacle].name.clone(),
                force,
            }));
            self.obstacles.resting[k] = now;
        }
        self.obstacles.let_go.clear();
    }

    /// Report states of the pairs that press, from a converged assembly at displacements `d`.
    pub fn obstacle_states(
        &self,
        cv: &ContactView<'_>,
        d: &[f64],
        asm: &Assembled,
    ) -> Vec<ObstacleState> {
        let m = &cv.structure.model;
        let o = cv.structure.origin;
        let friction = |k: usize| asm.elements.obstacle_friction.get(k).copied().flatten();
        (self
            .obstacles
            .links
            .iter()
            .zip(&asm.elements.obstacle_forces))
        .enumerate()
        .filter(|(_, (link, _))| link.active)
        .filter_map(|(k, (link, &force))| {
            let gap = cv.obstacle_gap(d, link.node, link.obstacle)?;
            Some(ObstacleState {
                node: m.nodes[link.node].id,
                obstacle: m.obstacles[link.obstacle].name.clone(),
                force,
                gap: gap.g,
                point: [gap.point[0] + o[0], gap.point[1] + o[1]],
                normal: gap.n,
                tangential: friction(k).map_or(0.0, |t| t.tangential),
                friction: match link.grip {
                    Some(g) if g.slip.is_some() => Friction::Slipping,
                    Some(_) => Friction::Sticking,
                    None => Friction::Frictionless,
                },
                stick: link.grip.map(|g| g.stick),
            })
        })
        .collect()
    }
}

/// The length a node's penetration is measured in: the mean length of its elements (the
/// model's size for a node with none).
fn node_length(cv: &ContactView<'_>, n: usize) -> f64 {
    let beams = &cv.structure.node_beams[n];
    if beams.is_empty() {
        return cv.structure.size;
    }
    beams
        .iter()
        .map(|&e| cv.structure.model.beam_length(e))
        .sum::<f64>()
        / beams.len() as f64
}
