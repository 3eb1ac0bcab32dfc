//! The contact active set at a converged pass: which tensile contacts let go and which crossing
//! nodes become contacts. All violations are fixed at once while that makes progress; once an
//! active set comes back within an attempt (cycling), one violation per pass, Murty's
//! least-index rule. Two nodes of different bodies that meet node on node each get a contact
//! on the other's body when each is found through it: one of them alone would leave the other
//! through the first body wherever their chords meet at an angle. Where one already rests on
//! the other's element within `xi_min` of the other node (vertex on vertex), the other gets
//! none (`met_node_on_node`). A node that went through a body right at a convex mesh node,
//! into the wedge outside it, cuts the increment back. A node
//! that touches only in some directions (`Node::reach`: a solid arc's centre and ends) touches
//! where the way from it to the beam lies within them, and a contact of it that leaves them is
//! handed to the one whose reach it enters.

use super::probe::{around, beside_a_convex_node, PassViews, Probe, FAR, SIDE};
use super::set::ContactView;
use super::set::{way_to, within_reach, ActiveContact, ContactSet};
use super::sides::THROUGH;
use crate::solver::assembly::{current, Assembled};
use crate::solver::index_map::IndexMap;
use crate::solver::report::{ContactChange, Event};

impl ContactSet {
    /// Forget the passes of a previous attempt (call at the start of each attempt).
    pub(crate) fn begin_attempt(&mut self) {
        self.beams.guard.clear();
        self.beams.slid_off.clear();
        self.obstacles.multiplier_updates = 0;
        self.obstacles.guard.clear();
        self.friction.guard.clear();
        self.friction.turned.clear();
        self.obstacles.touched.clear();
    }

    /// At a converged pass: transfers, releases of tensile contacts and activation of crossing
    /// nodes. Returns the number of changes (0 means the increment is done).
    ///
    /// Every violation (tensile contact, crossing node) is fixed at once, with one release per
    /// element. That can cycle when two beams lie along each other (most nodes touch, few carry
    /// load): once an active set comes back within the attempt, each pass fixes only the
    /// violation of least index (node, body), Murty's rule, which cannot cycle on a linear
    /// complementarity problem with a P-matrix.
    pub fn after_convergence(
        &mut self,
        cv: &ContactView<'_>,
        d: &[f64],
        asm: &Assembled,
        increment: usize,
        iteration: usize,
        events: &mut Vec<Event>,
    ) -> usize {
        let mut changes = self.transfer(cv, d, increment, iteration, true, events);
        changes += self.beyond_reach(cv, d, (increment, iteration), events);
        if changes > 0 {
            return changes;
        }
        // The pairs in contact through this pass: the state `d` holds their nodes on their
        // bodies, so a release below cannot have let one pass out of reach in it.
        let held = self.pairs();
        let mut crossings = Vec::new();
        let near = self.near_inactive(cv, d);
        let views = PassViews::default();
        for &(n, b) in &near {
            // Out of a node's reach (a solid arc's centre beyond the arc), it touches nothing.
            let crossing = self.crossing(cv, d, n, b, &views);
            if let Some((p, side)) = crossing.filter(|&(p, s)| within_reach(cv, d, n, p.beam, s)) {
                if -p.gap * side > cv.structure.params.max_penetration * p.length {
                    self.beams.too_deep = Some((n, b, -p.gap * side / p.length));
                }
                crossings.push((n, b, p, side));
            }
        }
        crossings.retain(|&(n, b, p, _)| {
            !self.met_by_a_tip(cv, n, b, &p) && !self.met_node_on_node(cv, d, n, &p)
        });
        if self.beams.guard.one_at_a_time() {
            let tensile = self.tensile(asm).into_iter().map(|k| {
                let a = self.beams.active[k];
                ((a.node, a.body), Some(k))
            });
            let crossing = crossings.iter().map(|&(n, b, ..)| ((n, b), None));
            if let Some((key, release)) = tensile.chain(crossing).min_by_key(|&(key, _)| key) {
                match release {
                    Some(k) => self.release(cv, asm, &[k], increment, iteration, events),
                    None => {
                        crossings.retain(|c| (c.0, c.1) == key);
                        self.activate(cv, d, &crossings, increment, iteration, events);
                    }
                }
                changes = 1;
            }
        } else {
            changes += self.release_tensile(cv, asm, increment, iteration, events);
            changes += self.activate(cv, d, &crossings, increment, iteration, events);
        }
        if self.beams.too_deep.is_none() {
            // A node that touches only in some directions (a solid arc's centre) goes past the
            // ends of a body and round its convex mesh nodes outside them freely, and within
            // them is held off by its radius before it could.
            let every_way =
                |&(n, ..): &(usize, usize, f64)| cv.structure.model.nodes[n].reach.is_none();
            self.beams.too_deep = (self.passed_out_of_reach(cv, d, &views, &held))
                .or_else(|| self.went_into_a_convex_wedge(cv, d, &near, &held))
                .filter(every_way);
        }
        if changes > 0 {
            self.beams.guard.reached(self.pairs());
        }
        changes
    }

    /// Whether node `n`, found through body `b` at `p` within the free-end margin of a free tip
    /// of `b`, meets that tip where the tip rests on an element of `n`'s own: the two bodies
    /// touch tip on node, and the tip's contact holds them apart. A contact of `n` there would
    /// slide off the tip at the next converged pass and be found through it again, without end.
    fn met_by_a_tip(&self, cv: &ContactView<'_>, n: usize, b: usize, p: &Probe) -> bool {
        let m = &cv.structure.model;
        let beam = &m.beams[p.beam];
        let margin = cv.structure.params.free_end_margin;
        let continues = |node: usize| {
            cv.structure.node_beams[node]
                .iter()
                .filter(|&&e| m.beams[e].body == b)
                .count()
                > 1
        };
        let tip = if p.xi > 1.0 - margin && !continues(beam.j) {
            beam.j
        } else if p.xi < margin && !continues(beam.i) {
            beam.i
        } else {
            return false;
        };
        (self.beams.active.iter()).any(|a| {
            let under = &m.beams[a.beam];
            a.node == tip && (under.i == n || under.j == n)
        })
    }

    /// Whether node `n`, found through `p.beam` within `xi_min` of one of its end nodes (either
    /// way along the chord) and less than `xi_min` element lengths from it, meets
    /// that node node on node: the end node rests in contact on an element that ends at `n`,
    /// within `xi_min` of `n`. Two layers that lie on each other mesh node on mesh node touch
    /// vertex on vertex, where a side means nothing: each vertex lies within the contact
    /// element's resolution (`xi_min` of an element) of the other's element, on one side of it
    /// or the other by their separation times the kink between the layers, and the contact
    /// of one holds them apart. A second contact there would take up part of the first's force
    /// on a normal a kink away from it, and pull.
    pub(super) fn met_node_on_node(
        &self,
        cv: &ContactView<'_>,
        d: &[f64],
        n: usize,
        p: &Probe,
    ) -> bool {
        let m = &cv.structure.model;
        let xi_min = cv.structure.params.xi_min;
        if p.gap.abs() >= xi_min * p.length {
            return false;
        }
        // The end node of element `e` that li/l = `x` lies within `xi_min` of, if any.
        let end_near = |e: usize, x: f64| match x {
            x if x.abs() < xi_min => Some(m.beams[e].i),
            x if (1.0 - x).abs() < xi_min => Some(m.beams[e].j),
            _ => None,
        };
        let Some(vertex) = end_near(p.beam, p.xi) else {
            return false;
        };
        (self.beams.active.iter()).any(|a| {
            a.node == vertex
                && end_near(a.beam, Self::chord_fraction(cv, d, vertex, a.beam)) == Some(n)
        })
    }

    /// Make the crossing nodes active contacts. Returns how many.
    fn activate(
        &mut self,
        cv: &ContactView<'_>,
        d: &[f64],
        crossings: &[(usize, usize, Probe, f64)],
        increment: usize,
        iteration: usize,
        events: &mut Vec<Event>,
    ) -> usize {
        for &(n, b, p, side) in crossings {
            let a = ActiveContact {
                node: n,
                beam: p.beam,
                body: b,
                side,
                stick: Self::stick_at(cv, d, (n, side), (b, p.beam), p.xi),
            };
            events.push(Self::event(
                cv,
                &a,
                ContactChange::Activated,
                increment,
                iteration,
                p.xi,
                0.0,
            ));
            self.beams.active.push(a);
        }
        crossings.len()
    }

    /// Indices of the active contacts whose force (from `asm`) is tensile.
    fn tensile(&self, asm: &Assembled) -> Vec<usize> {
        let forces = &asm.elements.contact_forces;
        (0..self.beams.active.len())
            .filter(|&k| self.beams.active[k].side * forces[k].0 > 0.0)
            .collect()
    }

    /// Release the active contacts with the given indices (ascending; from the `asm` they were
    /// judged on).
    fn release(
        &mut self,
        cv: &ContactView<'_>,
        asm: &Assembled,
        which: &[usize],
        increment: usize,
        iteration: usize,
        events: &mut Vec<Event>,
    ) {
        let forces = &asm.elements.contact_forces;
        for &k in which {
            let (yc, xi) = forces[k];
            events.push(Self::event(
                cv,
                &self.beams.active[k],
                ContactChange::Released,
                increment,
                iteration,
                xi,
                yc,
            ));
        }
        let mut k = 0;
        self.beams.active.retain(|_| {
            k += 1;
            which.binary_search(&(k - 1)).is_err()
        });
    }

    /// Release contacts whose force (from `asm`, assembled with the current contacts) is
    /// tensile. Returns the number released.
    pub fn release_tensile(
        &mut self,
        cv: &ContactView<'_>,
        asm: &Assembled,
        increment: usize,
        iteration: usize,
        events: &mut Vec<Event>,
    ) -> usize {
        let forces = &asm.elements.contact_forces;
        // Contacts on one element are coupled (one contact element carries them all): releasing
        // them together can cycle (A tensile with B, B tensile with A). Per element, only the
        // most tensile is released; the others are judged again after the next converged pass.
        let mut worst: IndexMap<usize, (f64, usize)> = IndexMap::default();
        for k in self.tensile(asm) {
            let t = self.beams.active[k].side * forces[k].0;
            let w = worst.entry(self.beams.active[k].beam).or_insert((0.0, k));
            if t > w.0 {
                *w = (t, k);
            }
        }
        let mut which: Vec<usize> = worst.values().map(|&(_, k)| k).collect();
        which.sort_unstable();
        self.release(cv, asm, &which, increment, iteration, events);
        which.len()
    }
}

impl ContactSet {
    /// Largest penetration of an inactive candidate node through a body's deformed shape,
    /// relative to the element length (0 if none), for a state `d` reached from the cv's
    /// converged state (the sides are those of that state).
    pub fn max_penetration(&self, cv: &ContactView<'_>, d: &[f64]) -> f64 {
        let mut worst: f64 = 0.0;
        let near = self.near_inactive(cv, d);
        if near.is_empty() {
            return worst;
        }
        let views = PassViews::default();
        for (n, b) in near {
            let crossing = self.crossing(cv, d, n, b, &views);
            let counts = |&(p, s): &(Probe, f64)| {
                within_reach(cv, d, n, p.beam, s) && !self.met_node_on_node(cv, d, n, &p)
            };
            if let Some((p, side)) = crossing.filter(counts) {
                worst = worst.max(-p.gap * side / p.length);
            }
        }
        worst
    }

    /// Let go of the contacts whose node touches only in some directions (a solid arc's
    /// centre and ends, `Node::reach`) and whose way to the beam has left them at `d`, each
    /// handed to the node whose reach it has entered (`reach_partner`): the contact slides off
    /// the arc onto its end, or off the end back onto the arc. Returns the changes.
    fn beyond_reach(
        &mut self,
        cv: &ContactView<'_>,
        d: &[f64],
        (increment, iteration): (usize, usize),
        events: &mut Vec<Event>,
    ) -> usize {
        let gone: Vec<ActiveContact> = (self.beams.active.iter().copied())
            .filter(|a| !within_reach(cv, d, a.node, a.beam, a.side))
            .collect();
        if gone.is_empty() {
            return 0;
        }
        let mut changes = 0;
        for a in gone {
            self.beams
                .active
                .retain(|b| (b.node, b.body) != (a.node, a.body));
            let xi = Self::chord_fraction(cv, d, a.node, a.beam);
            let off = Self::event(
                cv,
                &a,
                ContactChange::SlidOff,
                increment,
                iteration,
                xi,
                0.0,
            );
            events.push(off);
            changes += 1;
            let Some(k) = reach_partner(cv, d, &a) else {
                continue;
            };
            if self.is_active(k, a.body) {
                continue;
            }
            let xi = Self::chord_fraction(cv, d, k, a.beam);
            let on = ActiveContact {
                node: k,
                stick: Self::stick_at(cv, d, (k, a.side), (a.body, a.beam), xi),
                ..a
            };
            events.push(Self::event(
                cv,
                &on,
                ContactChange::Activated,
                increment,
                iteration,
                xi,
                0.0,
            ));
            self.beams.active.push(on);
            changes += 1;
        }
        changes
    }

    /// Start in contact every candidate pair whose node rests on its body at the undeformed
    /// state (within the touching tolerance of the deformed shape) on the side the scene
    /// declares for it: a bar laid on a floor beam is held by it from the first iteration, as a
    /// node resting on an obstacle is. A contact that pulls lets go at the first converged
    /// pass.
    pub(crate) fn beams_at_rest(&mut self, cv: &ContactView<'_>) {
        for &(n, b) in Self::candidates(cv) {
            let Some(&side) = cv.structure.declared_sides.get(&(n, b)) else {
                continue;
            };
            if self.is_active(n, b) {
                continue;
            }
            let Some(p) = self.probe_near(cv, cv.d, n, b, None) else {
                continue;
            };
            let touching = p.gap.abs() <= cv.structure.touching(SIDE, p.length);
            if !touching || !within_reach(cv, cv.d, n, p.beam, side) {
                continue;
            }
            let stick = Self::stick_at(cv, cv.d, (n, side), (b, p.beam), p.xi);
            self.beams.active.push(ActiveContact {
                node: n,
                beam: p.beam,
                body: b,
                side,
                stick,
            });
        }
    }

    /// The nodes resting on beams and the directions the beams hold them in (what holds a body
    /// up before it is loaded): the chord's normal, and its direction too where the contact has
    /// friction (it sticks).
    pub(crate) fn resting_on_beams(&self, cv: &ContactView<'_>) -> Vec<(usize, [f64; 2])> {
        let m = &cv.structure.model;
        let mut out = Vec::new();
        for a in &self.beams.active {
            let beam = &m.beams[a.beam];
            let (xi, _) = current(m, &cv.structure.dofs, cv.d, beam.i);
            let (xj, _) = current(m, &cv.structure.dofs, cv.d, beam.j);
            let (dx, dy) = (xj[0] - xi[0], xj[1] - xi[1]);
            let l = dx.hypot(dy);
            out.push((a.node, [-dy / l, dx / l]));
            if a.stick.is_some() {
                out.push((a.node, [dx / l, dy / l]));
            }
        }
        out
    }
}

impl ContactSet {
    /// A node not in contact that now lies in the wedge outside a convex mesh node of the part
    /// of a body its side was measured against (that element or a neighbour), on the other side
    /// of it from its remembered one, having lain within `FAR` element lengths of it at the last
    /// converged state: it went through the body right at that mesh node (a pin driven through
    /// the kink of a bent body, a tip let go at a mesh node of a coil's turn), projecting onto
    /// neither element there and nearest a far part of the body, so that neither `crossing`
    /// nor `passed_out_of_reach` finds it. The increment is cut back until the node is
    /// caught while it still projects onto the body. Looks at the pairs of `near` (those near
    /// their bodies at this pass) not in contact now; pairs in `held` (sorted) are skipped, as
    /// in `passed_out_of_reach`. Returns (node, body, depth in element lengths).
    pub(super) fn went_into_a_convex_wedge(
        &self,
        cv: &ContactView<'_>,
        d: &[f64],
        near: &[(usize, usize)],
        held: &[(usize, usize)],
    ) -> Option<(usize, usize, f64)> {
        near.iter().find_map(|&(n, b)| {
            if held.binary_search(&(n, b)).is_ok() || self.is_active(n, b) {
                return None;
            }
            // Remembered: the node was near the body at the last converged state.
            let &(side, was) = self.beams.sides.get(&(n, b))?;
            around(cv, (n, b), was).find_map(|f| {
                if !beside_a_convex_node(cv, d, n, b, f) {
                    return None;
                }
                let (now, l) = Self::chord_offset(cv, d, n, f);
                let (then, _) = Self::chord_offset(cv, cv.d, n, f);
                let through = now * side < -cv.structure.touching(THROUGH, l);
                (through && then.abs() <= FAR * l).then_some((n, b, -now * side / l))
            })
        })
    }
}

/// The node that takes over contact `a` once its way to the beam has left its node's reach
/// at `d`: a candidate on the same body whose reach holds that way and shares the bound it
/// crossed, standing the difference of their contact distances from `a`'s node (an arc's end
/// for its centre, the centre for an end).
fn reach_partner(cv: &ContactView<'_>, d: &[f64], a: &ActiveContact) -> Option<usize> {
    let m = &cv.structure.model;
    let reach = m.nodes[a.node].reach?;
    let way = way_to(cv, d, a.node, a.beam, a.side);
    let angle = way[1].atan2(way[0]);
    let tau = std::f64::consts::TAU;
    let apart = |x: f64, y: f64| {
        let w = (x - y).rem_euclid(tau);
        w.min(tau - w)
    };
    let bound = match apart(angle, reach.from) <= apart(angle, reach.to) {
        true => reach.from,
        false => reach.to,
    };
    let at = |n: usize| current(m, &cv.structure.dofs, d, n).0;
    let c = at(a.node);
    let size = m.nodes[a.node]
        .clearance
        .max(cv.structure.position_roundoff);
    (ContactSet::candidates(cv).iter())
        .filter(|&&(k, b)| b == a.body && k != a.node)
        .map(|&(k, _)| k)
        .find(|&k| {
            let Some(r) = m.nodes[k].reach else {
                return false;
            };
            let shares = apart(r.from, bound).min(apart(r.to, bound)) <= 1e-12;
            let x = at(k);
            let dist = (x[0] - c[0]).hypot(x[1] - c[1]);
            let expected = (m.nodes[k].clearance - m.nodes[a.node].clearance).abs();
            shares && r.holds(way) && (dist - expected).abs() <= 1e-9 * size
        })
}
