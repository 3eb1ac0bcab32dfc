//! Where a node lies relative to a body's deformed shape (`Probe`): the element it projects
//! onto, found through the element grid for a long body, and its gap from the element's
//! deflected shape (the contact element's interpolation with the pass's active contacts).

use std::cell::{OnceCell, RefCell};
use std::rc::Rc;

use super::broad_phase::ElementGrid;
use super::set::ContactView;
use super::set::{pressed_point, ContactSet};
use crate::solver::assembly::current;
use crate::solver::element::contact_element::{contact_response, deflection};
use crate::solver::element::rim::rim_point;
use crate::solver::index_map::IndexMap;

/// Beyond this many element lengths from an element's chord, a node's gap is its distance
/// from the chord (the deflected shape lies well within it).
pub(super) const FAR: f64 = 2.0;
/// A gap within this fraction of the element length (plus the round-off of the positions,
/// [`Solver::touching`]) is touching when sides are recorded: it tells no side.
pub(super) const SIDE: f64 = 1e-10;

/// A node is checked against another part of a body it lies near (`through_another_part`)
/// where it lies within this many of that part's element lengths from the element's chord:
/// the sag of an element bent by a quarter turn, and a crossing's depth, lie well within it.
const ANOTHER_PART: f64 = 0.25;

/// Bodies of more elements than this are probed through the element grid.
const GRID_MIN_ELEMENTS: usize = 32;

/// Where a node lies relative to a body's deformed shape.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Probe {
    /// Element the node projects onto.
    pub beam: usize,
    /// li/l on that element's chord (of the point of the axis it would press on, for a node
    /// that stands off the axis).
    pub xi: f64,
    /// Signed distance from the deformed shape along the chord normal (m); for a node that
    /// stands off the axis, of its surface (`rimmed`): negative where it overlaps the beam.
    pub gap: f64,
    /// The node's own signed distance from the deformed shape (`gap` but for the contact
    /// distance): its sign is the side the node is on, overlapping or not.
    pub centre: f64,
    /// Element chord length (m).
    pub length: f64,
}

/// What the probes of one pass know about one state, built as they need it: the element grid
/// (None with the broad phase off) and the deformed shapes (with the pass's active set). A view
/// serves probes at its own state only.
#[derive(Default)]
pub(super) struct StateView {
    pub(super) grid: OnceCell<Option<ElementGrid>>,
    pub(super) shapes: RefCell<IndexMap<usize, Rc<Shape>>>,
}

/// The views of the iterate and of the last converged state, for one pass.
#[derive(Default)]
pub(super) struct PassViews {
    pub(super) now: StateView,
    pub(super) before: StateView,
}

/// Deformed shape of one element at a state: chord plus bending forces.
pub(super) struct Shape {
    pub(super) origin: [f64; 2],
    pub(super) c: f64,
    pub(super) s: f64,
    pub(super) l: f64,
    pub(super) bending: Vec<f64>,
    pub(super) xis: Vec<f64>,
}
/// li/l of point `p` projected onto the chord from `xi` to `xj`.
#[inline]
pub(super) fn chord_fraction_of(p: [f64; 2], xi: [f64; 2], xj: [f64; 2]) -> f64 {
    let (dx, dy) = (xj[0] - xi[0], xj[1] - xi[1]);
    ((p[0] - xi[0]) * dx + (p[1] - xi[1]) * dy) / (dx * dx + dy * dy)
}

/// Whether node `n` at `d` lies past an end of element `was` of body `b` that is a mesh
/// node inside the body, and before the start of the next element there: in the wedge
/// between the two elements' normals at that node, which no element covers.
pub(super) fn beside_a_convex_node(
    cv: &ContactView<'_>,
    d: &[f64],
    n: usize,
    b: usize,
    was: usize,
) -> bool {
    let els = &cv.structure.model.bodies[b].elements;
    let Some(k) = els.iter().position(|&e| e == was) else {
        return false;
    };
    let t = ContactSet::chord_fraction(cv, d, n, was);
    let next = if t > 1.0 {
        els.get(k + 1)
            .map(|&e| (e, ContactSet::chord_fraction(cv, d, n, e) < 0.0))
    } else if t < 0.0 {
        k.checked_sub(1)
            .map(|j| (els[j], ContactSet::chord_fraction(cv, d, n, els[j]) > 1.0))
    } else {
        None
    };
    // The neighbour must share the mesh node (a body's elements follow one another).
    next.is_some_and(|(e, beyond)| {
        let (w, o) = (&cv.structure.model.beams[was], &cv.structure.model.beams[e]);
        beyond && (w.j == o.i || w.i == o.j)
    })
}

impl ContactSet {
    /// li/l of node `n` on the current chord of beam `e`.
    pub(super) fn chord_fraction(cv: &ContactView<'_>, d: &[f64], n: usize, e: usize) -> f64 {
        let m = &cv.structure.model;
        let (xi, _) = current(m, &cv.structure.dofs, d, m.beams[e].i);
        let (xj, _) = current(m, &cv.structure.dofs, d, m.beams[e].j);
        chord_fraction_of(current(m, &cv.structure.dofs, d, n).0, xi, xj)
    }

    /// The signed distance of node `n` from the current chord of beam `e` (along its left
    /// normal) and the chord's length.
    pub(super) fn chord_offset(cv: &ContactView<'_>, d: &[f64], n: usize, e: usize) -> (f64, f64) {
        let (m, dofs) = (&cv.structure.model, &cv.structure.dofs);
        let (xi, _) = current(m, dofs, d, m.beams[e].i);
        let (xj, _) = current(m, dofs, d, m.beams[e].j);
        let p = current(m, dofs, d, n).0;
        let (dx, dy) = (xj[0] - xi[0], xj[1] - xi[1]);
        let l = dx.hypot(dy);
        ((dx * (p[1] - xi[1]) - dy * (p[0] - xi[0])) / l, l)
    }

    pub(super) fn shape(&self, cv: &ContactView<'_>, d: &[f64], e: usize) -> Shape {
        let m = &cv.structure.model;
        let beam = &m.beams[e];
        let el = &cv.structure.elements[e];
        let (xi, pi) = current(m, &cv.structure.dofs, d, beam.i);
        let (xj, pj) = current(m, &cv.structure.dofs, d, beam.j);
        let on: Vec<[f64; 2]> = self
            .beams
            .active
            .iter()
            .filter(|a| a.beam == e)
            .map(|a| pressed_point(cv, d, a.node, e, a.side))
            .collect();
        let opts = cv.structure.params.contact_options(usize::MAX);
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
    pub(super) fn probe_near(
        &self,
        cv: &ContactView<'_>,
        d: &[f64],
        n: usize,
        b: usize,
        view: Option<&StateView>,
    ) -> Option<Probe> {
        let m = &cv.structure.model;
        let p = current(m, &cv.structure.dofs, d, n).0;
        // A short body is probed element by element: cheaper than building and asking a grid.
        let long = m.bodies[b].elements.len() > GRID_MIN_ELEMENTS;
        let grid = view.filter(|_| long).and_then(|v| {
            v.grid
                .get_or_init(|| ElementGrid::new(cv, d, FAR + 1.0))
                .as_ref()
                .map(|g| (g, v))
        });
        // A node on its own body (self-contact) never probes its own window; the other pairs
        // (all of them in most scenes) take the unfiltered path.
        let window = cv.structure.self_window_of(n, b);
        let place = &cv.structure.place;
        let reaches =
            move |e: &usize| window.is_none_or(|(lo, hi)| !(lo..=hi).contains(&place[*e]));
        if let Some((g, v)) = grid {
            let near = g.near(p).filter(|&e| m.beams[e].body == b);
            let best = match window {
                None => self.closest(cv, d, (n, p), near, Some(v)),
                Some(_) => self.closest(cv, d, (n, p), near.filter(reaches), Some(v)),
            };
            if best.is_some_and(|bp| bp.gap.abs() <= g.reach) {
                return best;
            }
        }
        let all = m.bodies[b].elements.iter().copied();
        match window {
            None => self.closest(cv, d, (n, p), all, view),
            Some(_) => self.closest(cv, d, (n, p), all.filter(reaches), view),
        }
    }

    /// The element among `elements` whose deformed shape is closest to node `n`, at `p`, along
    /// the chord normal, among those the node projects onto (the lowest index on a tie). For a
    /// node that stands off the axis (`Model::contact_distance`), the gap is its surface's:
    /// that of the point of the axis it would press on (`rimmed`), with the side of the node's
    /// centre.
    pub(super) fn closest(
        &self,
        cv: &ContactView<'_>,
        d: &[f64],
        at: (usize, [f64; 2]),
        elements: impl Iterator<Item = usize>,
        view: Option<&StateView>,
    ) -> Option<Probe> {
        // Most models have no contact distances: their probes skip them (`RIMS` false).
        match cv.structure.stands_off {
            true => self.closest_with::<true>(cv, d, at, elements, view),
            false => self.closest_with::<false>(cv, d, at, elements, view),
        }
    }

    /// `closest`, with contact distances looked up where `RIMS`.
    fn closest_with<const RIMS: bool>(
        &self,
        cv: &ContactView<'_>,
        d: &[f64],
        (n, p): (usize, [f64; 2]),
        elements: impl Iterator<Item = usize>,
        view: Option<&StateView>,
    ) -> Option<Probe> {
        let m = &cv.structure.model;
        let mut best: Option<Probe> = None;
        let mut rim = 0.0;
        for e in elements {
            let (xi, _) = current(m, &cv.structure.dofs, d, m.beams[e].i);
            let (xj, _) = current(m, &cv.structure.dofs, d, m.beams[e].j);
            let (dx, dy) = (xj[0] - xi[0], xj[1] - xi[1]);
            let l = dx.hypot(dy);
            let a = [p[0] - xi[0], p[1] - xi[1]];
            let t = (a[0] * dx + a[1] * dy) / (l * l);
            if !(0.0..=1.0).contains(&t) {
                continue;
            }
            let off = (-a[0] * dy + a[1] * dx) / l;
            let r = if RIMS { m.contact_distance(n, e) } else { 0.0 };
            // Far from the chord (more than two element lengths beyond the contact distance)
            // the deflected shape cannot change the side: skip the element's shape (the costly
            // part of a probe).
            let gap = if off.abs() - r > FAR * l {
                off
            } else {
                let sh = self.shape_in(cv, d, e, view);
                off - deflection(&cv.structure.elements[e], &sh.bending, &sh.xis, t)
            };
            if best.is_none_or(|bp| {
                gap.abs() < bp.gap.abs() || (gap.abs() == bp.gap.abs() && e < bp.beam)
            }) {
                best = Some(Probe {
                    beam: e,
                    xi: t,
                    gap,
                    centre: gap,
                    length: l,
                });
                rim = r;
            }
        }
        match best {
            Some(bp) if RIMS && rim > 0.0 => {
                let (gap, xi) = self.rimmed(cv, d, (n, bp), rim, view);
                Some(Probe { gap, xi, ..bp })
            }
            _ => best,
        }
    }

    /// The deformed shape of element `e` at state `d`, kept in `view` (of state `d`) if given.
    fn shape_in(
        &self,
        cv: &ContactView<'_>,
        d: &[f64],
        e: usize,
        view: Option<&StateView>,
    ) -> Rc<Shape> {
        match view {
            Some(v) => Rc::clone(
                v.shapes
                    .borrow_mut()
                    .entry(e)
                    .or_insert_with(|| Rc::new(self.shape(cv, d, e))),
            ),
            None => Rc::new(self.shape(cv, d, e)),
        }
    }

    /// The gap of probe `p` of node `n` that stands off the axis by `r`: its surface's, the
    /// gap of the point of the axis it would press on (`rim_point`, on the side of its centre)
    /// from the deformed shape along the chord normal, as the contact element holds that point
    /// on the shape; negative, against the centre's side, where the node overlaps the beam.
    /// Also that point's fraction along the chord.
    fn rimmed(
        &self,
        cv: &ContactView<'_>,
        d: &[f64],
        (n, p): (usize, Probe),
        r: f64,
        view: Option<&StateView>,
    ) -> (f64, f64) {
        let m = &cv.structure.model;
        let e = p.beam;
        let (xi, pi) = current(m, &cv.structure.dofs, d, m.beams[e].i);
        let (xj, pj) = current(m, &cv.structure.dofs, d, m.beams[e].j);
        let c = current(m, &cv.structure.dofs, d, n).0;
        let side = p.gap.signum();
        let (q, at, _) = rim_point(&cv.structure.elements[e], (xi, xj), [pi, pj], c, side * r);
        let (dx, dy) = (xj[0] - xi[0], xj[1] - xi[1]);
        let l = dx.hypot(dy);
        let off = (-(q[0] - xi[0]) * dy + (q[1] - xi[1]) * dx) / l;
        if off.abs() > FAR * l {
            return (off, at);
        }
        let sh = self.shape_in(cv, d, e, view);
        let along = at.clamp(0.0, 1.0);
        (
            off - deflection(&cv.structure.elements[e], &sh.bending, &sh.xis, along),
            at,
        )
    }

    /// Gap of every active contact node from its beam's deformed shape, relative to the element
    /// length (should be round-off small).
    pub fn active_gaps(&self, cv: &ContactView<'_>, d: &[f64]) -> Vec<f64> {
        self.beams
            .active
            .iter()
            .map(|a| {
                let sh = self.shape(cv, d, a.beam);
                let p = pressed_point(cv, d, a.node, a.beam, a.side);
                let q = [p[0] - sh.origin[0], p[1] - sh.origin[1]];
                let t = (q[0] * sh.c + q[1] * sh.s) / sh.l;
                let off = -q[0] * sh.s + q[1] * sh.c;
                (off - deflection(&cv.structure.elements[a.beam], &sh.bending, &sh.xis, t)) / sh.l
            })
            .collect()
    }

    /// Where node `n` lies at displacements `d` relative to element `e` of body `b` and its
    /// neighbours (those outside the node's own window): the one it projects onto closest, with
    /// `view` of state `d`. None where it projects onto none of them.
    pub(super) fn probe_around(
        &self,
        cv: &ContactView<'_>,
        d: &[f64],
        (n, b): (usize, usize),
        e: usize,
        view: &StateView,
    ) -> Option<Probe> {
        let at = current(&cv.structure.model, &cv.structure.dofs, d, n).0;
        self.closest(cv, d, (n, at), around(cv, (n, b), e), Some(view))
    }

    /// The elements of body `b` that point `c` projects onto at state `d` within `reach` of
    /// their lengths from the chord (found through the element grid for a long body), outside
    /// node `n`'s own window.
    fn elements_near(
        cv: &ContactView<'_>,
        d: &[f64],
        (n, b): (usize, usize),
        c: [f64; 2],
        reach: f64,
        view: &StateView,
    ) -> Vec<usize> {
        let m = &cv.structure.model;
        let els = &m.bodies[b].elements;
        let grid = (els.len() > GRID_MIN_ELEMENTS)
            .then(|| {
                view.grid
                    .get_or_init(|| ElementGrid::new(cv, d, FAR + 1.0))
                    .as_ref()
            })
            .flatten();
        let mut near: Vec<usize> = match grid {
            Some(g) => g.near(c).filter(|&e| m.beams[e].body == b).collect(),
            None => els.clone(),
        };
        near.retain(|&e| {
            let (xi, _) = current(m, &cv.structure.dofs, d, m.beams[e].i);
            let (xj, _) = current(m, &cv.structure.dofs, d, m.beams[e].j);
            let (dx, dy) = (xj[0] - xi[0], xj[1] - xi[1]);
            let l = dx.hypot(dy);
            let t = chord_fraction_of(c, xi, xj);
            let off = ((c[1] - xi[1]) * dx - (c[0] - xi[0]) * dy).abs() / l;
            let r = m.contact_distance(n, e);
            (0.0..=1.0).contains(&t) && off <= reach * l + r && cv.structure.outside_window(n, b, e)
        });
        near
    }

    /// A node of body `b` near two other parts of it (between two layers of a coil), checked
    /// against each: the first element near it now (`ANOTHER_PART`; more than one element from
    /// each of `skip`) that it lies beyond, on the other side from the one it was clear on at
    /// the last converged state (`local_side`), by more than `through` (a fraction of the
    /// element length). Against the element `kept` names (the pair's remembered side, measured
    /// there) or a neighbour of it, the remembered side is the side: a node that rested on it
    /// at the last converged state lay inside it by its contact's penetration, on the far side
    /// to the geometry. Returns its probe now and the side it came from.
    pub(super) fn through_another_part(
        &self,
        cv: &ContactView<'_>,
        d: &[f64],
        (n, b): (usize, usize),
        (skip, kept): ([usize; 2], (f64, usize)),
        views: &PassViews,
        through: f64,
    ) -> Option<(Probe, f64)> {
        // Only a body's own nodes: a body coils round its own nodes in the scenes that coil.
        cv.structure.self_window_of(n, b)?;
        let c = current(&cv.structure.model, &cv.structure.dofs, d, n).0;
        let near = Self::elements_near(cv, d, (n, b), c, ANOTHER_PART, &views.now);
        let far_from_skip = |e: &usize| {
            let place = cv.structure.place[*e];
            skip.iter()
                .all(|&s| cv.structure.place[s].abs_diff(place) > 1)
        };
        near.into_iter().filter(far_from_skip).find_map(|e| {
            let q = self.closest(cv, d, (n, c), std::iter::once(e), Some(&views.now))?;
            let beyond = q.gap.abs() > cv.structure.touching(through, q.length);
            let remembered = || {
                let (side, was) = kept;
                Self::adjacent(cv, b, was, e).then_some((side, was))
            };
            let local = || remembered().or_else(|| self.local_side(cv, (n, b), e, views));
            let (side, _) = beyond.then(local)??;
            (q.gap * side < 0.0).then_some((q, side))
        })
    }

    /// The side of body `b` node `n` was on at the last converged state against element `e` or
    /// a neighbour of it (`probe_around`), where it was clear of it and within `FAR` element
    /// lengths (farther, a side is that of the element's line): for a node whose remembered
    /// side was measured against a distant part of the body (a coil holds a node between two
    /// of its layers, on opposite sides of each). Where it projected onto none of them, the
    /// side of the wedge outside a convex mesh node between them it lay in (`wedge_side`).
    /// None where it lay in no such wedge, or touched them.
    pub(super) fn local_side(
        &self,
        cv: &ContactView<'_>,
        (n, b): (usize, usize),
        e: usize,
        views: &PassViews,
    ) -> Option<(f64, usize)> {
        let Some(q) = self.probe_around(cv, cv.d, (n, b), e, &views.before) else {
            return wedge_side(cv, (n, b), e);
        };
        let clear =
            q.centre.abs() > cv.structure.touching(SIDE, q.length) && q.gap.abs() <= FAR * q.length;
        clear.then(|| (q.centre.signum(), q.beam))
    }
}

/// The side of element `e` of body `b`, or of a neighbour of it, that node `n` lay on at the
/// last converged state where it lay in the wedge outside a convex mesh node of theirs
/// (`beside_a_convex_node`), clear of the element's chord and within `FAR` of its length: there
/// both elements meeting at the node have it on that side. A node gliding along a layer of a
/// coil passes its mesh nodes so, projecting onto none of its elements for a state.
fn wedge_side(cv: &ContactView<'_>, (n, b): (usize, usize), e: usize) -> Option<(f64, usize)> {
    around(cv, (n, b), e).find_map(|f| {
        if !beside_a_convex_node(cv, cv.d, n, b, f) {
            return None;
        }
        let (centre, l) = ContactSet::chord_offset(cv, cv.d, n, f);
        let clear = centre.abs() > cv.structure.touching(SIDE, l) && centre.abs() <= FAR * l;
        clear.then(|| (centre.signum(), f))
    })
}

/// Element `e` of body `b` and its neighbours along the body, outside node `n`'s own window.
pub(super) fn around<'a>(
    cv: &'a ContactView<'_>,
    (n, b): (usize, usize),
    e: usize,
) -> impl Iterator<Item = usize> + 'a {
    let els = &cv.structure.model.bodies[b].elements;
    let k = cv.structure.place[e];
    debug_assert_eq!(els.get(k), Some(&e), "element {e} lies in body {b}");
    (els[k.saturating_sub(1)..(k + 2).min(els.len())]
        .iter()
        .copied())
    .filter(move |&f| cv.structure.outside_window(n, b, f))
}
