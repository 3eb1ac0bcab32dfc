//! The geometry helpers of the obstacle shapes (`shape.rs`): vector arithmetic, the exact
//! arithmetic of a circle's gap, the nearest point of a polyline and its place along it, and
//! the ray count that tells the sides of a polyline for the acceptance check.

/// Where a point lies against an obstacle.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Gap {
    /// Signed distance to the curve: positive on the free side (m).
    pub g: f64,
    /// Unit normal: the gradient of `g`, pointing to the free side.
    pub n: [f64; 2],
    /// The Hessian of `g` is `curvature (I - n n^T)`: 1/g about a corner or 1/rho about a
    /// centre, with the sign of the side; 0 along a straight part.
    pub curvature: f64,
    /// The nearest point of the curve (m).
    pub point: [f64; 2],
}

pub(super) fn sub(a: [f64; 2], b: [f64; 2]) -> [f64; 2] {
    [a[0] - b[0], a[1] - b[1]]
}

pub(super) fn dot(a: [f64; 2], b: [f64; 2]) -> f64 {
    a[0] * b[0] + a[1] * b[1]
}

pub(super) fn cross(a: [f64; 2], b: [f64; 2]) -> f64 {
    a[0] * b[1] - a[1] * b[0]
}

/// The unit left normal of the direction `t` (not zero).
pub(super) fn left(t: [f64; 2]) -> [f64; 2] {
    let l = t[0].hypot(t[1]);
    [-t[1] / l, t[0] / l]
}

/// Where the polar angle `theta` lies past `from`, counter-clockwise, in [0, 2 pi).
pub(super) fn angle_past(theta: f64, from: f64) -> f64 {
    (theta - from).rem_euclid(std::f64::consts::TAU)
}

/// `Shape::place` on a polyline: the length along it to the nearest segment's start, plus the
/// way along that segment (negative before the first point, beyond the last past it).
pub(super) fn polyline_place(points: &[[f64; 2]], p: [f64; 2]) -> f64 {
    let last = points.len() - 2;
    let (mut best, mut place, mut start) = (f64::MAX, 0.0, 0.0);
    for s in 0..=last {
        let (a, b) = (points[s], points[s + 1]);
        let ab = sub(b, a);
        let len = ab[0].hypot(ab[1]);
        let lo = if s == 0 { f64::NEG_INFINITY } else { 0.0 };
        let hi = if s == last { f64::INFINITY } else { len };
        let along = (dot(sub(p, a), ab) / len).clamp(lo, hi);
        let q = [a[0] + along * ab[0] / len, a[1] + along * ab[1] / len];
        let d2 = dot(sub(p, q), sub(p, q));
        if d2 < best {
            (best, place) = (d2, start + along);
        }
        start += len;
    }
    place
}

/// `a - b` as an unevaluated sum (hi, lo), exactly (Knuth's two-sum).
fn two_diff(a: f64, b: f64) -> (f64, f64) {
    let s = a - b;
    let bb = s - a;
    (s, (a - (s - bb)) - (b + bb))
}

/// `a + b` as an unevaluated sum (hi, lo), exactly.
fn two_sum(a: f64, b: f64) -> (f64, f64) {
    let s = a + b;
    let bb = s - a;
    (s, (a - (s - bb)) + (b - bb))
}

/// `a * b` as an unevaluated sum (hi, lo), exactly (with a fused multiply-add).
fn two_prod(a: f64, b: f64) -> (f64, f64) {
    let p = a * b;
    (p, a.mul_add(b, -p))
}

/// `|x0 - c|^2 - r^2`, to a few units of round-off of the result (not of r^2): the
/// differences and squares are exact sums of two doubles, and the large terms cancel exactly.
fn power_at_rest(x0: [f64; 2], c: [f64; 2], r: f64) -> f64 {
    let (dx, ex) = two_diff(x0[0], c[0]);
    let (dy, ey) = two_diff(x0[1], c[1]);
    let (px, qx) = two_prod(dx, dx);
    let (py, qy) = two_prod(dy, dy);
    let (pr, qr) = two_prod(r, r);
    let (s1, e1) = two_sum(py, -pr);
    let (s2, e2) = two_sum(s1, px);
    let small = e1 + e2 + qx + qy - qr + 2.0 * (dx * ex + dy * ey) + ex * ex + ey * ey;
    s2 + small
}

/// `Shape::gap` of a circle (or, `hollow`, a hole) at `x0 + w`. With `r = x0 + w - c`,
/// `rho - R = (|r|^2 - R^2) / (rho + R)`, and `|r|^2 - R^2` is `|x0 - c|^2 - R^2` (from
/// `power_at_rest`) plus `2 (x0 - c) . w + w . w`, terms of the size of the motion: the gap
/// carries no round-off of the radius.
pub(super) fn circle_gap(
    centre: [f64; 2],
    radius: f64,
    hollow: bool,
    x0: [f64; 2],
    w: [f64; 2],
) -> Gap {
    let r0 = sub(x0, centre);
    let r = [r0[0] + w[0], r0[1] + w[1]];
    let rho = r[0].hypot(r[1]);
    let power = power_at_rest(x0, centre, radius) + 2.0 * dot(r0, w) + dot(w, w);
    let s = if hollow { -1.0 } else { 1.0 };
    // At the centre every direction is as near: any normal will do.
    let u = if rho > 0.0 {
        [r[0] / rho, r[1] / rho]
    } else {
        [0.0, 1.0]
    };
    Gap {
        g: s * power / (rho + radius),
        n: [s * u[0], s * u[1]],
        curvature: s / rho.max(f64::MIN_POSITIVE),
        point: [centre[0] + radius * u[0], centre[1] + radius * u[1]],
    }
}

/// `Shape::gap` of a polyline continued beyond its ends along its end segments. The nearest
/// point decides: inside a segment, the side of that segment; at a corner, the side of the
/// bisector of the two segments' normals (which tells the sides of a corner apart).
pub(super) fn polyline_gap(points: &[[f64; 2]], x: [f64; 2]) -> Gap {
    let last = points.len() - 2;
    // (squared distance, nearest point, segment, parameter along it)
    let mut best = (f64::MAX, points[0], 0, 0.0);
    for s in 0..=last {
        let (a, b) = (points[s], points[s + 1]);
        let t_ab = sub(b, a);
        let len2 = dot(t_ab, t_ab);
        let lo = if s == 0 { f64::NEG_INFINITY } else { 0.0 };
        let hi = if s == last { f64::INFINITY } else { 1.0 };
        let t = (dot(sub(x, a), t_ab) / len2).clamp(lo, hi);
        let p = [a[0] + t * t_ab[0], a[1] + t * t_ab[1]];
        let d2 = dot(sub(x, p), sub(x, p));
        if d2 < best.0 {
            best = (d2, p, s, t);
        }
    }
    let (d2, p, s, t) = best;
    let face = left(sub(points[s + 1], points[s]));
    // The corner at the nearest point, if it is one: the bisector of the two normals.
    let corner = if t <= 0.0 && s > 0 {
        Some(left(sub(points[s], points[s - 1])))
    } else if t >= 1.0 && s < last {
        Some(left(sub(points[s + 2], points[s + 1])))
    } else {
        None
    };
    let d = d2.sqrt();
    let side_normal = corner.map_or(face, |other| [face[0] + other[0], face[1] + other[1]]);
    let sign = if corner.is_some() {
        if dot(sub(x, p), side_normal) < 0.0 {
            -1.0
        } else {
            1.0
        }
    } else if cross(sub(points[s + 1], points[s]), sub(x, points[s])) < 0.0 {
        -1.0
    } else {
        1.0
    };
    let g = sign * d;
    match corner {
        Some(_) if d > 0.0 => Gap {
            g,
            n: [sign * (x[0] - p[0]) / d, sign * (x[1] - p[1]) / d],
            curvature: 1.0 / g,
            point: p,
        },
        _ => Gap {
            g,
            n: face,
            curvature: 0.0,
            point: p,
        },
    }
}

/// The distance from point `x` to the segment from `a` to `b`.
pub(super) fn segment_distance(a: [f64; 2], b: [f64; 2], x: [f64; 2]) -> f64 {
    let ab = sub(b, a);
    let len2 = ab[0] * ab[0] + ab[1] * ab[1];
    let t = (((x[0] - a[0]) * ab[0] + (x[1] - a[1]) * ab[1]) / len2).clamp(0.0, 1.0);
    (x[0] - a[0] - t * ab[0]).hypot(x[1] - a[1] - t * ab[1])
}

/// Whether point `x`'s polar angle about `centre` lies from `from` counter-clockwise to `to`.
pub(super) fn within_angles(centre: [f64; 2], from: f64, to: f64, x: [f64; 2]) -> bool {
    let r = sub(x, centre);
    let tau = std::f64::consts::TAU;
    (r[1].atan2(r[0]) - from).rem_euclid(tau) <= (to - from).rem_euclid(tau)
}

/// How far inside a disk (or outside a hole) point `x` lies.
pub(super) fn radial_depth(centre: [f64; 2], radius: f64, hollow: bool, x: [f64; 2]) -> f64 {
    let rho = (x[0] - centre[0]).hypot(x[1] - centre[1]);
    if hollow {
        rho - radius
    } else {
        radius - rho
    }
}

/// How far inside a polyline (continued along its end segments) point `x` lies: its distance
/// to the curve where a ray from it towards the free side's far field crosses the curve an
/// odd number of times, else 0.
pub(super) fn polyline_depth(points: &[[f64; 2]], x: [f64; 2]) -> f64 {
    let m = points.len();
    let unit = |v: [f64; 2]| {
        let l = v[0].hypot(v[1]);
        [v[0] / l, v[1] / l]
    };
    let first = unit(sub(points[1], points[0]));
    let last = unit(sub(points[m - 1], points[m - 2]));
    // Far away the curve is its two end rays: outward along -first and along last. The free
    // side's far field lies counter-clockwise from `last` to `-first`; the ray goes down its
    // middle (turned a little off it, so that it does not run along a piece).
    let a0 = last[1].atan2(last[0]);
    let sweep = ((-first[1]).atan2(-first[0]) - a0).rem_euclid(std::f64::consts::TAU);
    let sweep = if sweep == 0.0 {
        std::f64::consts::TAU
    } else {
        sweep
    };
    let a = a0 + 0.5 * sweep + 1e-3;
    let v = [a.cos(), a.sin()];
    // The pieces: the segments, then the end rays (as segments long enough to reach past x).
    let span = points
        .iter()
        .map(|p| (p[0] - x[0]).hypot(p[1] - x[1]))
        .fold(0.0, f64::max);
    let reach = 4.0 * span + 1.0;
    let mut pieces: Vec<([f64; 2], [f64; 2])> = points.windows(2).map(|w| (w[0], w[1])).collect();
    let p0 = points[0];
    pieces.push(([p0[0] - reach * first[0], p0[1] - reach * first[1]], p0));
    let pm = points[m - 1];
    pieces.push((pm, [pm[0] + reach * last[0], pm[1] + reach * last[1]]));
    let mut crossings = 0;
    let mut distance = f64::MAX;
    for &(a, b) in &pieces {
        let ab = sub(b, a);
        let len2 = ab[0] * ab[0] + ab[1] * ab[1];
        let t = ((x[0] - a[0]) * ab[0] + (x[1] - a[1]) * ab[1]) / len2;
        let t = t.clamp(0.0, 1.0);
        distance = distance.min((x[0] - a[0] - t * ab[0]).hypot(x[1] - a[1] - t * ab[1]));
        // The ray x + s v (s > 0) meets the piece a + u ab (0 <= u < 1).
        let den = cross(v, ab);
        if den != 0.0 {
            let ax = sub(a, x);
            let s = cross(ax, ab) / den;
            let u = cross(ax, v) / den;
            if s > 0.0 && (0.0..1.0).contains(&u) {
                crossings += 1;
            }
        }
    }
    if crossings % 2 == 1 {
        distance
    } else {
        0.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The ray count agrees with the sides drawn by hand: a step (free above-left), points on
    /// both sides of every piece and past both ends.
    #[test]
    fn the_ray_count_tells_the_sides_of_a_polyline() {
        let step = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [2.0, 1.0]];
        let inside = [([1.2, 0.9], 0.1), ([5.0, 0.5], 0.5), ([-3.0, -0.25], 0.25)];
        for (x, depth) in inside {
            let got = polyline_depth(&step, x);
            assert!((got - depth).abs() < 1e-12, "{x:?}: {got}");
        }
        for x in [
            [0.8, 0.5],
            [0.5, 0.1],
            [-4.0, 0.3],
            [1.5, 1.2],
            [9.0, 3.0],
            [0.9, 1.1],
        ] {
            assert_eq!(polyline_depth(&step, x), 0.0, "{x:?}");
        }
    }
}
