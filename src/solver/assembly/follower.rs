//! Distributed loads that follow the deformation (pressure): per unit of current length,
//! along and across the element's current chord, varying linearly from end i to end j. On a
//! chord D = x_j - x_i the load on node i is lambda (a_t D + a_n R D) and on node j
//! lambda (b_t D + b_n R D), with R the quarter turn and a = (2 q_i + q_j) / 6,
//! b = (q_i + 2 q_j) / 6 (the work-equivalent forces of the linear load): linear in the node
//! positions, so the tangent is exact and constant, and unsymmetric where a load acts across
//! the chord (a pressure is not conservative on an open beam).

use crate::solver::model::DistributedLoad;

/// The follower loads `loads` of one element at chord `chord` (x_j - x_i) and load factors
/// `factors` (one per load group), as internal forces over (u_i, v_i, u_j, v_j) (minus the loads, which is how the
/// assembly subtracts them from the unbalanced force), and their tangent (the derivative of
/// those internal forces by the same four dofs).
pub fn follower_response(
    loads: &[DistributedLoad],
    chord: [f64; 2],
    factors: &[f64],
) -> ([f64; 4], [[f64; 4]; 4]) {
    // Per node, the weights (along, across) of the chord.
    let (mut a, mut b) = ([0.0; 2], [0.0; 2]);
    for d in loads.iter().filter(|d| d.follower) {
        let lambda = factors[d.group];
        for o in 0..2 {
            a[o] += lambda * (2.0 * d.q[0][o] + d.q[1][o]) / 6.0;
            b[o] += lambda * (d.q[0][o] + 2.0 * d.q[1][o]) / 6.0;
        }
    }
    let turn = [-chord[1], chord[0]];
    let load = |w: [f64; 2]| {
        [
            w[0] * chord[0] + w[1] * turn[0],
            w[0] * chord[1] + w[1] * turn[1],
        ]
    };
    let (fi, fj) = (load(a), load(b));
    let nodal = [-fi[0], -fi[1], -fj[0], -fj[1]];
    // d(load on a node)/d(x_j) = w_t I + w_n R; d/d(x_i) the opposite. Internal forces are
    // minus the loads.
    let block = |w: [f64; 2]| [[w[0], -w[1]], [w[1], w[0]]];
    let (ba, bb) = (block(a), block(b));
    let mut k = [[0.0; 4]; 4];
    for r in 0..2 {
        for c in 0..2 {
            k[r][c] = ba[r][c];
            k[r][2 + c] = -ba[r][c];
            k[2 + r][c] = bb[r][c];
            k[2 + r][2 + c] = -bb[r][c];
        }
    }
    (nodal, k)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The tangent is the derivative of the internal forces: central differences of
    /// `follower_response` at a perturbed chord (the response is linear in the chord, so they
    /// agree to round-off), for a load with both components varying.
    #[test]
    fn the_tangent_is_the_derivative_of_the_forces() {
        let loads = [DistributedLoad {
            beam: 0,
            q: [[0.4, -1.3], [-0.2, 0.7]],
            follower: true,
            group: 0,
        }];
        let (chord, lambda) = ([0.8, 0.35], [1.7]);
        let (_, k) = follower_response(&loads, chord, &lambda);
        let h = 1e-6;
        for c in 0..4 {
            // Dof c moves node i (c < 2) or node j: the chord changes by -e or +e.
            let sign = if c < 2 { -1.0 } else { 1.0 };
            let mut plus = chord;
            let mut minus = chord;
            plus[c % 2] += sign * h;
            minus[c % 2] -= sign * h;
            let (fp, _) = follower_response(&loads, plus, &lambda);
            let (fm, _) = follower_response(&loads, minus, &lambda);
            for r in 0..4 {
                let fd = (fp[r] - fm[r]) / (2.0 * h);
                assert!(
                    (fd - k[r][c]).abs() < 1e-8,
                    "K[{r}][{c}] = {} vs {fd}",
                    k[r][c]
                );
            }
        }
    }

    /// A uniform pressure across a chord puts its resultant q l across the chord, half on each
    /// node: on a chord along x of length 2, q_n = -3 pushes each node by 3 in -y.
    #[test]
    fn a_uniform_pressure_is_shared_by_the_two_nodes() {
        let loads = [DistributedLoad {
            beam: 0,
            q: [[0.0, -3.0], [0.0, -3.0]],
            follower: true,
            group: 0,
        }];
        let (nodal, _) = follower_response(&loads, [2.0, 0.0], &[1.0]);
        assert_eq!(nodal, [0.0, 3.0, 0.0, 3.0]);
    }
}
