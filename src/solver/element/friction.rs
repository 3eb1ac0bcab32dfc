//! Coulomb friction at the contacts of a contact element: the friction force of one contact
//! in stick or in slip, and its nodal forces and exact tangent, added to a frictionless
//! `ContactResponse`.
//!
//! The tangential coordinate of a contact is its place along the beam's body measured in
//! undeformed length, s = s_i + xi Ls (xi = li / l from the current chord, Ls = s_j - s_i =
//! +-L0): the node's material point on the beam. While it sticks, a spring of stiffness kt holds
//! the node to the stick point s0: f = kt (s - s0). While it slips in direction sigma,
//! f = sigma mu N l / L0. f is work-conjugate to s, so the nodal forces are f grad s and the
//! tangent grad s (x) grad f + f hess s: unsymmetric where the contact slips, since f then
//! follows the normal force N. The force on the contact node along the chord is -f Ls / l, so
//! slip holds the physical tangential force at mu N exactly. Which of the two a contact is in
//! is decided at each converged pass from the trial force kt (s - s0) ([`Traction::mode`], the
//! return mapping), and held through the pass, so that Newton's convergence stays quadratic.

use nalgebra::{DMatrix, DVector, Matrix2, Vector2};

use super::contact_element::ContactResponse;
use super::obstacle::Gap;

/// The friction of one contact, for one evaluation of its contact element.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Grip {
    /// Friction coefficient mu (> 0).
    pub mu: f64,
    /// Stiffness kt of the spring that holds a sticking node to its stick point (N/m).
    pub stiffness: f64,
    /// The stick point s0 at the start of the increment, as a fraction of this element from
    /// end i (outside [0, 1] where the contact came from a neighbouring element).
    pub stick: f64,
    /// Ls: the body length from end i to end j (+L0, or -L0 where the element runs against
    /// its body's direction).
    pub span: f64,
    /// The side of the beam the node rests on (+1 or -1 along the chord normal).
    pub side: f64,
    /// `Some(sigma)`: the contact slips with s - s0 of sign sigma; `None`: it sticks.
    pub slip: Option<f64>,
    /// Half the thickness of the beam touched (m): the beam's part of a contact at a distance
    /// from the axes (`rim/friction.rs`); 0 on the axis.
    pub face: f64,
    /// The rim's roll at the stick point (m; `rim::friction::roll`): its radius times the
    /// node's rotation relative to the beam's surface normal; 0 on the axis.
    pub roll: f64,
    /// The contact node's rotation (rad, since rest), where it has one and its rim turns with
    /// it; `None`: its rim does not turn. Set by the assembly.
    pub turn: Option<f64>,
    /// The rim's roll since the stick point (m along the surface) and the slip it adds (m of
    /// body), set by the element (`rim/friction.rs`); 0 on the axis.
    pub rolled: (f64, f64),
}

/// The frictional state of one contact, from the return mapping.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Traction {
    /// f, the force conjugate to the tangential coordinate s (N).
    pub force: f64,
    /// s - s0: how far the node's material point lies from the stick point (m of body).
    pub slip: f64,
    /// Whether the contact slips (|f| at the Coulomb limit).
    pub slipping: bool,
    /// The trial force kt (s - s0) of the stick spring (N).
    pub trial: f64,
    /// The Coulomb limit of |f|: mu N l / L0 (N).
    pub limit: f64,
    /// The tangential force on the contact node along the chord, from i to j (N).
    pub tangential: f64,
    /// The normal pressure N (N, compressive positive).
    pub normal: f64,
    /// The part of `slip` a rim's roll makes (m of the coordinate: of body for a beam, along
    /// the curve for an obstacle); 0 on the axis.
    pub rolled: f64,
    /// The rim's roll since the stick point (m along the surface): its radius times the
    /// node's rotation relative to the normal of the obstacle or of the beam's surface.
    pub rim_roll: f64,
}

/// The gradient of xi = (a . d) / (d . d), with a = x_c - x_i and d = x_j - x_i, over the
/// dofs (u_i, v_i, phi_i, u_j, v_j, phi_j, u_c1, v_c1, ...) for contact `m`.
pub(super) fn xi_gradient(a: Vector2<f64>, d: Vector2<f64>, nd: usize, m: usize) -> DVector<f64> {
    let l2 = d.dot(&d);
    let xi = a.dot(&d) / l2;
    let ga = d / l2;
    let gd = (a - d * (2.0 * xi)) / l2;
    let mut g = DVector::zeros(nd);
    for k in 0..2 {
        g[k] = -ga[k] - gd[k];
        g[3 + k] = gd[k];
        g[6 + 2 * m + k] = ga[k];
    }
    g
}

/// The Hessian of xi over the same dofs.
pub(super) fn xi_hessian(a: Vector2<f64>, d: Vector2<f64>, nd: usize, m: usize) -> DMatrix<f64> {
    let l2 = d.dot(&d);
    let xi = a.dot(&d) / l2;
    let gd = (a - d * (2.0 * xi)) / l2;
    let h_ad = Matrix2::identity() / l2 - d * d.transpose() * (2.0 / (l2 * l2));
    let h_dd = -(d * gd.transpose() + gd * d.transpose()) * (2.0 / l2)
        - Matrix2::identity() * (2.0 * xi / l2);
    // a = x_c - x_i, d = x_j - x_i: (offset, sign) of each.
    let pa = [(0, -1.0), (6 + 2 * m, 1.0)];
    let pd = [(0, -1.0), (3, 1.0)];
    let mut h = DMatrix::zeros(nd, nd);
    for &(p, cp) in &pa {
        for &(q, cq) in &pd {
            for r in 0..2 {
                for c in 0..2 {
                    h[(p + r, q + c)] += cp * cq * h_ad[(r, c)];
                    h[(q + c, p + r)] += cp * cq * h_ad[(r, c)];
                }
            }
        }
    }
    for &(p, cp) in &pd {
        for &(q, cq) in &pd {
            for r in 0..2 {
                for c in 0..2 {
                    h[(p + r, q + c)] += cp * cq * h_dd[(r, c)];
                }
            }
        }
    }
    h
}

/// Add the friction of the contacts with a `Grip` (one entry per contact node of `r`, `None`
/// for a frictionless one) to the frictionless response `r` of a contact element of undeformed
/// length `length`, with its ends at `ends` and its contact nodes at `xc` (the positions `r`
/// was evaluated at), given the gradient of each contact's Yc (`normal_gradients`, read from
/// the frictionless tangent). Returns the traction of each contact.
pub fn add_friction(
    r: &mut ContactResponse,
    length: f64,
    ends: ([f64; 2], [f64; 2]),
    xc: &[[f64; 2]],
    grips: &[Option<Grip>],
    normal_gradients: &[Option<DVector<f64>>],
) -> Vec<Option<Traction>> {
    let nd = r.nodal.len();
    let xi_pos = Vector2::new(ends.0[0], ends.0[1]);
    let d = Vector2::new(ends.1[0], ends.1[1]) - xi_pos;
    let l = d.norm();
    let e = d / l;
    let mut grad_l = DVector::zeros(nd);
    for k in 0..2 {
        grad_l[k] = -e[k];
        grad_l[3 + k] = e[k];
    }
    let mut out = Vec::with_capacity(xc.len());
    for (m, grip) in grips.iter().enumerate() {
        let Some(g) = grip else {
            out.push(None);
            continue;
        };
        let a = Vector2::new(xc[m][0], xc[m][1]) - xi_pos;
        let xi = a.dot(&d) / d.dot(&d);
        let slip = g.span * (xi - g.stick) + g.rolled.1;
        let normal = -g.side * r.forces[3 + m];
        // Not cut at zero: an iterate that pulls the contact keeps a smooth force (the pass
        // releases a tensile contact before its friction is judged).
        let limit = g.mu * normal * l / length;
        let trial = g.stiffness * slip;
        let slipping = g.slip.is_some();
        let sign = g.slip.unwrap_or(0.0);
        let force = if slipping { sign * limit } else { trial };
        let grad = xi_gradient(a, d, nd, m);
        r.nodal.axpy(force * g.span, &grad, 1.0);
        if let Some(k) = r.tangent.as_mut() {
            let grad_f = if !slipping {
                &grad * (g.stiffness * g.span)
            } else {
                let grad_n = normal_gradients[m].as_ref().expect("tangent present") * -g.side;
                (grad_n * l + &grad_l * normal) * (sign * g.mu / length)
            };
            *k += (&grad * g.span) * grad_f.transpose();
            if force != 0.0 {
                *k += xi_hessian(a, d, nd, m) * (force * g.span);
            }
        }
        out.push(Some(Traction {
            force,
            slip,
            slipping,
            trial,
            limit,
            tangential: -force * g.span / l,
            normal,
            rolled: g.rolled.1,
            rim_roll: g.rolled.0,
        }));
    }
    out
}

/// The friction of a node resting on a rigid obstacle, for one evaluation.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ObstacleGrip {
    /// Friction coefficient mu (> 0).
    pub mu: f64,
    /// Stiffness kt of the spring that holds a sticking node to its stick point (N/m).
    pub stiffness: f64,
    /// The stick point s0: a place along the obstacle (`Shape::place`, m).
    pub stick: f64,
    /// `Some(sigma)`: the contact slips with s - s0 of sign sigma; `None`: it sticks.
    pub slip: Option<f64>,
    /// The length after which places repeat (`Shape::period`), if any.
    pub period: Option<f64>,
    /// How far the node's face stands off its axis (m; its clearance, 0 on the axis): the
    /// radius of the rim that rolls on the obstacle.
    pub reach: f64,
    /// The rim's turn at the stick point (rad): the node's rotation less the angle of the
    /// obstacle's normal, `phi - theta_n`; 0 on the axis.
    pub roll: f64,
}

/// The friction of a node at `place` along an obstacle (`Shape::place`), its face at gap `gap`
/// (the node's own distance from the curve less `grip.reach`), with rotation `phi` (rad; 0 for
/// a node without a rotation, whose rim does not turn) and normal force `normal` = multiplier -
/// `penalty` g. The tangential coordinate is the slip of the rim's point that touches,
/// s = place + r (phi - theta_n) (r = `grip.reach`, theta_n the angle of the normal): a rim
/// that rolls without slipping keeps s, on a flat face, about a disk and round a corner alike.
/// As for a beam, f = kt (s - s0) in stick and sigma mu N in slip. The gradient of s over the
/// node's position is (1 - g k) t (k the curvature of the gap's level line at the node,
/// t = (n_y, -n_x)) and r over its rotation; its Hessian is -(1 - g k) k (n t^T + t n^T), the
/// level line's curvature varying as -k^2 along the normal. Returns the traction and the
/// internal forces and tangent over (u, v) of the node, (u, v) of the obstacle's pilot (the
/// place depends on their difference), then the node's rotation.
pub fn obstacle_friction(
    gap: &Gap,
    (place, phi): (f64, f64),
    (normal, penalty): (f64, f64),
    grip: &ObstacleGrip,
) -> (Traction, [f64; 5], [[f64; 5]; 5]) {
    let n = gap.n;
    let t = [n[1], -n[0]];
    let a = 1.0 - gap.g * gap.curvature;
    let grad = [a * t[0], a * t[1], -a * t[0], -a * t[1], grip.reach];
    let mut slip = place - grip.stick;
    if let Some(p) = grip.period {
        slip -= p * (slip / p).round();
    }
    let rolled = if grip.reach > 0.0 {
        let turn = phi - n[1].atan2(n[0]) - grip.roll;
        let tau = std::f64::consts::TAU;
        grip.reach * (turn - tau * (turn / tau).round())
    } else {
        0.0
    };
    slip += rolled;
    let limit = grip.mu * normal;
    let trial = grip.stiffness * slip;
    let sign = grip.slip.unwrap_or(0.0);
    let force = if grip.slip.is_some() {
        sign * limit
    } else {
        trial
    };
    let grad_f = match grip.slip {
        None => grad.map(|g| grip.stiffness * g),
        Some(_) => {
            let dn = -sign * grip.mu * penalty;
            [dn * n[0], dn * n[1], -dn * n[0], -dn * n[1], 0.0]
        }
    };
    let curl = -a * gap.curvature * force;
    let mut k = [[0.0; 5]; 5];
    for (p, row) in k.iter_mut().enumerate() {
        for (q, v) in row.iter_mut().enumerate() {
            *v = grad[p] * grad_f[q];
        }
    }
    for p in 0..2 {
        for q in 0..2 {
            let v = curl * (n[p] * t[q] + t[p] * n[q]);
            k[p][q] += v;
            k[p][2 + q] -= v;
            k[2 + p][q] -= v;
            k[2 + p][2 + q] += v;
        }
    }
    let nodal = grad.map(|g| force * g);
    let traction = Traction {
        force,
        slip,
        slipping: grip.slip.is_some(),
        trial,
        limit,
        tangential: -force * a,
        normal,
        rolled,
        rim_roll: rolled,
    };
    (traction, nodal, k)
}

/// How far past the Coulomb limit a trial force may lie, relative to the limit, and still
/// stick (and how far below it a slipping contact's may lie and still slip): round-off of the
/// converged state, far below the solver's tolerance on the forces.
pub const COULOMB_TOLERANCE: f64 = 1e-9;

/// How many units in the last place of a stick point its recomputation may move it: a
/// sticking node's place is found again from its position and the body's, a few roundings.
pub const STICK_ROUNDOFF_ULPS: f64 = 4.0;

impl Traction {
    /// The return mapping: the mode (`None`: stick, `Some(sigma)`: slip in direction sigma)
    /// this contact's trial force asks for, given the mode `now` it was evaluated in. A slip
    /// goes on while the trial force stays beyond the limit in its direction; otherwise the
    /// contact sticks if the trial force is within the limit, and slips its way if not. With
    /// `cautious` (the modes have come back within an attempt), a slip that turns back sticks
    /// first instead, as the spring unloads through zero: no contact can then swing between
    /// the two directions; and a slip goes on while its trial force lies within `slack` (N,
    /// the state's unbalanced force: what the forces are known to) of the limit, so that a
    /// contact whose trial force sits on the limit to within that does not swing between
    /// stick and slip. Slipping, its friction force is the limit itself: the law holds.
    pub fn mode(&self, now: Option<f64>, cautious: bool, slack: f64) -> Option<f64> {
        let (trial, limit) = (self.trial, self.limit);
        let sign = if trial < 0.0 { -1.0 } else { 1.0 };
        let slack = if cautious { slack } else { 0.0 };
        match now {
            Some(sigma) if sigma * trial >= limit * (1.0 - COULOMB_TOLERANCE) - slack => {
                Some(sigma)
            }
            Some(_) if cautious => None,
            _ if trial.abs() <= limit * (1.0 + COULOMB_TOLERANCE) => None,
            _ => Some(sign),
        }
    }
}
