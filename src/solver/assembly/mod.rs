//! Assembly of the global equations at one state: the dof map and the equation ordering
//! (`dofs.rs`), the displacements carried with their rounding residues and the relative
//! positions the elements take from them (`coordinates.rs`), the external force at a load factor (`loads.rs`), and the unbalanced force and
//! band tangent summed from the beam and contact elements (`assemble.rs`, with the per-element
//! adds in `internal.rs`), the plain beams packed four at a time for the vector lanes
//! (`packed.rs`), the distributed loads that follow the deformation (`follower.rs`) and the
//! contacts with rigid obstacles (`obstacles.rs`).

mod assemble;
mod coordinates;
mod dofs;
mod follower;
mod internal;
mod loads;
mod obstacles;
mod packed;
#[cfg(test)]
mod tests;

pub use assemble::{assemble, assemble_into, Assembled, AssemblyContext, ElementResults};
pub use coordinates::{add_carried, between};
pub use dofs::{current, ContactLink, DofKind, DofMap, Ordering};
pub use follower::follower_response;
pub use loads::ExternalForce;
pub use obstacles::{obstacle_gap, obstacle_offset, ObstacleLink};
pub use packed::PackedBeam;
