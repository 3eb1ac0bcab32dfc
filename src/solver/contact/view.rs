//! What the contact stage reads of the solver: the structure, and the last converged
//! displacements and contact set that every test of a pass is measured from. Nothing else of
//! the solver's state or scratch space is in reach.

use std::ops::Deref;

use super::set::ContactSet;
use crate::solver::structure::Structure;

/// The structure (through `Deref`) and the last converged state, for the contact stage.
#[derive(Clone, Copy)]
pub struct ContactView<'a> {
    /// The model prepared for assembly.
    pub structure: &'a Structure,
    /// Displacements at the last converged state.
    pub d: &'a [f64],
    /// Contact set at the last converged state.
    pub contacts: &'a ContactSet,
}

impl Deref for ContactView<'_> {
    type Target = Structure;

    fn deref(&self) -> &Structure {
        self.structure
    }
}
