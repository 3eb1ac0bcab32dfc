//! Reductions over long vectors (norms, largest entries) with independent partial results, so that a
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

/// `out = -v` with `f` added at each `(k, f)` of `loads` (ascending k, each k once), and the
/// sum of squares of `out`, in one pass over the vectors: the sum is accumulated as
/// `sum_squares(out)` accumulates it, bit for bit. (The unbalanced force of a Newton iteration
/// and its norm from the internal forces, in a pass of its own: the assembly now settles the same
/// arithmetic block by block as it goes, and is tested against this.)
pub fn negated_with_loads(v: &[f64], loads: &[(usize, f64)], out: &mut Vec<f64>) -> f64 {
    let n = v.len();
    if out.len() != n {
        out.clear();
        out.resize(n, 0.0);
    }
    let mut loads = loads.iter().peekable();
    let mut acc = [0.0; 4];
    let whole = n - n % 4;
    let blocks = out[..whole].chunks_exact_mut(4).zip(v.chunks_exact(4));
    for (b, (o, x)) in blocks.enumerate() {
        for t in 0..4 {
            o[t] = -x[t];
        }
        while let Some(&(k, f)) = loads.next_if(|&&(k, _)| k < 4 * b + 4) {
            o[k - 4 * b] += f;
        }
        for t in 0..4 {
            acc[t] += o[t] * o[t];
        }
    }
    for (o, x) in out[whole..].iter_mut().zip(&v[whole..]) {
        *o = -x;
    }
    for &(k, f) in loads {
        out[k] += f;
    }
    out[whole..]
        .iter()
        .fold((acc[0] + acc[1]) + (acc[2] + acc[3]), |s, x| s + x * x)
}

/// Largest |v[start + k stride]| over k (0 for none), in four interleaved partial maxima (NaN
/// entries are ignored, as `f64::max` does).
pub fn max_abs_strided(v: &[f64], start: usize, stride: usize) -> f64 {
    let v = v.get(start..).unwrap_or(&[]);
    let mut acc = [0.0f64; 4];
    let blocks = v.chunks_exact(4 * stride);
    let rest = blocks.remainder();
    for block in blocks {
        for (t, m) in acc.iter_mut().enumerate() {
            let a = block[t * stride].abs();
            if a > *m {
                *m = a;
            }
        }
    }
    let mut m = acc.into_iter().fold(0.0, f64::max);
    for a in rest.iter().step_by(stride) {
        m = m.max(a.abs());
    }
    m
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
            for stride in [1, 3, 6] {
                for start in [0, 2] {
                    let max = v
                        .iter()
                        .skip(start)
                        .step_by(stride)
                        .fold(0.0, |m: f64, x| m.max(x.abs()));
                    let fast = max_abs_strided(&v, start, stride);
                    assert_eq!(fast, max, "n {n} stride {stride} start {start}");
                }
            }
        }
        assert_eq!(max_abs_strided(&[1.0, f64::NAN, -3.0], 0, 1), 3.0);
    }

    /// The one-pass negation with loads gives what negating, adding the loads and then
    /// `sum_squares` give, bit for bit: loads at the first entry, inside and at the ends of
    /// blocks of four, in the remainder, none at all; an output vector of another length.
    #[test]
    fn negation_with_loads_is_the_separate_passes_bit_for_bit() {
        for n in [0usize, 1, 3, 4, 7, 9, 1001] {
            let v: Vec<f64> = (0..n).map(|k| ((k * 37) % 11) as f64 / 3.0 - 1.7).collect();
            let all: Vec<(usize, f64)> = [0, 2, 3, 4, 7, 8, 998, 1000]
                .into_iter()
                .filter(|&k| k < n)
                .map(|k| (k, 0.1 * k as f64 + 0.3))
                .collect();
            for loads in [&all[..], &[]] {
                let mut expected: Vec<f64> = v.iter().map(|x| -x).collect();
                for &(k, f) in loads {
                    expected[k] += f;
                }
                let mut out = vec![9.0; 5];
                let sum = negated_with_loads(&v, loads, &mut out);
                let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
                assert_eq!(bits(&out), bits(&expected), "n {n}");
                assert_eq!(sum.to_bits(), sum_squares(&expected).to_bits(), "n {n}");
            }
        }
    }
}
