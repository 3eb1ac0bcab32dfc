//! What a Newton attempt reads (`Newton`: the structure, the last converged state and the
//! workspace), what it carries from one iteration to the next (`Iterate`, and the first one,
//! from the last converged state), and the tests and measures its iteration (`attempt.rs`)
//! applies: the residual and its reference force, equilibrium, divergence, chattering, a node
//! too deep, the round-off floor, and the factor-and-solve that names a singular dof.

use std::sync::Arc;

use super::convergence::{FloorBound, IterationLog, Stall};
use super::failure::{AttemptError, Chatter};
use super::workspace::Workspace;
use crate::solver::assembly::{Assembled, DofKind, ExternalForce, Ordering};
use crate::solver::contact::{ContactSet, ContactView};
use crate::solver::linear::{BandMatrix, NOT_FREE};
use crate::solver::params::StretchCorrection;
use crate::solver::report::Event;
use crate::solver::state::State;
use crate::solver::structure::Structure;

/// Passes that update the obstacle multipliers an attempt may make before it fails
/// ([`AttemptError::GapsOpen`]). A penalty of the order of the elements' axial stiffness closes
/// a gap by at least half, and mostly by orders of magnitude, a pass; a gap that stays open is
/// held there (a prescribed displacement driving a node into an obstacle).
const MAX_MULTIPLIER_UPDATES: usize = 50;

/// What a Newton attempt reads: the structure, the last converged state, and
/// the scratch space it borrows buffers from.
#[derive(Clone, Copy)]
pub struct Newton<'a> {
    /// The structure.
    pub structure: &'a Structure,
    /// The last converged state.
    pub state: &'a State,
    /// Scratch space.
    pub work: &'a Workspace,
}

impl<'a> Newton<'a> {
    /// The contact stage's view: the structure and the last converged state.
    pub(crate) fn view(&self) -> ContactView<'a> {
        ContactView {
            structure: self.structure,
            d: &self.state.d,
            contacts: &self.state.contacts,
        }
    }

    /// The equation ordering for a contact topology (kept in the workspace).
    pub(crate) fn ordering_for(&self, contacts: &ContactSet) -> Arc<Ordering> {
        self.work.ordering_for(self.structure, contacts)
    }

    /// Whether this attempt's Newton updates take the chords' stretch out
    /// (`SolverParams::stretch_correction`), every one of them.
    pub fn stretch_correcting(&self) -> bool {
        let mode = self.structure.params.stretch_correction;
        mode == StretchCorrection::Always || (mode.on_after_a_cut_back() && self.state.cut_back)
    }

    /// The external force `fext` at its equations in `ord`, ascending (dofs that are not free
    /// left out): what the assembly loads the unbalanced force with ([`AssemblyContext::loads`]).
    pub(crate) fn loads_at_equations(fext: &ExternalForce, ord: &Ordering) -> Vec<(usize, f64)> {
        let mut at: Vec<(usize, f64)> = (fext.0.iter())
            .filter(|&&(g, _)| ord.eq[g] != NOT_FREE)
            .map(|&(g, f)| (ord.eq[g] as usize, f))
            .collect();
        at.sort_unstable_by_key(|&(e, _)| e);
        at
    }

    /// The norm of the unbalanced force of `asm` (assembled, or reloaded, with the external
    /// force `fext`) and the reference force: the larger of the loads on the free dofs and the
    /// internal forces at the held dofs (what the supports and drives carry). A load on a held
    /// dof goes straight into its support: it strains nothing, and left in the reference it
    /// would loosen the test of every other dof.
    pub(crate) fn residual_norms(&self, asm: &Assembled, fext: &ExternalForce) -> (f64, f64) {
        let ext2: f64 = (fext.0.iter())
            .filter(|&&(g, _)| self.structure.dofs.kind[g] == DofKind::Free)
            .map(|&(_, f)| f * f)
            .sum();
        let reac2: f64 = asm.held_internal.iter().map(|i| i * i).sum();
        let reference = ext2
            .sqrt()
            .max(reac2.sqrt())
            .max(self.structure.force_floor);
        (asm.unbalanced_norm2.sqrt(), reference)
    }

    /// The error for a node found deeper through a body than `max_penetration` at a converged
    /// pass (the increment is then cut back), if there is one.
    pub(super) fn too_deep(&self, contacts: &ContactSet) -> Result<(), AttemptError> {
        if let Some((node, body, depth)) = contacts.beams.too_deep {
            return Err(AttemptError::TooDeep { node, body, depth });
        }
        match contacts.obstacles.too_deep {
            Some((node, obstacle, depth)) => Err(AttemptError::ObstacleTooDeep {
                node,
                obstacle,
                depth,
            }),
            None => Ok(()),
        }
    }

    /// Whether the obstacle contacts' multipliers may be updated once more in this attempt
    /// (`MAX_MULTIPLIER_UPDATES` passes).
    pub(super) fn gaps_closing(&self, contacts: &ContactSet) -> Result<(), AttemptError> {
        match contacts.obstacles.widest_gap {
            Some((node, obstacle, gap))
                if contacts.obstacles.multiplier_updates > MAX_MULTIPLIER_UPDATES =>
            {
                Err(AttemptError::GapsOpen {
                    updates: contacts.obstacles.multiplier_updates,
                    node,
                    obstacle,
                    gap,
                })
            }
            _ => Ok(()),
        }
    }

    /// Whether a pass at relative residual `rel` (round-off floor `floor`; `at_floor`: Newton
    /// stalled there) is in equilibrium: within the tolerance, or at the round-off floor within
    /// `roundoff_bound`. A stall above the bound fails the attempt.
    pub(crate) fn equilibrium_reached(
        &self,
        rel: f64,
        floor: f64,
        at_floor: bool,
    ) -> Result<bool, AttemptError> {
        let p = &self.structure.params;
        let bound = p.roundoff_bound.max(p.tolerance);
        if at_floor && rel > bound {
            return Err(AttemptError::AtFloor {
                residual: rel,
                floor,
            });
        }
        Ok(rel <= p.tolerance || (rel <= bound && (rel <= p.roundoff_factor * floor || at_floor)))
    }

    /// Fail a pass that diverged or ran out of iterations. The first residual of a pass
    /// measures the penetration of the contacts just activated (large where a node touches next
    /// to an element end), not divergence, so it is not tested.
    pub(super) fn pass_failed(
        &self,
        rel: f64,
        floor: f64,
        pass_iter: usize,
        iterations: usize,
    ) -> Result<(), AttemptError> {
        let p = &self.structure.params;
        if rel > p.divergence && pass_iter > 0 {
            return Err(AttemptError::Diverged {
                iteration: iterations,
                residual: rel,
            });
        }
        if pass_iter >= p.max_iterations {
            return Err(AttemptError::NoConvergence {
                iterations: p.max_iterations,
                residual: rel,
                floor,
            });
        }
        Ok(())
    }

    /// Add `more` contact state changes to `so_far`; too many in one increment is chattering,
    /// located at the contact of `events` (the attempt's) that changed most.
    pub(super) fn count_changes(
        &self,
        so_far: usize,
        more: usize,
        events: &[Event],
    ) -> Result<usize, AttemptError> {
        let total = so_far + more;
        // Every candidate node may touch, let go and touch again (one change per pass once an
        // active set repeats); beyond that, the allowance is for chattering.
        let candidates = self.structure.candidate_nodes + self.structure.obstacle_candidates.len();
        if total > self.structure.params.max_active_set_changes + 4 * candidates {
            return Err(AttemptError::Chattering {
                changes: total,
                most: Chatter::most_changed(events, &self.structure.model),
            });
        }
        Ok(total)
    }

    /// The coordinate scale of state `d` and the round-off floor of the relative residual there:
    /// `eps (max|K_ii| + extra) max|x| / reference`, `extra` what the solve adds to the
    /// diagonal (a snap's viscous stiffness).
    pub(crate) fn roundoff_floor(
        &self,
        tangent: &BandMatrix,
        d: &[f64],
        reference: f64,
        extra: f64,
    ) -> (f64, f64) {
        let scale = self.structure.coordinate_scale(d);
        (
            scale,
            f64::EPSILON * (tangent.max_diagonal() + extra) * scale / reference,
        )
    }

    /// Factor the tangent in place and solve for `rhs` with it (in one pass where the band
    /// allows, [`BandMatrix::factor_and_solve`]); a vanishing pivot fails the attempt, naming its
    /// dof.
    pub(super) fn factor_and_solve(
        &self,
        tangent: &mut BandMatrix,
        ord: &Ordering,
        rhs: &mut [f64],
    ) -> Result<(), AttemptError> {
        tangent
            .factor_and_solve(0.0, rhs)
            .map_err(|sp| AttemptError::Singular {
                dof: self.structure.equation_label(ord, sp.equation),
            })
    }
}

/// What an attempt carries from one iteration to the next.
pub(super) struct Iterate {
    /// The displacements.
    pub(super) d: Vec<f64>,
    /// The rounding residues of `d` (`assembly::add_carried`): `d + residue` is the iterate.
    pub(super) residue: Vec<f64>,
    /// The right-hand side of the last solve (the correction).
    pub(super) rhs: Vec<f64>,
    /// The contact set the iterate is assembled with.
    pub(super) contacts: ContactSet,
    /// The contact events so far.
    pub(super) events: Vec<Event>,
    /// Whether obstacle contact sets are predicted (`ContactSet::predicted_changes`): under
    /// prescribed displacements and load factors without a snap's viscous force, where the
    /// tangent alone gives the next Newton correction.
    pub(super) predicts: bool,
    /// Whether a slip the predictor turns back sticks, and the predictor is solved again
    /// (`ContactSet::unloaded_slips`): in every other attempt after a failed one.
    pub(super) unload_slips: bool,
    /// The displacements before the last update, where the stretch correction starts from
    /// (kept for the attempt, refilled at each correction).
    pub(super) before: Vec<f64>,
    /// The contact gaps' right-hand side and correction (`Newton::contact_gap_correction`;
    /// kept for the attempt, refilled at each correction).
    pub(super) gap_rhs: Vec<f64>,
    /// The equation ordering of `contacts`.
    pub(super) ordering: Arc<Ordering>,
    /// The assembly at `d` (its tangent taken out while it is factored).
    pub(super) asm: Assembled,
    /// Whether the next solve is the predictor.
    pub(super) predictor: bool,
    /// Newton iterations so far.
    pub(super) iterations: usize,
    /// Iterations of the current pass (since the contact set last changed).
    pub(super) pass_iter: usize,
    /// Active-set changes so far (chattering is counted from them).
    pub(super) changes: usize,
    /// The norm of the last correction.
    pub(super) last_step: f64,
    /// Whether a contact let go: node-on-beam contacts that turn tensile while the structure
    /// springs back are released at once.
    pub(super) springback: bool,
    /// The iteration records.
    pub(super) log: IterationLog,
    /// The stall test of the current pass.
    pub(super) stall: Stall,
    /// The bound on the round-off floor.
    pub(super) bound: FloorBound,
}

impl Newton<'_> {
    /// The iterate an attempt starts from: the last converged state, with the buffers of the
    /// last attempt (fresh memory would cost page faults), its contacts within `slide_off` of
    /// a free end slid off it.
    pub(super) fn first_iterate(&self, increment: usize, slide_off: Option<f64>) -> Iterate {
        let (mut d, rhs) = {
            let mut spare = self.work.spare.borrow_mut();
            (std::mem::take(&mut spare.d), std::mem::take(&mut spare.rhs))
        };
        d.clear();
        d.extend_from_slice(&self.state.d);
        let residue = self.state.residue.clone();
        let mut contacts = self.state.contacts.clone();
        contacts.begin_attempt();
        let mut events = Vec::new();
        if let Some(margin) = slide_off {
            contacts.slide_off_tips(&self.view(), &self.state.d, margin, increment, &mut events);
        }
        let bound = FloorBound::new(self.structure.coordinate_scale(&d));
        Iterate {
            d,
            residue,
            rhs,
            ordering: self.ordering_for(&contacts),
            contacts,
            events,
            asm: Assembled::default(),
            predictor: true,
            iterations: 0,
            pass_iter: 0,
            changes: 0,
            last_step: 0.0,
            springback: false,
            predicts: false,
            unload_slips: false,
            before: Vec::new(),
            gap_rhs: Vec::new(),
            log: IterationLog::default(),
            stall: Stall::new(),
            bound,
        }
    }

    /// Whether the predictor's assembly is the last converged one, taken into `it`: when
    /// nothing differs (no contact element or obstacle contact; `plain`: no prescribed
    /// increment, which would need the coupling K_fp dp, and no viscous force; no follower
    /// load).
    pub(super) fn reuses_the_converged_assembly(&self, it: &mut Iterate, plain: bool) -> bool {
        if !plain
            || !it.ordering.links.is_empty()
            || !it.contacts.obstacles.links.is_empty()
            || self.structure.model.has_followers()
        {
            return false;
        }
        let Some(kept) = self.work.converged_assembly.take(self.state.increment) else {
            return false;
        };
        it.asm = kept;
        it.asm.coupling.clear();
        (it.asm.tangent.as_ref()).is_some_and(|t| t.len() == it.ordering.n_eq)
    }
}

impl Iterate {
    /// A new pass starts: the contact set or its multipliers changed.
    pub(super) fn new_pass(&mut self) {
        self.pass_iter = 0;
        self.stall = Stall::new();
    }
}
