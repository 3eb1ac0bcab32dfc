//! Helpers shared by the integration tests.

/// A small deterministic pseudo-random sequence (xorshift) in [-1, 1), so failures are
/// reproducible.
pub struct Rng(pub u64);

impl Rng {
    /// Next value in [-1, 1).
    pub fn next(&mut self) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    }
}
