//! Sides: every candidate (node, body) pair keeps the side of the body it was last clear on,
//! through contact and release, and changes it only by going round an end of the body (its
//! free or supported end, or the edge of a self-contact window). A node found clear on the
//! other side of the part of the body it was over, without having gone round an end, went
//! through the body. The path between two recorded states is followed in straight-line
//! sub-steps of every position and rotation. An obstacle's convex features (the centre of a
//! circle or arc that nodes stay out of, a corner of a polyline that juts into the free side)
//! keep their sides of the bodies whose nodes may touch the obstacle in the same way: a
//! feature found beyond an element went through it between its nodes.

use super::finding::Finding;
use super::geometry::{Chains, Place};
use super::obstacles::{convex_features, feature_reach};
use crate::history::Topology;
use crate::solver::report::ContactState;
use crate::solver::IncrementRecord;

/// Sub-steps of the straight-line path between two recorded states, followed when a node turns
/// up on the other side.
const SUBSTEPS: usize = 64;

/// Places along the body within this many elements of the one a side was measured over are the
/// same part of the body: a side measured against a distant part of a curled body says nothing.
const NEIGHBOURS: usize = 2;

/// What the audit remembers of one candidate pair.
#[derive(Clone, Copy, Debug, Default)]
struct Track {
    /// The side (+1 left of the body's direction, -1 right) and the place it was measured over.
    side: Option<(f64, usize)>,
    /// The increment where that side was first seen.
    since: usize,
}

/// What keeps a side: a node, or an obstacle's feature (its place at rest, and the slot of
/// the pilot that moves it).
#[derive(Clone, Copy)]
enum Point {
    Node(usize),
    Feature([f64; 2], Option<usize>),
}

/// One candidate pair as the audit reads it.
struct Pair {
    /// The node's id, or the obstacle's index for a feature.
    node: u32,
    point: Point,
    /// The obstacle's name, for a feature.
    obstacle: Option<String>,
    body: usize,
    /// The side the scene declares for a node that starts touching the body.
    declared: Option<f64>,
    /// Self-contact: the places along its own body that the node leaves out.
    window: Option<(usize, usize)>,
    /// The polar angles (rad, from the first counter-clockwise to the second) of the ways
    /// from the point to the body in which it is kept out: a solid arc's centre goes past the
    /// body freely in any other.
    reach: Option<[f64; 2]>,
}

/// The side audit of a sequence of states.
pub struct SideAudit<'a> {
    chains: &'a Chains,
    topology: &'a Topology,
    pairs: Vec<Pair>,
    tracks: Vec<Track>,
    /// The contact element's resolution along an element (the run's `xi_min`): within it of
    /// a mesh node, a point is at that node.
    resolution: f64,
}

impl<'a> SideAudit<'a> {
    /// The audit of `topology`'s candidate pairs, every side open; `resolution` is the run's
    /// `xi_min`.
    pub fn new(topology: &'a Topology, chains: &'a Chains, resolution: f64) -> SideAudit<'a> {
        let body_of = |name: &str| topology.bodies.iter().position(|b| b.name == name);
        let pairs: Vec<Pair> = (topology.candidates.iter())
            .filter_map(|c| {
                let body = body_of(&c.body)?;
                let slot = *chains.slot.get(&c.node)?;
                let places: Vec<usize> = (chains.nodes[body].iter().enumerate())
                    .filter(|(_, &s)| s == slot)
                    .map(|(k, _)| k)
                    .collect();
                let window = match (places.first(), places.last()) {
                    (Some(&lo), Some(&hi)) => Some((
                        lo.saturating_sub(1 + topology.self_window),
                        hi + topology.self_window,
                    )),
                    _ => None,
                };
                let reach = (topology.nodes.iter()).find(|n| n.id == c.node)?.reach;
                Some(Pair {
                    node: c.node,
                    point: Point::Node(slot),
                    obstacle: None,
                    body,
                    declared: c.side,
                    window,
                    reach,
                })
            })
            .collect();
        let pairs: Vec<Pair> = pairs
            .into_iter()
            .chain(features(topology, chains))
            .collect();
        let tracks = vec![Track::default(); pairs.len()];
        SideAudit {
            chains,
            topology,
            pairs,
            tracks,
            resolution,
        }
    }

    /// Check the step from state `s0` to the record `r1` (`c0`: the contacts of `s0`), and carry
    /// every side on. Returns the crossings found.
    pub fn step(
        &mut self,
        s0: &[[f64; 3]],
        c0: &[(u32, usize, [f64; 2])],
        r1: &IncrementRecord,
        sag: &dyn Fn(usize) -> f64,
    ) -> Vec<Finding> {
        self.step_to(s0, c0, (r1.increment, &r1.nodes, &r1.contacts), sag)
    }

    /// Learn every side from state `s` (the first of a run), which has no contacts.
    pub fn start(&mut self, s: &[[f64; 3]]) {
        let found = self.step_to(s, &[], (0, s, &[]), &|_| 0.0);
        debug_assert!(found.is_empty());
    }

    /// `step` to a state given by its increment number, node states and contacts.
    fn step_to(
        &mut self,
        s0: &[[f64; 3]],
        c0: &[(u32, usize, [f64; 2])],
        (increment, s1, contacts): (usize, &[[f64; 3]], &[ContactState]),
        sag: &dyn Fn(usize) -> f64,
    ) -> Vec<Finding> {
        let body_of = |name: &str| self.topology.bodies.iter().position(|b| b.name == name);
        // Where each contact presses on its element (for a node off the axis, the point of the
        // axis it presses on).
        let resting1: Vec<(usize, [f64; 2])> = (contacts.iter())
            .filter_map(|c| {
                let slot = self.chains.slot.get(&c.node)?;
                Some((c.element, c.point.unwrap_or([s1[*slot][0], s1[*slot][1]])))
            })
            .collect();
        let mut found = Vec::new();
        for k in 0..self.pairs.len() {
            let pair = &self.pairs[k];
            let track = &mut self.tracks[k];
            let allowed = |at: usize| pair.window.is_none_or(|(lo, hi)| at < lo || at > hi);
            let contact = (contacts.iter())
                .filter(|_| pair.obstacle.is_none())
                .find(|c| c.node == pair.node && body_of(&c.body) == Some(pair.body));
            if let Some(c) = contact {
                found.extend(resting(
                    track,
                    pair,
                    c,
                    (self.chains, self.topology),
                    increment,
                ));
                continue;
            }
            let p1 = pair.at(s1, self.chains);
            let Some(now) = self
                .chains
                .place(s1, p1, pair.body, &allowed, &resting1, sag)
            else {
                continue;
            };
            let run = (self.chains, self.topology, self.resolution);
            let verdict = match vertex_on_vertex(run, pair, s1, &now, contacts) {
                true => Verdict::Touching,
                false => judge(track, &now),
            };
            if let (Verdict::Touching, None, Some(s)) = (verdict, track.side, pair.declared) {
                // Touching with no side yet: the side the scene declares.
                track.side = Some((s, now.at));
                track.since = increment;
            }
            if verdict != Verdict::Flipped {
                apply(track, &now, verdict, increment);
                continue;
            }
            // On the other side now. Over the outer half of an end element before, it may
            // have gone round that end.
            let resting0: Vec<(usize, [f64; 2])> = c0.iter().map(|&(_, e, p)| (e, p)).collect();
            let p0 = pair.at(s0, self.chains);
            let before = self
                .chains
                .place(s0, p0, pair.body, &allowed, &resting0, sag);
            if before.is_some_and(|b| b.at_end) {
                apply(track, &now, Verdict::Reassign, increment);
                continue;
            }
            // Otherwise follow the path from s0 to s1 in sub-steps.
            let mut crossed = None;
            let mut t = *track;
            for j in 1..=SUBSTEPS {
                let f = j as f64 / SUBSTEPS as f64;
                let s: Vec<[f64; 3]> = (s0.iter().zip(s1.iter()))
                    .map(|(a, b)| {
                        [
                            a[0] + f * (b[0] - a[0]),
                            a[1] + f * (b[1] - a[1]),
                            a[2] + f * (b[2] - a[2]),
                        ]
                    })
                    .collect();
                let p = pair.at(&s, self.chains);
                let resting = if f < 0.5 { &resting0 } else { &resting1 };
                let Some(at) = self.chains.place(&s, p, pair.body, &allowed, resting, sag) else {
                    continue;
                };
                match judge(&t, &at) {
                    Verdict::Flipped if !pair.kept_out(&s, self.chains, t.side, at.at) => {
                        apply(&mut t, &at, Verdict::Reassign, increment)
                    }
                    Verdict::Flipped => {
                        crossed = Some(at);
                        break;
                    }
                    v => apply(&mut t, &at, v, increment),
                }
            }
            match crossed {
                Some(at) => {
                    let (side, _) = track.side.unwrap_or((0.0, 0));
                    let element = self.chains.elements[pair.body][at.at];
                    let name = &self.topology.bodies[pair.body].name;
                    let what = match &pair.obstacle {
                        None => format!("node {}", pair.node),
                        Some(o) => format!("a feature of obstacle {o}"),
                    };
                    found.push(Finding {
                        increment,
                        node: pair.obstacle.is_none().then_some(pair.node),
                        body: Some(name.clone()),
                        what: format!(
                            "{what} went through {name} element {} with no contact on it: on its {} side since increment {}, {:.3e} m on the other side at increment {}",
                            at.at + 1,
                            side_name(side),
                            track.since,
                            now.gap.abs(),
                            increment,
                        ),
                        element: Some(element),
                    });
                    // Carry on from the side it is on, so that one crossing is told once.
                    apply(track, &now, Verdict::Reassign, increment);
                }
                None => apply(track, &now, Verdict::Reassign, increment),
            }
        }
        found
    }
}

impl Pair {
    /// Whether the point, on side `side` (with the place it was measured over) of its body,
    /// is kept out of the body's element at place `at` in state `s`: always, but for a point
    /// with a reach (a solid arc's centre), whose way to the element (against the element's
    /// chord normal on that side) must lie within its angles.
    fn kept_out(
        &self,
        s: &[[f64; 3]],
        chains: &Chains,
        side: Option<(f64, usize)>,
        at: usize,
    ) -> bool {
        let (Some([from, to]), Some((side, _))) = (self.reach, side) else {
            return true;
        };
        let chain = &chains.nodes[self.body];
        let (a, z) = (s[chain[at]], s[chain[at + 1]]);
        let u = [z[0] - a[0], z[1] - a[1]];
        within_angles([side * u[1], -side * u[0]], from, to)
    }

    /// Where the node or feature is in state `s`.
    fn at(&self, s: &[[f64; 3]], chains: &Chains) -> [f64; 2] {
        match self.point {
            Point::Node(k) => [s[k][0], s[k][1]],
            Point::Feature(p, pilot) => match pilot {
                None => p,
                Some(k) => {
                    let moved = [s[k][0] - chains.rest[k][0], s[k][1] - chains.rest[k][1]];
                    [p[0] + moved[0], p[1] + moved[1]]
                }
            },
        }
    }
}

/// A pair whose node rests on the body in contact `c` at `increment`: it keeps the side it
/// came from, and a side not yet known is the one the contact presses from. A contact that
/// presses from the other side of the same part of the body holds the node against the side it
/// never came from: the node is through the body, held at its surface (the finding returned).
/// The side goes along the body with the contact; on a distant part of the body (another layer
/// of a coil), the side the contact presses from is the one it has there. A contact from the
/// far side is told once.
fn resting(
    track: &mut Track,
    pair: &Pair,
    c: &ContactState,
    (chains, topology): (&Chains, &Topology),
    increment: usize,
) -> Option<Finding> {
    if c.force == 0.0 {
        return None;
    }
    let at = (chains.elements[pair.body].iter())
        .position(|&e| e == c.element)
        .unwrap_or(0);
    let pressing = contact_side(c.force);
    let Some((side, was)) = track.side else {
        track.side = Some((pressing, at));
        track.since = increment;
        return None;
    };
    let finding = (pressing != side && was.abs_diff(at) <= NEIGHBOURS).then(|| {
        let name = &topology.bodies[pair.body].name;
        Finding {
            increment,
            node: Some(pair.node),
            body: Some(name.clone()),
            what: format!(
                "node {} rests on {name} element {} from its {} side, but it came from its {} side (since increment {}): the contact holds it on the far side of the body",
                pair.node,
                at + 1,
                side_name(pressing),
                side_name(side),
                track.since,
            ),
            element: Some(c.element),
        }
    });
    if pressing != side {
        track.since = increment;
    }
    track.side = Some((pressing, at));
    finding
}

/// The convex features of the topology's obstacles, each paired with every body whose nodes
/// may touch the obstacle.
fn features(topology: &Topology, chains: &Chains) -> Vec<Pair> {
    let mut out = Vec::new();
    for (o, ob) in topology.obstacles.iter().enumerate() {
        let points = convex_features(&ob.shape);
        let pilot = ob.pilot.and_then(|p| chains.slot.get(&p).copied());
        let touching: Vec<usize> = (0..topology.bodies.len())
            .filter(|&b| {
                topology.bodies[b]
                    .nodes
                    .iter()
                    .any(|n| ob.nodes.contains(n))
            })
            .collect();
        let reach = feature_reach(&ob.shape);
        for &p in &points {
            for &body in &touching {
                out.push(Pair {
                    node: o as u32,
                    point: Point::Feature(p, pilot),
                    obstacle: Some(ob.name.clone()),
                    body,
                    declared: None,
                    window: None,
                    reach,
                });
            }
        }
    }
    out
}

/// The name of a side: left (+1) or right (-1) of the body's direction.
fn side_name(side: f64) -> &'static str {
    if side > 0.0 {
        "left"
    } else {
        "right"
    }
}

/// The side a contact presses from: its force Yc acts on the beam along the element's chord
/// normal, away from the node's side.
fn contact_side(force: f64) -> f64 {
    -force.signum()
}

/// What a pair's place at a state says of its side.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Verdict {
    /// Off the body's end: the side is open again.
    Open,
    /// Touching: the side is kept.
    Touching,
    /// Clear on the side it was on (or the first side seen), or over a distant part of the
    /// body: the side is set from here.
    Reassign,
    /// Clear on the other side of the part of the body its side was measured over.
    Flipped,
}

/// Whether the pair's node, over place `now.at` of its body at state `s`, lies within the
/// resolution of one of that element's nodes, and that node rests (a record of `contacts`)
/// on an element that ends at the pair's node, within the resolution of it: two layers
/// that lie on each other mesh node on mesh node touch vertex on vertex, where a side means
/// nothing (each vertex lies off the other's element by their separation times the kink, less
/// than the resolution).
fn vertex_on_vertex(
    (chains, topology, r): (&Chains, &Topology, f64),
    pair: &Pair,
    s: &[[f64; 3]],
    now: &Place,
    contacts: &[ContactState],
) -> bool {
    let Point::Node(slot) = pair.point else {
        return false;
    };
    let chain = &chains.nodes[pair.body];
    let (a, c) = (s[chain[now.at]], s[chain[now.at + 1]]);
    let (dx, dy) = (c[0] - a[0], c[1] - a[1]);
    if !now.beside || now.gap.abs() >= r * dx.hypot(dy) {
        return false;
    }
    // Within the resolution of an element's first node (Some(false)) or last (Some(true)).
    let at_end = |t: f64| match t {
        t if t.abs() < r => Some(false),
        t if (1.0 - t).abs() < r => Some(true),
        _ => None,
    };
    let t = ((s[slot][0] - a[0]) * dx + (s[slot][1] - a[1]) * dy) / (dx * dx + dy * dy);
    let Some(last) = at_end(t) else {
        return false;
    };
    let vertex = chain[now.at + usize::from(last)];
    contacts.iter().any(|k| {
        let Some(e) = topology.elements.get(k.element) else {
            return false;
        };
        let end = at_end(k.xi).map(|last| if last { e.j } else { e.i });
        chains.slot.get(&k.node) == Some(&vertex) && end == Some(pair.node)
    })
}

fn judge(track: &Track, at: &Place) -> Verdict {
    if !at.beside {
        return Verdict::Open;
    }
    if at.gap.abs() <= at.tol {
        return Verdict::Touching;
    }
    match track.side {
        Some((side, was)) if side * at.gap < 0.0 && was.abs_diff(at.at) <= NEIGHBOURS => {
            Verdict::Flipped
        }
        _ => Verdict::Reassign,
    }
}

fn apply(track: &mut Track, at: &Place, verdict: Verdict, increment: usize) {
    match verdict {
        Verdict::Open => track.side = None,
        Verdict::Touching => {}
        Verdict::Reassign | Verdict::Flipped => {
            let side = at.gap.signum();
            if track.side.is_none_or(|(s, _)| s != side) {
                track.since = increment;
            }
            track.side = Some((side, at.at));
        }
    }
}

/// Whether direction `dir` has a polar angle within [`from`, `to`] (rad, counter-clockwise
/// from `from`).
pub(super) fn within_angles(dir: [f64; 2], from: f64, to: f64) -> bool {
    let tau = std::f64::consts::TAU;
    (dir[1].atan2(dir[0]) - from).rem_euclid(tau) <= (to - from).rem_euclid(tau)
}
