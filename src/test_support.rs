//! Helpers shared by the unit tests (the integration tests have theirs in `tests/common`): a
//! reproducible pseudo-random sequence, a loaded state of a built-in scene, and the check that
//! the CPU can run the AVX2 builds being compared.

use crate::solver::{Silent, Solver};

/// A small deterministic pseudo-random sequence (xorshift), so failures are reproducible.
pub(crate) struct Rng(pub(crate) u64);

impl Rng {
    /// Next value in [0, 1).
    pub(crate) fn unit(&mut self) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// The solver of built-in scene `name` after `steps` converged steps.
pub(crate) fn solver_after(name: &str, steps: usize) -> Solver {
    let mut s = crate::scene::builtin::builtin(name)
        .expect("built-in")
        .expect("valid")
        .solver()
        .expect("stable");
    for _ in 0..steps {
        s.step(&mut Silent).expect("converges");
    }
    s
}

/// Whether the CPU has AVX2 (what a comparison of the AVX2 and baseline builds needs); says so
/// on stderr where it has not, so a skipped comparison is visible.
pub(crate) fn avx2() -> Option<crate::solver::linear::simd::Avx2> {
    let cpu = crate::solver::linear::simd::Avx2::detect();
    if cpu.is_none() {
        eprintln!("no AVX2 on this CPU: nothing to compare");
    }
    cpu
}
