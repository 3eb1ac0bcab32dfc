//! Newton-Raphson on the unbalanced force for one increment attempt: linear predictor for the
//! prescribed increment, iterations with the exact tangent, the stretch correction of an update,
//! the convergence and divergence tests, and the contact active-set passes (transfers during
//! iterations, activation and release between converged passes).

use super::assembly::{assemble_into, Assembled, AssemblyContext, DofKind, Ordering};
use super::contact::ContactSet;
use super::control::Solver;
use super::linear::{BandMatrix, NOT_FREE};
use super::loads::ExternalForce;
use super::reduce::sum_squares;
use super::report::{ContactChange, Event, Flow, IterationRecord, Observer};

/// The largest correction of an attempt that starts by sliding contacts off tips, as a fraction
/// of the model's size (`Solver::attempt`).
const SPRING_BACK_STEP: f64 = 0.2;

/// A residual within this factor of the round-off floor counts as stagnated.
const STAGNATION: f64 = 10.0;

/// Iterations without halving the best residual, below the round-off floor estimate, after
/// which an attempt counts as converged to round-off.
const STALL_ITERATIONS: usize = 3;

/// ... and once the displacement correction has shrunk below this fraction of the coordinates.
const STALL_STEP: f64 = 1e-10;

/// The factor by which the round-off of a residual norm over `n_eq` equations can exceed the
/// floor estimate, which is that of one equation (`eps max|K_ii| |x|`): each equation rounds
/// on its own, and the norm sums their squares, so up to sqrt(n_eq).
fn norm_spread(n_eq: usize) -> f64 {
    (n_eq.max(1) as f64).sqrt()
}

/// Round-off stagnation of one Newton pass: once the residual has stopped falling (no halving
/// of the best value for `STALL_ITERATIONS` iterations) while the corrections have vanished,
/// and lies within `STAGNATION` times the round-off a residual norm over all the equations can
/// have (the floor estimate times `norm_spread`), Newton cannot get closer: the state is
/// accepted and its residual reported.
pub(crate) struct Stall {
    best: f64,
    count: usize,
}

impl Stall {
    pub(crate) fn new() -> Stall {
        Stall {
            best: f64::INFINITY,
            count: 0,
        }
    }

    /// Record the relative residual `rel` of an iteration; true if the pass has stalled at the
    /// round-off floor `floor` of a system of `n_eq` equations, with a last correction `step`
    /// against coordinates of size `scale`.
    pub(crate) fn at_floor(
        &mut self,
        rel: f64,
        floor: f64,
        n_eq: usize,
        step: f64,
        scale: f64,
    ) -> bool {
        if rel < 0.5 * self.best {
            self.count = 0;
        } else {
            self.count += 1;
        }
        self.best = self.best.min(rel);
        self.count >= STALL_ITERATIONS
            && rel <= STAGNATION * norm_spread(n_eq) * floor
            && step <= STALL_STEP * scale
    }
}

/// An upper bound of the round-off floor over one attempt, at no cost per iteration: the band's
/// diagonal peak (`BandMatrix::diagonal_peak`, at least max|K_ii|) and the coordinate scale at
/// the start of the attempt plus every correction since (the largest coordinate moves no
/// further than the correction's norm). The exact floor takes a pass over the band and the
/// coordinates; it is worked out only where it can decide something (see `may_decide`).
/// Elsewhere the bound stands in, and every test gives the same outcome with it: each asks
/// whether the residual lies within a factor of the floor, and the residual lies beyond that
/// factor of the bound, so beyond that factor of the floor too.
pub(crate) struct FloorBound {
    /// Coordinate scale at the start of the attempt.
    start: f64,
    /// Sum of the largest coordinate moves since.
    moved: f64,
}

impl FloorBound {
    pub(crate) fn new(start: f64) -> FloorBound {
        FloorBound { start, moved: 0.0 }
    }

    /// Record a correction of the coordinates by at most `largest` in any entry.
    pub(crate) fn moved(&mut self, largest: f64) {
        self.moved += largest;
    }

    /// (coordinate scale, round-off floor), both bounds from above.
    pub(crate) fn get(&self, tangent: &BandMatrix, reference: f64) -> (f64, f64) {
        // A margin for the round-off of the sums above (relative 1e-16 each).
        let scale = (self.start + self.moved) * (1.0 + 1e-12);
        let floor = f64::EPSILON * tangent.diagonal_peak() * scale / reference;
        (scale, floor * (1.0 + 1e-12))
    }

    /// Whether the exact floor is needed at relative residual `rel` in iteration `pass_iter`
    /// of a pass: where the state converges (the floor is reported), where the pass runs out
    /// of iterations (the message gives it), and where `rel` lies within the widest factor the
    /// convergence tests put on the floor.
    pub(crate) fn may_decide(
        &self,
        rel: f64,
        tangent: &BandMatrix,
        reference: f64,
        params: &super::params::SolverParams,
        pass_iter: usize,
    ) -> bool {
        let widest = (STAGNATION * norm_spread(tangent.len())).max(params.roundoff_factor);
        !(rel > params.tolerance
            && pass_iter < params.max_iterations
            && rel > widest * self.get(tangent, reference).1)
    }
}

/// The converged outcome of one attempt, before it is committed.
pub struct Converged {
    /// Displacements.
    pub d: Vec<f64>,
    /// Contact state.
    pub contacts: ContactSet,
    /// Final assembly at the converged state.
    pub assembled: Assembled,
    /// Total iterations.
    pub iterations: usize,
    /// Iterations to an 8-order drop of the unbalanced force.
    pub iterations_8_orders: Option<usize>,
    /// Relative residual at convergence.
    pub relative_residual: f64,
    /// Reference force.
    pub reference: f64,
    /// Round-off floor estimate of the relative residual.
    pub roundoff_floor: f64,
    /// Iteration records.
    pub residuals: Vec<IterationRecord>,
    /// Contact events.
    pub events: Vec<Event>,
    /// Largest penetration through a body, in element lengths (see `IncrementRecord`).
    pub max_penetration: f64,
}

/// Why an attempt failed.
pub enum AttemptError {
    /// Recoverable by a smaller increment.
    Failed(String),
    /// Newton stalled at the round-off floor above `SolverParams::roundoff_bound`.
    AtFloor {
        /// Relative residual reached.
        residual: f64,
        /// Round-off floor estimate there.
        floor: f64,
    },
    /// The acceptance check found a node through a body it is not in contact with.
    Crossed(super::acceptance::Crossing),
    /// The observer asked to stop.
    Stopped,
}

/// The residual history of one attempt: the predictor's residual, the first iteration at which
/// the residual fell 8 orders below it, and every iteration's record.
#[derive(Default)]
pub(crate) struct IterationLog {
    /// Every iteration's record, in order.
    pub(crate) residuals: Vec<IterationRecord>,
    /// The residual after the predictor (the reference of the 8-order drop).
    pub(crate) r0: Option<f64>,
    /// The first iteration whose residual is 8 orders below `r0`.
    pub(crate) it8: Option<usize>,
}

impl IterationLog {
    /// Report `rec` to the observer and keep it. Fails when the observer asks to stop or the
    /// residual is not finite.
    pub(crate) fn record(
        &mut self,
        obs: &mut dyn Observer,
        rec: IterationRecord,
    ) -> Result<(), AttemptError> {
        let flow = obs.iteration(&rec);
        let (norm, rel, iteration) = (rec.residual, rec.relative_residual, rec.iteration);
        self.residuals.push(rec);
        if flow == Flow::Stop {
            return Err(AttemptError::Stopped);
        }
        if !rel.is_finite() {
            return Err(AttemptError::Failed(format!(
                "non-finite residual at iteration {iteration}"
            )));
        }
        if self.it8.is_none() && self.r0.is_some_and(|r0| norm <= 1e-8 * r0) {
            self.it8 = Some(iteration);
        }
        Ok(())
    }
}

impl Solver {
    /// The external force `fext` at its equations in `ord`, ascending (dofs that are not free
    /// left out): what the assembly loads the unbalanced force with (`AssemblyContext::loads`).
    pub(crate) fn loads_at_equations(fext: &ExternalForce, ord: &Ordering) -> Vec<(usize, f64)> {
        let mut at: Vec<(usize, f64)> = (fext.0.iter())
            .filter(|&&(g, _)| ord.eq[g] != NOT_FREE)
            .map(|&(g, f)| (ord.eq[g] as usize, f))
            .collect();
        at.sort_unstable_by_key(|&(e, _)| e);
        at
    }

    /// The norm of the unbalanced force of `asm` (assembled, or reloaded, with the external
    /// force `fext`, whose sum of squares is `ext2`) and the reference force: the larger of
    /// the external force and the reactions (internal minus external force at the held dofs).
    pub(crate) fn residual_norms(
        &self,
        asm: &Assembled,
        fext: &ExternalForce,
        ext2: f64,
    ) -> (f64, f64) {
        let mut reac2 = 0.0;
        let mut loads = fext.0.iter().peekable();
        for (&g, &i) in self.dofs.held.iter().zip(&asm.held_internal) {
            while loads.next_if(|&&(d, _)| d < g).is_some() {}
            let f = match loads.peek() {
                Some(&&(d, f)) if d == g => f,
                _ => 0.0,
            };
            reac2 += (i - f) * (i - f);
        }
        let reference = ext2.sqrt().max(reac2.sqrt()).max(self.force_floor);
        (asm.unbalanced_norm2.sqrt(), reference)
    }

    /// The error for a node found deeper through a body than `max_penetration` at a converged
    /// pass (the increment is then cut back), if there is one.
    pub(crate) fn too_deep(&self, contacts: &ContactSet) -> Result<(), AttemptError> {
        match contacts.too_deep {
            Some((n, b, depth)) => Err(AttemptError::Failed(format!(
                "{} went {depth:.2} element lengths through {} before contact was detected",
                self.model.node_label(n),
                self.model.bodies[b].name
            ))),
            None => Ok(()),
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
        let p = &self.params;
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
    pub(crate) fn pass_failed(
        &self,
        rel: f64,
        floor: f64,
        pass_iter: usize,
        iterations: usize,
    ) -> Result<(), AttemptError> {
        let p = &self.params;
        if rel > p.divergence && pass_iter > 0 {
            return Err(AttemptError::Failed(format!(
                "diverged at iteration {iterations}: relative residual {rel:.3e}"
            )));
        }
        if pass_iter >= p.max_iterations {
            return Err(AttemptError::Failed(format!(
                "no convergence in {} iterations: relative residual {rel:.3e} (round-off floor {floor:.1e})",
                p.max_iterations
            )));
        }
        Ok(())
    }

    /// One attempt to reach (`target_p`, `target_lambda`) from the last converged state.
    /// `slide_off`: first slide off the free ends the contacts within that fraction of their
    /// element of one (`ContactSet::slide_off_tips`); the beam then springs back, a large
    /// motion for one Newton solve, so each correction is held to `SPRING_BACK_STEP` of the
    /// model's size.
    pub(crate) fn attempt(
        &self,
        target_p: &[f64],
        target_lambda: f64,
        increment: usize,
        slide_off: Option<f64>,
        obs: &mut dyn Observer,
    ) -> Result<Converged, AttemptError> {
        let p = &self.params;
        // The buffers of the last attempt (fresh memory would cost page faults).
        let (mut d, mut rhs) = {
            let mut spare = self.spare.borrow_mut();
            (std::mem::take(&mut spare.d), std::mem::take(&mut spare.rhs))
        };
        d.clear();
        d.extend_from_slice(&self.d);
        let mut contacts = self.contacts.clone();
        contacts.begin_attempt();
        let mut events = Vec::new();
        let mut max_step = p.max_step;
        if let Some(margin) = slide_off {
            contacts.slide_off_tips(self, &self.d, margin, increment, &mut events);
            max_step = max_step.min(SPRING_BACK_STEP * self.model_size());
        }
        // The prescribed increments, one per `Model::prescribed` (0 where a later one on the
        // same dof overrides it).
        let dp: Vec<f64> = (self.model.prescribed.iter().enumerate())
            .map(|(k, pr)| {
                let g = self.dofs.dof(pr.node, pr.dof.offset());
                if self.dofs.kind[g] == DofKind::Prescribed(k) {
                    target_p[k] - self.prescribed[k]
                } else {
                    0.0
                }
            })
            .collect();
        let fext = self.external_force(target_lambda);
        let ext2 = fext.sum_squares();
        let mut ordering = self.ordering_for(&contacts);
        let mut predictor = true;
        let mut iterations = 0;
        let mut log = IterationLog::default();
        let mut changes = 0;
        let mut pass_iter = 0;
        let mut last_step = 0.0;
        let mut springback = false;
        let mut stall = Stall::new();
        let mut bound = FloorBound::new(self.coordinate_scale(&d));
        // The stretch correction (`take_out_stretch`), and the displacements before each
        // update that it starts from.
        let correcting = self.stretch_correcting();
        let mut before = Vec::new();
        // Buffers reused by every iteration: the assembly (band tangent included) and the
        // right-hand side.
        let mut asm = Assembled::default();
        // The predictor's assembly is the last converged one when nothing differs: no contact
        // element and no prescribed increment (which would need the coupling K_fp dp).
        let mut reuse = false;
        if ordering.links.is_empty() && dp.iter().all(|v| *v == 0.0) {
            if let Some(kept) = self.converged_assembly.take(self.increment()) {
                asm = kept;
                asm.coupling.clear();
                reuse = asm
                    .tangent
                    .as_ref()
                    .is_some_and(|t| t.len() == ordering.n_eq);
            }
        }
        loop {
            let loads = Self::loads_at_equations(&fext, &ordering);
            let ctx = AssemblyContext {
                contact: p.contact_options(pass_iter + 1),
                loads: &loads,
                ..self.context(&ordering)
            };
            if std::mem::take(&mut reuse) {
                asm.reload(&loads);
            } else {
                assemble_into(&ctx, &d, true, predictor.then_some(dp.as_slice()), &mut asm);
            }
            let (norm, reference) = self.residual_norms(&asm, &fext, ext2);
            if springback && !predictor && !contacts.one_at_a_time {
                let released =
                    contacts.release_tensile(self, &asm, increment, iterations, &mut events);
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
                        active_contacts: contacts.active.len(),
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
                if accepted || settled {
                    let changed = contacts.after_convergence(
                        self,
                        &d,
                        &asm,
                        increment,
                        iterations,
                        &mut events,
                    );
                    self.too_deep(&contacts)?;
                    if changed == 0 && accepted {
                        let max_penetration = contacts.max_penetration(self, &d);
                        // Unfactored: the next increment's predictor may start from it.
                        asm.tangent = Some(tangent);
                        self.spare.borrow_mut().rhs = rhs;
                        return Ok(Converged {
                            max_penetration,
                            d,
                            contacts,
                            assembled: asm,
                            iterations,
                            iterations_8_orders: log.it8,
                            relative_residual: rel,
                            reference,
                            roundoff_floor: floor,
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
                }
                self.pass_failed(rel, floor, pass_iter, iterations)?;
            }
            // The unbalanced force is the right-hand side, which the solve overwrites; the next
            // assembly gets the last right-hand side's storage.
            std::mem::swap(&mut rhs, &mut asm.unbalanced);
            self.factor_and_solve(&mut tangent, &ordering, &mut rhs)?;
            asm.tangent = Some(tangent);
            let mut step2 = sum_squares(&rhs);
            if predictor {
                step2 += sum_squares(&dp);
            }
            let step = step2.sqrt();
            let scale = if step > max_step {
                max_step / step
            } else {
                1.0
            };
            if correcting {
                before.clear();
                before.extend_from_slice(&d);
            }
            ordering.add_scaled(&mut d, scale, &rhs);
            // No entry moved further than the (scaled) correction's norm; the predictor's
            // prescribed part, which is not scaled, by at most as much again.
            bound.moved(if predictor { 2.0 * step } else { scale * step });
            if predictor {
                for (pr, v) in self.model.prescribed.iter().zip(&dp) {
                    d[self.dofs.dof(pr.node, pr.dof.offset())] += v;
                }
                predictor = false;
            }
            if correcting {
                let factors = asm.tangent.as_ref().expect("factored");
                let moved = self.take_out_stretch(&before, &mut d, &ordering, factors, &mut rhs);
                bound.moved(moved);
            }
            iterations += 1;
            pass_iter += 1;
            let moved = contacts.transfer(self, &d, increment, iterations, false, &mut events);
            // A transfer during the iterations follows the iterate (the next iterate may move
            // the contact back): not an active-set change, so not counted as chattering.
            if moved > 0 {
                ordering = self.ordering_for(&contacts);
            }
            last_step = scale * step;
        }
    }

    /// Take the chords' second-order errors out of the update from `before` to `d`.
    ///
    /// A linear update moves an element's end j by dc relative to i: dl along the old chord e
    /// and l dpsi across it (n). The element meant by that is the old chord turned by dpsi and
    /// stretched by dl; the update instead puts the chord at `(l + dl) e + l dpsi n`, which is
    /// longer by about l dpsi^2 / 2 and turned by less (atan). Times EA/L and 12 EI / l^3, those
    /// gaps are spurious forces that on fine meshes of stiff beams dwarf the residual the
    /// update came to remove: Newton zig-zags (every other iterate is stretched), and load
    /// steps fail. The correction loads the tangent just factored with each element's elastic
    /// forces for its gap (its end j moved by the gap, rotations held) and adds the
    /// displacements they produce: on a structure free to take them up (a tree), the turned
    /// chords exactly, up to the geometric stiffness; where supports hold the chords, what
    /// the structure really gives. `buf` is scratch (the right-hand side's storage). Returns
    /// the norm of the displacements added.
    pub(crate) fn take_out_stretch(
        &self,
        before: &[f64],
        d: &mut [f64],
        ordering: &Ordering,
        factors: &BandMatrix,
        buf: &mut Vec<f64>,
    ) -> f64 {
        let first = &self.dofs.first;
        let nodes = &self.model.nodes;
        let at = |d: &[f64], n: usize| [nodes[n].x + d[first[n]], nodes[n].y + d[first[n] + 1]];
        buf.clear();
        buf.resize(ordering.n_eq, 0.0);
        let mut any = false;
        let beams = self.model.beams.iter().zip(&self.elements);
        for ((beam, el), eqs) in beams.zip(&ordering.beam_eqs) {
            let (pi, pj) = (at(before, beam.i), at(before, beam.j));
            let (qi, qj) = (at(d, beam.i), at(d, beam.j));
            let c = [pj[0] - pi[0], pj[1] - pi[1]];
            let l = c[0].hypot(c[1]);
            let e = [c[0] / l, c[1] / l];
            let dc = [qj[0] - qi[0] - c[0], qj[1] - qi[1] - c[1]];
            let stretched = l + e[0] * dc[0] + e[1] * dc[1];
            let turn = (e[0] * dc[1] - e[1] * dc[0]) / l;
            if turn == 0.0 || !turn.is_finite() {
                continue;
            }
            // The gap from the update's chord, `stretched e + l turn n`, to the meant one,
            // `stretched (cos turn e + sin turn n)`, along e and across it (written without
            // cancellation).
            let half = (0.5 * turn).sin();
            let gap_along = -2.0 * stretched * half * half;
            let sin = turn.sin();
            let gap_across = l * (sin - turn) + (stretched - l) * sin;
            // The element's elastic forces for its end j moved by the gap, rotations held.
            let k = el.constants();
            let axial = k.ka * gap_along;
            let moment = -(k.k11 + k.k12) * gap_across / l;
            let shear = -2.0 * moment / l;
            let force = [axial * e[0] - shear * e[1], axial * e[1] + shear * e[0]];
            for (slot, value) in [
                (0, -force[0]),
                (1, -force[1]),
                (2, moment),
                (3, force[0]),
                (4, force[1]),
                (5, moment),
            ] {
                if eqs[slot] != NOT_FREE {
                    buf[eqs[slot] as usize] += value;
                }
            }
            any = true;
        }
        if !any {
            return 0.0;
        }
        factors.solve(buf);
        ordering.add_scaled(d, 1.0, buf);
        sum_squares(buf).sqrt()
    }

    /// Add `more` contact state changes to `so_far`; too many in one increment is chattering.
    pub(crate) fn count_changes(&self, so_far: usize, more: usize) -> Result<usize, AttemptError> {
        let total = so_far + more;
        // Every candidate node may touch, let go and touch again (one change per pass once an
        // active set repeats); beyond that, the allowance is for chattering.
        if total > self.params.max_active_set_changes + 4 * self.candidate_nodes {
            return Err(AttemptError::Failed(format!(
                "{total} contact state changes in one increment (chattering)"
            )));
        }
        Ok(total)
    }

    /// The coordinate scale of state `d` and the round-off floor of the relative residual there:
    /// `eps max|K_ii| max|x| / reference`.
    pub(crate) fn roundoff_floor(
        &self,
        tangent: &BandMatrix,
        d: &[f64],
        reference: f64,
    ) -> (f64, f64) {
        let scale = self.coordinate_scale(d);
        (
            scale,
            f64::EPSILON * tangent.max_diagonal() * scale / reference,
        )
    }

    /// Factor the tangent in place and solve for `rhs` with it (in one pass where the band
    /// allows, `BandMatrix::factor_and_solve`); a vanishing pivot fails the attempt, naming its
    /// dof.
    pub(crate) fn factor_and_solve(
        &self,
        tangent: &mut BandMatrix,
        ord: &Ordering,
        rhs: &mut [f64],
    ) -> Result<(), AttemptError> {
        tangent.factor_and_solve(0.0, rhs).map_err(|sp| {
            AttemptError::Failed(format!(
                "singular tangent at {}",
                self.equation_label(ord, sp.equation)
            ))
        })
    }

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

    /// "node N u" for an equation number.
    pub(crate) fn equation_label(&self, ord: &Ordering, eq: usize) -> String {
        match ord.dof_of.get(eq) {
            Some(&g) => self.dof_label(g as usize),
            None => format!("equation {eq}"),
        }
    }
}

#[cfg(test)]
mod tests {
    use crate::solver::Silent;

    /// The predictor of a load-driven increment starts from the assembly kept at the last
    /// converged state instead of assembling that state again: the increment must come out
    /// identical, residual for residual and bit for bit, to one that assembles afresh.
    #[test]
    fn reusing_the_converged_assembly_changes_nothing() {
        let mut warm = crate::scaling::long_beam(300).solver().expect("stable");
        warm.step(&mut Silent).expect("converges");
        let kept = |s: &crate::solver::Solver| {
            s.converged_assembly
                .0
                .borrow()
                .as_ref()
                .is_some_and(|(i, asm)| *i == s.increment() && asm.tangent.is_some())
        };
        assert!(kept(&warm), "no assembly kept at the converged state");
        let mut fresh = warm.clone();
        fresh.converged_assembly = Default::default();
        for _ in 0..2 {
            let a = warm.step(&mut Silent).expect("converges");
            let b = fresh.step(&mut Silent).expect("converges");
            let (a, b) = (a.last().expect("record"), b.last().expect("record"));
            assert_eq!(a.iterations, b.iterations);
            let bits = |r: &crate::solver::IncrementRecord| {
                r.residuals
                    .iter()
                    .map(|i| i.residual.to_bits())
                    .collect::<Vec<_>>()
            };
            assert_eq!(bits(a), bits(b));
            assert_eq!(warm.d, fresh.d);
            fresh.converged_assembly = Default::default();
        }
    }

    /// The stretch correction on a tree at rest (its tangent the elastic stiffness): a linear
    /// update that turns every chord by its own angle (up to 0.3 rad; the update alone leaves
    /// the chords up to 4.4% too long and turned by atan t) comes out with every chord at its
    /// length and turned by exactly its angle, to 1e-12. Bernoulli-Euler (Mattiasson's
    /// cantilever) and Timoshenko (the pin's cantilever, G = 0.4 E) elements.
    #[test]
    fn stretch_correction_turns_the_chords_of_a_tree_exactly() {
        use crate::solver::assembly::assemble;
        for scene in ["mattiasson", "pin_on_cantilever"] {
            let s = crate::test_support::solver_after(scene, 0);
            let ord = s.ordering_for(&s.contacts);
            let rest = s.d.clone();
            let mut tangent = assemble(&s.context(&ord), &rest, true, None)
                .tangent
                .expect("tangent");
            tangent.factor(0.0).expect("regular");
            let first = &s.dofs.first;
            let at = |d: &[f64], n: usize| {
                let node = &s.model.nodes[n];
                [node.x + d[first[n]], node.y + d[first[n] + 1]]
            };
            let turns: Vec<f64> = (0..s.model.beams.len())
                .map(|e| 0.3 * (((e * 7) % 11) as f64 / 5.0 - 1.0))
                .collect();
            let mut d = rest.clone();
            let mut offset = [0.0, 0.0];
            for (b, t) in s.model.beams.iter().zip(&turns) {
                let (pi, pj) = (at(&rest, b.i), at(&rest, b.j));
                offset[0] -= t * (pj[1] - pi[1]);
                offset[1] += t * (pj[0] - pi[0]);
                d[first[b.j]] = offset[0];
                d[first[b.j] + 1] = offset[1];
            }
            let chord = |d: &[f64], b: &crate::solver::Beam| {
                let (i, j) = (at(d, b.i), at(d, b.j));
                [j[0] - i[0], j[1] - i[1]]
            };
            let chords = |d: &[f64]| -> Vec<(f64, f64)> {
                let beams = s.model.beams.iter();
                beams
                    .map(|b| {
                        let (c0, c1) = (chord(&rest, b), chord(d, b));
                        let l0 = c0[0].hypot(c0[1]);
                        let turn =
                            (c0[0] * c1[1] - c0[1] * c1[0]).atan2(c0[0] * c1[0] + c0[1] * c1[1]);
                        (c1[0].hypot(c1[1]) / l0 - 1.0, turn)
                    })
                    .collect()
            };
            let worst = |d: &[f64]| {
                (chords(d).iter().zip(&turns))
                    .map(|(&(strain, turn), t)| strain.abs().max((turn - t).abs()))
                    .fold(0.0f64, f64::max)
            };
            assert!(
                worst(&d) > 0.04,
                "{scene}: the update alone is off by {}",
                worst(&d)
            );
            let mut buf = Vec::new();
            s.take_out_stretch(&rest, &mut d, &ord, &tangent, &mut buf);
            assert!(worst(&d) < 1e-12, "{scene}: {}", worst(&d));
        }
    }

    /// The round-off floor's bound stands in for the floor where the floor cannot decide
    /// anything; it must never fall below it. From a loaded state of the Mattiasson cantilever,
    /// the coordinates move by random corrections (recorded by their largest entry) and the
    /// tangent is assembled again: the bound holds at every step, and is tight (within 1e-9)
    /// before any move, where the diagonal peak and the coordinate scale are exact.
    #[test]
    fn the_floor_bound_never_falls_below_the_floor() {
        use super::FloorBound;
        use crate::solver::assembly::assemble;
        let s = crate::test_support::solver_after("mattiasson", 3);
        let ord = s.ordering_for(&s.contacts);
        let mut d = s.d.clone();
        let mut bound = FloorBound::new(s.coordinate_scale(&d));
        let mut rng = crate::test_support::Rng(0x5eed_f100);
        for step in 0..20 {
            let asm = assemble(&s.context(&ord), &d, true, None);
            let tangent = asm.tangent.expect("tangent");
            let reference = 3.0;
            let (scale, floor) = s.roundoff_floor(&tangent, &d, reference);
            let (scale_bound, floor_bound) = bound.get(&tangent, reference);
            assert!(scale <= scale_bound && floor <= floor_bound, "step {step}");
            if step == 0 {
                assert!(
                    floor_bound <= floor * (1.0 + 1e-9),
                    "{floor_bound} vs {floor}"
                );
            }
            let size = 0.05 * (step % 4) as f64;
            let mut largest = 0.0f64;
            for v in d.iter_mut() {
                let dv = size * (rng.unit() - 0.5);
                *v += dv;
                largest = largest.max(dv.abs());
            }
            bound.moved(largest);
        }
    }
}
