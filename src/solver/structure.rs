//! The structure: the model as the solver prepares it once and then only reads (elements with
//! their initial geometry and stiffness, the dof map, the contact candidates, the scales the
//! tests are measured against), and what can be worked out from it and a displacement vector
//! alone: node positions, the external force at a load factor, the assembly context, dof names,
//! and the dofs of a mechanism.

use super::assembly::{
    assemble, current, AssemblyContext, DofKind, DofMap, ExternalForce, ObstacleLink, Ordering,
    PackedBeam,
};
use super::element::beam::BeamElement;
use super::element::friction::Grip;
use super::index_map::IndexMap;
use super::model::Model;
use super::params::SolverParams;
use super::report::{NodeState, SolveError};
use super::rigid_modes::FreePart;

/// Up to this many equations a singular structure gets every dof of its null space named (dense
/// symmetric eigen-decomposition); above, the first vanishing pivot of the band LU.
const DENSE_MECHANISM_CHECK: usize = 200;

/// The model prepared for the solver, fixed for a run (only `params` may be changed between
/// increments).
#[derive(Clone, Debug)]
pub struct Structure {
    /// The model being solved, its coordinates measured from `origin` (the scene's own, unless
    /// the scene lies far from the origin: see [`Model::recentred`]).
    pub model: Model,
    /// Parameters.
    pub params: SolverParams,
    /// The beam element evaluators (initial geometry, stiffness), one per beam.
    pub(crate) elements: Vec<BeamElement>,
    /// The beam elements packed for the assembly (`PackedBeam`).
    pub(crate) packed: Vec<PackedBeam>,
    /// The dof numbering.
    pub(crate) dofs: DofMap,
    /// The smallest reference force ([`SolverParams::force_floor`] times the largest EA).
    pub(crate) force_floor: f64,
    /// Contact candidate (node, body) pairs.
    pub(crate) candidates: Vec<(usize, usize)>,
    /// Distinct candidate nodes.
    pub(crate) candidate_nodes: usize,
    /// The largest clearance of a node (its radius and half its thickest element's
    /// thickness; `Node::clearance`): how far beyond their axes nodes may touch.
    pub(crate) max_clearance: f64,
    /// Whether any contact stands off the axes (a node's clearance, a section's thickness):
    /// without, every contact distance is 0 and the probes skip looking them up.
    pub(crate) stands_off: bool,
    /// The beam elements at each node.
    pub(crate) node_beams: Vec<Vec<usize>>,
    /// Where the model's coordinates are measured from ([`Model::recentred`]): positions handed
    /// out add it back.
    pub(crate) origin: [f64; 2],
    /// The round-off of a node position: 64 units of the largest initial coordinate.
    pub(crate) position_roundoff: f64,
    /// The larger side of the model's bounding box at rest.
    pub(crate) size: f64,
    /// For every self-contact candidate pair (node, own body), the positions in the body
    /// (first, last) of the elements it leaves out ([`Model::self_window`]).
    pub(crate) self_windows: IndexMap<(usize, usize), (usize, usize)>,
    /// The position of every element in its body.
    pub(crate) place: Vec<usize>,
    /// The (node, obstacle) pairs that may touch.
    pub(crate) obstacle_candidates: Vec<(usize, usize)>,
    /// The largest axial stiffness EA/l of the model's elements (N/m).
    pub(crate) axial_stiffness: f64,
    /// The penalty of the obstacle contacts (N/m): [`SolverParams::obstacle_penalty`] times
    /// `axial_stiffness`.
    pub(crate) obstacle_penalty: f64,
    /// The friction coefficient of every frictional candidate pair (node, body); empty where
    /// every contact is frictionless.
    pub(crate) friction: IndexMap<(usize, usize), f64>,
    /// For every beam, the length along its body (undeformed, from the body's first node) at
    /// its ends i and j: where a contact's stick point lies, whichever element it rests on.
    pub(crate) body_length_at: Vec<[f64; 2]>,
    /// The side (+1 left, -1 right) the scene declares for candidate pairs (node, body) that
    /// start touching ([`ContactPair::side`]).
    pub(crate) declared_sides: IndexMap<(usize, usize), f64>,
}

/// The friction coefficient of every candidate pair (node, body) of a frictional contact pair.
fn friction_pairs(model: &Model) -> IndexMap<(usize, usize), f64> {
    let mut out = IndexMap::default();
    for pair in model.contacts.iter().filter(|p| p.mu > 0.0) {
        for &n in &pair.nodes {
            for &b in &pair.bodies {
                out.insert((n, b), pair.mu);
            }
        }
    }
    out
}

/// For every beam, the undeformed length along its body at ends i and j, from the body's
/// first node: an element's entry end is the node it shares with the element before it (the
/// first element's is the end it does not share with the second).
fn body_length_at(model: &Model, elements: &[BeamElement]) -> Vec<[f64; 2]> {
    let mut out = vec![[0.0, 0.0]; model.beams.len()];
    for body in &model.bodies {
        let mut s = 0.0;
        let mut entry = None;
        for (k, &e) in body.elements.iter().enumerate() {
            let b = &model.beams[e];
            let from_i = match entry {
                Some(n) => n == b.i,
                None => body.elements.get(k + 1).is_none_or(|&f| {
                    let next = &model.beams[f];
                    b.j == next.i || b.j == next.j
                }),
            };
            let l = elements[e].length;
            out[e] = if from_i { [s, s + l] } else { [s + l, s] };
            entry = Some(if from_i { b.j } else { b.i });
            s += l;
        }
    }
    out
}

impl Structure {
    /// Prepare `model` (recentred where it lies far from the origin) for the solver.
    pub fn new(model: Model, params: SolverParams) -> Structure {
        let (model, origin) = model.recentred();
        let elements: Vec<BeamElement> = (model.beams.iter())
            .map(|b| {
                BeamElement::new(
                    model.position(b.i),
                    model.position(b.j),
                    b.section,
                    b.section.psi(model.formulation),
                )
            })
            .collect();
        let dofs = DofMap::new(&model);
        let packed = PackedBeam::all(&model, &dofs, &elements);
        let max_ea = model.beams.iter().map(|b| b.section.ea).fold(0.0, f64::max);
        let candidates = model.contact_candidates();
        let mut nodes: Vec<usize> = candidates.iter().map(|c| c.0).collect();
        nodes.sort_unstable();
        nodes.dedup();
        let (lo, hi) = model.bounds();
        let axial = (0..model.beams.len())
            .map(|e| model.beams[e].section.ea / model.beam_length(e))
            .fold(0.0, f64::max);
        let node_beams = model.node_beams();
        let mut self_windows = IndexMap::default();
        // Only a node on its own body has a window (a look at its own elements first, so that
        // the other pairs cost nothing).
        let on_own = |n: usize, b: usize| node_beams[n].iter().any(|&e| model.beams[e].body == b);
        for &(n, b) in candidates.iter().filter(|&&(n, b)| on_own(n, b)) {
            if let Some(w) = model.self_window(n, b) {
                self_windows.insert((n, b), w);
            }
        }
        let mut place = vec![0; model.beams.len()];
        for body in &model.bodies {
            for (k, &e) in body.elements.iter().enumerate() {
                place[e] = k;
            }
        }
        let declared_sides = (model.contacts.iter())
            .filter_map(|p| p.side.map(|s| (p, s)))
            .flat_map(|(p, s)| {
                (p.nodes.iter()).flat_map(move |&n| p.bodies.iter().map(move |&b| ((n, b), s)))
            })
            .collect();
        Structure {
            declared_sides,
            friction: friction_pairs(&model),
            body_length_at: body_length_at(&model, &elements),
            self_windows,
            place,
            obstacle_candidates: model.obstacle_candidates(),
            axial_stiffness: axial,
            obstacle_penalty: params.obstacle_penalty * axial,
            force_floor: params.force_floor * max_ea.max(f64::MIN_POSITIVE),
            candidates,
            candidate_nodes: nodes.len(),
            max_clearance: model.nodes.iter().map(|n| n.clearance).fold(0.0, f64::max),
            stands_off: model.nodes.iter().any(|n| n.clearance > 0.0)
                || model.beams.iter().any(|b| b.section.thickness > 0.0),
            node_beams,
            origin,
            size: (hi[0] - lo[0]).max(hi[1] - lo[1]).max(0.0),
            position_roundoff: 64.0
                * f64::EPSILON
                * (model.nodes.iter()).fold(0.0f64, |m, n| m.max(n.x.abs()).max(n.y.abs())),
            elements,
            packed,
            dofs,
            params,
            model,
        }
    }

    /// The gap below which a node touches an element of chord `length`: `fraction` of the
    /// length plus the round-off of the positions at the model's scale (64 units of the
    /// largest initial coordinate), so that a translated scene decides alike.
    pub(crate) fn touching(&self, fraction: f64, length: f64) -> f64 {
        fraction * length + self.position_roundoff
    }

    /// The window of element positions (first, last) that node `n` leaves out of its own body
    /// `b` ([`Model::self_window`]), for a self-contact pair; `None` for any other pair.
    #[inline]
    pub(crate) fn self_window_of(&self, n: usize, b: usize) -> Option<(usize, usize)> {
        if self.self_windows.is_empty() {
            return None;
        }
        self.self_windows.get(&(n, b)).copied()
    }

    /// Whether element `e` of body `b` lies outside node `n`'s own window on that body (every
    /// element does for a pair that is not self-contact).
    #[inline]
    pub(crate) fn outside_window(&self, n: usize, b: usize, e: usize) -> bool {
        (self.self_window_of(n, b)).is_none_or(|(lo, hi)| !(lo..=hi).contains(&self.place[e]))
    }

    /// The larger side of the model's bounding box at rest (m).
    pub fn model_size(&self) -> f64 {
        self.size
    }

    /// The largest gap (either way) of an accepted obstacle contact (m):
    /// [`SolverParams::obstacle_gap`] of the model's size, and the round-off of the positions.
    pub fn obstacle_tolerance(&self) -> f64 {
        self.params.obstacle_gap * self.size + self.position_roundoff
    }

    /// Position and rotation of every node at displacements `d`, in the scene's coordinates.
    pub fn node_states(&self, d: &[f64]) -> Vec<NodeState> {
        (0..self.model.nodes.len())
            .map(|n| {
                let (x, phi) = self.node_state_at(d, n);
                [x[0], x[1], phi]
            })
            .collect()
    }

    /// Position (in the scene's coordinates) and rotation of node `n` at displacements `d`.
    pub fn node_state_at(&self, d: &[f64], n: usize) -> ([f64; 2], f64) {
        let (x, phi) = current(&self.model, &self.dofs, d, n);
        ([x[0] + self.origin[0], x[1] + self.origin[1]], phi)
    }

    /// The element evaluators (initial geometry, stiffness), one per beam.
    pub fn elements(&self) -> &[BeamElement] {
        &self.elements
    }

    /// The dof numbering.
    pub fn dofs(&self) -> &DofMap {
        &self.dofs
    }

    /// The external force at the load factors `factors` (one per load group).
    pub fn external_force(&self, factors: &[f64]) -> ExternalForce {
        ExternalForce::of(&self.model, &self.dofs, factors)
    }

    /// The assembly's view of the structure under equation ordering `ord`, without loads.
    pub(crate) fn context<'a>(&'a self, ord: &'a Ordering) -> AssemblyContext<'a> {
        AssemblyContext {
            model: &self.model,
            elements: &self.elements,
            packed: &self.packed,
            dofs: &self.dofs,
            ordering: ord,
            contact: self.params.contact_options(usize::MAX),
            loads: &[],
            follower: None,
            obstacles: &[],
            obstacle_penalty: self.obstacle_penalty,
            grips: &[],
            residue: &[],
        }
    }

    /// "node N u" for a global dof.
    pub fn dof_label(&self, g: usize) -> String {
        let (n, o) = self.dofs.owner(g);
        self.model.dof_label(n, o)
    }

    /// "node N u" for an equation number of ordering `ord`.
    pub(crate) fn equation_label(&self, ord: &Ordering, eq: usize) -> String {
        match ord.dof_of.get(eq) {
            Some(&g) => self.dof_label(g as usize),
            None => format!("equation {eq}"),
        }
    }

    /// The largest |coordinate| of the nodes at displacements `d` (at least 1e-300).
    pub(crate) fn coordinate_scale(&self, d: &[f64]) -> f64 {
        // x and y: two independent chains of maxima.
        let (mut mx, mut my) = (1e-300f64, 1e-300f64);
        for (node, &f) in self.model.nodes.iter().zip(&self.dofs.first) {
            let (x, y) = ((node.x + d[f]).abs(), (node.y + d[f + 1]).abs());
            if x > mx {
                mx = x;
            }
            if y > my {
                my = y;
            }
        }
        mx.max(my)
    }

    /// The free dofs (global numbers) that have no stiffness at displacements `d` under
    /// equation ordering `ord` (with its contact links) with the obstacle contacts and the
    /// grips of the frictional contacts given (empty if the structure is stable), and whether
    /// they are all of them: small models get every dof of the null space; large ones the first
    /// failing pivot.
    pub fn mechanism_dofs(
        &self,
        ord: &Ordering,
        d: &[f64],
        (obstacles, grips): (&[ObstacleLink], &[Option<Grip>]),
    ) -> (Vec<usize>, bool) {
        if ord.n_eq == 0 {
            return (Vec::new(), true);
        }
        let ctx = AssemblyContext {
            obstacles,
            grips,
            ..self.context(ord)
        };
        let asm = assemble(&ctx, d, true, None);
        let k = asm.tangent.expect("tangent");
        let scale = k.max_diagonal().max(f64::MIN_POSITIVE);
        let global = |eq: usize| ord.dof_of[eq] as usize;
        // The band LU decides (O(n)); only a singular structure pays for the dense
        // eigen-decomposition that names every dof of the null space.
        let first = match k.clone().factor(1e-14 * scale) {
            Ok(()) => return (Vec::new(), true),
            Err(sp) => global(sp.equation),
        };
        if ord.n_eq > DENSE_MECHANISM_CHECK {
            return (vec![first], false);
        }
        let dense = nalgebra::DMatrix::from_fn(ord.n_eq, ord.n_eq, |i, j| k.get(i, j));
        let eig = nalgebra::SymmetricEigen::new(&dense + dense.transpose());
        let mut out = Vec::new();
        for (m, lam) in eig.eigenvalues.iter().enumerate() {
            if lam.abs() < 1e-13 * scale {
                for (e, c) in eig.eigenvectors.column(m).iter().enumerate() {
                    if c.abs() > 1e-3 && !out.contains(&global(e)) {
                        out.push(global(e));
                    }
                }
            }
        }
        if out.is_empty() {
            out.push(first);
        }
        (out, true)
    }

    /// The mechanism error for the free global dofs `free`: their labels, and the bodies (or
    /// lone nodes) they belong to.
    pub(crate) fn mechanism(&self, free: &[usize], complete: bool) -> SolveError {
        let nodes = free.iter().map(|&g| self.dofs.owner(g).0);
        SolveError::Mechanism {
            dofs: free.iter().map(|&g| self.dof_label(g)).collect(),
            complete,
            bodies: self.owners(nodes),
        }
    }

    /// The error for the parts of the structure that can move rigidly: their bodies, their free
    /// rigid motions and their held dofs.
    pub(crate) fn rigid_motion(&self, parts: &[FreePart]) -> SolveError {
        let nodes = || parts.iter().flat_map(|p| p.nodes.iter().copied());
        let held = nodes()
            .flat_map(|n| {
                let first = self.dofs.first[n];
                first..first + self.model.node_dofs(n)
            })
            .filter(|&g| self.dofs.kind[g] != DofKind::Free)
            .map(|g| self.dof_label(g))
            .collect();
        SolveError::RigidMotion {
            parts: self.owners(nodes()),
            motions: parts.iter().map(|p| p.modes).sum(),
            held,
        }
    }

    /// The bodies (`body "NAME"`) and lone nodes (`node N`) of `nodes`, each once, in order.
    fn owners(&self, nodes: impl Iterator<Item = usize>) -> Vec<String> {
        let mut out: Vec<String> = Vec::new();
        for n in nodes {
            let name = match self.node_beams[n].first() {
                Some(&e) => {
                    let body = &self.model.bodies[self.model.beams[e].body];
                    format!("body \"{}\"", body.name)
                }
                None => self.model.node_label(n),
            };
            if !out.contains(&name) {
                out.push(name);
            }
        }
        out
    }
}
