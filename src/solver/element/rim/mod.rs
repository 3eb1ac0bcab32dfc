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
pub use point::{point_jacobian, rim_point, RimPoints};

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
    let at = RimPoints {
        beam,
        ends,
        phi,
        points: &points,
        rims,
    };
    if (grips.iter().zip(rims)).any(|(g, &rim)| g.is_some() && rim != 0.0) {
        return rim_friction_outcome(&at, opts, grips, with_tangent);
    }
    let on: Vec<[f64; 2]> = points.iter().map(|p| p.0).collect();
    let mut out = contact_outcome(beam, ends, phi, &on, opts, grips, with_tangent);
    if let Some(k) = out.response.tangent.as_mut() {
        let j = point_jacobian(&at);
        *k = &*k * j;
    }
    out
}

#[cfg(test)]
mod tests;
