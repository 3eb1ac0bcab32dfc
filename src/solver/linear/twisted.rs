//! The twisted L D L^T of a symmetric band: the top of the matrix is factored downward and the
//! bottom upward, two independent pivot chains in one loop, until they meet in a middle block
//! of at least 2K equations (K the bandwidth); `BandMatrix` (linear.rs) factors that block.
//! The substitutions run from both ends the same way. A long chain of elements then waits on
//! half as many pivot-to-pivot latencies (a division each), which is what limits a narrow band
//! factorisation, not the arithmetic. Given the right-hand side, the forward substitution runs
//! inside the factorisation, a chunk of columns behind it, while they are in cache. The kernels
//! are those of `ldlt.rs`, read reversed for the bottom.

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

/// Blocks of K columns each end factors before the forward substitution of `twisted_ldlt`
/// catches up (with K = 5, 5120 columns: about 250 KB of band at each end, so the substitution
/// reads the factors from cache, not memory).
const CHUNK_BLOCKS: usize = 1024;

/// Factor both ends of the lower band `ab` (n equations, k sub-diagonals, `k + 1` rows per
/// column) toward a middle block of 2k or 2k + 1 equations. Both ends stop at the first pivot
/// either meets that is tiny, not finite or fails to dominate its 2x2 minors (the middle block
/// is then larger). `None` (nothing done) where the matrix is small or k has no unrolled kernel.
///
/// With a right-hand side `b`, its forward substitution from both ends is done too, a chunk
/// of columns at a time right after the chunk is factored (the factors still in cache), with
/// the arithmetic of `twisted_solve`'s: `twisted_solve` with `forward_done` then finishes the
/// solve.
pub(super) fn twisted_ldlt(
    ab: &mut [f64],
    n: usize,
    k: usize,
    tiny: f64,
    b: Option<&mut [f64]>,
) -> Option<Twist> {
    if k == 0 || k > 8 || n < TWIST_FROM.max(4 * k + 4) {
        return None;
    }
    let count = (n - 2 * k) / 2;
    Some(dispatch(
        #[inline(always)]
        || twisted_kernel(ab, n, k, count, tiny, b),
    ))
}

/// The factorisation of `twisted_ldlt` for bandwidths 1 to 8.
#[inline(always)]
fn twisted_kernel(
    ab: &mut [f64],
    n: usize,
    k: usize,
    count: usize,
    tiny: f64,
    b: Option<&mut [f64]>,
) -> Twist {
    match k {
        1 => twisted_band::<1, 4, 5>(ab, n, count, tiny, b),
        2 => twisted_band::<2, 9, 10>(ab, n, count, tiny, b),
        3 => twisted_band::<3, 16, 17>(ab, n, count, tiny, b),
        4 => twisted_band::<4, 25, 26>(ab, n, count, tiny, b),
        5 => twisted_band::<5, 36, 37>(ab, n, count, tiny, b),
        6 => twisted_band::<6, 49, 50>(ab, n, count, tiny, b),
        7 => twisted_band::<7, 64, 65>(ab, n, count, tiny, b),
        8 => twisted_band::<8, 81, 82>(ab, n, count, tiny, b),
        _ => unreachable!("bandwidths 1 to 8 only"),
    }
}

/// `count` columns from each end, the two chains interleaved (windows of W entries from the
/// top, V = W + 1 from the bottom), a chunk of `CHUNK_BLOCKS` blocks of K at a time; after each
/// chunk, the forward substitution of `b` (if given) over the whole blocks factored so far.
#[inline(always)]
fn twisted_band<const K: usize, const W: usize, const V: usize>(
    ab: &mut [f64],
    n: usize,
    count: usize,
    tiny: f64,
    mut b: Option<&mut [f64]>,
) -> Twist {
    let (mut dt, mut ut) = first_column::<K, false>(ab, n);
    let (mut db, mut ub) = first_column::<K, true>(ab, n);
    // The forward substitution's rings of unknowns from the top and from the bottom, and the
    // blocks of K columns it has done at each end.
    let mut rings = (b.as_deref()).map(|b| load_rings::<K>(b, n));
    let mut solved = 0;
    let mut j = 0;
    let twist = loop {
        let end = count.min(j + CHUNK_BLOCKS * K);
        let mut stop = None;
        while j < end {
            if !ldlt_column::<K, W, false>(ab, n, j, &mut dt, &mut ut, tiny) {
                stop = Some(Twist { top: j, bottom: j });
                break;
            }
            if !ldlt_column::<K, V, true>(ab, n, j, &mut db, &mut ub, tiny) {
                stop = Some(Twist {
                    top: j + 1,
                    bottom: j,
                });
                break;
            }
            j += 1;
        }
        let twist = stop.unwrap_or(Twist { top: j, bottom: j });
        if let (Some(b), Some(rings)) = (b.as_deref_mut(), rings.as_mut()) {
            let ready = twist.top.min(twist.bottom) / K;
            forward_blocks::<K>(ab, n, b, solved..ready, rings);
            solved = ready;
        }
        if stop.is_some() || j == count {
            break twist;
        }
    };
    if let (Some(b), Some(rings)) = (b, rings) {
        forward_finish::<K>(ab, n, b, twist, solved, rings);
    }
    twist
}

/// The rings of the forward substitution from both ends, at their first unknowns.
#[inline(always)]
fn load_rings<const K: usize>(b: &[f64], n: usize) -> ([f64; K], [f64; K]) {
    (
        load_ring::<K, false>(b, n, 0),
        load_ring::<K, true>(b, n, 0),
    )
}

/// The forward substitution of `blocks` (blocks of K columns, factored at both ends) from the
/// top and from the bottom, each end's unknowns carried in its ring.
#[inline(always)]
fn forward_blocks<const K: usize>(
    ab: &[f64],
    n: usize,
    b: &mut [f64],
    blocks: std::ops::Range<usize>,
    (down, up): &mut ([f64; K], [f64; K]),
) {
    for block in blocks {
        forward_block::<K, false>(ab, n, b, block * K, down);
        forward_block::<K, true>(ab, n, b, block * K, up);
    }
}

/// The rest of the forward substitution after `solved` blocks from each end: the rings back
/// into `b`, then the columns each end factored beyond them, one by one.
#[inline(always)]
fn forward_finish<const K: usize>(
    ab: &[f64],
    n: usize,
    b: &mut [f64],
    twist: Twist,
    solved: usize,
    (down, up): ([f64; K], [f64; K]),
) {
    let done = solved * K;
    store_ring::<K, false>(b, n, done, &down);
    store_ring::<K, true>(b, n, done, &up);
    for j in done..twist.top {
        forward_one::<K, false>(ab, n, b, j);
    }
    for j in done..twist.bottom {
        forward_one::<K, true>(ab, n, b, j);
    }
}

/// Solve with the factors of `twisted_ldlt` (lower band of k sub-diagonals): forward
/// substitution from both ends at once (unless `twisted_ldlt` did it, `forward_done`), then
/// `middle` solves the middle block in place (its right-hand side then holds every
/// contribution from both ends), then back substitution out to both ends.
pub(super) fn twisted_solve(
    ab: &[f64],
    n: usize,
    k: usize,
    twist: Twist,
    b: &mut [f64],
    forward_done: bool,
    middle: impl FnOnce(&mut [f64]),
) {
    dispatch(
        #[inline(always)]
        || twisted_solve_kernel(ab, n, k, twist, b, forward_done, middle),
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
    forward_done: bool,
    middle: impl FnOnce(&mut [f64]),
) {
    match k {
        1 => twisted_solve_band::<1>(ab, n, twist, b, forward_done, middle),
        2 => twisted_solve_band::<2>(ab, n, twist, b, forward_done, middle),
        3 => twisted_solve_band::<3>(ab, n, twist, b, forward_done, middle),
        4 => twisted_solve_band::<4>(ab, n, twist, b, forward_done, middle),
        5 => twisted_solve_band::<5>(ab, n, twist, b, forward_done, middle),
        6 => twisted_solve_band::<6>(ab, n, twist, b, forward_done, middle),
        7 => twisted_solve_band::<7>(ab, n, twist, b, forward_done, middle),
        8 => twisted_solve_band::<8>(ab, n, twist, b, forward_done, middle),
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
    forward_done: bool,
    middle: impl FnOnce(&mut [f64]),
) {
    let Twist { top, bottom } = twist;
    let blocks = top.min(bottom) / K;
    let done = blocks * K;
    if !forward_done {
        let mut rings = load_rings::<K>(b, n);
        forward_blocks::<K>(ab, n, b, 0..blocks, &mut rings);
        forward_finish::<K>(ab, n, b, twist, blocks, rings);
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
            let Some(cpu) = crate::test_support::avx2() else {
                return;
            };
            for (n, k) in [(64usize, 1usize), (97, 2), (200, 3), (301, 5), (150, 8)] {
                let count = (n - 2 * k) / 2;
                let mut base = band(n, k, 0x9e37_79b9 + n as u64);
                let mut wide = base.clone();
                let t_base = twisted_kernel(&mut base, n, k, count, 0.0, None);
                let t_wide = cpu.run(
                    #[inline(always)]
                    || twisted_kernel(&mut wide, n, k, count, 0.0, None),
                );
                assert_eq!(t_base, t_wide, "n {n} k {k}");
                assert!(t_base.top == count && t_base.bottom == count, "n {n} k {k}");
                let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
                assert_eq!(bits(&base), bits(&wide), "factors, n {n} k {k}");
                let rhs: Vec<f64> = (0..n).map(|i| ((i * 7919) % 13) as f64 - 6.0).collect();
                let (mut x_base, mut x_wide) = (rhs.clone(), rhs.clone());
                // The middle block: the same stand-in (halving) in both builds.
                let middle = |m: &mut [f64]| m.iter_mut().for_each(|v| *v *= 0.5);
                twisted_solve_kernel(&base, n, k, t_base, &mut x_base, false, middle);
                cpu.run(
                    #[inline(always)]
                    || twisted_solve_kernel(&wide, n, k, t_wide, &mut x_wide, false, middle),
                );
                assert_eq!(bits(&x_base), bits(&x_wide), "solution, n {n} k {k}");
                assert!(x_base.iter().all(|v| v.is_finite() && *v != 0.0));
            }
        }
    }

    /// The forward substitution done inside the factorisation, a chunk of columns behind it,
    /// gives the separate substitution's results bit for bit, over several chunks at each end
    /// and wherever a pivot stops the ends: in the first chunk, either side of a chunk
    /// boundary, in a later chunk from the bottom, near the middle. The factors and the twist
    /// must not change either.
    #[test]
    fn forward_substitution_in_chunks_is_the_separate_one_bit_for_bit() {
        let chunk = CHUNK_BLOCKS * 5;
        let n = 4 * chunk + 37;
        let stops = [
            None,
            Some(7),
            Some(chunk - 1),
            Some(chunk),
            Some(n - 1 - (chunk + 3)),
            Some(n / 2 - 9),
        ];
        let cases = stops.iter().map(|&s| (n, 5, s));
        for (n, k, stop) in cases.chain([(2 * chunk + 11, 3, None), (3 * chunk, 8, None)]) {
            let mut ab = band(n, k, 0x5eed + n as u64);
            if let Some(i) = stop {
                // Row and column i zero: pivot i is exactly zero whichever end reaches it.
                for r in 0..=k.min(n - 1 - i) {
                    ab[i * (k + 1) + r] = 0.0;
                }
                for r in 1..=k.min(i) {
                    ab[(i - r) * (k + 1) + r] = 0.0;
                }
            }
            let count = (n - 2 * k) / 2;
            let rhs: Vec<f64> = (0..n).map(|i| ((i * 7919) % 13) as f64 - 6.0).collect();
            let middle = |m: &mut [f64]| m.iter_mut().for_each(|v| *v *= 0.5);
            let (mut apart, mut fused) = (ab.clone(), ab);
            let t_apart = twisted_kernel(&mut apart, n, k, count, 0.0, None);
            let mut x_apart = rhs.clone();
            twisted_solve_kernel(&apart, n, k, t_apart, &mut x_apart, false, middle);
            let mut x_fused = rhs;
            let t_fused = twisted_kernel(&mut fused, n, k, count, 0.0, Some(&mut x_fused));
            twisted_solve_kernel(&fused, n, k, t_fused, &mut x_fused, true, middle);
            let case = format!("n {n} k {k} stop {stop:?}");
            assert_eq!(t_apart, t_fused, "{case}");
            let expected = match stop {
                None => (count, count),
                Some(i) if i < n / 2 => (i, i),
                Some(i) => (n - i, n - 1 - i),
            };
            assert_eq!((t_apart.top, t_apart.bottom), expected, "{case}");
            let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
            assert_eq!(bits(&apart), bits(&fused), "factors, {case}");
            assert_eq!(bits(&x_apart), bits(&x_fused), "solution, {case}");
            assert!(
                x_fused.iter().filter(|v| **v != 0.0).count() > n / 2,
                "{case}"
            );
        }
    }
}
