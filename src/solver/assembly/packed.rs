//! A beam element packed for the assembly: what the assembly reads of a beam with no contact on
//! it, in one cache line.

use super::coordinates::residue_at;
use super::dofs::DofMap;
use crate::solver::element::beam::{BeamElement, ForceConstants};
use crate::solver::model::Model;

/// What the assembly reads of a beam with no contact on it, packed into one cache line: the
/// first global dofs of its end nodes (u, v, phi each), the initial position of its end j
/// relative to its end i, and its force constants.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PackedBeam {
    /// First global dof of node i, then of node j.
    pub first: [u32; 2],
    /// X_j - X_i (initial).
    pub span: [f64; 2],
    /// The element force equation's constants.
    pub constants: ForceConstants,
}

impl PackedBeam {
    /// The packed beams of `model` (whose elements are `elements`, numbered by `dofs`).
    pub fn all(model: &Model, dofs: &DofMap, elements: &[BeamElement]) -> Vec<PackedBeam> {
        let first = |n: usize| u32::try_from(dofs.first[n]).expect("dofs fit in u32");
        model
            .beams
            .iter()
            .zip(elements)
            .map(|(b, el)| {
                let (p, q) = (model.position(b.i), model.position(b.j));
                PackedBeam {
                    first: [first(b.i), first(b.j)],
                    span: [q[0] - p[0], q[1] - p[1]],
                    constants: el.constants(),
                }
            })
            .collect()
    }

    /// The beam's ends at displacements `d` with their residues `residue` (empty: none), as
    /// `coordinates::between` has them: end i at (0, 0), end j at `(X_j - X_i) + ((u_j - u_i) +
    /// (r_j - r_i))`, and the end rotations (i, j).
    #[inline(always)]
    pub fn ends(&self, d: &[f64], residue: &[f64]) -> ([f64; 2], [f64; 2], [f64; 2]) {
        let (fi, fj) = (self.first[0] as usize, self.first[1] as usize);
        let along = |k: usize| {
            let carried = residue_at(residue, fj + k) - residue_at(residue, fi + k);
            self.span[k] + ((d[fj + k] - d[fi + k]) + carried)
        };
        ([0.0, 0.0], [along(0), along(1)], [d[fi + 2], d[fj + 2]])
    }
}
