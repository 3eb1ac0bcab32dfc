//! The contact set: which nodes rest on which beam elements (`ActiveContact`), the side each
//! candidate node was last seen on relative to each candidate body, and what the assembly and
//! the records read of it. Probing a node against a body's deformed shape is `probe.rs`, sides
//! and crossings `sides.rs`, transfers and slide-off `transfer.rs`, activation and release at a
//! converged pass `active_set.rs`, the contacts with rigid obstacles `obstacles/`. The
//! contact stage reads the solver through a `ContactView`: the structure, and the last
//! converged displacements and contact set, nothing more.

use std::collections::HashMap;

use super::cycle::CycleGuard;
use crate::solver::assembly::{current, obstacle_gap, Assembled, ContactLink, ObstacleLink};
use crate::solver::element::beam::Chord;
use crate::solver::element::contact_law::surface_turn;
use crate::solver::element::rim::rim_point;
use crate::solver::index_map::IndexMap;
use crate::solver::model::Gap;
use crate::solver::model::Model;
use crate::solver::report::{ContactState, Friction};
use crate::solver::structure::Structure;

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
    /// Where a frictional contact sticks, at the last accepted state (`None`: frictionless).
    pub stick: Option<Stick>,
}

/// The stick point of a frictional contact and whether it slipped, at an accepted state.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Stick {
    /// The stick point: the length along the beam's body (undeformed, from its first node) of
    /// the material point the node is held to.
    pub at: f64,
    /// `Some(sigma)`: the contact slips, its body coordinate moving away from the stick point
    /// in direction sigma (+1 or -1); `None`: it sticks. At an accepted state, how it got
    /// there; within an attempt, the mode the passes try.
    pub slip: Option<f64>,
    /// The stiffest spring the Coulomb limit at the last accepted state resolves (N/m;
    /// infinite for a new contact): the stick spring is no stiffer.
    pub resolved: f64,
    /// The rim's roll at the stick point (m, `rim::friction::roll`) of a contact at a distance
    /// from the axes; 0 on the axis.
    pub roll: f64,
}

/// The contact set as its stages: node-on-beam contacts, contacts with rigid obstacles and the
/// friction modes of both, each with what it keeps through an attempt.
#[derive(Clone, Debug, Default)]
pub struct ContactSet {
    /// The node-on-beam contacts (`active_set.rs`, `sides.rs`, `transfer.rs`).
    pub beams: BeamContacts,
    /// The contacts with rigid obstacles (`obstacles/`).
    pub obstacles: ObstacleContacts,
    /// The friction modes' passes (`friction.rs`).
    pub(super) friction: FrictionModes,
}

/// The contact stage of nodes on beams: the active contacts and the remembered sides of every
/// candidate pair.
#[derive(Clone, Debug, Default)]
pub struct BeamContacts {
    /// Active contacts.
    pub active: Vec<ActiveContact>,
    /// Per (node, body): the side (+1/-1 along the chord normal) and the element it was
    /// measured against, at the last converged state.
    pub(super) sides: IndexMap<(usize, usize), (f64, usize)>,
    /// Set by `after_convergence` when a node was found deeper through a body than
    /// `max_penetration` element lengths: (node, body, depth / length). The increment is then
    /// cut back so that the touch is caught close to where it happens.
    pub(crate) too_deep: Option<(usize, usize, f64)>,
    /// The active sets met at the converged passes of the current attempt: once one comes
    /// back, each converged pass fixes one violation only (see `after_convergence`).
    pub(crate) guard: CycleGuard<Vec<(usize, usize)>>,
    /// A candidate pair whose node touches the body with its own beam's neighbouring nodes not
    /// all clear on one side of it, found by `remember_sides` (the first one): its side is
    /// ambiguous, and a scene that starts so is refused ([`SolveError::AmbiguousSide`]).
    pub(crate) ambiguous: Option<(usize, usize)>,
    /// The (node, body) pairs whose contact slid off a free end of the body in the current
    /// attempt: only such a node can have gone round that end (`ContactSet::crossing`).
    pub(super) slid_off: Vec<(usize, usize)>,
}

/// The contact stage of rigid obstacles: every candidate pair and what its passes keep
/// through an attempt.
#[derive(Clone, Debug, Default)]
pub struct ObstacleContacts {
    /// Every candidate (node, obstacle) pair of the structure, in its order, with its
    /// multiplier.
    pub links: Vec<ObstacleLink>,
    /// Whether each pair of `links` was in contact at the last accepted state.
    pub(crate) resting: Vec<bool>,
    /// The force each pair last let go with in the current attempt (by pair).
    pub(super) let_go: IndexMap<usize, f64>,
    /// The contacts met at the converged passes of the current attempt: once a set comes
    /// back, each pass makes one change.
    pub(crate) guard: CycleGuard<Vec<bool>>,
    /// Set by `obstacle_pass` when a node was found deeper inside an obstacle than
    /// `max_penetration` lengths of its elements: (node, obstacle, depth in m).
    pub(crate) too_deep: Option<(usize, usize, f64)>,
    /// Passes of the current attempt that updated multipliers.
    pub(crate) multiplier_updates: usize,
    /// The contact whose gap the last update found widest: (node, obstacle, gap in m).
    pub(crate) widest_gap: Option<(usize, usize, f64)>,
    /// The pairs (by index) that touched during the current attempt: their stick points are
    /// where they touched, not where the last accepted state had them.
    pub(crate) touched: Vec<usize>,
}

/// The friction stage: what the stick and slip passes keep through an attempt.
#[derive(Clone, Debug, Default)]
pub(crate) struct FrictionModes {
    /// The modes met at the converged passes of the current attempt: once a set comes back,
    /// each pass changes the mode of one contact.
    pub(super) guard: CycleGuard<Vec<i8>>,
    /// How often each frictional contact (node, body or obstacle, whether an obstacle) has
    /// turned its slip to the other direction within the attempt (`friction_pass`).
    pub(super) turned: HashMap<(usize, usize, bool), usize>,
}

/// Whether node `n` is a node of body `body`.
pub(super) fn on_body(cv: &ContactView<'_>, n: usize, body: usize) -> bool {
    cv.structure.node_beams[n]
        .iter()
        .any(|&e| cv.structure.model.beams[e].body == body)
}

impl ContactSet {
    /// The (node, body) pairs in contact, sorted.
    pub fn pairs(&self) -> Vec<(usize, usize)> {
        let mut set: Vec<(usize, usize)> =
            self.beams.active.iter().map(|a| (a.node, a.body)).collect();
        set.sort_unstable();
        set
    }

    /// The assembly's view of the active contacts in `model`.
    pub fn links(&self, model: &Model) -> Vec<ContactLink> {
        self.beams
            .active
            .iter()
            .map(|a| ContactLink {
                node: a.node,
                beam: a.beam,
                rim: a.side * model.contact_distance(a.node, a.beam),
            })
            .collect()
    }

    pub(crate) fn is_active(&self, node: usize, body: usize) -> bool {
        self.beams
            .active
            .iter()
            .any(|a| a.node == node && a.body == body)
    }

    /// Candidate (node, body) pairs of the cv's model (computed once).
    pub fn candidates<'a>(cv: &ContactView<'a>) -> &'a [(usize, usize)] {
        &cv.structure.candidates
    }

    /// Report states of the active contacts from a converged assembly.
    pub fn states(&self, cv: &ContactView<'_>, asm: &Assembled) -> Vec<ContactState> {
        let m = &cv.structure.model;
        let friction = |k: usize| asm.elements.contact_friction.get(k).copied().flatten();
        // The surface's turn from the chord at the contact point, from the state recorded.
        let turn = |a: &ActiveContact, xi: f64| {
            if !cv.structure.params.surface_normal {
                return 0.0;
            }
            let beam = &m.beams[a.beam];
            let (pi, fi) = current(m, &cv.structure.dofs, cv.d, beam.i);
            let (pj, fj) = current(m, &cv.structure.dofs, cv.d, beam.j);
            let ch = Chord::new(
                pi,
                pj,
                cv.structure.elements[a.beam].alpha0,
                0.5 * (fi + fj),
            );
            surface_turn(fi - ch.beta, fj - ch.beta, xi)
        };
        self.beams
            .active
            .iter()
            .zip(&asm.elements.contact_forces)
            .enumerate()
            .map(|(k, (a, &(yc, xi)))| ContactState {
                node: m.nodes[a.node].id,
                element: a.beam,
                place: (m.bodies[a.body].elements.iter())
                    .position(|&e| e == a.beam)
                    .map_or(0, |k| k + 1),
                body: m.bodies[a.body].name.clone(),
                xi,
                force: yc,
                pressure: -a.side * yc,
                tangential: friction(k).map_or(0.0, |t| t.tangential),
                turn: turn(a, xi),
                friction: match a.stick {
                    Some(Stick { slip: Some(_), .. }) => Friction::Slipping,
                    Some(_) => Friction::Sticking,
                    None => Friction::Frictionless,
                },
                stick: a.stick.map(|s| s.at),
                point: (m.contact_distance(a.node, a.beam) > 0.0).then(|| {
                    let p = pressed_point(cv, cv.d, a.node, a.beam, a.side);
                    [p[0] + cv.structure.origin[0], p[1] + cv.structure.origin[1]]
                }),
            })
            .collect()
    }
}

/// What the contact stage reads of the solver: the structure, and the last
/// converged displacements and contact set that every test of a pass is measured from.
#[derive(Clone, Copy)]
pub struct ContactView<'a> {
    /// The model prepared for assembly.
    pub structure: &'a Structure,
    /// Displacements at the last converged state.
    pub d: &'a [f64],
    /// Contact set at the last converged state.
    pub contacts: &'a ContactSet,
}

impl ContactView<'_> {
    /// The gap of node `n` to obstacle `o` at displacements `d` (`None`: out of its reach).
    pub(super) fn obstacle_gap(&self, d: &[f64], n: usize, o: usize) -> Option<Gap> {
        obstacle_gap(&self.structure.model, &self.structure.dofs, d, n, o)
    }
}

/// How far node `n` stands off the axis of beam `e` when it touches it
/// (`Model::contact_distance`; 0 at once in a model where nothing stands off).
#[inline]
pub(super) fn contact_reach(cv: &ContactView<'_>, n: usize, e: usize) -> f64 {
    if cv.structure.stands_off {
        cv.structure.model.contact_distance(n, e)
    } else {
        0.0
    }
}

/// Whether node `n`, on side `side` of beam `e` at displacements `d`, touches it within its
/// reach (`Node::reach`): the way from the node to the beam, against the beam's surface normal
/// where it presses (`rim_point`), lies within the node's angles (a solid arc's centre touches
/// only within the arc, its ends only beyond it); always for a node whose contacts hold in
/// every direction.
pub(super) fn within_reach(cv: &ContactView<'_>, d: &[f64], n: usize, e: usize, side: f64) -> bool {
    let Some(reach) = cv.structure.model.nodes[n].reach else {
        return true;
    };
    reach.holds(way_to(cv, d, n, e, side))
}

/// The way from node `n`, on side `side` of beam `e` at displacements `d`, to the beam: against
/// the beam's surface normal where the node presses on it (`rim_point`), a unit vector.
pub(super) fn way_to(cv: &ContactView<'_>, d: &[f64], n: usize, e: usize, side: f64) -> [f64; 2] {
    let m = &cv.structure.model;
    let c = current(m, &cv.structure.dofs, d, n).0;
    let (xi, pi) = current(m, &cv.structure.dofs, d, m.beams[e].i);
    let (xj, pj) = current(m, &cv.structure.dofs, d, m.beams[e].j);
    let r = contact_reach(cv, n, e);
    let (_, _, t) = rim_point(&cv.structure.elements[e], (xi, xj), [pi, pj], c, side * r);
    let a = (xj[1] - xi[1]).atan2(xj[0] - xi[0]) + t;
    [side * a.sin(), -side * a.cos()]
}

/// Where node `n`, on side `side` of beam `e` and touching it, presses on the beam's axis at
/// displacements `d`: the node itself, or for a node that stands off the axis
/// (`Model::contact_distance`), the point of the axis under it along the surface normal
/// (`rim_point`).
#[inline]
pub(super) fn pressed_point(
    cv: &ContactView<'_>,
    d: &[f64],
    n: usize,
    e: usize,
    side: f64,
) -> [f64; 2] {
    let m = &cv.structure.model;
    let c = current(m, &cv.structure.dofs, d, n).0;
    let r = contact_reach(cv, n, e);
    if r == 0.0 {
        return c;
    }
    let (xi, pi) = current(m, &cv.structure.dofs, d, m.beams[e].i);
    let (xj, pj) = current(m, &cv.structure.dofs, d, m.beams[e].j);
    rim_point(&cv.structure.elements[e], (xi, xj), [pi, pj], c, side * r).0
}
