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
    if k == 0 || n < TWIST_FROM.max(4 * k + 4) {
        return None;
    }
    let count = (n - 2 * k) / 2;
    Some(match k {
        1 => twisted_band::<1, 4, 5>(ab, n, count, tiny),
        2 => twisted_band::<2, 9, 10>(ab, n, count, tiny),
        3 => twisted_band::<3, 16, 17>(ab, n, count, tiny),
        4 => twisted_band::<4, 25, 26>(ab, n, count, tiny),
        5 => twisted_band::<5, 36, 37>(ab, n, count, tiny),
        6 => twisted_band::<6, 49, 50>(ab, n, count, tiny),
        7 => twisted_band::<7, 64, 65>(ab, n, count, tiny),
        8 => twisted_band::<8, 81, 82>(ab, n, count, tiny),
        _ => return None,
    })
}

/// `count` columns from each end, the two chains interleaved (windows of W entries from the
/// top, V = W + 1 from the bottom).
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
