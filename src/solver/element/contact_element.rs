//! The Timoshenko contact element (beam ends i, j and k >= 1 contact nodes c): the element force
//! equation S = K(li) e in the chord frame, built from the flexibility of a simply supported
//! Timoshenko (or Bernoulli-Euler, Psi = 0) beam loaded by end moments and k point forces.
//! For k = 1 this is the paper's eq. (5) with K23 corrected as in the primer.
//! Also: nodal forces U = B^T S and the exact tangent, including the unsymmetric term from K(li).

use nalgebra::{DMatrix, DVector};

use super::beam::{BeamElement, Chord};
use super::dual::{Dual, Real};

/// Flexibility matrix (row-major, size (2+k)^2) of a simply supported beam of length `len` in its
/// chord frame for the generalised forces (Mi, Mj, Y_1..Y_k), with Y_m at `a[m]` from end i.
/// Bending `int m_p m_q / EI` plus shear `int v_p v_q / (G Ae)`; integrals are exact (Simpson on
/// piecewise-linear moments, midpoint on piecewise-constant shear).
pub fn flexibility<T: Real + Into<Dual>>(len: f64, inv_ei: f64, inv_gae: f64, a: &[T]) -> Vec<T> {
    let k = a.len();
    let n = 2 + k;
    let mut order: Vec<usize> = (0..k).collect();
    order.sort_by(|&p, &q| value(a[p]).total_cmp(&value(a[q])));
    let mut rank = vec![0; k];
    for (r, &p) in order.iter().enumerate() {
        rank[p] = r;
    }
    let zero = T::from(0.0);
    let lt = T::from(len);
    let one = T::from(1.0);
    let mut bp = Vec::with_capacity(k + 2);
    bp.push(zero);
    bp.extend(order.iter().map(|&p| a[p]));
    bp.push(lt);
    let mut f = vec![zero; n * n];
    let mut m = [vec![zero; n], vec![zero; n], vec![zero; n]];
    let mut v = vec![zero; n];
    for s in 0..=k {
        let (x0, x1) = (bp[s], bp[s + 1]);
        let h = x1 - x0;
        let xs = [x0, (x0 + x1) * T::from(0.5), x1];
        for (t, &x) in xs.iter().enumerate() {
            m[t][0] = one - x / lt;
            m[t][1] = zero - x / lt;
            for p in 0..k {
                m[t][2 + p] = if s <= rank[p] {
                    (one - a[p] / lt) * x
                } else {
                    a[p] * (one - x / lt)
                };
            }
        }
        v[0] = one / lt;
        v[1] = one / lt;
        for p in 0..k {
            v[2 + p] = if s <= rank[p] {
                zero - (one - a[p] / lt)
            } else {
                a[p] / lt
            };
        }
        let wb = h * T::from(inv_ei / 6.0);
        let ws = h * T::from(inv_gae);
        for p in 0..n {
            for q in p..n {
                let bend = m[0][p] * m[0][q] + T::from(4.0) * m[1][p] * m[1][q] + m[2][p] * m[2][q];
                let add = wb * bend + ws * v[p] * v[q];
                f[p * n + q] = f[p * n + q] + add;
            }
        }
    }
    for p in 0..n {
        for q in 0..p {
            f[p * n + q] = f[q * n + p];
        }
    }
    f
}

fn value<T: Into<Dual>>(x: T) -> f64 {
    x.into().re
}

/// Chord-frame stiffness of the bending part, K_b = F^{-1}, over (theta_i, theta_j, w_1..w_k),
/// for contact points at fractions `xi` of the element.
pub fn bending_stiffness(beam: &BeamElement, xi: &[f64]) -> DMatrix<f64> {
    contact_stiffness(beam, xi, 0.0)
}

/// `bending_stiffness` with a compliance `compliance` in series with every contact force: the
/// flexibility's contact diagonal grows by it (`contact_compliance`).
pub fn contact_stiffness(beam: &BeamElement, xi: &[f64], compliance: f64) -> DMatrix<f64> {
    let a: Vec<f64> = xi.iter().map(|x| x * beam.length).collect();
    let n = 2 + xi.len();
    let (inv_ei, inv_gae) = inverse_stiffness(beam);
    let mut f = DMatrix::from_row_slice(n, n, &flexibility(beam.length, inv_ei, inv_gae, &a));
    for m in 2..n {
        f[(m, m)] += compliance;
    }
    invert_spd(f)
}

/// The compliance in series with the contact force of `beam` for a contact spring of
/// `stiffness` EI / l^3 (`SolverParams::contact_stiffness`).
///
/// An element's stiffness against its contact force grows without bound as the contact point
/// nears an end node: as 3 EI / li^3 for Bernoulli-Euler, as G Ae / li for Timoshenko (shear
/// softens it, but only so far). On the node it is infinite, and first touch exactly on a node
/// has no stiffness matrix at all; near it the residual's round-off floor goes with it, far
/// above any tolerance: a pin pressed straight onto a mesh node stalls there. With the spring
/// the stiffness stays finite everywhere, on the nodes too, and a node in contact sits inside
/// the beam's shape by Yc l^3 / (stiffness EI), of order h^3 (below the h^2 error of the
/// mesh).
pub fn contact_compliance(beam: &BeamElement, stiffness: f64) -> f64 {
    beam.length.powi(3) / (stiffness * beam.section.ei)
}

fn inverse_stiffness(beam: &BeamElement) -> (f64, f64) {
    let inv_ei = 1.0 / beam.section.ei;
    (inv_ei, beam.psi * inv_ei)
}

/// Inverse of a flexibility matrix; all-NaN (same size) if singular, e.g. two contact points at
/// the same place, so the caller's residual turns non-finite and the increment is cut back.
fn invert_spd(f: DMatrix<f64>) -> DMatrix<f64> {
    let n = f.nrows();
    match f.clone().cholesky() {
        Some(ch) => ch.inverse(),
        None => f
            .try_inverse()
            .unwrap_or_else(|| DMatrix::from_element(n, n, f64::NAN)),
    }
}

/// Derivative of K_b with respect to the contact fraction xi_m: `-K_b dF/dxi_m K_b`.
pub fn bending_stiffness_derivative(
    beam: &BeamElement,
    xi: &[f64],
    kb: &DMatrix<f64>,
    m: usize,
) -> DMatrix<f64> {
    let l = beam.length;
    let a: Vec<Dual> = xi
        .iter()
        .enumerate()
        .map(|(p, x)| Dual {
            re: x * l,
            du: if p == m { l } else { 0.0 },
        })
        .collect();
    let n = 2 + xi.len();
    let (inv_ei, inv_gae) = inverse_stiffness(beam);
    let fd = flexibility(l, inv_ei, inv_gae, &a);
    let df = DMatrix::from_row_slice(n, n, &fd.iter().map(|d| d.du).collect::<Vec<_>>());
    -(kb * df * kb)
}

/// Options for evaluating a contact element.
#[derive(Clone, Copy, Debug)]
pub struct ContactOptions {
    /// Contact fractions are clamped to [xi_min, 1 - xi_min] inside K (never in the kinematics).
    pub xi_min: f64,
    /// Weight of the unsymmetric tangent term B^T (dK/dxi e) (dxi/du)^T: 1 exact, 0 dropped.
    pub unsymmetric: f64,
    /// The contact spring of Bernoulli-Euler elements in EI / l^3 (`contact_compliance`);
    /// infinite: none (the exact element, singular with the contact on a node).
    pub contact_stiffness: f64,
    /// Whether a frictionless contact force is normal to the beam's surface at the contact
    /// point (`contact_law.rs`) rather than to the chord (the paper's element).
    pub surface_normal: bool,
}

impl Default for ContactOptions {
    fn default() -> Self {
        ContactOptions {
            xi_min: 1e-6,
            unsymmetric: 1.0,
            contact_stiffness: 1e4,
            surface_normal: true,
        }
    }
}

/// What a contact element returns for one configuration.
#[derive(Clone, Debug)]
pub struct ContactResponse {
    /// Deformations (dl, theta_i, theta_j, dyc_1..dyc_k).
    pub deformation: Vec<f64>,
    /// Element forces (N, Mi, Mj, Yc_1..Yc_k).
    pub forces: Vec<f64>,
    /// Contact fractions li/l from the current chord (unclamped).
    pub xi: Vec<f64>,
    /// Nodal forces over (u_i, v_i, phi_i, u_j, v_j, phi_j, u_c1, v_c1, ...).
    pub nodal: DVector<f64>,
    /// Tangent over the same dofs (if requested).
    pub tangent: Option<DMatrix<f64>>,
}

/// Evaluate the contact element of `beam` with contact nodes at current positions `xc`.
pub fn contact_response(
    beam: &BeamElement,
    xi_pos: [f64; 2],
    xj_pos: [f64; 2],
    phi: [f64; 2],
    xc: &[[f64; 2]],
    opts: ContactOptions,
    with_tangent: bool,
) -> ContactResponse {
    let k = xc.len();
    let nd = 6 + 2 * k;
    let ch = Chord::new(xi_pos, xj_pos, beam.alpha0, 0.5 * (phi[0] + phi[1]));
    let (c, s, l) = (ch.c, ch.s, ch.l);
    let dl = l - beam.length;
    let (ti, tj) = (phi[0] - ch.beta, phi[1] - ch.beta);
    let mut li = vec![0.0; k];
    let mut w = vec![0.0; k];
    let mut xi = vec![0.0; k];
    let mut xi_eff = vec![0.0; k];
    for m in 0..k {
        let a = [xc[m][0] - xi_pos[0], xc[m][1] - xi_pos[1]];
        li[m] = a[0] * c + a[1] * s;
        w[m] = -a[0] * s + a[1] * c;
        xi[m] = li[m] / l;
        xi_eff[m] = xi[m].clamp(opts.xi_min, 1.0 - opts.xi_min);
    }
    let kb = contact_stiffness(
        beam,
        &xi_eff,
        contact_compliance(beam, opts.contact_stiffness),
    );
    let mut eb = DVector::zeros(2 + k);
    eb[0] = ti;
    eb[1] = tj;
    for m in 0..k {
        eb[2 + m] = w[m];
    }
    let sb = &kb * &eb;
    let ka = beam.section.ea / beam.length;
    let n_force = ka * dl;

    // Rows of B = de/du.
    let pad = |v: &nalgebra::SVector<f64, 6>| {
        let mut out = DVector::zeros(nd);
        out.rows_mut(0, 6).copy_from(v);
        out
    };
    let r = pad(&ch.r);
    let z = pad(&ch.z);
    let mut b_rows: Vec<DVector<f64>> = Vec::with_capacity(3 + k);
    b_rows.push(r.clone());
    let mut bi = -&z / l;
    bi[2] += 1.0;
    let mut bj = -&z / l;
    bj[5] += 1.0;
    b_rows.push(bi);
    b_rows.push(bj);
    let mut a_e = Vec::with_capacity(k);
    for m in 0..k {
        // d(dyc)/du = A_n - (li/l) z, with A_n = -n at i, +n at c.
        let mut an = DVector::zeros(nd);
        an[0] = s;
        an[1] = -c;
        an[6 + 2 * m] = -s;
        an[7 + 2 * m] = c;
        b_rows.push(an - &z * (li[m] / l));
        let mut ae = DVector::zeros(nd);
        ae[0] = -c;
        ae[1] = -s;
        ae[6 + 2 * m] = c;
        ae[7 + 2 * m] = s;
        a_e.push(ae);
    }
    let mut forces = vec![n_force];
    forces.extend(sb.iter().copied());
    let mut nodal = DVector::zeros(nd);
    for (row, f) in b_rows.iter().zip(&forces) {
        nodal += row * *f;
    }
    let mut deformation = vec![dl, ti, tj];
    deformation.extend(w.iter().copied());

    let tangent = with_tangent.then(|| {
        let bmat = DMatrix::from_fn(3 + k, nd, |p, q| b_rows[p][q]);
        let mut kfull = DMatrix::zeros(3 + k, 3 + k);
        kfull[(0, 0)] = ka;
        kfull.view_mut((1, 1), (2 + k, 2 + k)).copy_from(&kb);
        let mut kt = bmat.transpose() * &kfull * &bmat;
        let g6 = ch.geometric_stiffness(n_force, forces[1] + forces[2]);
        let mut g = kt.view_mut((0, 0), (6, 6));
        g += g6;
        let rz = &r * z.transpose();
        let zz = &z * z.transpose();
        for m in 0..k {
            let ym = forces[3 + m];
            let aez = &a_e[m] * z.transpose();
            // Second derivative of dyc_m.
            let h = -(&aez + aez.transpose()) / l - &zz * (w[m] / (l * l))
                + (&rz + rz.transpose()) * (li[m] / (l * l));
            kt += h * ym;
            let clamped = xi[m] != xi_eff[m];
            if opts.unsymmetric != 0.0 && !clamped {
                let dkb = bending_stiffness_derivative(beam, &xi_eff, &kb, m);
                let ds = dkb * &eb; // dS_b/dxi_m
                let mut dnodal = DVector::zeros(nd);
                for p in 0..(2 + k) {
                    dnodal += &b_rows[1 + p] * ds[p];
                }
                let grad_xi = (&a_e[m] + &z * (w[m] / l)) / l - &r * (li[m] / (l * l));
                kt += dnodal * grad_xi.transpose() * opts.unsymmetric;
            }
        }
        kt
    });
    ContactResponse {
        deformation,
        forces,
        xi,
        nodal,
        tangent,
    }
}

/// Deflection from the chord at fraction `x` of the element, given the bending forces
/// (Mi, Mj, Y_1..Y_k) and the (clamped) contact fractions. Exact for Timoshenko and
/// Bernoulli-Euler; passes through every contact node.
pub fn deflection(beam: &BeamElement, bending_forces: &[f64], xi: &[f64], x: f64) -> f64 {
    let l = beam.length;
    let mut a: Vec<f64> = xi.iter().map(|v| v * l).collect();
    a.push(x * l);
    let n = 2 + a.len();
    let (inv_ei, inv_gae) = inverse_stiffness(beam);
    let f = flexibility(l, inv_ei, inv_gae, &a);
    let row = n - 1;
    bending_forces
        .iter()
        .enumerate()
        .map(|(q, sq)| sq * f[row * n + q])
        .sum()
}
