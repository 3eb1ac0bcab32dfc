//! Sides and crossings: the side every candidate node was last seen on relative to each
//! candidate body (against the body's deformed shape), and the detection of a node that crossed
//! a body since the last converged state (on the wrong side now, or swept through a chord).

use super::broad_phase::BodyBoxes;
use super::probe::{
    beside_a_convex_node, chord_fraction_of, PassViews, Probe, StateView, FAR, SIDE,
};
use super::set::ContactView;
use super::set::{on_body, ContactSet};
use crate::solver::assembly::current;
use crate::solver::index_map::IndexMap;

/// A node found through a body by less than this (in element lengths) is taken as a crossing
/// without the swept test: the chords used by that test miss the elements' own deflection.
pub(super) const SHAPE_MARGIN: f64 = 0.05;

/// A node must be this fraction of the element length (plus the positions' round-off) on the
/// wrong side of an element to have crossed it.
pub(super) const THROUGH: f64 = 1e-10;

/// Steps of the straight path between two states on which a node on the wrong side of a
/// distant element is followed (`crossed_on_the_way`).
const WAY_STEPS: usize = 16;

impl ContactSet {
    /// Whether node `n` passed through a chord of body `b` between the last converged state and
    /// `d`, with every position interpolated linearly in between (continuous collision test):
    /// the signed area cross(xj - xi, xc - xi) is quadratic in the interpolation parameter; a
    /// root where the node projects inside the chord is a crossing. Tells a node that went
    /// through a beam from one that went round its end while the beam swung.
    pub(super) fn swept_through(cv: &ContactView<'_>, d: &[f64], n: usize, b: usize) -> bool {
        Self::swept_crossing(cv, d, n, b, 0.0).is_some()
    }

    /// The element of body `b` whose chord node `n` passed through (see `swept_through`) at an
    /// interpolation parameter in [`t_min`, 1], if any.
    pub(super) fn swept_crossing(
        cv: &ContactView<'_>,
        d: &[f64],
        n: usize,
        b: usize,
        t_min: f64,
    ) -> Option<usize> {
        let m = &cv.structure.model;
        let at = |dd: &[f64], k: usize| current(m, &cv.structure.dofs, dd, k).0;
        let (c0, c1) = (at(cv.d, n), at(d, n));
        let window = cv.structure.self_window_of(n, b);
        // A node resting on the body at the last converged state touches its chord there
        // without being about to cross it.
        let resting = cv.contacts.is_active(n, b);
        let mut elements = m.bodies[b].elements.iter().copied();
        elements.find(|&e| {
            if window.is_some_and(|(lo, hi)| (lo..=hi).contains(&cv.structure.place[e])) {
                return false;
            }
            let (i, j) = (m.beams[e].i, m.beams[e].j);
            let (p0, p1, q0, q1) = (at(cv.d, i), at(d, i), at(cv.d, j), at(d, j));
            // u(t) = q - p, v(t) = c - p, both linear in t: u = u0 + t du, v = v0 + t dv.
            let sub = |a: [f64; 2], b: [f64; 2]| [a[0] - b[0], a[1] - b[1]];
            let cross = |a: [f64; 2], b: [f64; 2]| a[0] * b[1] - a[1] * b[0];
            let (u0, v0) = (sub(q0, p0), sub(c0, p0));
            let (du, dv) = (sub(sub(q1, p1), u0), sub(sub(c1, p1), v0));
            let (qa, qb, qc) = (cross(du, dv), cross(u0, dv) + cross(du, v0), cross(u0, v0));
            // Touching the chord at the start, over it: the path leaves the line at t = 0
            // (a step that landed exactly on the line, to round-off, and goes on through).
            let l0 = (u0[0] * u0[0] + u0[1] * u0[1]).sqrt();
            let s0 = (u0[0] * v0[0] + u0[1] * v0[1]) / (l0 * l0);
            if t_min == 0.0
                && !resting
                && qc.abs() <= cv.structure.touching(THROUGH, l0) * l0
                && (0.0..=1.0).contains(&s0)
            {
                return true;
            }
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

    /// Whether node `n` lay, at the last converged state, over the outer half of element `e`
    /// of body `b` where `e` is an end element of the body: from there it can go round the
    /// body's end within one increment.
    pub(super) fn over_an_end_half(cv: &ContactView<'_>, n: usize, b: usize, e: usize) -> bool {
        let els = &cv.structure.model.bodies[b].elements;
        let (first, last) = (els.first() == Some(&e), els.last() == Some(&e));
        if !first && !last {
            return false;
        }
        let t = Self::chord_fraction(cv, cv.d, n, e);
        (first && t < 0.5) || (last && t > 0.5)
    }

    /// Whether elements `e` and `f` of body `b` are the same or neighbours. A node crossing a body
    /// within one increment does so near one element; a side measured against a distant element
    /// of a curled beam says nothing about a crossing.
    pub(super) fn adjacent(cv: &ContactView<'_>, b: usize, e: usize, f: usize) -> bool {
        let els = &cv.structure.model.bodies[b].elements;
        match (
            els.iter().position(|&x| x == e),
            els.iter().position(|&x| x == f),
        ) {
            (Some(i), Some(j)) => i.abs_diff(j) <= 1,
            _ => false,
        }
    }

    /// Record the side of every candidate pair that projects onto its body, and forget the pairs
    /// that no longer do, at a converged state. Sides are compared between consecutive converged
    /// states only: a beam that curls can bring a node to the other side of an element's
    /// extension without the node ever crossing the element.
    pub fn remember_sides(&mut self, cv: &ContactView<'_>, d: &[f64]) {
        let pairs = Self::candidates(cv);
        if pairs.is_empty() {
            // No contact pairs: no side to remember (and no body boxes to build).
            return;
        }
        let boxes = BodyBoxes::new(cv, &[d], FAR + 1.0);
        let view = StateView::default();
        for &(n, b) in pairs {
            if let Some(a) = self
                .beams
                .active
                .iter()
                .find(|a| a.node == n && a.body == b)
            {
                self.beams.sides.insert((n, b), (a.side, a.beam));
                continue;
            }
            // Broad phase: far from the body, the side is worked out when the node comes near
            // (`side_of`, from this converged state).
            if !boxes.near(cv, &[d], n, b) {
                self.beams.sides.remove(&(n, b));
                continue;
            }
            match self.probe_near(cv, d, n, b, Some(&view)) {
                // Met vertex on vertex (`met_node_on_node`), a node is touching: it tells no side.
                Some(p)
                    if p.centre.abs() > cv.structure.touching(SIDE, p.length)
                        && !self.met_node_on_node(cv, d, n, &p) =>
                {
                    // Every crossing since the last converged state was caught by
                    // `after_convergence`, so the side now is the side to keep.
                    self.beams.sides.insert((n, b), (p.centre.signum(), p.beam));
                }
                // Touching: the node lies on the body, so its own position says nothing. The
                // side the scene declares; else a node of a beam touches from the side its own
                // beam lies on: take the side of its neighbouring nodes (a pin has none and
                // must start with a gap).
                Some(p) if !self.beams.sides.contains_key(&(n, b)) => {
                    let declared = cv.structure.declared_sides.get(&(n, b)).copied();
                    match declared.or_else(|| self.neighbour_side(cv, d, n, b, Some(&view))) {
                        Some(side) => {
                            self.beams.sides.insert((n, b), (side, p.beam));
                        }
                        // A node of a beam whose neighbours do not all lie clear on one side:
                        // no rule gives its side.
                        None if !cv.structure.node_beams[n].is_empty() => {
                            self.beams.ambiguous.get_or_insert((n, b));
                        }
                        None => {}
                    }
                }
                Some(_) => {}
                // Projecting onto no element, the node lies beyond an end of the body, or in
                // the wedge outside a convex mesh node of it, where both elements meeting
                // there have it on the side it had: that side is kept.
                None => {
                    let kept = (self.beams.sides.get(&(n, b)))
                        .is_some_and(|&(_, was)| beside_a_convex_node(cv, d, n, b, was));
                    if !kept {
                        self.beams.sides.remove(&(n, b));
                    }
                }
            }
        }
    }

    /// Candidate pairs not in contact whose node came near the body between the last converged
    /// state and `d` (the broad phase).
    pub(super) fn near_inactive(&self, cv: &ContactView<'_>, d: &[f64]) -> Vec<(usize, usize)> {
        let pairs = Self::candidates(cv);
        if pairs.is_empty() {
            return Vec::new();
        }
        let states = [cv.d, d];
        let boxes = BodyBoxes::new(cv, &states, FAR + 1.0);
        let active: IndexMap<(usize, usize), ()> = self
            .beams
            .active
            .iter()
            .map(|a| ((a.node, a.body), ()))
            .collect();
        pairs
            .iter()
            .copied()
            .filter(|&(n, b)| !active.contains_key(&(n, b)) && boxes.near(cv, &states, n, b))
            .collect()
    }

    /// The side of body `b` node `n` was on at the last converged state, and the element it
    /// projected onto: remembered if the node was near the body, else worked out now from that
    /// state (far away, the node's side is plain geometry).
    pub(super) fn side_of(
        &self,
        cv: &ContactView<'_>,
        n: usize,
        b: usize,
        view: Option<&StateView>,
    ) -> Option<(f64, usize)> {
        if let Some(&s) = self.beams.sides.get(&(n, b)) {
            return Some(s);
        }
        let p = self.probe_near(cv, cv.d, n, b, view)?;
        (p.centre.abs() > cv.structure.touching(SIDE, p.length))
            .then(|| (p.centre.signum(), p.beam))
    }

    /// The side of body `b` on which the beam neighbours of node `n` lie, if they agree and are
    /// clear of it.
    pub(super) fn neighbour_side(
        &self,
        cv: &ContactView<'_>,
        d: &[f64],
        n: usize,
        b: usize,
        view: Option<&StateView>,
    ) -> Option<f64> {
        let m = &cv.structure.model;
        let mut side = None;
        for beam in cv.structure.node_beams[n]
            .iter()
            .map(|&e| &m.beams[e])
            .filter(|e| e.body != b)
        {
            let other = if beam.i == n { beam.j } else { beam.i };
            let p = self.probe_near(cv, d, other, b, view)?;
            if p.centre.abs() <= cv.structure.touching(SIDE, p.length) {
                return None;
            }
            match side {
                None => side = Some(p.centre.signum()),
                Some(s) if s != p.centre.signum() => return None,
                Some(_) => {}
            }
        }
        side
    }

    /// Whether the inactive candidate node `n` crossed body `b` between the last converged state
    /// and `d`: the probe now and the side the node came from.
    ///
    /// With a remembered side, a crossing is a node now on the other side of an element next to
    /// the one the side was measured against (at any depth, unless it lay over the outer half of
    /// an end element), or with a swept path through a chord. Without one, because at the last converged state the node projected onto no
    /// element (it lay past an end node of the body: beyond a free tip, or beyond a clamped
    /// end), a crossing is a swept path through a chord: a node that passes the body right at
    /// an end node (li/l = 0 or 1) goes from the region no element covers straight to the other
    /// side, and a comparison of sides cannot see it. A node that merely goes round the end has
    /// no such path.
    pub(super) fn crossing(
        &self,
        cv: &ContactView<'_>,
        d: &[f64],
        n: usize,
        b: usize,
        views: &PassViews,
    ) -> Option<(Probe, f64)> {
        let p = self.probe_near(cv, d, n, b, Some(&views.now))?;
        if let Some((side, was)) = self.side_of(cv, n, b, Some(&views.before)) {
            // The part the node lies over now is judged by the rules below, with the side it
            // had there; so is the part the side was measured against (where the node rested,
            // if it did) where that is the same part. Every other part near the node, that one
            // included where the node now lies over another layer of a coil, is judged by its
            // side of that part (`through_another_part`).
            let kept = (side, was);
            let (skip, side, was) = match Self::adjacent(cv, b, was, p.beam) {
                true => ([was, p.beam], side, was),
                false => {
                    let local = self.local_side(cv, (n, b), p.beam, views);
                    let (side, was) = local.unwrap_or((side, was));
                    ([p.beam, p.beam], side, was)
                }
            };
            // Beyond an element next to the one its side was measured against, a node went
            // through at any depth: a beam that springs back past a node resting inside the sag
            // of its chord, or a node that crosses inside the sag, crosses no chord. Beyond one
            // further along (a beam springing back past a node that let go two elements away),
            // only with a swept path: a beam that curls brings far elements round a node
            // without passing through it. A node that lay over the outer half of an end element
            // may have gone round that end within the increment, which a straight sweep of the
            // chords cannot tell: there, only shallow or with a swept path; and if its contact
            // slid off that end in this attempt, its side is open again. A contact let go there
            // as tensile did not go round the end: it keeps its side.
            let wrong_side = p.gap * side < -cv.structure.touching(THROUGH, p.length);
            let round_an_end = Self::over_an_end_half(cv, n, b, was);
            if round_an_end && self.beams.slid_off.contains(&(n, b)) {
                return None;
            }
            if !wrong_side {
                return self.through_another_part(cv, d, (n, b), (skip, kept), views, THROUGH);
            }
            // A side measured from afar (more than `FAR` element lengths from the element's line)
            // tells which side of the line the node lay on, not of the beam: a beam that
            // straightens swings its line past such a node without touching it.
            // Probed once, and only where a rule asks.
            let near = std::cell::OnceCell::new();
            let near_before = || {
                *near.get_or_init(|| {
                    self.probe_near(cv, cv.d, n, b, Some(&views.before))
                        .is_some_and(|q| q.gap.abs() <= FAR * q.length)
                })
            };
            let crossed = (Self::adjacent(cv, b, was, p.beam)
                && (!round_an_end || -p.gap * side < SHAPE_MARGIN * p.length)
                && near_before())
                || Self::swept_through(cv, d, n, b)
                || self.crossed_on_the_way(cv, d, (n, b), side, was, near_before());
            return crossed.then_some((p, side));
        }
        if p.gap != p.centre {
            // A node that stands off the axis has its side from its centre: with no side
            // remembered, an overlap on that side is a touch.
            let side = p.centre.signum();
            return (p.gap * side < -cv.structure.touching(THROUGH, p.length)).then_some((p, side));
        }
        if p.gap.abs() <= cv.structure.touching(THROUGH, p.length) {
            return None;
        }
        if let Some(q) = self.probe_near(cv, cv.d, n, b, Some(&views.before)) {
            // It projected onto the body before, so it touched it then (no side was recorded)
            // or was in contact and slid off a tip in this increment. A node that touched with
            // no side comes from the side opposite to its motion (the zero-gap rule): it is
            // activated, and released again at the next pass if the contact pulls.
            let touched = q.gap.abs() <= cv.structure.touching(SIDE, q.length);
            let was_active = cv.contacts.is_active(n, b);
            return (touched && !was_active).then_some((p, -p.gap.signum()));
        }
        let e = Self::swept_crossing(cv, d, n, b, 0.0)?;
        let m = &cv.structure.model;
        // A node of the crossed element resting on the node's own beam: the two chords meet at
        // that contact (e.g. a tip resting on a beam as one of the beam's nodes passes under
        // it), and the contact there is what keeps the bodies apart.
        let (ei, ej) = (m.beams[e].i, m.beams[e].j);
        if self
            .beams
            .active
            .iter()
            .any(|a| (a.node == ei || a.node == ej) && on_body(cv, n, a.body))
        {
            return None;
        }
        // It must have started clear of the chord it passed through (not exactly on its end).
        let at = |k: usize| current(m, &cv.structure.dofs, cv.d, k).0;
        let (c, xi, xj) = (at(n), at(m.beams[e].i), at(m.beams[e].j));
        let (dx, dy) = (xj[0] - xi[0], xj[1] - xi[1]);
        let t = chord_fraction_of(c, xi, xj).clamp(0.0, 1.0);
        let clear = (c[0] - xi[0] - t * dx).hypot(c[1] - xi[1] - t * dy);
        let l = (dx * dx + dy * dy).sqrt();
        (clear > cv.structure.touching(THROUGH, l) && Self::adjacent(cv, b, e, p.beam))
            .then_some((p, -p.centre.signum()))
    }

    /// Whether node `n`, now on the wrong side of body `b` (its side `side`, measured against
    /// element `was` at the last converged state) two or more elements from there, went through
    /// the body on the way: the straight path from the last converged state to `d`, in
    /// `WAY_STEPS` steps, finds it on the wrong side of the element it lay over at the step
    /// before or of a neighbour, away from the body's ends. A body that rolls along the node
    /// moves the element under it by more than one within an increment; a beam that curls
    /// round the node brings the far element from beyond its end, which the steps see.
    fn crossed_on_the_way(
        &self,
        cv: &ContactView<'_>,
        d: &[f64],
        (n, b): (usize, usize),
        side: f64,
        was: usize,
        was_near: bool,
    ) -> bool {
        // The element the node lay over at the step before, and its side there: carried from
        // element to neighbour, and taken afresh where the node jumps to an element that is
        // no neighbour or lies far (a side against a distant element of a curled beam says
        // nothing about one against this).
        // A side measured from afar is not carried: it is taken where the node comes near.
        let (mut at, mut local) = (was_near.then_some(was), side);
        let mut s = cv.d.to_vec();
        for k in 1..=WAY_STEPS {
            let f = k as f64 / WAY_STEPS as f64;
            for (x, (a, z)) in s.iter_mut().zip(cv.d.iter().zip(d)) {
                *x = a + f * (z - a);
            }
            let Some(p) = self.probe_near(cv, &s, n, b, None) else {
                continue;
            };
            let near = p.gap.abs() <= FAR * p.length;
            let Some(from) = at.filter(|&e| near && Self::adjacent(cv, b, e, p.beam)) else {
                (at, local) = (near.then_some(p.beam), p.centre.signum());
                continue;
            };
            if p.gap * local < -cv.structure.touching(THROUGH, p.length)
                && !Self::over_an_end_half(cv, n, b, from)
            {
                return true;
            }
            at = Some(p.beam);
        }
        false
    }

    /// A node that passed through a chord of a body since the last converged state but now
    /// projects onto no element of it (the chord swept past it right at an end node, e.g. a
    /// clamped end coming down past the other beam's tip): the contact cannot be placed, so the
    /// increment is cut back until the node is caught while it still projects onto the body.
    /// Pairs in `held` (sorted; in contact through the pass that reached `d`) are skipped: `d`
    /// holds each such node on its body, and a contact let go there is judged at the next pass.
    /// Returns (node, body, distance from the body's end node in element lengths).
    pub(super) fn passed_out_of_reach(
        &self,
        cv: &ContactView<'_>,
        d: &[f64],
        views: &PassViews,
        held: &[(usize, usize)],
    ) -> Option<(usize, usize, f64)> {
        let m = &cv.structure.model;
        for (n, b) in self.near_inactive(cv, d) {
            if held.binary_search(&(n, b)).is_ok() {
                continue;
            }
            let Some((_, was)) = self.side_of(cv, n, b, Some(&views.before)) else {
                continue;
            };
            // A contact that slid off an end in this attempt went round it (`crossing`).
            if self.beams.slid_off.contains(&(n, b)) && Self::over_an_end_half(cv, n, b, was) {
                continue;
            }
            if self.probe_near(cv, d, n, b, Some(&views.now)).is_some() {
                continue;
            }
            let Some(e) = Self::swept_crossing(cv, d, n, b, 0.0) else {
                continue;
            };
            let (ei, ej) = (m.beams[e].i, m.beams[e].j);
            // A node of that element resting on the node's own beam keeps them apart there.
            let explained = self
                .beams
                .active
                .iter()
                .any(|a| (a.node == ei || a.node == ej) && on_body(cv, n, a.body));
            if explained || !Self::adjacent(cv, b, was, e) {
                continue;
            }
            let p = current(m, &cv.structure.dofs, d, n).0;
            let (xi, xj) = (
                current(m, &cv.structure.dofs, d, ei).0,
                current(m, &cv.structure.dofs, d, ej).0,
            );
            let l = (xj[0] - xi[0]).hypot(xj[1] - xi[1]);
            let dist = (p[0] - xi[0])
                .hypot(p[1] - xi[1])
                .min((p[0] - xj[0]).hypot(p[1] - xj[1]));
            return Some((n, b, dist / l));
        }
        None
    }
}
