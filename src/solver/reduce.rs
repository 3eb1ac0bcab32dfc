//! Reductions over long vectors (norms, maxima) with independent partial results, so that a
//! sum over 10^5 entries is not one serial chain of additions: each Newton iteration takes
//! several of them.

/// Sum of squares, accumulated in four interleaved partial sums.
pub fn sum_squares(v: &[f64]) -> f64 {
    let mut acc = [0.0; 4];
    let chunks = v.chunks_exact(4);
    let rest = chunks.remainder();
    for c in chunks {
        for t in 0..4 {
            acc[t] += c[t] * c[t];
        }
    }
    rest.iter()
        .fold((acc[0] + acc[1]) + (acc[2] + acc[3]), |s, x| s + x * x)
}

/// Largest of `values` and `floor`, taken in four interleaved partial maxima (NaN entries are
/// ignored, as `f64::max` does).
pub fn max_of(values: impl Iterator<Item = f64>, floor: f64) -> f64 {
    let mut acc = [floor; 4];
    for (k, v) in values.enumerate() {
        let slot = &mut acc[k % 4];
        if v > *slot {
            *slot = v;
        }
    }
    acc.into_iter().fold(floor, f64::max)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reductions_agree_with_the_serial_ones() {
        for n in [0usize, 1, 3, 4, 7, 1001] {
            let v: Vec<f64> = (0..n).map(|k| ((k * 37) % 11) as f64 - 5.5).collect();
            let serial: f64 = v.iter().map(|x| x * x).sum();
            assert!(
                (sum_squares(&v) - serial).abs() <= 1e-12 * serial.max(1.0),
                "n {n}"
            );
            let max = v.iter().fold(-1e300, |m: f64, &x| m.max(x));
            assert_eq!(max_of(v.iter().copied(), -1e300), max, "n {n}");
        }
        assert_eq!(max_of([1.0, f64::NAN, 3.0].into_iter(), 0.0), 3.0);
    }
}
