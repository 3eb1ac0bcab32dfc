//! The `Solver`: the structure, its converged state and the Newton workspace of one run, set
//! up at the undeformed state, with what callers read of it.

use crate::solver::acceptance::CrossingCheck;
use crate::solver::assembly::{assemble, AssemblyContext};
use crate::solver::contact::{ContactSet, ContactView};
use crate::solver::model::Model;
use crate::solver::newton::{Newton, Workspace};
use crate::solver::params::SolverParams;
use crate::solver::report::SolveError;
use crate::solver::rigid_modes::free_parts;
use crate::solver::state::State;

use super::Checkpoint;
use crate::solver::structure::Structure;

/// The TSM solver for one model: the structure, the converged state, and
/// everything needed to advance it.
#[derive(Clone, Debug)]
pub struct Solver {
    /// The model prepared for the solver.
    pub(crate) structure: Structure,
    /// The last converged state.
    pub(crate) state: State,
    /// Scratch space of the Newton attempts.
    pub(crate) work: Workspace,
    /// The acceptance check's geometric test, at the last accepted state.
    pub(crate) crossing: CrossingCheck,
    /// Checkpoints of the accepted increments, when asked for (`keep_checkpoints`).
    pub(crate) kept: Option<Vec<Checkpoint>>,
    /// The stage of the load path the increments being solved belong to (none off the path).
    pub(crate) marching: Option<usize>,
}

impl Solver {
    /// The structure: the model prepared for the solver, its parameters, elements and dofs.
    pub fn structure(&self) -> &Structure {
        &self.structure
    }

    /// Set up a solver at the undeformed state; fails if the structure is a mechanism or a
    /// contact candidate node starts on a body with no side to tell.
    pub fn new(model: Model, params: SolverParams) -> Result<Solver, SolveError> {
        let structure = Structure::new(model, params);
        let state = State {
            d: vec![0.0; structure.dofs.len()],
            residue: vec![0.0; structure.dofs.len()],
            prescribed: vec![0.0; structure.model.prescribed.len()],
            load_factors: vec![0.0; structure.model.group_count()],
            ..State::default()
        };
        // Rigid motions left free by the supports, from geometry; then what the tangent has no
        // stiffness for (inner mechanisms, and lone nodes).
        // Nodes resting on obstacles at rest start in contact, and nodes resting on beams on a
        // declared side: what they rest on holds them.
        let mut state = state;
        let mut contacts = std::mem::take(&mut state.contacts);
        let view = ContactView {
            structure: &structure,
            d: &state.d,
            contacts: &ContactSet::default(),
        };
        contacts.obstacles_at_rest(&view);
        contacts.beams_at_rest(&view);
        let mut normals = contacts.resting_normals(&view);
        normals.extend(contacts.resting_on_beams(&view));
        let grips = contacts.grips(&view);
        state.contacts = contacts;
        let free = free_parts(&structure.model, &normals);
        if !free.is_empty() {
            return Err(structure.rigid_motion(&free));
        }
        // The ordering with the contacts at rest, kept in the workspace for the first attempt.
        let work = Workspace::default();
        let ord = work.ordering_for(&structure, &state.contacts);
        let (free, complete) =
            structure.mechanism_dofs(&ord, &state.d, (&state.contacts.obstacles.links, &grips));
        if !free.is_empty() {
            return Err(structure.mechanism(&free, complete));
        }
        let mut solver = Solver {
            structure,
            state,
            work,
            crossing: CrossingCheck::default(),
            kept: None,
            marching: None,
        };
        let mut contacts = std::mem::take(&mut solver.state.contacts);
        contacts.remember_sides(&solver.view(), &solver.state.d);
        if let Some((n, b)) = contacts.beams.ambiguous {
            return Err(SolveError::AmbiguousSide {
                node: solver.structure.model.nodes[n].id,
                body: solver.structure.model.bodies[b].name.clone(),
            });
        }
        solver.state.contacts = contacts;
        if !solver.structure.candidates.is_empty() {
            let start = solver.structure.node_states(&solver.state.d);
            let pairs = solver.structure.candidates.clone();
            solver.crossing = CrossingCheck::new(&solver.structure.model, pairs, start);
        }
        Ok(solver)
    }

    /// The parameters, to change between increments (e.g. the stretch correction).
    pub fn params_mut(&mut self) -> &mut SolverParams {
        &mut self.structure.params
    }

    /// What a Newton attempt reads of the solver.
    pub(crate) fn newton(&self) -> Newton<'_> {
        Newton {
            structure: &self.structure,
            state: &self.state,
            work: &self.work,
        }
    }

    /// What the contact stage reads of the solver.
    pub fn view(&self) -> ContactView<'_> {
        ContactView {
            structure: &self.structure,
            d: &self.state.d,
            contacts: &self.state.contacts,
        }
    }

    /// Unbalanced force `sum lambda_g F_g - sum J S` over the free dofs and the dense tangent over the
    /// same dofs, at displacements `d` with the current contacts and load factor. Returns the
    /// free global dofs too, in the order of the vector and matrix. For checks and tests.
    pub fn unbalanced_force_and_tangent(
        &self,
        d: &[f64],
    ) -> (Vec<f64>, nalgebra::DMatrix<f64>, Vec<usize>) {
        self.unbalanced_force_and_tangent_carried(d, &[])
    }

    /// `unbalanced_force_and_tangent` at the converged state itself: its displacements with
    /// the rounding residues the solver carries with them (`assembly::add_carried`), the state
    /// whose residual the increment's record reports.
    pub fn state_unbalanced_force_and_tangent(
        &self,
    ) -> (Vec<f64>, nalgebra::DMatrix<f64>, Vec<usize>) {
        self.unbalanced_force_and_tangent_carried(&self.state.d, &self.state.residue)
    }

    /// `unbalanced_force_and_tangent` at displacements `d` with residues `residue` (empty:
    /// none).
    fn unbalanced_force_and_tangent_carried(
        &self,
        d: &[f64],
        residue: &[f64],
    ) -> (Vec<f64>, nalgebra::DMatrix<f64>, Vec<usize>) {
        let ord = self
            .work
            .ordering_for(&self.structure, &self.state.contacts);
        let grips = self.state.contacts.grips(&self.view());
        let ctx = AssemblyContext {
            follower: (self.structure.model.has_followers())
                .then_some(&self.state.load_factors[..]),
            obstacles: &self.state.contacts.obstacles.links,
            grips: &grips,
            residue,
            ..self.structure.context(&ord)
        };
        let asm = assemble(&ctx, d, true, None);
        let fext = self.structure.external_force(&self.state.load_factors);
        let free: Vec<usize> = ord.dof_of.iter().map(|&g| g as usize).collect();
        // Assembled with no loads: the unbalanced force is -sum J S.
        let r = (free.iter().zip(&asm.unbalanced))
            .map(|(&g, u)| fext.at(g) + u)
            .collect();
        let k = asm.tangent.expect("tangent");
        let dense = nalgebra::DMatrix::from_fn(ord.n_eq, ord.n_eq, |i, j| k.get(i, j));
        (r, dense, free)
    }

    /// Number of converged increments so far.
    pub fn increment(&self) -> usize {
        self.state.increment
    }

    /// Current values of the prescribed displacements.
    pub fn prescribed_values(&self) -> &[f64] {
        &self.state.prescribed
    }

    /// Current load factor (the first load group's where the model has several).
    pub fn load_factor(&self) -> f64 {
        self.state.load_factors[0]
    }

    /// Current load factors, one per load group.
    pub fn load_factors(&self) -> &[f64] {
        &self.state.load_factors
    }

    /// The steps of the load path completed (0 where the model has no path).
    pub fn path_step(&self) -> usize {
        self.state.path_step
    }

    /// Converged displacements over all dofs.
    pub fn displacements(&self) -> &[f64] {
        &self.state.d
    }

    /// The active contacts.
    pub fn contacts(&self) -> &ContactSet {
        &self.state.contacts
    }

    /// Current position (in the scene's coordinates) and rotation of node `n`.
    pub fn node_state(&self, n: usize) -> ([f64; 2], f64) {
        self.structure.node_state_at(&self.state.d, n)
    }

    /// Whether the next attempt's Newton updates take the chords' stretch out, every one of them
    /// ([`SolverParams::stretch_correction`]; `WhereNeeded` before a cut-back judges each).
    pub fn stretch_correcting(&self) -> bool {
        self.newton().stretch_correcting()
    }
}

impl Solver {
    /// The accepted state as it is now.
    pub fn checkpoint(&self) -> Checkpoint {
        Checkpoint {
            state: self.state.clone(),
            crossing: self.crossing.memory(),
        }
    }

    /// Go on from `checkpoint` (taken from this solver, or one built from the same model and
    /// parameters): the next increment is solved exactly as it was after the checkpoint.
    pub fn restore(&mut self, checkpoint: &Checkpoint) {
        self.state = checkpoint.state.clone();
        if !self.crossing.is_empty() {
            self.crossing.restore(&checkpoint.crossing);
        }
        // The kept assembly belongs to another state of the same number, perhaps.
        self.work.converged_assembly.0.borrow_mut().take();
    }

    /// Keep a checkpoint of every accepted increment from now on (or stop keeping them), for
    /// `take_checkpoints`.
    pub fn keep_checkpoints(&mut self, on: bool) {
        self.kept = on.then(Vec::new);
    }

    /// The checkpoints kept since the last call, oldest first.
    pub fn take_checkpoints(&mut self) -> Vec<Checkpoint> {
        self.kept.as_mut().map(std::mem::take).unwrap_or_default()
    }

    /// Keep a checkpoint of the state just accepted, if asked to (`keep_checkpoints`).
    pub(crate) fn keep_checkpoint(&mut self) {
        if self.kept.is_some() {
            let c = self.checkpoint();
            if let Some(kept) = &mut self.kept {
                kept.push(c);
            }
        }
    }
}
