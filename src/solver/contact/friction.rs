//! The stick points of frictional contacts: where a new contact sticks, the `Grip` each
//! contact element is evaluated with (its stick point from the last accepted state, so that
//! every pass of an increment maps back from there, and the mode the pass tries), the return
//! mapping at a converged pass (each contact whose trial force asks for the other mode
//! changes, and the pass is repeated), and, once an increment is accepted, the stick points the
//! slip moved and the changes between stick and slip as events.
//!
//! A stick point is a length along the body, not a place on an element: a contact that moves
//! onto the neighbouring element keeps it. On an obstacle it is a place along the curve
//! ([`Shape::place`]), kept in the obstacle link with the mode.

use super::set::{contact_reach, ActiveContact, ContactSet, ContactView, Stick};
use crate::solver::assembly::{current, obstacle_offset, Assembled};
use crate::solver::element::friction::{Grip, ObstacleGrip, Traction, STICK_ROUNDOFF_ULPS};
use crate::solver::element::rim::friction::roll;
use crate::solver::report::{ContactChange, Event, ObstacleEvent};

/// The stiffness kt that holds sticking node `node` to beam `beam` (N/m): `friction_penalty`
/// times the smallest axial stiffness EA / L0 of that element and the node's own elements, so
/// that a stiff floor does not make the spring stiffer than what rests on it, and no stiffer
/// than its Coulomb limit resolves (`Stick::resolved`).
fn stick_stiffness(cv: &ContactView<'_>, a: &ActiveContact) -> f64 {
    let full = cv.structure.params.friction_penalty * least_axial(cv, a.node, axial(cv, a.beam));
    a.stick.map_or(full, |s| full.min(s.resolved))
}

/// The stiffness kt that holds a node sticking to an obstacle (N/m): `friction_penalty` times
/// the least axial stiffness of the node's elements (of the obstacle penalty for a node
/// without elements).
fn obstacle_stick_stiffness(cv: &ContactView<'_>, node: usize) -> f64 {
    let stiffness = least_axial(cv, node, f64::INFINITY);
    let stiffness = if stiffness.is_finite() {
        stiffness
    } else {
        cv.structure.obstacle_penalty
    };
    cv.structure.params.friction_penalty * stiffness
}

/// The largest part of its Coulomb limit the round-off of a stick spring's force may be (its
/// stiffness times `STICK_ROUNDOFF_ULPS` units in the last place of the coordinates).
const STICK_RESOLUTION: f64 = 1e-3;

/// The stiffest stick spring whose force's round-off is within `STICK_RESOLUTION` of Coulomb
/// limit `limit` (N) where the coordinates and stick points are of size `scale` (m); infinite
/// where the limit is not positive (nothing presses: the spring keeps its full stiffness). A
/// contact that barely presses (a strip whose weight a drive has nearly taken off) would
/// otherwise have a limit below the round-off of its own spring, and the return mapping would
/// decide stick and slip on round-off.
fn resolvable(limit: f64, scale: f64) -> f64 {
    if limit > 0.0 {
        STICK_RESOLUTION * limit / (STICK_ROUNDOFF_ULPS * f64::EPSILON * scale)
    } else {
        f64::INFINITY
    }
}

/// The axial stiffness EA / L0 of element `e` (N/m).
fn axial(cv: &ContactView<'_>, e: usize) -> f64 {
    cv.structure.elements[e].section.ea / cv.structure.elements[e].length
}

/// The least of `start` and the axial stiffnesses of node `node`'s own elements (N/m).
fn least_axial(cv: &ContactView<'_>, node: usize, start: f64) -> f64 {
    let own = cv.structure.node_beams[node].iter().map(|&e| axial(cv, e));
    own.fold(start, f64::min)
}

/// The rim's roll (`rim::friction::roll`) of node `n` on side `side` of `beam` (body span
/// `span`) at displacements `d`, its stick point at fraction `stick` of `beam`: 0 for a node
/// on the axis.
fn rim_roll(
    cv: &ContactView<'_>,
    d: &[f64],
    (n, side): (usize, f64),
    (beam, span): (usize, f64),
    stick: f64,
) -> f64 {
    let m = &cv.structure.model;
    let r = contact_reach(cv, n, beam);
    if r == 0.0 {
        return 0.0;
    }
    let dofs = &cv.structure.dofs;
    let turn = current(m, dofs, d, n).1;
    let phi = [m.beams[beam].i, m.beams[beam].j].map(|k| current(m, dofs, d, k).1);
    let face = 0.5 * m.beams[beam].section.thickness;
    let turn = m.nodes[n].rotation.then_some(turn);
    roll(phi, (side * r, face, turn), (span, stick))
}

/// The turns of a slip from one direction to the other a contact may take within an attempt;
/// at the next it sticks first.
const MAX_TURNS: usize = 2;

/// A mode as a small integer (0 stick, +1 or -1 slip), for telling a repeated set of modes.
fn mode_code(slip: Option<f64>) -> i8 {
    slip.map_or(0, |s| if s < 0.0 { -1 } else { 1 })
}

impl ContactSet {
    /// The stick point of a new contact of node `n` on side `side` of `beam` (of body `body`)
    /// at fraction `xi` of it, at displacements `d`: there, sticking, with the rim's roll
    /// there for a node that stands off the axis; `None` for a frictionless pair.
    pub(super) fn stick_at(
        cv: &ContactView<'_>,
        d: &[f64],
        (n, side): (usize, f64),
        (body, beam): (usize, usize),
        xi: f64,
    ) -> Option<Stick> {
        if cv.structure.friction.is_empty() || !cv.structure.friction.contains_key(&(n, body)) {
            return None;
        }
        let [si, sj] = cv.structure.body_length_at[beam];
        Some(Stick {
            at: si + xi * (sj - si),
            slip: None,
            resolved: f64::INFINITY,
            roll: rim_roll(cv, d, (n, side), (beam, sj - si), xi),
        })
    }

    /// The grip of a new contact of node `n` with obstacle `o` at displacements `d`: sticking
    /// where it touches; `None` for a frictionless obstacle or a node out of its reach. The
    /// spring is `friction_penalty` times the least axial stiffness of the node's elements (of
    /// the obstacle penalty for a node without elements).
    pub(super) fn obstacle_grip_at(
        cv: &ContactView<'_>,
        d: &[f64],
        n: usize,
        o: usize,
    ) -> Option<ObstacleGrip> {
        let obstacle = &cv.structure.model.obstacles[o];
        if obstacle.mu <= 0.0 {
            return None;
        }
        let gap = cv.obstacle_gap(d, n, o)?;
        let model = &cv.structure.model;
        let t = obstacle_offset(model, &cv.structure.dofs, d, o);
        let reach = model.nodes[n].clearance;
        let phi = if model.nodes[n].rotation {
            d[cv.structure.dofs.dof(n, 2)]
        } else {
            0.0
        };
        Some(ObstacleGrip {
            mu: obstacle.mu,
            stiffness: obstacle_stick_stiffness(cv, n),
            stick: (obstacle.shape).place([gap.point[0] - t[0], gap.point[1] - t[1]]),
            slip: None,
            period: obstacle.shape.period(),
            reach,
            roll: if reach > 0.0 {
                phi - gap.n[1].atan2(gap.n[0])
            } else {
                0.0
            },
        })
    }

    /// The grip of every active contact, in their order, for the assembly: empty where no
    /// contact has friction.
    pub fn grips(&self, cv: &ContactView<'_>) -> Vec<Option<Grip>> {
        if cv.structure.friction.is_empty() || self.beams.active.iter().all(|a| a.stick.is_none()) {
            return Vec::new();
        }
        self.beams
            .active
            .iter()
            .map(|a| Self::grip(cv, a))
            .collect()
    }

    fn grip(cv: &ContactView<'_>, a: &ActiveContact) -> Option<Grip> {
        let stick = a.stick?;
        let mu = *cv.structure.friction.get(&(a.node, a.body))?;
        let [si, sj] = cv.structure.body_length_at[a.beam];
        let span = sj - si;
        Some(Grip {
            mu,
            stiffness: stick_stiffness(cv, a),
            stick: (stick.at - si) / span,
            span,
            side: a.side,
            slip: stick.slip,
            face: 0.5 * cv.structure.model.beams[a.beam].section.thickness,
            roll: stick.roll,
            turn: None,
            rolled: (0.0, 0.0),
        })
    }

    /// The return mapping at a converged pass (assembled in `asm`): every frictional contact,
    /// with a beam or an obstacle, whose trial force asks for the other mode
    /// ([`Traction::mode`]) changes to it. Returns the number of changes (0: the friction law
    /// holds). Once a set of modes comes back within the attempt, one change a pass, the
    /// contact of least index, and a slip that turns back sticks first.
    pub(crate) fn friction_pass(&mut self, cv: &ContactView<'_>, asm: &Assembled) -> usize {
        let tractions = &asm.elements.contact_friction;
        let mut changes = Vec::new();
        // A slip that has turned to the other direction within the attempt sticks first at its
        // next turn: an unloaded slipping zone whose every node turns at once overshoots, and
        // would swing from one direction to the other, wider at each pass.
        let mut turned = std::mem::take(&mut self.friction.turned);
        // What a trial force is known to: the state's unbalanced force, and the stick spring
        // over the round-off of the places it stretches between (a stiff spring turns one
        // unit in the last place of a coordinate into a sizeable force).
        let unbalanced = asm.unbalanced_norm2.sqrt();
        let slack = |stiffness: f64, place: f64| {
            unbalanced + stiffness * STICK_ROUNDOFF_ULPS * f64::EPSILON * place.abs()
        };
        let mut want = |key, now: Option<f64>, t: &Traction, slack: f64| {
            let swings = turned.get(&key).copied().unwrap_or(0);
            let want = t.mode(
                now,
                self.friction.guard.one_at_a_time() || swings >= MAX_TURNS,
                slack,
            );
            if let (Some(a), Some(b)) = (now, want) {
                if a * b < 0.0 {
                    turned.insert(key, swings + 1);
                }
            }
            want
        };
        for (k, a) in self.beams.active.iter().enumerate() {
            let (Some(stick), Some(Some(t))) = (a.stick, tractions.get(k)) else {
                continue;
            };
            let kt = stick_stiffness(cv, a);
            // The stick point and a rim's roll, what the slip is worked from.
            let size = stick.at.abs().max(stick.roll.abs());
            let want = want((a.node, a.body, false), stick.slip, t, slack(kt, size));
            if want != stick.slip {
                changes.push((k, want));
            }
        }
        let obstacle_tractions = &asm.elements.obstacle_friction;
        for (k, link) in self.obstacles.links.iter().enumerate() {
            let (Some(grip), Some(Some(t))) = (link.grip, obstacle_tractions.get(k)) else {
                continue;
            };
            let size = grip.stick.abs().max(grip.reach * grip.roll.abs());
            let place = slack(grip.stiffness, size);
            let want = want((link.node, link.obstacle, true), grip.slip, t, place);
            if want != grip.slip {
                changes.push((self.beams.active.len() + k, want));
            }
        }
        self.friction.turned = turned;
        if self.friction.guard.one_at_a_time() {
            changes.truncate(1);
        }
        let beams = self.beams.active.len();
        for &(k, want) in &changes {
            if k >= beams {
                if let Some(grip) = self.obstacles.links[k - beams].grip.as_mut() {
                    grip.slip = want;
                }
            } else if let Some(stick) = self.beams.active[k].stick.as_mut() {
                stick.slip = want;
            }
        }
        if !changes.is_empty() {
            let on_obstacles =
                (self.obstacles.links.iter()).map(|l| l.grip.map_or(0, |g| mode_code(g.slip)));
            let modes = (self.beams.active.iter())
                .map(|a| a.stick.map_or(0, |s| mode_code(s.slip)))
                .chain(on_obstacles)
                .collect();
            self.friction.guard.reached(modes);
        }
        changes.len()
    }

    /// After the predictor of an attempt (assembled in `asm`): every slipping contact, with a
    /// beam or an obstacle, whose trial force the predicted state brings back inside the
    /// Coulomb cone sticks. The slip has turned back against its own friction (the drive
    /// unloads or reverses): under the slip mode the contact would slide freely the wrong
    /// way, with the friction pushing it on, a near-mechanism Newton cannot converge on at
    /// any step size. Returns how many stick now.
    pub(crate) fn unloaded_slips(&mut self, asm: &Assembled) -> usize {
        // A slip the cautious return mapping, with no slack, would stick.
        let inside =
            |slip: Option<f64>, t: &Traction| slip.is_some() && t.mode(slip, true, 0.0).is_none();
        let mut stuck = 0;
        let tractions = &asm.elements.contact_friction;
        for (a, t) in self.beams.active.iter_mut().zip(tractions) {
            if let (Some(stick), Some(t)) = (a.stick.as_mut(), t) {
                if inside(stick.slip, t) {
                    stick.slip = None;
                    stuck += 1;
                }
            }
        }
        let tractions = &asm.elements.obstacle_friction;
        for (link, t) in self.obstacles.links.iter_mut().zip(tractions) {
            if let (Some(grip), Some(t)) = (link.grip.as_mut(), t) {
                if inside(grip.slip, t) {
                    grip.slip = None;
                    stuck += 1;
                }
            }
        }
        stuck
    }

    /// At the accepted pass of an increment (at displacements `d`, assembled in `asm`): the stick point of every
    /// slipping contact, with a beam or an obstacle, moves to where its spring carries the
    /// Coulomb force, s - f / kt, and every contact that changed between stick and slip since
    /// the last accepted state (`cv`) is an event.
    pub(crate) fn settle_friction(
        &mut self,
        cv: &ContactView<'_>,
        (d, asm): (&[f64], &Assembled),
        increment: usize,
        iteration: usize,
        events: &mut Vec<Event>,
    ) {
        let tractions = &asm.elements.contact_friction;
        let frictional = |t: &[Option<Traction>]| t.iter().any(Option::is_some);
        let scale = if frictional(tractions) || frictional(&asm.elements.obstacle_friction) {
            cv.structure.coordinate_scale(cv.d)
        } else {
            1.0
        };
        for k in 0..self.beams.active.len() {
            let a = self.beams.active[k];
            let (Some(mut stick), Some(Some(t))) = (a.stick, tractions.get(k)) else {
                continue;
            };
            // A rim's roll since the stick point moves into it, as on an obstacle, and the
            // roll is measured afresh from where it now sticks.
            stick.at -= t.rolled;
            if t.slipping {
                stick.at += t.slip - t.force / stick_stiffness(cv, &a);
            }
            if t.rim_roll != 0.0 || stick.roll != 0.0 {
                let [si, sj] = cv.structure.body_length_at[a.beam];
                let at = (stick.at - si) / (sj - si);
                stick.roll = rim_roll(cv, d, (a.node, a.side), (a.beam, sj - si), at);
            }
            let before = (cv.contacts.beams.active.iter())
                .find(|b| b.node == a.node && b.body == a.body)
                .and_then(|b| b.stick);
            let slipped = before.is_some_and(|b| b.slip.is_some());
            if t.slipping != slipped {
                let change = if t.slipping {
                    ContactChange::Slips
                } else {
                    ContactChange::Sticks
                };
                let xi = asm.elements.contact_forces[k].1;
                let event = Self::event(cv, &a, change, increment, iteration, xi, t.tangential);
                events.push(event);
            }
            // The spring the next increment holds it with, from the same stick point.
            stick.resolved = resolvable(t.limit, scale.max(stick.at.abs()));
            self.beams.active[k].stick = Some(stick);
        }
        let tractions = &asm.elements.obstacle_friction;
        for k in 0..self.obstacles.links.len() {
            let link = self.obstacles.links[k];
            let (Some(mut grip), Some(Some(t))) = (link.grip, tractions.get(k)) else {
                continue;
            };
            // A rim's turn since the stick point moves into the place: the stick point stays
            // where it is, and the turn is measured from the rim as it is now.
            if grip.reach > 0.0 {
                grip.stick -= t.rolled;
                grip.roll += t.rim_roll / grip.reach;
            }
            if t.slipping {
                grip.stick += t.slip - t.force / grip.stiffness;
            }
            // The spring the next increment holds it with, from the same stick point.
            let size = scale.max(grip.stick.abs()).max(grip.period.unwrap_or(0.0));
            grip.stiffness = obstacle_stick_stiffness(cv, link.node).min(resolvable(t.limit, size));
            let before = cv.contacts.obstacles.links.get(k).and_then(|b| b.grip);
            let slipped = before.is_some_and(|b| b.slip.is_some());
            if t.slipping != slipped {
                let m = &cv.structure.model;
                events.push(Event::Obstacle(ObstacleEvent {
                    change: if t.slipping {
                        ContactChange::Slips
                    } else {
                        ContactChange::Sticks
                    },
                    increment,
                    iteration,
                    node: m.nodes[link.node].id,
                    obstacle: m.obstacles[link.obstacle].name.clone(),
                    force: t.tangential,
                }));
            }
            self.obstacles.links[k].grip = Some(grip);
        }
    }
}
