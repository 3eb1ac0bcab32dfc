//! Reverse Cuthill-McKee: the equation ordering that keeps the band of a frame's tangent narrow
//! (a chain of elements gets the bandwidth of one element, whatever its node labels).

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
