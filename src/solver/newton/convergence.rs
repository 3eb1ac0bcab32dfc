//! When a Newton pass has converged, stalled or failed: the record of every iteration
//! (`IterationLog`), the round-off stagnation test (`Stall`) and the bound of the round-off
//! floor that stands in for it where it cannot decide (`FloorBound`).

use super::failure::AttemptError;
use crate::solver::linear::BandMatrix;
use crate::solver::params::SolverParams;
use crate::solver::report::{Flow, IterationRecord, Observer};

/// A residual within this factor of the round-off floor counts as stagnated.
pub(super) const STAGNATION: f64 = 10.0;

/// Iterations without halving the best residual, below the round-off floor estimate, after
/// which an attempt counts as converged to round-off.
const STALL_ITERATIONS: usize = 3;

/// ... and once the displacement correction has shrunk below this fraction of the coordinates.
const STALL_STEP: f64 = 1e-10;

/// Units in the last place of the coordinates that a correction may come to, on the average
/// over its entries (its norm within `ROUNDOFF_ULPS eps sqrt(n)` of their size), and still be
/// round-off: such a correction moves the state by little more than its coordinates resolve,
/// so one iteration without halving the residual after it is a stall. So is one after a
/// larger correction (still below `STALL_STEP` of the coordinates) where the next correction,
/// extrapolated from the last two at their own rate of contraction (`step^2 / previous`),
/// comes to that: Newton's corrections contract at least as fast as that (linearly at the
/// rate seen, or faster), so what is left to correct lies below what the coordinates resolve.
/// The residual must have stopped halving too: in the stiff directions of a contact it can
/// still fall tenfold an iteration under corrections that small.
const ROUNDOFF_ULPS: f64 = 16.0;

/// The factor by which the round-off of a residual norm over `n_eq` equations can exceed the
/// floor estimate, which is that of one equation (`eps max|K_ii| |x|`): each equation rounds
/// on its own, and the norm sums their squares, so up to sqrt(n_eq).
fn norm_spread(n_eq: usize) -> f64 {
    (n_eq.max(1) as f64).sqrt()
}

/// Round-off stagnation of one Newton pass: once the residual has stopped falling (no halving
/// of the best value for `STALL_ITERATIONS` iterations, or for one where the last correction
/// was round-off itself, or where the next one would be: `ROUNDOFF_ULPS` of the coordinates
/// on the average) while the corrections have vanished, and lies within `STAGNATION` times
/// the round-off a residual norm over all the equations can have (the floor estimate times
/// `norm_spread`), Newton cannot get closer: the state is accepted and its residual reported.
pub(crate) struct Stall {
    best: f64,
    count: usize,
    /// The correction before the last one recorded (infinite before the second).
    previous: f64,
}

impl Stall {
    pub(crate) fn new() -> Stall {
        Stall {
            best: f64::INFINITY,
            count: 0,
            previous: f64::INFINITY,
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
        let roundoff_step = ROUNDOFF_ULPS * f64::EPSILON * norm_spread(n_eq) * scale;
        let next = if self.previous.is_finite() && step < self.previous {
            step * (step / self.previous)
        } else {
            f64::INFINITY
        };
        self.previous = step;
        let stalled =
            self.count >= STALL_ITERATIONS || (self.count >= 1 && step.min(next) <= roundoff_step);
        stalled && rel <= STAGNATION * norm_spread(n_eq) * floor && step <= STALL_STEP * scale
    }
}

/// An upper bound of the round-off floor over one attempt, at no cost per iteration: the band's
/// diagonal peak ([`BandMatrix::diagonal_peak`], at least max|K_ii|) and the coordinate scale at
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
    /// What the solve adds to the tangent's diagonal beyond the assembly: a snap's viscous
    /// stiffness, whose force rounds as the elements' do.
    diagonal: f64,
}

impl FloorBound {
    pub(crate) fn new(start: f64) -> FloorBound {
        FloorBound {
            start,
            moved: 0.0,
            diagonal: 0.0,
        }
    }

    /// Count `extra` on the tangent's diagonal (a snap's viscous stiffness `c w`, its largest).
    pub(crate) fn add_diagonal(&mut self, extra: f64) {
        self.diagonal += extra;
    }

    /// What the solve adds to the tangent's diagonal beyond the assembly.
    pub(crate) fn extra_diagonal(&self) -> f64 {
        self.diagonal
    }

    /// Record a correction of the coordinates by at most `largest` in any entry.
    pub(crate) fn moved(&mut self, largest: f64) {
        self.moved += largest;
    }

    /// (coordinate scale, round-off floor), both bounds from above.
    pub(crate) fn get(&self, tangent: &BandMatrix, reference: f64) -> (f64, f64) {
        // A margin for the round-off of the sums above (relative 1e-16 each).
        let scale = (self.start + self.moved) * (1.0 + 1e-12);
        let floor = f64::EPSILON * (tangent.diagonal_peak() + self.diagonal) * scale / reference;
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
        params: &SolverParams,
        pass_iter: usize,
    ) -> bool {
        let widest = (STAGNATION * norm_spread(tangent.len())).max(params.roundoff_factor);
        !(rel > params.tolerance
            && pass_iter < params.max_iterations
            && rel > widest * self.get(tangent, reference).1)
    }
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
            return Err(AttemptError::NonFinite { iteration });
        }
        if self.it8.is_none() && self.r0.is_some_and(|r0| norm <= 1e-8 * r0) {
            self.it8 = Some(iteration);
        }
        Ok(())
    }
}
