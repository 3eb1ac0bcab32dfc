//! The global linear solve: a banded LU with partial pivoting (LAPACK gbtrf layout, widened only
//! when a row interchange needs it) over equations numbered by a reverse Cuthill-McKee ordering,
//! so a chain of n elements costs O(n).
//! A dense LU path exists for cross-checks and tiny systems.

/// A square band matrix with `kl` sub- and `ku` super-diagonals.
///
/// Stored column by column (LAPACK band layout). The storage starts compact, `kl + ku + 1` rows
/// per column; the factorisation widens it to `2 kl + ku + 1` rows (room for the `kl` extra
/// super-diagonals that row interchanges fill in) only when a pivot actually needs a row swap.
/// A well-ordered frame tangent usually needs none, so it is factored without the extra traffic.
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
        };
        m.reset(n, kl, ku);
        m
    }

    /// Make this a zero n x n band matrix with the given bandwidths, reusing the storage (no
    /// allocation when it is large enough: Newton iterations refill the same matrix).
    pub fn reset(&mut self, n: usize, kl: usize, ku: usize) {
        self.n = n;
        self.kl = kl;
        self.ku = ku;
        self.ld = kl + ku + 1;
        self.off = ku;
        self.uw = ku;
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

    /// In-place LU factorisation with partial pivoting. A pivot below `tiny` (absolute) is
    /// reported as singular.
    pub fn factor(&mut self, tiny: f64) -> Result<(), SingularPivot> {
        let (n, kl, ku) = (self.n, self.kl, self.ku);
        let mut ju = 0usize;
        let mut max_p = 0usize;
        for j in 0..n {
            let km = kl.min(n - 1 - j);
            // Column j from the diagonal down is contiguous.
            let dj = self.idx(j, j);
            let mut p = 0;
            let mut best = self.ab[dj].abs();
            for (t, v) in self.ab[dj + 1..dj + 1 + km].iter().enumerate() {
                if v.abs() > best {
                    best = v.abs();
                    p = t + 1;
                }
            }
            self.pivots[j] = j + p;
            if best <= tiny || !best.is_finite() {
                return Err(SingularPivot { equation: j });
            }
            ju = ju.max((j + ku + p).min(n - 1));
            if p != 0 {
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
            lcol.iter_mut().for_each(|v| *v /= d);
            for c in (j + 1)..=ju {
                // Storage index of (j, c), relative to the start of column j + 1.
                let base = (c - j - 1) * ld + off + j - c;
                let a = tail[base];
                if a != 0.0 {
                    for (x, l) in tail[base + 1..base + 1 + km].iter_mut().zip(lcol.iter()) {
                        *x -= l * a;
                    }
                }
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
            for (x, l) in b[j + 1..j + 1 + km].iter_mut().zip(col) {
                *x -= l * bj;
            }
        }
        // U has `uw` super-diagonals: entries further out are structurally zero.
        let w = self.uw;
        for j in (0..n).rev() {
            let top = j * ld + off;
            b[j] /= self.ab[top];
            let bj = b[j];
            let lo = j.saturating_sub(w);
            let col = &self.ab[top - (j - lo)..top];
            for (x, u) in b[lo..j].iter_mut().zip(col) {
                *x -= u * bj;
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
