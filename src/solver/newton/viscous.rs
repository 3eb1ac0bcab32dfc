//! The viscous force of a snap's pseudo-time steps (`control/snap.rs`): a force
//! `c w_g (d_g - a_g)` on every free dof g, against the motion from the anchor state a (the
//! last state of the snap), with `w_g` 1 for a translation and the square of the shortest
//! element length for a rotation, so that c is a stiffness (N/m) for both. An attempt given
//! one adds it to the internal forces and `c w_g` to the tangent's diagonal: each step is a
//! backward-Euler step of the damped motion `c w v + f_int(d) = f_ext`, which goes down to a
//! stable state from a state that has no equilibrium near it.

use crate::solver::assembly::{Assembled, Ordering};
use crate::solver::linear::reduce::sum_squares;
use crate::solver::linear::BandMatrix;

/// A viscous force `c w (d - anchor)` over the free dofs.
#[derive(Clone, Copy, Debug)]
pub struct Viscous<'a> {
    /// The viscosity over the pseudo-time step (N/m).
    pub c: f64,
    /// The state the step starts from (all dofs).
    pub anchor: &'a [f64],
    /// The weight of every dof: 1 for a translation, the square of a length for a rotation.
    pub weight: &'a [f64],
}

impl Viscous<'_> {
    /// The viscous force on dof g at displacements `d`.
    fn force(&self, d: &[f64], g: usize) -> f64 {
        self.c * self.weight[g] * (d[g] - self.anchor[g])
    }

    /// Take the viscous force at `d` off the unbalanced force of `asm` (over the free
    /// equations of `ord`), and its sum of squares with it.
    pub(crate) fn load(&self, d: &[f64], ord: &Ordering, asm: &mut Assembled) {
        for (e, r) in asm.unbalanced.iter_mut().enumerate() {
            *r -= self.force(d, ord.dof_of[e] as usize);
        }
        asm.unbalanced_norm2 = sum_squares(&asm.unbalanced);
    }

    /// The largest viscous stiffness `c w` the solve adds to the tangent's diagonal.
    pub(crate) fn peak(&self) -> f64 {
        self.c * self.weight.iter().fold(0.0f64, |w, &x| w.max(x))
    }

    /// Add the viscous force's stiffness `c w` to the diagonal of `tangent` (over the free
    /// equations of `ord`).
    pub(crate) fn stiffen(&self, ord: &Ordering, tangent: &mut BandMatrix) {
        for e in 0..tangent.len() {
            tangent.add(e, e, self.c * self.weight[ord.dof_of[e] as usize]);
        }
    }

    /// Put the viscous force at `d` back into the unbalanced force of `asm`, as
    /// [`Viscous::load`] found it: the assembly of the state itself, out of equilibrium by the
    /// viscous force.
    pub(crate) fn unload(&self, d: &[f64], ord: &Ordering, asm: &mut Assembled) {
        for (e, r) in asm.unbalanced.iter_mut().enumerate() {
            *r += self.force(d, ord.dof_of[e] as usize);
        }
        asm.unbalanced_norm2 = sum_squares(&asm.unbalanced);
    }
}
