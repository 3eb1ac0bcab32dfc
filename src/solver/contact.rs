//! The contact life cycle: which nodes rest on which beam elements, the side each candidate
//! node is on relative to each candidate body (against the beam's deformed shape), activation
//! when a node crosses a body, transfer to the neighbouring element when li/l leaves (0, 1),
//! release when the contact force turns tensile or the node slides off a free end.

use std::collections::HashMap;

use super::assembly::{current, Assembled, ContactLink};
use super::contact_element::{contact_response, deflection};
use super::control::Solver;
use super::report::{ContactChange, ContactEvent, ContactState, Event};

/// A contact node resting on a beam element.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ActiveContact {
    /// Contact node index.
    pub node: usize,
    /// Beam element index.
    pub beam: usize,
    /// Body index of the beam.
    pub body: usize,
    /// Side of the beam (along its chord normal n) the node came from: +1 or -1.
    pub side: f64,
}

/// Where a node lies relative to a body's deformed shape.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Probe {
    /// Element the node projects onto.
    pub beam: usize,
    /// li/l on that element's chord.
    pub xi: f64,
    /// Signed distance from the deformed shape along the chord normal (m).
    pub gap: f64,
    /// Element chord length (m).
    pub length: f64,
}

/// The active contacts and the remembered sides of every candidate pair.
#[derive(Clone, Debug, Default)]
pub struct ContactSet {
    /// Active contacts.
    pub active: Vec<ActiveContact>,
    sides: HashMap<(usize, usize), f64>,
}

/// Deformed shape of one element at a state: chord plus bending forces.
struct Shape {
    origin: [f64; 2],
    c: f64,
    s: f64,
    l: f64,
    bending: Vec<f64>,
    xis: Vec<f64>,
}

impl ContactSet {
    /// The remembered side of node `node` relative to body `body` (+1 along the chord normal).
    pub fn side(&self, node: usize, body: usize) -> Option<f64> {
        self.sides.get(&(node, body)).copied()
    }

    /// The assembly's view of the active contacts.
    pub fn links(&self) -> Vec<ContactLink> {
        self.active.iter().map(|a| ContactLink { node: a.node, beam: a.beam }).collect()
    }

    fn is_active(&self, node: usize, body: usize) -> bool {
        self.active.iter().any(|a| a.node == node && a.body == body)
    }

    /// Candidate (node, body) pairs of the model.
    pub fn candidates(solver: &Solver) -> Vec<(usize, usize)> {
        let m = &solver.model;
        let mut out = Vec::new();
        for pair in &m.contacts {
            for &b in &pair.bodies {
                let own: Vec<usize> =
                    m.bodies[b].elements.iter().flat_map(|&e| [m.beams[e].i, m.beams[e].j]).collect();
                for &n in &pair.nodes {
                    if !own.contains(&n) && !out.contains(&(n, b)) {
                        out.push((n, b));
                    }
                }
            }
        }
        out
    }

    fn shape(&self, solver: &Solver, d: &[f64], e: usize) -> Shape {
        let m = &solver.model;
        let beam = &m.beams[e];
        let el = &solver.elements[e];
        let (xi, pi) = current(m, &solver.dofs, d, beam.i);
        let (xj, pj) = current(m, &solver.dofs, d, beam.j);
        let on: Vec<[f64; 2]> =
            self.active.iter().filter(|a| a.beam == e).map(|a| current(m, &solver.dofs, d, a.node).0).collect();
        let opts = solver.params.contact_options(usize::MAX);
        let r = contact_response(el, xi, xj, [pi, pj], &on, opts, false);
        let (dx, dy) = (xj[0] - xi[0], xj[1] - xi[1]);
        let l = dx.hypot(dy);
        let xis = r.xi.iter().map(|x| x.clamp(opts.xi_min, 1.0 - opts.xi_min)).collect();
        Shape { origin: xi, c: dx / l, s: dy / l, l, bending: r.forces[1..].to_vec(), xis }
    }

    /// Where node `n` lies relative to body `b` at displacements `d` (None if it projects onto no
    /// element of the body).
    pub fn probe(&self, solver: &Solver, d: &[f64], n: usize, b: usize) -> Option<Probe> {
        let m = &solver.model;
        let p = current(m, &solver.dofs, d, n).0;
        let mut best: Option<Probe> = None;
        for &e in &m.bodies[b].elements {
            let (xi, _) = current(m, &solver.dofs, d, m.beams[e].i);
            let (xj, _) = current(m, &solver.dofs, d, m.beams[e].j);
            let (dx, dy) = (xj[0] - xi[0], xj[1] - xi[1]);
            let l = dx.hypot(dy);
            let a = [p[0] - xi[0], p[1] - xi[1]];
            let t = (a[0] * dx + a[1] * dy) / (l * l);
            if !(0.0..=1.0).contains(&t) {
                continue;
            }
            let off = (-a[0] * dy + a[1] * dx) / l;
            let sh = self.shape(solver, d, e);
            let w = deflection(&solver.elements[e], &sh.bending, &sh.xis, t);
            let gap = off - w;
            if best.is_none_or(|bp| gap.abs() < bp.gap.abs()) {
                best = Some(Probe { beam: e, xi: t, gap, length: l });
            }
        }
        best
    }

    /// Record the side of every candidate pair that newly projects onto its body, and forget the
    /// pairs that no longer do, at a converged state.
    pub fn remember_sides(&mut self, solver: &Solver, d: &[f64]) {
        for (n, b) in Self::candidates(solver) {
            if let Some(a) = self.active.iter().find(|a| a.node == n && a.body == b) {
                self.sides.insert((n, b), a.side);
                continue;
            }
            match self.probe(solver, d, n, b) {
                Some(p) if p.gap.abs() > 1e-12 * p.length => {
                    // A side, once known, only changes by going round an end of the body.
                    self.sides.entry((n, b)).or_insert(p.gap.signum());
                }
                Some(_) => {}
                None => {
                    self.sides.remove(&(n, b));
                }
            }
        }
    }

    fn event(
        solver: &Solver,
        a: &ActiveContact,
        change: ContactChange,
        increment: usize,
        iteration: usize,
        xi: f64,
        force: f64,
    ) -> Event {
        let m = &solver.model;
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

    /// Move contacts whose li/l left [0, 1] to the neighbouring element. Between iterations a
    /// contact moves by at most one element and never leaves the body (intermediate iterates can
    /// be far off); at a converged state (`converged`) it walks to the element it now lies on, or
    /// slides off a free end. Returns the number of changes.
    pub fn transfer(
        &mut self,
        solver: &Solver,
        d: &[f64],
        increment: usize,
        iteration: usize,
        converged: bool,
        events: &mut Vec<Event>,
    ) -> usize {
        let m = &solver.model;
        let tol = solver.params.transfer_tolerance;
        let margin = if converged { solver.params.free_end_margin } else { -tol };
        let mut changes = 0;
        let mut k = 0;
        while k < self.active.len() {
            let mut a = self.active[k];
            let mut moved = false;
            let mut off_end = false;
            let mut xi_now = 0.0;
            let walk = if converged { m.bodies[a.body].elements.len() } else { 1 };
            for _ in 0..walk {
                let beam = &m.beams[a.beam];
                let (xi, _) = current(m, &solver.dofs, d, beam.i);
                let (xj, _) = current(m, &solver.dofs, d, beam.j);
                let p = current(m, &solver.dofs, d, a.node).0;
                let (dx, dy) = (xj[0] - xi[0], xj[1] - xi[1]);
                let t = ((p[0] - xi[0]) * dx + (p[1] - xi[1]) * dy) / (dx * dx + dy * dy);
                xi_now = t;
                let before = m.bodies[a.body].elements.iter().copied().find(|&e| m.beams[e].j == beam.i);
                let after = m.bodies[a.body].elements.iter().copied().find(|&e| m.beams[e].i == beam.j);
                let next = if t < -tol || (before.is_none() && t < margin) {
                    before
                } else if t > 1.0 + tol || (after.is_none() && t > 1.0 - margin) {
                    after
                } else {
                    break;
                };
                match next {
                    Some(e) => {
                        a.beam = e;
                        moved = true;
                    }
                    None => {
                        off_end = converged;
                        break;
                    }
                }
            }
            if off_end {
                events.push(Self::event(solver, &a, ContactChange::SlidOff, increment, iteration, xi_now, 0.0));
                // The node went round the end: its side is unknown until it projects again.
                self.sides.remove(&(a.node, a.body));
                self.active.remove(k);
                changes += 1;
                continue;
            }
            if moved {
                events.push(Self::event(solver, &a, ContactChange::Transferred, increment, iteration, xi_now, 0.0));
                self.active[k] = a;
                changes += 1;
            }
            k += 1;
        }
        changes
    }

    /// At a converged pass: transfers, releases of tensile contacts and activation of crossing
    /// nodes. Returns the number of changes (0 means the increment is done).
    pub fn after_convergence(
        &mut self,
        solver: &Solver,
        d: &[f64],
        asm: &Assembled,
        increment: usize,
        iteration: usize,
        events: &mut Vec<Event>,
    ) -> usize {
        let mut changes = self.transfer(solver, d, increment, iteration, true, events);
        if changes > 0 {
            return changes;
        }
        changes += self.release_tensile(solver, asm, increment, iteration, events);
        for (n, b) in Self::candidates(solver) {
            if self.is_active(n, b) {
                continue;
            }
            let Some(&side) = self.sides.get(&(n, b)) else { continue };
            if let Some(p) = self.probe(solver, d, n, b) {
                if p.gap * side < -1e-10 * p.length {
                    let a = ActiveContact { node: n, beam: p.beam, body: b, side };
                    events.push(Self::event(solver, &a, ContactChange::Activated, increment, iteration, p.xi, 0.0));
                    self.active.push(a);
                    changes += 1;
                }
            }
        }
        changes
    }

    /// Release every contact whose force (from `asm`, assembled with the current contacts) is
    /// tensile. Returns the number released.
    pub fn release_tensile(
        &mut self,
        solver: &Solver,
        asm: &Assembled,
        increment: usize,
        iteration: usize,
        events: &mut Vec<Event>,
    ) -> usize {
        let forces = &asm.elements.contact_forces;
        let before = self.active.len();
        let mut keep = Vec::with_capacity(before);
        for (a, &(yc, xi)) in self.active.iter().zip(forces) {
            if -a.side * yc < 0.0 {
                events.push(Self::event(solver, a, ContactChange::Released, increment, iteration, xi, yc));
            } else {
                keep.push(*a);
            }
        }
        self.active = keep;
        before - self.active.len()
    }

    /// Report states of the active contacts from a converged assembly.
    pub fn states(&self, solver: &Solver, asm: &Assembled) -> Vec<ContactState> {
        let m = &solver.model;
        self.active
            .iter()
            .zip(&asm.elements.contact_forces)
            .map(|(a, &(yc, xi))| ContactState {
                node: m.nodes[a.node].id,
                element: a.beam,
                body: m.bodies[a.body].name.clone(),
                xi,
                force: yc,
                pressure: -a.side * yc,
            })
            .collect()
    }

    /// Largest penetration of an inactive candidate node through a body's deformed shape,
    /// relative to the element length (0 if none).
    pub fn max_penetration(&self, solver: &Solver, d: &[f64]) -> f64 {
        let mut worst: f64 = 0.0;
        for (n, b) in Self::candidates(solver) {
            if self.is_active(n, b) {
                continue;
            }
            if let (Some(&side), Some(p)) = (self.sides.get(&(n, b)), self.probe(solver, d, n, b)) {
                worst = worst.max(-p.gap * side / p.length);
            }
        }
        worst
    }

    /// Gap of every active contact node from its beam's deformed shape, relative to the element
    /// length (should be round-off small).
    pub fn active_gaps(&self, solver: &Solver, d: &[f64]) -> Vec<f64> {
        self.active
            .iter()
            .map(|a| {
                let sh = self.shape(solver, d, a.beam);
                let p = current(&solver.model, &solver.dofs, d, a.node).0;
                let q = [p[0] - sh.origin[0], p[1] - sh.origin[1]];
                let t = (q[0] * sh.c + q[1] * sh.s) / sh.l;
                let off = -q[0] * sh.s + q[1] * sh.c;
                (off - deflection(&solver.elements[a.beam], &sh.bending, &sh.xis, t)) / sh.l
            })
            .collect()
    }
}
