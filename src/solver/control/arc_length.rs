//! Arc-length increment control for load-driven scenes: every increment moves a fixed length
//! along the equilibrium path in displacement space with the load factor an unknown
//! ([`Constraint::Arc`]), so limit points (snap-through, snap-back of the load) are passed
//! without the tangent's singularity stopping the run. The length is halved on a failed
//! attempt and doubled back after an easy increment. The Newton iteration is the same as for
//! the other controls (`newton::Newton::attempt`).

use std::time::Instant;

use super::increments::GROW_ITERATIONS;
use super::solver::Solver;
use crate::solver::newton::{AttemptError, Constraint};
use crate::solver::report::{Event, IncrementRecord, Observer, SolveError};

impl Solver {
    /// One arc-length increment of the scene's nominal length `params.arc_length` (or less
    /// after a failure). Returns the converged increment. Errors if the model has no loads.
    pub fn arc_length_step(
        &mut self,
        obs: &mut dyn Observer,
    ) -> Result<Vec<IncrementRecord>, SolveError> {
        let nominal = self
            .structure
            .params
            .arc_length
            .ok_or_else(|| SolveError::Invalid {
                reason: "arc-length control needs control.arc_length".into(),
            })?;
        if self.structure.model.has_followers() {
            return Err(SolveError::Invalid {
                reason: "follower loads cannot be traced by arc length: use load control".into(),
            });
        }
        if !self.structure.model.has_loads() {
            return Err(SolveError::Invalid {
                reason: "arc-length control needs at least one load".into(),
            });
        }
        let mut ds = self.state.arc.ds.unwrap_or(nominal);
        let mut cutbacks = 0;
        let clock = Instant::now();
        loop {
            let number = self.increment() + 1;
            let accepted = (self.newton())
                .attempt(Constraint::Arc { ds }, number, None, None, false, obs)
                .and_then(|conv| {
                    let checked = self.acceptance(&conv)?;
                    Ok((conv, checked))
                });
            match accepted {
                Ok((conv, checked)) => {
                    let before = self.displacements().to_vec();
                    let easy = conv.iterations <= GROW_ITERATIONS;
                    let p = self.prescribed_values().to_vec();
                    let secs = clock.elapsed().as_secs_f64();
                    let rec = self.commit(conv, checked, (p, false), cutbacks, secs);
                    let dd = (self.state.d.iter().zip(&before))
                        .map(|(a, b)| a - b)
                        .collect();
                    self.state.arc.last = Some(dd);
                    self.state.arc.ds = Some(if easy { (2.0 * ds).min(nominal) } else { ds });
                    self.keep_checkpoint();
                    for e in &rec.events {
                        obs.event(e);
                    }
                    // One increment per call: a Stop from the observer ends the run here.
                    let _ = obs.increment(&rec);
                    return Ok(vec![rec]);
                }
                Err(AttemptError::Stopped) => return Err(SolveError::Stopped),
                Err(e) => {
                    cutbacks += 1;
                    if cutbacks > self.structure.params.max_cutbacks {
                        return Err(self.give_up(number, cutbacks - 1, e));
                    }
                    let reason = self.failure_reason(&e);
                    ds *= 0.5;
                    self.state.arc.ds = Some(ds);
                    obs.event(&Event::CutBack {
                        increment: number,
                        reason,
                        fraction: ds / nominal,
                    });
                    if !std::mem::replace(&mut self.state.cut_back, true)
                        && self
                            .structure
                            .params
                            .stretch_correction
                            .on_after_a_cut_back()
                    {
                        obs.event(&Event::StretchCorrectionOn { increment: number });
                    }
                }
            }
        }
    }
}
