//! Reductions over long vectors and the short vector update of the band solves (`axpy`).
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

/// `x -= a v`, unrolled for the short lengths of a band.
#[inline(always)]
pub(crate) fn axpy(x: &mut [f64], v: &[f64], a: f64) {
    fn fixed<const K: usize>(x: &mut [f64], v: &[f64], a: f64) {
        let x: &mut [f64; K] = x.try_into().expect("K entries");
        let v: &[f64; K] = v.try_into().expect("K entries");
        for t in 0..K {
            x[t] -= v[t] * a;
        }
    }
    match x.len() {
        3 => fixed::<3>(x, v, a),
        4 => fixed::<4>(x, v, a),
        5 => fixed::<5>(x, v, a),
        6 => fixed::<6>(x, v, a),
        _ => {
            for (x, v) in x.iter_mut().zip(v) {
                *x -= v * a;
            }
        }
    }
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
}
