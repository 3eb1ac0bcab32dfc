//! The curve of a rigid obstacle and everything the solver asks of it, one arm for each
//! shape: the nearest point and signed gap the contact code works with (`gap`), the place along
//! the curve friction measures from (`place`), the depth the acceptance check measures (by a
//! ray count for a polyline, not by the nearest point, so that a bug in the gap cannot hide
//! itself: `depth_inside`, `clearance`, `depth_on_path`), the convex features that may pass
//! between two nodes (`convex_features`, `chord_through`) and the outline a figure draws.
//! A new shape is a new variant here, its format in `scene/shape.rs`, and its own geometry in
//! the audit (`audit/obstacles.rs`).

use serde::{Deserialize, Serialize};

use super::curves::{
    angle_past, circle_gap, cross, dot, left, polyline_depth, polyline_gap, polyline_place,
    radial_depth, segment_distance, sub, within_angles, Gap,
};

/// The curve of a rigid obstacle, in the scene's coordinates. Each shape has a free side, where
/// the nodes stay, and a solid side they may not enter.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum Shape {
    /// The straight line through `from` and `to`, unbounded; free side to the left of the
    /// direction from `from` to `to` (a floor drawn left to right is free above).
    Line {
        /// A point of the line (m).
        from: [f64; 2],
        /// A second point of the line (m).
        to: [f64; 2],
    },
    /// The chain of straight segments through `points`, continued beyond its first and last
    /// point along its end segments, so that it divides the plane in two; free side to the
    /// left of the direction of travel.
    Polyline {
        /// The corners, at least two (m).
        points: Vec<[f64; 2]>,
    },
    /// A circle: a solid disk (nodes stay outside) or, `hollow`, a hole (nodes stay inside).
    Circle {
        /// Centre (m).
        centre: [f64; 2],
        /// Radius (m).
        radius: f64,
        /// Whether the nodes stay inside.
        hollow: bool,
    },
    /// The part of a circle between the polar angles `from` and `to` (rad, counter-clockwise
    /// from `from`): a node touches it only while its polar angle about the centre lies in
    /// that range; there, it is a disk or a hole as for `Circle`.
    Arc {
        /// Centre (m).
        centre: [f64; 2],
        /// Radius (m).
        radius: f64,
        /// Start angle (rad).
        from: f64,
        /// End angle (rad), reached counter-clockwise from `from`.
        to: f64,
        /// Whether the nodes stay inside.
        hollow: bool,
    },
}

impl Shape {
    /// The shape moved by `by` (m).
    pub fn translated(&self, by: [f64; 2]) -> Shape {
        let mv = |p: &mut [f64; 2]| *p = [p[0] + by[0], p[1] + by[1]];
        let mut moved = self.clone();
        match &mut moved {
            Shape::Line { from, to } => {
                mv(from);
                mv(to);
            }
            Shape::Polyline { points } => points.iter_mut().for_each(mv),
            Shape::Circle { centre, .. } | Shape::Arc { centre, .. } => mv(centre),
        }
        moved
    }

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

/// Points along a path at which a polyline's depth is looked at (`Shape::depth_on_path`).
const PATH_SAMPLES: usize = 32;

/// Points on a full circle's outline (`Shape::outline`).
const CIRCLE_POINTS: usize = 128;

impl Shape {
    /// How far inside the shape point `x` lies (m; 0 or less where it is free).
    pub fn depth_inside(&self, x: [f64; 2]) -> f64 {
        match self {
            Shape::Line { from, to } => {
                let t = sub(*to, *from);
                -cross(t, sub(x, *from)) / t[0].hypot(t[1])
            }
            Shape::Circle {
                centre,
                radius,
                hollow,
            } => radial_depth(*centre, *radius, *hollow, x),
            Shape::Arc {
                centre,
                radius,
                from,
                to,
                hollow,
            } => {
                if within_angles(*centre, *from, *to, x) {
                    radial_depth(*centre, *radius, *hollow, x)
                } else {
                    0.0
                }
            }
            Shape::Polyline { points } => polyline_depth(points, x),
        }
    }

    /// How far outside the shape point `x` lies (m; 0 or less where it is inside or on it):
    /// the distance to the curve on the free side (an arc's nodes outside its angles are
    /// clear).
    pub fn clearance(&self, x: [f64; 2]) -> f64 {
        match self {
            Shape::Arc {
                centre, from, to, ..
            } if !within_angles(*centre, *from, *to, x) => f64::INFINITY,
            Shape::Line { .. } | Shape::Circle { .. } | Shape::Arc { .. } => -self.depth_inside(x),
            Shape::Polyline { points } => {
                if polyline_depth(points, x) > 0.0 {
                    return 0.0;
                }
                (points.windows(2))
                    .map(|w| segment_distance(w[0], w[1], x))
                    .fold(f64::INFINITY, f64::min)
            }
        }
    }

    /// How deep inside the shape the straight path from `a` to `b` runs: about a circle or an
    /// arc, the radius less the path's distance from the centre where the nearest point lies
    /// within the path (and, for an arc, within its angles); for a polyline, the deepest of
    /// points along the path; a line's solid side is a half-plane, which a straight path
    /// between free ends cannot enter.
    pub fn depth_on_path(&self, a: [f64; 2], b: [f64; 2]) -> f64 {
        match self {
            Shape::Line { .. } => 0.0,
            Shape::Circle { hollow: true, .. } | Shape::Arc { hollow: true, .. } => 0.0,
            Shape::Circle { centre, .. } | Shape::Arc { centre, .. } => {
                let ab = sub(b, a);
                let len2 = ab[0] * ab[0] + ab[1] * ab[1];
                if len2 == 0.0 {
                    return 0.0;
                }
                let t = (((centre[0] - a[0]) * ab[0] + (centre[1] - a[1]) * ab[1]) / len2)
                    .clamp(0.0, 1.0);
                self.depth_inside([a[0] + t * ab[0], a[1] + t * ab[1]])
            }
            Shape::Polyline { .. } => (1..PATH_SAMPLES)
                .map(|k| {
                    let t = k as f64 / PATH_SAMPLES as f64;
                    self.depth_inside([a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])])
                })
                .fold(0.0, f64::max),
        }
    }

    /// The largest coordinate of the shape moved by `t`, plus its radius (m; at least the
    /// smallest positive double): the size its coordinates' round-off scales with.
    pub fn scale(&self, t: [f64; 2]) -> f64 {
        let big = |p: &[f64; 2]| (p[0] + t[0]).abs().max((p[1] + t[1]).abs());
        match self {
            Shape::Line { from, to } => big(from).max(big(to)),
            Shape::Polyline { points } => points.iter().map(big).fold(0.0, f64::max),
            Shape::Circle { centre, radius, .. } | Shape::Arc { centre, radius, .. } => {
                big(centre) + radius
            }
        }
        .max(f64::MIN_POSITIVE)
    }

    /// The convex features of the shape at rest, which fit between two nodes: the centre of a
    /// circle or arc that nodes stay out of, each corner of a polyline that juts into the free
    /// side.
    pub fn convex_features(&self) -> Vec<[f64; 2]> {
        match self {
            Shape::Circle {
                centre,
                hollow: false,
                ..
            }
            | Shape::Arc {
                centre,
                hollow: false,
                ..
            } => vec![*centre],
            Shape::Polyline { .. } => self.convex_corners(),
            _ => Vec::new(),
        }
    }

    /// The corners of a polyline where it turns right (juts into the free side); none for any
    /// other shape.
    pub fn convex_corners(&self) -> Vec<[f64; 2]> {
        match self {
            Shape::Polyline { points } => (points.windows(3))
                .filter(|w| cross(sub(w[1], w[0]), sub(w[2], w[1])) < 0.0)
                .map(|w| w[1])
                .collect(),
            _ => Vec::new(),
        }
    }

    /// The centre and radius of a solid circle (a disk nodes stay out of); `None` for any
    /// other shape.
    pub fn disk(&self) -> Option<([f64; 2], f64)> {
        match self {
            Shape::Circle {
                centre,
                radius,
                hollow: false,
            } => Some((*centre, *radius)),
            _ => None,
        }
    }

    /// The centre, radius and angles (rad, counter-clockwise from the first to the second) of
    /// a solid arc (the part of a disk's rim nodes stay out of within those angles); `None` for
    /// any other shape.
    pub fn solid_arc(&self) -> Option<([f64; 2], f64, [f64; 2])> {
        match self {
            Shape::Arc {
                centre,
                radius,
                from,
                to,
                hollow: false,
            } => Some((*centre, *radius, [*from, *to])),
            _ => None,
        }
    }

    /// How deep the straight segment from `p` to `q` (an element's chord at rest) runs into a
    /// solid circle between its two ends, both clear of it (by more than 1e-9 of the radius);
    /// `None` where it does not, or for any other shape. Ends resting on the disk (a band laid
    /// round a drum) touch it where contact acts: their chords dip inside by the sagitta, as
    /// they must.
    pub fn chord_through(&self, p: [f64; 2], q: [f64; 2]) -> Option<f64> {
        let Shape::Circle {
            centre,
            radius,
            hollow: false,
        } = *self
        else {
            return None;
        };
        let (dx, dy) = (q[0] - p[0], q[1] - p[1]);
        let l2 = dx * dx + dy * dy;
        let t = (((centre[0] - p[0]) * dx + (centre[1] - p[1]) * dy) / l2).clamp(0.0, 1.0);
        let (cx, cy) = (p[0] + t * dx - centre[0], p[1] + t * dy - centre[1]);
        let depth = radius - cx.hypot(cy);
        let clear =
            |x: [f64; 2]| (x[0] - centre[0]).hypot(x[1] - centre[1]) - radius > 1e-9 * radius;
        let through = clear(p) && clear(q) && t > 0.0 && t < 1.0;
        (through && depth > 1e-9 * radius).then_some(depth)
    }

    /// The outline to draw, a polyline: lines and the ends of polylines reach `reach` beyond
    /// the circle of that radius about `centre` (a figure's box), circles and arcs are fine
    /// polygons.
    pub fn outline(&self, centre: [f64; 2], reach: f64) -> Vec<[f64; 2]> {
        // How far along a direction from point p the drawing goes: past the box by `reach`.
        let far = |p: [f64; 2]| (p[0] - centre[0]).hypot(p[1] - centre[1]) + reach;
        let ray = |p: [f64; 2], t: [f64; 2]| {
            let l = t[0].hypot(t[1]);
            let k = far(p) / l;
            [p[0] + k * t[0], p[1] + k * t[1]]
        };
        let arc = |c: [f64; 2], radius: f64, from: f64, sweep: f64| -> Vec<[f64; 2]> {
            let n = ((CIRCLE_POINTS as f64 * sweep / std::f64::consts::TAU).ceil() as usize).max(4);
            (0..=n)
                .map(|k| {
                    let a = from + sweep * k as f64 / n as f64;
                    [c[0] + radius * a.cos(), c[1] + radius * a.sin()]
                })
                .collect()
        };
        match self {
            Shape::Line { from, to } => {
                // Both ways from the point of the line nearest the centre.
                let d = sub(*to, *from);
                let t = dot(sub(centre, *from), d) / dot(d, d);
                let foot = [from[0] + t * d[0], from[1] + t * d[1]];
                vec![ray(foot, [-d[0], -d[1]]), ray(foot, d)]
            }
            Shape::Polyline { points } => {
                let m = points.len();
                let first = sub(points[0], points[1]);
                let last = sub(points[m - 1], points[m - 2]);
                let mut line = vec![ray(points[0], first)];
                line.extend_from_slice(points);
                line.push(ray(points[m - 1], last));
                line
            }
            Shape::Circle { centre, radius, .. } => {
                arc(*centre, *radius, 0.0, std::f64::consts::TAU)
            }
            Shape::Arc {
                centre,
                radius,
                from,
                to,
                ..
            } => arc(
                *centre,
                *radius,
                *from,
                (to - from).rem_euclid(std::f64::consts::TAU),
            ),
        }
    }
}
