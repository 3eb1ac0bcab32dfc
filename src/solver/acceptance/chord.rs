//! An element's chord at one state, and the swept test of a node passing through a chord
//! that moves over an increment: the geometry the crossing check works with.

use crate::solver::model::Model;
use crate::solver::report::NodeState;

/// A bound of the deflection of an element from its chord per radian of end rotation (relative
/// to the chord), in element lengths: the cubic with one end rotated peaks at 4/27; shear
/// deformation and loads inside the element are given the margin up to 1/4.
const DEFLECTION_PER_RADIAN: f64 = 0.25;

/// An element's chord at one state: end i, the vector i->j, its length and the tangent angles
/// at its ends.
#[derive(Clone, Copy, Debug)]
pub(super) struct Chord {
    pub(super) p: [f64; 2],
    pub(super) u: [f64; 2],
    pub(super) l: f64,
    /// The tangent angles at the ends: initial chord angle plus node rotation.
    pub(super) ends: [f64; 2],
}

impl Chord {
    pub(super) fn at(model: &Model, angle0: f64, e: usize, s: &[NodeState]) -> Chord {
        let (a, b) = (s[model.beams[e].i], s[model.beams[e].j]);
        let u = [b[0] - a[0], b[1] - a[1]];
        Chord {
            p: [a[0], a[1]],
            u,
            l: u[0].hypot(u[1]),
            ends: [a[2] + angle0, b[2] + angle0],
        }
    }

    /// A bound of the element's deflection from its chord: `DEFLECTION_PER_RADIAN` times the
    /// length per radian of end rotation relative to the chord.
    pub(super) fn bulge(&self) -> f64 {
        let angle = self.u[1].atan2(self.u[0]);
        // End rotations relative to the chord (wrapped to [-pi, pi)).
        let rel = |phi: f64| wrapped(phi - angle);
        DEFLECTION_PER_RADIAN * self.l * (rel(self.ends[0]).abs() + rel(self.ends[1]).abs())
    }

    /// The end rotations against the chord (rad, not wrapped).
    pub(super) fn turns(&self) -> [f64; 2] {
        let angle = self.u[1].atan2(self.u[0]);
        [self.ends[0] - angle, self.ends[1] - angle]
    }

    /// Whether node `n` of `model`, on side `side` of this chord (+1: left of i -> j), meets
    /// it within its reach (`Node::reach`): the way from the node to the chord, against the
    /// chord's normal on that side, lies within the node's angles (always, for a node whose
    /// contacts hold in every direction).
    pub(super) fn within_reach(&self, model: &Model, n: usize, side: f64) -> bool {
        (model.nodes[n].reach).is_none_or(|r| r.holds([side * self.u[1], -side * self.u[0]]))
    }

    /// (li/l, signed distance along the normal) of point `c`.
    pub(super) fn locate(&self, c: [f64; 2]) -> (f64, f64) {
        let v = [c[0] - self.p[0], c[1] - self.p[1]];
        let s = (v[0] * self.u[0] + v[1] * self.u[1]) / (self.l * self.l);
        let h = (self.u[0] * v[1] - self.u[1] * v[0]) / self.l;
        (s, h)
    }
}

/// An angle wrapped to [-pi, pi).
pub(super) fn wrapped(a: f64) -> f64 {
    (a + std::f64::consts::PI).rem_euclid(std::f64::consts::TAU) - std::f64::consts::PI
}

/// Whether point c, moving linearly from `c0` to `c1`, passes through the chord moving linearly
/// from `k0` to `k1` (between its ends) at some time in [0, 1]: the signed area
/// cross(u(t), c(t) - p(t)) is quadratic in t, and a root where c projects inside the chord is
/// a passage.
pub(super) fn swept_through(k0: Chord, k1: Chord, c0: [f64; 2], c1: [f64; 2]) -> bool {
    let sub = |a: [f64; 2], b: [f64; 2]| [a[0] - b[0], a[1] - b[1]];
    let cross = |a: [f64; 2], b: [f64; 2]| a[0] * b[1] - a[1] * b[0];
    let (u0, v0) = (k0.u, sub(c0, k0.p));
    let (du, dv) = (sub(k1.u, u0), sub(sub(c1, k1.p), v0));
    let (qa, qb, qc) = (cross(du, dv), cross(u0, dv) + cross(du, v0), cross(u0, v0));
    let mut roots = [f64::NAN; 2];
    if qa.abs() <= 1e-14 * (qb.abs() + qc.abs()) {
        if qb != 0.0 {
            roots[0] = -qc / qb;
        }
    } else {
        let disc = qb * qb - 4.0 * qa * qc;
        if disc >= 0.0 {
            // Without cancellation: q = -(qb + sign(qb) sqrt(disc)) / 2, roots q/qa and qc/q.
            let q = -0.5 * (qb + qb.signum() * disc.sqrt());
            roots = [q / qa, if q != 0.0 { qc / q } else { f64::NAN }];
        }
    }
    roots.iter().any(|&t| {
        (0.0..=1.0).contains(&t) && {
            let u = [u0[0] + t * du[0], u0[1] + t * du[1]];
            let v = [v0[0] + t * dv[0], v0[1] + t * dv[1]];
            let s = (u[0] * v[0] + u[1] * v[1]) / (u[0] * u[0] + u[1] * u[1]);
            (0.0..=1.0).contains(&s)
        }
    })
}
