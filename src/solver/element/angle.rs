//! The chord angle of a beam element: `atan2(y, x)` to within 2 ulp of the correctly rounded
//! value, inlined into the element evaluation (the libm call was a tenth of an iteration).
//!
//! The octant is folded to a ratio t = num/den in [0, 1], t is split at the nearest of the
//! points c = i/8 (atan(t) = atan(c) + atan(s), s = (t - c)/(1 + c t), |s| <= 1/16), atan(s)
//! is its Taylor series to s^13 (the first term left out is below 2^-60 of s), and atan(c) comes
//! from a table in two parts (the value rounded, and its rounding error), as do pi and pi/2 in
//! the unfolding. Infinite, NaN and (0, 0) arguments go to libm. Near the axes (where chords of
//! straight members lie) the result is rounded once, like libm's.

/// atan(i/8), i = 0..8, as [value rounded to f64, the rest] (an array, so that
/// the four-lane path in `beam_lanes.rs` can gather from it).
pub(super) static ATAN_EIGHTHS: [[f64; 2]; 9] = [
    [0.0, 0.0],
    [0.12435499454676144, -3.1253241424539383e-18],
    [0.24497866312686414, 1.0698755618734451e-17],
    [0.35877067027057225, -2.4623815582638635e-17],
    [0.4636476090008061, 2.2698777452961687e-17],
    [0.5585993153435624, -5.4556305485916264e-18],
    [0.6435011087932844, 1.5834785051444286e-17],
    [0.7188299996216245, -2.1478388444456983e-17],
    [std::f64::consts::FRAC_PI_4, 3.061616997868383e-17],
];

/// pi as (value rounded to f64, the rest).
pub(super) const PI: (f64, f64) = (std::f64::consts::PI, 1.2246467991473532e-16);

/// pi/2 as (value rounded to f64, the rest).
pub(super) const HALF_PI: (f64, f64) = (std::f64::consts::FRAC_PI_2, 6.123233995736766e-17);

/// The angle of the vector (x, y) from the x axis, in [-pi, pi]: `y.atan2(x)` to within 2 ulp
/// (signed zeros and the axes as `atan2` has them).
#[inline(always)]
pub fn chord_angle(y: f64, x: f64) -> f64 {
    let (ax, ay) = (x.abs(), y.abs());
    if !(ax.max(ay) > 0.0 && ax.max(ay) < f64::INFINITY) {
        // (0, 0), infinities and NaN: never a chord of positive finite length.
        return y.atan2(x);
    }
    // Fold to the first octant: t = num / den in [0, 1].
    let steep = ay > ax;
    let (num, den) = if steep { (ax, ay) } else { (ay, ax) };
    let i = (num / den * 8.0 + 0.5) as usize;
    let c = i as f64 * 0.125;
    // s = (t - c) / (1 + c t), from num and den (no rounding of t in it).
    let s = (num - c * den) / (den + c * num);
    let z = s * s;
    let series = (((((z * (-1.0 / 13.0) + 1.0 / 11.0) * z - 1.0 / 9.0) * z + 1.0 / 7.0) * z
        - 1.0 / 5.0)
        * z
        + 1.0 / 3.0)
        * z;
    let [hi, lo] = ATAN_EIGHTHS[i.min(8)];
    // atan(t) = atan(c) + (s - s^3/3 + ...), the small parts summed first.
    let a = hi + (lo + (s - s * series));
    // Unfold in one step, base +- a with the rounded base added last: near an axis (a tiny)
    // the result is rounded once, as atan2 has it (a near-vertical chord keeps its pi/2).
    let ((base, rest), a) = match (steep, x < 0.0) {
        (false, false) => ((0.0, 0.0), a),
        (true, false) => (HALF_PI, -a),
        (true, true) => (HALF_PI, a),
        (false, true) => (PI, -a),
    };
    (base + (rest + a)).copysign(y)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Distance in units in the last place between two finite f64 of the same sign.
    fn ulps(a: f64, b: f64) -> u64 {
        if a == b {
            return 0;
        }
        assert_eq!(a.is_sign_negative(), b.is_sign_negative(), "{a} vs {b}");
        (a.abs().to_bits() as i64 - b.abs().to_bits() as i64).unsigned_abs()
    }

    /// Against libm's atan2 (glibc: within 1 ulp of the exact value) at a million points of
    /// every octant and of magnitudes from 1e-300 to 1e300, the octant boundaries and the
    /// split points i/8 included: within 2 ulp everywhere.
    #[test]
    fn chord_angle_is_atan2_to_two_ulp() {
        let mut rng = crate::test_support::Rng(0x2545_f491_4f6c_dd1d);
        let mut next = || rng.unit();
        let mut worst = 0;
        for k in 0..1_000_000 {
            let angle = (next() * 2.0 - 1.0) * std::f64::consts::PI;
            let r = match k % 4 {
                0 => 1.0,
                1 => 10f64.powf(next() * 600.0 - 300.0),
                _ => next() * 3.0,
            };
            let (x, y) = (r * angle.cos(), r * angle.sin());
            worst = worst.max(ulps(chord_angle(y, x), y.atan2(x)));
        }
        for i in 0..=8 {
            for t in [
                i as f64 / 8.0,
                i as f64 / 8.0 + 1e-12,
                (i as f64 + 0.5) / 8.0,
            ] {
                for (x, y) in [(1.0, t), (t, 1.0), (-1.0, t), (-t, -1.0), (1.0, -t)] {
                    worst = worst.max(ulps(chord_angle(y, x), y.atan2(x)));
                }
            }
        }
        assert!(worst <= 2, "worst {worst} ulp");
    }

    /// The axes, signed zeros and the arguments libm handles: exactly atan2's values.
    #[test]
    fn chord_angle_has_atan2_values_on_the_axes() {
        for (y, x) in [
            (0.0, 1.0),
            (-0.0, 1.0),
            (0.0, -1.0),
            (-0.0, -1.0),
            (1.0, 0.0),
            (1.0, -0.0),
            (-1.0, 0.0),
            (2.0, 2.0),
            (-3.0, -3.0),
            (0.0, 0.0),
            (-0.0, -0.0),
            (f64::INFINITY, 1.0),
        ] {
            let (a, b) = (chord_angle(y, x), y.atan2(x));
            assert!(ulps(a, b) <= 1, "atan2({y}, {x}): {a} vs {b}");
            assert_eq!(a.is_sign_negative(), b.is_sign_negative(), "({y}, {x})");
        }
        assert!(chord_angle(f64::NAN, 1.0).is_nan());
    }

    /// A chord within round-off of an axis (a straight vertical or horizontal member moved
    /// by round-off): rounded once, so exactly atan2's value, as rigid-body motions need (a
    /// last-bit error there is a spurious element rotation that Newton cannot remove).
    #[test]
    fn chord_angle_is_atan2_exactly_next_to_the_axes() {
        for tiny in [7.9e-20, 6.3e-19, 2.4e-18, 1.5e-17, 1e-16] {
            for (y, x) in [
                (0.05, tiny),
                (0.05, -tiny),
                (-0.05, tiny),
                (-0.05, -tiny),
                (tiny, 2.0),
                (-tiny, 2.0),
                (tiny, -2.0),
                (-tiny, -2.0),
            ] {
                assert_eq!(chord_angle(y, x), y.atan2(x), "atan2({y}, {x})");
            }
        }
    }
}
