//! The twisted L D L^T of a symmetric band: the top of the matrix is factored downward and the
//! bottom upward, two independent pivot chains in one loop, until they meet in a middle block
//! of at least 2K equations (K the bandwidth); `BandMatrix` (linear.rs) factors that block.
//! The substitutions run from both ends the same way. A long chain of elements then waits on
//! half as many pivot-to-pivot latencies (a division each), which is what limits a narrow band
//! factorisation, not the arithmetic. The kernels are those of `ldlt.rs`, read reversed for
//! the bottom.

use super::ldlt::{
    backward_block, backward_one, first_column, forward_block, forward_one, ldlt_column, load_ring,
    store_ring,
};
use super::simd::dispatch;

/// How far each end of a twisted factorisation went: columns 0..top factored from the top,
/// rows n - bottom..n from the bottom. The equations between are the middle block.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) struct Twist {
    /// Columns factored from the top.
    pub(super) top: usize,
    /// Rows factored from the bottom.
    pub(super) bottom: usize,
}

impl Twist {
    /// The middle block's equations.
    pub(super) fn middle(&self, n: usize) -> std::ops::Range<usize> {
        self.top..n - self.bottom
    }
}

/// The fewest equations factored twisted: below this, one chain is short anyway.
pub(super) const TWIST_FROM: usize = 64;

/// Factor both ends of the lower band `ab` (n equations, k sub-diagonals, `k + 1` rows per
/// column) toward a middle block of 2k or 2k + 1 equations. Both ends stop at the first pivot
/// either meets that is tiny, not finite or fails to dominate its 2x2 minors (the middle block
/// is then larger). `None` (nothing done) where the matrix is small or k has no unrolled kernel.
pub(super) fn twisted_ldlt(ab: &mut [f64], n: usize, k: usize, tiny: f64) -> Option<Twist> {
    if k == 0 || k > 8 || n < TWIST_FROM.max(4 * k + 4) {
        return None;
    }
    let count = (n - 2 * k) / 2;
    Some(dispatch(
        #[inline(always)]
        || twisted_kernel(ab, n, k, count, tiny),
    ))
}

/// The factorisation of `twisted_ldlt` for bandwidths 1 to 8.
#[inline(always)]
fn twisted_kernel(ab: &mut [f64], n: usize, k: usize, count: usize, tiny: f64) -> Twist {
    match k {
        1 => twisted_band::<1, 4, 5>(ab, n, count, tiny),
        2 => twisted_band::<2, 9, 10>(ab, n, count, tiny),
        3 => twisted_band::<3, 16, 17>(ab, n, count, tiny),
        4 => twisted_band::<4, 25, 26>(ab, n, count, tiny),
        5 => twisted_band::<5, 36, 37>(ab, n, count, tiny),
        6 => twisted_band::<6, 49, 50>(ab, n, count, tiny),
        7 => twisted_band::<7, 64, 65>(ab, n, count, tiny),
        8 => twisted_band::<8, 81, 82>(ab, n, count, tiny),
        _ => unreachable!("bandwidths 1 to 8 only"),
    }
}

/// `count` columns from each end, the two chains interleaved (windows of W entries from the
/// top, V = W + 1 from the bottom).
#[inline(always)]
fn twisted_band<const K: usize, const W: usize, const V: usize>(
    ab: &mut [f64],
    n: usize,
    count: usize,
    tiny: f64,
) -> Twist {
    let (mut dt, mut ut) = first_column::<K, false>(ab, n);
    let (mut db, mut ub) = first_column::<K, true>(ab, n);
    for j in 0..count {
        if !ldlt_column::<K, W, false>(ab, n, j, &mut dt, &mut ut, tiny) {
            return Twist { top: j, bottom: j };
        }
        if !ldlt_column::<K, V, true>(ab, n, j, &mut db, &mut ub, tiny) {
            return Twist {
                top: j + 1,
                bottom: j,
            };
        }
    }
    Twist {
        top: count,
        bottom: count,
    }
}

/// Solve with the factors of `twisted_ldlt` (lower band of k sub-diagonals): forward
/// substitution from both ends at once, then `middle` solves the middle block in place (its
/// right-hand side then holds every contribution from both ends), then back substitution out
/// to both ends.
pub(super) fn twisted_solve(
    ab: &[f64],
    n: usize,
    k: usize,
    twist: Twist,
    b: &mut [f64],
    middle: impl FnOnce(&mut [f64]),
) {
    dispatch(
        #[inline(always)]
        || twisted_solve_kernel(ab, n, k, twist, b, middle),
    )
}

/// The substitutions of `twisted_solve`.
#[inline(always)]
fn twisted_solve_kernel(
    ab: &[f64],
    n: usize,
    k: usize,
    twist: Twist,
    b: &mut [f64],
    middle: impl FnOnce(&mut [f64]),
) {
    match k {
        1 => twisted_solve_band::<1>(ab, n, twist, b, middle),
        2 => twisted_solve_band::<2>(ab, n, twist, b, middle),
        3 => twisted_solve_band::<3>(ab, n, twist, b, middle),
        4 => twisted_solve_band::<4>(ab, n, twist, b, middle),
        5 => twisted_solve_band::<5>(ab, n, twist, b, middle),
        6 => twisted_solve_band::<6>(ab, n, twist, b, middle),
        7 => twisted_solve_band::<7>(ab, n, twist, b, middle),
        8 => twisted_solve_band::<8>(ab, n, twist, b, middle),
        _ => unreachable!("twisted_ldlt factors bandwidths 1 to 8 only"),
    }
}

/// `twisted_solve` for K sub-diagonals: over the columns both ends factored, in whole blocks
/// of K, each end keeps its K unknowns in a ring (see `ldlt_solve_band`); the rest step by step.
#[inline(always)]
fn twisted_solve_band<const K: usize>(
    ab: &[f64],
    n: usize,
    twist: Twist,
    b: &mut [f64],
    middle: impl FnOnce(&mut [f64]),
) {
    let Twist { top, bottom } = twist;
    let blocks = top.min(bottom) / K;
    let done = blocks * K;
    if blocks > 0 {
        let (mut down, mut up) = (
            load_ring::<K, false>(b, n, 0),
            load_ring::<K, true>(b, n, 0),
        );
        for block in 0..blocks {
            forward_block::<K, false>(ab, n, b, block * K, &mut down);
            forward_block::<K, true>(ab, n, b, block * K, &mut up);
        }
        store_ring::<K, false>(b, n, done, &down);
        store_ring::<K, true>(b, n, done, &up);
    }
    for j in done..top {
        forward_one::<K, false>(ab, n, b, j);
    }
    for j in done..bottom {
        forward_one::<K, true>(ab, n, b, j);
    }
    middle(&mut b[twist.middle(n)]);
    for j in (done..top).rev() {
        backward_one::<K, false>(ab, n, b, j);
    }
    for j in (done..bottom).rev() {
        backward_one::<K, true>(ab, n, b, j);
    }
    if blocks > 0 {
        let (mut down, mut up) = (
            load_ring::<K, false>(b, n, done),
            load_ring::<K, true>(b, n, done),
        );
        for block in (0..blocks).rev() {
            backward_block::<K, false>(ab, n, b, block * K, &mut down);
            backward_block::<K, true>(ab, n, b, block * K, &mut up);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A diagonally dominant symmetric lower band (n equations, k sub-diagonals) with entries
    /// of mixed scales, from a fixed xorshift sequence.
    fn band(n: usize, k: usize, seed: u64) -> Vec<f64> {
        let mut rng = crate::test_support::Rng(seed);
        let mut next = || rng.unit() - 0.5;
        let scale = [1e6f64, 1.0, 30.0];
        let mut ab = vec![0.0; n * (k + 1)];
        for j in 0..n {
            for r in 0..=k.min(n - 1 - j) {
                let s = (scale[j % 3] * scale[(j + r) % 3]).sqrt();
                let v = if r == 0 { k as f64 + 1.5 } else { next() };
                ab[j * (k + 1) + r] = v * s;
            }
        }
        ab
    }

    /// The AVX2 build of the factorisation and the substitutions gives the baseline build's
    /// results bit for bit (no fused multiply-add, no reordering): the solver's results do not
    /// depend on the CPU it runs on. Skipped (with a note) on a CPU without AVX2.
    #[test]
    fn avx2_build_factors_and_solves_bit_for_bit_like_the_baseline() {
        #[cfg(target_arch = "x86_64")]
        {
            if !crate::test_support::has_avx2() {
                return;
            }
            for (n, k) in [(64usize, 1usize), (97, 2), (200, 3), (301, 5), (150, 8)] {
                let count = (n - 2 * k) / 2;
                let mut base = band(n, k, 0x9e37_79b9 + n as u64);
                let mut wide = base.clone();
                let t_base = twisted_kernel(&mut base, n, k, count, 0.0);
                // SAFETY: the CPU has AVX2 (checked above).
                let t_wide = unsafe {
                    crate::solver::simd::with_avx2(
                        #[inline(always)]
                        || twisted_kernel(&mut wide, n, k, count, 0.0),
                    )
                };
                assert_eq!(t_base, t_wide, "n {n} k {k}");
                assert!(t_base.top == count && t_base.bottom == count, "n {n} k {k}");
                let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
                assert_eq!(bits(&base), bits(&wide), "factors, n {n} k {k}");
                let rhs: Vec<f64> = (0..n).map(|i| ((i * 7919) % 13) as f64 - 6.0).collect();
                let (mut x_base, mut x_wide) = (rhs.clone(), rhs.clone());
                // The middle block: the same stand-in (halving) in both builds.
                let middle = |m: &mut [f64]| m.iter_mut().for_each(|v| *v *= 0.5);
                twisted_solve_kernel(&base, n, k, t_base, &mut x_base, middle);
                // SAFETY: as above.
                unsafe {
                    crate::solver::simd::with_avx2(
                        #[inline(always)]
                        || twisted_solve_kernel(&wide, n, k, t_wide, &mut x_wide, middle),
                    )
                };
                assert_eq!(bits(&x_base), bits(&x_wide), "solution, n {n} k {k}");
                assert!(x_base.iter().all(|v| v.is_finite() && *v != 0.0));
            }
        }
    }
}
