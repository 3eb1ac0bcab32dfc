//! Contacts that move during the iterations: transfer along the body to the element the node
//! lies over when li/l leaves (0, 1), and release when the node slides off a free end of the
//! beam.

use super::probe::chord_fraction_of;
use super::set::pressed_point;
use super::set::ContactView;
use super::set::{ActiveContact, ContactSet};
use crate::solver::assembly::current;
use crate::solver::report::{ContactChange, ContactEvent, Event};

/// How far chord fraction `t` lies beyond its element, in element lengths (negative inside).
fn overshoot(t: f64) -> f64 {
    (-t).max(t - 1.0)
}

impl ContactSet {
    pub(super) fn event(
        cv: &ContactView<'_>,
        a: &ActiveContact,
        change: ContactChange,
        increment: usize,
        iteration: usize,
        xi: f64,
        force: f64,
    ) -> Event {
        let m = &cv.structure.model;
        Event::Contact(ContactEvent {
            change,
            increment,
            iteration,
            node: m.nodes[a.node].id,
            element: a.beam,
            body: m.bodies[a.body].name.clone(),
            xi,
            force,
        })
    }

    /// Move contacts whose li/l left [0, 1] along the body: each walks to the element its node
    /// lies over, however many elements on (a node that slides three elements in one increment
    /// rests on the third from the first iterate on).
    /// Between iterations it never leaves the body (intermediate iterates can be far off); at a
    /// converged state (`converged`) it slides off a free end. Returns the number of changes.
    pub fn transfer(
        &mut self,
        cv: &ContactView<'_>,
        d: &[f64],
        increment: usize,
        iteration: usize,
        converged: bool,
        events: &mut Vec<Event>,
    ) -> usize {
        let margin = if converged {
            cv.structure.params.free_end_margin
        } else {
            -cv.structure.params.transfer_tolerance
        };
        self.transfer_within(cv, d, (increment, iteration), converged, margin, events)
    }

    /// Slide off a free end every contact that lies within `margin` (a fraction of its element)
    /// of it at the converged state `d`: for an increment that finds no equilibrium with the
    /// contact on a tip (past the limit point where the tip slips under the node, the contact
    /// point runs to the tip and Newton fails), the attempt that starts with the node let go.
    /// Returns the number of contacts slid off.
    pub(crate) fn slide_off_tips(
        &mut self,
        cv: &ContactView<'_>,
        d: &[f64],
        margin: f64,
        increment: usize,
        events: &mut Vec<Event>,
    ) -> usize {
        self.transfer_within(cv, d, (increment, 0), true, margin, events)
    }

    /// Whether node `n` may touch element `beam` of body `b`: `(n, b)` is a candidate pair and,
    /// for a node of `b` itself, the element lies outside the node's own window.
    fn may_touch(cv: &ContactView<'_>, n: usize, b: usize, beam: usize) -> bool {
        let own = &cv.structure.model.beams[beam];
        if own.i == n || own.j == n || !Self::candidates(cv).contains(&(n, b)) {
            return false;
        }
        cv.structure.outside_window(n, b, beam)
    }

    /// Whether the side of a contact handed over to node `h.node` on body `h.body` (what the
    /// hand-over infers from the bodies' directions) is the side the node was on at the last
    /// converged state, where that was measured against `h.beam` or a neighbour of it. A node
    /// clear of the body then has not crossed it since (every crossing is caught at a converged
    /// pass); where the two disagree (two bodies that meet tip on node at an angle), the node is
    /// not handed over: it is let go, and found through the body from the side it is on if it
    /// crosses.
    fn side_agrees(&self, cv: &ContactView<'_>, h: &ActiveContact) -> bool {
        match self.beams.sides.get(&(h.node, h.body)) {
            Some(&(side, was)) if Self::adjacent(cv, h.body, was, h.beam) => side == h.side,
            _ => true,
        }
    }

    /// The contact of tip `tip` on the body of node `a.node`, which slides off that tip: on the
    /// element at the node that the tip projects onto, from the side opposite to the node's
    /// (the elements lying roughly parallel). The two may be parts of one body: a coil whose
    /// turn rests on its own first element until the coil opens and the turn slides off the
    /// clamped end, which then rests on the turn; and the node may be an end of its body, the
    /// tip then lying over its element clear of the free end's margin. `None` where the node
    /// is no mesh node of a body, the tip may not touch that body there or already rests on
    /// it, or the two elements cross steeply (the side would be a guess).
    fn tip_onto_node_body(
        &self,
        cv: &ContactView<'_>,
        d: &[f64],
        a: &ActiveContact,
        tip: usize,
    ) -> Option<ActiveContact> {
        let m = &cv.structure.model;
        let (e1, e2) = match *cv.structure.node_beams[a.node].as_slice() {
            [e1, e2] => (e1, e2),
            [e] => (e, e),
            _ => return None,
        };
        let body = m.beams[e1].body;
        if m.beams[e2].body != body || self.is_active(tip, body) {
            return None;
        }
        let outside = |e: usize| overshoot(Self::chord_fraction(cv, d, tip, e)).max(0.0);
        let e = if outside(e1) <= outside(e2) { e1 } else { e2 };
        if !Self::may_touch(cv, tip, body, e) {
            return None;
        }
        // The node an end of its body: the tip must lie over its element clear of the free
        // end's margin, or the touch would slide off there at the next pass and come back.
        let margin = cv.structure.params.free_end_margin;
        let over = |t: f64| t > margin && t < 1.0 - margin;
        if e1 == e2 && !over(Self::chord_fraction(cv, d, tip, e)) {
            return None;
        }
        let normal = |e: usize| {
            let (xi, _) = current(m, &cv.structure.dofs, d, m.beams[e].i);
            let (xj, _) = current(m, &cv.structure.dofs, d, m.beams[e].j);
            let (dx, dy) = (xj[0] - xi[0], xj[1] - xi[1]);
            let l = dx.hypot(dy);
            [-dy / l, dx / l]
        };
        let (na, nb) = (normal(a.beam), normal(e));
        let cos = na[0] * nb[0] + na[1] * nb[1];
        if cos.abs() < 0.5 {
            return None;
        }
        let xi = Self::chord_fraction(cv, d, tip, e);
        Some(ActiveContact {
            node: tip,
            beam: e,
            body,
            side: -a.side * cos.signum(),
            stick: Self::stick_at(cv, d, (tip, -a.side * cos.signum()), (body, e), xi),
        })
    }

    /// `transfer` with the free-end margin given: contacts within `margin` of a free end slide
    /// off (a negative margin: only those past it).
    pub(super) fn transfer_within(
        &mut self,
        cv: &ContactView<'_>,
        d: &[f64],
        (increment, iteration): (usize, usize),
        converged: bool,
        margin: f64,
        events: &mut Vec<Event>,
    ) -> usize {
        let m = &cv.structure.model;
        let tol = cv.structure.params.transfer_tolerance;
        let mut changes = 0;
        let mut k = 0;
        while k < self.beams.active.len() {
            let mut a = self.beams.active[k];
            let start = a.beam;
            let mut came_from = None;
            let mut off_end = false;
            let mut xi_now = 0.0;
            let walk = m.bodies[a.body].elements.len();
            for _ in 0..walk {
                let beam = &m.beams[a.beam];
                let (xi, _) = current(m, &cv.structure.dofs, d, beam.i);
                let (xj, _) = current(m, &cv.structure.dofs, d, beam.j);
                let p = pressed_point(cv, d, a.node, a.beam, a.side);
                let t = chord_fraction_of(p, xi, xj);
                xi_now = t;
                let before = cv.structure.node_beams[beam.i]
                    .iter()
                    .copied()
                    .find(|&e| m.beams[e].body == a.body && m.beams[e].j == beam.i);
                let after = cv.structure.node_beams[beam.j]
                    .iter()
                    .copied()
                    .find(|&e| m.beams[e].body == a.body && m.beams[e].i == beam.j);
                let next = if t < -tol || (before.is_none() && t < margin) {
                    before
                } else if t > 1.0 + tol || (after.is_none() && t > 1.0 - margin) {
                    after
                } else {
                    break;
                };
                // In a hollow at a mesh node, a node pressed a little into the beam (the contact
                // spring) lies past the end of each element and before the start of the other:
                // it rests on the node, and stays on its element rather than hop between them.
                if let Some(e) = next {
                    let other = &m.beams[e];
                    let (oi, _) = current(m, &cv.structure.dofs, d, other.i);
                    let (oj, _) = current(m, &cv.structure.dofs, d, other.j);
                    let there = chord_fraction_of(p, oi, oj);
                    let hollow = if t > 1.0 {
                        there < -tol
                    } else {
                        there > 1.0 + tol
                    };
                    if hollow {
                        break;
                    }
                    // A node standing off the beam (a thickness, a radius) is pressed to a
                    // point that depends on the element: at a convex mesh node it can lie past
                    // each of two elements towards the other. It rests on the one it overshoots
                    // less, whichever it came from, so that every pass finds the same.
                    if came_from == Some(e) {
                        let q = pressed_point(cv, d, a.node, e, a.side);
                        if overshoot(chord_fraction_of(q, oi, oj)) < overshoot(t) {
                            a.beam = e;
                        }
                        break;
                    }
                }
                match next {
                    Some(e) => {
                        came_from = Some(a.beam);
                        a.beam = e;
                    }
                    None => {
                        off_end = converged;
                        break;
                    }
                }
            }
            if off_end {
                self.beams.slid_off.push((a.node, a.body));
                events.push(Self::event(
                    cv,
                    &a,
                    ContactChange::SlidOff,
                    increment,
                    iteration,
                    xi_now,
                    0.0,
                ));
                // The node keeps the side it rested on: found beyond the body at the end of
                // the increment, it went round the end only if it lay over the outer half of
                // that end element at the last accepted state (`ContactSet::crossing`).
                // A tip resting on another body hands the node over to that body (the paper's
                // "jump"): the node sits on the tip, so it sits on the other body's surface.
                let beam = &m.beams[a.beam];
                let tip = if xi_now > 0.5 { beam.j } else { beam.i };
                // Only to a body the node may touch there: a candidate pair, and for a node of
                // that body, an element outside its own window (never its own element).
                let under = (self.beams.active.iter())
                    .find(|b| {
                        b.node == tip
                            && b.body != a.body
                            && Self::may_touch(cv, a.node, b.body, b.beam)
                    })
                    .copied();
                let onto_under =
                    under
                        .filter(|u| !self.is_active(a.node, u.body))
                        .map(|u| ActiveContact {
                            node: a.node,
                            beam: u.beam,
                            body: u.body,
                            side: u.side,
                            stick: Self::stick_at(
                                cv,
                                d,
                                (a.node, u.side),
                                (u.body, u.beam),
                                Self::chord_fraction(cv, d, a.node, u.beam),
                            ),
                        });
                // Else a node sliding off a tip (of another body, or of its own in a coil) that
                // rests on nothing of the node's body leaves the tip resting on that body at
                // the node: the same touch, seen from the tip.
                let handed = onto_under
                    .or_else(|| self.tip_onto_node_body(cv, d, &a, tip))
                    .filter(|h| self.side_agrees(cv, h));
                if let Some(h) = handed {
                    let xi_there = Self::chord_fraction(cv, d, h.node, h.beam);
                    events.push(Self::event(
                        cv,
                        &h,
                        ContactChange::Activated,
                        increment,
                        iteration,
                        xi_there,
                        0.0,
                    ));
                    self.beams.sides.insert((h.node, h.body), (h.side, h.beam));
                    self.beams.active[k] = h;
                    changes += 1;
                    k += 1;
                    continue;
                }
                self.beams.active.remove(k);
                changes += 1;
                continue;
            }
            if a.beam != start {
                let xi_there = Self::chord_fraction(cv, d, a.node, a.beam);
                events.push(Self::event(
                    cv,
                    &a,
                    ContactChange::Transferred,
                    increment,
                    iteration,
                    xi_there,
                    0.0,
                ));
                self.beams.active[k] = a;
                changes += 1;
            }
            k += 1;
        }
        changes
    }
}
