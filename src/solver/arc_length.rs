//! Arc-length increment control (Crisfield's cylindrical arc length, Riks-type predictor) for
//! load-driven scenes: the load factor becomes an unknown, every increment moves a fixed length
//! `ds` along the equilibrium path in displacement space, so limit points (snap-through,
//! snap-back of the load) are passed without the Newton tangent's singularity stopping the run.
//!
//! Prescribed displacements are held at their current values. Contacts follow the same rules as
//! in `newton`: transfers during iterations, activation and release at converged passes.

use std::time::Instant;

use super::assembly::{assemble_into, Assembled, AssemblyContext, DofKind};
use super::control::Solver;
use super::newton::{AttemptError, Converged, IterationLog, Stall};
use super::report::{Event, IncrementRecord, IterationRecord, Observer, SolveError};

/// Where the arc-length control stands between increments.
#[derive(Clone, Debug, Default)]
pub struct ArcState {
    /// Arc length of the next increment (shrinks on failure, regrows to the nominal length).
    pub ds: Option<f64>,
    /// The last converged increment of the displacements (all dofs), for the sign of the next
    /// predictor (the path keeps its direction through limit points).
    pub last: Option<Vec<f64>>,
}

/// Dot product.
fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

impl Solver {
    /// One arc-length increment of the scene's nominal length `params.arc_length` (or less after
    /// a failure; the length is halved on every failed attempt and doubled back after an easy
    /// increment). Returns the converged increment. Errors if the model has no loads.
    pub fn arc_length_step(
        &mut self,
        obs: &mut dyn Observer,
    ) -> Result<Vec<IncrementRecord>, SolveError> {
        let nominal = self.params.arc_length.ok_or_else(|| SolveError::Invalid {
            reason: "arc-length control needs control.arc_length".into(),
        })?;
        if self.model.loads.is_empty() {
            return Err(SolveError::Invalid {
                reason: "arc-length control needs at least one load".into(),
            });
        }
        let mut ds = self.arc.ds.unwrap_or(nominal);
        let mut cutbacks = 0;
        let clock = Instant::now();
        loop {
            let number = self.increment() + 1;
            let accepted = self
                .arc_attempt(ds, number, obs)
                .and_then(|(conv, lambda)| {
                    let checked = self.acceptance(&conv)?;
                    Ok((conv, lambda, checked))
                });
            match accepted {
                Ok((conv, lambda, checked)) => {
                    let before = self.displacements().to_vec();
                    let easy = conv.iterations <= 6;
                    let p = self.prescribed_values().to_vec();
                    let secs = clock.elapsed().as_secs_f64();
                    let rec = self.commit(conv, checked, p, lambda, cutbacks, secs);
                    let dd: Vec<f64> = self.d.iter().zip(&before).map(|(a, b)| a - b).collect();
                    self.arc.last = Some(dd);
                    self.arc.ds = Some(if easy { (2.0 * ds).min(nominal) } else { ds });
                    for e in &rec.events {
                        obs.event(e);
                    }
                    let _ = obs.increment(&rec);
                    return Ok(vec![rec]);
                }
                Err(AttemptError::Stopped) => return Err(SolveError::Stopped),
                Err(e) => {
                    cutbacks += 1;
                    if cutbacks > self.params.max_cutbacks {
                        return Err(self.give_up(number, cutbacks - 1, e));
                    }
                    let reason = self.failure_reason(&e);
                    ds *= 0.5;
                    self.arc.ds = Some(ds);
                    obs.event(&Event::CutBack {
                        increment: number,
                        reason,
                        fraction: ds / nominal,
                    });
                }
            }
        }
    }

    /// One arc-length attempt of length `ds` from the converged state: the converged state and
    /// its load factor.
    fn arc_attempt(
        &self,
        ds: f64,
        increment: usize,
        obs: &mut dyn Observer,
    ) -> Result<(Converged, f64), AttemptError> {
        let p = &self.params;
        // The arc is the root-mean-square change of the free dofs: the same length means the
        // same path spacing on any mesh.
        let n_free = self
            .dofs
            .kind
            .iter()
            .filter(|k| **k == DofKind::Free)
            .count();
        let ds = ds * (n_free.max(1) as f64).sqrt();
        let mut d = self.d.clone();
        let mut lambda = self.load_factor;
        let mut contacts = self.contacts.clone();
        contacts.begin_attempt();
        let mut ordering = self.ordering_for(&contacts);
        let fref = self.external_force(1.0).dense(self.dofs.len());
        // Free-dof vectors are kept over all dofs (zero at supports and prescribed dofs).
        let free = |g: usize| self.dofs.kind[g] == DofKind::Free;
        let mut dd = vec![0.0; d.len()];
        let mut iterations = 0;
        let mut pass_iter = 0;
        let mut log = IterationLog::default();
        let mut events = Vec::new();
        let mut changes = 0;
        let mut predictor = true;
        let mut stall = Stall::new();
        let mut last_step = f64::INFINITY;
        // The assembly buffers (band tangent included) are reused by every iteration.
        let mut asm = Assembled::default();
        loop {
            let fext = self.external_force(lambda);
            let loads = Self::loads_at_equations(&fext, &ordering);
            let ctx = AssemblyContext {
                contact: p.contact_options(pass_iter + 1),
                loads: &loads,
                ..self.context(&ordering)
            };
            assemble_into(&ctx, &d, true, None, &mut asm);
            let (norm, reference) = self.residual_norms(&asm, &fext, fext.sum_squares());
            let rhs = asm.unbalanced.clone();
            let mut tangent = asm.tangent.take().expect("tangent requested");
            let (scale, floor) = self.roundoff_floor(&tangent, &d, reference);
            if !predictor {
                let rel = norm / reference;
                log.record(
                    obs,
                    IterationRecord {
                        increment,
                        iteration: iterations,
                        residual: norm,
                        relative_residual: rel,
                        reference,
                        step_norm: dot(&dd, &dd).sqrt(),
                        active_contacts: contacts.active.len(),
                    },
                )?;
                let at_floor = stall.at_floor(rel, floor, ordering.n_eq, last_step, scale);
                if self.equilibrium_reached(rel, floor, at_floor)? {
                    let changed = contacts.after_convergence(
                        self,
                        &d,
                        &asm,
                        increment,
                        iterations,
                        &mut events,
                    );
                    self.too_deep(&contacts)?;
                    if changed == 0 {
                        let max_penetration = contacts.max_penetration(self, &d);
                        let conv = Converged {
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
                        };
                        return Ok((conv, lambda));
                    }
                    changes = self.count_changes(changes, changed)?;
                    ordering = self.ordering_for(&contacts);
                    pass_iter = 0;
                    stall = Stall::new();
                    continue;
                }
                self.pass_failed(rel, floor, pass_iter, iterations)?;
            }
            // Displacement responses to the unbalanced force and to the reference load.
            let mut qr = rhs;
            self.factor_and_solve(&mut tangent, &ordering, &mut qr)?;
            let mut qf = vec![0.0; ordering.n_eq];
            for (g, e) in ordering.free_dofs() {
                if free(g) {
                    qf[e] = fref[g];
                }
            }
            tangent.solve(&mut qf);
            asm.tangent = Some(tangent);
            let scatter = |v: &[f64]| {
                let mut out = vec![0.0; self.dofs.len()];
                for (g, e) in ordering.free_dofs() {
                    out[g] = v[e];
                }
                out
            };
            let (qf, qr) = (scatter(&qf), scatter(&qr));
            let delta = if predictor {
                // Riks predictor along the tangent, in the direction of the last increment
                // (Feng's criterion), so the path turns round limit points instead of going back.
                let size = dot(&qf, &qf).sqrt();
                if size == 0.0 || !size.is_finite() {
                    return Err(AttemptError::Failed(
                        "arc length: the reference load does no work on the free dofs".into(),
                    ));
                }
                let sign = match &self.arc.last {
                    Some(last_d) if dot(last_d, &qf) < 0.0 => -1.0,
                    _ => 1.0,
                };
                log.r0 = Some((ds / size) * dot(&fref, &fref).sqrt());
                sign * ds / size
            } else {
                // The correction keeps |dd| = ds: a quadratic in the load-factor correction; the
                // root that turns the increment least is taken.
                let a: Vec<f64> = dd.iter().zip(&qr).map(|(x, y)| x + y).collect();
                let a1 = dot(&qf, &qf);
                let a2 = 2.0 * dot(&qf, &a);
                let a3 = dot(&a, &a) - ds * ds;
                let disc = a2 * a2 - 4.0 * a1 * a3;
                if disc < 0.0 || a1 == 0.0 {
                    return Err(AttemptError::Failed(format!(
                        "arc length: no real root at iteration {iterations}"
                    )));
                }
                let sq = disc.sqrt();
                let roots = [(-a2 + sq) / (2.0 * a1), (-a2 - sq) / (2.0 * a1)];
                let turn = |r: f64| {
                    let new: f64 = dd
                        .iter()
                        .zip(a.iter().zip(&qf))
                        .map(|(o, (x, f))| o * (x + r * f))
                        .sum();
                    new
                };
                if turn(roots[0]) >= turn(roots[1]) {
                    roots[0]
                } else {
                    roots[1]
                }
            };
            let mut step2 = 0.0;
            for g in 0..d.len() {
                let step = if predictor {
                    delta * qf[g]
                } else {
                    qr[g] + delta * qf[g]
                };
                d[g] += step;
                dd[g] += step;
                step2 += step * step;
            }
            last_step = step2.sqrt();
            lambda += delta;
            predictor = false;
            iterations += 1;
            pass_iter += 1;
            let moved = contacts.transfer(self, &d, increment, iterations, false, &mut events);
            // A transfer during the iterations follows the iterate: not counted as chattering.
            if moved > 0 {
                ordering = self.ordering_for(&contacts);
            }
        }
    }
}
