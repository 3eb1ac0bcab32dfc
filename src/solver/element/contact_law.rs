//! The contact element as the assembly adds it: `contact_element.rs`'s frictionless forces,
//! turned to the beam's surface normal, then the friction of the contacts that have a grip
//! (`friction.rs`), in that order.
//!
//! **The surface normal.** The paper's contact element pushes along the chord's normal. Where a
//! node rests near a mesh node of a bent beam, the two elements meeting there have chords
//! turned apart by the bend, so the force turns abruptly as the contact moves from one element
//! to the next: over a mesh node in a hollow each element pushes the node onto the other, and
//! no equilibrium exists on either (the "mesh-node valley"). The beam's own shape has no such
//! kink: its tangent at a node is the node's rotation, shared by both elements.
//!
//! So the frictionless force is turned to the normal of the surface tangent tau = cos(t) e +
//! sin(t) n, with t the element's end rotations relative to its chord interpolated linearly at
//! the contact point, `t = (1 - xi) theta_i + xi theta_j`: continuous from one element to the
//! next (at a shared node both give the node's rotation). The turn adds a force along the chord
//! on the contact node, `T = -Yc tan(t)`, carried as a generalised force g = T l conjugate to
//! xi (self-equilibrated, exact for rigid motion), with its exact tangent. The turn is held
//! within `MAX_TURN`, far beyond any element within its small strains.
//!
//! **Contacts at a distance from the axis** (`rim_outcome`): a pin with a radius, beams with a
//! thickness. The contact node c stands off the beam's axis by the contact distance r (its radius plus
//! the half thicknesses of the two surfaces), along the beam's surface normal where it touches.
//!
//! **The point on the axis.** The contact element works on the point of the
//! axis that the node presses on, `c' = c - rim nu(t)`, with `rim = side r` (the node's side
//! of the beam along the chord normal) and `nu(t)` the surface normal turned by the surface
//! turn t at the fraction of c' itself (`surface_turn`): the beam's parallel curve at distance
//! r, to the element's interpolation of its tangent. c' depends on t and t on where c' lies,
//! so it is found by a fixed point, which contracts by `r |theta_j - theta_i| / l` a pass.
//!
//! **Forces.** The contact element's frictionless force on c' is along `nu(t)`, so it acts on
//! the line through c and c': moved to c unchanged, it does no work on the turn of the arm
//! `c - c'` (`nu . d nu = 0`, and the force is along nu). The nodal forces are the element's
//! with the force on c' put on c, and the tangent their exact derivative by the chain rule,
//! `K = K' dc'/du`, with dc'/du from differentiating the fixed point:
//! `dc' = dc + rim tau da`, with a the normal's angle (the chord's plus t),
//! `da = (1 - xi) dphi_i + xi dphi_j + (theta_j - theta_i) dxi`.
//! Without a rim (r = 0) the element is `contact_outcome`'s, bit for bit.

use nalgebra::{DMatrix, DVector, Matrix2, Vector2};

use super::beam::{BeamElement, Chord};
use super::contact_element::{contact_response, ContactOptions, ContactResponse};
use super::friction::{add_friction, xi_gradient, xi_hessian, Grip, Traction};

/// What a contact element with its frictionless forces turned to the surface normal (if
/// `opts.surface_normal`) and friction at the contacts with a grip returns.
#[derive(Clone, Debug)]
pub struct ContactOutcome {
    /// Forces, nodal forces and tangent, turn and friction included.
    pub response: ContactResponse,
    /// The friction of each contact (`None`: frictionless).
    pub friction: Vec<Option<Traction>>,
}

/// `contact_response`, then the turn to the surface normal (above) and the
/// friction of the contacts with a `Grip` (`friction.rs`; `grips` empty: none), in that
/// order: the element as the assembly adds it.
pub fn contact_outcome(
    beam: &BeamElement,
    ends: ([f64; 2], [f64; 2]),
    phi: [f64; 2],
    xc: &[[f64; 2]],
    opts: ContactOptions,
    grips: &[Option<Grip>],
    with_tangent: bool,
) -> ContactOutcome {
    let mut r = contact_response(beam, ends.0, ends.1, phi, xc, opts, with_tangent);
    let gripped = grips.iter().any(Option::is_some);
    let gradients = if with_tangent && (opts.surface_normal || gripped) {
        normal_gradients(&r, ends)
    } else {
        vec![None; xc.len()]
    };
    if opts.surface_normal {
        turn_to_surface(&mut r, ends, xc, &gradients);
    }
    let friction = if gripped {
        add_friction(&mut r, beam.length, ends, xc, grips, &gradients)
    } else {
        vec![None; xc.len()]
    };
    ContactOutcome {
        response: r,
        friction,
    }
}

/// The largest turn taken (rad): an element bent further than this against its chord is far
/// outside the small strains the element models, and the turn stays bounded there.
pub const MAX_TURN: f64 = std::f64::consts::FRAC_PI_4;

/// The angle t from the chord to the surface tangent at fraction `xi`, given the end
/// rotations relative to the chord, within `MAX_TURN`.
pub fn surface_turn(theta_i: f64, theta_j: f64, xi: f64) -> f64 {
    ((1.0 - xi) * theta_i + xi * theta_j).clamp(-MAX_TURN, MAX_TURN)
}

/// Turn the frictionless forces of `r` (evaluated with ends at `ends` and contact nodes at
/// `xc`) to the surface normal. `normal_gradients` are the gradients of each Yc, read before
/// the turn.
pub fn turn_to_surface(
    r: &mut ContactResponse,
    ends: ([f64; 2], [f64; 2]),
    xc: &[[f64; 2]],
    normal_gradients: &[Option<DVector<f64>>],
) {
    let nd = r.nodal.len();
    let xi_pos = Vector2::new(ends.0[0], ends.0[1]);
    let d = Vector2::new(ends.1[0], ends.1[1]) - xi_pos;
    let l = d.norm();
    let e = d / l;
    let (ti, tj) = (r.deformation[1], r.deformation[2]);
    for (m, &c) in xc.iter().enumerate() {
        let a = Vector2::new(c[0], c[1]) - xi_pos;
        let xi = a.dot(&d) / d.dot(&d);
        let t = surface_turn(ti, tj, xi);
        let yc = r.forces[3 + m];
        let tan = t.tan();
        let g = -yc * tan * l;
        let grad_xi = xi_gradient(a, d, nd, m);
        r.nodal.axpy(g, &grad_xi, 1.0);
        if let (Some(k), Some(grad_y)) = (r.tangent.as_mut(), normal_gradients[m].as_ref()) {
            // grad t = (1 - xi) grad theta_i + xi grad theta_j + (theta_j - theta_i) grad xi,
            // grad theta = e_phi - z / l, z = [s, -c, 0, -s, c, 0].
            let free = t.abs() < MAX_TURN;
            let mut grad_t = &grad_xi * (tj - ti);
            let zl = [e[1] / l, -e[0] / l, 0.0, -e[1] / l, e[0] / l, 0.0];
            for (q, z) in zl.iter().enumerate() {
                grad_t[q] -= z;
            }
            grad_t[2] += 1.0 - xi;
            grad_t[5] += xi;
            if !free {
                grad_t.fill(0.0);
            }
            let mut grad_l = DVector::zeros(nd);
            for q in 0..2 {
                grad_l[q] = -e[q];
                grad_l[3 + q] = e[q];
            }
            let sec2 = 1.0 + tan * tan;
            let grad_g: DVector<f64> =
                -(grad_y * (tan * l) + &grad_l * (yc * tan) + &grad_t * (yc * sec2 * l));
            *k += &grad_xi * grad_g.transpose();
            if g != 0.0 {
                *k += xi_hessian(a, d, nd, m) * g;
            }
        }
    }
}

/// The gradient of each contact force Yc of a frictionless response over its dofs: the
/// contact node's rows of the tangent along the chord normal (the force on the node is Yc n,
/// and n . dn = 0).
pub fn normal_gradients(
    r: &ContactResponse,
    ends: ([f64; 2], [f64; 2]),
) -> Vec<Option<DVector<f64>>> {
    let d = [ends.1[0] - ends.0[0], ends.1[1] - ends.0[1]];
    let l = d[0].hypot(d[1]);
    let n = [-d[1] / l, d[0] / l];
    (0..r.xi.len())
        .map(|m| {
            let k: &DMatrix<f64> = r.tangent.as_ref()?;
            Some((k.row(6 + 2 * m) * n[0] + k.row(7 + 2 * m) * n[1]).transpose())
        })
        .collect()
}

/// Passes of the fixed point for c' at most; it contracts by `r |theta_j - theta_i| / l`, far
/// below 1 on any element within its small strains, and stops at round-off.
const PASSES: usize = 32;

/// Where a contact node at `c` with signed contact distance `rim` (side times distance) presses
/// on the axis of `beam` with ends at `ends` and rotations `phi`: the point c', its fraction
/// along the chord and the surface turn there.
pub fn rim_point(
    beam: &BeamElement,
    ends: ([f64; 2], [f64; 2]),
    phi: [f64; 2],
    c: [f64; 2],
    rim: f64,
) -> ([f64; 2], f64, f64) {
    let ch = Chord::new(ends.0, ends.1, beam.alpha0, 0.5 * (phi[0] + phi[1]));
    let (ti, tj) = (phi[0] - ch.beta, phi[1] - ch.beta);
    let fraction = |p: [f64; 2]| ((p[0] - ends.0[0]) * ch.c + (p[1] - ends.0[1]) * ch.s) * ch.inv_l;
    let mut p = c;
    let mut xi = fraction(p);
    let mut t = surface_turn(ti, tj, xi);
    let size = rim.abs() + ch.l;
    for _ in 0..PASSES {
        // The surface normal turned by t from the chord normal n = (-s, c).
        let (st, ct) = t.sin_cos();
        let nu = [-st * ch.c - ct * ch.s, -st * ch.s + ct * ch.c];
        let q = [c[0] - rim * nu[0], c[1] - rim * nu[1]];
        let moved = (q[0] - p[0]).hypot(q[1] - p[1]);
        p = q;
        xi = fraction(p);
        t = surface_turn(ti, tj, xi);
        if moved <= 1e-15 * size {
            break;
        }
    }
    (p, xi, t)
}

/// `contact_outcome` for contact nodes at `xc` standing off the axis by the signed contact
/// distances `rims` (side times distance; all 0: none): the element evaluated at the points on
/// the axis (`rim_point`), its forces on them put on the nodes, its tangent carried over by
/// the chain rule (see the module's notes). A grip acts at the point on the axis, its force put on
/// the node unchanged: the friction of a rigid circle that does not turn, which holds the
/// moment about its centre (`Model::friction_allowed`). An empty
/// `rims` is all 0.
#[allow(clippy::too_many_arguments)]
#[inline]
pub fn rim_outcome(
    beam: &BeamElement,
    ends: ([f64; 2], [f64; 2]),
    phi: [f64; 2],
    xc: &[[f64; 2]],
    rims: &[f64],
    opts: ContactOptions,
    grips: &[Option<Grip>],
    with_tangent: bool,
) -> ContactOutcome {
    if rims.iter().all(|&r| r == 0.0) {
        // No rims (an empty slice included): the plain element.
        return contact_outcome(beam, ends, phi, xc, opts, grips, with_tangent);
    }
    let points: Vec<([f64; 2], f64, f64)> = (xc.iter().zip(rims))
        .map(|(&c, &rim)| rim_point(beam, ends, phi, c, rim))
        .collect();
    let on: Vec<[f64; 2]> = points.iter().map(|p| p.0).collect();
    let mut out = contact_outcome(beam, ends, phi, &on, opts, grips, with_tangent);
    if let Some(k) = out.response.tangent.as_mut() {
        let j = point_jacobian(beam, ends, phi, &points, rims);
        *k = &*k * j;
    }
    out
}

/// d(ends, c'_1..c'_k) / d(ends, c_1..c_k): the identity but in the rows of each c'.
fn point_jacobian(
    beam: &BeamElement,
    ends: ([f64; 2], [f64; 2]),
    phi: [f64; 2],
    points: &[([f64; 2], f64, f64)],
    rims: &[f64],
) -> DMatrix<f64> {
    let nd = 6 + 2 * points.len();
    let mut j = DMatrix::identity(nd, nd);
    let ch = Chord::new(ends.0, ends.1, beam.alpha0, 0.5 * (phi[0] + phi[1]));
    let (ti, tj) = (phi[0] - ch.beta, phi[1] - ch.beta);
    let (l, e) = (ch.l, Vector2::new(ch.c, ch.s));
    let d = Vector2::new(ends.1[0] - ends.0[0], ends.1[1] - ends.0[1]);
    for (m, (&(p, xi, t), &rim)) in points.iter().zip(rims).enumerate() {
        if rim == 0.0 || t.abs() >= MAX_TURN {
            continue;
        }
        let dtheta = tj - ti;
        // The surface normal's own angle is the chord's plus t, (1 - xi) phi_i + xi phi_j
        // and a constant: its gradient over the end dofs with c' held is
        // (1 - xi) e_phi_i + xi e_phi_j + dtheta grad xi (the chord's turn cancels).
        let a = Vector2::new(p[0] - ends.0[0], p[1] - ends.0[1]);
        let l2 = d.dot(&d);
        let gd = (a - d * (2.0 * xi)) / l2;
        let ga = d / l2;
        let mut g = [0.0; 6];
        for k in 0..2 {
            g[k] = dtheta * (-ga[k] - gd[k]);
            g[3 + k] = dtheta * gd[k];
        }
        g[2] += 1.0 - xi;
        g[5] += xi;
        // (I - kappa tau e^T) dc' = dc + rim tau g^T du, kappa = rim dtheta / l.
        let (st, ct) = t.sin_cos();
        let tau = e * ct + Vector2::new(-ch.s, ch.c) * st;
        let kappa = rim * dtheta / l;
        let inv = Matrix2::identity() + tau * e.transpose() * (kappa / (1.0 - kappa * ct));
        let row = 6 + 2 * m;
        for q in 0..nd {
            let mut rhs = Vector2::zeros();
            if q < 6 {
                rhs += tau * (rim * g[q]);
            } else if q == row || q == row + 1 {
                rhs[q - row] = 1.0;
            }
            let col = inv * rhs;
            j[(row, q)] = col[0];
            j[(row + 1, q)] = col[1];
        }
    }
    j
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::solver::model::Section;

    fn beam() -> BeamElement {
        let section = Section {
            ea: 2e3,
            ei: 1.5,
            gae: 4e2,
            thickness: 0.0,
        };
        BeamElement::new([0.0, 0.0], [1.0, 0.0], section, 0.0)
    }

    /// The ends, end rotations and contact node of one state.
    type State = (([f64; 2], [f64; 2]), [f64; 2], [f64; 2]);

    /// A bent element (ends moved and turned) with a node above it.
    fn state() -> State {
        (([0.01, -0.02], [0.98, 0.07]), [0.06, 0.16], [0.43, 0.31])
    }

    /// The node stands off the element's axis point by the contact distance along the surface
    /// normal there, and c' lies on the chord fraction that gives that normal.
    #[test]
    fn the_node_stands_off_the_axis_by_its_distance_along_the_surface_normal() {
        let (ends, phi, c) = state();
        let b = beam();
        let rim = 0.2;
        let (p, xi, t) = rim_point(&b, ends, phi, c, rim);
        let dist = (c[0] - p[0]).hypot(c[1] - p[1]);
        assert!((dist - rim).abs() < 1e-14, "{dist}");
        let ch = Chord::new(ends.0, ends.1, b.alpha0, 0.5 * (phi[0] + phi[1]));
        let along = ((p[0] - ends.0[0]) * ch.c + (p[1] - ends.0[1]) * ch.s) / ch.l;
        assert!((along - xi).abs() < 1e-15);
        let t_here = surface_turn(phi[0] - ch.beta, phi[1] - ch.beta, xi);
        assert!((t - t_here).abs() < 1e-15);
        // c - c' is the chord normal turned by t.
        let n = [-ch.s, ch.c];
        let cos = ((c[0] - p[0]) * n[0] + (c[1] - p[1]) * n[1]) / dist;
        assert!((cos - t.cos()).abs() < 1e-13, "{cos} against {}", t.cos());
    }

    /// The tangent is the derivative of the nodal forces (central differences over every dof)
    /// with rims on both sides and two contacts on the element.
    #[test]
    fn the_tangent_with_rims_is_the_derivative_of_the_forces() {
        let b = beam();
        let (ends, phi, c) = state();
        let c2 = [0.71, -0.18];
        let rims = [0.2, -0.15];
        let opts = ContactOptions::default();
        let eval = |u: &[f64]| {
            let ends = ([u[0], u[1]], [u[3], u[4]]);
            let phi = [u[2], u[5]];
            let xc = [[u[6], u[7]], [u[8], u[9]]];
            rim_outcome(&b, ends, phi, &xc, &rims, opts, &[], true)
        };
        let u0 = vec![
            ends.0[0], ends.0[1], phi[0], ends.1[0], ends.1[1], phi[1], c[0], c[1], c2[0], c2[1],
        ];
        let k = eval(&u0).response.tangent.unwrap();
        let h = 1e-6;
        let scale = k.amax();
        for q in 0..10 {
            let (mut up, mut um) = (u0.clone(), u0.clone());
            up[q] += h;
            um[q] -= h;
            let fd = (eval(&up).response.nodal - eval(&um).response.nodal) / (2.0 * h);
            for p in 0..10 {
                let err = (fd[p] - k[(p, q)]).abs();
                assert!(
                    err < 1e-6 * scale,
                    "K[{p},{q}]: {} against {}",
                    k[(p, q)],
                    fd[p]
                );
            }
        }
    }

    /// Without rims the element is the plain one, bit for bit.
    #[test]
    fn without_a_rim_the_element_is_the_plain_one() {
        let b = beam();
        let (ends, phi, c) = state();
        let opts = ContactOptions::default();
        let plain = contact_outcome(&b, ends, phi, &[c], opts, &[], true).response;
        let rimmed = rim_outcome(&b, ends, phi, &[c], &[0.0], opts, &[], true).response;
        assert_eq!(plain.nodal, rimmed.nodal);
        assert_eq!(plain.tangent, rimmed.tangent);
    }

    /// The frictionless force on the node passes through the axis point: along c - c'.
    #[test]
    fn the_force_on_the_node_points_along_its_arm() {
        let b = beam();
        let (ends, phi, c) = state();
        let rim = 0.2;
        let out = rim_outcome(
            &b,
            ends,
            phi,
            &[c],
            &[rim],
            ContactOptions::default(),
            &[],
            false,
        );
        let f = [out.response.nodal[6], out.response.nodal[7]];
        let (p, ..) = rim_point(&b, ends, phi, c, rim);
        let arm = [c[0] - p[0], c[1] - p[1]];
        let cross = f[0] * arm[1] - f[1] * arm[0];
        assert!(cross.abs() < 1e-12 * f[0].hypot(f[1]) * rim, "{cross:e}");
    }
}
