//! The one Newton-Raphson iteration of the solver, for every kind of increment control: from
//! the last converged state, a predictor and corrections with the exact tangent under the
//! increment's constraint (`constraint.rs`), the stretch correction of an update
//! (`stretch.rs`), the convergence, stall and divergence tests (`convergence.rs`), and the
//! contact stages between the iterations.
//!
//! Each turn of an attempt runs its stages in this order:
//! 1. assemble the internal forces and tangent at the iterate (and a snap's viscous force);
//! 2. while the structure springs back from a contact let go, release the node-on-beam
//!    contacts that turn tensile (`ContactSet::release_tensile`);
//! 3. judge the iterate: in every other attempt after a failed one, after the predictor, a
//!    slip it turned back sticks and the predictor is solved again
//!    (`ContactSet::unloaded_slips`); then equilibrium, the round-off floor, a stall; near
//!    equilibrium, the obstacle contacts change where one turned tensile or a node went
//!    inside (`ContactSet::predicted_changes`, else only the tensile ones let go);
//! 4. at a converged pass, the contact stages one after the other, each only once the one
//!    before has nothing to change: node-on-beam activation and release
//!    (`ContactSet::after_convergence`), obstacle contacts and their multipliers
//!    (`ContactSet::obstacle_pass`), the friction modes (`ContactSet::friction_pass`); with
//!    none left to change the state is accepted, otherwise a new pass starts;
//! 5. solve for the correction and update the iterate under the constraint, the stretch
//!    correction after it;
//! 6. follow the contacts across element ends (`ContactSet::transfer`).

use super::constraint::{Constraint, Path};
use super::convergence::STAGNATION;
use super::failure::{AttemptError, Converged};
use super::iteration::{Iterate, Newton};
use super::viscous::Viscous;
use crate::solver::assembly::{assemble_into, AssemblyContext};
use crate::solver::linear::reduce::sum_squares;
use crate::solver::linear::BandMatrix;
use crate::solver::report::{ContactChange, Event, IterationRecord, Observer};

/// The largest correction of an attempt that starts by sliding contacts off tips, as a fraction
/// of the model's size ([`Newton::attempt`]).
const SPRING_BACK_STEP: f64 = 0.2;

/// Below this relative residual a pass changes its obstacle contacts without waiting for
/// convergence ([`Newton::attempt`]): the set the linearised problem predicts, or where that
/// does not apply, the release of the contacts that turned tensile: a strip peeling off a
/// table lets go node after node, and a pass saved is an iteration or two. Much earlier (1e-2
/// and above) the linearisation is too rough, and some random drives of the robustness
/// campaign take more passes or stop (`tsm-contact robust`, seed 1).
const EARLY_RELEASE: f64 = 1e-3;

/// The residual of an iterate: its norm and the reference force it is measured against.
#[derive(Clone, Copy)]
struct Residual {
    norm: f64,
    reference: f64,
}

impl Residual {
    fn relative(&self) -> f64 {
        self.norm / self.reference
    }
}

/// What judging an iterate (stages 3 and 4) decides.
enum Verdict {
    /// Go on iterating: solve for the next correction.
    Correct,
    /// The contact set changed: assemble again at the same displacements.
    Again,
    /// The state is accepted, at this round-off floor.
    Accept { floor: f64 },
    /// A slip the predictor turned back sticks now: solve the predictor again, from the last
    /// converged state.
    Repredict,
}

impl Newton<'_> {
    /// One attempt to meet `constraint` from the last converged state.
    /// `slide_off`: first slide off the free ends the contacts within that fraction of their
    /// element of one ([`ContactSet::slide_off_tips`]); the beam then springs back, a large
    /// motion for one Newton solve, so each correction is held to `SPRING_BACK_STEP` of the
    /// model's size. `viscous`: a pseudo-time step of a snap, the viscous force added to the
    /// internal forces (the relative residual without it goes to
    /// [`Converged::equilibrium_residual`]). `unload_slips`: the predictor is checked for
    /// slips it turns back (stage 3a), as every other attempt after a failed one is: a step
    /// that unloads a slipping contact can fail under the slip mode at any size, and one whose
    /// predictor turns a slip back only to the first order can fail sticking it.
    pub(crate) fn attempt(
        &self,
        constraint: Constraint<'_>,
        increment: usize,
        slide_off: Option<f64>,
        viscous: Option<&Viscous<'_>>,
        unload_slips: bool,
        obs: &mut dyn Observer,
    ) -> Result<Converged, AttemptError> {
        let mut it = self.first_iterate(increment, slide_off);
        if let Some(v) = viscous {
            // The viscous stiffness rounds with the residual it is part of.
            it.bound.add_diagonal(v.peak());
        }
        it.unload_slips = unload_slips;
        let mut max_step = self.structure.params.max_step;
        if slide_off.is_some() {
            max_step = max_step.min(SPRING_BACK_STEP * self.structure.model_size());
        }
        let mut path = Path::new(constraint, self);
        it.predicts = viscous.is_none() && path.dp().is_some();
        let plain = viscous.is_none() && path.starts_at_the_converged_state();
        let mut reuse = self.reuses_the_converged_assembly(&mut it, plain);
        loop {
            // 1. The assembly.
            let residual = self.assemble(&mut it, &path, viscous, std::mem::take(&mut reuse));
            // 2. Releases while springing back.
            if self.spring_back(&mut it, increment)? {
                continue;
            }
            let mut tangent = it.asm.tangent.take().expect("tangent requested");
            if it.predictor {
                for (e, c) in it.asm.unbalanced.iter_mut().zip(&it.asm.coupling) {
                    *e -= c;
                }
                it.log.r0 = Some(sum_squares(&it.asm.unbalanced).sqrt());
            } else {
                // 3 and 4. The iterate judged, and the contact stages at a converged pass.
                // A new pass assembles again into the same storage.
                match self.judge(&mut it, &tangent, residual, increment, obs)? {
                    Verdict::Correct => {}
                    Verdict::Again => {
                        it.asm.tangent = Some(tangent);
                        continue;
                    }
                    Verdict::Repredict => {
                        it.asm.tangent = Some(tangent);
                        self.repredict(&mut it);
                        path = Path::new(constraint, self);
                        continue;
                    }
                    Verdict::Accept { floor } => {
                        let at = (residual, floor, increment);
                        return Ok(self.accept(it, tangent, &path, at, viscous));
                    }
                }
            }
            // 5. The correction.
            self.correct(&mut it, &mut path, &mut tangent, viscous, max_step)?;
            it.asm.tangent = Some(tangent);
            // 6. Transfers: a transfer during the iterations follows the iterate (the next
            // iterate may move the contact back), not an active-set change, so not counted as
            // chattering.
            let view = self.view();
            let (d, iterations) = (&it.d, it.iterations);
            if (it.contacts).transfer(&view, d, increment, iterations, false, &mut it.events) > 0 {
                it.ordering = self.ordering_for(&it.contacts);
            }
        }
    }

    /// Stage 1: the internal forces and tangent at the iterate (reloaded with the current
    /// loads where `reuse`), with a snap's viscous force; returns the residual.
    fn assemble(
        &self,
        it: &mut Iterate,
        path: &Path,
        viscous: Option<&Viscous<'_>>,
        reuse: bool,
    ) -> Residual {
        let p = &self.structure.params;
        let fext = path.external_force();
        let loads = Self::loads_at_equations(fext, &it.ordering);
        if reuse {
            it.asm.reload(&loads);
        } else {
            let grips = it.contacts.grips(&self.view());
            let ctx = AssemblyContext {
                contact: p.contact_options(it.pass_iter + 1),
                loads: &loads,
                follower: (self.structure.model.has_followers()).then(|| path.load_factors()),
                obstacles: &it.contacts.obstacles.links,
                grips: &grips,
                residue: &it.residue,
                ..self.structure.context(&it.ordering)
            };
            let dp = path.dp().filter(|_| it.predictor);
            assemble_into(&ctx, &it.d, true, dp, &mut it.asm);
        }
        if let Some(v) = viscous {
            v.load(&it.d, &it.ordering, &mut it.asm);
        }
        let (norm, reference) = self.residual_norms(&it.asm, fext);
        Residual { norm, reference }
    }

    /// Stage 2: while the structure springs back from a contact let go, the node-on-beam
    /// contacts that turn tensile are released as soon as they do. Returns whether any was.
    fn spring_back(&self, it: &mut Iterate, increment: usize) -> Result<bool, AttemptError> {
        if !it.springback || it.predictor || it.contacts.beams.guard.one_at_a_time() {
            return Ok(false);
        }
        let view = self.view();
        let released =
            (it.contacts).release_tensile(&view, &it.asm, increment, it.iterations, &mut it.events);
        if released == 0 {
            return Ok(false);
        }
        it.changes = self.count_changes(it.changes, released, &it.events)?;
        it.ordering = self.ordering_for(&it.contacts);
        Ok(true)
    }

    /// Stages 3 and 4: record the iterate's residual and judge it, and at a converged pass run
    /// the contact stages.
    fn judge(
        &self,
        it: &mut Iterate,
        tangent: &BandMatrix,
        residual: Residual,
        increment: usize,
        obs: &mut dyn Observer,
    ) -> Result<Verdict, AttemptError> {
        let p = &self.structure.params;
        let rel = residual.relative();
        let record = IterationRecord {
            increment,
            iteration: it.iterations,
            residual: residual.norm,
            relative_residual: rel,
            reference: residual.reference,
            step_norm: it.last_step,
            active_contacts: it.contacts.beams.active.len(),
        };
        it.log.record(obs, record)?;
        // 3a. After the predictor: a slip it turned back sticks (`ContactSet::unloaded_slips`).
        if it.unload_slips && it.iterations == 1 && it.contacts.unloaded_slips(&it.asm) > 0 {
            return Ok(Verdict::Repredict);
        }
        let reference = residual.reference;
        let (scale, floor) = if (it.bound).may_decide(rel, tangent, reference, p, it.pass_iter) {
            self.roundoff_floor(tangent, &it.d, reference, it.bound.extra_diagonal())
        } else {
            it.bound.get(tangent, reference)
        };
        let n_eq = it.ordering.n_eq;
        let at_floor = (it.stall).at_floor(rel, floor, n_eq, it.last_step, scale);
        let accepted = self.equilibrium_reached(rel, floor, at_floor)?;
        // At the round-off floor the state is as converged as it can be: let the contact state
        // settle there too (e.g. a node that must slide off a tip), even if the tolerance
        // itself is out of reach for this contact set.
        let settled = rel <= STAGNATION * floor;
        if !accepted && !settled && self.lets_go_early(it, tangent, rel)? {
            return Ok(Verdict::Again);
        }
        if accepted || settled {
            let verdict = self.contact_stages(it, tangent, increment, accepted.then_some(floor))?;
            if !matches!(verdict, Verdict::Correct) {
                return Ok(verdict);
            }
        }
        self.pass_failed(rel, floor, it.pass_iter, it.iterations)?;
        Ok(Verdict::Correct)
    }

    /// Stage 3's early change: once the pass is near convergence (`EARLY_RELEASE`), the
    /// obstacle contacts change before it has converged: the set the linearised problem
    /// predicts (`ContactSet::predicted_changes`), or, where that does not apply, the contacts
    /// that turned tensile let go (a strip peeling off a table lets go node after node, a pass
    /// for each, and every pass saved is an iteration or two; touches then wait for the
    /// converged pass). Returns whether any changed.
    fn lets_go_early(
        &self,
        it: &mut Iterate,
        tangent: &BandMatrix,
        rel: f64,
    ) -> Result<bool, AttemptError> {
        if it.pass_iter == 0
            || rel >= EARLY_RELEASE
            || it.contacts.obstacles.links.is_empty()
            || it.contacts.obstacles.guard.one_at_a_time()
        {
            return Ok(false);
        }
        let view = self.view();
        let predicted = it.predicts.then(|| {
            (it.contacts).predicted_changes(&view, &it.d, &it.asm, (tangent, &it.ordering))
        });
        let predicted = predicted.flatten();
        let changed = match predicted {
            Some(changed) => changed,
            None => (it.contacts).obstacle_changes(&view, &it.d, &it.asm, true),
        };
        if changed == 0 {
            return Ok(false);
        }
        it.changes = self.count_changes(it.changes, changed, &it.events)?;
        it.ordering = self.ordering_for(&it.contacts);
        it.new_pass();
        Ok(true)
    }

    /// Stage 4, at a converged pass: node-on-beam activation and release, then (with none)
    /// obstacle contacts and their multipliers, then (with neither) the friction modes. Stick
    /// and slip are judged once the normal forces hold: every contact made and every obstacle
    /// gap closed. `Accept` where nothing changed and the state is in equilibrium (`accepted`:
    /// at that round-off floor); `Again` for a new pass; `Correct` where the pass only
    /// settled at the round-off floor.
    fn contact_stages(
        &self,
        it: &mut Iterate,
        tangent: &BandMatrix,
        increment: usize,
        accepted: Option<f64>,
    ) -> Result<Verdict, AttemptError> {
        let view = self.view();
        let (d, iterations) = (&it.d, it.iterations);
        let mut changed = (it.contacts).after_convergence(
            &view,
            d,
            &it.asm,
            increment,
            iterations,
            &mut it.events,
        );
        let mut updated = 0;
        if changed == 0 {
            (changed, updated) = (it.contacts).obstacle_pass(
                &view,
                d,
                &it.asm,
                it.predicts.then_some((tangent, &it.ordering)),
            );
        }
        if changed == 0 && updated == 0 {
            changed = it.contacts.friction_pass(&view, &it.asm);
        }
        self.too_deep(&it.contacts)?;
        if let Some(floor) = accepted.filter(|_| changed == 0 && updated == 0) {
            return Ok(Verdict::Accept { floor });
        }
        if changed > 0 {
            // A contact let go: the structure springs back, and contacts that turn tensile on
            // the way are released as soon as they do.
            it.springback |= it.events.iter().any(|e| {
                matches!(e, Event::Contact(c) if matches!(c.change, ContactChange::Released | ContactChange::SlidOff))
            });
            it.changes = self.count_changes(it.changes, changed, &it.events)?;
            it.ordering = self.ordering_for(&it.contacts);
            it.new_pass();
            return Ok(Verdict::Again);
        }
        if updated > 0 {
            // The same contacts with new multipliers: another pass closes the gaps.
            self.gaps_closing(&it.contacts)?;
            it.new_pass();
            return Ok(Verdict::Again);
        }
        Ok(Verdict::Correct)
    }

    /// The accepted state (with its residual and round-off floor, at `increment`): the
    /// contacts settled against the last accepted ones (the events of the obstacle contacts
    /// and friction modes), and a snap's residual without its viscous force.
    fn accept(
        &self,
        mut it: Iterate,
        tangent: BandMatrix,
        path: &Path,
        (residual, floor, increment): (Residual, f64, usize),
        viscous: Option<&Viscous<'_>>,
    ) -> Converged {
        let view = self.view();
        let iterations = it.iterations;
        (it.contacts).obstacle_settle(&view, increment, iterations, &mut it.events);
        let accepted = (&it.d[..], &it.asm);
        (it.contacts).settle_friction(&view, accepted, increment, iterations, &mut it.events);
        let max_penetration = it.contacts.max_penetration(&view, &it.d);
        // A snap's step: its state's own assembly, and how far that is from equilibrium.
        let equilibrium_residual = viscous.map(|v| {
            v.unload(&it.d, &it.ordering, &mut it.asm);
            it.asm.unbalanced_norm2.sqrt() / residual.reference
        });
        // Unfactored: the next increment's predictor may start from it.
        it.asm.tangent = Some(tangent);
        self.work.spare.borrow_mut().rhs = it.rhs;
        Converged {
            max_penetration,
            d: it.d,
            residue: it.residue,
            load_factors: path.load_factors().to_vec(),
            contacts: it.contacts,
            assembled: it.asm,
            iterations,
            iterations_8_orders: it.log.it8,
            relative_residual: residual.relative(),
            reference: residual.reference,
            roundoff_floor: floor,
            equilibrium_residual,
            residuals: it.log.residuals,
            events: it.events,
        }
    }

    /// Stage 3a's restart: the iterate back at the last converged state, to be predicted
    /// again with the contacts' new modes (the iterations done stay counted).
    fn repredict(&self, it: &mut Iterate) {
        it.d.copy_from_slice(&self.state.d);
        it.residue.copy_from_slice(&self.state.residue);
        it.predictor = true;
        it.pass_iter = 0;
        it.last_step = 0.0;
    }

    /// Stage 5: solve for the correction with the factored tangent and update the iterate
    /// under the constraint, then take the chords' stretch out where asked.
    fn correct(
        &self,
        it: &mut Iterate,
        path: &mut Path,
        tangent: &mut BandMatrix,
        viscous: Option<&Viscous<'_>>,
        max_step: f64,
    ) -> Result<(), AttemptError> {
        // The unbalanced force is the right-hand side, which the solve overwrites; the next
        // assembly gets the last right-hand side's storage.
        std::mem::swap(&mut it.rhs, &mut it.asm.unbalanced);
        if let Some(v) = viscous {
            v.stiffen(&it.ordering, tangent);
        }
        // The stretch correction (`take_out_stretch`) starts from the displacements before the
        // update.
        let contact_gaps = viscous.is_none() && it.pass_iter > 0;
        let correction = self.correction(path, max_step, &it.rhs, contact_gaps);
        self.factor_and_solve(tangent, &it.ordering, &mut it.rhs)?;
        if correction.is_some() {
            it.before.clear();
            it.before.extend_from_slice(&it.d);
        }
        let step = path.update(
            self,
            it.predictor,
            &it.ordering,
            tangent,
            &it.rhs,
            (&mut it.d, &mut it.residue),
            max_step,
            it.iterations,
            &mut it.log,
            &mut it.bound,
        );
        it.last_step = step?;
        it.predictor = false;
        if let Some(correction) = correction {
            let after = path.counts_moves().then(|| it.d.clone());
            let moved = self.take_out_stretch(
                &it.before,
                (&mut it.d, &mut it.residue),
                (&it.ordering, tangent),
                correction,
                (&mut it.rhs, &mut it.gap_rhs),
            );
            it.bound.moved(moved);
            if let Some(after) = after {
                path.moved(&after, &it.d);
            }
        }
        it.iterations += 1;
        it.pass_iter += 1;
        Ok(())
    }
}
