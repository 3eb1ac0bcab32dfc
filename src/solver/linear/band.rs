//! The band matrix the tangent is assembled into: its storage (the lower band of a symmetric
//! matrix, or the LAPACK gbtrf layout of a general one), adding element matrices, and reading
//! entries and the diagonal's scale. Factoring and solving is `factor.rs`.

use std::ops::Range;

use super::twisted::Twist;

/// Where each column of the packed lower triangle of a symmetric 6x6 matrix lies in its array
/// of 21 entries: column b from the diagonal down (rows b..6).
pub const LOWER_COLUMNS: [Range<usize>; 6] = [0..6, 6..11, 11..15, 15..18, 18..20, 20..21];

/// The whole symmetric 6x6 matrix of packed lower columns (`LOWER_COLUMNS`), mirrored exactly.
#[inline(always)]
pub fn symmetric6(lower: &[f64; 21]) -> [[f64; 6]; 6] {
    let mut out = [[0.0; 6]; 6];
    for (b, rows) in LOWER_COLUMNS.into_iter().enumerate() {
        for (a, &v) in (b..6).zip(&lower[rows]) {
            out[a][b] = v;
            out[b][a] = v;
        }
    }
    out
}

/// The equation number of a dof that is not free, in [`BandMatrix::add_element`].
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
pub(crate) fn zero_ahead(v: &mut [f64], zeroed: &mut usize, end: usize) {
    if end > *zeroed {
        let to = end.max(*zeroed + ZERO_AHEAD).min(v.len());
        v[*zeroed..to].fill(0.0);
        *zeroed = to;
    }
}

/// How a band matrix is stored.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Layout {
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
    pub(super) n: usize,
    pub(super) kl: usize,
    pub(super) ku: usize,
    pub(super) layout: Layout,
    /// Rows stored per column.
    pub(super) ld: usize,
    /// Storage row of the diagonal in every column: `0` (lower), `ku` (compact) or `kl + ku`
    /// (wide). Entry (i, j) lies at `j ld + off + i - j`.
    pub(super) off: usize,
    pub(super) ab: Vec<f64>,
    pub(super) pivots: Vec<usize>,
    /// Upper bandwidth of U after an LU factorisation: `ku` plus the largest row interchange
    /// distance.
    pub(super) uw: usize,
    /// For a symmetric matrix: the column from which the LU with partial pivoting took over.
    pub(super) lu_from: Option<usize>,
    /// For a symmetric matrix factored twisted: how far each end went; the middle block's
    /// factors are in `middle`.
    pub(super) twist: Option<Twist>,
    /// The middle block of a twisted factorisation (storage kept for the next one).
    pub(super) middle: Option<Box<BandMatrix>>,
    /// Storage entries before this are valid; those after it are left over from the last use
    /// and are zeroed as the assembly reaches them (`reset_symmetric_lazily`).
    pub(super) zeroed: usize,
    /// The largest |value| any diagonal entry took since the last reset (`diagonal_peak`).
    pub(super) peak: f64,
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

    pub(super) fn empty() -> BandMatrix {
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
    pub(super) fn zero_to(&mut self, end: usize) {
        zero_ahead(&mut self.ab, &mut self.zeroed, end);
    }

    /// Panics if the storage is read while `reset_symmetric_lazily` has left some of it stale.
    pub(super) fn assert_assembled(&self) {
        assert!(
            self.zeroed >= self.ab.len(),
            "band matrix read before finish_assembly"
        );
    }

    pub(super) fn set_shape(&mut self, n: usize, kl: usize, ku: usize, layout: Layout) {
        self.ab.clear();
        self.set_shape_keeping(n, kl, ku, layout);
        self.zeroed = self.ab.len();
    }

    /// `set_shape` that leaves the old storage contents in place (stale, for the caller to zero).
    pub(super) fn set_shape_keeping(&mut self, n: usize, kl: usize, ku: usize, layout: Layout) {
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
    pub(super) fn idx(&self, i: usize, j: usize) -> usize {
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

    /// Add a symmetric 6x6 element matrix, given as its packed lower columns (`LOWER_COLUMNS`),
    /// over equations `eqs` (as `add_element` with the whole matrix, and bit for bit the same):
    /// an element whose six dofs are free and numbered consecutively in a symmetric band
    /// (`consecutive_first`) takes its lower columns straight from `lower`.
    #[inline(always)]
    pub fn add_symmetric6(&mut self, eqs: &[u32; 6], lower: &[f64; 21]) {
        match consecutive_first(eqs) {
            Some(first) => self.add_symmetric6_consecutive(first, lower),
            None => self.add_symmetric6_any(eqs, lower),
        }
    }

    /// `add_symmetric6` for an element over the consecutive equations `first..first + 6`.
    #[inline(always)]
    pub fn add_symmetric6_consecutive(&mut self, first: usize, lower: &[f64; 21]) {
        if self.layout != Layout::Lower {
            let eqs = std::array::from_fn(|a| (first + a) as u32);
            return self.add_symmetric6_any(&eqs, lower);
        }
        self.zero_to((first + 6) * self.ld);
        self.add_consecutive::<6>(first, |b, a| lower[LOWER_COLUMNS[b].start + a]);
    }

    /// `add_symmetric6` through the whole 6x6 matrix.
    fn add_symmetric6_any(&mut self, eqs: &[u32; 6], lower: &[f64; 21]) {
        self.add_element(eqs, &symmetric6(lower))
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
}

/// The first of an element's equations `eqs` if they are free and consecutive in local order
/// (`first..first + N`: a chain numbered along itself), else `None`.
#[inline]
pub fn consecutive_first<const N: usize>(eqs: &[u32; N]) -> Option<usize> {
    let first = eqs[0] as usize;
    (eqs[N - 1] != NOT_FREE && eqs[N - 1] as usize == first + N - 1 && eqs.is_sorted())
        .then_some(first)
}
