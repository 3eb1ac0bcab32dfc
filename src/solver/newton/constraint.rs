//! The constraint that closes the equations of a Newton increment, and the update it makes of
//! each solve: prescribed displacements and a fixed load factor (displacement and load control:
//! a linear predictor for the prescribed increment, then plain Newton corrections), or an arc
//! of given length along the equilibrium path with the load factor an unknown (Crisfield's
//! cylindrical arc length with a Riks-type predictor, so that limit points are passed).

use super::convergence::{FloorBound, IterationLog};
use super::failure::AttemptError;
use super::iteration::Newton;
use crate::solver::assembly::{add_carried, DofKind, ExternalForce, Ordering};
use crate::solver::linear::reduce::sum_squares;
use crate::solver::linear::BandMatrix;

/// What closes an increment's equations.
#[derive(Clone, Copy, Debug)]
pub enum Constraint<'a> {
    /// The prescribed displacements reach `targets` (one per `Model::prescribed`) and the load
    /// factors are `factors` (one per load group).
    Prescribed {
        /// Target values of the prescribed displacements.
        targets: &'a [f64],
        /// Target load factors.
        factors: &'a [f64],
    },
    /// The free dofs move by `ds` (root-mean-square over the free dofs, so that one length
    /// means one path spacing on any mesh) from the converged state; the prescribed
    /// displacements are held.
    Arc {
        /// Arc length.
        ds: f64,
    },
}

/// A constraint set up for one attempt, with what it carries from iteration to iteration.
pub(super) enum Path {
    /// See [`Constraint::Prescribed`].
    Prescribed {
        /// The prescribed increments, one per [`Model::prescribed`] (0 where a later one on the
        /// same dof overrides it).
        dp: Vec<f64>,
        factors: Vec<f64>,
        fext: ExternalForce,
    },
    /// See [`Constraint::Arc`].
    Arc {
        /// The arc length over all the free dofs.
        ds: f64,
        lambda: f64,
        /// `lambda` for every load group (a run with one load factor).
        factors: Vec<f64>,
        /// The reference load over all dofs.
        fref: Vec<f64>,
        /// The increment so far over all dofs (0 at dofs that are not free).
        dd: Vec<f64>,
        fext: ExternalForce,
    },
}

/// Dot product.
fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

impl Path {
    /// `c` set up from the converged state of `n`.
    pub(super) fn new(c: Constraint<'_>, n: &Newton<'_>) -> Path {
        match c {
            Constraint::Prescribed { targets, factors } => {
                let dp = (n.structure.model.prescribed.iter().enumerate())
                    .map(|(k, pr)| {
                        let g = n.structure.dofs.dof(pr.node, pr.dof.offset());
                        if n.structure.dofs.kind[g] == DofKind::Prescribed(k) {
                            targets[k] - n.state.prescribed[k]
                        } else {
                            0.0
                        }
                    })
                    .collect();
                let fext = n.structure.external_force(factors);
                Path::Prescribed {
                    dp,
                    factors: factors.to_vec(),
                    fext,
                }
            }
            Constraint::Arc { ds } => {
                let n_free = (n.structure.dofs.kind.iter())
                    .filter(|k| **k == DofKind::Free)
                    .count();
                let lambda = n.state.load_factors[0];
                let factors = n.structure.model.uniform_factors(lambda);
                Path::Arc {
                    ds: ds * (n_free.max(1) as f64).sqrt(),
                    lambda,
                    fref: (n
                        .structure
                        .external_force(&n.structure.model.uniform_factors(1.0)))
                    .dense(n.structure.dofs.len()),
                    dd: vec![0.0; n.state.d.len()],
                    fext: n.structure.external_force(&factors),
                    factors,
                }
            }
        }
    }

    /// The prescribed increments the predictor applies (none for arc length).
    pub(super) fn dp(&self) -> Option<&[f64]> {
        match self {
            Path::Prescribed { dp, .. } => Some(dp),
            Path::Arc { .. } => None,
        }
    }

    /// Whether the predictor's assembly is the converged state's: no prescribed increment.
    pub(super) fn starts_at_the_converged_state(&self) -> bool {
        self.dp().is_none_or(|dp| dp.iter().all(|v| *v == 0.0))
    }

    /// The load factors of the current iterate, one per load group.
    pub(super) fn load_factors(&self) -> &[f64] {
        match self {
            Path::Prescribed { factors, .. } | Path::Arc { factors, .. } => factors,
        }
    }

    /// The external force at the current load factor.
    pub(super) fn external_force(&self) -> &ExternalForce {
        match self {
            Path::Prescribed { fext, .. } | Path::Arc { fext, .. } => fext,
        }
    }

    /// Apply the update of one solve to `d`: `rhs` holds the tangent's response to the
    /// unbalanced force, `tangent` is factored. A prescribed path scales its correction down to
    /// `max_step`; the predictor adds the prescribed increments. An arc path adds the response
    /// to the reference load that keeps the arc length (the predictor's sign follows the last
    /// increment, `last`). Returns the norm of the update; records it in `bound`, and the
    /// predictor's residual scale in `log`.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn update(
        &mut self,
        n: &Newton<'_>,
        predictor: bool,
        ordering: &Ordering,
        tangent: &BandMatrix,
        rhs: &[f64],
        (d, residue): (&mut [f64], &mut [f64]),
        max_step: f64,
        iterations: usize,
        log: &mut IterationLog,
        bound: &mut FloorBound,
    ) -> Result<f64, AttemptError> {
        match self {
            Path::Prescribed { dp, .. } => {
                let mut step2 = sum_squares(rhs);
                if predictor {
                    step2 += sum_squares(dp);
                }
                let step = step2.sqrt();
                let scale = if step > max_step {
                    max_step / step
                } else {
                    1.0
                };
                ordering.add_scaled((&mut *d, &mut *residue), scale, rhs);
                // No entry moved further than the (scaled) correction's norm; the predictor's
                // prescribed part, which is not scaled, by at most as much again.
                bound.moved(if predictor { 2.0 * step } else { scale * step });
                if predictor {
                    // Every dof a prescribed value holds: its own, and those of the nodes that
                    // move with it (`Node::moves_with`).
                    for &g in &n.structure.dofs.held {
                        if let DofKind::Prescribed(k) = n.structure.dofs.kind[g] {
                            add_carried(&mut d[g], &mut residue[g], dp[k]);
                        }
                    }
                }
                Ok(scale * step)
            }
            Path::Arc {
                ds,
                lambda,
                factors,
                fref,
                dd,
                fext,
            } => {
                let ds = *ds;
                // Displacement responses to the unbalanced force and to the reference load,
                // over all dofs.
                let mut qf = vec![0.0; ordering.n_eq];
                for (g, e) in ordering.free_dofs() {
                    if n.structure.dofs.kind[g] == DofKind::Free {
                        qf[e] = fref[g];
                    }
                }
                tangent.solve(&mut qf);
                let scatter = |v: &[f64]| {
                    let mut out = vec![0.0; n.structure.dofs.len()];
                    for (g, e) in ordering.free_dofs() {
                        out[g] = v[e];
                    }
                    out
                };
                let (qf, qr) = (scatter(&qf), scatter(rhs));
                let delta = if predictor {
                    // Riks predictor along the tangent, in the direction of the last increment
                    // (Feng's criterion), so the path turns round limit points instead of going
                    // back.
                    let size = dot(&qf, &qf).sqrt();
                    if size == 0.0 || !size.is_finite() {
                        return Err(AttemptError::NoLoadPath);
                    }
                    let sign = match &n.state.arc.last {
                        Some(last_d) if dot(last_d, &qf) < 0.0 => -1.0,
                        _ => 1.0,
                    };
                    log.r0 = Some((ds / size) * dot(fref, fref).sqrt());
                    sign * ds / size
                } else {
                    arc_root(dd, &qr, &qf, ds).ok_or(AttemptError::NoArcRoot {
                        iteration: iterations,
                    })?
                };
                let mut step2 = 0.0;
                for g in 0..d.len() {
                    let step = if predictor {
                        delta * qf[g]
                    } else {
                        qr[g] + delta * qf[g]
                    };
                    add_carried(&mut d[g], &mut residue[g], step);
                    dd[g] += step;
                    step2 += step * step;
                }
                *lambda += delta;
                factors.fill(*lambda);
                *fext = n.structure.external_force(factors);
                let step = step2.sqrt();
                bound.moved(step);
                Ok(step)
            }
        }
    }

    /// Whether the path keeps count of moves made outside `update` (`moved`).
    pub(super) fn counts_moves(&self) -> bool {
        matches!(self, Path::Arc { .. })
    }

    /// `d` moved from `before` outside `update` (the stretch correction): an arc path counts
    /// the move in its increment.
    pub(super) fn moved(&mut self, before: &[f64], d: &[f64]) {
        if let Path::Arc { dd, .. } = self {
            for ((x, b), a) in dd.iter_mut().zip(before).zip(d) {
                *x += a - b;
            }
        }
    }
}

/// The load-factor correction that keeps the increment `dd + qr + delta qf` at length `ds`: a
/// quadratic in `delta`; of its roots, the one that turns the increment least. None if it has
/// no real root.
fn arc_root(dd: &[f64], qr: &[f64], qf: &[f64], ds: f64) -> Option<f64> {
    let a: Vec<f64> = dd.iter().zip(qr).map(|(x, y)| x + y).collect();
    let a1 = dot(qf, qf);
    let a2 = 2.0 * dot(qf, &a);
    let a3 = dot(&a, &a) - ds * ds;
    let disc = a2 * a2 - 4.0 * a1 * a3;
    if disc < 0.0 || a1 == 0.0 {
        return None;
    }
    let sq = disc.sqrt();
    let roots = [(-a2 + sq) / (2.0 * a1), (-a2 - sq) / (2.0 * a1)];
    let turn = |r: f64| -> f64 {
        dd.iter()
            .zip(a.iter().zip(qf))
            .map(|(o, (x, f))| o * (x + r * f))
            .sum()
    };
    Some(if turn(roots[0]) >= turn(roots[1]) {
        roots[0]
    } else {
        roots[1]
    })
}
