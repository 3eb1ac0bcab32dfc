//! The curve of an obstacle as a scene writes it (`ShapeDef`: m, degrees) and its checks on
//! the way to the solver's shape (`to_shape`).

use serde::{Deserialize, Serialize};

use super::units::sized;
use crate::solver::Shape;

/// The curve of an obstacle (m, degrees).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub enum ShapeDef {
    /// The unbounded straight line through two points; free side to the left of `from` ->
    /// `to`.
    Line {
        /// A point.
        from: (f64, f64),
        /// A second point.
        to: (f64, f64),
    },
    /// Straight segments through the points, continued beyond both ends; free side to the
    /// left of the direction of travel.
    Polyline {
        /// The corners, at least two.
        points: Vec<(f64, f64)>,
    },
    /// A circle: a solid disk, or a hole with `hollow: true`.
    Circle {
        /// Centre.
        centre: (f64, f64),
        /// Radius.
        radius: f64,
        /// Whether the nodes stay inside (default false).
        #[serde(default)]
        hollow: bool,
    },
    /// The part of a circle from polar angle `from_deg` counter-clockwise to `to_deg`.
    Arc {
        /// Centre.
        centre: (f64, f64),
        /// Radius.
        radius: f64,
        /// Start angle (degrees).
        from_deg: f64,
        /// End angle (degrees).
        to_deg: f64,
        /// Whether the nodes stay inside (default false).
        #[serde(default)]
        hollow: bool,
    },
}

impl ShapeDef {
    /// The solver's shape, or what is wrong with this one.
    pub fn to_shape(&self) -> Result<Shape, String> {
        let pt = |p: (f64, f64)| [p.0, p.1];
        let finite = |v: &[f64]| v.iter().all(|&x| sized(x));
        match self {
            ShapeDef::Line { from, to } => {
                if !finite(&[from.0, from.1, to.0, to.1]) || from == to {
                    return Err(
                        "a line needs two different points, finite and below 1e100 in size".into(),
                    );
                }
                Ok(Shape::Line {
                    from: pt(*from),
                    to: pt(*to),
                })
            }
            ShapeDef::Polyline { points } => {
                let flat: Vec<f64> = points.iter().flat_map(|p| [p.0, p.1]).collect();
                if points.len() < 2 || !finite(&flat) {
                    return Err(
                        "a polyline needs at least two points, finite and below 1e100 in size"
                            .into(),
                    );
                }
                // Two points in a row closer than the round-off of their coordinates make a segment
                // with no direction; a segment that turns straight back makes a spike with no free
                // side.
                let scale = flat.iter().fold(0.0f64, |m, v| m.max(v.abs()));
                let seg = |k: usize| [points[k + 1].0 - points[k].0, points[k + 1].1 - points[k].1];
                let len = |d: [f64; 2]| d[0].hypot(d[1]);
                if let Some(k) = (0..points.len() - 1).find(|&k| len(seg(k)) <= 1e-12 * scale) {
                    return Err(format!(
                        "points {} and {} of the polyline are the same to round-off",
                        k + 1,
                        k + 2
                    ));
                }
                if let Some(k) = (1..points.len() - 1).find(|&k| {
                    let (a, b) = (seg(k - 1), seg(k));
                    let cross = a[0] * b[1] - a[1] * b[0];
                    let dot = a[0] * b[0] + a[1] * b[1];
                    dot < 0.0 && cross.abs() <= 1e-9 * len(a) * len(b)
                }) {
                    return Err(format!(
                        "the polyline folds straight back on itself at point {}",
                        k + 1
                    ));
                }
                Ok(Shape::Polyline {
                    points: points.iter().map(|&p| pt(p)).collect(),
                })
            }
            ShapeDef::Circle {
                centre,
                radius,
                hollow,
            } => {
                if !finite(&[centre.0, centre.1, *radius]) || *radius <= 0.0 {
                    return Err(
                        "a circle needs a centre and a positive radius, finite and below 1e100 in size"
                            .into(),
                    );
                }
                Ok(Shape::Circle {
                    centre: pt(*centre),
                    radius: *radius,
                    hollow: *hollow,
                })
            }
            ShapeDef::Arc {
                centre,
                radius,
                from_deg,
                to_deg,
                hollow,
            } => {
                let ok = finite(&[centre.0, centre.1, *radius, *from_deg, *to_deg]);
                if !ok || *radius <= 0.0 || (to_deg - from_deg).rem_euclid(360.0) == 0.0 {
                    return Err(
                        "an arc needs a centre, a positive radius and two different angles, finite and below 1e100 in size"
                            .into(),
                    );
                }
                Ok(Shape::Arc {
                    centre: pt(*centre),
                    radius: *radius,
                    from: from_deg.to_radians(),
                    to: to_deg.to_radians(),
                    hollow: *hollow,
                })
            }
        }
    }
}
