//! Displacement and load control: a scene step advances the prescribed displacements and the
//! load factor, or goes to the next point of the model's load path; a step that finds no
//! equilibrium is halved (reported as cut-back events) and grows again once Newton has it easy,
//! with one last attempt that slides contacts off the tips they are about to leave, then a snap
//! (`snap.rs`) where no step finds an equilibrium.

use std::time::Instant;

use super::solver::Solver;
use crate::solver::newton::{AttemptError, Constraint};
use crate::solver::report::{Event, Flow, IncrementRecord, Observer, SolveError};

/// A contact within this fraction of its element from a free end slides off it when the
/// increment finds no equilibrium after every cut-back ([`Solver::advance_to`]).
const TIP_SLIDE_OFF: f64 = 1e-2;

/// A sub-increment that converged in at most this many iterations lets the next one double.
pub(super) const GROW_ITERATIONS: usize = 6;

impl Solver {
    /// Advance by one scene step: to the next point of the model's load path if it has one
    /// (nothing past its end), else prescribed values += per_step and load factor +=
    /// load_per_step; or by one arc length if `params.arc_length` is set.
    pub fn step(&mut self, obs: &mut dyn Observer) -> Result<Vec<IncrementRecord>, SolveError> {
        if self.structure.params.arc_length.is_some() {
            return self.arc_length_step(obs);
        }
        let Some((targets, factors)) = self.step_targets() else {
            return Ok(Vec::new());
        };
        let stage =
            (self.structure.model.path.as_ref()).and_then(|p| p.locate(self.state.path_step));
        self.marching = stage.map(|(s, _)| s);
        let out = self.advance_to(&targets, &factors, obs);
        self.marching = None;
        // A step the observer stopped halfway is taken again, toward the same point.
        if stage.is_some() && self.state.prescribed == targets && self.state.load_factors == factors
        {
            self.state.path_step += 1;
        }
        out
    }

    /// Where one scene step from the converged state goes: the next point of the load path,
    /// or every prescribed value moved by its `per_step` and the load factor by
    /// `load_per_step`. None past the end of the path.
    pub fn step_targets(&self) -> Option<(Vec<f64>, Vec<f64>)> {
        if let Some(path) = &self.structure.model.path {
            let point = path.point(self.state.path_step)?;
            return Some((point.prescribed, point.factors));
        }
        let targets = (self.structure.model.prescribed.iter())
            .zip(&self.state.prescribed)
            .map(|(p, v)| v + p.per_step)
            .collect();
        let factors = (self.state.load_factors.iter())
            .map(|l| l + self.structure.model.load_per_step)
            .collect();
        Some((targets, factors))
    }

    /// Advance from the converged state to the given prescribed values and load factors (one
    /// per load group), halving the increment on failure (at most `max_cutbacks` times in all).
    /// Returns the converged increments (more than one if the step was cut back).
    pub fn advance_to(
        &mut self,
        targets: &[f64],
        factors: &[f64],
        obs: &mut dyn Observer,
    ) -> Result<Vec<IncrementRecord>, SolveError> {
        let start_p = self.state.prescribed.clone();
        let start_l = self.state.load_factors.clone();
        let mut done = 0.0f64;
        let mut h = 1.0f64;
        let mut cutbacks = 0;
        let mut out = Vec::new();
        let mut clock = Instant::now();
        // Set for the attempt that first slides contacts off the tips they are about to leave.
        let mut slide_off = None;
        // Whether the next attempt sticks the slips its predictor turns back: every other
        // attempt after a failed one, so that a cut-back tries both (`Newton::attempt`).
        let mut unload_slips = false;
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
            let tl: Vec<f64> = if next >= 1.0 {
                factors.to_vec()
            } else {
                (start_l.iter().zip(factors))
                    .map(|(a, b)| a + next * (b - a))
                    .collect()
            };
            let number = self.state.increment + 1;
            let constraint = Constraint::Prescribed {
                targets: &tp,
                factors: &tl,
            };
            let accepted = (self.newton())
                .attempt(constraint, number, slide_off, None, unload_slips, obs)
                .and_then(|conv| {
                    let checked = self.acceptance(&conv)?;
                    Ok((conv, checked))
                });
            match accepted {
                Ok((conv, checked)) => {
                    slide_off = None;
                    unload_slips = false;
                    // After a cut-back the sub-increment grows again (doubles) once Newton has
                    // it easy, so one hard moment does not leave the rest of the step in
                    // tiny pieces.
                    if conv.iterations <= GROW_ITERATIONS && h < 1.0 {
                        h *= 2.0;
                    }
                    let secs = clock.elapsed().as_secs_f64();
                    let targets = (tp, next < 1.0);
                    let (rec, flow) = self.publish(conv, checked, targets, cutbacks, secs, obs);
                    clock = Instant::now();
                    done = next;
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
                    if h <= 0.5f64.powi(self.structure.params.max_cutbacks as i32) {
                        if slide_off.is_none() && self.has_contact_near_a_tip(number) {
                            slide_off = Some(TIP_SLIDE_OFF);
                            continue;
                        }
                        // A step refused for what it found (a crossing, a feature through a
                        // body) stops here. A body that touches itself snaps as any other: a
                        // snap's steps move no node more than a fifth of an element, and each
                        // is checked for sides as a drive's step is.
                        if !self.structure.params.snap || !e.finds_no_state() {
                            return Err(self.give_up(number, cutbacks, e));
                        }
                        // No step finds an equilibrium near this one: the structure snaps.
                        slide_off = None;
                        let why = self.failure_reason(&e);
                        let snapped = self.snap(&tp, &tl, next < 1.0, (why, cutbacks), obs)?;
                        out.extend(snapped.records);
                        if snapped.stopped {
                            return Ok(out);
                        }
                        clock = Instant::now();
                        done = next;
                        continue;
                    }
                    let reason = self.failure_reason(&e);
                    unload_slips = !unload_slips;
                    cutbacks += 1;
                    h *= 0.5;
                    obs.event(&Event::CutBack {
                        increment: number,
                        reason,
                        fraction: h,
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
        Ok(out)
    }

    /// Whether a contact of the converged state lies within `TIP_SLIDE_OFF` of a free end.
    fn has_contact_near_a_tip(&self, increment: usize) -> bool {
        let mut contacts = self.state.contacts.clone();
        let d = &self.state.d;
        contacts.slide_off_tips(&self.view(), d, TIP_SLIDE_OFF, increment, &mut Vec::new()) > 0
    }
}
