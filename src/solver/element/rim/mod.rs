//! Contacts at a distance from the axis (`rim_outcome`): a pin with a radius, beams with a
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
//!
//! Friction between faces off the axis acts where they touch (`friction.rs`).

pub mod friction;
pub mod point;

use super::beam::BeamElement;
use super::contact_element::ContactOptions;
use super::contact_law::{contact_outcome, ContactOutcome};
use super::friction::Grip;
use friction::rim_friction_outcome;
pub use point::{point_jacobian, rim_point};

/// `contact_outcome` for contact nodes at `xc` standing off the axis by the signed contact
/// distances `rims` (side times distance; all 0: none): the element evaluated at the points on
/// the axis (`rim_point`), its forces on them put on the nodes, its tangent carried over by
/// the chain rule (see the module's notes). Where a contact off the axis has a grip, its
/// friction acts where the faces touch (`friction.rs`), and the element's dofs gain the
/// rotations of the nodes whose rims turn (`friction::turns_node`). An empty `rims` is
/// all 0.
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
    if (grips.iter().zip(rims)).any(|(g, &rim)| g.is_some() && rim != 0.0) {
        return rim_friction_outcome(beam, ends, phi, &points, rims, opts, grips, with_tangent);
    }
    let on: Vec<[f64; 2]> = points.iter().map(|p| p.0).collect();
    let mut out = contact_outcome(beam, ends, phi, &on, opts, grips, with_tangent);
    if let Some(k) = out.response.tangent.as_mut() {
        let j = point_jacobian(beam, ends, phi, &points, rims);
        *k = &*k * j;
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::solver::element::beam::Chord;
    use crate::solver::element::contact_law::surface_turn;
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
