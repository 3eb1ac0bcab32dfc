//! The one Newton-Raphson iteration of the solver, for every kind of increment control: from
//! the last converged state, a predictor and corrections with the exact tangent under the
//! increment's constraint (`constraint.rs`), the stretch correction of an update
//! (`stretch.rs`), the convergence, stall and divergence tests (`convergence.rs`), and the
//! contact active-set passes (transfers during the iterations; activation and release between
//! converged passes; release of contacts that turn tensile while the structure springs back,
//! and of obstacle contacts that do so near convergence).

use super::constraint::{Constraint, Path};
use super::convergence::{FloorBound, IterationLog, Stall, STAGNATION};
use super::failure::{AttemptError, Converged};
use super::iteration::Newton;
use super::viscous::Viscous;
use crate::solver::assembly::{assemble_into, Assembled, AssemblyContext};
use crate::solver::linear::reduce::sum_squares;
use crate::solver::report::{ContactChange, Event, IterationRecord, Observer};

/// The largest correction of an attempt that starts by sliding contacts off tips, as a fraction
/// of the model's size ([`Newton::attempt`]).
const SPRING_BACK_STEP: f64 = 0.2;

/// Below this relative residual a pass lets go of the obstacle contacts that turned tensile
/// without waiting for convergence ([`Newton::attempt`]). The built-in `table_lift` takes 40
/// Newton iterations in its first increment instead of 62, `roller` 716 in all instead of 902;
/// at 1e-2 and above, faster still on those, some random drives of the robustness campaign
/// take more passes or stop (`tsm-contact robust`, seed 1).
const EARLY_RELEASE: f64 = 1e-3;

impl Newton<'_> {
    /// One attempt to meet `constraint` from the last converged state.
    /// `slide_off`: first slide off the free ends the contacts within that fraction of their
    /// element of one ([`ContactSet::slide_off_tips`]); the beam then springs back, a large
    /// motion for one Newton solve, so each correction is held to `SPRING_BACK_STEP` of the
    /// model's size. `viscous`: a pseudo-time step of a snap, the viscous force added to the
    /// internal forces (the relative residual without it goes to
    /// [`Converged::equilibrium_residual`]).
    pub(crate) fn attempt(
        &self,
        constraint: Constraint<'_>,
        increment: usize,
        slide_off: Option<f64>,
        viscous: Option<&Viscous<'_>>,
        obs: &mut dyn Observer,
    ) -> Result<Converged, AttemptError> {
        let p = &self.structure.params;
        // The buffers of the last attempt (fresh memory would cost page faults).
        let (mut d, mut rhs) = {
            let mut spare = self.work.spare.borrow_mut();
            (std::mem::take(&mut spare.d), std::mem::take(&mut spare.rhs))
        };
        d.clear();
        d.extend_from_slice(&self.state.d);
        let mut contacts = self.state.contacts.clone();
        contacts.begin_attempt();
        let mut events = Vec::new();
        let mut max_step = p.max_step;
        if let Some(margin) = slide_off {
            contacts.slide_off_tips(&self.view(), &self.state.d, margin, increment, &mut events);
            max_step = max_step.min(SPRING_BACK_STEP * self.structure.model_size());
        }
        let mut path = Path::new(constraint, self);
        let mut ordering = self.ordering_for(&contacts);
        let mut predictor = true;
        let mut iterations = 0;
        let mut log = IterationLog::default();
        let mut changes = 0;
        let mut pass_iter = 0;
        let mut last_step = 0.0;
        let mut springback = false;
        let mut stall = Stall::new();
        let mut bound = FloorBound::new(self.structure.coordinate_scale(&d));
        // The stretch correction (`take_out_stretch`), and the displacements before each
        // update that it starts from.
        let correcting = self.stretch_correcting();
        let mut before = Vec::new();
        // Buffers reused by every iteration: the assembly (band tangent included) and the
        // right-hand side.
        let mut asm = Assembled::default();
        // The predictor's assembly is the last converged one when nothing differs: no contact
        // element or obstacle contact and no prescribed increment (which would need the
        // coupling K_fp dp).
        let mut reuse = false;
        if ordering.links.is_empty()
            && viscous.is_none()
            && contacts.obstacles.links.is_empty()
            && path.starts_at_the_converged_state()
            && !self.structure.model.has_followers()
        {
            if let Some(kept) = self.work.converged_assembly.take(self.state.increment) {
                asm = kept;
                asm.coupling.clear();
                reuse = asm
                    .tangent
                    .as_ref()
                    .is_some_and(|t| t.len() == ordering.n_eq);
            }
        }
        loop {
            let fext = path.external_force();
            let loads = Self::loads_at_equations(fext, &ordering);
            let grips = contacts.grips(&self.view());
            let ctx = AssemblyContext {
                contact: p.contact_options(pass_iter + 1),
                loads: &loads,
                follower: self
                    .structure
                    .model
                    .has_followers()
                    .then(|| path.load_factors()),
                obstacles: &contacts.obstacles.links,
                grips: &grips,
                ..self.structure.context(&ordering)
            };
            if std::mem::take(&mut reuse) {
                asm.reload(&loads);
            } else {
                let dp = path.dp().filter(|_| predictor);
                assemble_into(&ctx, &d, true, dp, &mut asm);
            }
            if let Some(v) = viscous {
                v.load(&d, &ordering, &mut asm);
            }
            let (norm, reference) = self.residual_norms(&asm, fext);
            if springback && !predictor && !contacts.beams.guard.one_at_a_time() {
                let released = contacts.release_tensile(
                    &self.view(),
                    &asm,
                    increment,
                    iterations,
                    &mut events,
                );
                if released > 0 {
                    changes = self.count_changes(changes, released)?;
                    ordering = self.ordering_for(&contacts);
                    continue;
                }
            }
            let mut tangent = asm.tangent.take().expect("tangent requested");
            if predictor {
                for (e, c) in asm.unbalanced.iter_mut().zip(&asm.coupling) {
                    *e -= c;
                }
                log.r0 = Some(sum_squares(&asm.unbalanced).sqrt());
            } else {
                let rel = norm / reference;
                log.record(
                    obs,
                    IterationRecord {
                        increment,
                        iteration: iterations,
                        residual: norm,
                        relative_residual: rel,
                        reference,
                        step_norm: last_step,
                        active_contacts: contacts.beams.active.len(),
                    },
                )?;
                let (scale, floor) = if bound.may_decide(rel, &tangent, reference, p, pass_iter) {
                    self.roundoff_floor(&tangent, &d, reference)
                } else {
                    bound.get(&tangent, reference)
                };
                let at_floor = stall.at_floor(rel, floor, ordering.n_eq, last_step, scale);
                let accepted = self.equilibrium_reached(rel, floor, at_floor)?;
                // At the round-off floor the state is as converged as it can be: let the contact
                // state settle there too (e.g. a node that must slide off a tip), even if the
                // tolerance itself is out of reach for this contact set.
                let settled = rel <= STAGNATION * floor;
                // An obstacle contact that turned tensile lets go before the pass has
                // converged, once it is near (`EARLY_RELEASE`): a strip peeling off a table
                // lets go node after node, a pass for each, and every pass saved is an
                // iteration or two. Touches wait for the converged pass.
                if !accepted
                    && !settled
                    && pass_iter > 0
                    && rel < EARLY_RELEASE
                    && !contacts.obstacles.links.is_empty()
                    && !contacts.obstacles.guard.one_at_a_time()
                {
                    let changed = contacts.obstacle_changes(&self.view(), &d, &asm, true);
                    if changed > 0 {
                        changes = self.count_changes(changes, changed)?;
                        ordering = self.ordering_for(&contacts);
                        pass_iter = 0;
                        stall = Stall::new();
                        continue;
                    }
                }
                if accepted || settled {
                    let mut changed = contacts.after_convergence(
                        &self.view(),
                        &d,
                        &asm,
                        increment,
                        iterations,
                        &mut events,
                    );
                    let mut updated = 0;
                    if changed == 0 {
                        (changed, updated) = contacts.obstacle_pass(&self.view(), &d, &asm);
                    }
                    // Stick and slip are judged once the normal forces hold: every contact
                    // made and every obstacle gap closed.
                    if changed == 0 && updated == 0 {
                        changed = contacts.friction_pass(&self.view(), &asm);
                    }
                    self.too_deep(&contacts)?;
                    if changed == 0 && updated == 0 && accepted {
                        let view = self.view();
                        contacts.obstacle_settle(&view, increment, iterations, &mut events);
                        contacts.settle_friction(&view, &asm, increment, iterations, &mut events);
                        let max_penetration = contacts.max_penetration(&self.view(), &d);
                        // A snap's step: its state's own assembly, and how far that is from
                        // equilibrium.
                        let equilibrium_residual = viscous.map(|v| {
                            v.unload(&d, &ordering, &mut asm);
                            asm.unbalanced_norm2.sqrt() / reference
                        });
                        // Unfactored: the next increment's predictor may start from it.
                        asm.tangent = Some(tangent);
                        self.work.spare.borrow_mut().rhs = rhs;
                        return Ok(Converged {
                            max_penetration,
                            d,
                            load_factors: path.load_factors().to_vec(),
                            contacts,
                            assembled: asm,
                            iterations,
                            iterations_8_orders: log.it8,
                            relative_residual: rel,
                            reference,
                            roundoff_floor: floor,
                            equilibrium_residual,
                            residuals: log.residuals,
                            events,
                        });
                    }
                    if changed > 0 {
                        // A contact let go: the structure springs back, and contacts that turn
                        // tensile on the way are released as soon as they do.
                        springback |= events.iter().any(|e| {
                            matches!(e, Event::Contact(c) if matches!(c.change, ContactChange::Released | ContactChange::SlidOff))
                        });
                        changes = self.count_changes(changes, changed)?;
                        ordering = self.ordering_for(&contacts);
                        pass_iter = 0;
                        stall = Stall::new();
                        continue;
                    }
                    if updated > 0 {
                        // The same contacts with new multipliers: another pass closes the gaps.
                        self.gaps_closing(&contacts)?;
                        pass_iter = 0;
                        stall = Stall::new();
                        continue;
                    }
                }
                self.pass_failed(rel, floor, pass_iter, iterations)?;
            }
            // The unbalanced force is the right-hand side, which the solve overwrites; the next
            // assembly gets the last right-hand side's storage.
            std::mem::swap(&mut rhs, &mut asm.unbalanced);
            if let Some(v) = viscous {
                v.stiffen(&ordering, &mut tangent);
            }
            self.factor_and_solve(&mut tangent, &ordering, &mut rhs)?;
            if correcting {
                before.clear();
                before.extend_from_slice(&d);
            }
            let step = path.update(
                self, predictor, &ordering, &tangent, &rhs, &mut d, max_step, iterations, &mut log,
                &mut bound,
            );
            asm.tangent = Some(tangent);
            last_step = step?;
            predictor = false;
            if correcting {
                let factors = asm.tangent.as_ref().expect("factored");
                let after = path.counts_moves().then(|| d.clone());
                let moved = self.take_out_stretch(&before, &mut d, &ordering, factors, &mut rhs);
                bound.moved(moved);
                if let Some(after) = after {
                    path.moved(&after, &d);
                }
            }
            iterations += 1;
            pass_iter += 1;
            let moved =
                contacts.transfer(&self.view(), &d, increment, iterations, false, &mut events);
            // A transfer during the iterations follows the iterate (the next iterate may move
            // the contact back): not an active-set change, so not counted as chattering.
            if moved > 0 {
                ordering = self.ordering_for(&contacts);
            }
        }
    }
}
