//! The contact life cycle: which nodes rest on which beam elements, the side each candidate
//! node is on relative to each candidate body (against the beam's deformed shape), detection of
//! a node crossing a body, transfer to the neighbouring element when li/l leaves (0, 1), and
//! release when the node slides off a free end. Which crossings become contacts and which
//! tensile contacts let go at a converged pass is `active_set.rs`.

use std::cell::{OnceCell, RefCell};
use std::collections::HashSet;
use std::rc::Rc;

use super::assembly::{current, Assembled, ContactLink};
use super::broad_phase::{BodyBoxes, ElementGrid, IndexMap};
use super::contact_element::{contact_response, deflection};
use super::control::Solver;
use super::model::Model;

/// Beyond this many element lengths from an element's chord, a node's gap is its distance
/// from the chord (the deflected shape lies well within it).
const FAR: f64 = 2.0;
use super::report::{ContactChange, ContactEvent, ContactState, Event};

/// A node found through a body by less than this (in element lengths) is taken as a crossing
/// without the swept test: the chords used by that test miss the elements' own deflection.
const SHAPE_MARGIN: f64 = 0.05;

/// A gap within this fraction of the element length (plus the round-off of the positions,
/// `Solver::touching`) is touching when sides are recorded: it tells no side.
const SIDE: f64 = 1e-10;

/// A node must be this fraction of the element length (plus the positions' round-off) on the
/// wrong side of an element to have crossed it.
const THROUGH: f64 = 1e-10;

/// Bodies of more elements than this are probed through the element grid.
const GRID_MIN_ELEMENTS: usize = 32;

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
    /// Per (node, body): the side (+1/-1 along the chord normal) and the element it was
    /// measured against, at the last converged state.
    sides: IndexMap<(usize, usize), (f64, usize)>,
    /// Set by `after_convergence` when a node was found deeper through a body than
    /// `max_penetration` element lengths: (node, body, depth / length). The increment is then
    /// cut back so that the touch is caught close to where it happens.
    pub(crate) too_deep: Option<(usize, usize, f64)>,
    /// Active sets met at the converged passes of the current attempt, to tell cycling.
    pub(super) seen: HashSet<Vec<(usize, usize)>>,
    /// A candidate pair whose node touches the body with its own beam's neighbouring nodes not
    /// all clear on one side of it, found by `remember_sides` (the first one): its side is
    /// ambiguous, and a scene that starts so is refused (`SolveError::AmbiguousSide`).
    pub(crate) ambiguous: Option<(usize, usize)>,
    /// Set once an active set repeats within an attempt: from then on each converged pass fixes
    /// one violation only (see `after_convergence`).
    pub(crate) one_at_a_time: bool,
}

/// Whether node `n` is a node of body `body`.
pub(super) fn on_body(solver: &Solver, n: usize, body: usize) -> bool {
    solver.node_beams[n]
        .iter()
        .any(|&e| solver.model.beams[e].body == body)
}

/// What the probes of one pass know about one state, built as they need it: the element grid
/// (None with the broad phase off) and the deformed shapes (with the pass's active set). A view
/// serves probes at its own state only.
#[derive(Default)]
pub(super) struct StateView {
    grid: OnceCell<Option<ElementGrid>>,
    shapes: RefCell<IndexMap<usize, Rc<Shape>>>,
}

/// The views of the iterate and of the last converged state, for one pass.
#[derive(Default)]
pub(super) struct PassViews {
    pub(super) now: StateView,
    pub(super) before: StateView,
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
    /// Whether node `n` passed through a chord of body `b` between the last converged state and
    /// `d`, with every position interpolated linearly in between (continuous collision test):
    /// the signed area cross(xj - xi, xc - xi) is quadratic in the interpolation parameter; a
    /// root where the node projects inside the chord is a crossing. Tells a node that went
    /// through a beam from one that went round its end while the beam swung.
    fn swept_through(solver: &Solver, d: &[f64], n: usize, b: usize) -> bool {
        Self::swept_crossing(solver, d, n, b, 0.0).is_some()
    }

    /// The element of body `b` whose chord node `n` passed through (see `swept_through`) at an
    /// interpolation parameter in [`t_min`, 1], if any.
    fn swept_crossing(solver: &Solver, d: &[f64], n: usize, b: usize, t_min: f64) -> Option<usize> {
        let m = &solver.model;
        let at = |dd: &[f64], k: usize| current(m, &solver.dofs, dd, k).0;
        let (c0, c1) = (at(&solver.d, n), at(d, n));
        m.bodies[b].elements.iter().copied().find(|&e| {
            let (i, j) = (m.beams[e].i, m.beams[e].j);
            let (p0, p1, q0, q1) = (at(&solver.d, i), at(d, i), at(&solver.d, j), at(d, j));
            // u(t) = q - p, v(t) = c - p, both linear in t: u = u0 + t du, v = v0 + t dv.
            let sub = |a: [f64; 2], b: [f64; 2]| [a[0] - b[0], a[1] - b[1]];
            let cross = |a: [f64; 2], b: [f64; 2]| a[0] * b[1] - a[1] * b[0];
            let (u0, v0) = (sub(q0, p0), sub(c0, p0));
            let (du, dv) = (sub(sub(q1, p1), u0), sub(sub(c1, p1), v0));
            let (qa, qb, qc) = (cross(du, dv), cross(u0, dv) + cross(du, v0), cross(u0, v0));
            let mut roots = Vec::with_capacity(2);
            if qa.abs() < 1e-14 * (qb.abs() + qc.abs()) {
                if qb != 0.0 {
                    roots.push(-qc / qb);
                }
            } else {
                let disc = qb * qb - 4.0 * qa * qc;
                if disc >= 0.0 {
                    let r = disc.sqrt();
                    roots.push((-qb - r) / (2.0 * qa));
                    roots.push((-qb + r) / (2.0 * qa));
                }
            }
            roots
                .into_iter()
                .filter(|t| (t_min..=1.0).contains(t))
                .any(|t| {
                    let u = [u0[0] + t * du[0], u0[1] + t * du[1]];
                    let v = [v0[0] + t * dv[0], v0[1] + t * dv[1]];
                    let s = (u[0] * v[0] + u[1] * v[1]) / (u[0] * u[0] + u[1] * u[1]);
                    (0.0..=1.0).contains(&s)
                })
        })
    }

    /// li/l of node `n` on the current chord of beam `e`.
    fn chord_fraction(solver: &Solver, d: &[f64], n: usize, e: usize) -> f64 {
        let m = &solver.model;
        let (xi, _) = current(m, &solver.dofs, d, m.beams[e].i);
        let (xj, _) = current(m, &solver.dofs, d, m.beams[e].j);
        let p = current(m, &solver.dofs, d, n).0;
        let (dx, dy) = (xj[0] - xi[0], xj[1] - xi[1]);
        ((p[0] - xi[0]) * dx + (p[1] - xi[1]) * dy) / (dx * dx + dy * dy)
    }

    /// Whether elements `e` and `f` of body `b` are the same or neighbours. A node crossing a body
    /// within one increment does so near one element; a side measured against a distant element
    /// of a curled beam says nothing about a crossing.
    fn adjacent(solver: &Solver, b: usize, e: usize, f: usize) -> bool {
        let els = &solver.model.bodies[b].elements;
        match (
            els.iter().position(|&x| x == e),
            els.iter().position(|&x| x == f),
        ) {
            (Some(i), Some(j)) => i.abs_diff(j) <= 1,
            _ => false,
        }
    }

    /// The (node, body) pairs in contact, sorted.
    pub fn pairs(&self) -> Vec<(usize, usize)> {
        let mut set: Vec<(usize, usize)> = self.active.iter().map(|a| (a.node, a.body)).collect();
        set.sort_unstable();
        set
    }

    /// The assembly's view of the active contacts.
    pub fn links(&self) -> Vec<ContactLink> {
        self.active
            .iter()
            .map(|a| ContactLink {
                node: a.node,
                beam: a.beam,
            })
            .collect()
    }

    pub(crate) fn is_active(&self, node: usize, body: usize) -> bool {
        self.active.iter().any(|a| a.node == node && a.body == body)
    }

    /// Candidate (node, body) pairs of the model (a node never touches its own body), in the
    /// order the scene lists them, each once.
    pub fn candidates_of(m: &Model) -> Vec<(usize, usize)> {
        let mut out = Vec::new();
        let mut seen = std::collections::HashSet::new();
        let mut own = vec![usize::MAX; m.nodes.len()];
        for pair in &m.contacts {
            for &b in &pair.bodies {
                for &e in &m.bodies[b].elements {
                    own[m.beams[e].i] = b;
                    own[m.beams[e].j] = b;
                }
                for &n in &pair.nodes {
                    let on_body = m.bodies[b]
                        .elements
                        .iter()
                        .any(|&e| m.beams[e].i == n || m.beams[e].j == n);
                    if own[n] != b && !on_body && seen.insert((n, b)) {
                        out.push((n, b));
                    }
                }
            }
        }
        out
    }

    /// Candidate (node, body) pairs of the solver's model (computed once).
    pub fn candidates(solver: &Solver) -> &[(usize, usize)] {
        &solver.candidates
    }

    fn shape(&self, solver: &Solver, d: &[f64], e: usize) -> Shape {
        let m = &solver.model;
        let beam = &m.beams[e];
        let el = &solver.elements[e];
        let (xi, pi) = current(m, &solver.dofs, d, beam.i);
        let (xj, pj) = current(m, &solver.dofs, d, beam.j);
        let on: Vec<[f64; 2]> = self
            .active
            .iter()
            .filter(|a| a.beam == e)
            .map(|a| current(m, &solver.dofs, d, a.node).0)
            .collect();
        let opts = solver.params.contact_options(usize::MAX);
        let r = contact_response(el, xi, xj, [pi, pj], &on, opts, false);
        let (dx, dy) = (xj[0] - xi[0], xj[1] - xi[1]);
        let l = dx.hypot(dy);
        let xis =
            r.xi.iter()
                .map(|x| x.clamp(opts.xi_min, 1.0 - opts.xi_min))
                .collect();
        Shape {
            origin: xi,
            c: dx / l,
            s: dy / l,
            l,
            bending: r.forces[1..].to_vec(),
            xis,
        }
    }

    /// Where node `n` lies relative to body `b` at displacements `d` (None if it projects onto no
    /// element of the body), with what `view` (of state `d`) knows: the elements its grid finds near the
    /// node are tried first. The closest found there is the closest of all when its gap is
    /// within the grid's reach: every element outside is farther than that from the node, and
    /// far enough from it (more than `FAR` element lengths) that its gap is its plain distance.
    /// Otherwise every element of the body is tried. Shapes are kept in the view.
    fn probe_near(
        &self,
        solver: &Solver,
        d: &[f64],
        n: usize,
        b: usize,
        view: Option<&StateView>,
    ) -> Option<Probe> {
        let m = &solver.model;
        let p = current(m, &solver.dofs, d, n).0;
        // A short body is probed element by element: cheaper than building and asking a grid.
        let long = m.bodies[b].elements.len() > GRID_MIN_ELEMENTS;
        let grid = view.filter(|_| long).and_then(|v| {
            v.grid
                .get_or_init(|| ElementGrid::new(solver, d, FAR + 1.0))
                .as_ref()
                .map(|g| (g, v))
        });
        if let Some((g, v)) = grid {
            let near = g.near(p).filter(|&e| m.beams[e].body == b);
            let best = self.closest(solver, d, p, near, Some(v));
            if best.is_some_and(|bp| bp.gap.abs() <= g.reach) {
                return best;
            }
        }
        self.closest(solver, d, p, m.bodies[b].elements.iter().copied(), view)
    }

    /// The element among `elements` whose deformed shape is closest to point `p` along the
    /// chord normal, among those `p` projects onto (the lowest index on a tie).
    fn closest(
        &self,
        solver: &Solver,
        d: &[f64],
        p: [f64; 2],
        elements: impl Iterator<Item = usize>,
        view: Option<&StateView>,
    ) -> Option<Probe> {
        let m = &solver.model;
        let mut best: Option<Probe> = None;
        for e in elements {
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
            // Far from the chord (more than two element lengths) the deflected shape cannot
            // change the side: skip the element's shape (the costly part of a probe).
            let gap = if off.abs() > FAR * l {
                off
            } else {
                let sh = match view {
                    Some(v) => Rc::clone(
                        v.shapes
                            .borrow_mut()
                            .entry(e)
                            .or_insert_with(|| Rc::new(self.shape(solver, d, e))),
                    ),
                    None => Rc::new(self.shape(solver, d, e)),
                };
                off - deflection(&solver.elements[e], &sh.bending, &sh.xis, t)
            };
            if best.is_none_or(|bp| {
                gap.abs() < bp.gap.abs() || (gap.abs() == bp.gap.abs() && e < bp.beam)
            }) {
                best = Some(Probe {
                    beam: e,
                    xi: t,
                    gap,
                    length: l,
                });
            }
        }
        best
    }

    /// Record the side of every candidate pair that projects onto its body, and forget the pairs
    /// that no longer do, at a converged state. Sides are compared between consecutive converged
    /// states only: a beam that curls can bring a node to the other side of an element's
    /// extension without the node ever crossing the element.
    pub fn remember_sides(&mut self, solver: &Solver, d: &[f64]) {
        let pairs = Self::candidates(solver);
        if pairs.is_empty() {
            // No contact pairs: no side to remember (and no body boxes to build).
            return;
        }
        let boxes = BodyBoxes::new(solver, &[d], FAR + 1.0);
        let view = StateView::default();
        for &(n, b) in pairs {
            if let Some(a) = self.active.iter().find(|a| a.node == n && a.body == b) {
                self.sides.insert((n, b), (a.side, a.beam));
                continue;
            }
            // Broad phase: far from the body, the side is worked out when the node comes near
            // (`side_of`, from this converged state).
            if !boxes.near(solver, &[d], n, b) {
                self.sides.remove(&(n, b));
                continue;
            }
            match self.probe_near(solver, d, n, b, Some(&view)) {
                Some(p) if p.gap.abs() > solver.touching(SIDE, p.length) => {
                    // Every crossing since the last converged state was caught by
                    // `after_convergence`, so the side now is the side to keep.
                    self.sides.insert((n, b), (p.gap.signum(), p.beam));
                }
                // Touching: the node lies on the body, so its own position says nothing. A
                // node of a beam touches from the side its own beam lies on: take the side of
                // its neighbouring nodes (a pin has none and must start with a gap).
                Some(p) if !self.sides.contains_key(&(n, b)) => {
                    match self.neighbour_side(solver, d, n, b, Some(&view)) {
                        Some(side) => {
                            self.sides.insert((n, b), (side, p.beam));
                        }
                        // A node of a beam whose neighbours do not all lie clear on one side:
                        // no rule gives its side.
                        None if !solver.node_beams[n].is_empty() => {
                            self.ambiguous.get_or_insert((n, b));
                        }
                        None => {}
                    }
                }
                Some(_) => {}
                None => {
                    self.sides.remove(&(n, b));
                }
            }
        }
    }

    /// Candidate pairs not in contact whose node came near the body between the last converged
    /// state and `d` (the broad phase).
    pub(super) fn near_inactive(&self, solver: &Solver, d: &[f64]) -> Vec<(usize, usize)> {
        let pairs = Self::candidates(solver);
        if pairs.is_empty() {
            return Vec::new();
        }
        let states = [solver.d.as_slice(), d];
        let boxes = BodyBoxes::new(solver, &states, FAR + 1.0);
        let active: IndexMap<(usize, usize), ()> =
            self.active.iter().map(|a| ((a.node, a.body), ())).collect();
        pairs
            .iter()
            .copied()
            .filter(|&(n, b)| !active.contains_key(&(n, b)) && boxes.near(solver, &states, n, b))
            .collect()
    }

    /// The side of body `b` node `n` was on at the last converged state, and the element it
    /// projected onto: remembered if the node was near the body, else worked out now from that
    /// state (far away, the node's side is plain geometry).
    pub(super) fn side_of(
        &self,
        solver: &Solver,
        n: usize,
        b: usize,
        view: Option<&StateView>,
    ) -> Option<(f64, usize)> {
        if let Some(&s) = self.sides.get(&(n, b)) {
            return Some(s);
        }
        let p = self.probe_near(solver, &solver.d, n, b, view)?;
        (p.gap.abs() > solver.touching(SIDE, p.length)).then(|| (p.gap.signum(), p.beam))
    }

    /// The side of body `b` on which the beam neighbours of node `n` lie, if they agree and are
    /// clear of it.
    fn neighbour_side(
        &self,
        solver: &Solver,
        d: &[f64],
        n: usize,
        b: usize,
        view: Option<&StateView>,
    ) -> Option<f64> {
        let m = &solver.model;
        let mut side = None;
        for beam in solver.node_beams[n]
            .iter()
            .map(|&e| &m.beams[e])
            .filter(|e| e.body != b)
        {
            let other = if beam.i == n { beam.j } else { beam.i };
            let p = self.probe_near(solver, d, other, b, view)?;
            if p.gap.abs() <= solver.touching(SIDE, p.length) {
                return None;
            }
            match side {
                None => side = Some(p.gap.signum()),
                Some(s) if s != p.gap.signum() => return None,
                Some(_) => {}
            }
        }
        side
    }

    pub(super) fn event(
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
        let margin = if converged {
            solver.params.free_end_margin
        } else {
            -solver.params.transfer_tolerance
        };
        self.transfer_within(solver, d, (increment, iteration), converged, margin, events)
    }

    /// Slide off a free end every contact that lies within `margin` (a fraction of its element)
    /// of it at the converged state `d`: for an increment that finds no equilibrium with the
    /// contact on a tip (past the limit point where the tip slips under the node, the contact
    /// point runs to the tip and Newton fails), the attempt that starts with the node let go.
    /// Returns the number of contacts slid off.
    pub(crate) fn slide_off_tips(
        &mut self,
        solver: &Solver,
        d: &[f64],
        margin: f64,
        increment: usize,
        events: &mut Vec<Event>,
    ) -> usize {
        self.transfer_within(solver, d, (increment, 0), true, margin, events)
    }

    /// `transfer` with the free-end margin given: contacts within `margin` of a free end slide
    /// off (a negative margin: only those past it).
    fn transfer_within(
        &mut self,
        solver: &Solver,
        d: &[f64],
        (increment, iteration): (usize, usize),
        converged: bool,
        margin: f64,
        events: &mut Vec<Event>,
    ) -> usize {
        let m = &solver.model;
        let tol = solver.params.transfer_tolerance;
        let mut changes = 0;
        let mut k = 0;
        while k < self.active.len() {
            let mut a = self.active[k];
            let mut moved = false;
            let mut off_end = false;
            let mut xi_now = 0.0;
            let walk = if converged {
                m.bodies[a.body].elements.len()
            } else {
                1
            };
            for _ in 0..walk {
                let beam = &m.beams[a.beam];
                let (xi, _) = current(m, &solver.dofs, d, beam.i);
                let (xj, _) = current(m, &solver.dofs, d, beam.j);
                let p = current(m, &solver.dofs, d, a.node).0;
                let (dx, dy) = (xj[0] - xi[0], xj[1] - xi[1]);
                let t = ((p[0] - xi[0]) * dx + (p[1] - xi[1]) * dy) / (dx * dx + dy * dy);
                xi_now = t;
                let before = solver.node_beams[beam.i]
                    .iter()
                    .copied()
                    .find(|&e| m.beams[e].body == a.body && m.beams[e].j == beam.i);
                let after = solver.node_beams[beam.j]
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
                events.push(Self::event(
                    solver,
                    &a,
                    ContactChange::SlidOff,
                    increment,
                    iteration,
                    xi_now,
                    0.0,
                ));
                // The node went round the end: its side is unknown until it projects again.
                self.sides.remove(&(a.node, a.body));
                // A tip resting on another body hands the node over to that body (the paper's
                // "jump"): the node sits on the tip, so it sits on the other body's surface.
                let beam = &m.beams[a.beam];
                let tip = if xi_now > 0.5 { beam.j } else { beam.i };
                let under = self
                    .active
                    .iter()
                    .find(|b| b.node == tip && b.body != a.body)
                    .copied();
                if let Some(u) = under {
                    if !self.is_active(a.node, u.body) {
                        let h = ActiveContact {
                            node: a.node,
                            beam: u.beam,
                            body: u.body,
                            side: u.side,
                        };
                        let xi_there = Self::chord_fraction(solver, d, a.node, u.beam);
                        events.push(Self::event(
                            solver,
                            &h,
                            ContactChange::Activated,
                            increment,
                            iteration,
                            xi_there,
                            0.0,
                        ));
                        self.sides.insert((a.node, u.body), (u.side, u.beam));
                        self.active[k] = h;
                        changes += 1;
                        k += 1;
                        continue;
                    }
                }
                self.active.remove(k);
                changes += 1;
                continue;
            }
            if moved {
                let xi_there = Self::chord_fraction(solver, d, a.node, a.beam);
                events.push(Self::event(
                    solver,
                    &a,
                    ContactChange::Transferred,
                    increment,
                    iteration,
                    xi_there,
                    0.0,
                ));
                self.active[k] = a;
                changes += 1;
            }
            k += 1;
        }
        changes
    }

    /// Whether the inactive candidate node `n` crossed body `b` between the last converged state
    /// and `d`: the probe now and the side the node came from.
    ///
    /// With a remembered side, a crossing is a node now on the other side of an element next to
    /// the one the side was measured against, found either shallow or with a swept path through
    /// a chord. Without one, because at the last converged state the node projected onto no
    /// element (it lay past an end node of the body: beyond a free tip, or beyond a clamped
    /// end), a crossing is a swept path through a chord: a node that passes the body right at
    /// an end node (li/l = 0 or 1) goes from the region no element covers straight to the other
    /// side, and a comparison of sides cannot see it. A node that merely goes round the end has
    /// no such path.
    pub(super) fn crossing(
        &self,
        solver: &Solver,
        d: &[f64],
        n: usize,
        b: usize,
        views: &PassViews,
    ) -> Option<(Probe, f64)> {
        let p = self.probe_near(solver, d, n, b, Some(&views.now))?;
        if let Some((side, was)) = self.side_of(solver, n, b, Some(&views.before)) {
            // On the other side of an element next to the remembered one, shallow or with a
            // swept path; on the other side of one further along (a beam springing back past a
            // node that let go two elements away), only with a swept path: a beam that curls
            // brings far elements round a node without passing through it.
            let wrong_side = p.gap * side < -solver.touching(THROUGH, p.length);
            let crossed = wrong_side
                && ((-p.gap * side < SHAPE_MARGIN * p.length
                    && Self::adjacent(solver, b, was, p.beam))
                    || Self::swept_through(solver, d, n, b));
            return crossed.then_some((p, side));
        }
        if p.gap.abs() <= solver.touching(THROUGH, p.length) {
            return None;
        }
        if let Some(q) = self.probe_near(solver, &solver.d, n, b, Some(&views.before)) {
            // It projected onto the body before, so it touched it then (no side was recorded)
            // or was in contact and slid off a tip in this increment. A node that touched with
            // no side comes from the side opposite to its motion (the zero-gap rule): it is
            // activated, and released again at the next pass if the contact pulls.
            let touched = q.gap.abs() <= solver.touching(SIDE, q.length);
            let was_active = solver.contacts.is_active(n, b);
            return (touched && !was_active).then_some((p, -p.gap.signum()));
        }
        let e = Self::swept_crossing(solver, d, n, b, 0.0)?;
        let m = &solver.model;
        // A node of the crossed element resting on the node's own beam: the two chords meet at
        // that contact (e.g. a tip resting on a beam as one of the beam's nodes passes under
        // it), and the contact there is what keeps the bodies apart.
        let (ei, ej) = (m.beams[e].i, m.beams[e].j);
        if self
            .active
            .iter()
            .any(|a| (a.node == ei || a.node == ej) && on_body(solver, n, a.body))
        {
            return None;
        }
        // It must have started clear of the chord it passed through (not exactly on its end).
        let at = |k: usize| current(m, &solver.dofs, &solver.d, k).0;
        let (c, xi, xj) = (at(n), at(m.beams[e].i), at(m.beams[e].j));
        let (dx, dy) = (xj[0] - xi[0], xj[1] - xi[1]);
        let l2 = dx * dx + dy * dy;
        let t = (((c[0] - xi[0]) * dx + (c[1] - xi[1]) * dy) / l2).clamp(0.0, 1.0);
        let clear = (c[0] - xi[0] - t * dx).hypot(c[1] - xi[1] - t * dy);
        (clear > solver.touching(THROUGH, l2.sqrt()) && Self::adjacent(solver, b, e, p.beam))
            .then_some((p, -p.gap.signum()))
    }

    /// A node that passed through a chord of a body since the last converged state but now
    /// projects onto no element of it (the chord swept past it right at an end node, e.g. a
    /// clamped end coming down past the other beam's tip): the contact cannot be placed, so the
    /// increment is cut back until the node is caught while it still projects onto the body.
    /// Returns (node, body, distance from the body's end node in element lengths).
    pub(super) fn passed_out_of_reach(
        &self,
        solver: &Solver,
        d: &[f64],
        views: &PassViews,
    ) -> Option<(usize, usize, f64)> {
        let m = &solver.model;
        for (n, b) in self.near_inactive(solver, d) {
            let Some((_, was)) = self.side_of(solver, n, b, Some(&views.before)) else {
                continue;
            };
            if self.probe_near(solver, d, n, b, Some(&views.now)).is_some() {
                continue;
            }
            let Some(e) = Self::swept_crossing(solver, d, n, b, 0.0) else {
                continue;
            };
            let (ei, ej) = (m.beams[e].i, m.beams[e].j);
            // A node of that element resting on the node's own beam keeps them apart there.
            let explained = self
                .active
                .iter()
                .any(|a| (a.node == ei || a.node == ej) && on_body(solver, n, a.body));
            if explained || !Self::adjacent(solver, b, was, e) {
                continue;
            }
            let p = current(m, &solver.dofs, d, n).0;
            let (xi, xj) = (
                current(m, &solver.dofs, d, ei).0,
                current(m, &solver.dofs, d, ej).0,
            );
            let l = (xj[0] - xi[0]).hypot(xj[1] - xi[1]);
            let dist = (p[0] - xi[0])
                .hypot(p[1] - xi[1])
                .min((p[0] - xj[0]).hypot(p[1] - xj[1]));
            return Some((n, b, dist / l));
        }
        None
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
    /// relative to the element length (0 if none), for a state `d` reached from the solver's
    /// converged state (the sides are those of that state).
    pub fn max_penetration(&self, solver: &Solver, d: &[f64]) -> f64 {
        let mut worst: f64 = 0.0;
        let near = self.near_inactive(solver, d);
        if near.is_empty() {
            return worst;
        }
        let views = PassViews::default();
        for (n, b) in near {
            if let Some((p, side)) = self.crossing(solver, d, n, b, &views) {
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
