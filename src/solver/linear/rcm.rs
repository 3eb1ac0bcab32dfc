//! Reverse Cuthill-McKee: the equation ordering that keeps the band of a frame's tangent narrow
//! (a chain of elements gets the bandwidth of one element, whatever its node labels).

/// Reverse Cuthill-McKee ordering of a graph given by adjacency lists. Returns `perm` with
/// `perm[new] = old`. Every connected component is ordered from a pseudo-peripheral node.
pub fn reverse_cuthill_mckee(adj: &[Vec<usize>]) -> Vec<usize> {
    let n = adj.len();
    let mut visited = vec![false; n];
    let mut order = Vec::with_capacity(n);
    let degree = |v: usize| adj[v].len();
    // One distance array for every search, reset where a search wrote (a fresh one per search
    // would make a model of many separate bodies cost quadratic time).
    let mut dist = vec![usize::MAX; n];
    for start in 0..n {
        if visited[start] {
            continue;
        }
        let root = pseudo_peripheral(adj, start, &mut dist);
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

/// A node far from every other of `start`'s component: repeated farthest-node searches.
/// `dist` is all `usize::MAX` on entry and on return.
fn pseudo_peripheral(adj: &[Vec<usize>], start: usize, dist: &mut [usize]) -> usize {
    let mut root = start;
    let mut depth = 0;
    for _ in 0..4 {
        let (far, d) = farthest(adj, root, dist);
        if d <= depth {
            break;
        }
        depth = d;
        root = far;
    }
    root
}

/// The last node a breadth-first search from `root` reaches, and its distance. `dist` is all
/// `usize::MAX` on entry and is left so (the search's queue lists every entry it wrote).
fn farthest(adj: &[Vec<usize>], root: usize, dist: &mut [usize]) -> (usize, usize) {
    dist[root] = 0;
    let mut queue = vec![root];
    let mut q = 0;
    while q < queue.len() {
        let v = queue[q];
        q += 1;
        for &u in &adj[v] {
            if dist[u] == usize::MAX {
                dist[u] = dist[v] + 1;
                queue.push(u);
            }
        }
    }
    let last = *queue.last().expect("the root");
    let depth = dist[last];
    for &v in &queue {
        dist[v] = usize::MAX;
    }
    (last, depth)
}
