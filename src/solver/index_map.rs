//! A hash map keyed by small integers (node, element and body indices): no need for the
//! default hasher's resistance to crafted keys, and several times faster to hash.

use std::collections::HashMap;
use std::hash::{BuildHasherDefault, Hasher};

/// A fast hasher for small integer keys (cells, element indices): multiply and rotate, as in
/// rustc's FxHasher. Not resistant to adversarial keys, which these are not.
#[derive(Default, Clone, Copy)]
pub struct IndexHasher(u64);

impl Hasher for IndexHasher {
    fn write(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.write_u64(u64::from(b));
        }
    }
    fn write_u64(&mut self, v: u64) {
        self.0 = (self.0.rotate_left(5) ^ v).wrapping_mul(0x51_7c_c1_b7_27_22_0a_95);
    }
    fn write_i64(&mut self, v: i64) {
        self.write_u64(v as u64);
    }
    fn write_usize(&mut self, v: usize) {
        self.write_u64(v as u64);
    }
    fn finish(&self) -> u64 {
        self.0
    }
}

/// A `HashMap` keyed by small integers, hashed with `IndexHasher`.
pub type IndexMap<K, V> = HashMap<K, V, BuildHasherDefault<IndexHasher>>;
