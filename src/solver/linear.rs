//! The global linear solve: a band matrix over equations numbered by a reverse Cuthill-McKee
//! ordering, so a chain of n elements costs O(n). A symmetric matrix (a tangent of beams alone)
//! is stored as its lower band and factored L D L^T without interchanges while every pivot
//! dominates its 2x2 minors; from the first pivot that does not, and for every unsymmetric
//! matrix (contact elements), a banded LU with partial pivoting (LAPACK gbtrf layout, widened
//! only when a row interchange needs it) does the rest.
//! A long symmetric band is factored twisted (`twisted.rs`): from both ends at once toward a
//! small middle block, which is factored here as a band matrix of its own.
//! The L D L^T kernels are in `ldlt.rs`, the ordering in `rcm.rs`. A dense LU path exists for
//! cross-checks and tiny systems.

use super::beam::{TangentEntries, LOWER_COLUMNS};
use super::ldlt::{ldlt, ldlt_solve};
pub use super::rcm::reverse_cuthill_mckee;
use super::twisted::{twisted_ldlt, twisted_solve, Twist};

/// The equation number of a dof that is not free, in `BandMatrix::add_element`.
pub const NOT_FREE: u32 = u32::MAX;

/// The fewest entries `zero_ahead` zeroes at a time (4 KiB).
const ZERO_AHEAD: usize = 512;

/// Make the entries of `v` before `end` valid, where those before `*zeroed` are and the rest
/// are left over from an earlier use: zero from the mark to `end`, but at least `ZERO_AHEAD`
/// entries (no element has reached those beyond the mark yet), and move the mark. An assembly
/// that reaches its storage in order so clears it in a few hundred large fills, each while in
/// cache, rather than in a pass of its own or one small fill per element. (The lazily reset
/// band, and the assembly's internal forces.)
#[inline(always)]
pub(super) fn zero_ahead(v: &mut [f64], zeroed: &mut usize, end: usize) {
    if end > *zeroed {
        let to = end.max(*zeroed + ZERO_AHEAD).min(v.len());
        v[*zeroed..to].fill(0.0);
        *zeroed = to;
    }
}

/// How a band matrix is stored.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Layout {
    /// Symmetric: the diagonal and `kl` sub-diagonals only, `kl + 1` rows per column.
    Lower,
    /// General, `kl + ku + 1` rows per column.
    Compact,
    /// General with room for the fill of row interchanges, `2 kl + ku + 1` rows per column.
    Wide,
}

/// A square band matrix with `kl` sub- and `ku` super-diagonals.
///
/// Stored column by column (LAPACK band layout). A general matrix starts compact, `kl + ku + 1`
/// rows per column; the factorisation widens it to `2 kl + ku + 1` rows (room for the `kl` extra
/// super-diagonals that row interchanges fill in) only when a pivot actually needs a row swap.
/// A widened matrix stays wide when it is `reset` (the next tangent of the same model will
/// likely need the room again). A symmetric matrix (`symmetric_zeros`, `reset_symmetric`)
/// stores its lower band only, `kl + 1` rows per column: half the memory traffic and, factored
/// as L D L^T, little more than half the work.
#[derive(Clone, Debug)]
pub struct BandMatrix {
    n: usize,
    kl: usize,
    ku: usize,
    layout: Layout,
    /// Rows stored per column.
    ld: usize,
    /// Storage row of the diagonal in every column: `0` (lower), `ku` (compact) or `kl + ku`
    /// (wide). Entry (i, j) lies at `j ld + off + i - j`.
    off: usize,
    ab: Vec<f64>,
    pivots: Vec<usize>,
    /// Upper bandwidth of U after an LU factorisation: `ku` plus the largest row interchange
    /// distance.
    uw: usize,
    /// For a symmetric matrix: the column from which the LU with partial pivoting took over.
    lu_from: Option<usize>,
    /// For a symmetric matrix factored twisted: how far each end went; the middle block's
    /// factors are in `middle`.
    twist: Option<Twist>,
    /// The middle block of a twisted factorisation (storage kept for the next one).
    middle: Option<Box<BandMatrix>>,
    /// Storage entries before this are valid; those after it are left over from the last use
    /// and are zeroed as the assembly reaches them (`reset_symmetric_lazily`).
    zeroed: usize,
    /// The largest |value| any diagonal entry took since the last reset (`diagonal_peak`).
    peak: f64,
}

/// Why a factorisation failed.
#[derive(Clone, Debug, PartialEq)]
pub struct SingularPivot {
    /// Equation (0-based, in solver ordering) whose pivot vanished.
    pub equation: usize,
}

impl BandMatrix {
    /// A zero n x n band matrix.
    pub fn zeros(n: usize, kl: usize, ku: usize) -> BandMatrix {
        let mut m = BandMatrix::empty();
        m.reset(n, kl, ku);
        m
    }

    /// A zero symmetric n x n band matrix with `k` sub- and super-diagonals (lower band stored).
    pub fn symmetric_zeros(n: usize, k: usize) -> BandMatrix {
        let mut m = BandMatrix::empty();
        m.reset_symmetric(n, k);
        m
    }

    fn empty() -> BandMatrix {
        BandMatrix {
            n: 0,
            kl: 0,
            ku: 0,
            layout: Layout::Compact,
            ld: 1,
            off: 0,
            ab: Vec::new(),
            pivots: Vec::new(),
            uw: 0,
            lu_from: None,
            twist: None,
            middle: None,
            zeroed: 0,
            peak: 0.0,
        }
    }

    /// Make this a zero general n x n band matrix with the given bandwidths, reusing the
    /// storage (no allocation when it is large enough: Newton iterations refill the same matrix).
    pub fn reset(&mut self, n: usize, kl: usize, ku: usize) {
        let layout = if self.layout == Layout::Wide && self.kl > 0 {
            Layout::Wide
        } else {
            Layout::Compact
        };
        self.set_shape(n, kl, ku, layout);
    }

    /// Make this a zero symmetric n x n band matrix with `k` sub- and super-diagonals. Only the
    /// lower band is stored: `add` keeps entries on or below the diagonal and drops the rest
    /// (their mirror images), so callers add whole symmetric element matrices as usual.
    pub fn reset_symmetric(&mut self, n: usize, k: usize) {
        self.set_shape(n, k, k, Layout::Lower);
    }

    /// `reset_symmetric` without zeroing the storage now: each column is zeroed when an
    /// element first reaches it (in one pass with the assembly, while it is in cache, instead of
    /// a separate pass over the whole band). Call `finish_assembly` before reading the matrix.
    pub fn reset_symmetric_lazily(&mut self, n: usize, k: usize) {
        self.set_shape_keeping(n, k, k, Layout::Lower);
        // Everything is zeroed again as the assembly reaches it, the new storage beyond the old
        // length (zero already) included: what counts is that every entry before the mark is
        // valid.
        self.zeroed = 0;
    }

    /// Zero whatever `reset_symmetric_lazily` left that no element reached.
    pub fn finish_assembly(&mut self) {
        self.zero_to(self.ab.len());
    }

    /// Make the storage entries before `end` valid (`zero_ahead`).
    #[inline]
    fn zero_to(&mut self, end: usize) {
        zero_ahead(&mut self.ab, &mut self.zeroed, end);
    }

    /// Panics if the storage is read while `reset_symmetric_lazily` has left some of it stale.
    fn assert_assembled(&self) {
        assert!(
            self.zeroed >= self.ab.len(),
            "band matrix read before finish_assembly"
        );
    }

    fn set_shape(&mut self, n: usize, kl: usize, ku: usize, layout: Layout) {
        self.ab.clear();
        self.set_shape_keeping(n, kl, ku, layout);
        self.zeroed = self.ab.len();
    }

    /// `set_shape` that leaves the old storage contents in place (stale, for the caller to zero).
    fn set_shape_keeping(&mut self, n: usize, kl: usize, ku: usize, layout: Layout) {
        self.peak = 0.0;
        (self.n, self.kl, self.ku, self.layout) = (n, kl, ku, layout);
        (self.ld, self.off) = match layout {
            Layout::Lower => (kl + 1, 0),
            Layout::Compact => (kl + ku + 1, ku),
            Layout::Wide => (2 * kl + ku + 1, kl + ku),
        };
        self.uw = ku;
        self.lu_from = None;
        self.twist = None;
        self.ab.resize(self.ld * n, 0.0);
        self.pivots.clear();
        if layout != Layout::Lower {
            // L D L^T makes no interchanges.
            self.pivots.resize(n, 0);
        }
    }

    /// Number of equations.
    pub fn len(&self) -> usize {
        self.n
    }

    /// True if the matrix has no equations.
    pub fn is_empty(&self) -> bool {
        self.n == 0
    }

    /// For a symmetric matrix after `factor`: the equation from which an LU with partial
    /// pivoting finished the job, because a diagonal pivot did not dominate its 2x2 minors
    /// (`None`: L D L^T throughout, or not symmetric). In a twisted factorisation this is an
    /// equation of the middle block, which then starts where the two ends stopped.
    pub fn pivoting_from(&self) -> Option<usize> {
        self.lu_from
    }

    #[inline]
    fn idx(&self, i: usize, j: usize) -> usize {
        j * self.ld + self.off + i - j
    }

    /// Add `v` to entry (i, j); panics in debug builds if (i, j) lies outside the band. A
    /// symmetric matrix keeps only entries with i >= j.
    #[inline]
    pub fn add(&mut self, i: usize, j: usize, v: f64) {
        debug_assert!(
            i <= j + self.kl && j <= i + self.ku,
            "({i},{j}) outside band"
        );
        if self.layout == Layout::Lower && i < j {
            return;
        }
        self.finish_assembly();
        let k = self.idx(i, j);
        self.ab[k] += v;
        if i == j {
            self.peak = self.peak.max(self.ab[k].abs());
        }
    }

    /// Add a beam's tangent, given by its distinct entries, over equations `eqs` (as
    /// `add_element` with `t.write`, and bit for bit the same): a beam whose six dofs are free and
    /// numbered consecutively in a symmetric band takes its lower columns straight from `t`.
    #[inline(always)]
    pub fn add_beam(&mut self, eqs: &[u32; 6], t: &TangentEntries) {
        match consecutive_first(eqs) {
            Some(first) => self.add_beam_consecutive(first, t),
            None => self.add_beam_any(eqs, t),
        }
    }

    /// `add_beam` for a beam over the consecutive equations `first..first + 6` (see
    /// `consecutive_first`).
    #[inline(always)]
    pub fn add_beam_consecutive(&mut self, first: usize, t: &TangentEntries) {
        if self.layout != Layout::Lower {
            let eqs = std::array::from_fn(|a| (first + a) as u32);
            return self.add_beam_any(&eqs, t);
        }
        self.zero_to((first + 6) * self.ld);
        let lower = t.lower_columns();
        self.add_consecutive::<6>(first, |b, a| lower[LOWER_COLUMNS[b].start + a]);
    }

    /// `add_beam` through the whole 6x6 tangent.
    fn add_beam_any(&mut self, eqs: &[u32; 6], t: &TangentEntries) {
        let mut k = [[0.0; 6]; 6];
        t.write(&mut k);
        self.add_element(eqs, &k)
    }

    /// The lower columns of an N x N symmetric element over the consecutive equations
    /// `first..first + N` of a symmetric band (zeroed that far): column first + b takes its rows
    /// first + b.. in one run from (first + b) ld, entry (first + b + a, first + b) being
    /// `entry(b, a)`. Keeps the diagonal peak.
    #[inline(always)]
    fn add_consecutive<const N: usize>(
        &mut self,
        first: usize,
        entry: impl Fn(usize, usize) -> f64,
    ) {
        let ld = self.ld;
        let mut peak = self.peak;
        for b in 0..N {
            let start = (first + b) * ld;
            let run = &mut self.ab[start..start + N - b];
            for (a, v) in run.iter_mut().enumerate() {
                *v += entry(b, a);
            }
            // A plain comparison (one instruction; `f64::max` also sorts out NaNs).
            let diagonal = run[0].abs();
            if diagonal > peak {
                peak = diagonal;
            }
        }
        self.peak = peak;
    }

    /// Add a dense element matrix `k` (row-major) over the equations `eqs` (`NOT_FREE`: a dof
    /// that is not free, skipped). Panics in debug builds if an entry lies outside the band. A
    /// symmetric matrix keeps the entries on or below the diagonal.
    #[inline(always)]
    pub fn add_element<const N: usize>(&mut self, eqs: &[u32; N], k: &[[f64; N]; N]) {
        // Entry (i, j) lies at j (ld - 1) + off + i.
        let (ld, off) = (self.ld, self.off);
        let lower = self.layout == Layout::Lower;
        if lower && eqs.is_sorted() && eqs[N - 1] != NOT_FREE {
            // Symmetric, every dof free and numbered in local order (the usual case): column
            // eqs[b] takes rows eqs[a], a >= b, at eqs[b] (ld - 1) + eqs[a].
            let top = eqs[N - 1] as usize;
            debug_assert!(top - eqs[0] as usize <= self.kl, "element outside band");
            // Column `top` is the last this element reaches.
            self.zero_to((top + 1) * ld);
            let first = eqs[0] as usize;
            if top - first == N - 1 {
                // Consecutive equations (a chain numbered along itself).
                self.add_consecutive::<N>(first, |b, a| k[b + a][b]);
                return;
            }
            for b in 0..N {
                let base = eqs[b] as usize * (ld - 1);
                let column = &mut self.ab[base..=base + top];
                for a in b..N {
                    column[eqs[a] as usize] += k[a][b];
                }
                self.peak = self.peak.max(column[eqs[b] as usize].abs());
            }
            return;
        }
        if lower {
            // A dof not free, or numbered out of local order: the lower entries of the free
            // dofs lie in the columns up to the highest free equation.
            let top = eqs.iter().filter(|&&q| q != NOT_FREE).max();
            let Some(&top) = top else { return };
            self.zero_to((top as usize + 1) * ld);
        } else {
            self.finish_assembly();
        }
        if !lower && !eqs.contains(&NOT_FREE) {
            // Every dof free (the usual case): each column's N entries lie in rows lo..=hi.
            let (lo, hi) = (eqs.iter().min(), eqs.iter().max());
            let (Some(&lo), Some(&hi)) = (lo, hi) else {
                return;
            };
            let (lo, hi) = (lo as usize, hi as usize);
            debug_assert!(hi - lo <= self.kl.min(self.ku), "element outside band");
            for (b, &eb) in eqs.iter().enumerate() {
                let base = eb as usize * (ld - 1) + off;
                let column = &mut self.ab[base + lo..=base + hi];
                for (a, &ea) in eqs.iter().enumerate() {
                    column[ea as usize - lo] += k[a][b];
                }
                self.peak = self.peak.max(column[eb as usize - lo].abs());
            }
            return;
        }
        // Otherwise (a dof not free, or a symmetric element numbered out of local order): each
        // pair, the lower entry only for a symmetric matrix (k is symmetric, so k[a][b] is it).
        for (b, &eb) in eqs.iter().enumerate() {
            if eb == NOT_FREE {
                continue;
            }
            let base = eb as usize * (ld - 1) + off;
            for (a, &ea) in eqs.iter().enumerate() {
                if ea == NOT_FREE || (lower && ea < eb) {
                    continue;
                }
                let (ea, eb) = (ea as usize, eb as usize);
                debug_assert!(
                    ea <= eb + self.kl && eb <= ea + self.ku,
                    "({ea},{eb}) outside band"
                );
                self.ab[base + ea] += k[a][b];
                if ea == eb {
                    self.peak = self.peak.max(self.ab[base + ea].abs());
                }
            }
        }
    }

    /// Entry (i, j) (zero outside the band). Valid before factorisation.
    pub fn get(&self, i: usize, j: usize) -> f64 {
        self.assert_assembled();
        let (i, j) = if self.layout == Layout::Lower {
            (i.max(j), i.min(j))
        } else {
            (i, j)
        };
        if i > j + self.kl || j > i + self.ku {
            0.0
        } else {
            self.ab[self.idx(i, j)]
        }
    }

    /// The largest |value| any diagonal entry took while the matrix was assembled (with `add`
    /// and `add_element` since the last reset): every final diagonal entry is one of those
    /// values, so this is an upper bound of `max_diagonal` that costs no pass over the band
    /// (equal to it where no diagonal entry shrinks during the assembly).
    pub fn diagonal_peak(&self) -> f64 {
        self.peak
    }

    /// Largest absolute diagonal entry (before factorisation), a scale for pivot tests.
    pub fn max_diagonal(&self) -> f64 {
        self.assert_assembled();
        super::reduce::max_abs_strided(&self.ab, self.off, self.ld)
    }

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

/// The first of an element's equations `eqs` if they are free and consecutive in local order
/// (`first..first + N`: a chain numbered along itself), else `None`.
#[inline]
pub fn consecutive_first<const N: usize>(eqs: &[u32; N]) -> Option<usize> {
    let first = eqs[0] as usize;
    (eqs[N - 1] != NOT_FREE && eqs[N - 1] as usize == first + N - 1 && eqs.is_sorted())
        .then_some(first)
}

/// `x -= a v`, unrolled for the short lengths of a band.
#[inline(always)]
pub(super) fn axpy(x: &mut [f64], v: &[f64], a: f64) {
    fn fixed<const K: usize>(x: &mut [f64], v: &[f64], a: f64) {
        let x: &mut [f64; K] = x.try_into().expect("K entries");
        let v: &[f64; K] = v.try_into().expect("K entries");
        for t in 0..K {
            x[t] -= v[t] * a;
        }
    }
    match x.len() {
        3 => fixed::<3>(x, v, a),
        4 => fixed::<4>(x, v, a),
        5 => fixed::<5>(x, v, a),
        6 => fixed::<6>(x, v, a),
        _ => {
            for (x, v) in x.iter_mut().zip(v) {
                *x -= v * a;
            }
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

/// Dense LU solve (partial pivoting) of a row-major n x n system; `None` if singular.
pub fn dense_solve(n: usize, a: &[f64], b: &[f64]) -> Option<Vec<f64>> {
    let m = nalgebra::DMatrix::from_row_slice(n, n, a);
    let rhs = nalgebra::DVector::from_column_slice(b);
    m.lu().solve(&rhs).map(|x| x.iter().copied().collect())
}
