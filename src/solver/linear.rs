//! The global linear solve: a banded LU with partial pivoting (LAPACK gbtrf layout, widened only
//! when a row interchange needs it; diagonal pivots kept for an exactly symmetric matrix while
//! they dominate their 2x2 minors) over equations numbered by a reverse Cuthill-McKee ordering,
//! so a chain of n elements costs O(n).
//! A dense LU path exists for cross-checks and tiny systems.

/// A square band matrix with `kl` sub- and `ku` super-diagonals.
///
/// Stored column by column (LAPACK band layout). The storage starts compact, `kl + ku + 1` rows
/// per column; the factorisation widens it to `2 kl + ku + 1` rows (room for the `kl` extra
/// super-diagonals that row interchanges fill in) only when a pivot actually needs a row swap.
/// A frame tangent usually needs none, so it is factored without the extra traffic. Once
/// widened, a matrix stays wide when it is `reset` (the next tangent of the same model will
/// likely need the room again).
#[derive(Clone, Debug)]
pub struct BandMatrix {
    n: usize,
    kl: usize,
    ku: usize,
    /// Rows stored per column: `kl + ku + 1` (compact) or `2 kl + ku + 1` (widened).
    ld: usize,
    /// Storage row of the diagonal in every column: `ku` (compact) or `kl + ku` (widened).
    off: usize,
    ab: Vec<f64>,
    pivots: Vec<usize>,
    /// Upper bandwidth of U after factorisation: `ku` plus the largest row interchange distance.
    uw: usize,
    /// Declared exactly symmetric by whoever filled it (see `set_symmetric`).
    symmetric: bool,
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
        let mut m = BandMatrix {
            n: 0,
            kl: 0,
            ku: 0,
            ld: 1,
            off: 0,
            ab: Vec::new(),
            pivots: Vec::new(),
            uw: 0,
            symmetric: false,
        };
        m.reset(n, kl, ku);
        m
    }

    /// Make this a zero n x n band matrix with the given bandwidths, reusing the storage (no
    /// allocation when it is large enough: Newton iterations refill the same matrix).
    pub fn reset(&mut self, n: usize, kl: usize, ku: usize) {
        let wide = self.kl > 0 && self.off == self.kl + self.ku;
        self.n = n;
        self.kl = kl;
        self.ku = ku;
        self.ld = if wide { 2 * kl + ku + 1 } else { kl + ku + 1 };
        self.off = if wide { kl + ku } else { ku };
        self.uw = ku;
        self.symmetric = false;
        self.ab.clear();
        self.ab.resize(self.ld * n, 0.0);
        self.pivots.clear();
        self.pivots.resize(n, 0);
    }

    /// Number of equations.
    pub fn len(&self) -> usize {
        self.n
    }

    /// True if the matrix has no equations.
    pub fn is_empty(&self) -> bool {
        self.n == 0
    }

    #[inline]
    fn idx(&self, i: usize, j: usize) -> usize {
        j * self.ld + self.off + i - j
    }

    /// Add `v` to entry (i, j); panics in debug builds if (i, j) lies outside the band.
    #[inline]
    pub fn add(&mut self, i: usize, j: usize, v: f64) {
        debug_assert!(
            i <= j + self.kl && j <= i + self.ku,
            "({i},{j}) outside band"
        );
        let k = self.idx(i, j);
        self.ab[k] += v;
    }

    /// Add a dense element matrix `k` (row-major) over the equations `eqs` (`None`: a dof that
    /// is not free, skipped). Panics in debug builds if an entry lies outside the band.
    #[inline]
    pub fn add_element<const N: usize>(&mut self, eqs: &[Option<usize>; N], k: &[[f64; N]; N]) {
        let (ld, off) = (self.ld, self.off);
        if eqs.iter().all(Option::is_some) {
            // Every dof free (the usual case): each column's N entries lie in rows lo..=hi.
            let e: [usize; N] = std::array::from_fn(|a| eqs[a].unwrap_or(0));
            let (lo, hi) = (e.iter().min(), e.iter().max());
            let (Some(&lo), Some(&hi)) = (lo, hi) else {
                return;
            };
            debug_assert!(hi - lo <= self.kl.min(self.ku), "element outside band");
            for (b, &eb) in e.iter().enumerate() {
                let base = eb * (ld - 1) + off;
                let column = &mut self.ab[base + lo..=base + hi];
                for (a, &ea) in e.iter().enumerate() {
                    column[ea - lo] += k[a][b];
                }
            }
            return;
        }
        for (b, eb) in eqs.iter().enumerate() {
            let Some(eb) = *eb else { continue };
            // Storage index of (i, eb) is base + i.
            let base = eb * (ld - 1) + off;
            for (a, ea) in eqs.iter().enumerate() {
                let Some(ea) = *ea else { continue };
                debug_assert!(
                    ea <= eb + self.kl && eb <= ea + self.ku,
                    "({ea},{eb}) outside band"
                );
                self.ab[base + ea] += k[a][b];
            }
        }
    }

    /// Entry (i, j) (zero outside the band). Valid before factorisation.
    pub fn get(&self, i: usize, j: usize) -> f64 {
        if i > j + self.kl || j > i + self.ku {
            0.0
        } else {
            self.ab[self.idx(i, j)]
        }
    }

    /// Largest absolute diagonal entry (before factorisation), a scale for pivot tests.
    pub fn max_diagonal(&self) -> f64 {
        self.ab
            .iter()
            .skip(self.off)
            .step_by(self.ld)
            .map(|v| v.abs())
            .fold(0.0, f64::max)
    }

    /// Give every column room for the `kl` super-diagonals that row interchanges fill in.
    fn widen(&mut self) {
        if self.off == self.kl + self.ku {
            return;
        }
        let (ld, ld2, kl) = (self.ld, 2 * self.kl + self.ku + 1, self.kl);
        let mut wide = vec![0.0; ld2 * self.n];
        for (to, from) in wide.chunks_exact_mut(ld2).zip(self.ab.chunks_exact(ld)) {
            to[kl..].copy_from_slice(from);
        }
        self.ab = wide;
        self.ld = ld2;
        self.off = self.kl + self.ku;
    }

    /// Declare the matrix exactly symmetric (as assembled), which lets `factor` keep diagonal
    /// pivots that dominate their 2x2 minors. `reset` clears it.
    pub fn set_symmetric(&mut self, symmetric: bool) {
        self.symmetric = symmetric;
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

    /// In-place LU factorisation. A pivot below `tiny` (absolute) is reported as singular.
    ///
    /// Pivoting: strict partial pivoting (the largest entry of the column), except for a matrix
    /// declared symmetric (`set_symmetric`), whose diagonal stays the pivot as long as it
    /// dominates its 2x2 minors (always so for a positive definite matrix, where elimination
    /// without interchanges is stable). That saves the row interchanges partial pivoting makes
    /// on mere scaling differences (EA/L against EI/L^3) and the fill they bring. From the first
    /// pivot that fails the test on, the factorisation is strict partial pivoting.
    pub fn factor(&mut self, tiny: f64) -> Result<(), SingularPivot> {
        let (n, kl, ku) = (self.n, self.kl, self.ku);
        let mut symmetric = self.symmetric && kl == ku;
        let mut ju = 0usize;
        let mut max_p = 0usize;
        for j in 0..n {
            let km = kl.min(n - 1 - j);
            // The common case first: a symmetric trailing matrix, a full band below and after the
            // diagonal, and a diagonal pivot that passes the test (unrolled for the bandwidth).
            if symmetric && km == kl {
                let (ab, ld, off) = (&mut self.ab[..], self.ld, self.off);
                let done = match kl {
                    3 => symmetric_step::<3>(ab, j, ld, off, tiny),
                    4 => symmetric_step::<4>(ab, j, ld, off, tiny),
                    5 => symmetric_step::<5>(ab, j, ld, off, tiny),
                    6 => symmetric_step::<6>(ab, j, ld, off, tiny),
                    _ => false,
                };
                if done {
                    self.pivots[j] = j;
                    ju = ju.max(j + ku);
                    continue;
                }
            }
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

/// `x -= a v`, unrolled for the short lengths of a band.
#[inline(always)]
fn axpy(x: &mut [f64], v: &[f64], a: f64) {
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

/// Column j of a symmetric trailing matrix with K = kl = ku and a full band (K rows below, K
/// columns after): if its diagonal dominates every 2x2 minor and is above `tiny`, scale the
/// multipliers and update the K columns after it, and return true; otherwise touch nothing.
#[inline(always)]
fn symmetric_step<const K: usize>(
    ab: &mut [f64],
    j: usize,
    ld: usize,
    off: usize,
    tiny: f64,
) -> bool {
    let dj = j * ld + off;
    let d = ab[dj];
    let ad = d.abs();
    if ad <= tiny || !ad.is_finite() {
        return false;
    }
    let mut dominates = true;
    for t in 1..K + 1 {
        let a = ab[dj + t];
        dominates &= a * a <= ad * ab[dj + t * ld].abs();
    }
    if !dominates {
        return false;
    }
    let inv = 1.0 / d;
    let (head, tail) = ab.split_at_mut((j + 1) * ld);
    let l = &mut head[dj + 1..dj + 1 + K];
    l.iter_mut().for_each(|v| *v *= inv);
    rank_one::<K>(tail, l, ld, off, K);
    true
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

/// Reverse Cuthill-McKee ordering of a graph given by adjacency lists. Returns `perm` with
/// `perm[new] = old`. Every connected component is ordered from a pseudo-peripheral node.
pub fn reverse_cuthill_mckee(adj: &[Vec<usize>]) -> Vec<usize> {
    let n = adj.len();
    let mut visited = vec![false; n];
    let mut order = Vec::with_capacity(n);
    let degree = |v: usize| adj[v].len();
    for start in 0..n {
        if visited[start] {
            continue;
        }
        let root = pseudo_peripheral(adj, start);
        visited[root] = true;
        let head = order.len();
        order.push(root);
        let mut q = head;
        while q < order.len() {
            let v = order[q];
            q += 1;
            let mut next: Vec<usize> = adj[v].iter().copied().filter(|&u| !visited[u]).collect();
            next.sort_by_key(|&u| degree(u));
            next.dedup();
            for u in next {
                if !visited[u] {
                    visited[u] = true;
                    order.push(u);
                }
            }
        }
    }
    order.reverse();
    order
}

fn pseudo_peripheral(adj: &[Vec<usize>], start: usize) -> usize {
    let mut root = start;
    let mut depth = 0;
    for _ in 0..4 {
        let (far, d) = farthest(adj, root);
        if d <= depth {
            break;
        }
        depth = d;
        root = far;
    }
    root
}

fn farthest(adj: &[Vec<usize>], root: usize) -> (usize, usize) {
    let mut dist = vec![usize::MAX; adj.len()];
    dist[root] = 0;
    let mut queue = std::collections::VecDeque::from([root]);
    let mut last = root;
    while let Some(v) = queue.pop_front() {
        last = v;
        for &u in &adj[v] {
            if dist[u] == usize::MAX {
                dist[u] = dist[v] + 1;
                queue.push_back(u);
            }
        }
    }
    (last, dist[last])
}

/// Dense LU solve (partial pivoting) of a row-major n x n system; `None` if singular.
pub fn dense_solve(n: usize, a: &[f64], b: &[f64]) -> Option<Vec<f64>> {
    let m = nalgebra::DMatrix::from_row_slice(n, n, a);
    let rhs = nalgebra::DVector::from_column_slice(b);
    m.lu().solve(&rhs).map(|x| x.iter().copied().collect())
}
