//! The geometric half of the acceptance check (`CrossingCheck`): no contact-candidate node
//! passed through an element of a candidate body between the last accepted state and this one
//! unless it is in contact with that body. The test works on node positions and rotations
//! alone (the chords swept linearly over the increment), so that a bug in the active set
//! cannot hide itself; it is also run on a written history (`tests/contact/acceptance.rs`).

use std::cell::RefCell;
use std::sync::Arc;

use super::chord::{swept_through, Chord};
use super::grid::SweptGrid;
use crate::solver::index_map::IndexMap;
use crate::solver::model::Model;
use crate::solver::report::NodeState;

/// A node found through a body it is not in contact with.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Crossing {
    /// Node index.
    pub node: usize,
    /// Body index.
    pub body: usize,
    /// Element (index) the node ends beyond.
    pub element: usize,
    /// How far beyond the element's deflected shape, in element lengths (a lower bound).
    pub depth: f64,
}

/// Gaps below this fraction of the element length, or below `ROUNDOFF_ULPS` round-off units of
/// the coordinates, are touching: the side of such a node is not evidence of anything.
const TOUCH: f64 = 1e-9;

/// A node whose end position projects within this fraction of the end element's length of a free
/// end, or past it, counts as past that end (`past_free_end`; the contact code lets a node slide
/// off a tip within a thousandth of the element).
const FREE_END: f64 = 0.05;

/// How far from a free end (in lengths of the end element) a node past it counts as having gone
/// round it.
const FREE_REACH: f64 = 2.0;

/// Bodies of more elements than this are searched through the grid (`SweptGrid`), shorter
/// ones element by element.
const GRID_MIN_ELEMENTS: usize = 32;

/// Round-off units of the largest coordinate that a gap may be off by (positions are sums of
/// the initial coordinates and the displacements).
const ROUNDOFF_ULPS: f64 = 64.0;

/// The geometric half of the acceptance check: the side every candidate pair near its body was
/// last seen on, and the last accepted state.
#[derive(Clone, Debug, Default)]
pub struct CrossingCheck {
    /// Candidate (node, body) pairs.
    pairs: Vec<(usize, usize)>,
    /// The candidate bodies, each once.
    bodies: Vec<usize>,
    /// Side (+1/-1 along the element normal, which turns the chord i->j by +90 degrees) of
    /// each pair that was near its body and clear of it at an accepted state.
    sides: IndexMap<(usize, usize), f64>,
    /// The body each element belongs to, and the position of the element in its body.
    place: Vec<(usize, usize)>,
    /// The bodies every node belongs to.
    own: Vec<Vec<usize>>,
    /// Initial chord angle of every element.
    angle0: Vec<f64>,
    /// Whether each element's end i, and its end j, is a free end of its body (no other
    /// element of the body there).
    free: Vec<(bool, bool)>,
    /// The elements of each body with a free end.
    ends: Vec<Vec<usize>>,
    /// The last accepted state.
    last: Vec<NodeState>,
    /// For each self-contact pair (a node and its own body), the positions in the body of the
    /// elements it may not touch: those at the node and two more on either side.
    windows: IndexMap<(usize, usize), (usize, usize)>,
    /// The sweep to the state last checked (`sweep`).
    cache: RefCell<Option<(Vec<NodeState>, Arc<Sweep>)>>,
}

/// What the crossing check carries from one accepted state to the next: the remembered sides
/// and the last accepted state ([`CrossingCheck::memory`], [`CrossingCheck::restore`]).
#[derive(Clone, Debug, Default)]
pub struct CrossingMemory {
    sides: IndexMap<(usize, usize), f64>,
    last: Vec<NodeState>,
}

impl CrossingMemory {
    /// Bytes held (an estimate, for memory budgets).
    pub fn bytes(&self) -> usize {
        self.sides.len() * 32 + self.last.len() * std::mem::size_of::<NodeState>()
    }
}

/// The chords of the candidate bodies' elements at both ends of an increment, and their grid.
#[derive(Debug)]
struct Sweep {
    chords: Vec<Option<(Chord, Chord)>>,
    grid: SweptGrid,
}

impl CrossingCheck {
    /// The check for a model's candidate `pairs`, starting from state `start`.
    pub fn new(model: &Model, pairs: Vec<(usize, usize)>, start: Vec<NodeState>) -> CrossingCheck {
        let mut place = vec![(usize::MAX, 0); model.beams.len()];
        for (b, body) in model.bodies.iter().enumerate() {
            for (k, &e) in body.elements.iter().enumerate() {
                place[e] = (b, k);
            }
        }
        let mut own = vec![Vec::new(); model.nodes.len()];
        for beam in &model.beams {
            for n in [beam.i, beam.j] {
                if !own[n].contains(&beam.body) {
                    own[n].push(beam.body);
                }
            }
        }
        let angle0 = (0..model.beams.len())
            .map(|e| {
                let (a, b) = (
                    model.position(model.beams[e].i),
                    model.position(model.beams[e].j),
                );
                (b[1] - a[1]).atan2(b[0] - a[0])
            })
            .collect();
        let mut count = vec![0u8; model.nodes.len()];
        for beam in &model.beams {
            count[beam.i] = count[beam.i].saturating_add(1);
            count[beam.j] = count[beam.j].saturating_add(1);
        }
        let free: Vec<(bool, bool)> = (model.beams.iter())
            .map(|b| (count[b.i] == 1, count[b.j] == 1))
            .collect();
        let ends = (model.bodies.iter())
            .map(|body| {
                let els = body.elements.iter().copied();
                els.filter(|&e| free[e].0 || free[e].1).collect()
            })
            .collect();
        // A node's own elements in its own body, and two more on either side: the pairs of a
        // node and its own body never look at them.
        let mut windows = IndexMap::default();
        for &(n, b) in &pairs {
            if !own[n].contains(&b) {
                continue;
            }
            let at: Vec<usize> = (model.bodies[b].elements.iter().enumerate())
                .filter(|(_, &e)| model.beams[e].i == n || model.beams[e].j == n)
                .map(|(k, _)| k)
                .collect();
            if let (Some(&lo), Some(&hi)) = (at.first(), at.last()) {
                windows.insert((n, b), (lo.saturating_sub(2), hi + 2));
            }
        }
        let mut bodies: Vec<usize> = pairs.iter().map(|p| p.1).collect();
        bodies.sort_unstable();
        bodies.dedup();
        let mut check = CrossingCheck {
            pairs,
            bodies,
            sides: IndexMap::default(),
            place,
            own,
            angle0,
            free,
            ends,
            last: Vec::new(),
            windows,
            cache: RefCell::new(None),
        };
        check.last = start.clone();
        check.accept(model, start, &[]);
        check
    }

    /// Whether point `c` (a node's end position) lies past a free end of body `b` as the body
    /// was at the last accepted state: beyond the end of the end element's chord (to within
    /// `FREE_END` of its length), and within `FREE_REACH` lengths of the end node. Such a node
    /// slid off that end in the increment, and the body may have sprung back past it: the
    /// straight-line sweep of a body springing back says nothing about which side of it the
    /// node went.
    fn past_free_end(&self, model: &Model, (n, b): (usize, usize), c: [f64; 2]) -> bool {
        // A free end in the node's own window (its own tip) is not one it can go round.
        let ends = self.ends[b].iter().filter(|&&e| self.reaches(n, b, e));
        ends.into_iter().any(|&e| {
            let (free_i, free_j) = self.free[e];
            let k = Chord::at(model, self.angle0[e], e, &self.last);
            let (s, _) = k.locate(c);
            let end = if free_j {
                model.beams[e].j
            } else {
                model.beams[e].i
            };
            let reach = (self.last[end][0] - c[0]).hypot(self.last[end][1] - c[1]);
            let beyond = (free_j && s >= 1.0 - FREE_END) || (free_i && s <= FREE_END);
            beyond && reach <= FREE_REACH * k.l
        })
    }

    /// Whether the check has anything to check (the model has contact candidates).
    pub fn is_empty(&self) -> bool {
        self.pairs.is_empty()
    }

    /// The largest coordinate of two states, for the round-off part of the touching gap.
    fn scale(a: &[NodeState], b: &[NodeState]) -> f64 {
        a.iter()
            .chain(b)
            .fold(0.0f64, |m, s| m.max(s[0].abs()).max(s[1].abs()))
    }

    /// Whether the pair (n, b) is excused at a state with contacts `active` ((node, body)
    /// pairs): n rests on b, or an end node of element `e` rests on a body n belongs to (the
    /// two chords meet at that contact).
    fn excused(
        &self,
        model: &Model,
        active: &[(usize, usize)],
        n: usize,
        b: usize,
        e: usize,
    ) -> bool {
        active.iter().any(|&(m, body)| {
            (m == n && body == b)
                || ((m == model.beams[e].i || m == model.beams[e].j) && self.own[n].contains(&body))
        })
    }

    /// The elements of body `b` whose chords' boxes over both states, grown by an element
    /// length, meet the box of node `n`'s path.
    /// A short body's elements are tried one by one; a long one's through the grid.
    fn near(
        &self,
        model: &Model,
        grid: &SweptGrid,
        (n, b): (usize, usize),
        path: [[f64; 2]; 2],
    ) -> Vec<usize> {
        let lo = [path[0][0].min(path[1][0]), path[0][1].min(path[1][1])];
        let hi = [path[0][0].max(path[1][0]), path[0][1].max(path[1][1])];
        if !grid.meets_body(b, lo, hi) {
            return Vec::new();
        }
        let els = &model.bodies[b].elements;
        let mut out: Vec<usize> = if els.len() <= GRID_MIN_ELEMENTS {
            els.iter()
                .copied()
                .filter(|&e| grid.meets_element(e, lo, hi))
                .collect()
        } else {
            let mut out = grid.query(lo, hi);
            out.retain(|&e| self.place[e].0 == b);
            out
        };
        if !self.windows.is_empty() {
            out.retain(|&e| self.reaches(n, b, e));
        }
        out
    }

    /// Whether node `n` may touch element `e` of body `b` (not one of its own window on its
    /// own body).
    fn reaches(&self, n: usize, b: usize, e: usize) -> bool {
        if self.windows.is_empty() {
            return true;
        }
        match self.windows.get(&(n, b)) {
            Some(&(lo, hi)) => !(lo..=hi).contains(&self.place[e].1),
            None => true,
        }
    }

    /// The candidate pairs (n, b) not in contact (`active` lists those that are) with the
    /// node's positions at the last accepted state and at `after`.
    fn paths_out_of_contact<'a>(
        &'a self,
        after: &'a [NodeState],
        active: &[(usize, usize)],
    ) -> impl Iterator<Item = (usize, usize, [f64; 2], [f64; 2])> + 'a {
        let mut sorted = active.to_vec();
        sorted.sort_unstable();
        (self.pairs.iter())
            .filter(move |p| sorted.binary_search(p).is_err())
            .map(|&(n, b)| {
                let c0 = [self.last[n][0], self.last[n][1]];
                (n, b, c0, [after[n][0], after[n][1]])
            })
    }

    /// The chords and their grid from the last accepted state to `after`, built once for both
    /// `find` and `accept` of the same state.
    fn sweep(&self, model: &Model, after: &[NodeState]) -> Arc<Sweep> {
        let mut cache = self.cache.borrow_mut();
        if let Some((state, sweep)) = cache.as_ref() {
            if state.as_slice() == after {
                return Arc::clone(sweep);
            }
        }
        let chords = self.chords(model, after);
        let body_of = |e: usize| self.place[e].0;
        let long = |b: usize| model.bodies[b].elements.len() > GRID_MIN_ELEMENTS;
        let grid = SweptGrid::new(&chords, body_of, long, model.bodies.len());
        let sweep = Arc::new(Sweep { chords, grid });
        *cache = Some((after.to_vec(), Arc::clone(&sweep)));
        sweep
    }

    /// The chords at the last accepted state and at `after` of every element of a candidate
    /// body (None for the rest).
    fn chords(&self, model: &Model, after: &[NodeState]) -> Vec<Option<(Chord, Chord)>> {
        let mut out = vec![None; model.beams.len()];
        for &b in &self.bodies {
            for &e in &model.bodies[b].elements {
                let a0 = self.angle0[e];
                out[e] = Some((
                    Chord::at(model, a0, e, &self.last),
                    Chord::at(model, a0, e, after),
                ));
            }
        }
        out
    }

    /// The first crossing from the last accepted state to `after`, where `active` lists the
    /// (node, body) pairs in contact at `after`; None if there is none.
    ///
    /// A crossing: node n's path, with the chord of element e of body b, both moved linearly
    /// over the increment, passes through the chord (between its ends), and at `after` n lies
    /// on the other side of e or a neighbour of e (one it projects onto) than it came from,
    /// further than that element's deflection can reach. The side it came from is its side of
    /// e at the start if it was clear then, else the side remembered from the last state where
    /// it was (a node that starts touching with no remembered side gives no evidence).
    pub fn find(
        &self,
        model: &Model,
        after: &[NodeState],
        active: &[(usize, usize)],
    ) -> Option<Crossing> {
        if self.pairs.is_empty() {
            return None;
        }
        let sweep = self.sweep(model, after);
        let (chords, grid) = (&sweep.chords, &sweep.grid);
        let round = ROUNDOFF_ULPS * f64::EPSILON * Self::scale(&self.last, after);
        for (n, b, c0, c1) in self.paths_out_of_contact(after, active) {
            let near = self.near(model, grid, (n, b), [c0, c1]);
            if near.is_empty() || self.past_free_end(model, (n, b), c1) {
                continue;
            }
            for e in near {
                let (k0, _) = chords[e].expect("near elements have chords");
                if !swept_through(k0, chords[e].expect("chord").1, c0, c1) {
                    continue;
                }
                let (_, h0) = k0.locate(c0);
                let side = if h0.abs() > k0.bulge() + TOUCH * k0.l + round {
                    h0.signum()
                } else if let Some(&s) = self.sides.get(&(n, b)) {
                    s
                } else {
                    continue;
                };
                if let Some(c) = self.beyond(model, chords, n, b, e, side, c1, round, active) {
                    return Some(c);
                }
            }
        }
        None
    }

    /// Whether node n at `c` (the end state) lies beyond element e of body b, or beyond a
    /// neighbour it projects onto, on the side opposite to `side` (that of e).
    #[allow(clippy::too_many_arguments)]
    fn beyond(
        &self,
        model: &Model,
        chords: &[Option<(Chord, Chord)>],
        n: usize,
        b: usize,
        e: usize,
        side: f64,
        c: [f64; 2],
        round: f64,
        active: &[(usize, usize)],
    ) -> Option<Crossing> {
        let els = &model.bodies[b].elements;
        let k = self.place[e].1;
        let (ei, ej) = (model.beams[e].i, model.beams[e].j);
        (k.saturating_sub(1)..(k + 2).min(els.len())).find_map(|kf| {
            let f = els[kf];
            let chord = chords[f]?.1;
            let (s, h) = chord.locate(c);
            // The neighbour's normal agrees with e's when the two run the same way.
            let (fi, fj) = (model.beams[f].i, model.beams[f].j);
            let same = f == e || fi == ej || fj == ei;
            let side_f = if same { side } else { -side };
            let depth = -side_f * h - chord.bulge() - TOUCH * chord.l - round;
            // A node whose contacts hold only in some directions (a solid arc's centre) goes
            // past an element freely where the element lies outside them.
            let counts = self.reaches(n, b, f)
                && !self.excused(model, active, n, b, f)
                && chord.within_reach(model, n, side_f);
            ((0.0..=1.0).contains(&s) && depth > 0.0 && counts).then_some(Crossing {
                node: n,
                body: b,
                element: f,
                depth: depth / chord.l,
            })
        })
    }

    /// What this check carries to the next increment.
    pub fn memory(&self) -> CrossingMemory {
        CrossingMemory {
            sides: self.sides.clone(),
            last: self.last.clone(),
        }
    }

    /// Go on from a remembered accepted state.
    pub fn restore(&mut self, memory: &CrossingMemory) {
        self.sides = memory.sides.clone();
        self.last = memory.last.clone();
        *self.cache.get_mut() = None;
    }

    /// Take `after` as the last accepted state (with contacts `active`): remember the side of
    /// every pair near its body and clear of it that is not in contact, and forget the sides of
    /// the pairs that are no longer near.
    pub fn accept(&mut self, model: &Model, after: Vec<NodeState>, active: &[(usize, usize)]) {
        if !self.pairs.is_empty() {
            let sweep = self.sweep(model, &after);
            let (chords, grid) = (&sweep.chords, &sweep.grid);
            let round = ROUNDOFF_ULPS * f64::EPSILON * Self::scale(&self.last, &after);
            let paths: Vec<_> = self.paths_out_of_contact(&after, active).collect();
            for (n, b, c0, c1) in paths {
                // The element the node projects onto that is closest along its normal.
                let closest = self
                    .near(model, grid, (n, b), [c0, c1])
                    .into_iter()
                    .filter_map(|e| {
                        let (k0, k1) = chords[e]?;
                        let (s, h) = k1.locate(c1);
                        (0.0..=1.0).contains(&s).then_some((e, h, k0, k1))
                    })
                    .min_by(|x, y| x.1.abs().total_cmp(&y.1.abs()));
                match closest {
                    None => {
                        self.sides.remove(&(n, b));
                    }
                    Some((_, h, _, k1)) if h.abs() > k1.bulge() + TOUCH * k1.l + round => {
                        self.sides.insert((n, b), h.signum());
                    }
                    Some((_, _, k0, _)) => {
                        // Touching now: the side it came from, if it was clear at the start.
                        let (s, h0) = k0.locate(c0);
                        if (0.0..=1.0).contains(&s) && h0.abs() > k0.bulge() + TOUCH * k0.l + round
                        {
                            self.sides.entry((n, b)).or_insert(h0.signum());
                        }
                    }
                }
            }
        }
        self.last = after;
        *self.cache.get_mut() = None;
    }
}
