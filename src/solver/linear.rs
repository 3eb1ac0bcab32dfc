//! The global linear solve: a banded LU with partial pivoting (LAPACK gbtrf layout) over
//! equations numbered by a reverse Cuthill-McKee ordering, so a chain of n elements costs O(n).
//! A dense LU path exists for cross-checks and tiny systems.

/// A square band matrix with `kl` sub- and `ku` super-diagonals, stored with room for the
/// `kl` extra super-diagonals that row pivoting fills in.
#[derive(Clone, Debug)]
pub struct BandMatrix {
    n: usize,
    kl: usize,
    ku: usize,
    ld: usize,
    ab: Vec<f64>,
    pivots: Vec<usize>,
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
        let ld = 2 * kl + ku + 1;
        BandMatrix {
            n,
            kl,
            ku,
            ld,
            ab: vec![0.0; ld * n],
            pivots: vec![0; n],
        }
    }

    #[inline]
    fn idx(&self, i: usize, j: usize) -> usize {
        j * self.ld + self.kl + self.ku + i - j
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
        (0..self.n)
            .map(|i| self.ab[self.idx(i, i)].abs())
            .fold(0.0, f64::max)
    }

    /// In-place LU factorisation with partial pivoting. A pivot below `tiny` (absolute) is
    /// reported as singular.
    pub fn factor(&mut self, tiny: f64) -> Result<(), SingularPivot> {
        let (n, kl, ku) = (self.n, self.kl, self.ku);
        let mut ju = 0usize;
        for j in 0..n {
            let km = kl.min(n - 1 - j);
            let mut p = 0;
            let mut best = self.ab[self.idx(j, j)].abs();
            for t in 1..=km {
                let v = self.ab[self.idx(j + t, j)].abs();
                if v > best {
                    best = v;
                    p = t;
                }
            }
            self.pivots[j] = j + p;
            if best <= tiny || !best.is_finite() {
                return Err(SingularPivot { equation: j });
            }
            ju = ju.max((j + ku + p).min(n - 1));
            if p != 0 {
                for c in j..=ju {
                    let (a, b) = (self.idx(j, c), self.idx(j + p, c));
                    self.ab.swap(a, b);
                }
            }
            let d = self.ab[self.idx(j, j)];
            let ld = self.ld;
            // Column j below the diagonal (the multipliers) and each later column's rows
            // j+1..=j+km are contiguous in the band storage: the update is an axpy on slices.
            let (head, tail) = self.ab.split_at_mut((j + 1) * ld);
            let lstart = j * ld + kl + ku + 1;
            let lcol = &mut head[lstart..lstart + km];
            lcol.iter_mut().for_each(|v| *v /= d);
            for c in (j + 1)..=ju {
                let base = (c - j - 1) * ld + kl + ku + j - c;
                let a = tail[base];
                if a != 0.0 {
                    for (x, l) in tail[base + 1..base + 1 + km].iter_mut().zip(lcol.iter()) {
                        *x -= l * a;
                    }
                }
            }
        }
        Ok(())
    }

    /// Solve A x = b in place with the factors from `factor`.
    pub fn solve(&self, b: &mut [f64]) {
        let (n, kl, ku) = (self.n, self.kl, self.ku);
        for j in 0..n {
            let p = self.pivots[j];
            if p != j {
                b.swap(j, p);
            }
            let km = kl.min(n - 1 - j);
            let bj = b[j];
            for t in 1..=km {
                b[j + t] -= self.ab[self.idx(j + t, j)] * bj;
            }
        }
        let w = kl + ku;
        for j in (0..n).rev() {
            b[j] /= self.ab[self.idx(j, j)];
            let bj = b[j];
            let lo = j.saturating_sub(w);
            for (i, bi) in b[lo..j].iter_mut().enumerate() {
                *bi -= self.ab[self.idx(lo + i, j)] * bj;
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
