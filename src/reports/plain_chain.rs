//! The yardstick of the scale report: a plain banded assemble-and-factor loop for a chain of beam
//! elements, with nothing of the general solver (no dof map, no ordering, no contact, no
//! bookkeeping). One iteration evaluates every element (the same [`BeamElement::evaluate`] the
//! solver uses), sums the internal forces, adds the tangents into a symmetric band, factors it
//! L D L^T and solves for the unbalanced force. The general solver aims to lose little to this
//! loop.

use crate::solver::element::beam::BeamElement;
use crate::solver::linear::{BandMatrix, NOT_FREE};
use crate::solver::model::Section;

/// A straight chain of `n` elements 1 m long along x (the Mattiasson section, EA = 1e6, EI = 1,
/// Bernoulli-Euler), clamped at node 0, loaded at its tip by 1e-3 N across, in a fixed state.
/// Node k (1..=n) owns equations 3 (k - 1) .. 3 (k - 1) + 2: a half-bandwidth of 5.
#[derive(Clone, Debug)]
pub struct PlainChain {
    elements: Vec<BeamElement>,
    /// Displacements (u, v, phi) of nodes 1..=n.
    d: Vec<f64>,
    band: BandMatrix,
    rhs: Vec<f64>,
}

impl PlainChain {
    /// The chain of `n` elements, undeformed.
    pub fn new(n: usize) -> PlainChain {
        PlainChain::with_amplitude(n, 0.0)
    }

    /// The chain of `n` elements in a gentle wave (transverse amplitude `a`, rotations
    /// `a / 100`): a generic state, in which no element is exactly straight.
    pub fn with_amplitude(n: usize, a: f64) -> PlainChain {
        let section = Section {
            ea: 1.0e6,
            ei: 1.0,
            gae: 1.0e12,
            thickness: 0.0,
        };
        let elements = (0..n)
            .map(|e| BeamElement::new([e as f64, 0.0], [(e + 1) as f64, 0.0], section, 0.0))
            .collect();
        let d = (0..3 * n)
            .map(|q| match q % 3 {
                1 => a * (0.01 * (q / 3) as f64).sin(),
                2 => 0.01 * a * (0.01 * (q / 3) as f64).cos(),
                _ => 0.0,
            })
            .collect();
        PlainChain {
            elements,
            d,
            band: BandMatrix::symmetric_zeros(3 * n, 5),
            rhs: vec![0.0; 3 * n],
        }
    }

    /// The last correction (u, v, phi of nodes 1..=n), after `iteration`.
    pub fn correction(&self) -> &[f64] {
        &self.rhs
    }

    /// Number of elements.
    pub fn len(&self) -> usize {
        self.elements.len()
    }

    /// True if the chain has no elements.
    pub fn is_empty(&self) -> bool {
        self.elements.is_empty()
    }

    /// One Newton iteration at the fixed state: assemble, factor, solve. Returns the norm of
    /// the correction (so the work cannot be optimised away), or `None` if the tangent is
    /// singular.
    pub fn iteration(&mut self) -> Option<f64> {
        let n = self.elements.len();
        self.band.reset_symmetric_lazily(3 * n, 5);
        self.rhs.iter_mut().for_each(|r| *r = 0.0);
        if let Some(tip) = self.rhs.len().checked_sub(2) {
            self.rhs[tip] = -1e-3;
        }
        let mut k = [[0.0; 6]; 6];
        for (e, el) in self.elements.iter().enumerate() {
            // Node e (0 is the clamp) and node e + 1; positions relative to node e.
            let ui = match e {
                0 => [0.0; 3],
                _ => [self.d[3 * e - 3], self.d[3 * e - 2], self.d[3 * e - 1]],
            };
            let uj = [self.d[3 * e], self.d[3 * e + 1], self.d[3 * e + 2]];
            let r = el.evaluate(
                [ui[0], ui[1]],
                [1.0 + uj[0], uj[1]],
                ui[2],
                uj[2],
                Some(&mut k),
            );
            let eqs: [u32; 6] = std::array::from_fn(|a| match (e, a / 3) {
                (0, 0) => NOT_FREE,
                (_, 0) => (3 * e - 3 + a) as u32,
                _ => (3 * e + a - 3) as u32,
            });
            for (a, &q) in eqs.iter().enumerate() {
                if q != NOT_FREE {
                    self.rhs[q as usize] -= r.nodal[a];
                }
            }
            self.band.add_element(&eqs, &k);
        }
        self.band.finish_assembly();
        self.band.factor(0.0).ok()?;
        self.band.solve(&mut self.rhs);
        Some(self.rhs.iter().map(|v| v * v).sum::<f64>().sqrt())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// From the undeformed state the first correction is the linear solution: the cantilever's
    /// tip deflection P L^3 / (3 EI) and rotation P L^2 / (2 EI), exact for cubic elements.
    #[test]
    fn first_correction_is_the_linear_cantilever() {
        let n = 10;
        let mut chain = PlainChain::new(n);
        chain.iteration().expect("nonsingular");
        let tip = &chain.correction()[3 * n - 3..];
        let (p, l) = (1e-3, n as f64);
        assert!((tip[1] + p * l.powi(3) / 3.0).abs() < 1e-12, "{}", tip[1]);
        assert!((tip[2] + p * l.powi(2) / 2.0).abs() < 1e-12, "{}", tip[2]);
        assert!(tip[0].abs() < 1e-15, "{}", tip[0]);
    }
}
