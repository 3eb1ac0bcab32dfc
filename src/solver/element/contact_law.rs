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
//! Contacts at a distance from the axes are `rim/`'s: the element evaluated on the point of
//! the axis the node presses on.

use nalgebra::{DMatrix, DVector, Vector2};

use super::beam::BeamElement;
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
