//! The 2-node TSM beam element (Bernoulli-Euler or Timoshenko): chord kinematics from total
//! coordinates, the element force equation S = k e in the chord frame, nodal forces U = J S and
//! the exact tangent J k J^T + K_G.

use nalgebra::{SMatrix, SVector};

use super::angle::chord_angle;
use crate::solver::linear::symmetric6;
use crate::solver::model::Section;

/// 6x6 matrix over the dofs (u_i, v_i, phi_i, u_j, v_j, phi_j).
pub type Mat6 = SMatrix<f64, 6, 6>;
/// 6-vector over the dofs (u_i, v_i, phi_i, u_j, v_j, phi_j).
pub type Vec6 = SVector<f64, 6>;

/// Current chord of an element: length, direction, rotation and its first derivatives.
#[derive(Clone, Copy, Debug)]
pub struct Chord {
    /// Current chord length l.
    pub l: f64,
    /// 1 / l.
    pub inv_l: f64,
    /// cos of the current chord angle.
    pub c: f64,
    /// sin of the current chord angle.
    pub s: f64,
    /// Chord rotation beta (current minus initial angle), unwrapped.
    pub beta: f64,
    /// dl/du = (-c, -s, 0, c, s, 0).
    pub r: Vec6,
    /// l dbeta/du = (s, -c, 0, -s, c, 0).
    pub z: Vec6,
}

/// Unwrap a raw chord rotation so that it lies within pi of `reference`.
///
/// Using the mean rotation of the element's end nodes as the reference makes the unwrapping
/// stateless and continuous for any number of turns, as long as the element itself deforms by
/// less than half a turn (small strain).
#[inline]
pub fn unwrap_angle(raw: f64, reference: f64) -> f64 {
    let two_pi = std::f64::consts::TAU;
    let turns = (reference - raw) / two_pi;
    // Within half a turn (the usual case) there is nothing to round: skip the libm call.
    if turns.abs() < 0.5 {
        return raw + two_pi * 0.0f64.copysign(turns);
    }
    raw + two_pi * turns.round()
}

impl Chord {
    /// Chord from the current end positions, the initial chord angle `alpha0` and a reference
    /// rotation for unwrapping (the mean end rotation).
    #[inline(always)]
    pub fn new(xi: [f64; 2], xj: [f64; 2], alpha0: f64, reference: f64) -> Chord {
        let (dx, dy) = (xj[0] - xi[0], xj[1] - xi[1]);
        let l = (dx * dx + dy * dy).sqrt();
        let inv_l = 1.0 / l;
        let (c, s) = (dx * inv_l, dy * inv_l);
        let beta = unwrap_angle(chord_angle(dy, dx) - alpha0, reference);
        Chord {
            l,
            inv_l,
            c,
            s,
            beta,
            r: Vec6::new(-c, -s, 0.0, c, s, 0.0),
            z: Vec6::new(s, -c, 0.0, -s, c, 0.0),
        }
    }

    /// The part of the geometric stiffness that comes from N and the end moments:
    /// `N/l z z^T + (Mi + Mj)/l^2 (r z^T + z r^T)`.
    pub fn geometric_stiffness(&self, n: f64, m_sum: f64) -> Mat6 {
        let zz = self.z * self.z.transpose();
        let rz = self.r * self.z.transpose();
        zz * (n / self.l) + (rz + rz.transpose()) * (m_sum / (self.l * self.l))
    }
}

/// A 2-node beam element ready to evaluate: initial geometry and stiffnesses.
#[derive(Clone, Copy, Debug)]
pub struct BeamElement {
    /// Initial length L.
    pub length: f64,
    /// Initial chord angle.
    pub alpha0: f64,
    /// Section stiffnesses.
    pub section: Section,
    /// Shear parameter Psi = EI/(G Ae); 0 for Bernoulli-Euler.
    pub psi: f64,
}

/// What a beam element returns for one configuration.
#[derive(Clone, Copy, Debug)]
pub struct BeamResponse {
    /// Element deformations (dl, theta_i, theta_j).
    pub deformation: [f64; 3],
    /// Element forces S = (N, Mi, Mj).
    pub forces: [f64; 3],
    /// Nodal forces U = J S over (u_i, v_i, phi_i, u_j, v_j, phi_j).
    pub nodal: Vec6,
    /// Tangent stiffness J k J^T + K_G (if requested).
    pub tangent: Option<Mat6>,
}

impl BeamElement {
    /// Element from its initial end positions.
    pub fn new(xi: [f64; 2], xj: [f64; 2], section: Section, psi: f64) -> BeamElement {
        let (dx, dy) = (xj[0] - xi[0], xj[1] - xi[1]);
        BeamElement {
            length: dx.hypot(dy),
            alpha0: chord_angle(dy, dx),
            section,
            psi,
        }
    }

    /// The bending part of the element force equation: [[k11, k12], [k12, k11]] with
    /// `EI/(L(1+p)) [[4+p, 2-p], [2-p, 4+p]]`, `p = 12 Psi / L^2`.
    pub fn bending_stiffness(&self) -> (f64, f64) {
        let l = self.length;
        let p = 12.0 * self.psi / (l * l);
        let f = self.section.ei / (l * (1.0 + p));
        (f * (4.0 + p), f * (2.0 - p))
    }

    /// Element forces, nodal forces and (optionally) the tangent at the given total state.
    /// `ui`, `uj` are the current positions; `phi_i`, `phi_j` the total node rotations.
    pub fn response(
        &self,
        xi: [f64; 2],
        xj: [f64; 2],
        phi_i: f64,
        phi_j: f64,
        with_tangent: bool,
    ) -> BeamResponse {
        let mut k = [[0.0; 6]; 6];
        let mut r = self.evaluate(xi, xj, phi_i, phi_j, with_tangent.then_some(&mut k));
        r.tangent = with_tangent.then(|| Mat6::from_fn(|a, b| k[a][b]));
        r
    }

    /// The constants of the element force equation, worked out once.
    pub fn constants(&self) -> ForceConstants {
        let (k11, k12) = self.bending_stiffness();
        ForceConstants {
            length: self.length,
            alpha0: self.alpha0,
            ka: self.section.ea / self.length,
            k11,
            k12,
        }
    }

    /// `response` for the assembly: the tangent, if wanted, is written row by row into `k`
    /// (the returned `tangent` is `None`), with no 6x6 temporaries.
    #[inline(always)]
    pub fn evaluate(
        &self,
        xi: [f64; 2],
        xj: [f64; 2],
        phi_i: f64,
        phi_j: f64,
        k: Option<&mut [[f64; 6]; 6]>,
    ) -> BeamResponse {
        let (r, t) = self
            .constants()
            .evaluate_entries(xi, xj, phi_i, phi_j, k.is_some());
        if let (Some(k), Some(t)) = (k, t) {
            t.write(k);
        }
        r
    }
}

/// What the element force equation needs of a beam, its divisions done once: the initial
/// length and chord angle, EA/L and the bending pair (k11, k12) (see `bending_stiffness`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ForceConstants {
    /// Initial length L.
    pub length: f64,
    /// Initial chord angle.
    pub alpha0: f64,
    /// Axial stiffness EA/L.
    pub ka: f64,
    /// Bending stiffness on the diagonal.
    pub k11: f64,
    /// Bending stiffness off the diagonal.
    pub k12: f64,
}

impl ForceConstants {
    /// [`BeamElement::evaluate`] with these constants, the tangent (if wanted) as its distinct
    /// entries (for the assembly).
    #[inline(always)]
    pub fn evaluate_entries(
        &self,
        xi: [f64; 2],
        xj: [f64; 2],
        phi_i: f64,
        phi_j: f64,
        with_tangent: bool,
    ) -> (BeamResponse, Option<TangentEntries>) {
        let ch = Chord::new(xi, xj, self.alpha0, 0.5 * (phi_i + phi_j));
        let dl = ch.l - self.length;
        let (ti, tj) = (phi_i - ch.beta, phi_j - ch.beta);
        let (ka, k11, k12) = (self.ka, self.k11, self.k12);
        let n = ka * dl;
        let mi = k11 * ti + k12 * tj;
        let mj = k12 * ti + k11 * tj;
        // Columns of J: r = (-c, -s, 0, c, s, 0), bi = e3 - z/l = (w, 1, -w, 0) and
        // bj = e6 - z/l = (w, 0, -w, 1), with w = (-s/l, c/l).
        let w = [-ch.s * ch.inv_l, ch.c * ch.inv_l];
        let nodal = Vec6::new(
            (-ch.c * n + w[0] * mi) + w[0] * mj,
            (-ch.s * n + w[1] * mi) + w[1] * mj,
            mi,
            (ch.c * n - w[0] * mi) - w[0] * mj,
            (ch.s * n - w[1] * mi) - w[1] * mj,
            mj,
        );
        let t = with_tangent.then(|| {
            let g = [n * ch.inv_l, (mi + mj) * (ch.inv_l * ch.inv_l)];
            tangent(&ch, w, [ka, k11, k12], g)
        });
        let r = BeamResponse {
            deformation: [dl, ti, tj],
            forces: [n, mi, mj],
            nodal,
            tangent: None,
        };
        (r, t)
    }
}

/// The distinct entries of a beam tangent (see `tangent`): the translational block of node i
/// (t00, t01, t11), the couplings of the translations with either rotation (c0, c1) and the
/// rotational pair (k11, k12).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TangentEntries {
    /// Entry (u_i, u_i).
    pub t00: f64,
    /// Entry (u_i, v_i).
    pub t01: f64,
    /// Entry (v_i, v_i).
    pub t11: f64,
    /// Entry (u_i, phi_i).
    pub c0: f64,
    /// Entry (v_i, phi_i).
    pub c1: f64,
    /// Entry (phi_i, phi_i).
    pub k11: f64,
    /// Entry (phi_i, phi_j).
    pub k12: f64,
}

impl TangentEntries {
    /// The lower triangle column by column (column b from the diagonal down: rows b..6, at
    /// `linear::LOWER_COLUMNS[b]`), over (u_i, v_i, phi_i, u_j, v_j, phi_j).
    #[inline(always)]
    pub fn lower_columns(&self) -> [f64; 21] {
        let TangentEntries {
            t00,
            t01,
            t11,
            c0,
            c1,
            k11,
            k12,
        } = *self;
        [
            t00, t01, c0, -t00, -t01, c0, // column 0
            t11, c1, -t01, -t11, c1, // column 1
            k11, -c0, -c1, k12, // column 2
            t00, t01, -c0, // column 3
            t11, -c1, // column 4
            k11, // column 5
        ]
    }

    /// The whole 6x6 tangent (exactly symmetric: the lower columns mirrored).
    #[inline(always)]
    pub fn write(&self, out: &mut [[f64; 6]; 6]) {
        *out = symmetric6(&self.lower_columns());
    }
}

/// The tangent `ka r r^T + k11 (bi bi^T + bj bj^T) + k12 (bi bj^T + bj bi^T)` plus the geometric
/// stiffness `N/l z z^T + (Mi + Mj)/l^2 (r z^T + z r^T)`, entry by entry in closed form.
///
/// `k = [ka, k11, k12]`, `g = [N/l, (Mi + Mj)/l^2]`. With r = (-c, -s, 0, c, s, 0),
/// z = (s, -c, 0, -s, c, 0), bi = (w, 1, -w, 0) and bj = (w, 0, -w, 1) for w = -z[0..2]/l, only
/// ten entries are distinct; the translational blocks of node j are exact negatives (or copies)
/// of node i's. Every entry is summed in the same order as the outer-product form (terms that
/// vanish identically left out), so the two agree to the last bit.
#[inline(always)]
fn tangent(ch: &Chord, w: [f64; 2], k: [f64; 3], g: [f64; 2]) -> TangentEntries {
    let (r, z) = (&ch.r, &ch.z);
    let [ka, k11, k12] = k;
    let [nl, ml2] = g;
    // Translational block of node i: bi_a bi_b + bj_a bj_b = bi_a bj_b + bj_a bi_b = 2 w_a w_b.
    let t = |a: usize, b: usize| {
        let ww = w[a] * w[b] + w[a] * w[b];
        (((r[a] * r[b]) * ka + ww * k11) + ww * k12)
            + ((z[a] * z[b]) * nl + (r[a] * z[b] + r[b] * z[a]) * ml2)
    };
    // Couplings of the translations with either rotation: w_a k11 + w_a k12.
    TangentEntries {
        t00: t(0, 0),
        t01: t(0, 1),
        t11: t(1, 1),
        c0: w[0] * k11 + w[0] * k12,
        c1: w[1] * k11 + w[1] * k12,
        k11,
        k12,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The outer-product form of the tangent, as first written.
    fn outer_product_tangent(el: &BeamElement, xi: [f64; 2], xj: [f64; 2], p: [f64; 2]) -> Mat6 {
        let ch = Chord::new(xi, xj, el.alpha0, 0.5 * (p[0] + p[1]));
        let (ti, tj) = (p[0] - ch.beta, p[1] - ch.beta);
        let ka = el.section.ea / el.length;
        let (k11, k12) = el.bending_stiffness();
        let n = ka * (ch.l - el.length);
        let (mi, mj) = (k11 * ti + k12 * tj, k12 * ti + k11 * tj);
        let mut bi = -ch.z * ch.inv_l;
        bi[2] += 1.0;
        let mut bj = -ch.z * ch.inv_l;
        bj[5] += 1.0;
        let mut k = ch.r * ch.r.transpose() * ka;
        k += (bi * bi.transpose() + bj * bj.transpose()) * k11;
        k += (bi * bj.transpose() + bj * bi.transpose()) * k12;
        let zz = ch.z * ch.z.transpose();
        let rz = ch.r * ch.z.transpose();
        k + (zz * (n * ch.inv_l) + (rz + rz.transpose()) * ((mi + mj) * (ch.inv_l * ch.inv_l)))
    }

    #[test]
    fn closed_form_tangent_equals_the_outer_products_bit_for_bit() {
        let section = Section {
            ea: 3.0e6,
            ei: 2.5,
            gae: 1.0e5,
            thickness: 0.0,
        };
        for (k, psi) in [0.0, 2.5e-5].into_iter().enumerate() {
            let el = BeamElement::new([0.3, -0.2], [1.1, 0.4], section, psi);
            for m in 0..20 {
                let f = (m + 7 * k) as f64;
                let xi = [0.3 + 0.01 * f.sin(), -0.2 + 0.02 * (1.3 * f).cos()];
                let xj = [1.1 - 0.3 * (0.7 * f).sin(), 0.4 + 0.5 * (0.3 * f).sin()];
                let p = [0.4 * (0.9 * f).sin(), -0.3 * (1.7 * f).cos()];
                let fast = el.response(xi, xj, p[0], p[1], true).tangent.unwrap();
                let reference = outer_product_tangent(&el, xi, xj, p);
                for a in 0..6 {
                    for b in 0..6 {
                        assert_eq!(fast[(a, b)], reference[(a, b)], "({a},{b}) at {m}");
                    }
                }
            }
        }
    }
}
