//! Rigid motions the supports leave free: for each part of the structure that beams join into
//! one piece, whether its held dofs (supports and prescribed displacements) stop its three
//! rigid motions in the plane. Decided from geometry alone (the rank of the held dofs' rows of
//! the rigid-motion matrix), so that a long, slender part free to spin about its one pin is
//! found however ill-conditioned its tangent is; the band factorisation's pivot test cannot tell
//! that spin from a flexible beam of the same size.

use crate::solver::model::{Dof, Model};

/// A part whose supports leave a rigid motion free.
#[derive(Clone, Debug, PartialEq)]
pub struct FreePart {
    /// Node indices of the part.
    pub nodes: Vec<usize>,
    /// The rigid motions left free (1 to 3).
    pub modes: usize,
}

/// A rigid motion counts as stopped when the held dofs' rows give it this fraction of the
/// stiffest direction's weight (the rows are made dimensionless with the part's size).
const RANK_TOLERANCE: f64 = 1e-10;

/// The parts of `model` (nodes joined by beams; a node without beams is a part of its own) whose
/// held dofs, and the rigid obstacles they rest on (`resting`: a node and the obstacle's unit
/// normal there, which holds the node's motion along it), leave a rigid motion free. Parts of
/// one node without a rotation dof have only two rigid motions (translations).
pub fn free_parts(model: &Model, resting: &[(usize, [f64; 2])]) -> Vec<FreePart> {
    let n = model.nodes.len();
    let mut root: Vec<usize> = (0..n).collect();
    fn find(root: &mut [usize], mut a: usize) -> usize {
        while root[a] != a {
            root[a] = root[root[a]];
            a = root[a];
        }
        a
    }
    for b in &model.beams {
        let (ri, rj) = (find(&mut root, b.i), find(&mut root, b.j));
        if ri != rj {
            root[ri.max(rj)] = ri.min(rj);
        }
    }
    let mut parts: Vec<Vec<usize>> = Vec::new();
    let mut slot = vec![usize::MAX; n];
    for k in 0..n {
        let r = find(&mut root, k);
        if slot[r] == usize::MAX {
            slot[r] = parts.len();
            parts.push(Vec::new());
        }
        parts[slot[r]].push(k);
    }
    let mut held: Vec<[bool; 3]> = vec![[false; 3]; n];
    let mut hold = |node: usize, dof: Dof| {
        held[node][match dof {
            Dof::U => 0,
            Dof::V => 1,
            Dof::Phi => 2,
        }] = true;
    };
    for s in &model.supports {
        hold(s.node, s.dof);
    }
    for p in &model.prescribed {
        hold(p.node, p.dof);
    }
    for (k, node) in model.nodes.iter().enumerate() {
        if node.moves_with.is_some() {
            hold(k, Dof::U);
            hold(k, Dof::V);
        }
    }
    parts
        .into_iter()
        .filter_map(|nodes| {
            let modes = free_modes(model, &nodes, &held, resting);
            (modes > 0).then_some(FreePart { nodes, modes })
        })
        .collect()
}

/// The rigid motions of the part `nodes` that the held dofs leave free: 3 (or 2 for a lone node
/// without rotation) minus the rank of the held rows of the rigid-motion matrix, whose columns
/// are the translations along x and y and the rotation about the part's centre.
fn free_modes(
    model: &Model,
    nodes: &[usize],
    held: &[[bool; 3]],
    resting: &[(usize, [f64; 2])],
) -> usize {
    let pos = |k: usize| [model.nodes[k].x, model.nodes[k].y];
    let count = nodes.len() as f64;
    let centre = nodes.iter().fold([0.0, 0.0], |c, &k| {
        [c[0] + pos(k)[0] / count, c[1] + pos(k)[1] / count]
    });
    let size = (nodes.iter())
        .map(|&k| (pos(k)[0] - centre[0]).hypot(pos(k)[1] - centre[1]))
        .fold(0.0f64, f64::max);
    // A node held in all three dofs stops every rigid motion of its part (the common clamp).
    if nodes.iter().any(|&k| held[k] == [true; 3]) {
        return 0;
    }
    let spins = nodes.len() > 1 || model.nodes[nodes[0]].rotation;
    let rests = resting.iter().any(|(k, _)| nodes.contains(k));
    if (size == 0.0 || !spins) && !rests {
        // A lone node: its translations (and rotation, if it has one) are held or not.
        let h = held[nodes[0]];
        let own = if spins { 3 } else { 2 };
        return (0..own).filter(|&d| !h[d]).count();
    }
    // Gram matrix of the held rows: u row (1, 0, -y), v row (0, 1, x), phi row (0, 0, 1), with
    // x, y measured from the centre over the part's size (the rotation's column in lengths).
    let mut g = nalgebra::Matrix3::<f64>::zeros();
    for &k in nodes {
        let (x, y) = (
            (pos(k)[0] - centre[0]) / size,
            (pos(k)[1] - centre[1]) / size,
        );
        let rows = [[1.0, 0.0, -y], [0.0, 1.0, x], [0.0, 0.0, 1.0]];
        for (d, row) in rows.iter().enumerate() {
            if held[k][d] {
                let r = nalgebra::Vector3::from(*row);
                g += r * r.transpose();
            }
        }
    }
    for &(k, n) in resting.iter().filter(|(k, _)| nodes.contains(k)) {
        let (x, y) = (
            (pos(k)[0] - centre[0]) / size.max(f64::MIN_POSITIVE),
            (pos(k)[1] - centre[1]) / size.max(f64::MIN_POSITIVE),
        );
        let r = nalgebra::Vector3::new(n[0], n[1], n[1] * x - n[0] * y);
        g += r * r.transpose();
    }
    let eig = nalgebra::SymmetricEigen::new(g).eigenvalues;
    let top = eig.iter().fold(0.0f64, |m, v| m.max(*v)).max(1.0);
    eig.iter().filter(|&&v| v < RANK_TOLERANCE * top).count()
}
