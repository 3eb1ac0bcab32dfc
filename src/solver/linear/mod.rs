//! The linear algebra of the global solve, knowing nothing of beams or contact: a band matrix
//! over equations numbered by a reverse Cuthill-McKee ordering (`rcm.rs`), so a chain of n
//! elements costs O(n); its storage and assembly (`band.rs`), its factorisation and solve
//! (`factor.rs`: L D L^T while the pivots dominate, banded LU with partial pivoting beyond),
//! the L D L^T kernels (`ldlt.rs`) and the twisted factorisation of a long band from both ends
//! (`twisted.rs`), vector reductions (`reduce.rs`), the AVX2 dispatch (`simd.rs`) and a dense LU
//! for cross-checks (`dense.rs`).

mod band;
mod dense;
mod factor;
mod ldlt;
mod rcm;
pub mod reduce;
pub mod simd;
mod twisted;

pub(crate) use band::zero_ahead;
pub use band::{consecutive_first, symmetric6, BandMatrix, SingularPivot, LOWER_COLUMNS, NOT_FREE};
pub use dense::dense_solve;
pub use rcm::reverse_cuthill_mckee;
