//! Increment control: the `Solver` that owns the converged state, advances the prescribed
//! displacements and the load factor, halves the increment on failure (reported as events),
//! and turns converged attempts into increment records.

use std::sync::Arc;
use std::time::Instant;

use super::acceptance::{CrossingCheck, IncrementStatus, NodeState};
use super::arc_length::ArcState;
use super::assembly::{
    assemble, current, Assembled, AssemblyContext, DofMap, Ordering, PackedBeam,
};
use super::beam::BeamElement;
use super::contact::ContactSet;
use super::model::Model;
use super::newton::{AttemptError, Converged};
use super::params::{SolverParams, StretchCorrection};
use super::report::{Event, Flow, IncrementRecord, Observer, Reaction, SolveError};

/// Up to this many equations a singular structure gets every dof of its null space named (dense
/// symmetric eigen-decomposition); above, the first vanishing pivot of the band LU.
const DENSE_MECHANISM_CHECK: usize = 200;

/// A contact within this fraction of its element from a free end slides off it when the
/// increment finds no equilibrium after every cut-back (`Solver::advance_to`).
const TIP_SLIDE_OFF: f64 = 1e-2;

/// A sub-increment that converged in at most this many iterations lets the next one double.
const GROW_ITERATIONS: usize = 6;

/// The assembly at the last converged state, kept for the next increment's predictor, which
/// starts from that very state: for a structure without contact elements and with no prescribed
/// increment, it would assemble the same internal forces and tangent again. Taken (not copied)
/// by the first attempt that uses it.
#[derive(Clone, Default)]
pub(crate) struct ConvergedAssembly(pub(crate) std::cell::RefCell<Option<(usize, Assembled)>>);

impl ConvergedAssembly {
    /// Keep `asm`, assembled at the state converged in `increment`.
    pub(crate) fn keep(&self, increment: usize, asm: Assembled) {
        *self.0.borrow_mut() = Some((increment, asm));
    }

    /// The assembly kept at `increment`, if there is one with a tangent (it is handed over).
    pub(crate) fn take(&self, increment: usize) -> Option<Assembled> {
        match self.0.borrow_mut().take() {
            Some((i, asm)) if i == increment && asm.tangent.is_some() => Some(asm),
            _ => None,
        }
    }
}

/// Buffers an attempt takes over from the one before, so that the increments of a large model
/// allocate no fresh memory (each fresh page costs a page fault, some microseconds on this kind
/// of machine): a displacement vector no longer in use and the right-hand side.
#[derive(Clone, Debug, Default)]
pub(crate) struct Spare {
    /// The displacements before the last commit (any contents: they are overwritten).
    pub(crate) d: Vec<f64>,
    /// The right-hand side of the last attempt (any contents).
    pub(crate) rhs: Vec<f64>,
}

impl std::fmt::Debug for ConvergedAssembly {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let kept = self.0.borrow().as_ref().map(|(i, _)| *i);
        f.debug_tuple("ConvergedAssembly").field(&kept).finish()
    }
}

/// The TSM solver for one model: converged state plus everything needed to advance it.
#[derive(Clone, Debug)]
pub struct Solver {
    /// The model being solved, its coordinates measured from `origin` (the scene's own, unless
    /// the scene lies far from the origin: see `Model::recentred`).
    pub model: Model,
    /// Parameters.
    pub params: SolverParams,
    pub(crate) elements: Vec<BeamElement>,
    /// The beam elements packed for the assembly (`PackedBeam`).
    pub(crate) packed: Vec<PackedBeam>,
    pub(crate) dofs: DofMap,
    pub(crate) d: Vec<f64>,
    pub(crate) prescribed: Vec<f64>,
    pub(crate) load_factor: f64,
    pub(crate) contacts: ContactSet,
    pub(crate) force_floor: f64,
    ordering_cache: std::cell::RefCell<Option<Arc<Ordering>>>,
    /// The assembly (internal forces and unfactored tangent) at the last converged state.
    pub(crate) converged_assembly: ConvergedAssembly,
    /// Buffers for the next attempt.
    pub(crate) spare: std::cell::RefCell<Spare>,
    increment: usize,
    pub(crate) arc: ArcState,
    /// Contact candidate (node, body) pairs.
    pub(crate) candidates: Vec<(usize, usize)>,
    /// Distinct candidate nodes.
    pub(crate) candidate_nodes: usize,
    /// The beam elements at each node.
    pub(crate) node_beams: Vec<Vec<usize>>,
    /// Whether the run has cut an increment back (`StretchCorrection::AfterCutBack`).
    cut_back: bool,
    /// Where the model's coordinates are measured from (`Model::recentred`): positions handed out
    /// (`node_state`, `node_states`, the records) add it back.
    origin: [f64; 2],
    /// The acceptance check's geometric test, at the last accepted state.
    pub(crate) crossing: CrossingCheck,
    /// The round-off of a node position: 64 units of the largest initial coordinate.
    position_roundoff: f64,
    /// The larger side of the model's bounding box at rest.
    size: f64,
}

impl Solver {
    /// Set up a solver at the undeformed state; fails if the structure is a mechanism.
    pub fn new(model: Model, params: SolverParams) -> Result<Solver, SolveError> {
        let (model, origin) = model.recentred();
        let elements: Vec<BeamElement> = model
            .beams
            .iter()
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
        let mut solver = Solver {
            d: vec![0.0; dofs.len()],
            prescribed: vec![0.0; model.prescribed.len()],
            load_factor: 0.0,
            contacts: ContactSet::default(),
            force_floor: params.force_floor * max_ea.max(f64::MIN_POSITIVE),
            ordering_cache: std::cell::RefCell::new(None),
            converged_assembly: ConvergedAssembly::default(),
            spare: Default::default(),
            increment: 0,
            arc: ArcState::default(),
            candidates: ContactSet::candidates_of(&model),
            candidate_nodes: 0,
            node_beams: model.node_beams(),
            cut_back: false,
            origin,
            crossing: CrossingCheck::default(),
            size: {
                let (lo, hi) = model.bounds();
                (hi[0] - lo[0]).max(hi[1] - lo[1]).max(0.0)
            },
            position_roundoff: 64.0
                * f64::EPSILON
                * (model.nodes.iter()).fold(0.0f64, |m, n| m.max(n.x.abs()).max(n.y.abs())),
            elements,
            packed,
            dofs,
            params,
            model,
        };
        let mut nodes: Vec<usize> = solver.candidates.iter().map(|c| c.0).collect();
        nodes.sort_unstable();
        nodes.dedup();
        solver.candidate_nodes = nodes.len();
        let free = solver.mechanism_dofs();
        if !free.is_empty() {
            return Err(SolveError::Mechanism { dofs: free });
        }
        let mut contacts = std::mem::take(&mut solver.contacts);
        contacts.remember_sides(&solver, &solver.d);
        if let Some((n, b)) = contacts.ambiguous {
            return Err(SolveError::AmbiguousSide {
                node: solver.model.nodes[n].id,
                body: solver.model.bodies[b].name.clone(),
            });
        }
        solver.contacts = contacts;
        if !solver.candidates.is_empty() {
            let start = solver.node_states(&solver.d);
            solver.crossing = CrossingCheck::new(&solver.model, solver.candidates.clone(), start);
        }
        Ok(solver)
    }

    /// The gap below which a node touches an element of chord `length`: `fraction` of the
    /// length plus the round-off of the positions at the model's scale (64 units of the
    /// largest initial coordinate), so that a translated scene decides alike.
    pub(crate) fn touching(&self, fraction: f64, length: f64) -> f64 {
        fraction * length + self.position_roundoff
    }

    /// The larger side of the model's bounding box at rest (m).
    pub fn model_size(&self) -> f64 {
        self.size
    }

    /// Position and rotation of every node at displacements `d`.
    pub fn node_states(&self, d: &[f64]) -> Vec<NodeState> {
        (0..self.model.nodes.len())
            .map(|n| {
                let (x, phi) = current(&self.model, &self.dofs, d, n);
                [x[0] + self.origin[0], x[1] + self.origin[1], phi]
            })
            .collect()
    }

    /// The free dofs that have no stiffness in the undeformed state (empty if the structure is
    /// stable). Small models get every dof of the null space; large ones the first failing pivot.
    pub fn mechanism_dofs(&self) -> Vec<String> {
        let ord = self.ordering_for(&self.contacts);
        if ord.n_eq == 0 {
            return Vec::new();
        }
        let ctx = self.context(&ord);
        let asm = assemble(&ctx, &self.d, true, None);
        let k = asm.tangent.expect("tangent");
        let scale = k.max_diagonal().max(f64::MIN_POSITIVE);
        // The band LU decides (O(n)); only a singular structure pays for the dense
        // eigen-decomposition that names every dof of the null space.
        let first = match k.clone().factor(1e-14 * scale) {
            Ok(()) => return Vec::new(),
            Err(sp) => self.equation_label(&ord, sp.equation),
        };
        if ord.n_eq > DENSE_MECHANISM_CHECK {
            return vec![first];
        }
        let dense = nalgebra::DMatrix::from_fn(ord.n_eq, ord.n_eq, |i, j| k.get(i, j));
        let eig = nalgebra::SymmetricEigen::new(&dense + dense.transpose());
        let mut out = Vec::new();
        for (m, lam) in eig.eigenvalues.iter().enumerate() {
            if lam.abs() < 1e-13 * scale {
                for (e, c) in eig.eigenvectors.column(m).iter().enumerate() {
                    let label = self.equation_label(&ord, e);
                    if c.abs() > 1e-3 && !out.contains(&label) {
                        out.push(label);
                    }
                }
            }
        }
        if out.is_empty() {
            out.push(first);
        }
        out
    }

    pub(crate) fn context<'a>(&'a self, ord: &'a Ordering) -> AssemblyContext<'a> {
        AssemblyContext {
            model: &self.model,
            elements: &self.elements,
            packed: &self.packed,
            dofs: &self.dofs,
            ordering: ord,
            contact: self.params.contact_options(usize::MAX),
            loads: &[],
        }
    }

    /// The equation ordering for a contact topology; the last one built is kept, since the
    /// topology rarely changes between iterations and increments. Shared, so handing it out copies
    /// nothing.
    pub(crate) fn ordering_for(&self, contacts: &ContactSet) -> Arc<Ordering> {
        let links = contacts.links();
        let mut cache = self.ordering_cache.borrow_mut();
        match cache.as_ref() {
            Some(o) if o.links == links => o.clone(),
            _ => {
                let o = Arc::new(Ordering::new(&self.model, &self.dofs, &links));
                *cache = Some(o.clone());
                o
            }
        }
    }

    /// "node N u" for a global dof.
    pub fn dof_label(&self, g: usize) -> String {
        let (n, o) = self.dofs.owner(g);
        format!("node {} {}", self.model.nodes[n].id, ["u", "v", "phi"][o])
    }

    /// Unbalanced force `lambda F - sum J S` over the free dofs and the dense tangent over the
    /// same dofs, at displacements `d` with the current contacts and load factor. Returns the
    /// free global dofs too, in the order of the vector and matrix. For checks and tests.
    pub fn unbalanced_force_and_tangent(
        &self,
        d: &[f64],
    ) -> (Vec<f64>, nalgebra::DMatrix<f64>, Vec<usize>) {
        let ord = self.ordering_for(&self.contacts);
        let ctx = self.context(&ord);
        let asm = assemble(&ctx, d, true, None);
        let fext = self.external_force(self.load_factor);
        let free: Vec<usize> = ord.dof_of.iter().map(|&g| g as usize).collect();
        // Assembled with no loads: the unbalanced force is -sum J S.
        let r = free
            .iter()
            .zip(&asm.unbalanced)
            .map(|(&g, u)| fext.at(g) + u)
            .collect();
        let k = asm.tangent.expect("tangent");
        let dense = nalgebra::DMatrix::from_fn(ord.n_eq, ord.n_eq, |i, j| k.get(i, j));
        (r, dense, free)
    }

    /// Number of converged increments so far.
    pub fn increment(&self) -> usize {
        self.increment
    }

    /// Current values of the prescribed displacements.
    pub fn prescribed_values(&self) -> &[f64] {
        &self.prescribed
    }

    /// Current load factor.
    pub fn load_factor(&self) -> f64 {
        self.load_factor
    }

    /// Converged displacements over all dofs.
    pub fn displacements(&self) -> &[f64] {
        &self.d
    }

    /// The active contacts.
    pub fn contacts(&self) -> &ContactSet {
        &self.contacts
    }

    /// Current position and rotation of node `n`.
    pub fn node_state(&self, n: usize) -> ([f64; 2], f64) {
        let (x, phi) = current(&self.model, &self.dofs, &self.d, n);
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

    /// Advance by one scene step (prescribed values += per_step, load factor += load_per_step),
    /// or by one arc length if `params.arc_length` is set.
    pub fn step(&mut self, obs: &mut dyn Observer) -> Result<Vec<IncrementRecord>, SolveError> {
        if self.params.arc_length.is_some() {
            return self.arc_length_step(obs);
        }
        let targets: Vec<f64> = self
            .model
            .prescribed
            .iter()
            .zip(&self.prescribed)
            .map(|(p, v)| v + p.per_step)
            .collect();
        let lambda = self.load_factor + self.model.load_per_step;
        self.advance_to(&targets, lambda, obs)
    }

    /// Advance from the converged state to the given prescribed values and load factor, halving
    /// the increment on failure (at most `max_cutbacks` times in all). Returns the converged
    /// increments (more than one if the step was cut back).
    pub fn advance_to(
        &mut self,
        targets: &[f64],
        lambda: f64,
        obs: &mut dyn Observer,
    ) -> Result<Vec<IncrementRecord>, SolveError> {
        let start_p = self.prescribed.clone();
        let start_l = self.load_factor;
        let mut done = 0.0f64;
        let mut h = 1.0f64;
        let mut cutbacks = 0;
        let mut out = Vec::new();
        let mut clock = Instant::now();
        // Set for the attempt that first slides contacts off the tips they are about to leave.
        let mut slide_off = None;
        while done < 1.0 {
            let next = (done + h).min(1.0);
            // The last sub-increment lands exactly on the targets.
            let tp: Vec<f64> = if next >= 1.0 {
                targets.to_vec()
            } else {
                start_p
                    .iter()
                    .zip(targets)
                    .map(|(a, b)| a + next * (b - a))
                    .collect()
            };
            let tl = if next >= 1.0 {
                lambda
            } else {
                start_l + next * (lambda - start_l)
            };
            let number = self.increment + 1;
            let accepted = self
                .attempt(&tp, tl, number, slide_off, obs)
                .and_then(|conv| {
                    let checked = self.acceptance(&conv)?;
                    Ok((conv, checked))
                });
            match accepted {
                Ok((conv, checked)) => {
                    slide_off = None;
                    // After a cut-back the sub-increment grows again (doubles) once Newton has
                    // it easy, so one hard moment does not leave the rest of the step in
                    // tiny pieces.
                    if conv.iterations <= GROW_ITERATIONS && h < 1.0 {
                        h *= 2.0;
                    }
                    let secs = clock.elapsed().as_secs_f64();
                    let rec = self.commit(conv, checked, tp, tl, cutbacks, secs);
                    clock = Instant::now();
                    done = next;
                    for e in &rec.events {
                        obs.event(e);
                    }
                    let flow = obs.increment(&rec);
                    out.push(rec);
                    if flow == Flow::Stop {
                        return Ok(out);
                    }
                }
                Err(AttemptError::Stopped) => return Err(SolveError::Stopped),
                Err(e) => {
                    // Halved at most `max_cutbacks` times below the full step. Before giving
                    // up, one attempt with the contacts near a free tip slid off it: past the
                    // limit point where a tip slips under a node there is no equilibrium with
                    // the contact on the tip.
                    if h <= 0.5f64.powi(self.params.max_cutbacks as i32) {
                        if slide_off.is_none() && self.has_contact_near_a_tip(number) {
                            slide_off = Some(TIP_SLIDE_OFF);
                            continue;
                        }
                        return Err(self.give_up(number, cutbacks, e));
                    }
                    let reason = self.failure_reason(&e);
                    cutbacks += 1;
                    h *= 0.5;
                    obs.event(&Event::CutBack {
                        increment: number,
                        reason,
                        fraction: h,
                    });
                    if !std::mem::replace(&mut self.cut_back, true)
                        && self.params.stretch_correction == StretchCorrection::AfterCutBack
                    {
                        obs.event(&Event::StretchCorrectionOn { increment: number });
                    }
                }
            }
        }
        Ok(out)
    }

    /// Whether a contact of the converged state lies within `TIP_SLIDE_OFF` of a free end.
    fn has_contact_near_a_tip(&self, increment: usize) -> bool {
        let mut contacts = self.contacts.clone();
        contacts.slide_off_tips(self, &self.d, TIP_SLIDE_OFF, increment, &mut Vec::new()) > 0
    }

    /// Whether this attempt's Newton updates take the chords' stretch out
    /// (`SolverParams::stretch_correction`).
    pub fn stretch_correcting(&self) -> bool {
        match self.params.stretch_correction {
            StretchCorrection::Never => false,
            StretchCorrection::AfterCutBack => self.cut_back,
            StretchCorrection::Always => true,
        }
    }

    /// Make an accepted attempt (`acceptance` gave `checked`) the converged state, and its
    /// record.
    pub(crate) fn commit(
        &mut self,
        c: Converged,
        checked: (IncrementStatus, Vec<NodeState>),
        tp: Vec<f64>,
        tl: f64,
        cutbacks: usize,
        seconds: f64,
    ) -> IncrementRecord {
        self.increment += 1;
        self.spare.get_mut().d = std::mem::replace(&mut self.d, c.d);
        self.contacts = c.contacts;
        self.prescribed = tp;
        self.load_factor = tl;
        let max_penetration = c.max_penetration;
        let mut contacts = std::mem::take(&mut self.contacts);
        contacts.remember_sides(self, &self.d);
        self.contacts = contacts;
        let (status, nodes) = checked;
        if !self.crossing.is_empty() {
            let active = self.contacts.pairs();
            self.crossing.accept(&self.model, nodes.clone(), &active);
        }
        let fext = self.external_force(tl);
        let reactions = self
            .dofs
            .held
            .iter()
            .zip(&c.assembled.held_internal)
            .map(|(&g, i)| {
                let (n, o) = self.dofs.owner(g);
                Reaction {
                    node: self.model.nodes[n].id,
                    dof: ["u", "v", "phi"][o].to_string(),
                    value: i - fext.at(g),
                }
            })
            .collect();
        let contacts = self.contacts.states(self, &c.assembled);
        let Assembled {
            unbalanced,
            unbalanced_norm2,
            unloaded,
            held_internal,
            tangent,
            elements,
            ..
        } = c.assembled;
        self.converged_assembly.keep(
            self.increment,
            Assembled {
                unbalanced,
                unbalanced_norm2,
                unloaded,
                held_internal,
                tangent,
                coupling: Vec::new(),
                elements: Default::default(),
            },
        );
        IncrementRecord {
            increment: self.increment,
            prescribed: self.prescribed.clone(),
            load_factor: tl,
            iterations: c.iterations,
            iterations_8_orders: c.iterations_8_orders,
            relative_residual: c.relative_residual,
            reference: c.reference,
            roundoff_floor: c.roundoff_floor,
            status,
            cutbacks,
            residuals: c.residuals,
            nodes,
            element_forces: elements.beam_forces,
            reactions,
            contacts,
            max_penetration,
            events: c.events,
            seconds,
        }
    }
}
