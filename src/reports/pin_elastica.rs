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
//!
//! "Normal to the beam" needs care with shear. The pin's force is a jump of the shear force,
//! so the shear strain jumps at s_c by g and the centreline has a kink there: on the loaded side
//! its tangent is (x', y') above, beyond s_c (no force, no strain) it is the section's direction
//! (cos t, sin t). A frictionless pin in the kink may push along any normal between the two,
//! and the continuum leaves the choice open (a rounded pin or a spread load would settle it).
//! The contact element settles it by its chord: its force is normal to the chord i-j, which
//! on a fine mesh is the mean of the two tangents weighted by the lengths li and lj on either
//! side of the pin. So the reference takes a share w of the kink (`kink_share`: the normal is
//! to `(1 + e) (cos t, sin t) + w g (-sin t, cos t)`), and w = li / l reproduces the element's
//! choice. The force's spread over w in [0, 1] is of the order of the shear strain g (here
//! about 5e-6 of the force); without shear (Bernoulli-Euler) there is no kink and w does not
//! matter.
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

/// A tangent of the centreline at a section of angle `t` carrying the force `f` on its loaded
/// side: the section's direction, stretched by the axial strain and turned by the share `w` of
/// the shear strain. `w = 1` is the loaded side's tangent (x', y'); `w = 0` the unloaded side's
/// at the pin; between, the normals a frictionless pin in the kink may push along.
fn tangent(t: f64, f: [f64; 2], k: Stiffness, w: f64) -> [f64; 2] {
    let (c, s) = (t.cos(), t.sin());
    let stretch = 1.0 + (f[0] * c + f[1] * s) / k.ea;
    let shear = w * (f[1] * c - f[0] * s) / k.gae;
    [stretch * c - shear * s, stretch * s + shear * c]
}

/// State (x, y, t, m) at s_c for the unknowns `u` = (F_x, F_y, m_0, s_c), integrated in
/// `steps` steps.
fn shoot(u: [f64; 4], k: Stiffness, steps: usize) -> [f64; 4] {
    let [fx, fy, m0, sc] = u;
    let rate = |z: [f64; 4]| {
        let [dx, dy] = tangent(z[2], [fx, fy], k, 1.0);
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

/// The four conditions at s_c (zero when met), scaled to comparable sizes. A pin of radius
/// `radius` touches the beam's parallel curve: its centre lies `radius` from the contact
/// point along the beam's normal on the pin's side (left of the beam's direction).
fn conditions(
    u: [f64; 4],
    (pin, radius): ([f64; 2], f64),
    k: Stiffness,
    length: f64,
    w: f64,
) -> [f64; 4] {
    let z = shoot(u, k, STEPS);
    let scale = u[0].hypot(u[1]).max(f64::MIN_POSITIVE);
    let [dx, dy] = tangent(z[2], [u[0], u[1]], k, w);
    let (nx, ny) = if radius == 0.0 {
        (0.0, 0.0)
    } else {
        let norm = dx.hypot(dy);
        (-dy / norm * radius, dx / norm * radius)
    };
    [
        (z[0] + nx - pin[0]) / length,
        (z[1] + ny - pin[1]) / length,
        z[3] / (scale * length),
        (u[0] * dx + u[1] * dy) / (scale * dx.hypot(dy)),
    ]
}

/// The state where a pin at `pin` (below the undeformed beam, 0 < pin x < `length`) holds a
/// cantilever of the given length and stiffnesses `k`, the pin's force normal to the share
/// `kink_share` (0 to 1) of the shear kink under it (see the module's comment; a contact
/// element takes li / l). `None` if the shooting does not converge (the pin off the beam's
/// reach, or past its tip).
pub fn pin_on_cantilever(
    pin: [f64; 2],
    length: f64,
    k: Stiffness,
    kink_share: f64,
) -> Option<PinContact> {
    rim_on_cantilever((pin, 0.0), length, k, kink_share)
}

/// `pin_on_cantilever` for a pin of radius `radius` (the pin's centre at `pin`, above the
/// beam): the contact on the beam's parallel curve at that distance, the force along the
/// normal through the pin's centre.
pub fn rim_on_cantilever(
    (pin, radius): ([f64; 2], f64),
    length: f64,
    k: Stiffness,
    kink_share: f64,
) -> Option<PinContact> {
    // Start from small-deflection theory: a tip load at the pin's distance.
    let a = pin[0];
    let p = -3.0 * k.ei * (pin[1] - radius) / a.powi(3);
    let mut u = [0.0, -p, -p * a, a];
    for _ in 0..60 {
        let g = conditions(u, (pin, radius), k, length, kink_share);
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
            let gp = conditions(v, (pin, radius), k, length, kink_share);
            v[j] = u[j] - du;
            let gm = conditions(v, (pin, radius), k, length, kink_share);
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
        let r = pin_on_cantilever([a, -delta], 1.0, k, 0.0).expect("converges");
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
        let table = crate::reports::work_precision::MATTIASSON;
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

    /// The pin of the report's last increment on its section (EA L^2 / EI = 1e6, G Ae = 0.4
    /// EA).
    fn large_deflection() -> ([f64; 2], Stiffness) {
        let k = Stiffness {
            ea: 1e6,
            ei: 1.0,
            gae: 4e5,
        };
        ([0.7, -0.299], k)
    }

    /// Large deflection: the solution meets its four conditions when integrated again with
    /// twice the steps (so the step does not matter at this accuracy), the clamp moment is the
    /// moment of the pin's force about the clamp (global equilibrium), and the force is normal
    /// to a beam sloping down (here to the section: share 0), so it leans toward the clamp.
    #[test]
    fn large_deflection_meets_its_conditions() {
        let (pin, k) = large_deflection();
        let r = pin_on_cantilever(pin, 1.0, k, 0.0).expect("converges");
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

    /// The kink's share: at w = 1 the force is normal to the loaded side's tangent (x', y'),
    /// at w = 0 to the section's direction. The two forces differ by about the shear strain
    /// g = |F| / G Ae (a normal turned by g turns the force by g): between g / 2 and 2 g
    /// (measured 1.02 g, g = 5.1e-6 here). Halfway is their mean to O(g^2) (asserted 1e-9 of
    /// the force, measured 1.5e-12). Without shear the share changes nothing.
    #[test]
    fn kink_share_spans_the_shear_strain() {
        let (pin, k) = large_deflection();
        let at = |w: f64| pin_on_cantilever(pin, 1.0, k, w).expect("converges");
        let (r0, r1, rh) = (at(0.0), at(1.0), at(0.5));
        let u = [r1.force[0], r1.force[1], r1.clamp_moment, r1.arc];
        let z = shoot(u, k, STEPS);
        let [dx, dy] = tangent(z[2], r1.force, k, 1.0);
        let p = r1.force[0].hypot(r1.force[1]);
        assert!((r1.force[0] * dx + r1.force[1] * dy).abs() < 1e-12 * p);
        let g = p / k.gae;
        let spread = (r1.force[0] - r0.force[0]).hypot(r1.force[1] - r0.force[1]) / p;
        assert!(
            spread > g / 2.0 && spread < 2.0 * g,
            "spread {spread:e}, g {g:e}"
        );
        for i in 0..2 {
            let mean = 0.5 * (r0.force[i] + r1.force[i]);
            assert!(
                (rh.force[i] - mean).abs() < 1e-9 * p,
                "{:?} {mean}",
                rh.force
            );
        }
        let rigid = Stiffness {
            gae: f64::INFINITY,
            ..k
        };
        let (b0, b1) = (
            pin_on_cantilever(pin, 1.0, rigid, 0.0).expect("converges"),
            pin_on_cantilever(pin, 1.0, rigid, 1.0).expect("converges"),
        );
        assert_eq!(b0, b1);
    }
}
