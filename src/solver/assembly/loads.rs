//! The external force `lambda F` at one load factor, kept at the loaded dofs only: a model of
//! 10^5 elements with a tip load needs one entry, not a vector over every dof per increment.
//! A distributed load adds the work-equivalent forces of its linear variation to the element's
//! two nodes (per undeformed length and in fixed directions, it does not depend on the
//! deformation, so it adds nothing to the tangent). Follower loads depend on the state: they
//! are assembled with the elements (`follower.rs`).

use super::dofs::DofMap;
use crate::solver::model::Model;

/// The external force at one load factor: (global dof, force), each loaded dof once, ascending,
/// the loads on one dof summed in the model's order.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ExternalForce(pub Vec<(usize, f64)>);

impl ExternalForce {
    /// The force at global dof `g` (0 where nothing is applied).
    pub fn at(&self, g: usize) -> f64 {
        match self.0.binary_search_by_key(&g, |&(d, _)| d) {
            Ok(k) => self.0[k].1,
            Err(_) => 0.0,
        }
    }

    /// Sum of the squares of the forces.
    pub fn sum_squares(&self) -> f64 {
        self.0.iter().map(|(_, f)| f * f).sum()
    }

    /// The force over every global dof (`len` of them).
    pub fn dense(&self, len: usize) -> Vec<f64> {
        let mut f = vec![0.0; len];
        for &(g, v) in &self.0 {
            f[g] = v;
        }
        f
    }
}

impl ExternalForce {
    /// The external force of `model`'s loads at the load factors `factors` (one per load
    /// group).
    pub fn of(model: &Model, dofs: &DofMap, factors: &[f64]) -> ExternalForce {
        let mut entries: Vec<(usize, f64)> = Vec::new();
        for l in &model.loads {
            for o in 0..model.node_dofs(l.node) {
                entries.push((dofs.dof(l.node, o), factors[l.group] * l.force[o]));
            }
        }
        for d in model.distributed.iter().filter(|d| !d.follower) {
            let b = &model.beams[d.beam];
            let l = model.beam_length(d.beam);
            // Linear shape functions: (2 qi + qj) l / 6 at i and (qi + 2 qj) l / 6 at j.
            for (node, (a, c)) in [(b.i, (2.0, 1.0)), (b.j, (1.0, 2.0))] {
                for o in 0..2 {
                    let f = l * (a * d.q[0][o] + c * d.q[1][o]) / 6.0;
                    entries.push((dofs.dof(node, o), factors[d.group] * f));
                }
            }
        }
        // Stable: the loads on one dof stay in the model's order, and are summed in it.
        entries.sort_by_key(|&(g, _)| g);
        let mut merged: Vec<(usize, f64)> = Vec::with_capacity(entries.len());
        for (g, f) in entries {
            match merged.last_mut() {
                Some((last, sum)) if *last == g => *sum += f,
                _ => merged.push((g, 0.0 + f)),
            }
        }
        ExternalForce(merged)
    }
}

#[cfg(test)]
mod tests {
    /// Against the force summed over every dof, load by load: two loads on one node (summed),
    /// one elsewhere, at a load factor of 0.7.
    #[test]
    fn loads_on_one_dof_are_summed_and_looked_up() {
        let mut s = crate::test_support::solver_after("mattiasson", 0);
        let tip = s.structure.model.loads[0].node;
        s.structure.model.loads.push(crate::solver::Load {
            node: tip,
            force: [2.0, -0.5, 0.25],
            group: 0,
        });
        s.structure.model.loads.push(crate::solver::Load {
            node: 1,
            force: [0.0, 3.0, 0.0],
            group: 0,
        });
        let lambda = 0.7;
        let mut dense = vec![0.0; s.structure.dofs.len()];
        for l in &s.structure.model.loads {
            for o in 0..3 {
                dense[s.structure.dofs.dof(l.node, o)] += lambda * l.force[o];
            }
        }
        let f = s.structure.external_force(&[lambda]);
        assert!(f.0.windows(2).all(|w| w[0].0 < w[1].0), "ascending, once");
        for (g, &v) in dense.iter().enumerate() {
            assert_eq!(f.at(g), v, "dof {g}");
        }
        assert_eq!(f.dense(s.structure.dofs.len()), dense);
        let squares: f64 = dense.iter().map(|v| v * v).sum();
        assert!((f.sum_squares() - squares).abs() <= 1e-15 * squares);
    }

    /// A load varying linearly along one element puts on each end node the integral of its
    /// linear shape function times the load (midpoint rule on 10^4 pieces), and nothing on
    /// the rotations.
    #[test]
    fn a_linear_distributed_load_is_the_integral_of_the_shape_functions() {
        let mut s = crate::test_support::solver_after("mattiasson", 0);
        let q = [[0.3, -2.0], [-0.1, 5.0]];
        s.structure.model.loads.clear();
        s.structure
            .model
            .distributed
            .push(crate::solver::DistributedLoad {
                beam: 2,
                q,
                follower: false,
                group: 0,
            });
        let (l, b) = (
            s.structure.model.beam_length(2),
            s.structure.model.beams[2].clone(),
        );
        let f = s.structure.external_force(&[1.0]);
        let pieces = 10_000;
        for (node, weight) in [
            (b.i, (|t: f64| 1.0 - t) as fn(f64) -> f64),
            (b.j, |t: f64| t),
        ] {
            for (o, (qi, qj)) in q[0].iter().zip(&q[1]).enumerate() {
                let integral: f64 = (0..pieces)
                    .map(|k| {
                        let t = (k as f64 + 0.5) / pieces as f64;
                        weight(t) * (qi + t * (qj - qi)) * l / pieces as f64
                    })
                    .sum();
                let got = f.at(s.structure.dofs.dof(node, o));
                assert!(
                    (got - integral).abs() < 1e-8,
                    "node {node} dof {o}: {got} vs {integral}"
                );
            }
            assert_eq!(f.at(s.structure.dofs.dof(node, 2)), 0.0);
        }
    }
}
