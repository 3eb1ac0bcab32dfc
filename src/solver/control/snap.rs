//! Snap-through: where no step of the drive, however short, finds an equilibrium near the
//! last one (a limit point of the drive, past which the structure jumps), the drive is held
//! and the structure moves to the next stable state along a damped path, in pseudo-time
//! steps (`newton/viscous.rs`): each a backward-Euler step of `c w v + f_int(d) = f_ext` from
//! the last, found by the same Newton iteration and contact passes as any increment, checked
//! by the same acceptance rule and committed as a state marked
//! [`IncrementStatus::Snapping`], so that the history shows the snap and every state of it is
//! checked for pass-through. The viscosity c follows the motion: a step that moves a node
//! more than [`MAX_MOTION`] shortest element lengths, leaves a contact off its element or
//! bends an element beyond [`MAX_BEND`], is taken again with a stiffer one, and
//! one that moves less than [`MIN_MOTION`] lets the next go faster. The snap ends at the first
//! state in equilibrium without the viscous force: a step's own, or an attempt without it
//! from a state that hardly moves. A snap whose steps are all refused stops with what refused
//! the softest of them (the stiffer ones after it only hold the structure still): an element
//! bent too far names the body whose mesh is too coarse for the shape
//! ([`SolveError::MeshTooCoarse`]); a failed attempt gives its reason.

use std::time::Instant;

use super::solver::Solver;
use crate::solver::acceptance::most_bent;
use crate::solver::model::Dof;
use crate::solver::newton::{AttemptError, Constraint, Viscous};
use crate::solver::report::{Event, Flow, IncrementRecord, IncrementStatus, Observer, SolveError};

/// The most pseudo-time steps (committed or taken again) one snap may take.
const MAX_SNAP_STEPS: usize = 2000;
/// The most a node may move in one pseudo-time step, in shortest element lengths: well within
/// the depth at which a node found through a body cuts the step back
/// (`SolverParams::max_penetration`).
const MAX_MOTION: f64 = 0.2;
/// A step that moves no node further than this (in shortest element lengths) lets the next go
/// faster.
const MIN_MOTION: f64 = 0.05;
/// Below this motion (in shortest element lengths) the snap also tries the equilibrium itself,
/// without the viscous force, from the state it has reached.
const SETTLING: f64 = 0.01;

/// A contact of a snap's step that lies further than this fraction of its element beyond an
/// end of it (held there in the hollow of a kinked body) makes the step be taken again with a
/// stiffer viscosity: the contact element's shape is the element's own only over its length.
const OFF_ELEMENT: f64 = 0.05;

/// Whether a contact of attempt `c` lies beyond an end of its element by more than
/// [`OFF_ELEMENT`].
fn off_its_element(c: &crate::solver::newton::Converged) -> bool {
    (c.assembled.elements.contact_forces.iter())
        .any(|&(_, xi)| !(-OFF_ELEMENT..=1.0 + OFF_ELEMENT).contains(&xi))
}

/// The most an element's end may turn against its chord in a state of a snap (rad): a snap
/// that bends an element further goes where its mesh cannot follow, and stops.
const MAX_BEND: f64 = 0.5;

/// Steps of a snap that fail, or are refused (too long, a contact off its element, an element
/// bent too far), one after the other before it gives up: each is taken again with four times
/// the viscosity, so the last ones hardly move.
const MAX_FAILED_STEPS: usize = 12;

/// What refused the first step of the last run of refused steps: what the snap's softest
/// attempt met, before the viscosity grew to hold the structure still.
enum Refused {
    /// The attempt failed.
    Failed(AttemptError),
    /// The step bent an element (index) beyond [`MAX_BEND`] (rad).
    Bent(usize, f64),
    /// The step went too far, or left a contact off its element.
    TooFar,
}

/// How a snap ended.
pub(super) struct Snapped {
    /// The states committed, the last in equilibrium unless the observer stopped the run.
    pub records: Vec<IncrementRecord>,
    /// The observer asked to stop.
    pub stopped: bool,
}

impl Solver {
    /// Hold the drive at `targets` and `factors` (reached where the snap starts) and let the
    /// structure move to the next stable state. `why` is the reason the last attempt of the
    /// drive failed, after `cutbacks` cut-backs; `partial`: the targets are short of the scene
    /// step's.
    pub(super) fn snap(
        &mut self,
        targets: &[f64],
        factors: &[f64],
        partial: bool,
        (why, cutbacks): (String, usize),
        obs: &mut dyn Observer,
    ) -> Result<Snapped, SolveError> {
        let start = self.state.increment + 1;
        let shortest = (0..self.structure.model.beams.len())
            .map(|e| self.structure.model.beam_length(e))
            .fold(f64::INFINITY, f64::min);
        let weight: Vec<f64> = (0..self.structure.dofs.kind.len())
            .map(|g| match Dof::ALL[self.structure.dofs.owner(g).1] {
                Dof::Phi => shortest * shortest,
                Dof::U | Dof::V => 1.0,
            })
            .collect();
        // Stiff enough at first that the first step hardly moves: the axial stiffness.
        let mut c = self.structure.axial_stiffness;
        let mut out = Vec::new();
        let mut clock = Instant::now();
        let mut settle = false;
        let mut last_error = None;
        // How far the snap has gone (in shortest element lengths), and the viscosity of its
        // last failed step, which the next ones stay clear of.
        let mut travelled = 0.0;
        let mut failed_at = 0.0f64;
        let mut failed = 0;
        let mut first_refusal = None;
        for _ in 0..MAX_SNAP_STEPS {
            if failed >= MAX_FAILED_STEPS {
                break;
            }
            let number = self.state.increment + 1;
            let viscous = Viscous {
                c,
                anchor: &self.state.d,
                weight: &weight,
            };
            let constraint = Constraint::Prescribed { targets, factors };
            let damped = (!settle).then_some(&viscous);
            let attempt = (self.newton())
                .attempt(constraint, number, None, damped, false, obs)
                .and_then(|conv| {
                    let checked = self.acceptance(&conv)?;
                    Ok((conv, checked))
                });
            let (mut conv, checked) = match attempt {
                Ok(accepted) => accepted,
                Err(AttemptError::Stopped) => return Err(SolveError::Stopped),
                Err(e) => {
                    if !std::mem::take(&mut settle) {
                        if failed == 0 {
                            first_refusal = Some(Refused::Failed(e.clone()));
                        }
                        failed_at = failed_at.max(c);
                        c *= 4.0;
                        failed += 1;
                    }
                    last_error = Some(e);
                    continue;
                }
            };
            let motion = self.largest_motion(&conv.d) / shortest;
            let (element, turn) =
                most_bent(&self.structure.model, &self.structure.elements, &checked.1);
            let bent = turn > MAX_BEND;
            if motion > MAX_MOTION || bent || off_its_element(&conv) {
                if !std::mem::take(&mut settle) {
                    if failed == 0 {
                        first_refusal = Some(match bent {
                            true => Refused::Bent(element, turn),
                            false => Refused::TooFar,
                        });
                    }
                    c *= 4.0;
                    failed += 1;
                }
                continue;
            }
            failed = 0;
            first_refusal = None;
            if let Some(residual) = conv.equilibrium_residual {
                conv.relative_residual = residual;
            }
            if out.is_empty() {
                obs.event(&Event::Snaps {
                    increment: number,
                    reason: why.clone(),
                });
            }
            let done = !matches!(checked.0, IncrementStatus::Snapping { .. });
            let secs = clock.elapsed().as_secs_f64();
            let held = (targets.to_vec(), partial);
            let (rec, flow) = self.publish(conv, checked, held, 0, secs, obs);
            clock = Instant::now();
            out.push(rec);
            if flow == Flow::Stop || done {
                return Ok(Snapped {
                    records: out,
                    stopped: flow == Flow::Stop,
                });
            }
            travelled += motion;
            if motion < MIN_MOTION {
                c = (c * (motion / MIN_MOTION).max(1.0 / 16.0)).max(2.0 * failed_at);
            }
            failed_at *= 0.5;
            settle = motion < SETTLING && travelled > MAX_MOTION;
        }
        let number = self.state.increment + 1;
        // The reason is what met the softest attempt of the last run of refused steps: the
        // stiffer ones after it only hold the structure still.
        let telling = match first_refusal {
            Some(Refused::Bent(element, turn)) => {
                return Err(self.mesh_too_coarse(number, cutbacks, start, (element, turn)));
            }
            Some(Refused::Failed(e)) => Some(e),
            Some(Refused::TooFar) | None => None,
        };
        Err(match last_error {
            // A state refused for what it is stops the run as it would without the snap.
            Some(e) if !e.finds_no_state() => self.give_up(number, cutbacks, e),
            last => SolveError::NoConvergence {
                increment: number,
                cutbacks,
                reason: format!(
                    "the structure snaps from increment {start} and finds no stable state in {} steps{}",
                    number - start,
                    telling.or(last).map_or(String::new(), |e| format!(": {}", self.failure_reason(&e)))
                ),
            },
        })
    }

    /// The error of a snap from increment `start` that stops at increment `number` because
    /// every step bends an element (index, turn in rad) beyond [`MAX_BEND`].
    fn mesh_too_coarse(
        &self,
        number: usize,
        cutbacks: usize,
        start: usize,
        (element, turn): (usize, f64),
    ) -> SolveError {
        let model = &self.structure.model;
        let body = model.beams[element].body;
        SolveError::MeshTooCoarse {
            increment: number,
            cutbacks,
            snap_from: start,
            body: model.bodies[body].name.clone(),
            element: model.element_place(element),
            turn,
            limit: MAX_BEND,
        }
    }

    /// The largest distance a node moves from the converged state to displacements `d`.
    fn largest_motion(&self, d: &[f64]) -> f64 {
        (0..self.structure.model.nodes.len())
            .map(|n| {
                let g = self.structure.dofs.first[n];
                (d[g] - self.state.d[g]).hypot(d[g + 1] - self.state.d[g + 1])
            })
            .fold(0.0, f64::max)
    }
}
