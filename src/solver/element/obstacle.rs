//! The contact of a node with a rigid obstacle: where the node lies against the obstacle's
//! exact curve ([`Shape::gap`]: the signed distance, its gradient and the curvature of its
//! level line), and the force and tangent of an active contact under the augmented
//! Lagrangian (`obstacle_response`). The force pushes the node out along the normal,
//! `F_N = multiplier - penalty g`; at convergence the multiplier carries it and the gap closes.

use crate::solver::model::Shape;

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

fn sub(a: [f64; 2], b: [f64; 2]) -> [f64; 2] {
    [a[0] - b[0], a[1] - b[1]]
}

fn dot(a: [f64; 2], b: [f64; 2]) -> f64 {
    a[0] * b[0] + a[1] * b[1]
}

fn cross(a: [f64; 2], b: [f64; 2]) -> f64 {
    a[0] * b[1] - a[1] * b[0]
}

/// The unit left normal of the direction `t` (not zero).
fn left(t: [f64; 2]) -> [f64; 2] {
    let l = t[0].hypot(t[1]);
    [-t[1] / l, t[0] / l]
}

/// Where the polar angle `theta` lies past `from`, counter-clockwise, in [0, 2 pi).
fn angle_past(theta: f64, from: f64) -> f64 {
    (theta - from).rem_euclid(std::f64::consts::TAU)
}

impl Shape {
    /// Where point `x` lies against the shape, or `None` where the shape does not reach it
    /// (an arc, outside its angular range).
    pub fn gap(&self, x: [f64; 2]) -> Option<Gap> {
        self.gap_at(x, [0.0, 0.0])
    }

    /// `gap` at the point `x0 + w`: a node at rest at `x0` moved by `w`. About a circle, the
    /// gap is worked out so that its round-off scales with `w`, not with the radius
    /// (`circle_gap`): a penalty of the elements' axial stiffness would otherwise turn the
    /// round-off of a large radius into forces above the tolerance.
    pub fn gap_at(&self, x0: [f64; 2], w: [f64; 2]) -> Option<Gap> {
        let x = [x0[0] + w[0], x0[1] + w[1]];
        match self {
            Shape::Line { from, to } => {
                let n = left(sub(*to, *from));
                let g = dot(sub(x, *from), n);
                Some(Gap {
                    g,
                    n,
                    curvature: 0.0,
                    point: [x[0] - g * n[0], x[1] - g * n[1]],
                })
            }
            Shape::Polyline { points } => Some(polyline_gap(points, x)),
            Shape::Circle {
                centre,
                radius,
                hollow,
            } => Some(circle_gap(*centre, *radius, *hollow, x0, w)),
            Shape::Arc {
                centre,
                radius,
                from,
                to,
                hollow,
            } => {
                let r = sub(x, *centre);
                let past = angle_past(r[1].atan2(r[0]), *from);
                (past <= angle_past(*to, *from))
                    .then(|| circle_gap(*centre, *radius, *hollow, x0, w))
            }
        }
    }
}

impl Shape {
    /// The place of point `p` of the curve (at rest) along it (m): the length from a fixed
    /// point of the curve in the direction of the tangent `(n_y, -n_x)` (n the normal to the
    /// free side), so that a node's place s has the gradient `(1 - g curvature) t`: along a
    /// line from `from` towards `to`, along a polyline from its first point, about a disk
    /// clockwise and about a hole counter-clockwise from the polar angle 0 (an arc: from
    /// `from`).
    pub fn place(&self, p: [f64; 2]) -> f64 {
        match self {
            Shape::Line { from, to } => {
                let e = sub(*to, *from);
                dot(sub(p, *from), e) / e[0].hypot(e[1])
            }
            Shape::Polyline { points } => polyline_place(points, p),
            Shape::Circle {
                centre,
                radius,
                hollow,
            } => {
                let r = sub(p, *centre);
                let turn = if *hollow { 1.0 } else { -1.0 };
                turn * radius * r[1].atan2(r[0])
            }
            Shape::Arc {
                centre,
                radius,
                from,
                hollow,
                ..
            } => {
                let r = sub(p, *centre);
                let turn = if *hollow { 1.0 } else { -1.0 };
                turn * radius * angle_past(r[1].atan2(r[0]), *from)
            }
        }
    }

    /// The length after which places repeat (a circle's or an arc's circumference), if any.
    pub fn period(&self) -> Option<f64> {
        match self {
            Shape::Circle { radius, .. } | Shape::Arc { radius, .. } => {
                Some(std::f64::consts::TAU * radius)
            }
            _ => None,
        }
    }
}

/// [`Shape::place`] on a polyline: the length along it to the nearest segment's start, plus the
/// way along that segment (negative before the first point, beyond the last past it).
fn polyline_place(points: &[[f64; 2]], p: [f64; 2]) -> f64 {
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

/// [`Shape::gap`] of a circle (or, `hollow`, a hole) at `x0 + w`. With `r = x0 + w - c`,
/// `rho - R = (|r|^2 - R^2) / (rho + R)`, and `|r|^2 - R^2` is `|x0 - c|^2 - R^2` (from
/// `power_at_rest`) plus `2 (x0 - c) . w + w . w`, terms of the size of the motion: the gap
/// carries no round-off of the radius.
fn circle_gap(centre: [f64; 2], radius: f64, hollow: bool, x0: [f64; 2], w: [f64; 2]) -> Gap {
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

/// [`Shape::gap`] of a polyline continued beyond its ends along its end segments. The nearest
/// point decides: inside a segment, the side of that segment; at a corner, the side of the
/// bisector of the two segments' normals (which tells the sides of a corner apart).
fn polyline_gap(points: &[[f64; 2]], x: [f64; 2]) -> Gap {
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

/// The internal forces and tangent of one obstacle contact with gap `gap`, multiplier
/// `multiplier` (N) and penalty `penalty` (N/m): over (u, v) of the node, then (u, v) of the
/// obstacle's pilot node (the gap depends on their difference). The contact force on the
/// node is `F_N n` with `F_N = multiplier - penalty g`; its internal force is minus that, and
/// the tangent `penalty n n^T - multiplier curvature (I - n n^T)`: the derivative at a closed
/// gap, where `F_N` is the multiplier and where the augmented Lagrangian ends. (With `F_N`
/// itself, a node deep inside a curved obstacle during the iterations would bring a large
/// negative stiffness across the normal, and Newton would leave the solution.) Returns
/// (F_N, forces, tangent).
pub fn obstacle_response(
    gap: &Gap,
    multiplier: f64,
    penalty: f64,
) -> (f64, [f64; 4], [[f64; 4]; 4]) {
    let f = multiplier - penalty * gap.g;
    let n = gap.n;
    let r = [-f * n[0], -f * n[1]];
    let mut k2 = [[0.0; 2]; 2];
    for (a, row) in k2.iter_mut().enumerate() {
        for (b, k) in row.iter_mut().enumerate() {
            let id = if a == b { 1.0 } else { 0.0 };
            *k = penalty * n[a] * n[b] - multiplier * gap.curvature * (id - n[a] * n[b]);
        }
    }
    let mut k = [[0.0; 4]; 4];
    for a in 0..2 {
        for b in 0..2 {
            k[a][b] = k2[a][b];
            k[a][2 + b] = -k2[a][b];
            k[2 + a][b] = -k2[a][b];
            k[2 + a][2 + b] = k2[a][b];
        }
    }
    (f, [r[0], r[1], -r[0], -r[1]], k)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn shapes() -> Vec<Shape> {
        vec![
            Shape::Line {
                from: [0.0, -0.1],
                to: [1.0, 0.2],
            },
            Shape::Polyline {
                points: vec![[-1.0, 0.0], [0.0, 0.0], [0.5, 0.6], [1.5, 0.4]],
            },
            Shape::Circle {
                centre: [0.2, -0.9],
                radius: 0.7,
                hollow: false,
            },
            Shape::Arc {
                centre: [0.1, 1.2],
                radius: 1.6,
                from: 3.5,
                to: 6.0,
                hollow: true,
            },
        ]
    }

    /// The gap's normal and curvature are its derivatives: central differences of `g` (the
    /// gradient) and of the gradient (the Hessian `curvature (I - n n^T)`), at points on both
    /// sides of every shape, near corners included.
    #[test]
    fn the_normal_and_curvature_are_the_derivatives_of_the_gap() {
        let h = 1e-6;
        let points = [
            [0.3, 0.05],
            [0.2, -0.3],
            [0.62, 0.9],
            [0.1, 0.2],
            [0.75, 0.3],
        ];
        for shape in shapes() {
            for &x in &points {
                let Some(at) = shape.gap(x) else { continue };
                for c in 0..2 {
                    let mut p = x;
                    let mut m = x;
                    p[c] += h;
                    m[c] -= h;
                    let (gp, gm) = (shape.gap(p).unwrap(), shape.gap(m).unwrap());
                    let fd = (gp.g - gm.g) / (2.0 * h);
                    assert!((fd - at.n[c]).abs() < 1e-6, "{shape:?} {x:?}: dg/dx{c}");
                    for r in 0..2 {
                        let fd = (gp.n[r] - gm.n[r]) / (2.0 * h);
                        let id = if r == c { 1.0 } else { 0.0 };
                        let exact = at.curvature * (id - at.n[r] * at.n[c]);
                        assert!((fd - exact).abs() < 1e-5, "{shape:?} {x:?}: H{r}{c}");
                    }
                }
            }
        }
    }

    /// At a closed gap the tangent is the derivative of the internal forces (central
    /// differences over the node's and the pilot's positions), on a curved shape with a force.
    #[test]
    fn the_tangent_is_the_derivative_of_the_forces_at_a_closed_gap() {
        let shape = &shapes()[2];
        // A point of the circle (centre (0.2, -0.9), radius 0.7), the pilot moved off it.
        let pilot = [0.01, -0.02];
        let angle: f64 = 0.7;
        let x = [
            0.2 + 0.7 * angle.cos() + pilot[0],
            -0.9 + 0.7 * angle.sin() + pilot[1],
        ];
        let (lambda, k) = (3.0, 40.0);
        let at = |x: [f64; 2], t: [f64; 2]| {
            let g = shape.gap(sub(x, t)).unwrap();
            obstacle_response(&g, lambda, k)
        };
        let (_, _, tangent) = at(x, pilot);
        let h = 1e-7;
        for c in 0..4 {
            let (mut xp, mut xm, mut tp, mut tm) = (x, x, pilot, pilot);
            if c < 2 {
                xp[c] += h;
                xm[c] -= h;
            } else {
                tp[c - 2] += h;
                tm[c - 2] -= h;
            }
            let (_, fp, _) = at(xp, tp);
            let (_, fm, _) = at(xm, tm);
            for r in 0..4 {
                let fd = (fp[r] - fm[r]) / (2.0 * h);
                assert!((fd - tangent[r][c]).abs() < 1e-6, "K{r}{c}");
            }
        }
    }

    /// About a circle of radius 1e3 the gap of a node moved by 1e-3 is right to round-off of
    /// the motion, not of the radius: against the same gap in exact rational terms (the
    /// coordinates are binary fractions, so (rho^2 - R^2) is exact in i128 units of 2^-40).
    #[test]
    fn the_gap_about_a_large_circle_carries_no_round_off_of_the_radius() {
        let unit = (2.0f64).powi(-40);
        let c = [0.0, -1000.0];
        let r = 1000.0 - 3.0 * (2.0f64).powi(-20);
        let x0 = [0.5, 0.0];
        let w = [1.0 * (2.0f64).powi(-10), -5.0 * (2.0f64).powi(-12)];
        let shape = Shape::Circle {
            centre: c,
            radius: r,
            hollow: false,
        };
        let got = shape.gap_at(x0, w).unwrap().g;
        let q = |v: f64| (v / unit).round() as i128;
        let (rx, ry) = (q(x0[0] + w[0] - c[0]), q(x0[1] + w[1] - c[1]));
        let power = rx * rx + ry * ry - q(r) * q(r);
        let rho = ((rx * rx + ry * ry) as f64).sqrt() * unit;
        let exact = power as f64 * unit * unit / (rho + r);
        assert!((got - exact).abs() < 1e-15, "{got:e} against {exact:e}");
    }

    /// The sides: a floor drawn left to right is free above; a disk free outside, a hole
    /// inside; the polyline's corner between two segments takes the side of the bisector; an
    /// arc reaches only its angular range.
    #[test]
    fn the_free_side_is_where_the_shape_says() {
        let floor = Shape::Line {
            from: [0.0, 0.0],
            to: [1.0, 0.0],
        };
        assert_eq!(floor.gap([5.0, 0.25]).unwrap().g, 0.25);
        assert_eq!(floor.gap([-5.0, -0.5]).unwrap().g, -0.5);
        let step = Shape::Polyline {
            points: vec![[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [2.0, 1.0]],
        };
        // Below the step's upper floor, right of its riser: solid.
        assert!(step.gap([1.2, 0.9]).unwrap().g < 0.0);
        // Above the lower floor left of the riser: free, 0.2 from the riser.
        let g = step.gap([0.8, 0.5]).unwrap().g;
        assert!((g - 0.2).abs() < 1e-15, "{g}");
        // Beyond the last point, the last segment goes on.
        assert!((step.gap([9.0, 1.5]).unwrap().g - 0.5).abs() < 1e-15);
        // Off the outer corner at (1, 1): free, at distance sqrt(2) * 0.1.
        let g = step.gap([0.9, 1.1]).unwrap().g;
        assert!((g - 0.1 * 2f64.sqrt()).abs() < 1e-15, "{g}");
        let hole = Shape::Circle {
            centre: [0.0, 0.0],
            radius: 1.0,
            hollow: true,
        };
        assert!((hole.gap([0.0, 0.25]).unwrap().g - 0.75).abs() < 1e-15);
        let arc = Shape::Arc {
            centre: [0.0, 0.0],
            radius: 1.0,
            from: 0.0,
            to: 1.0,
            hollow: false,
        };
        assert!(arc.gap([0.0, -2.0]).is_none());
        assert!((arc.gap([2.0, 0.5]).unwrap().g - (4.25f64.sqrt() - 1.0)).abs() < 1e-15);
    }
}
