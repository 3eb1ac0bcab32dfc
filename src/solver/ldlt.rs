//! The symmetric band kernels of the linear solve: L D L^T of a band stored as its lower part
//! (`k + 1` rows per column: the diagonal, then the sub-diagonals), without interchanges while
//! every pivot dominates its 2x2 minors, and its substitutions. `BandMatrix` (linear.rs) owns
//! the storage and hands over to its pivoting LU where these kernels stop.

use super::linear::axpy;

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

/// The columns of `ldlt` with a full band of K sub-diagonals below them (unrolled for K; the
/// window of the K + 1 columns a step touches is a fixed array of W = (K + 1)^2 entries).
/// Returns the first column it left to the general step.
fn ldlt_band<const K: usize, const W: usize>(
    ab: &mut [f64],
    n: usize,
    tiny: f64,
) -> Result<usize, usize> {
    debug_assert_eq!(W, (K + 1) * (K + 1));
    let ld = K + 1;
    let columns = n.saturating_sub(K);
    // The pivot and the column below it are carried from one column to the next in registers:
    // the chain from pivot to pivot is u_0^2, one division and one subtraction
    // (d' = a - u_0^2 / d, u'_0 = a - (u_1 u_0) / d), with no store and reload between.
    let mut d = ab.first().copied().unwrap_or(0.0);
    let mut u: [f64; K] = std::array::from_fn(|t| ab.get(1 + t).copied().unwrap_or(0.0));
    for j in 0..columns {
        let window: &mut [f64; W] = (&mut ab[j * ld..j * ld + W]).try_into().expect("W entries");
        let ad = d.abs();
        if ad <= tiny || !ad.is_finite() {
            return Err(j);
        }
        let mut dominates = true;
        for t in 0..K {
            dominates &= u[t] * u[t] <= ad * window[(t + 1) * ld].abs();
        }
        if !dominates {
            return Err(j);
        }
        // Two divisions per column: more would make the divider, not the chain, the limit.
        let next = window[ld] - u[0] * u[0] / d;
        let inv = 1.0 / d;
        let mut below: [f64; K] = std::array::from_fn(|s| window[ld + 1 + s]);
        for s in 0..K - 1 {
            below[s] -= (u[s + 1] * u[0]) * inv;
        }
        // Column j + t + 1 loses u_s u_t / d in its rows j + s + 1 for s >= t (column j + 1,
        // t = 0, is done above).
        for t in 1..K {
            let column = (t + 1) * ld;
            for s in t..K {
                window[column + s - t] -= (u[s] * u[t]) * inv;
            }
        }
        window[ld] = next;
        window[ld + 1..ld + 1 + K].copy_from_slice(&below);
        for t in 0..K {
            window[1 + t] = u[t] * inv;
        }
        (d, u) = (next, below);
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
        // Forward: before column j, slot j mod K holds b[j] (final) and the others b[j+1..j+K-1].
        let mut ring: [f64; K] = b[..K].try_into().expect("K unknowns");
        for block in 0..blocks {
            let j = block * K;
            forward_step::<K, 0>(ab, b, j, &mut ring);
            forward_step::<K, 1>(ab, b, j, &mut ring);
            forward_step::<K, 2>(ab, b, j, &mut ring);
            forward_step::<K, 3>(ab, b, j, &mut ring);
            forward_step::<K, 4>(ab, b, j, &mut ring);
            forward_step::<K, 5>(ab, b, j, &mut ring);
            forward_step::<K, 6>(ab, b, j, &mut ring);
            forward_step::<K, 7>(ab, b, j, &mut ring);
        }
        b[done..done + K].copy_from_slice(&ring);
    }
    ldlt_forward(ab, n, K, b, done..n);
    ldlt_backward(ab, n, K, b, done..n);
    if blocks == 0 {
        return;
    }
    // Backward: after column j, slot j mod K holds x[j] and the others x[j+1..j+K-1].
    let mut ring: [f64; K] = b[done..done + K].try_into().expect("K unknowns");
    for block in (0..blocks).rev() {
        let j = block * K;
        backward_step::<K, 7>(ab, b, j, &mut ring);
        backward_step::<K, 6>(ab, b, j, &mut ring);
        backward_step::<K, 5>(ab, b, j, &mut ring);
        backward_step::<K, 4>(ab, b, j, &mut ring);
        backward_step::<K, 3>(ab, b, j, &mut ring);
        backward_step::<K, 2>(ab, b, j, &mut ring);
        backward_step::<K, 1>(ab, b, j, &mut ring);
        backward_step::<K, 0>(ab, b, j, &mut ring);
    }
}

/// Column `block + R` of the forward ring substitution (nothing if R >= K, K <= 8).
#[inline(always)]
fn forward_step<const K: usize, const R: usize>(
    ab: &[f64],
    b: &mut [f64],
    block: usize,
    ring: &mut [f64; K],
) {
    if R >= K {
        return;
    }
    let j = block + R;
    let l: &[f64; K] = ab[j * (K + 1) + 1..].first_chunk().expect("K rows");
    let x = ring[R];
    b[j] = x;
    ring[R] = b[j + K];
    for t in 1..=K {
        ring[(R + t) % K] -= l[t - 1] * x;
    }
}

/// Column `block + R` of the backward ring substitution (nothing if R >= K, K <= 8).
#[inline(always)]
fn backward_step<const K: usize, const R: usize>(
    ab: &[f64],
    b: &mut [f64],
    block: usize,
    ring: &mut [f64; K],
) {
    if R >= K {
        return;
    }
    let j = block + R;
    let column: &[f64] = &ab[j * (K + 1)..];
    let (d, l): (&f64, &[f64; K]) = (&column[0], column[1..].first_chunk().expect("K rows"));
    // The nearest unknown, the last computed, enters last.
    let mut dot = 0.0;
    for t in (1..=K).rev() {
        dot += l[t - 1] * ring[(R + t) % K];
    }
    let x = b[j] / d - dot;
    b[j] = x;
    ring[R] = x;
}
