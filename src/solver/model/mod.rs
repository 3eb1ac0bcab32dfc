//! The structural model: nodes, sections, beam elements, supports, loads, prescribed
//! displacements, contact candidates and rigid obstacles (their curves: `shape.rs`). Plain
//! data, validated by `scene` before it gets here.

use serde::{Deserialize, Serialize};

use super::load_path::LoadPath;

mod curves;
mod shape;

pub use curves::Gap;
pub use shape::Shape;

/// Which beam theory an element's force equation follows.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize, Default)]
pub enum Formulation {
    /// Shear-rigid beam (Psi = 0).
    BernoulliEuler,
    /// Shear-flexible beam, Psi = EI / (G Ae).
    #[default]
    Timoshenko,
}

/// A degree of freedom of a node.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize, Hash)]
pub enum Dof {
    /// Displacement along global x.
    U,
    /// Displacement along global y.
    V,
    /// Rotation (counter-clockwise positive).
    Phi,
}

impl Formulation {
    /// Both formulations, the scenes' default first.
    pub const ALL: [Formulation; 2] = [Formulation::Timoshenko, Formulation::BernoulliEuler];

    /// The name people read ("Bernoulli-Euler").
    pub fn name(self) -> &'static str {
        match self {
            Formulation::BernoulliEuler => "Bernoulli-Euler",
            Formulation::Timoshenko => "Timoshenko",
        }
    }
}

impl Dof {
    /// The three dofs of a node, in offset order.
    pub const ALL: [Dof; 3] = [Dof::U, Dof::V, Dof::Phi];

    /// Offset of this dof within its node (u = 0, v = 1, phi = 2).
    pub fn offset(self) -> usize {
        match self {
            Dof::U => 0,
            Dof::V => 1,
            Dof::Phi => 2,
        }
    }
    /// Short lower-case name used in messages.
    pub fn name(self) -> &'static str {
        match self {
            Dof::U => "u",
            Dof::V => "v",
            Dof::Phi => "phi",
        }
    }
}

/// A node in its initial position.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Node {
    /// The user's id (as written in the scene).
    pub id: u32,
    /// Initial x coordinate (m).
    pub x: f64,
    /// Initial y coordinate (m).
    pub y: f64,
    /// Whether the node carries a rotation dof (false for 2-dof contact pins).
    pub rotation: bool,
    /// Its radius plus half its thickest element's thickness: where it touches obstacles (m).
    #[serde(default)]
    pub clearance: f64,
    /// The pilot node (index) this node moves with: a convex corner of a moving polyline
    /// that touches elements. Its (u, v) are held as the pilot's are, by the same supports and
    /// prescribed values, so that it stays where the obstacle's corner is; the reactions at
    /// its dofs are the force on the obstacle there.
    #[serde(default)]
    pub moves_with: Option<usize>,
    /// The directions its contacts with beams hold in, where they are bounded: a solid arc's
    /// centre touches the elements of its bodies only where the way from it to the point
    /// touched lies within the arc's angles. `None`: every direction (a pin, a roller).
    #[serde(default)]
    pub reach: Option<Reach>,
}

/// The polar angles a node's contacts hold within: from `from` counter-clockwise to `to`
/// (rad), the angles of a solid arc about its centre.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Reach {
    /// The first angle (rad).
    pub from: f64,
    /// The last angle (rad), counter-clockwise from `from`.
    pub to: f64,
}

impl Reach {
    /// Whether the direction `dir` (from the node towards the point it touches) lies within.
    pub fn holds(&self, dir: [f64; 2]) -> bool {
        curves::angle_past(dir[1].atan2(dir[0]), self.from)
            <= curves::angle_past(self.to, self.from)
    }
}

/// Section and material of a beam, reduced to the stiffnesses the element force equation needs.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Section {
    /// Axial stiffness E A (N).
    pub ea: f64,
    /// Bending stiffness E I (N m^2).
    pub ei: f64,
    /// Shear stiffness G Ae (N).
    pub gae: f64,
    /// Depth of the section across the beam's plane of bending (m; 0: a line).
    #[serde(default)]
    pub thickness: f64,
}

impl Section {
    /// Shear flexibility parameter Psi = EI/(G Ae) (m^2) for the given formulation (0 for Bernoulli-Euler).
    pub fn psi(&self, formulation: Formulation) -> f64 {
        match formulation {
            Formulation::BernoulliEuler => 0.0,
            Formulation::Timoshenko => self.ei / self.gae,
        }
    }
}

/// A 2-node beam element between node indices `i` and `j` (indices into [`Model::nodes`]).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Beam {
    /// Index of the start node.
    pub i: usize,
    /// Index of the end node.
    pub j: usize,
    /// Section properties.
    pub section: Section,
    /// Index of the body this element belongs to.
    pub body: usize,
}

/// A named chain of beam elements (a cantilever, a frame member).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Body {
    /// Name used in messages and the GUI.
    pub name: String,
    /// Element indices along the body, in order.
    pub elements: Vec<usize>,
}

/// A dof held at zero.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Support {
    /// Node index.
    pub node: usize,
    /// Which dof.
    pub dof: Dof,
}

/// A reference nodal load; the applied load is the load factor times this.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Load {
    /// Node index.
    pub node: usize,
    /// Force along x (N), force along y (N), moment (N m).
    pub force: [f64; 3],
    /// The load group whose factor scales it (index into [`Model::load_groups`]; 0 where the
    /// model has one group).
    #[serde(default)]
    pub group: usize,
}

/// A load distributed along a beam element, varying linearly from end i to end j, scaled by
/// the load factor like the nodal loads. Either fixed: per unit of undeformed length in global
/// directions (self-weight is one: density A g); or a follower: per unit of current length,
/// along and across the current chord (a pressure), so that it turns and stretches with the
/// element.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct DistributedLoad {
    /// Beam element index.
    pub beam: usize,
    /// Load per length at end i and at end j: (x, y), or for a follower (along the chord i -> j,
    /// across it to the left).
    pub q: [[f64; 2]; 2],
    /// Whether it follows the element.
    #[serde(default)]
    pub follower: bool,
    /// The load group whose factor scales it (index into [`Model::load_groups`]).
    #[serde(default)]
    pub group: usize,
}

/// A prescribed ("compulsory") displacement of one dof.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Prescribed {
    /// Node index.
    pub node: usize,
    /// Which dof.
    pub dof: Dof,
    /// Change of the prescribed value per increment (m or rad).
    pub per_step: f64,
}

/// Which nodes may touch which bodies.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ContactPair {
    /// Candidate node indices.
    pub nodes: Vec<usize>,
    /// Body indices the nodes may touch.
    pub bodies: Vec<usize>,
    /// Whether a node may touch its own body too (self-contact), away from its own elements and
    /// the `SELF_CONTACT_WINDOW` elements on either side of them.
    #[serde(default)]
    pub own: bool,
    /// Coulomb friction coefficient mu of these contacts (0: frictionless).
    #[serde(default)]
    pub mu: f64,
    /// The side of the bodies the nodes are on where they start touching them: +1 to the
    /// left of each body's direction (the element normal turns its chord i -> j by +90
    /// degrees), -1 to the right; `None`: from the start geometry.
    #[serde(default)]
    pub side: Option<f64>,
}

/// The elements on either side of a node's own elements that its self-contact leaves out: a
/// node cannot press on the elements it bends with.
pub const SELF_CONTACT_WINDOW: usize = 2;

/// A rigid obstacle: a curve the candidate nodes may touch and slide along but not cross.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Obstacle {
    /// Name used in messages and the GUI.
    pub name: String,
    /// Its curve at rest.
    pub shape: Shape,
    /// The node whose displacement (u, v) moves the obstacle (its u and v are supported or
    /// prescribed), or `None`: the obstacle is fixed. The force on the obstacle is that node's
    /// reaction, and those of its corners' nodes where they touch elements
    /// ([`Node::moves_with`]).
    pub pilot: Option<usize>,
    /// The nodes that may touch it (node indices, ascending).
    pub nodes: Vec<usize>,
    /// Coulomb friction coefficient between it and the nodes (0: frictionless).
    #[serde(default)]
    pub mu: f64,
    /// Whether its convex features touch its bodies' elements as contact nodes of their own
    /// (a circle's centre, a polyline's corners: `touches: Elements` in a scene), so that the
    /// node-on-beam contacts, not the feature check, keep them out of the elements.
    #[serde(default)]
    pub touches_elements: bool,
}

/// The whole model as the solver sees it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Model {
    /// Nodes in index order.
    pub nodes: Vec<Node>,
    /// Beam elements.
    pub beams: Vec<Beam>,
    /// Bodies (chains of beams).
    pub bodies: Vec<Body>,
    /// Supported dofs.
    pub supports: Vec<Support>,
    /// Reference loads (multiplied by the load factor).
    pub loads: Vec<Load>,
    /// Distributed loads, sorted by element.
    #[serde(default)]
    pub distributed: Vec<DistributedLoad>,
    /// Prescribed displacements.
    pub prescribed: Vec<Prescribed>,
    /// Load factor increment per step.
    pub load_per_step: f64,
    /// Element formulation for every beam.
    pub formulation: Formulation,
    /// Contact candidate pairs.
    pub contacts: Vec<ContactPair>,
    /// Rigid obstacles.
    #[serde(default)]
    pub obstacles: Vec<Obstacle>,
    /// The names of the load groups, each scaled by its own factor along a load path; empty
    /// where every load has the one load factor (group 0).
    #[serde(default)]
    pub load_groups: Vec<String>,
    /// The stages a run goes through, if the scene has any: then each step lands where the
    /// path says, and `load_per_step` and the `per_step` of the prescribed dofs do not drive
    /// the run.
    #[serde(default)]
    pub path: Option<LoadPath>,
}

impl Model {
    /// Contact candidate (node, body) pairs (a node touches its own body only where its pair
    /// allows self-contact), in the order the scene lists them, each once.
    pub fn contact_candidates(&self) -> Vec<(usize, usize)> {
        let m = self;
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
                    let allowed = pair.own || (own[n] != b && !on_body);
                    if allowed && seen.insert((n, b)) {
                        out.push((n, b));
                    }
                }
            }
        }
        out
    }

    /// Whether any body may touch itself (a contact pair with `own`).
    pub fn has_self_contact(&self) -> bool {
        self.contacts.iter().any(|c| c.own)
    }

    /// For a node `n` of body `b`, the positions in the body (first, last) of the elements its
    /// self-contact leaves out: its own, and `SELF_CONTACT_WINDOW` on either side (`None` for a
    /// node not on the body).
    pub fn self_window(&self, n: usize, b: usize) -> Option<(usize, usize)> {
        let els = &self.bodies[b].elements;
        let at = |k: &usize| self.beams[els[*k]].i == n || self.beams[els[*k]].j == n;
        let places: Vec<usize> = (0..els.len()).filter(at).collect();
        let (lo, hi) = (*places.first()?, *places.last()?);
        Some((
            lo.saturating_sub(SELF_CONTACT_WINDOW),
            hi + SELF_CONTACT_WINDOW,
        ))
    }

    /// The beam elements at each node (indices into `beams`).
    pub fn node_beams(&self) -> Vec<Vec<usize>> {
        let mut out = vec![Vec::new(); self.nodes.len()];
        for (e, b) in self.beams.iter().enumerate() {
            out[b.i].push(e);
            out[b.j].push(e);
        }
        out
    }

    /// Number of dofs of node `n` (2 or 3).
    pub fn node_dofs(&self, n: usize) -> usize {
        2 + usize::from(self.nodes[n].rotation)
    }

    /// Initial position of node `n`.
    pub fn position(&self, n: usize) -> [f64; 2] {
        [self.nodes[n].x, self.nodes[n].y]
    }

    /// How far node `n` stands off the axis of beam `e` when it touches it (m): its radius
    /// and half its own beams' thickness (`Node::clearance`), plus half the thickness of `e`.
    /// 0 for a point pin on a line beam.
    pub fn contact_distance(&self, n: usize, e: usize) -> f64 {
        self.nodes[n].clearance + 0.5 * self.beams[e].section.thickness
    }

    /// The ids of node `n` and of the nodes that move with it (a moving polyline's corners,
    /// [`Node::moves_with`]), whose reactions together are the force that drives it.
    pub fn moving_with(&self, n: usize) -> Vec<u32> {
        (self.nodes.iter().enumerate())
            .filter(|(k, node)| *k == n || node.moves_with == Some(n))
            .map(|(_, node)| node.id)
            .collect()
    }

    /// Initial length of beam `e`.
    pub fn beam_length(&self, e: usize) -> f64 {
        let b = &self.beams[e];
        let (p, q) = (self.position(b.i), self.position(b.j));
        (q[0] - p[0]).hypot(q[1] - p[1])
    }

    /// The distributed loads on beam element `e` (`distributed` is sorted by element).
    pub fn distributed_on(&self, e: usize) -> &[DistributedLoad] {
        let from = self.distributed.partition_point(|d| d.beam < e);
        let to = self.distributed.partition_point(|d| d.beam <= e);
        &self.distributed[from..to]
    }

    /// Whether the model has distributed loads that follow the deformation.
    pub fn has_followers(&self) -> bool {
        self.distributed.iter().any(|d| d.follower)
    }

    /// The (node, obstacle) pairs that may touch, node by node within each obstacle.
    pub fn obstacle_candidates(&self) -> Vec<(usize, usize)> {
        (self.obstacles.iter().enumerate())
            .flat_map(|(o, ob)| ob.nodes.iter().map(move |&n| (n, o)))
            .collect()
    }

    /// The number of load factors a state carries: one per load group, at least one.
    pub fn group_count(&self) -> usize {
        self.load_groups.len().max(1)
    }

    /// Every group's factor equal to `lambda` (a run with one load factor).
    pub fn uniform_factors(&self, lambda: f64) -> Vec<f64> {
        vec![lambda; self.group_count()]
    }

    /// Whether the model has loads (nodal or distributed) for the load factor to scale.
    pub fn has_loads(&self) -> bool {
        !self.loads.is_empty() || !self.distributed.is_empty()
    }

    /// "bar element 3": beam element `e` named by its body and its place in the body, from 1
    /// (what every message and panel calls an element).
    pub fn element_label(&self, e: usize) -> String {
        let b = self.beams[e].body;
        format!("{} element {}", self.bodies[b].name, self.element_place(e))
    }

    /// The place of beam element `e` in its body, from 1 (the numbering of the scene, the app
    /// and the messages).
    pub fn element_place(&self, e: usize) -> usize {
        (self.bodies[self.beams[e].body].elements.iter())
            .position(|&x| x == e)
            .map_or(e, |k| k + 1)
    }

    /// "node N u": dof `offset` (0 u, 1 v, 2 phi) of node `n`, by the node's user id.
    pub fn dof_label(&self, n: usize, offset: usize) -> String {
        format!("node {} {}", self.nodes[n].id, Dof::ALL[offset].name())
    }

    /// Describe node `n` by its user id, for messages.
    pub fn node_label(&self, n: usize) -> String {
        format!("node {}", self.nodes[n].id)
    }

    /// The corners (lower left, upper right) of the bounding box of the nodes at rest.
    pub fn bounds(&self) -> ([f64; 2], [f64; 2]) {
        let (mut lo, mut hi) = ([f64::MAX; 2], [f64::MIN; 2]);
        for n in &self.nodes {
            lo = [lo[0].min(n.x), lo[1].min(n.y)];
            hi = [hi[0].max(n.x), hi[1].max(n.y)];
        }
        (lo, hi)
    }

    /// The model with its coordinates measured from the centre of its bounding box, and that
    /// centre, where the model lies further from the origin than its own size (else unchanged, with
    /// origin 0). Far from the origin, positions carry the round-off of their large coordinates
    /// into every chord and gap (a scene translated by 1e8 m would lose its contacts); measured
    /// from the centre, the solver sees the translated scene as the untranslated one, up to the
    /// rounding of the input.
    pub fn recentred(mut self) -> (Model, [f64; 2]) {
        let (lo, hi) = self.bounds();
        let centre = [0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1])];
        let size = (hi[0] - lo[0]).max(hi[1] - lo[1]);
        if !(centre[0].hypot(centre[1]) > size && size.is_finite()) {
            return (self, [0.0, 0.0]);
        }
        for n in &mut self.nodes {
            n.x -= centre[0];
            n.y -= centre[1];
        }
        for o in &mut self.obstacles {
            o.shape = o.shape.translated([-centre[0], -centre[1]]);
        }
        (self, centre)
    }
}
