//! The scratch space the Newton attempts of a run share: the equation ordering of the last
//! contact topology, the assembly at the last converged state (the next predictor may start
//! from it), and the buffers an attempt takes over from the one before.

use std::cell::RefCell;
use std::sync::Arc;

use crate::solver::assembly::{Assembled, Ordering};
use crate::solver::contact::ContactSet;
use crate::solver::structure::Structure;

/// The assembly at the last converged state, kept for the next increment's predictor, which
/// starts from that very state: for a structure without contact elements and with no
/// prescribed increment, it would assemble the same internal forces and tangent again. Taken
/// (not copied) by the first attempt that uses it.
#[derive(Clone, Default)]
pub(crate) struct ConvergedAssembly(pub(crate) RefCell<Option<(usize, Assembled)>>);

impl ConvergedAssembly {
    /// Keep `asm`, assembled at the state converged in `increment`.
    pub(crate) fn keep(&self, increment: usize, asm: Assembled) {
        *self.0.borrow_mut() = Some((increment, asm));
    }

    /// The assembly kept at `increment`, if there is one with a tangent (it is handed over).
    pub(crate) fn take(&self, increment: usize) -> Option<Assembled> {
        match self.0.borrow_mut().take() {
            Some((i, asm)) if i == increment && asm.tangent.is_some() => Some(asm),
            _ => None,
        }
    }
}

impl std::fmt::Debug for ConvergedAssembly {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let kept = self.0.borrow().as_ref().map(|(i, _)| *i);
        f.debug_tuple("ConvergedAssembly").field(&kept).finish()
    }
}

/// Buffers an attempt takes over from the one before, so that the increments of a large model
/// allocate no fresh memory (each fresh page costs a page fault, some microseconds on this kind
/// of machine): a displacement vector no longer in use and the right-hand side.
#[derive(Clone, Debug, Default)]
pub(crate) struct Spare {
    /// The displacements before the last commit (any contents: they are overwritten).
    pub(crate) d: Vec<f64>,
    /// The right-hand side of the last attempt (any contents).
    pub(crate) rhs: Vec<f64>,
}

/// The scratch space of a run's Newton attempts.
#[derive(Clone, Debug, Default)]
pub struct Workspace {
    /// The ordering of the last contact topology asked for.
    ordering: RefCell<Option<Arc<Ordering>>>,
    /// The assembly (internal forces and unfactored tangent) at the last converged state.
    pub(crate) converged_assembly: ConvergedAssembly,
    /// Buffers for the next attempt.
    pub(crate) spare: RefCell<Spare>,
}

impl Workspace {
    /// The equation ordering of `structure` for a contact topology; the last one built is
    /// kept, since the topology rarely changes between iterations and increments. Shared, so
    /// handing it out copies nothing.
    pub(crate) fn ordering_for(
        &self,
        structure: &Structure,
        contacts: &ContactSet,
    ) -> Arc<Ordering> {
        let links = contacts.links(&structure.model);
        let mut cache = self.ordering.borrow_mut();
        match cache.as_ref() {
            Some(o) if o.links == links => o.clone(),
            _ => {
                let o = Arc::new(Ordering::new(&structure.model, &structure.dofs, &links));
                *cache = Some(o.clone());
                o
            }
        }
    }
}
