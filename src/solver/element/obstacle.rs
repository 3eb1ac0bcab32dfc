//! The contact of a node with a rigid obstacle: the force and tangent of an active contact
//! under the augmented Lagrangian (`obstacle_response`), given where the node lies against the
//! obstacle's exact curve ([`Shape::gap`](crate::solver::model::Shape::gap): the signed distance, its gradient and the curvature
//! of its level line; `model/shape.rs`). The force pushes the node out along the normal,
//! `F_N = multiplier - penalty g`; at convergence the multiplier carries it and the gap closes.

pub use crate::solver::model::Gap;

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
    use crate::solver::model::Shape;

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
            let g = shape.gap([x[0] - t[0], x[1] - t[1]]).unwrap();
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
