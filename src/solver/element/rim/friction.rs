//! Friction between beams at a distance from the axes: a node whose rim (its radius, half its
//! own thickness) touches a beam's face (half the beam's thickness) at the point P between
//! them, `c - c' = rim nu` (`rim/mod.rs`: c' the point of the beam's axis the contact
//! element works on, nu the beam's surface normal there, `rim = side D` with D the contact
//! distance, the node's part r and the beam's part h).
//!
//! **What slips.** The contact element's tangential coordinate, s = s_i + xi' Ls at c', is the
//! place of c on the beam's parallel surface at D: the slip of the node's centre over that
//! surface. The faces meet at P, r short of c, so the rim's point at P slips by that and the
//! rim's turn relative to the beam's sections there: `rho = sign(Ls) side r (phi_c - a)`,
//! phi_c the node's rotation (0 for a node without one, whose rim does not turn) and a the
//! rotation of the beam's sections at the stick point (`(1 - xi_s) phi_i + xi_s phi_j`). rho
//! is a length along the surface; the slip gains it from the stick point's, taken into body
//! length by the parallel surface's stretch at c (`surface_stretch`). A rim rolling without
//! slipping keeps the slip, on a stretched and bent beam too: what sticks is its point that
//! touches.
//!
//! **The friction's moment.** The element's forces on c' are put on c unchanged
//! (`rim_outcome`), so the friction force F, along the chord, acts on the node at c and on the
//! beam at c': a couple `(c - c') x F` that P, where the faces touch, does not have. It is
//! taken out by moments: `h w` on the beam, shared between its end rotations as (1 - xi', xi'),
//! and `r w` on the node's rotation, w = nu x F (side times the arm's share): F then acts on
//! both at P. A node without a rotation takes no moment: what holds it (a rigid circle's
//! pilot) holds the moment too.
//!
//! The tangent is the exact derivative of these forces: the roll enters the stick force
//! kt (s + rho - s0), whose gradient adds `grad(force dir) (x) kt grad rho`, and the moments'
//! gradients follow from F's rows of the tangent, the normal's angle and xi' (through
//! `dc'/du`, `point_jacobian`).

use nalgebra::{DVector, Vector2};

use super::point::{point_jacobian, RimPoints};
use crate::solver::element::beam::Chord;
use crate::solver::element::contact_element::ContactOptions;
use crate::solver::element::contact_law::{contact_outcome, ContactOutcome, MAX_TURN};
use crate::solver::element::friction::{xi_gradient, Grip};

/// Whether the contact of `grip` at signed contact distance `rim` takes the moment of its
/// friction on its node's rotation: frictional, off the axis by more than the beam's face,
/// and a node with a rotation. Such a contact's element has that rotation among its dofs,
/// after every contact node's (u, v), in the order of the contacts.
pub fn turns_node(rim: f64, grip: &Option<Grip>) -> bool {
    grip.is_some_and(|g| rim != 0.0 && g.turn.is_some() && node_part(rim, g.face) > 0.0)
}

/// The node's part r of a contact distance `|rim|` whose beam's part is `face` (m).
fn node_part(rim: f64, face: f64) -> f64 {
    (rim.abs() - face).max(0.0)
}

/// The rim's roll `rho` (m) of a contact node with signed contact distance `rim`, the beam's
/// face `face` of it, the node's rotation `turn` (`None`: its rim does not turn), on an
/// element of body span `span` (`Grip::span`) with end rotations `phi`, its stick point at
/// fraction `stick` of it: `sign(span) side r (phi_c - a)`, a the rotation of the beam's
/// sections at the stick point, `(1 - stick) phi_i + stick phi_j`.
pub fn roll(
    phi: [f64; 2],
    (rim, face, turn): (f64, f64, Option<f64>),
    (span, stick): (f64, f64),
) -> f64 {
    let r = node_part(rim, face);
    let a = (1.0 - stick) * phi[0] + stick * phi[1];
    span.signum() * rim.signum() * r * (turn.unwrap_or(0.0) - a)
}

/// The body length per length along the surface tangent that the node's centre moves while
/// it keeps touching (a beam of chord `ch` and body span `span`, surface turn `t` at c',
/// signed contact distance `rim`, end rotations `dtheta` apart): c = c' + rim nu(t(xi')) moves
/// by `(l cos t - rim dtheta) dxi'` along tau, and the body coordinate by `|Ls| dxi'`. It takes
/// a rim's roll, a length along the surface, into the slip, a length of body.
fn surface_stretch(ch: &Chord, span: f64, (t, rim, dtheta): (f64, f64, f64)) -> f64 {
    span.abs() / (ch.l * t.cos() - rim * dtheta)
}

/// The gradient of the logarithm of `surface_stretch` over the element's `total` dofs, given
/// the gradient of the normal's angle `grad_a` (t = a - beta unless it is held at its bound).
fn stretch_log_gradient(
    ch: &Chord,
    (t, rim, dtheta): (f64, f64, f64),
    grad_a: &DVector<f64>,
    total: usize,
) -> DVector<f64> {
    let (st, ct) = t.sin_cos();
    let mut grad = DVector::zeros(total);
    for q in 0..2 {
        // l cos t - rim dtheta, its l part.
        grad[q] = -[ch.c, ch.s][q] * ct;
        grad[3 + q] = [ch.c, ch.s][q] * ct;
    }
    if t.abs() < MAX_TURN {
        grad.axpy(-ch.l * st, grad_a, 1.0);
        for (q, z) in ch.z.iter().enumerate() {
            grad[q] += ch.l * st * z * ch.inv_l;
        }
    }
    grad[2] += rim;
    grad[5] -= rim;
    grad / -(ch.l * ct - rim * dtheta)
}

/// `ContactOutcome` of `beam` for contact nodes at `xc` standing off the axis by the signed
/// distances `rims`, with the friction of `grips` acting where the faces touch (the module's
/// notes): the contact element on the axis points `points` (`rim_point`'s), the rims' rolls in
/// the slips, the friction's moments on the beam's end rotations and on the rotations of the
/// nodes that turn (`turns_node`), appended to the dofs.
pub fn rim_friction_outcome(
    at: &RimPoints<'_>,
    opts: ContactOptions,
    grips: &[Option<Grip>],
    with_tangent: bool,
) -> ContactOutcome {
    let (beam, ends, phi, points, rims) = (at.beam, at.ends, at.phi, at.points, at.rims);
    let ch = Chord::new(ends.0, ends.1, beam.alpha0, 0.5 * (phi[0] + phi[1]));
    let mut grips = grips.to_vec();
    let (ti, tj) = (phi[0] - ch.beta, phi[1] - ch.beta);
    for (m, grip) in grips.iter_mut().enumerate() {
        if let Some(g) = grip.as_mut().filter(|_| rims[m] != 0.0) {
            let rho = roll(phi, (rims[m], g.face, g.turn), (g.span, g.stick));
            // The rotations are unwrapped, and so is the roll.
            let turned = rho - g.roll;
            let stretch = surface_stretch(&ch, g.span, (points[m].2, rims[m], tj - ti));
            g.rolled = (turned, turned * stretch);
        }
    }
    let on: Vec<[f64; 2]> = points.iter().map(|p| p.0).collect();
    let mut out = contact_outcome(beam, ends, phi, &on, opts, &grips, with_tangent);
    let nd = out.response.nodal.len();
    let turning: Vec<usize> = (0..rims.len())
        .filter(|&m| turns_node(rims[m], &grips[m]))
        .collect();
    let total = nd + turning.len();
    let jacobian = with_tangent.then(|| point_jacobian(at));
    let r = &mut out.response;
    r.nodal = r.nodal.clone().resize_vertically(total, 0.0);
    if let (Some(k), Some(j)) = (r.tangent.take(), jacobian.as_ref()) {
        r.tangent = Some((k * j).resize(total, total, 0.0));
    }
    let (e, n) = (Vector2::new(ch.c, ch.s), Vector2::new(-ch.s, ch.c));
    let d = Vector2::new(ends.1[0] - ends.0[0], ends.1[1] - ends.0[1]);
    for m in 0..rims.len() {
        let (Some(g), Some(trac)) = (grips[m], out.friction[m]) else {
            continue;
        };
        if rims[m] == 0.0 {
            continue;
        }
        let (p, xi, t) = points[m];
        let side = rims[m].signum();
        let (q_beam, q_node) = (side * g.face, side * node_part(rims[m], g.face));
        let extra = turning.iter().position(|&k| k == m).map(|k| nd + k);
        let (st, ct) = t.sin_cos();
        let nu = n * ct - e * st;
        let tau = e * ct + n * st;
        let row = 6 + 2 * m;
        let fc = Vector2::new(-r.nodal[row], -r.nodal[row + 1]);
        let w = nu[0] * fc[1] - nu[1] * fc[0];
        if let (Some(k), Some(j)) = (r.tangent.as_mut(), jacobian.as_ref()) {
            // xi' and the normal's angle a over every dof, through dc'/du.
            let a_vec = Vector2::new(p[0] - ends.0[0], p[1] - ends.0[1]);
            let gx = xi_gradient(a_vec, d, nd, m);
            let mut grad_xi = DVector::zeros(total);
            grad_xi.rows_mut(0, nd).copy_from(&(j.transpose() * &gx));
            let mut grad_a = DVector::zeros(total);
            if t.abs() < MAX_TURN {
                grad_a.axpy(tj - ti, &grad_xi, 0.0);
                grad_a[2] += 1.0 - xi;
                grad_a[5] += xi;
            } else {
                for (q, z) in ch.z.iter().enumerate() {
                    grad_a[q] = z * ch.inv_l;
                }
            }
            if !trac.slipping && q_node != 0.0 {
                // The stick force kt (s + f (rho - rho0) - s0) follows the roll and the
                // stretch f of the surface it is measured on: along the friction's direction
                // in the forces, span grad xi' (rows of the ends and c).
                let mut grad_rho = DVector::zeros(total);
                grad_rho[2] = -(1.0 - g.stick) * g.span.signum() * q_node;
                grad_rho[5] = -g.stick * g.span.signum() * q_node;
                if let Some(x) = extra {
                    grad_rho[x] += g.span.signum() * q_node;
                }
                let rolled = g.rolled.1;
                let stretch = surface_stretch(&ch, g.span, (t, rims[m], tj - ti));
                let grad_log = stretch_log_gradient(&ch, (t, rims[m], tj - ti), &grad_a, total);
                let grad_rolled = grad_rho * stretch + grad_log * rolled;
                let mut dir = DVector::zeros(total);
                dir.rows_mut(0, nd).copy_from(&(&gx * g.span));
                *k += dir * (grad_rolled * g.stiffness).transpose();
            }
            let grad_fc_x = -k.row(row).transpose();
            let grad_fc_y = -k.row(row + 1).transpose();
            let lever = tau[0] * fc[1] - tau[1] * fc[0];
            let grad_w: DVector<f64> = -(&grad_a * lever) + grad_fc_y * nu[0] - grad_fc_x * nu[1];
            let mut add_row = |at: usize, v: DVector<f64>| {
                let mut rowv = k.row_mut(at);
                rowv += v.transpose();
            };
            add_row(2, (&grad_w * (1.0 - xi) - &grad_xi * w) * q_beam);
            add_row(5, (&grad_w * xi + &grad_xi * w) * q_beam);
            if let Some(x) = extra {
                add_row(x, &grad_w * q_node);
            }
        }
        r.nodal[2] += q_beam * w * (1.0 - xi);
        r.nodal[5] += q_beam * w * xi;
        if let Some(x) = extra {
            r.nodal[x] += q_node * w;
        }
    }
    out
}
