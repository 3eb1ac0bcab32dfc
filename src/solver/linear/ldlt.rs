//! The symmetric band kernels of the linear solve: L D L^T of a band stored as its lower part
//! (`k + 1` rows per column: the diagonal, then the sub-diagonals), without interchanges while
//! every pivot dominates its 2x2 minors, and its substitutions. `BandMatrix` (linear.rs) owns
//! the storage and hands over to its pivoting LU where these kernels stop. Each kernel step is
//! written once for either end of the matrix (`REV`: the matrix read from its last equation
//! up, as the twisted factorisation in `twisted.rs` does from the bottom).

use super::reduce::axpy;

/// L D L^T of a symmetric band matrix stored as its lower band (`k + 1` rows per column: the
/// diagonal, then the sub-diagonals), in place: D on the diagonal, L below it. Stops before the
/// first column whose pivot is tiny, not finite or fails to dominate its 2x2 minors, and
/// returns that column (columns before it factored, the rest the updated trailing matrix).
pub(super) fn ldlt(ab: &mut [f64], n: usize, k: usize, tiny: f64) -> Result<(), usize> {
    let full = match k {
        1 => ldlt_band::<1, 4>(ab, n, tiny),
        2 => ldlt_band::<2, 9>(ab, n, tiny),
        3 => ldlt_band::<3, 16>(ab, n, tiny),
        4 => ldlt_band::<4, 25>(ab, n, tiny),
        5 => ldlt_band::<5, 36>(ab, n, tiny),
        6 => ldlt_band::<6, 49>(ab, n, tiny),
        7 => ldlt_band::<7, 64>(ab, n, tiny),
        8 => ldlt_band::<8, 81>(ab, n, tiny),
        _ => Ok(0),
    }?;
    for j in full..n {
        if !ldlt_step_any(ab, j, k, k.min(n - 1 - j), tiny) {
            return Err(j);
        }
    }
    Ok(())
}

/// Where entry (row offset `r`, column `c`) of a column step's window lies: from the top, the
/// window starts at column j and column j + c's rows j + c + r follow one another; from the
/// bottom (`REV`), the matrix is read reversed, so reversed column j + c's entry r is the stored
/// entry r of column R - c - r (R the stored row of reversed column j), and the window starts
/// at column R - K - 1.
#[inline(always)]
pub(super) const fn at<const K: usize, const REV: bool>(c: usize, r: usize) -> usize {
    if REV {
        (K + 1 - c - r) * (K + 1) + r
    } else {
        c * (K + 1) + r
    }
}

/// The carried pivot and column below it of (reversed, for `REV`) column 0.
#[inline(always)]
pub(super) fn first_column<const K: usize, const REV: bool>(
    ab: &[f64],
    n: usize,
) -> (f64, [f64; K]) {
    let ld = K + 1;
    if REV {
        let d = ab[(n - 1) * ld];
        (d, std::array::from_fn(|t| ab[(n - 2 - t) * ld + 1 + t]))
    } else {
        let d = ab.first().copied().unwrap_or(0.0);
        (
            d,
            std::array::from_fn(|t| ab.get(1 + t).copied().unwrap_or(0.0)),
        )
    }
}

/// One column of the unrolled L D L^T (reversed column `j` for `REV`), with a full band of K
/// sub-diagonals below it and one more column after. The pivot `d` and the column `u` below it
/// come in carried from the last step and leave as the next column's. False (and nothing
/// written) if the pivot is tiny, not finite or fails to dominate its 2x2 minors. The window
/// holds W entries: (K + 1)^2 from the top, one more from the bottom.
#[inline(always)]
pub(super) fn ldlt_column<const K: usize, const W: usize, const REV: bool>(
    ab: &mut [f64],
    n: usize,
    j: usize,
    d: &mut f64,
    u: &mut [f64; K],
    tiny: f64,
) -> bool {
    let ld = K + 1;
    let base = if REV { (n - 2 - j - K) * ld } else { j * ld };
    let window: &mut [f64; W] = (&mut ab[base..base + W]).try_into().expect("W entries");
    let ad = d.abs();
    if ad <= tiny || !ad.is_finite() {
        return false;
    }
    let mut dominates = true;
    for t in 0..K {
        dominates &= u[t] * u[t] <= ad * window[at::<K, REV>(t + 1, 0)].abs();
    }
    if !dominates {
        return false;
    }
    // The chain from pivot to pivot is u_0^2, one division and one subtraction
    // (d' = a - u_0^2 / d), with no store and reload between. Two divisions per column: more
    // would make the divider, not the chain, the limit.
    let next = window[at::<K, REV>(1, 0)] - u[0] * u[0] / *d;
    let inv = 1.0 / *d;
    // The multipliers l = u / d, stored as the column of L and used for the update: one
    // multiplication an entry.
    let l: [f64; K] = std::array::from_fn(|t| u[t] * inv);
    let mut below: [f64; K] = std::array::from_fn(|s| window[at::<K, REV>(1, 1 + s)]);
    for s in 0..K - 1 {
        below[s] -= l[s + 1] * u[0];
    }
    // Column j + t + 1 loses l_s u_t in its rows j + s + 1 for s >= t (column j + 1, t = 0,
    // is done above).
    for t in 1..K {
        for s in t..K {
            window[at::<K, REV>(t + 1, s - t)] -= l[s] * u[t];
        }
    }
    window[at::<K, REV>(1, 0)] = next;
    for s in 0..K {
        window[at::<K, REV>(1, 1 + s)] = below[s];
    }
    for t in 0..K {
        window[at::<K, REV>(0, 1 + t)] = l[t];
    }
    (*d, *u) = (next, below);
    true
}

/// The columns of `ldlt` with a full band of K sub-diagonals below them (unrolled for K; the
/// window of the K + 1 columns a step touches is a fixed array of W = (K + 1)^2 entries).
/// Returns the first column it left to the general step.
fn ldlt_band<const K: usize, const W: usize>(
    ab: &mut [f64],
    n: usize,
    tiny: f64,
) -> Result<usize, usize> {
    debug_assert_eq!(W, (K + 1) * (K + 1));
    let columns = n.saturating_sub(K);
    let (mut d, mut u) = first_column::<K, false>(ab, n);
    for j in 0..columns {
        if !ldlt_column::<K, W, false>(ab, n, j, &mut d, &mut u, tiny) {
            return Err(j);
        }
    }
    Ok(columns)
}

/// `ldlt_step` for any bandwidth `k` (storage) and `km` rows below the diagonal.
fn ldlt_step_any(ab: &mut [f64], j: usize, k: usize, km: usize, tiny: f64) -> bool {
    let ld = k + 1;
    let dj = j * ld;
    let d = ab[dj];
    let ad = d.abs();
    if ad <= tiny || !ad.is_finite() {
        return false;
    }
    if (0..km).any(|t| ab[dj + 1 + t].powi(2) > ad * ab[dj + (t + 1) * ld].abs()) {
        return false;
    }
    let inv = 1.0 / d;
    for t in 0..km {
        let u = ab[dj + 1 + t];
        let column = dj + (t + 1) * ld;
        for s in t..km {
            let l = ab[dj + 1 + s] * inv;
            ab[column + s - t] -= l * u;
        }
    }
    for v in &mut ab[dj + 1..dj + 1 + km] {
        *v *= inv;
    }
    true
}

/// Solve L D L^T x = b in place (factors from `ldlt`, lower band of `k` sub-diagonals).
pub(super) fn ldlt_solve(ab: &[f64], n: usize, k: usize, b: &mut [f64]) {
    match k {
        3 => ldlt_solve_band::<3>(ab, n, b),
        4 => ldlt_solve_band::<4>(ab, n, b),
        5 => ldlt_solve_band::<5>(ab, n, b),
        6 => ldlt_solve_band::<6>(ab, n, b),
        8 => ldlt_solve_band::<8>(ab, n, b),
        _ => {
            ldlt_forward(ab, n, k, b, 0..n);
            ldlt_backward(ab, n, k, b, 0..n);
        }
    }
}

/// The forward substitution L y = b over the columns `columns` (any bandwidth).
fn ldlt_forward(ab: &[f64], n: usize, k: usize, b: &mut [f64], columns: std::ops::Range<usize>) {
    let ld = k + 1;
    for j in columns {
        let km = k.min(n - 1 - j);
        let bj = b[j];
        axpy(
            &mut b[j + 1..j + 1 + km],
            &ab[j * ld + 1..j * ld + 1 + km],
            bj,
        );
    }
}

/// The scaling and back substitution x = L^-T D^-1 y over the columns `columns`, last first
/// (any bandwidth).
fn ldlt_backward(ab: &[f64], n: usize, k: usize, b: &mut [f64], columns: std::ops::Range<usize>) {
    let ld = k + 1;
    for j in columns.rev() {
        let km = k.min(n - 1 - j);
        let l = &ab[j * ld + 1..j * ld + 1 + km];
        let dot: f64 = l
            .iter()
            .zip(&b[j + 1..j + 1 + km])
            .map(|(l, x)| l * x)
            .sum();
        b[j] = b[j] / ab[j * ld] - dot;
    }
}

/// `ldlt_solve` for a band of K sub-diagonals. Over whole blocks of K columns with full bands,
/// the K unknowns a column touches stay in registers as a ring (slot `m mod K` holds unknown m;
/// each column of a block is its own instance of the step, so every slot index is a constant):
/// each substitution step then waits on one multiply-subtract, not on a store and reload of b.
#[inline(always)]
fn ldlt_solve_band<const K: usize>(ab: &[f64], n: usize, b: &mut [f64]) {
    let blocks = n.saturating_sub(K) / K;
    let done = blocks * K;
    if blocks > 0 {
        let mut ring = load_ring::<K, false>(b, n, 0);
        for block in 0..blocks {
            forward_block::<K, false>(ab, n, b, block * K, &mut ring);
        }
        store_ring::<K, false>(b, n, done, &ring);
    }
    ldlt_forward(ab, n, K, b, done..n);
    ldlt_backward(ab, n, K, b, done..n);
    if blocks == 0 {
        return;
    }
    let mut ring = load_ring::<K, false>(b, n, done);
    for block in (0..blocks).rev() {
        backward_block::<K, false>(ab, n, b, block * K, &mut ring);
    }
}

/// Where unknown `j` (reversed for `REV`) lies in b.
#[inline(always)]
pub(super) const fn unknown<const REV: bool>(n: usize, j: usize) -> usize {
    if REV {
        n - 1 - j
    } else {
        j
    }
}

/// The ring of unknowns j..j + K (reversed for `REV`; j a multiple of K, so slot t holds
/// unknown j + t).
#[inline(always)]
pub(super) fn load_ring<const K: usize, const REV: bool>(
    b: &[f64],
    n: usize,
    j: usize,
) -> [f64; K] {
    std::array::from_fn(|t| b[unknown::<REV>(n, j + t)])
}

/// Write the ring of unknowns j..j + K back (see `load_ring`).
#[inline(always)]
pub(super) fn store_ring<const K: usize, const REV: bool>(
    b: &mut [f64],
    n: usize,
    j: usize,
    ring: &[f64; K],
) {
    for (t, v) in ring.iter().enumerate() {
        b[unknown::<REV>(n, j + t)] = *v;
    }
}

/// The pivot and the K multipliers below it of (reversed, for `REV`) column j.
#[inline(always)]
fn factor_column<const K: usize, const REV: bool>(
    ab: &[f64],
    n: usize,
    j: usize,
) -> (f64, [f64; K]) {
    let ld = K + 1;
    if REV {
        // Reversed column j: stored row R = n - 1 - j, its entries t in columns R - 1 - t.
        let base = (n - 1 - j - K) * ld;
        let w = &ab[base..base + ld * ld];
        (
            w[K * ld],
            std::array::from_fn(|t| w[(K - 1 - t) * ld + 1 + t]),
        )
    } else {
        let column: &[f64; K] = ab[j * ld + 1..].first_chunk().expect("K rows");
        (ab[j * ld], *column)
    }
}

/// The forward substitution of the K columns from `j` (a multiple of K) with the ring.
#[inline(always)]
pub(super) fn forward_block<const K: usize, const REV: bool>(
    ab: &[f64],
    n: usize,
    b: &mut [f64],
    j: usize,
    ring: &mut [f64; K],
) {
    forward_step::<K, 0, REV>(ab, n, b, j, ring);
    forward_step::<K, 1, REV>(ab, n, b, j, ring);
    forward_step::<K, 2, REV>(ab, n, b, j, ring);
    forward_step::<K, 3, REV>(ab, n, b, j, ring);
    forward_step::<K, 4, REV>(ab, n, b, j, ring);
    forward_step::<K, 5, REV>(ab, n, b, j, ring);
    forward_step::<K, 6, REV>(ab, n, b, j, ring);
    forward_step::<K, 7, REV>(ab, n, b, j, ring);
}

/// The scaling and back substitution of the K columns from `j` (a multiple of K), last first,
/// with the ring.
#[inline(always)]
pub(super) fn backward_block<const K: usize, const REV: bool>(
    ab: &[f64],
    n: usize,
    b: &mut [f64],
    j: usize,
    ring: &mut [f64; K],
) {
    backward_step::<K, 7, REV>(ab, n, b, j, ring);
    backward_step::<K, 6, REV>(ab, n, b, j, ring);
    backward_step::<K, 5, REV>(ab, n, b, j, ring);
    backward_step::<K, 4, REV>(ab, n, b, j, ring);
    backward_step::<K, 3, REV>(ab, n, b, j, ring);
    backward_step::<K, 2, REV>(ab, n, b, j, ring);
    backward_step::<K, 1, REV>(ab, n, b, j, ring);
    backward_step::<K, 0, REV>(ab, n, b, j, ring);
}

/// Column `block + R` of the forward ring substitution (nothing if R >= K, K <= 8). Before
/// it, slot j mod K holds b[j] (final) and the others b[j+1..j+K-1].
#[inline(always)]
fn forward_step<const K: usize, const R: usize, const REV: bool>(
    ab: &[f64],
    n: usize,
    b: &mut [f64],
    block: usize,
    ring: &mut [f64; K],
) {
    if R >= K {
        return;
    }
    let j = block + R;
    let (_, l) = factor_column::<K, REV>(ab, n, j);
    let x = ring[R];
    b[unknown::<REV>(n, j)] = x;
    ring[R] = b[unknown::<REV>(n, j + K)];
    // Plain ranges (not `1..=K`) so that every loop unrolls and the ring stays in registers.
    for t in 0..K {
        ring[(R + 1 + t) % K] -= l[t] * x;
    }
}

/// Column `block + R` of the backward ring substitution (nothing if R >= K, K <= 8). After
/// it, slot j mod K holds x[j] and the others x[j+1..j+K-1].
#[inline(always)]
fn backward_step<const K: usize, const R: usize, const REV: bool>(
    ab: &[f64],
    n: usize,
    b: &mut [f64],
    block: usize,
    ring: &mut [f64; K],
) {
    if R >= K {
        return;
    }
    let j = block + R;
    let (d, l) = factor_column::<K, REV>(ab, n, j);
    // The nearest unknown, the last computed, enters last.
    let mut dot = 0.0;
    for t in (0..K).rev() {
        dot += l[t] * ring[(R + 1 + t) % K];
    }
    let at = unknown::<REV>(n, j);
    let x = b[at] / d - dot;
    b[at] = x;
    ring[R] = x;
}

/// One forward substitution step of (reversed, for `REV`) column j, outside the ring.
#[inline(always)]
pub(super) fn forward_one<const K: usize, const REV: bool>(
    ab: &[f64],
    n: usize,
    b: &mut [f64],
    j: usize,
) {
    let (_, l) = factor_column::<K, REV>(ab, n, j);
    let x = b[unknown::<REV>(n, j)];
    for t in 0..K {
        b[unknown::<REV>(n, j + 1 + t)] -= l[t] * x;
    }
}

/// One back substitution step of (reversed, for `REV`) column j, outside the ring.
#[inline(always)]
pub(super) fn backward_one<const K: usize, const REV: bool>(
    ab: &[f64],
    n: usize,
    b: &mut [f64],
    j: usize,
) {
    let (d, l) = factor_column::<K, REV>(ab, n, j);
    let mut dot = 0.0;
    for t in (0..K).rev() {
        dot += l[t] * b[unknown::<REV>(n, j + 1 + t)];
    }
    let at = unknown::<REV>(n, j);
    b[at] = b[at] / d - dot;
}
