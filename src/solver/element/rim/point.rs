//! The point of a beam's axis that a contact node standing off it presses on (`rim_point`:
//! c' = c - rim nu(t), a fixed point), and its derivative over the element's dofs
//! (`point_jacobian`), for the contact element at a distance (`mod.rs`) and its friction
//! (`friction.rs`).

use nalgebra::{DMatrix, Matrix2, Vector2};

use crate::solver::element::beam::{BeamElement, Chord};
use crate::solver::element::contact_law::{surface_turn, MAX_TURN};

/// Passes of the fixed point for c' at most; it contracts by `r |theta_j - theta_i| / l`, far
/// below 1 on any element within its small strains, and stops at round-off.
const PASSES: usize = 32;

/// Where a contact node at `c` with signed contact distance `rim` (side times distance) presses
/// on the axis of `beam` with ends at `ends` and rotations `phi`: the point c', its fraction
/// along the chord and the surface turn there.
pub fn rim_point(
    beam: &BeamElement,
    ends: ([f64; 2], [f64; 2]),
    phi: [f64; 2],
    c: [f64; 2],
    rim: f64,
) -> ([f64; 2], f64, f64) {
    let ch = Chord::new(ends.0, ends.1, beam.alpha0, 0.5 * (phi[0] + phi[1]));
    let (ti, tj) = (phi[0] - ch.beta, phi[1] - ch.beta);
    let fraction = |p: [f64; 2]| ((p[0] - ends.0[0]) * ch.c + (p[1] - ends.0[1]) * ch.s) * ch.inv_l;
    let mut p = c;
    let mut xi = fraction(p);
    let mut t = surface_turn(ti, tj, xi);
    let size = rim.abs() + ch.l;
    for _ in 0..PASSES {
        // The surface normal turned by t from the chord normal n = (-s, c).
        let (st, ct) = t.sin_cos();
        let nu = [-st * ch.c - ct * ch.s, -st * ch.s + ct * ch.c];
        let q = [c[0] - rim * nu[0], c[1] - rim * nu[1]];
        let moved = (q[0] - p[0]).hypot(q[1] - p[1]);
        p = q;
        xi = fraction(p);
        t = surface_turn(ti, tj, xi);
        if moved <= 1e-15 * size {
            break;
        }
    }
    (p, xi, t)
}

/// One contact element's points on the axis: the beam with its ends at `ends` and rotations
/// `phi`, and for each of its contact nodes the point it presses on (`rim_point`'s: c', its
/// fraction along the chord, the surface turn there) with its signed contact distance.
#[derive(Clone, Copy)]
pub struct RimPoints<'a> {
    /// The beam element.
    pub beam: &'a BeamElement,
    /// Its end positions (m).
    pub ends: ([f64; 2], [f64; 2]),
    /// Its end rotations (rad).
    pub phi: [f64; 2],
    /// Per contact node, `rim_point` of it.
    pub points: &'a [([f64; 2], f64, f64)],
    /// Per contact node, its signed contact distance (side times distance).
    pub rims: &'a [f64],
}

/// d(ends, c'_1..c'_k) / d(ends, c_1..c_k): the identity but in the rows of each c'.
pub fn point_jacobian(at: &RimPoints<'_>) -> DMatrix<f64> {
    let (beam, ends, phi, points, rims) = (at.beam, at.ends, at.phi, at.points, at.rims);
    let nd = 6 + 2 * points.len();
    let mut j = DMatrix::identity(nd, nd);
    let ch = Chord::new(ends.0, ends.1, beam.alpha0, 0.5 * (phi[0] + phi[1]));
    let (ti, tj) = (phi[0] - ch.beta, phi[1] - ch.beta);
    let (l, e) = (ch.l, Vector2::new(ch.c, ch.s));
    let d = Vector2::new(ends.1[0] - ends.0[0], ends.1[1] - ends.0[1]);
    for (m, (&(p, xi, t), &rim)) in points.iter().zip(rims).enumerate() {
        if rim == 0.0 {
            continue;
        }
        if t.abs() >= MAX_TURN {
            // The turn held at its bound: c' = c - rim nu(beta + t) turns with the chord
            // alone, dc' = dc + rim tau dbeta.
            let (st, ct) = t.sin_cos();
            let tau = e * ct + Vector2::new(-ch.s, ch.c) * st;
            let row = 6 + 2 * m;
            for (q, z) in ch.z.iter().enumerate() {
                j[(row, q)] += rim * tau[0] * z * ch.inv_l;
                j[(row + 1, q)] += rim * tau[1] * z * ch.inv_l;
            }
            continue;
        }
        let dtheta = tj - ti;
        // The surface normal's own angle is the chord's plus t, (1 - xi) phi_i + xi phi_j
        // and a constant: its gradient over the end dofs with c' held is
        // (1 - xi) e_phi_i + xi e_phi_j + dtheta grad xi (the chord's turn cancels).
        let a = Vector2::new(p[0] - ends.0[0], p[1] - ends.0[1]);
        let l2 = d.dot(&d);
        let gd = (a - d * (2.0 * xi)) / l2;
        let ga = d / l2;
        let mut g = [0.0; 6];
        for k in 0..2 {
            g[k] = dtheta * (-ga[k] - gd[k]);
            g[3 + k] = dtheta * gd[k];
        }
        g[2] += 1.0 - xi;
        g[5] += xi;
        // (I - kappa tau e^T) dc' = dc + rim tau g^T du, kappa = rim dtheta / l.
        let (st, ct) = t.sin_cos();
        let tau = e * ct + Vector2::new(-ch.s, ch.c) * st;
        let kappa = rim * dtheta / l;
        let inv = Matrix2::identity() + tau * e.transpose() * (kappa / (1.0 - kappa * ct));
        let row = 6 + 2 * m;
        for q in 0..nd {
            let mut rhs = Vector2::zeros();
            if q < 6 {
                rhs += tau * (rim * g[q]);
            } else if q == row || q == row + 1 {
                rhs[q - row] = 1.0;
            }
            let col = inv * rhs;
            j[(row, q)] = col[0];
            j[(row + 1, q)] = col[1];
        }
    }
    j
}

/// The worst entry of tangent `k` at the dofs `u0` against central differences (step 1e-6) of
/// the nodal forces `nodal`, relative to the tangent's largest entry: the error and its row
/// and column. For the tangent tests of the elements off the axis.
#[cfg(test)]
pub(crate) fn tangent_error(
    nodal: impl Fn(&[f64]) -> nalgebra::DVector<f64>,
    k: &DMatrix<f64>,
    u0: &[f64],
) -> (f64, usize, usize) {
    let h = 1e-6;
    let scale = k.amax();
    let mut worst = (0.0, 0, 0);
    for q in 0..u0.len() {
        let (mut up, mut um) = (u0.to_vec(), u0.to_vec());
        up[q] += h;
        um[q] -= h;
        let fd = (nodal(&up) - nodal(&um)) / (2.0 * h);
        for p in 0..u0.len() {
            let err = (fd[p] - k[(p, q)]).abs() / scale;
            if err > worst.0 {
                worst = (err, p, q);
            }
        }
    }
    worst
}
