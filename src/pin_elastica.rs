//! The converged reference of the work-precision report's contact problem, worked out without
//! the finite elements: a cantilever pushed down by a frictionless pin, as Reissner's plane beam
//! (axial strain N / EA, shear strain Q / G Ae for a Timoshenko beam, none for Bernoulli-Euler),
//! solved by shooting. The clamp is at the origin, the beam along +x; the pin, at a given
//! position, touches the beam at an unknown material point s_c and pushes on it with a force
//! normal to the beam there. Beyond s_c the beam carries nothing and stays straight.
//!
//! Along 0 <= s <= s_c (undeformed arc length), with F the force on the beam at s_c (so the
//! section force everywhere there), and t the section's angle:
//!
//! `x' = (1 + e) cos t - g sin t`, `y' = (1 + e) sin t + g cos t`, `t' = m / EI`,
//! `m' = y' F_x - x' F_y`, with `e = (F_x cos t + F_y sin t) / EA` and
//! `g = (F_y cos t - F_x sin t) / G Ae`,
//!
//! from x = y = t = 0 and m = m_0 at the clamp. Four unknowns (F_x, F_y, m_0, s_c) meet four
//! conditions at s_c: the pin's position (two), no moment, and a force normal to the beam.
//! Classical Runge-Kutta over a fixed number of steps and Newton on the four conditions (a
//! finite-difference Jacobian, the crate's dense solve) find them to round-off.

use crate::solver::linear::dense_solve;

/// The reference state of the pin problem.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PinContact {
    /// Force of the pin on the beam (N).
    pub force: [f64; 2],
    /// Material (undeformed) arc length from the clamp to the contact point (m).
    pub arc: f64,
    /// Clamp moment (N m).
    pub clamp_moment: f64,
}

/// Runge-Kutta steps along the loaded part: the global error goes as the fourth power of the
/// step, about 1e-16 here for curvatures of order 1/L.
const STEPS: usize = 4000;

/// The beam's stiffnesses: axial EA, bending EI, shear G Ae (infinite: no shear strain, as
/// Bernoulli-Euler).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Stiffness {
    /// EA (N).
    pub ea: f64,
    /// EI (N m^2).
    pub ei: f64,
    /// G Ae (N).
    pub gae: f64,
}

/// State (x, y, t, m) at s_c for the unknowns `u` = (F_x, F_y, m_0, s_c), integrated in
/// `steps` steps.
fn shoot(u: [f64; 4], k: Stiffness, steps: usize) -> [f64; 4] {
    let [fx, fy, m0, sc] = u;
    let rate = |z: [f64; 4]| {
        let (c, s) = (z[2].cos(), z[2].sin());
        let stretch = 1.0 + (fx * c + fy * s) / k.ea;
        let shear = (fy * c - fx * s) / k.gae;
        let (dx, dy) = (stretch * c - shear * s, stretch * s + shear * c);
        [dx, dy, z[3] / k.ei, dy * fx - dx * fy]
    };
    let h = sc / steps as f64;
    let mut z = [0.0, 0.0, 0.0, m0];
    let along = |z: [f64; 4], k: [f64; 4], a: f64| std::array::from_fn(|i| z[i] + a * k[i]);
    for _ in 0..steps {
        let k1 = rate(z);
        let k2 = rate(along(z, k1, h / 2.0));
        let k3 = rate(along(z, k2, h / 2.0));
        let k4 = rate(along(z, k3, h));
        z = std::array::from_fn(|i| z[i] + h / 6.0 * (k1[i] + 2.0 * (k2[i] + k3[i]) + k4[i]));
    }
    z
}

/// The four conditions at s_c (zero when met), scaled to comparable sizes.
fn conditions(u: [f64; 4], pin: [f64; 2], k: Stiffness, length: f64) -> [f64; 4] {
    let z = shoot(u, k, STEPS);
    let scale = u[0].hypot(u[1]).max(f64::MIN_POSITIVE);
    [
        (z[0] - pin[0]) / length,
        (z[1] - pin[1]) / length,
        z[3] / (scale * length),
        (u[0] * z[2].cos() + u[1] * z[2].sin()) / scale,
    ]
}

/// The state where a pin at `pin` (below the undeformed beam, 0 < pin x < `length`) holds a
/// cantilever of the given length and stiffnesses `k`. `None` if the shooting does not converge
/// (the pin off the beam's reach, or past its tip).
pub fn pin_on_cantilever(pin: [f64; 2], length: f64, k: Stiffness) -> Option<PinContact> {
    // Start from small-deflection theory: a tip load at the pin's distance.
    let a = pin[0];
    let p = -3.0 * k.ei * pin[1] / a.powi(3);
    let mut u = [0.0, -p, -p * a, a];
    for _ in 0..60 {
        let g = conditions(u, pin, k, length);
        let size = g.iter().map(|v| v.abs()).fold(0.0, f64::max);
        if size < 1e-14 {
            let out = PinContact {
                force: [u[0], u[1]],
                arc: u[3],
                clamp_moment: u[2],
            };
            return (u[3] < length).then_some(out);
        }
        let mut jac = [[0.0; 4]; 4];
        for j in 0..4 {
            let du = 1e-7 * u[j].abs().max(1e-3);
            let mut v = u;
            v[j] += du;
            let gp = conditions(v, pin, k, length);
            v[j] = u[j] - du;
            let gm = conditions(v, pin, k, length);
            for i in 0..4 {
                jac[i][j] = (gp[i] - gm[i]) / (2.0 * du);
            }
        }
        let rows: Vec<f64> = jac.iter().flatten().copied().collect();
        let step = dense_solve(4, &rows, &g.map(|v| -v))?;
        // Damped where the linear guess is far off: at most a quarter of the length along s.
        let damp = (0.25 * length / step[3].abs().max(f64::MIN_POSITIVE)).min(1.0);
        for j in 0..4 {
            u[j] += damp * step[j];
        }
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Small deflection: the force is the linear cantilever's 3 EI delta / a^3 at the pin's
    /// distance a (to the relative size of the neglected terms, delta^2 / a^2), and the
    /// contact point is the pin's x to second order.
    #[test]
    fn small_deflection_is_the_linear_cantilever() {
        let (a, delta) = (0.6, 1e-5);
        let k = Stiffness {
            ea: 1e12,
            ei: 1.0,
            gae: f64::INFINITY,
        };
        let r = pin_on_cantilever([a, -delta], 1.0, k).expect("converges");
        let p = 3.0 * delta / a.powi(3);
        assert!((r.force[1] + p).abs() < 1e-8 * p, "{:?} vs {p}", r.force);
        assert!(r.force[0].abs() < 1e-3 * p, "{:?}", r.force);
        assert!((r.arc - a).abs() < 1e-9, "{}", r.arc);
        assert!(
            (r.clamp_moment + p * a).abs() < 1e-8 * p * a,
            "{}",
            r.clamp_moment
        );
    }

    /// The integration against a published table: Mattiasson's cantilever under a dead tip
    /// load P (k = P L^2 / EI) is this system with s_c = L and F = (0, -P); only the clamp
    /// moment is unknown (no moment at the tip), found here by bisection. The tip
    /// displacements must match the table's nine digits.
    #[test]
    fn tip_load_matches_mattiasson() {
        let table = crate::work_precision::MATTIASSON;
        for (k, u_ref, w_ref) in table {
            let stiff = Stiffness {
                ea: f64::INFINITY,
                ei: 1.0,
                gae: f64::INFINITY,
            };
            let tip_moment = |m0: f64| shoot([0.0, -k, m0, 1.0], stiff, STEPS)[3];
            // The first sign change of the tip moment below m_0 = 0 brackets the primary
            // branch (the least bent); bisection closes it.
            let mut a = 0.0;
            let mut b = -0.05 * k;
            while tip_moment(a).signum() == tip_moment(b).signum() {
                (a, b) = (b, b - 0.05 * k);
            }
            for _ in 0..200 {
                let c = 0.5 * (a + b);
                if c == a || c == b {
                    break;
                }
                if tip_moment(c).signum() == tip_moment(a).signum() {
                    a = c;
                } else {
                    b = c;
                }
            }
            let z = shoot([0.0, -k, b, 1.0], stiff, STEPS);
            assert!(
                (1.0 - z[0] - u_ref).abs() < 2e-9,
                "k {k}: u/L {}",
                1.0 - z[0]
            );
            assert!((-z[1] - w_ref).abs() < 2e-9, "k {k}: w/L {}", -z[1]);
        }
    }

    /// Large deflection: the solution meets its four conditions when integrated again with
    /// twice the steps (so the step does not matter at this accuracy), the clamp moment is the
    /// moment of the pin's force about the clamp (global equilibrium), and the force is normal
    /// to a beam sloping down, so it leans toward the clamp.
    #[test]
    fn large_deflection_meets_its_conditions() {
        let pin = [0.7, -0.299];
        let k = Stiffness {
            ea: 1e6,
            ei: 1.0,
            gae: 4e5,
        };
        let r = pin_on_cantilever(pin, 1.0, k).expect("converges");
        let u = [r.force[0], r.force[1], r.clamp_moment, r.arc];
        let z = shoot(u, k, 2 * STEPS);
        let p = r.force[0].hypot(r.force[1]);
        assert!(
            (z[0] - pin[0]).abs() < 1e-12 && (z[1] - pin[1]).abs() < 1e-12,
            "{z:?}"
        );
        assert!(z[3].abs() < 1e-12 * p, "{z:?}");
        assert!((r.force[0] * z[2].cos() + r.force[1] * z[2].sin()).abs() < 1e-12 * p);
        let m0 = pin[0] * r.force[1] - pin[1] * r.force[0];
        assert!(
            (r.clamp_moment - m0).abs() < 1e-12 * m0.abs(),
            "{} {m0}",
            r.clamp_moment
        );
        assert!(r.force[0] < 0.0 && r.force[1] < 0.0, "{:?}", r.force);
        assert!(r.arc > pin[0] && r.arc < 1.0, "{}", r.arc);
    }
}
