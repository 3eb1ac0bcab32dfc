//! Element-level identities: the contact element against the primer's closed form (K23
//! corrected), symmetry, condensation to the 2-node element, the Psi -> 0 limit, exact tangents
//! against central finite differences, and rigid-body invariance of any size.

use crate::common;
use common::Rng;
use nalgebra::DMatrix;
use tsm_contact::solver::element::beam::BeamElement;
use tsm_contact::solver::element::contact_element::{
    bending_stiffness, contact_response, ContactOptions,
};
use tsm_contact::solver::element::contact_law::contact_outcome;
use tsm_contact::solver::model::Section;

/// The paper's material (Example 3.1/3.2): E = 2e7, A = 3e-4, I = 2.2e-8, G = 7.142e6, Ae = A.
fn strip() -> Section {
    Section {
        ea: 2.0e7 * 3.0e-4,
        ei: 2.0e7 * 2.2e-8,
        gae: 7.142e6 * 3.0e-4,
        thickness: 0.0,
    }
}

fn element(length: f64, psi: f64) -> BeamElement {
    BeamElement::new([0.0, 0.0], [length, 0.0], strip(), psi)
}

/// The primer's closed-form Timoshenko contact matrix (bending part, over theta_i, theta_j, dyc).
fn primer_matrix(ei: f64, psi: f64, li: f64, lj: f64) -> DMatrix<f64> {
    let l0 = li + lj;
    let omega = (li * lj).powi(2) + 3.0 * psi * (l0 * l0 + li * lj) + 36.0 * psi * psi;
    let kc = ei / (l0 * omega);
    let k22 = (4.0 * omega + 3.0 * li * lj.powi(3) - 108.0 * psi * psi) * kc;
    let k33 = (4.0 * omega + 3.0 * li.powi(3) * lj - 108.0 * psi * psi) * kc;
    let k23 = (9.0 * psi * (l0 * l0 - li * lj) - omega) * kc;
    let k24 = -3.0 * l0 * (lj * l0 + 6.0 * psi) * kc;
    let k34 = 3.0 * l0 * (li * l0 + 6.0 * psi) * kc;
    let k44 = 3.0 * l0 * (l0.powi(3) + 12.0 * l0 * psi) / (li * lj) * kc;
    DMatrix::from_row_slice(3, 3, &[k22, k23, k24, k23, k33, k34, k24, k34, k44])
}

fn rel_diff(a: &DMatrix<f64>, b: &DMatrix<f64>) -> f64 {
    (a - b).abs().max() / b.abs().max()
}

#[test]
fn contact_matrix_matches_primer_closed_form() {
    let s = strip();
    for &psi in &[s.ei / s.gae, 1e-3, 0.0] {
        for &xi in &[0.01, 0.25, 0.5, 0.9739] {
            let l = 0.1;
            let el = element(l, psi);
            let k = bending_stiffness(&el, &[xi]);
            let reference = if psi == 0.0 {
                // Primer's Psi -> 0 limits.
                let (li, lj) = (xi * l, (1.0 - xi) * l);
                let ei = s.ei;
                DMatrix::from_row_slice(
                    3,
                    3,
                    &[
                        ei * (4.0 * li + 3.0 * lj) / (li * l),
                        -ei / l,
                        -3.0 * ei * l / (li * li * lj),
                        -ei / l,
                        ei * (4.0 * lj + 3.0 * li) / (lj * l),
                        3.0 * ei * l / (li * lj * lj),
                        -3.0 * ei * l / (li * li * lj),
                        3.0 * ei * l / (li * lj * lj),
                        3.0 * ei * l.powi(3) / (li.powi(3) * lj.powi(3)),
                    ],
                )
            } else {
                primer_matrix(s.ei, psi, xi * l, (1.0 - xi) * l)
            };
            let e = rel_diff(&k, &reference);
            assert!(e < 1e-12, "psi {psi} xi {xi}: relative difference {e:e}");
            let asym = (&k - k.transpose()).abs().max() / k.abs().max();
            assert!(asym < 1e-14, "not symmetric: {asym:e}");
        }
    }
}

#[test]
fn primer_k23_differs_from_the_papers_misprint() {
    // The paper prints K23 = {9 (l0^2 - lj Psi) - Omega} k_c; the corrected entry is
    // {9 Psi (l0^2 - li lj) - Omega} k_c. Our matrix must agree with the corrected one only.
    let s = strip();
    let (psi, l, xi) = (s.ei / s.gae, 0.1, 0.3);
    let k = bending_stiffness(&element(l, psi), &[xi]);
    let (li, lj) = (xi * l, (1.0 - xi) * l);
    let omega = (li * lj).powi(2) + 3.0 * psi * (l * l + li * lj) + 36.0 * psi * psi;
    let kc = s.ei / (l * omega);
    let misprint = (9.0 * (l * l - lj * psi) - omega) * kc;
    let corrected = -(li * li - 6.0 * psi) * (lj * lj - 6.0 * psi) * kc;
    assert!(((k[(0, 1)] - corrected) / corrected).abs() < 1e-12);
    assert!(((k[(0, 1)] - misprint) / misprint).abs() > 1e-2);
}

#[test]
fn condensing_out_the_contact_gives_the_two_node_element() {
    let s = strip();
    for &psi in &[s.ei / s.gae, 0.0] {
        for &xi in &[0.05, 0.5, 0.8] {
            let el = element(0.1, psi);
            let k = bending_stiffness(&el, &[xi]);
            // Yc = 0: Schur complement on (theta_i, theta_j).
            let kaa = k.view((0, 0), (2, 2)).into_owned();
            let kab = k.view((0, 2), (2, 1)).into_owned();
            let kbb = k[(2, 2)];
            let cond = kaa - &kab * kab.transpose() / kbb;
            let (k11, k12) = el.bending_stiffness();
            let reference = DMatrix::from_row_slice(2, 2, &[k11, k12, k12, k11]);
            let e = rel_diff(&cond, &reference);
            assert!(e < 1e-12, "psi {psi} xi {xi}: {e:e}");
        }
    }
}

#[test]
fn several_contacts_reduce_to_one_and_to_none() {
    // k point loads: with one point the general flexibility element is the paper's matrix (checked
    // above); with two points, condensing one out must give the one-point matrix.
    let s = strip();
    let el = element(0.1, s.ei / s.gae);
    let k2 = bending_stiffness(&el, &[0.3, 0.7]);
    let keep = [0usize, 1, 2];
    let kaa = DMatrix::from_fn(3, 3, |i, j| k2[(keep[i], keep[j])]);
    let kab = DMatrix::from_fn(3, 1, |i, _| k2[(keep[i], 3)]);
    let cond = kaa - &kab * kab.transpose() / k2[(3, 3)];
    let k1 = bending_stiffness(&el, &[0.3]);
    assert!(rel_diff(&cond, &k1) < 1e-11, "{:e}", rel_diff(&cond, &k1));
}

/// Central finite-difference Jacobian of `f` at `x`.
fn fd_jacobian(x: &[f64], h: f64, f: impl Fn(&[f64]) -> Vec<f64>) -> DMatrix<f64> {
    let n = x.len();
    let m = f(x).len();
    let mut jac = DMatrix::zeros(m, n);
    for j in 0..n {
        let mut xp = x.to_vec();
        let mut xm = x.to_vec();
        xp[j] += h;
        xm[j] -= h;
        let (fp, fm) = (f(&xp), f(&xm));
        for i in 0..m {
            jac[(i, j)] = (fp[i] - fm[i]) / (2.0 * h);
        }
    }
    jac
}

#[test]
fn beam_tangent_equals_finite_differences() {
    let s = strip();
    let mut rng = Rng(0x9e3779b97f4a7c15);
    for &psi in &[s.ei / s.gae, 0.0] {
        for _ in 0..20 {
            let el = BeamElement::new(
                [0.1 * rng.next(), 0.1 * rng.next()],
                [1.0 + 0.1 * rng.next(), 0.3 * rng.next()],
                s,
                psi,
            );
            // A random large rigid rotation plus a deformation.
            let rot = 7.0 * rng.next();
            let (c, sn) = (rot.cos(), rot.sin());
            let x0 = [0.2 * rng.next(), 0.2 * rng.next()];
            let dx = [el.length * c * (1.0 + 1e-3 * rng.next()), el.length * sn];
            let state = vec![
                x0[0],
                x0[1],
                rot + 0.2 * rng.next(),
                x0[0] + dx[0],
                x0[1] + dx[1],
                rot + 0.2 * rng.next(),
            ];
            let eval = |x: &[f64]| el.response([x[0], x[1]], [x[3], x[4]], x[2], x[5], true);
            let k = eval(&state).tangent.unwrap();
            let k = DMatrix::from_fn(6, 6, |i, j| k[(i, j)]);
            let fd = fd_jacobian(&state, 1e-6, |x| eval(x).nodal.iter().copied().collect());
            let e = rel_diff(&fd, &k);
            assert!(e < 1e-6, "psi {psi}: tangent vs finite differences {e:e}");
        }
    }
}

#[test]
fn contact_tangent_equals_finite_differences() {
    let s = strip();
    let mut rng = Rng(0x2545f4914f6cdd1d);
    for &psi in &[s.ei / s.gae, 0.0] {
        for k in 1..=3 {
            for _ in 0..10 {
                let l = 0.1;
                let el = BeamElement::new([0.0, 0.0], [l, 0.0], s, psi);
                let rot = 9.0 * rng.next();
                let (c, sn) = (rot.cos(), rot.sin());
                let lcur = l * (1.0 + 1e-3 * rng.next());
                let mut state = vec![
                    0.3,
                    -0.2,
                    rot + 0.05 * rng.next(),
                    0.3 + lcur * c,
                    -0.2 + lcur * sn,
                    rot + 0.05 * rng.next(),
                ];
                for m in 0..k {
                    let t = (m as f64 + 0.5 + 0.4 * rng.next()) / k as f64;
                    let w = 2e-3 * rng.next();
                    state.push(0.3 + t * lcur * c - w * sn);
                    state.push(-0.2 + t * lcur * sn + w * c);
                }
                // The paper's element (force normal to the chord), and the element as the
                // assembly adds it: forces turned to the surface normal.
                for surface_normal in [false, true] {
                    let opts = ContactOptions {
                        surface_normal,
                        ..ContactOptions::default()
                    };
                    let eval = |x: &[f64]| {
                        let xc: Vec<[f64; 2]> =
                            (0..k).map(|m| [x[6 + 2 * m], x[7 + 2 * m]]).collect();
                        let ends = ([x[0], x[1]], [x[3], x[4]]);
                        let grips = vec![None; k];
                        let out = contact_outcome(&el, ends, [x[2], x[5]], &xc, opts, &grips, true);
                        out.response
                    };
                    let kt = eval(&state).tangent.unwrap();
                    let fd = fd_jacobian(&state, 1e-7, |x| eval(x).nodal.iter().copied().collect());
                    let e = rel_diff(&fd, &kt);
                    assert!(
                        e < 1e-6,
                        "psi {psi} k {k} surface normal {surface_normal}: tangent vs finite differences {e:e}"
                    );
                }
            }
        }
    }
}

#[test]
fn rigid_body_motion_of_any_size_gives_zero_forces() {
    let s = strip();
    for &psi in &[s.ei / s.gae, 0.0] {
        let el = BeamElement::new([0.2, 0.1], [1.1, 0.5], s, psi);
        let (xi, xj) = ([0.2, 0.1], [1.1, 0.5]);
        for &rot in &[
            0.3,
            3.0,
            -3.5,
            2.0 * std::f64::consts::TAU + 0.7,
            5.0 * std::f64::consts::TAU - 0.1,
            -40.0,
        ] {
            let (c, sn) = (f64::cos(rot), f64::sin(rot));
            let t = [123.4, -56.7];
            let map = |p: [f64; 2]| [t[0] + c * p[0] - sn * p[1], t[1] + sn * p[0] + c * p[1]];
            let r = el.response(map(xi), map(xj), rot, rot, false);
            // Scale: forces of a unit deformation.
            let scale = s.ea / el.length;
            for f in r.forces {
                assert!(f.abs() < 1e-12 * scale, "rotation {rot}: force {f:e}");
            }
            // Contact element with a node on the chord: also force-free.
            let pc = [xi[0] + 0.3 * (xj[0] - xi[0]), xi[1] + 0.3 * (xj[1] - xi[1])];
            let cr = contact_response(
                &el,
                map(xi),
                map(xj),
                [rot, rot],
                &[map(pc)],
                ContactOptions::default(),
                false,
            );
            let kscale = bending_stiffness(&el, &[0.3]).abs().max() * el.length;
            for f in &cr.forces {
                assert!(
                    f.abs() < 1e-12 * kscale.max(scale),
                    "contact, rotation {rot}: force {f:e}"
                );
            }
        }
    }
}

/// Two Timoshenko elements i-c and c-j (lengths xi L and (1 - xi) L) with the rotation at c
/// condensed out (moment equilibrium there): nodal forces over (i, j, c) translations plus
/// rotations at i, j, and the condensed tangent, in the contact element's dof order.
fn two_elements(
    s: Section,
    psi: f64,
    len: f64,
    xi: f64,
    x: &[f64; 8],
) -> (nalgebra::DVector<f64>, DMatrix<f64>) {
    let e1 = BeamElement {
        length: xi * len,
        alpha0: 0.0,
        section: s,
        psi,
    };
    let e2 = BeamElement {
        length: (1.0 - xi) * len,
        alpha0: 0.0,
        section: s,
        psi,
    };
    let (pi, pj, pc) = ([x[0], x[1]], [x[3], x[4]], [x[6], x[7]]);
    // Solve Z_c(phi_c) = 0 by Newton, starting from the mean end rotation.
    let mut phic = 0.5 * (x[2] + x[5]);
    for _ in 0..50 {
        let r1 = e1.response(pi, pc, x[2], phic, true);
        let r2 = e2.response(pc, pj, phic, x[5], true);
        let z = r1.nodal[5] + r2.nodal[2];
        let k = r1.tangent.unwrap()[(5, 5)] + r2.tangent.unwrap()[(2, 2)];
        phic -= z / k;
        if z.abs() < 1e-15 {
            break;
        }
    }
    let r1 = e1.response(pi, pc, x[2], phic, true);
    let r2 = e2.response(pc, pj, phic, x[5], true);
    // Assemble over (ui, vi, phii, uj, vj, phij, uc, vc, phic).
    let map1 = [0usize, 1, 2, 6, 7, 8];
    let map2 = [6usize, 7, 8, 3, 4, 5];
    let mut f = nalgebra::DVector::<f64>::zeros(9);
    let mut k = DMatrix::<f64>::zeros(9, 9);
    for (r, map) in [(&r1, map1), (&r2, map2)] {
        let kt = r.tangent.unwrap();
        for a in 0..6 {
            f[map[a]] += r.nodal[a];
            for b in 0..6 {
                k[(map[a], map[b])] += kt[(a, b)];
            }
        }
    }
    let kpp = k[(8, 8)];
    let cond = DMatrix::from_fn(8, 8, |a, b| k[(a, b)] - k[(a, 8)] * k[(8, b)] / kpp);
    (f.rows(0, 8).into_owned(), cond)
}

#[test]
fn contact_element_at_fixed_li_equals_two_elements_joined_at_c() {
    let s = strip();
    let (len, xi) = (0.1, 0.3);
    for &psi in &[s.ei / s.gae, 0.0] {
        let el = BeamElement::new([0.0, 0.0], [len, 0.0], s, psi);
        let mut diffs = Vec::new();
        for &amp in &[1e-4, 1e-5] {
            // A large rigid motion plus a deformation of relative size `amp`: end rotations,
            // stretch, and c off the chord; c sits at li/l = xi exactly (uniform stretch).
            let (rot, t) = (2.3, [0.7, -0.4]);
            let (c, sn) = (f64::cos(rot), f64::sin(rot));
            let lcur = len * (1.0 + 0.3 * amp);
            let map = |p: [f64; 2]| [t[0] + c * p[0] - sn * p[1], t[1] + sn * p[0] + c * p[1]];
            let (pi, pj) = (map([0.0, 0.0]), map([lcur, 0.0]));
            let pc = map([xi * lcur, 0.8 * amp * len]);
            let x = [
                pi[0],
                pi[1],
                rot + 2.0 * amp,
                pj[0],
                pj[1],
                rot - 1.5 * amp,
                pc[0],
                pc[1],
            ];
            let opts = ContactOptions {
                xi_min: 1e-6,
                unsymmetric: 0.0,
                // The exact element, without the Bernoulli-Euler contact spring.
                contact_stiffness: f64::INFINITY,
                surface_normal: false,
            };
            let cr = contact_response(&el, pi, pj, [x[2], x[5]], &[pc], opts, true);
            assert!((cr.xi[0] - xi).abs() < 1e-12);
            let (f2, k2) = two_elements(s, psi, len, xi, &x);
            let scale = f2.abs().max();
            diffs.push((&cr.nodal - &f2).abs().max() / scale);
            // Tangents over i, j and c's motion normal to the chord. Along the chord the contact
            // node slides freely, so the joined node's tangential dof is condensed out (zero
            // tangential force), exactly as its rotation was.
            let (n, tg) = ([-sn, c], [c, sn]);
            let basis = DMatrix::from_fn(8, 8, |a, b| match (a, b) {
                (a, b) if a < 6 && a == b => 1.0,
                (6, 6) => n[0],
                (7, 6) => n[1],
                (6, 7) => tg[0],
                (7, 7) => tg[1],
                _ => 0.0,
            });
            let kc_full = basis.transpose() * cr.tangent.unwrap() * &basis;
            let kt_full = basis.transpose() * k2 * &basis;
            let kc = kc_full.view((0, 0), (7, 7)).into_owned();
            let ktt = kt_full[(7, 7)];
            let kt = DMatrix::from_fn(7, 7, |a, b| {
                kt_full[(a, b)] - kt_full[(a, 7)] * kt_full[(7, b)] / ktt
            });
            let e = (&kc - &kt).abs().max() / kt.abs().max();
            // The two models share their linear part exactly; they differ by the segments' own
            // chord rotations, first order in the deformation (relative).
            assert!(
                e < 5.0 * amp,
                "psi {psi} amp {amp}: tangents differ by {e:e}"
            );
        }
        // The element force equations agree to first order: the difference is second order in
        // the deformation, i.e. falls 10x with a 10x smaller deformation.
        assert!(diffs[0] < 1e-3 && diffs[1] < 1e-4, "psi {psi}: {diffs:?}");
        let ratio = diffs[0] / diffs[1];
        assert!(
            (5.0..20.0).contains(&ratio),
            "psi {psi}: differences {diffs:?}"
        );
    }
}

/// The turned force on a contact node is normal to the surface tangent there: the chord turned
/// by the end rotations interpolated at the contact point (independent of the element's
/// algebra: only the nodal forces are read).
#[test]
fn the_turned_force_is_normal_to_the_interpolated_surface() {
    let s = strip();
    let l = 0.1;
    let el = BeamElement::new([0.0, 0.0], [l, 0.0], s, s.ei / s.gae);
    let (ti, tj) = (0.03, -0.05);
    for xi in [0.0, 0.2, 0.5, 0.9, 1.0] {
        let pc = [xi * l, -1e-3];
        let out = contact_outcome(
            &el,
            ([0.0, 0.0], [l, 0.0]),
            [ti, tj],
            &[pc],
            ContactOptions::default(),
            &[None],
            false,
        );
        let f = [out.response.nodal[6], out.response.nodal[7]];
        let t = (1.0 - xi) * ti + xi * tj;
        let tangent = [t.cos(), t.sin()];
        let along = (f[0] * tangent[0] + f[1] * tangent[1]) / f[0].hypot(f[1]);
        assert!(
            along.abs() < 1e-12,
            "xi {xi}: force {f:?} along the surface by {along:e}"
        );
    }
}

/// At a mesh node two elements push a node resting there alike: the same direction whichever
/// element carries the contact, normal to the node's rotation (the chord's normal turns by the
/// bend between them).
#[test]
fn two_elements_push_alike_at_their_shared_node() {
    let s = strip();
    let l = 0.1;
    // A bent beam: node 1 at the origin, its neighbours below on either side; the node's
    // rotation 0.01 rad.
    let (a, m, b) = ([-l, -0.01], [0.0, 0.0], [l, -0.012]);
    let phi = [0.02, 0.01, -0.005];
    // The node rests on the mesh node (its force comes from the bend: K42 theta_i + K43
    // theta_j).
    let pc = m;
    let direction = |p: [f64; 2], q: [f64; 2], rot: [f64; 2]| {
        let d = [q[0] - p[0], q[1] - p[1]];
        let len = d[0].hypot(d[1]);
        let el = BeamElement::new([0.0, 0.0], [len, 0.0], s, s.ei / s.gae);
        let out = contact_outcome(
            &el,
            (p, q),
            rot,
            &[pc],
            ContactOptions::default(),
            &[None],
            false,
        );
        let f = [out.response.nodal[6], out.response.nodal[7]];
        f[1].atan2(f[0])
    };
    let left = direction(a, m, [phi[0], phi[1]]);
    let right = direction(m, b, [phi[1], phi[2]]);
    assert!((left - right).abs() < 1e-12, "left {left}, right {right}");
    let normal = phi[1] + std::f64::consts::FRAC_PI_2;
    let off = (left - normal).rem_euclid(std::f64::consts::PI);
    assert!(
        off.min(std::f64::consts::PI - off) < 1e-12,
        "{left} against {normal}"
    );
    // The paper's element: the directions differ by the bend.
    let chord = |p: [f64; 2], q: [f64; 2], rot: [f64; 2]| {
        let d = [q[0] - p[0], q[1] - p[1]];
        let len = d[0].hypot(d[1]);
        let el = BeamElement::new([0.0, 0.0], [len, 0.0], s, s.ei / s.gae);
        let r = contact_response(&el, p, q, rot, &[pc], ContactOptions::default(), false);
        r.nodal[7].atan2(r.nodal[6])
    };
    let bend = (chord(a, m, [phi[0], phi[1]]) - chord(m, b, [phi[1], phi[2]])).abs();
    assert!(bend > 0.1, "chord normals differ by {bend}");
}
