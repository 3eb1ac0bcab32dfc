//! Four plain beam elements evaluated at once in the lanes of AVX2 vectors
//! ([`ForceConstants::evaluate_entries`], tangent included): the same arithmetic in the same order
//! as the scalar path, so the results agree bit for bit, with the four chord lengths, chord
//! angles and force equations worked side by side. The chord angle and its unwrapping have no
//! branches here; a group in which a lane leaves their common route (a zero or non-finite
//! chord, a chord rotation more than half a turn from the mean of its end rotations) is handed
//! back for the scalar path.

use core::arch::x86_64::*;

use super::angle::{ATAN_EIGHTHS, HALF_PI, PI};
use super::beam::{ForceConstants, TangentEntries};
use crate::solver::linear::simd::Avx2;

/// What `evaluate4` gives for its four elements, lane k for element k: element forces (N, Mi,
/// Mj), nodal forces U = J S over (u_i, v_i, phi_i, u_j, v_j, phi_j) and the tangent's
/// distinct entries t00, t01, t11, c0, c1 (see `TangentEntries`; k11 and k12 are the
/// constants').
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Group {
    /// N, Mi, Mj.
    pub forces: [[f64; 4]; 3],
    /// U = J S.
    pub nodal: [[f64; 4]; 6],
    /// t00, t01, t11, c0, c1.
    pub tangent: [[f64; 4]; 5],
}

impl Group {
    /// Element `k`'s forces, nodal forces and tangent entries (`c` its constants, for k11 and
    /// k12), as `evaluate_entries` gives them.
    #[inline(always)]
    pub fn lane(&self, k: usize, c: &ForceConstants) -> ([f64; 3], [f64; 6], TangentEntries) {
        let [t00, t01, t11, c0, c1] = self.tangent.map(|t| t[k]);
        let tangent = TangentEntries {
            t00,
            t01,
            t11,
            c0,
            c1,
            k11: c.k11,
            k12: c.k12,
        };
        (self.forces.map(|f| f[k]), self.nodal.map(|f| f[k]), tangent)
    }
}

/// The current ends of an element: end i's position, end j's, and the end rotations (i, j).
pub type Ends = ([f64; 2], [f64; 2], [f64; 2]);

/// `evaluate_entries` (tangent included) of four elements with constants `c` and ends `ends`,
/// or None if a lane needs the scalar path. `cpu` proves that the CPU has AVX2.
#[inline(always)]
pub fn evaluate4(cpu: Avx2, c: [&ForceConstants; 4], ends: [Ends; 4]) -> Option<Group> {
    let _ = cpu;
    // SAFETY: the CPU has AVX2 (`cpu`).
    unsafe { evaluate4_avx2(c, ends) }
}

/// `evaluate4` in AVX2 instructions.
///
/// # Safety
/// The CPU must have AVX2.
#[target_feature(enable = "avx2")]
#[inline]
unsafe fn evaluate4_avx2(c: [&ForceConstants; 4], ends: [Ends; 4]) -> Option<Group> {
    let (xi, xj, phi) = (ends.map(|x| x.0), ends.map(|x| x.1), ends.map(|x| x.2));
    let lanes = |f: &dyn Fn(usize) -> f64| _mm256_set_pd(f(3), f(2), f(1), f(0));
    let splat = _mm256_set1_pd;
    let (add, sub, mul, div) = (_mm256_add_pd, _mm256_sub_pd, _mm256_mul_pd, _mm256_div_pd);
    let sign = splat(-0.0);
    let neg = |a| _mm256_xor_pd(a, sign);
    let abs = |a| _mm256_andnot_pd(sign, a);
    let all = |mask| _mm256_movemask_pd(mask) == 0b1111;

    let dx = sub(lanes(&|k| xj[k][0]), lanes(&|k| xi[k][0]));
    let dy = sub(lanes(&|k| xj[k][1]), lanes(&|k| xi[k][1]));
    let l = _mm256_sqrt_pd(add(mul(dx, dx), mul(dy, dy)));
    let inv_l = div(splat(1.0), l);
    let (cs, sn) = (mul(dx, inv_l), mul(dy, inv_l));

    // The chord angle (`chord_angle`): the octant folded to num/den, split at the nearest
    // eighth, the series, the table, and the unfolding.
    let (ax, ay) = (abs(dx), abs(dy));
    let inf = splat(f64::INFINITY);
    let finite = _mm256_and_pd(
        _mm256_cmp_pd::<_CMP_LT_OQ>(ax, inf),
        _mm256_cmp_pd::<_CMP_LT_OQ>(ay, inf),
    );
    let positive = _mm256_cmp_pd::<_CMP_GT_OQ>(_mm256_max_pd(ax, ay), splat(0.0));
    if !all(_mm256_and_pd(finite, positive)) {
        return None;
    }
    let steep = _mm256_cmp_pd::<_CMP_GT_OQ>(ay, ax);
    let num = _mm256_blendv_pd(ay, ax, steep);
    let den = _mm256_blendv_pd(ax, ay, steep);
    let i = _mm256_cvttpd_epi32(add(mul(div(num, den), splat(8.0)), splat(0.5)));
    let eighth = mul(_mm256_cvtepi32_pd(i), splat(0.125));
    let s = div(sub(num, mul(eighth, den)), add(den, mul(eighth, num)));
    let z = mul(s, s);
    let mut series = add(mul(z, splat(-1.0 / 13.0)), splat(1.0 / 11.0));
    series = sub(mul(series, z), splat(1.0 / 9.0));
    series = add(mul(series, z), splat(1.0 / 7.0));
    series = sub(mul(series, z), splat(1.0 / 5.0));
    series = add(mul(series, z), splat(1.0 / 3.0));
    series = mul(series, z);
    // Entry [i][0] is the table's f64 number 2 i, [i][1] the next.
    let t = _mm_min_epi32(i, _mm_set1_epi32(8));
    let t = _mm_add_epi32(t, t);
    let table = ATAN_EIGHTHS.as_ptr().cast::<f64>();
    // SAFETY: every index 2 t + 1 <= 17 lies within the 9 x 2 table.
    let (hi, lo) = unsafe {
        (
            _mm256_i32gather_pd::<8>(table, t),
            _mm256_i32gather_pd::<8>(table.add(1), t),
        )
    };
    let a = add(hi, add(lo, sub(s, mul(s, series))));
    let left = _mm256_cmp_pd::<_CMP_LT_OQ>(dx, splat(0.0));
    let base = _mm256_blendv_pd(_mm256_and_pd(left, splat(PI.0)), splat(HALF_PI.0), steep);
    let rest = _mm256_blendv_pd(_mm256_and_pd(left, splat(PI.1)), splat(HALF_PI.1), steep);
    let signed = _mm256_xor_pd(a, _mm256_and_pd(_mm256_xor_pd(steep, left), sign));
    let folded = add(base, add(rest, signed));
    let angle = _mm256_or_pd(abs(folded), _mm256_and_pd(dy, sign));

    // Unwrapped within half a turn of the mean end rotation (`unwrap_angle`).
    let raw = sub(angle, lanes(&|k| c[k].alpha0));
    let (phi_i, phi_j) = (lanes(&|k| phi[k][0]), lanes(&|k| phi[k][1]));
    let reference = mul(splat(0.5), add(phi_i, phi_j));
    // `unwrap_angle` rounds nothing where |reference - raw| / 2 pi < 0.5, and adds 2 pi times
    // a zero signed like reference - raw. Taken here where |reference - raw| < 3 (a quotient
    // below 0.48 however it rounds), without the division.
    let off = sub(reference, raw);
    if !all(_mm256_cmp_pd::<_CMP_LT_OQ>(abs(off), splat(3.0))) {
        return None;
    }
    let beta = add(raw, _mm256_and_pd(off, sign));

    // The element force equation and U = J S (see `evaluate_entries`).
    let ka = lanes(&|k| c[k].ka);
    let k11 = lanes(&|k| c[k].k11);
    let k12 = lanes(&|k| c[k].k12);
    let dl = sub(l, lanes(&|k| c[k].length));
    let (ti, tj) = (sub(phi_i, beta), sub(phi_j, beta));
    let n = mul(ka, dl);
    let mi = add(mul(k11, ti), mul(k12, tj));
    let mj = add(mul(k12, ti), mul(k11, tj));
    let w0 = mul(neg(sn), inv_l);
    let w1 = mul(cs, inv_l);
    let nodal = [
        add(add(mul(neg(cs), n), mul(w0, mi)), mul(w0, mj)),
        add(add(mul(neg(sn), n), mul(w1, mi)), mul(w1, mj)),
        mi,
        sub(sub(mul(cs, n), mul(w0, mi)), mul(w0, mj)),
        sub(sub(mul(sn, n), mul(w1, mi)), mul(w1, mj)),
        mj,
    ];

    // The tangent's distinct entries (see `tangent` in beam.rs): r = (-c, -s), z = (s, -c)
    // over the translations of node i.
    let nl = mul(n, inv_l);
    let ml2 = mul(add(mi, mj), mul(inv_l, inv_l));
    let (r0, r1, z0, z1) = (neg(cs), neg(sn), sn, neg(cs));
    let entry = |wa, wb, ra, rb, za, zb| {
        let ww = add(mul(wa, wb), mul(wa, wb));
        add(
            add(add(mul(mul(ra, rb), ka), mul(ww, k11)), mul(ww, k12)),
            add(
                mul(mul(za, zb), nl),
                mul(add(mul(ra, zb), mul(rb, za)), ml2),
            ),
        )
    };
    let tangent = [
        entry(w0, w0, r0, r0, z0, z0),
        entry(w0, w1, r0, r1, z0, z1),
        entry(w1, w1, r1, r1, z1, z1),
        add(mul(w0, k11), mul(w0, k12)),
        add(mul(w1, k11), mul(w1, k12)),
    ];

    let mut group = Group::default();
    let rows = (group.forces.iter_mut().zip([n, mi, mj]))
        .chain(group.nodal.iter_mut().zip(nodal))
        .chain(group.tangent.iter_mut().zip(tangent));
    for (row, v) in rows {
        // SAFETY: a row holds four f64.
        unsafe { _mm256_storeu_pd(row.as_mut_ptr(), v) };
    }
    Some(group)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::solver::element::beam::BeamElement;
    use crate::solver::model::Section;

    /// Four elements at a time give `evaluate_entries`' forces, nodal forces and tangent bit
    /// for bit, over chords in every octant (steep and shallow, left and right, up and down),
    /// near the axes and at the octant diagonals, for Bernoulli-Euler and Timoshenko sections;
    /// a group with a zero chord or a rotation past half a turn is handed back.
    #[test]
    fn four_lanes_evaluate_like_the_scalar_path_bit_for_bit() {
        let Some(cpu) = crate::test_support::avx2() else {
            return;
        };
        let section = Section {
            ea: 3.0e6,
            ei: 2.5,
            gae: 1.0e5,
            thickness: 0.0,
        };
        let mut rng = crate::test_support::Rng(0x9e37_79b9_7f4a_7c15);
        let mut next = || rng.unit();
        let mut compared = 0;
        for round in 0..2000 {
            // Any initial direction, a rigid turn of up to 2.5 rad (the end rotations follow
            // it), a stretch and a bend; every fifth round the current chords lie on the axes
            // and octant diagonals.
            let els: [BeamElement; 4] = std::array::from_fn(|k| {
                let a = (next() * 2.0 - 1.0) * std::f64::consts::PI;
                let psi = if (round + k) % 2 == 0 { 0.0 } else { 2.5e-5 };
                BeamElement::new([0.0, 0.0], [a.cos(), a.sin()], section, psi)
            });
            let consts = els.map(|e| e.constants());
            let turn: [f64; 4] = std::array::from_fn(|_| (next() * 2.0 - 1.0) * 2.5);
            let xi: [[f64; 2]; 4] = std::array::from_fn(|_| [1e-3 * next(), -1e-3 * next()]);
            let xj: [[f64; 2]; 4] = std::array::from_fn(|k| {
                let a = match round % 5 {
                    0 => (((next() * 8.0) as i32 - 4) as f64) * std::f64::consts::FRAC_PI_4,
                    _ => consts[k].alpha0 + turn[k] + 0.1 * (next() - 0.5),
                };
                let l = consts[k].length * (1.0 + 0.01 * (next() - 0.5));
                [xi[k][0] + l * a.cos(), xi[k][1] + l * a.sin()]
            });
            let phi: [[f64; 2]; 4] = std::array::from_fn(|k| {
                let bend = 0.2 * (next() - 0.5);
                [turn[k] + bend, turn[k] - bend]
            });
            let c = [&consts[0], &consts[1], &consts[2], &consts[3]];
            let ends = std::array::from_fn(|k| (xi[k], xj[k], phi[k]));
            let Some(g) = evaluate4(cpu, c, ends) else {
                continue;
            };
            for k in 0..4 {
                let (r, t) = consts[k].evaluate_entries(xi[k], xj[k], phi[k][0], phi[k][1], true);
                let entries = |t: TangentEntries| [t.t00, t.t01, t.t11, t.c0, t.c1, t.k11, t.k12];
                let want = [
                    &r.forces[..],
                    r.nodal.as_slice(),
                    &entries(t.expect("tangent")),
                ]
                .concat();
                let (forces, nodal, t) = g.lane(k, &consts[k]);
                let got = [&forces[..], &nodal[..], &entries(t)].concat();
                let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
                assert_eq!(bits(&got), bits(&want), "round {round}, lane {k}");
            }
            compared += 1;
        }
        // (Chords turned across the negative x axis are unwrapped by the scalar path: about two
        // groups in three here.)
        assert!(
            compared > 500,
            "only {compared} groups took the vector path"
        );
        // Handed back: a zero chord, and a chord turned past half a turn from its nodes.
        let el = BeamElement::new([0.0, 0.0], [1.0, 0.0], section, 0.0).constants();
        let c = [&el; 4];
        let mut ends = [([0.0; 2], [1.0, 0.0], [0.0; 2]); 4];
        ends[2].1 = [0.0, 0.0];
        assert!(evaluate4(cpu, c, ends).is_none());
        ends[2] = ([0.0; 2], [-1.0, -1e-3], [3.0, 3.0]);
        assert!(evaluate4(cpu, c, ends).is_none());
    }
}
