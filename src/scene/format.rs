//! The scene file format (RON): what a user writes. Every field is documented in
//! `docs/scene-format.md`; `validate` turns a `SceneFile` into a solver `Model`.

use serde::{Deserialize, Serialize};

pub use super::shape::ShapeDef;
use super::units::Units;
use crate::solver::{Dof, Formulation, StretchCorrection};

/// A whole scene file.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SceneFile {
    /// Display name.
    pub name: String,
    /// Free text shown in the GUI and `solve` output.
    #[serde(default)]
    pub description: String,
    /// The units the scene's numbers are in (default `N_m`); the solver works in any
    /// consistent set, and every number shown or written is labelled with these.
    #[serde(default)]
    pub units: Units,
    /// Element formulation for every beam (default Timoshenko).
    #[serde(default)]
    pub formulation: Formulation,
    /// Named sections.
    pub sections: Vec<SectionDef>,
    /// Explicit nodes (pins, frame joints). Body nodes are generated.
    #[serde(default)]
    pub nodes: Vec<NodeDef>,
    /// Bodies: straight or polyline beams divided into elements.
    #[serde(default)]
    pub bodies: Vec<BodyDef>,
    /// Supported dofs.
    #[serde(default)]
    pub supports: Vec<SupportDef>,
    /// Reference nodal loads (multiplied by the load factor).
    #[serde(default)]
    pub loads: Vec<LoadDef>,
    /// Prescribed displacements.
    #[serde(default)]
    pub prescribed: Vec<PrescribedDef>,
    /// Loads distributed along bodies.
    #[serde(default)]
    pub distributed: Vec<DistributedDef>,
    /// Which nodes may touch which bodies.
    #[serde(default)]
    pub contacts: Vec<ContactDef>,
    /// Rigid obstacles the nodes may touch but not cross.
    #[serde(default)]
    pub obstacles: Vec<ObstacleDef>,
    /// Increment control.
    #[serde(default)]
    pub control: ControlDef,
    /// The load path, stage after stage (weight first, then a pull; a press, then a drag to and
    /// fro; loading, unloading, reversal). Without stages every step adds `load_per_step` to
    /// the one load factor and `per_step` to each prescribed dof.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub stages: Vec<StageDef>,
}

/// One stage of the load path: over its steps, what it names moves linearly from where the
/// previous stage left it to its target; every load group and prescribed dof it does not name
/// holds its value.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StageDef {
    /// Name shown on the timeline and in reports (default "stage N", from 1).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub name: Option<String>,
    /// Number of steps, at least one (with `values`, the number of values; may be left out).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub steps: Option<usize>,
    /// The load groups' factors.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub loads: Vec<GroupChangeDef>,
    /// The prescribed dofs' values.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub prescribed: Vec<DofChangeDef>,
}

/// A load group's factor over a stage: exactly one of `to`, `by` and `values`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GroupChangeDef {
    /// The group: a `group` of the loads, "loads" for the loads that name none, or
    /// "gravity" for the self-weight.
    pub group: String,
    /// The factor at the stage's end.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub to: Option<f64>,
    /// The change of the factor over the stage.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub by: Option<f64>,
    /// The factor at the end of each step, one per step (a drive kept as it was made).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub values: Option<Vec<f64>>,
}

/// A prescribed dof's value over a stage: exactly one of `to`, `by` and `values`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DofChangeDef {
    /// Node id.
    pub node: u32,
    /// Dof: U, V or Phi.
    pub dof: Dof,
    /// The value at the stage's end (m or rad).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub to: Option<f64>,
    /// The change over the stage.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub by: Option<f64>,
    /// The value at the end of each step, one per step (a drag kept as it was made).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub values: Option<Vec<f64>>,
}

/// A section and material.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SectionDef {
    /// Name referred to by bodies.
    pub name: String,
    /// Young's modulus E (N/m^2).
    #[serde(rename = "E")]
    pub e: f64,
    /// Area A (m^2).
    #[serde(rename = "A")]
    pub a: f64,
    /// Second moment of area I (m^4).
    #[serde(rename = "I")]
    pub i: f64,
    /// Shear modulus G (N/m^2); if absent, E / (2 (1 + nu)).
    #[serde(rename = "G", default)]
    pub g: Option<f64>,
    /// Poisson's ratio, used when G is absent (default 0.3).
    #[serde(default)]
    pub nu: Option<f64>,
    /// Shear area Ae (m^2); default A.
    #[serde(rename = "Ae", default)]
    pub ae: Option<f64>,
    /// Mass per volume (kg/m^3): with `control.gravity`, the bodies of this section carry
    /// their self-weight, density A g per length.
    #[serde(default)]
    pub density: Option<f64>,
    /// Depth across the plane of bending (m, default 0): the bodies of this section touch
    /// obstacles with their faces, half of it either side of the axis.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub thickness: Option<f64>,
}

/// An explicit node.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct NodeDef {
    /// Id, unique in the scene.
    pub id: u32,
    /// x (m).
    pub x: f64,
    /// y (m).
    pub y: f64,
    /// Whether the node has a rotation dof (default true; false for contact pins).
    #[serde(default = "yes")]
    pub rotation: bool,
    /// Radius (m, default 0): the node is a pin that touches obstacles with its rim.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub radius: Option<f64>,
}

fn yes() -> bool {
    true
}

/// A body: a polyline through `path`, each segment divided into `elements` equal elements.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BodyDef {
    /// Name.
    pub name: String,
    /// Section name.
    pub section: String,
    /// Corner points (m), at least two.
    pub path: Vec<(f64, f64)>,
    /// Elements per segment of the path.
    pub elements: usize,
    /// Id of the first generated node; the rest follow consecutively. A generated node whose id
    /// is an explicit node's id is that node (it must sit at the same place).
    pub first_node: u32,
}

/// A support.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SupportDef {
    /// Node id.
    pub node: u32,
    /// Fix u (default false).
    #[serde(default)]
    pub u: bool,
    /// Fix v (default false).
    #[serde(default)]
    pub v: bool,
    /// Fix phi (default false).
    #[serde(default)]
    pub phi: bool,
}

/// A reference nodal load.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LoadDef {
    /// Node id.
    pub node: u32,
    /// Force along x (N).
    #[serde(default)]
    pub fx: f64,
    /// Force along y (N).
    #[serde(default)]
    pub fy: f64,
    /// Moment (N m).
    #[serde(default)]
    pub m: f64,
    /// The load group whose factor scales it along the stages (default "loads").
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub group: Option<String>,
}

/// A load distributed along a body's elements, per unit of undeformed length, in fixed
/// directions.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DistributedDef {
    /// The body it acts on.
    pub body: String,
    /// The first and last element (from 1, in body order) it covers; default all of them.
    #[serde(default)]
    pub elements: Option<(usize, usize)>,
    /// Load per length (x, y) at the start of the first element (N/m).
    pub q: (f64, f64),
    /// Load per length at the end of the last element, for a load varying linearly along the
    /// range; default `q` (uniform).
    #[serde(default)]
    pub q_end: Option<(f64, f64)>,
    /// The load follows the deformation (a pressure): `q` and `q_end` are then per unit of
    /// current length, along each element's chord (from its start to its end) and across it
    /// (to the left). Default false: per undeformed length, in fixed x and y.
    #[serde(default)]
    pub follower: bool,
    /// The load group whose factor scales it along the stages (default "loads").
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub group: Option<String>,
}

/// A prescribed displacement.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PrescribedDef {
    /// Node id.
    pub node: u32,
    /// Dof: U, V or Phi.
    pub dof: Dof,
    /// Increment per step (m or rad) of a scene without stages; in a scene with stages, the
    /// largest step a drag of it takes in the app.
    pub per_step: f64,
}

/// Contact candidates: these nodes may touch these bodies.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ContactDef {
    /// Candidate node ids (explicit pins or body nodes).
    #[serde(default)]
    pub nodes: Vec<u32>,
    /// Every node of these bodies is a candidate too.
    #[serde(default)]
    pub node_bodies: Vec<String>,
    /// Bodies the candidates may touch.
    pub bodies: Vec<String>,
    /// Whether a candidate may touch its own body too (self-contact), away from its own and
    /// the two neighbouring elements on either side (default false).
    #[serde(default)]
    pub own: bool,
    /// Coulomb friction coefficient between the candidates and the bodies (default 0:
    /// frictionless).
    #[serde(default)]
    pub mu: f64,
    /// The side of each body the candidates are on where they start touching it (a beam laid
    /// on a beam): `Left` or `Right` of the body's direction, from the first point of its path
    /// to the last. Without it, a node that starts on a body's line takes the side its own
    /// beam's neighbouring nodes lie on, or a pin the side opposite to its motion.
    #[serde(default)]
    pub side: Option<SideDef>,
}

/// A side of a body, looking along it from the first point of its path to the last.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum SideDef {
    /// To the left (above a body drawn left to right).
    Left,
    /// To the right (below a body drawn left to right).
    Right,
}

/// A rigid obstacle: its curve, the nodes that may touch it, and the node that moves it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ObstacleDef {
    /// Name, unique among the obstacles.
    pub name: String,
    /// Its curve.
    pub shape: ShapeDef,
    /// Every node of these bodies may touch it.
    #[serde(default)]
    pub bodies: Vec<String>,
    /// These nodes may touch it too (ids).
    #[serde(default)]
    pub nodes: Vec<u32>,
    /// The node (id) whose displacement moves the obstacle, its u and v supported or
    /// prescribed; none: the obstacle is fixed.
    #[serde(default)]
    pub pilot: Option<u32>,
    /// Coulomb friction coefficient between it and the nodes (default 0: frictionless).
    #[serde(default)]
    pub mu: f64,
    /// What of its bodies it touches (default `Nodes`).
    #[serde(default, skip_serializing_if = "Touches::is_nodes")]
    pub touches: Touches,
}

/// What of a body an obstacle touches.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub enum Touches {
    /// The bodies' nodes, each pushed out along the obstacle's normal (any shape; a body may
    /// lie along it, as a strip wrapped round a drum).
    #[default]
    Nodes,
    /// Any point of the bodies' elements, at one place of each body: a solid circle (a
    /// roller, a peg) touching as a pin of its radius at its centre, or a polyline's convex
    /// corners, the contact element carrying the force where it touches the element's
    /// deformed shape.
    Elements,
}

impl Touches {
    /// Whether it is the default, `Nodes`.
    pub fn is_nodes(&self) -> bool {
        *self == Touches::Nodes
    }
}

/// Increment control.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct ControlDef {
    /// Number of steps a run makes (default 10).
    pub steps: usize,
    /// Load factor increment per step (default 0 if the scene has no loads, else 1/steps).
    pub load_per_step: Option<f64>,
    /// Newton tolerance on the relative residual (default 1e-8).
    pub tolerance: Option<f64>,
    /// Largest relative residual accepted where Newton stalls at the round-off floor
    /// (default 1e-5; such increments are marked `roundoff` in the history).
    pub roundoff_bound: Option<f64>,
    /// Largest displacement correction per Newton iteration (m), if any.
    pub max_step: Option<f64>,
    /// When Newton's updates take the chords' second-order gaps out: `Never`, `WhereNeeded`
    /// (the default), `AfterCutBack` or `Always`; `true` and `false` mean `Always` and `Never`.
    pub stretch_correction: StretchCorrection,
    /// Arc-length control (load-driven scenes): length of one increment along the equilibrium
    /// path as the root-mean-square change of the free dofs (m, rad). Each step is one arc; the load factor is solved for.
    pub arc_length: Option<f64>,
    /// Acceleration of gravity (x, y) (m/s^2): the self-weight of the sections with a
    /// `density`, scaled by the load factor like every load.
    pub gravity: Option<(f64, f64)>,
    /// The largest gap (either way) of a node resting on an obstacle, as a fraction of the
    /// model's size (default 1e-9).
    pub obstacle_gap: Option<f64>,
    /// The direction a frictionless node-to-beam contact pushes in: `Surface` (the default),
    /// normal to the beam's surface at the contact point, continuous from one element to the
    /// next; `Chord`, normal to the element's chord, as the paper's element.
    pub contact_normal: ContactNormal,
    /// Where every cut-back of a step has failed, the structure snaps: the drive held, it
    /// moves to the next stable state along a damped path (default true; false: the run stops
    /// there).
    pub snap: bool,
}

/// The direction of a frictionless node-to-beam contact force ([`ControlDef::contact_normal`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub enum ContactNormal {
    /// Normal to the beam's surface at the contact point: the element's end rotations
    /// interpolated along it.
    #[default]
    Surface,
    /// Normal to the element's chord (the paper's element): the direction turns abruptly where
    /// the contact passes a mesh node of a bent beam.
    Chord,
}

impl Default for ControlDef {
    fn default() -> Self {
        ControlDef {
            steps: 10,
            load_per_step: None,
            tolerance: None,
            roundoff_bound: None,
            contact_normal: ContactNormal::Surface,
            max_step: None,
            stretch_correction: StretchCorrection::WhereNeeded,
            arc_length: None,
            gravity: None,
            obstacle_gap: None,
            snap: true,
        }
    }
}
