//! The audit's own geometry: where a point lies relative to a body at a recorded state. An
//! element's deflected shape is worked out here from its end nodes' positions and rotations
//! alone (the cubic of a beam loaded at its ends, with its shear flexibility), and a body is the
//! chain of its elements, ends and self-contact windows included. Nothing here calls the
//! solver's element or contact code.

use crate::history::Topology;

/// Gaps below this fraction of the element length are touching: they tell no side.
const TOUCH: f64 = 1e-9;
/// Round-off units of the largest coordinate that a gap may be off by.
const ROUNDOFF_ULPS: f64 = 64.0;

/// The bodies of a topology as the audit walks them: node slots in order along each body, and
/// each element's rest angle and shear parameter.
pub struct Chains {
    /// Per body: the slots (indices into a record's `nodes`) of its nodes in order.
    pub nodes: Vec<Vec<usize>>,
    /// Per body: the element index of each place along it.
    pub elements: Vec<Vec<usize>>,
    /// Per element: its chord angle at rest (rad).
    pub angle0: Vec<f64>,
    /// Per element: Phi = 12 E I / (G Ae l0^2) (0 for Bernoulli-Euler).
    pub shear: Vec<f64>,
    /// The slot of every node id.
    pub slot: std::collections::HashMap<u32, usize>,
    /// Round-off of a position (m): `ROUNDOFF_ULPS` units of the largest rest coordinate.
    pub roundoff: f64,
    /// Every node's place at rest, by slot.
    pub rest: Vec<[f64; 2]>,
}

/// Where a point lies relative to a body at one state.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Place {
    /// The place along the body (from 0) of the element it lies over.
    pub at: usize,
    /// Its signed gap from the element's deflected shape (m), positive to the left of the body's
    /// direction.
    pub gap: f64,
    /// Gaps up to this are touching (m).
    pub tol: f64,
    /// Whether the point lies beside the body: not off one of its ends, nor in the corner
    /// beyond an end node where a side means nothing.
    pub beside: bool,
    /// Whether it lies over the outer half of an end element (of the body, or of the part its
    /// self-contact window leaves): from there it can go round that end within one increment,
    /// which a straight path between two states cannot show.
    pub at_end: bool,
}

impl Chains {
    /// The chains of `topology`, whose nodes are in the order of `node_ids`.
    pub fn new(topology: &Topology, node_ids: &[u32]) -> Chains {
        let slot: std::collections::HashMap<u32, usize> = node_ids
            .iter()
            .enumerate()
            .map(|(k, &id)| (id, k))
            .collect();
        let rest: std::collections::HashMap<u32, [f64; 2]> =
            topology.nodes.iter().map(|n| (n.id, [n.x, n.y])).collect();
        let timoshenko = matches!(
            topology.formulation,
            Some(crate::solver::Formulation::Timoshenko)
        );
        let (mut angle0, mut shear) = (Vec::new(), Vec::new());
        for e in &topology.elements {
            let (a, b) = (rest[&e.i], rest[&e.j]);
            let l0 = (b[0] - a[0]).hypot(b[1] - a[1]);
            angle0.push((b[1] - a[1]).atan2(b[0] - a[0]));
            shear.push(if timoshenko && e.gae > 0.0 {
                12.0 * e.ei / (e.gae * l0 * l0)
            } else {
                0.0
            });
        }
        let size = rest
            .values()
            .fold(1.0f64, |m, p| m.max(p[0].abs()).max(p[1].abs()));
        Chains {
            nodes: (topology.bodies.iter())
                .map(|b| b.nodes.iter().map(|id| slot[id]).collect())
                .collect(),
            elements: topology.bodies.iter().map(|b| b.elements.clone()).collect(),
            angle0,
            shear,
            rest: node_ids
                .iter()
                .map(|id| rest.get(id).copied().unwrap_or([0.0; 2]))
                .collect(),
            slot,
            roundoff: ROUNDOFF_ULPS * f64::EPSILON * size,
        }
    }

    /// Where point `p` lies relative to body `b` in state `s` (every node's x, y, phi), over
    /// the places `allowed` accepts; `resting` lists the points resting on elements
    /// (element, point), which bend the element's shape; `sag(e)` is what the loads along
    /// element e may bend it beyond its end-loaded shape (m). None where no place is allowed.
    pub fn place(
        &self,
        s: &[[f64; 3]],
        p: [f64; 2],
        b: usize,
        allowed: &dyn Fn(usize) -> bool,
        resting: &[(usize, [f64; 2])],
        sag: &dyn Fn(usize) -> f64,
    ) -> Option<Place> {
        let chain = &self.nodes[b];
        let last = chain.len().checked_sub(2)?;
        // The closest chord (distance to the segment).
        let mut best: Option<(f64, usize, f64)> = None;
        for k in (0..=last).filter(|&k| allowed(k)) {
            let (a, c) = (s[chain[k]], s[chain[k + 1]]);
            let (dx, dy) = (c[0] - a[0], c[1] - a[1]);
            let l2 = dx * dx + dy * dy;
            let t = (((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / l2).clamp(0.0, 1.0);
            let dist = (p[0] - a[0] - t * dx).hypot(p[1] - a[1] - t * dy);
            if best.is_none_or(|bb| dist < bb.0) {
                best = Some((dist, k, t));
            }
        }
        let (dist, k, t) = best?;
        let e = self.elements[b][k];
        let (a, c) = (s[chain[k]], s[chain[k + 1]]);
        let (dx, dy) = (c[0] - a[0], c[1] - a[1]);
        let l = dx.hypot(dy);
        let chord = dy.atan2(dx);
        let wrap = |x: f64| {
            (x + std::f64::consts::PI).rem_euclid(std::f64::consts::TAU) - std::f64::consts::PI
        };
        let (ti, tj) = (
            wrap(a[2] + self.angle0[e] - chord),
            wrap(c[2] + self.angle0[e] - chord),
        );
        let off = (dx * (p[1] - a[1]) - dy * (p[0] - a[0])) / l;
        let on: Vec<[f64; 2]> = (resting.iter()).filter(|r| r.0 == e).map(|r| r.1).collect();
        let mut tol = TOUCH * l + self.roundoff + sag(e);
        let gap = if on.is_empty() {
            off - l * deflection(t, ti, tj, self.shear[e])
        } else {
            // Points resting on the element kink its shape there: the gap from the polyline
            // through them, within the sag of its pieces.
            tol += l * (ti.abs() + tj.abs()) / 4.0;
            off - polyline_offset(a, c, &on, t)
        };
        let prev = k > 0 && allowed(k - 1);
        let next = k < last && allowed(k + 1);
        let gap = if (t == 0.0 && prev) || (t == 1.0 && next) {
            // At an interior node: the side from the mean direction of its two chords.
            let j = if t == 0.0 { k } else { k + 1 };
            let (u, v, n) = (s[chain[j - 1]], s[chain[j + 1]], s[chain[j]]);
            let (ex, ey) = (v[0] - u[0], v[1] - u[1]);
            dist.copysign(ex * (p[1] - n[1]) - ey * (p[0] - n[0]))
        } else {
            gap
        };
        // Off an end of the allowed chain, or in the corner beyond its end node.
        let off_start = !prev && t * l <= gap.abs();
        let off_end = !next && (1.0 - t) * l <= gap.abs();
        Some(Place {
            at: k,
            gap,
            tol,
            beside: !(off_start || off_end),
            at_end: (!prev && t < 0.5) || (!next && t > 0.5),
        })
    }
}

/// The deflection (per element length, along the chord's left normal) at chord fraction `t` of
/// an element whose ends turn `ti` and `tj` from its chord, with shear parameter `phi`: the
/// exact shape of a Timoshenko beam loaded at its ends (the cubic Hermite shape at phi = 0).
pub fn deflection(t: f64, ti: f64, tj: f64, phi: f64) -> f64 {
    let c = 3.0 * (ti + tj) / (1.0 + phi);
    let b = tj - ti - c;
    (ti - c * phi / 6.0) * t + b * t * t / 2.0 + c * t * t * t / 3.0
}

/// The offset (m, along the chord's left normal) at chord fraction `t` of the polyline from
/// `a` through the points `on` to `c`.
fn polyline_offset(a: [f64; 3], c: [f64; 3], on: &[[f64; 2]], t: f64) -> f64 {
    let (dx, dy) = (c[0] - a[0], c[1] - a[1]);
    let l = dx.hypot(dy);
    let frame = |p: [f64; 2]| {
        let (px, py) = (p[0] - a[0], p[1] - a[1]);
        ((px * dx + py * dy) / (l * l), (dx * py - dy * px) / l)
    };
    let mut pts: Vec<(f64, f64)> = vec![(0.0, 0.0), (1.0, 0.0)];
    pts.extend(on.iter().map(|&p| frame(p)));
    pts.sort_by(|x, y| x.0.total_cmp(&y.0));
    for w in pts.windows(2) {
        if t >= w[0].0 && t <= w[1].0 {
            let span = w[1].0 - w[0].0;
            let f = if span > 0.0 { (t - w[0].0) / span } else { 0.0 };
            return w[0].1 + f * (w[1].1 - w[0].1);
        }
    }
    0.0
}

/// The place of a dof, by its name in a history ("u", "v", "phi"), in a record's node state
/// `[x, y, phi]`; `None` for any other name.
pub fn dof_place(name: &str) -> Option<usize> {
    match name {
        "u" => Some(0),
        "v" => Some(1),
        "phi" => Some(2),
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::deflection;

    /// The Hermite shape at phi = 0, and the Timoshenko shape's end slopes: w'(0) = ti - c phi/6
    /// differs from the section rotation by the shear strain.
    #[test]
    fn the_shape_meets_its_ends() {
        for phi in [0.0, 0.3, 3.0] {
            assert!(deflection(1.0, 0.01, -0.02, phi).abs() < 1e-15);
            assert_eq!(deflection(0.0, 0.01, -0.02, phi), 0.0);
        }
        let h = |t: f64, ti: f64, tj: f64| t * (1.0 - t) * (1.0 - t) * ti - t * t * (1.0 - t) * tj;
        for t in [0.1, 0.5, 0.77] {
            assert!((deflection(t, 0.01, 0.03, 0.0) - h(t, 0.01, 0.03)).abs() < 1e-15);
        }
    }
}
