//! The model's topology as a history carries it (`History::topology`): nodes at rest, elements
//! with their sections, bodies as ordered node chains, contact candidate pairs, obstacles with
//! their shape and pilot, loads and their groups, the held dofs and the stages of the load path. With it a history describes itself: an
//! independent checker (`tsm-contact check`) needs nothing else.

use serde::{Deserialize, Serialize};

use crate::solver::{Dof, Formulation, Model, Shape};

/// The version of the history format this program writes. Version 1 histories carry no
/// `format_version` and no topology; version 2 adds both.
pub const FORMAT_VERSION: u32 = 2;

/// The topology of the model a history was solved on.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Topology {
    /// Element formulation of every beam.
    pub formulation: Option<Formulation>,
    /// Every node at rest, in the order of `History::node_ids`.
    pub nodes: Vec<TopologyNode>,
    /// Every beam element, in index order (`ContactState::element` indexes it).
    pub elements: Vec<TopologyElement>,
    /// Every body: its name and its nodes in order along it.
    pub bodies: Vec<TopologyBody>,
    /// The contact candidate pairs: a node and a body it may touch.
    pub candidates: Vec<TopologyPair>,
    /// How many elements on either side of a node's own elements its self-contact leaves out.
    pub self_window: usize,
    /// The rigid obstacles.
    pub obstacles: Vec<TopologyObstacle>,
    /// Nodal loads at load factor 1.
    pub loads: Vec<TopologyLoad>,
    /// Distributed loads at load factor 1.
    pub distributed: Vec<TopologyDistributed>,
    /// The held dofs: supported or prescribed, (node id, "u" | "v" | "phi").
    pub held: Vec<(u32, String)>,
    /// The prescribed dofs, (node id, "u" | "v" | "phi"), in the order of
    /// `IncrementRecord::prescribed`; empty in a history written without them.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub prescribed: Vec<(u32, String)>,
    /// The names of the load groups, in the order of `IncrementRecord::load_factors`; empty
    /// where every load has the one load factor.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub load_groups: Vec<String>,
    /// The stages of the load path, in the order `IncrementRecord::stage` counts them.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub stages: Vec<TopologyStage>,
}

/// A stage of the load path.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct TopologyStage {
    /// Name.
    pub name: String,
    /// Number of steps.
    pub steps: usize,
}

/// Whether a load group index is the first (left out of the file).
fn first_group(g: &usize) -> bool {
    *g == 0
}

/// A node at rest.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct TopologyNode {
    /// User id.
    pub id: u32,
    /// Position at rest (m).
    pub x: f64,
    /// Position at rest (m).
    pub y: f64,
    /// How far the face it touches obstacles with stands from it (m): its radius plus half
    /// its thickest element's thickness.
    #[serde(default, skip_serializing_if = "is_zero")]
    pub clearance: f64,
    /// The pilot (id) whose u and v it moves with: a moving polyline's corner that touches
    /// elements.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub moves_with: Option<u32>,
    /// The polar angles (rad, counter-clockwise from the first to the second) of the
    /// directions from it to the points it touches beams at, where they are bounded: a solid
    /// arc's centre, which touches its bodies' elements only within the arc.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub reach: Option<[f64; 2]>,
    /// Whether it has a rotation (false for a 2-dof pin, which does not turn: what holds it
    /// holds the moment of a friction at its rim).
    #[serde(default = "turns", skip_serializing_if = "is_true")]
    pub rotation: bool,
}

/// A node's rotation where a file leaves it out: it has one.
fn turns() -> bool {
    true
}

/// Whether a flag is true (its default, left out of the file).
fn is_true(v: &bool) -> bool {
    *v
}

/// Whether a size is zero (left out of the file).
fn is_zero(v: &f64) -> bool {
    *v == 0.0
}

/// A beam element.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct TopologyElement {
    /// Index of its body in [`Topology::bodies`].
    pub body: usize,
    /// User id of its end node i.
    pub i: u32,
    /// User id of its end node j.
    pub j: u32,
    /// E A (N).
    pub ea: f64,
    /// E I (N m^2).
    pub ei: f64,
    /// G Ae (N).
    pub gae: f64,
    /// Depth of the section across the plane of bending (m; 0: a line).
    #[serde(default, skip_serializing_if = "is_zero")]
    pub thickness: f64,
}

/// A body: a chain of elements.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct TopologyBody {
    /// Name.
    pub name: String,
    /// Its elements (indices into [`Topology::elements`]) in order along it.
    pub elements: Vec<usize>,
    /// Its node ids in order along it (one more than the elements).
    pub nodes: Vec<u32>,
}

/// A contact candidate pair.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct TopologyPair {
    /// User id of the node.
    pub node: u32,
    /// Name of the body.
    pub body: String,
    /// Coulomb friction coefficient.
    pub mu: f64,
    /// The side (+1 left of the body's direction, -1 right) the scene declares for a node
    /// that starts touching the body.
    #[serde(default)]
    pub side: Option<f64>,
}

/// A rigid obstacle.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct TopologyObstacle {
    /// Name.
    pub name: String,
    /// Its curve at rest.
    pub shape: Shape,
    /// The node whose displacement moves it, if any.
    pub pilot: Option<u32>,
    /// The node ids that may touch it.
    pub nodes: Vec<u32>,
    /// Coulomb friction coefficient.
    pub mu: f64,
}

/// A nodal load at load factor 1.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct TopologyLoad {
    /// User id of the node.
    pub node: u32,
    /// (Fx, Fy, M) (N, N m).
    pub force: [f64; 3],
    /// Its load group (index into [`Topology::load_groups`]; 0 where there is one factor).
    #[serde(default, skip_serializing_if = "first_group")]
    pub group: usize,
}

/// A distributed load at load factor 1 on one element.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct TopologyDistributed {
    /// Element index.
    pub element: usize,
    /// Intensity at end i and end j (N/m): global (x, y) per length at rest, or, for a
    /// follower, (along, across) the current chord per current length.
    pub q: [[f64; 2]; 2],
    /// Whether it turns with the element.
    pub follower: bool,
    /// Its load group (index into [`Topology::load_groups`]; 0 where there is one factor).
    #[serde(default, skip_serializing_if = "first_group")]
    pub group: usize,
}

impl Topology {
    /// The topology of `model`.
    pub fn of(model: &Model) -> Topology {
        let id = |n: usize| model.nodes[n].id;
        let bodies = (model.bodies.iter())
            .map(|b| {
                let mut nodes: Vec<u32> = b
                    .elements
                    .first()
                    .map(|&e| id(model.beams[e].i))
                    .into_iter()
                    .collect();
                nodes.extend(b.elements.iter().map(|&e| id(model.beams[e].j)));
                TopologyBody {
                    name: b.name.clone(),
                    elements: b.elements.clone(),
                    nodes,
                }
            })
            .collect();
        let pair = |n: usize, b: usize| {
            (model.contacts.iter()).find(|p| p.nodes.contains(&n) && p.bodies.contains(&b))
        };
        let mut held: Vec<(u32, String)> = (model.supports.iter())
            .map(|s| (id(s.node), s.dof))
            .chain(model.prescribed.iter().map(|p| (id(p.node), p.dof)))
            .map(|(n, d): (u32, Dof)| (n, d.name().to_string()))
            .collect();
        held.sort();
        held.dedup();
        Topology {
            formulation: Some(model.formulation),
            nodes: (model.nodes.iter())
                .map(|n| TopologyNode {
                    id: n.id,
                    x: n.x,
                    y: n.y,
                    clearance: n.clearance,
                    moves_with: n.moves_with.map(id),
                    reach: n.reach.map(|r| [r.from, r.to]),
                    rotation: n.rotation,
                })
                .collect(),
            elements: (model.beams.iter())
                .map(|b| TopologyElement {
                    body: b.body,
                    i: id(b.i),
                    j: id(b.j),
                    ea: b.section.ea,
                    ei: b.section.ei,
                    gae: b.section.gae,
                    thickness: b.section.thickness,
                })
                .collect(),
            bodies,
            candidates: (model.contact_candidates().into_iter())
                .map(|(n, b)| TopologyPair {
                    node: id(n),
                    body: model.bodies[b].name.clone(),
                    mu: pair(n, b).map_or(0.0, |p| p.mu),
                    side: pair(n, b).and_then(|p| p.side),
                })
                .collect(),
            self_window: crate::solver::model::SELF_CONTACT_WINDOW,
            obstacles: (model.obstacles.iter())
                .map(|o| TopologyObstacle {
                    name: o.name.clone(),
                    shape: o.shape.clone(),
                    pilot: o.pilot.map(id),
                    nodes: o.nodes.iter().map(|&n| id(n)).collect(),
                    mu: o.mu,
                })
                .collect(),
            loads: (model.loads.iter())
                .map(|l| TopologyLoad {
                    node: id(l.node),
                    force: l.force,
                    group: l.group,
                })
                .collect(),
            distributed: (model.distributed.iter())
                .map(|d| TopologyDistributed {
                    element: d.beam,
                    q: d.q,
                    follower: d.follower,
                    group: d.group,
                })
                .collect(),
            held,
            prescribed: (model.prescribed.iter())
                .map(|p| (id(p.node), p.dof.name().to_string()))
                .collect(),
            load_groups: model.load_groups.clone(),
            stages: (model.path.iter().flat_map(|p| &p.stages))
                .map(|s| TopologyStage {
                    name: s.name.clone(),
                    steps: s.steps,
                })
                .collect(),
        }
    }
}
