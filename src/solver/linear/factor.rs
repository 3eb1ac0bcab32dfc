//! Factoring and solving a band matrix: L D L^T without interchanges while every pivot
//! dominates its 2x2 minors, twisted from both ends for a long symmetric band (`twisted.rs`),
//! and a banded LU with partial pivoting (LAPACK gbtrf layout, widened only when a row
//! interchange needs it) from the first pivot that does not, or for an unsymmetric matrix.

use super::band::{BandMatrix, Layout, SingularPivot};
use super::ldlt::{ldlt, ldlt_solve};
use super::reduce::axpy;
use super::twisted::{twisted_ldlt, twisted_solve, Twist};

impl BandMatrix {
    /// Give every column room for the `kl` super-diagonals that row interchanges fill in.
    fn widen(&mut self) {
        if self.layout == Layout::Wide {
            return;
        }
        let (ld, ld2, kl) = (self.ld, 2 * self.kl + self.ku + 1, self.kl);
        let mut wide = vec![0.0; ld2 * self.n];
        for (to, from) in wide.chunks_exact_mut(ld2).zip(self.ab.chunks_exact(ld)) {
            to[kl..].copy_from_slice(from);
        }
        self.ab = wide;
        self.zeroed = self.ab.len();
        self.ld = ld2;
        self.off = self.kl + self.ku;
        self.layout = Layout::Wide;
    }

    /// True if pivot j of a symmetric trailing matrix dominates every 2x2 principal minor it is
    /// part of: `a_ij^2 <= |a_jj a_ii|` for the rows i below it.
    fn diagonal_dominates(&self, j: usize, km: usize, tiny: f64) -> bool {
        let dj = self.idx(j, j);
        let d = self.ab[dj].abs();
        // Diagonal entry i = j + t + 1 lies (t + 1) columns on, at the same storage row.
        let column = &self.ab[dj + 1..dj + 1 + km];
        d > tiny
            && column
                .iter()
                .enumerate()
                .all(|(t, &a)| a * a <= d * self.ab[dj + (t + 1) * self.ld].abs())
    }

    /// In-place factorisation. A pivot below `tiny` (absolute) is reported as singular.
    ///
    /// A symmetric matrix is factored L D L^T, its diagonal the pivot as long as it dominates
    /// its 2x2 minors (always so for a positive definite matrix, where elimination without
    /// interchanges is stable). That saves the row interchanges partial pivoting makes on mere
    /// scaling differences (EA/L against EI/L^3) and the fill they bring. From the first pivot
    /// that fails the test on (`pivoting_from`), and for a general matrix throughout, it is an LU
    /// with partial pivoting (the largest entry of the column), which still keeps a dominating
    /// diagonal pivot while no interchange has broken the trailing matrix's symmetry.
    ///
    /// A long symmetric matrix is factored twisted: L D L^T from the top and U D U^T from the
    /// bottom at once, toward a middle block of about twice the bandwidth, which is then
    /// factored as above (a pivot failing the test at either end stops both, and the middle
    /// block then covers the rest).
    pub fn factor(&mut self, tiny: f64) -> Result<(), SingularPivot> {
        self.finish_assembly();
        if self.layout != Layout::Lower {
            return self.lu(0, false, tiny);
        }
        match twisted_ldlt(&mut self.ab, self.n, self.kl, tiny, None) {
            Some(twist) => self.factor_middle(twist, tiny),
            None => self.factor_from_top(tiny),
        }
    }

    /// `factor`, then `solve` of `b` (the same factors and the same solution, bit for bit).
    /// A long symmetric band does the forward substitution inside its twisted factorisation, a
    /// chunk of columns behind it, so that the substitution reads the factors from cache: one
    /// pass over the band fewer. On an error `b` holds a partial substitution.
    pub fn factor_and_solve(&mut self, tiny: f64, b: &mut [f64]) -> Result<(), SingularPivot> {
        self.finish_assembly();
        let n = self.n;
        if self.layout == Layout::Lower {
            let b = &mut b[..n];
            if let Some(twist) = twisted_ldlt(&mut self.ab, n, self.kl, tiny, Some(&mut *b)) {
                self.factor_middle(twist, tiny)?;
                let middle = self.middle.as_ref().expect("factored just above");
                twisted_solve(&self.ab, n, self.kl, twist, b, true, |m| middle.solve(m));
                return Ok(());
            }
        }
        self.factor(tiny)?;
        self.solve(b);
        Ok(())
    }

    /// The rest of `factor` after `twisted_ldlt` factored both ends as far as `twist`: the
    /// middle block, copied out and factored as a band matrix of its own.
    fn factor_middle(&mut self, twist: Twist, tiny: f64) -> Result<(), SingularPivot> {
        let range = twist.middle(self.n);
        let mut middle = self
            .middle
            .take()
            .unwrap_or_else(|| Box::new(BandMatrix::empty()));
        middle.reset_symmetric(range.len(), self.kl);
        let ld = self.ld;
        for (m, j) in range.clone().enumerate() {
            // Rows of column j within the middle block (the rows beyond hold the bottom's
            // factors).
            let rows = ld.min(range.end - j);
            middle.ab[m * ld..m * ld + rows].copy_from_slice(&self.ab[j * ld..j * ld + rows]);
        }
        let result = middle.factor_from_top(tiny);
        self.lu_from = middle.lu_from.map(|e| e + twist.top);
        self.twist = Some(twist);
        self.middle = Some(middle);
        result.map_err(|sp| SingularPivot {
            equation: sp.equation + twist.top,
        })
    }

    /// `factor` of a symmetric matrix from its first column on (no twist).
    fn factor_from_top(&mut self, tiny: f64) -> Result<(), SingularPivot> {
        match ldlt(&mut self.ab, self.n, self.kl, tiny) {
            Ok(()) => Ok(()),
            Err(j) => {
                self.lower_to_lu(j);
                self.lu_from = Some(j);
                self.lu(j, true, tiny)
            }
        }
    }

    /// Rewrite an L D L^T factorisation stopped before column j as the LU factorisation of the
    /// same columns (U = D L^T), over the wide general layout, with the symmetric trailing
    /// matrix mirrored into its upper band.
    fn lower_to_lu(&mut self, j: usize) {
        let (n, k, ldo) = (self.n, self.kl, self.ld);
        let old = std::mem::take(&mut self.ab);
        self.set_shape(n, k, k, Layout::Wide);
        let (ld, off) = (self.ld, self.off);
        for m in 0..n {
            let column = m * ld + off - m;
            for i in m..=(m + k).min(n - 1) {
                self.ab[column + i] = old[m * ldo + i - m];
            }
            for i in m.saturating_sub(k)..m {
                let v = old[i * ldo + m - i];
                self.ab[column + i] = if i < j { old[i * ldo] * v } else { v };
            }
        }
        for (p, pivot) in self.pivots.iter_mut().enumerate().take(j) {
            *pivot = p;
        }
    }

    /// LU with partial pivoting of columns `start..` (columns before it already factored
    /// without interchanges). `symmetric`: the trailing matrix is exactly symmetric, so a
    /// diagonal pivot that dominates its 2x2 minors is kept until the first interchange.
    fn lu(&mut self, start: usize, mut symmetric: bool, tiny: f64) -> Result<(), SingularPivot> {
        let (n, kl, ku) = (self.n, self.kl, self.ku);
        let mut ju = (start + ku).saturating_sub(1).min(n.saturating_sub(1));
        let mut max_p = 0usize;
        for j in start..n {
            let km = kl.min(n - 1 - j);
            // Column j from the diagonal down is contiguous.
            let dj = self.idx(j, j);
            let diagonal = self.ab[dj].abs();
            let mut p = 0;
            let mut best = diagonal;
            if !(symmetric && self.diagonal_dominates(j, km, tiny)) {
                for (t, v) in self.ab[dj + 1..dj + 1 + km].iter().enumerate() {
                    if v.abs() > best {
                        best = v.abs();
                        p = t + 1;
                    }
                }
            }
            self.pivots[j] = j + p;
            if best <= tiny || !best.is_finite() {
                return Err(SingularPivot { equation: j });
            }
            ju = ju.max((j + ku + p).min(n - 1));
            if p != 0 {
                // Rows j and j + p swap: the trailing matrix is no longer symmetric.
                symmetric = false;
                self.widen();
                max_p = max_p.max(p);
                for c in j..=ju {
                    let (a, b) = (self.idx(j, c), self.idx(j + p, c));
                    self.ab.swap(a, b);
                }
            }
            let (ld, off) = (self.ld, self.off);
            let d = self.ab[j * ld + off];
            // Column j below the diagonal (the multipliers) and each later column's rows
            // j+1..=j+km are contiguous in the band storage: the update is an axpy on slices.
            let (head, tail) = self.ab.split_at_mut((j + 1) * ld);
            let lstart = j * ld + off + 1;
            let lcol = &mut head[lstart..lstart + km];
            // Multipliers by the reciprocal pivot, as LAPACK's dgbtf2 does: one division.
            let inv = 1.0 / d;
            lcol.iter_mut().for_each(|v| *v *= inv);
            let (lcol, count) = (&*lcol, ju - j);
            match km {
                1 => rank_one::<1>(tail, lcol, ld, off, count),
                2 => rank_one::<2>(tail, lcol, ld, off, count),
                3 => rank_one::<3>(tail, lcol, ld, off, count),
                4 => rank_one::<4>(tail, lcol, ld, off, count),
                5 => rank_one::<5>(tail, lcol, ld, off, count),
                6 => rank_one::<6>(tail, lcol, ld, off, count),
                7 => rank_one::<7>(tail, lcol, ld, off, count),
                8 => rank_one::<8>(tail, lcol, ld, off, count),
                _ => rank_one_any(tail, lcol, ld, off, count),
            }
        }
        self.uw = (ku + max_p).min(kl + ku);
        Ok(())
    }

    /// Solve A x = b in place with the factors from `factor`.
    pub fn solve(&self, b: &mut [f64]) {
        let (n, kl, ld, off) = (self.n, self.kl, self.ld, self.off);
        let b = &mut b[..n];
        if self.layout == Layout::Lower {
            match (self.twist, &self.middle) {
                (Some(twist), Some(middle)) => {
                    twisted_solve(&self.ab, n, kl, twist, b, false, |m| middle.solve(m))
                }
                _ => ldlt_solve(&self.ab, n, kl, b),
            }
            return;
        }
        for j in 0..n {
            let p = self.pivots[j];
            if p != j {
                b.swap(j, p);
            }
            let km = kl.min(n - 1 - j);
            let bj = b[j];
            let col = &self.ab[j * ld + off + 1..j * ld + off + 1 + km];
            axpy(&mut b[j + 1..j + 1 + km], col, bj);
        }
        // U has `uw` super-diagonals: entries further out are structurally zero.
        let w = self.uw;
        for j in (0..n).rev() {
            let top = j * ld + off;
            b[j] /= self.ab[top];
            let bj = b[j];
            let lo = j.saturating_sub(w);
            let col = &self.ab[top - (j - lo)..top];
            axpy(&mut b[lo..j], col, bj);
        }
    }
}

/// The elimination step of column j: for each of the `count` columns after it, subtract the
/// multipliers `l` (rows j+1..=j+K) times the column's row-j entry. `tail` starts at column
/// j + 1; there the row-j entry of the m-th column sits at `off - 1 + m (ld - 1)`, directly
/// above its rows j+1..=j+K. The bandwidth K is a constant here, so the inner loop unrolls.
#[inline(always)]
fn rank_one<const K: usize>(tail: &mut [f64], l: &[f64], ld: usize, off: usize, count: usize) {
    let l: &[f64; K] = l.try_into().expect("K multipliers");
    for m in 0..count {
        let b = m * (ld - 1) + off - 1;
        let a = tail[b];
        if a != 0.0 {
            let x: &mut [f64; K] = (&mut tail[b + 1..b + 1 + K]).try_into().expect("K rows");
            for t in 0..K {
                x[t] -= l[t] * a;
            }
        }
    }
}

/// `rank_one` for any bandwidth.
fn rank_one_any(tail: &mut [f64], l: &[f64], ld: usize, off: usize, count: usize) {
    for m in 0..count {
        let b = m * (ld - 1) + off - 1;
        let a = tail[b];
        if a != 0.0 {
            for (x, l) in tail[b + 1..b + 1 + l.len()].iter_mut().zip(l) {
                *x -= l * a;
            }
        }
    }
}
