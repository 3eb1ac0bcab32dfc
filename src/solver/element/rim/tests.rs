//! The tests of the contact element off the axes: the point on the axis, the tangent against
//! central differences, the plain element without rims, and friction where the faces touch.

use super::friction::roll;
use super::*;
use crate::solver::element::beam::Chord;
use crate::solver::element::contact_law::{contact_outcome, surface_turn};
use crate::solver::model::Section;

/// An element of unit length along x, of `thickness`.
fn beam_of(thickness: f64) -> BeamElement {
    let section = Section {
        ea: 2e3,
        ei: 1.5,
        gae: 4e2,
        thickness,
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
    let b = beam_of(0.0);
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
/// with rims on both sides and two contacts on the element, and with the element bent so
/// far that the surface turn is held at its bound.
#[test]
fn the_tangent_with_rims_is_the_derivative_of_the_forces() {
    let (ends, _, c) = state();
    for phi in [state().1, [1.0, 1.1]] {
        tangent_with_rims_matches_central_differences(ends, phi, c);
    }
}

fn tangent_with_rims_matches_central_differences(
    ends: ([f64; 2], [f64; 2]),
    phi: [f64; 2],
    c: [f64; 2],
) {
    let b = beam_of(0.0);
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
    let nodal = |u: &[f64]| eval(u).response.nodal;
    let (err, p, q) = point::tangent_error(nodal, &k, &u0);
    assert!(err < 1e-6, "K[{p},{q}] off by {err:e}");
}

/// Without rims the element is the plain one, bit for bit.
#[test]
fn without_a_rim_the_element_is_the_plain_one() {
    let b = beam_of(0.0);
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
    let b = beam_of(0.0);
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

/// A grip of a stick point at 0.45 of the element, on a beam face of 0.05 m, in mode `slip`,
/// its node turned by `turn`.
fn grip(slip: Option<f64>, turn: Option<f64>) -> Grip {
    Grip {
        mu: 0.4,
        stiffness: 30.0,
        stick: 0.45,
        span: 1.0,
        side: 1.0,
        slip,
        face: 0.05,
        roll: -0.01,
        turn,
        rolled: (0.0, 0.0),
    }
}

/// The tangent is the derivative of the forces (central differences over every dof, the
/// node's rotation included), sticking and slipping, for a node whose rim turns and for
/// one whose rim does not, with a second, frictionless contact on the element, the
/// surface turn free and held at its bound.
#[test]
fn the_tangent_with_friction_at_a_distance_is_the_derivative_of_the_forces() {
    let b = beam_of(0.1);
    let ends = ([0.01, -0.02], [0.98, 0.07]);
    let (c, c2) = ([0.43, 0.31], [0.71, -0.18]);
    let rims = [0.2, -0.15];
    let opts = ContactOptions::default();
    // Bent within the turn's bound, and so far that the turn is held at it.
    let cases = [[0.06, 0.16], [1.0, 1.1]].map(|phi| {
        [
            (None, true),
            (None, false),
            (Some(1.0), true),
            (Some(1.0), false),
        ]
        .map(move |m| (phi, m))
    });
    for (phi, (slip, turning)) in cases.into_iter().flatten() {
        let eval = |u: &[f64]| {
            let ends = ([u[0], u[1]], [u[3], u[4]]);
            let phi = [u[2], u[5]];
            let xc = [[u[6], u[7]], [u[8], u[9]]];
            let turn = turning.then(|| u[10]);
            let grips = [Some(grip(slip, turn)), None];
            rim_outcome(&b, ends, phi, &xc, &rims, opts, &grips, true)
        };
        let mut u0 = vec![
            ends.0[0], ends.0[1], phi[0], ends.1[0], ends.1[1], phi[1], c[0], c[1], c2[0], c2[1],
        ];
        if turning {
            u0.push(0.12);
        }
        let out = eval(&u0);
        let k = out.response.tangent.unwrap();
        assert_eq!(
            k.nrows(),
            u0.len(),
            "the node's rotation is a dof where it turns"
        );
        let nodal = |u: &[f64]| eval(u).response.nodal;
        let (err, p, q) = point::tangent_error(nodal, &k, &u0);
        assert!(
            err < 1e-6,
            "{slip:?}, turning {turning}: K[{p},{q}] off by {err:e}"
        );
    }
}

/// A rim that rolls without slipping over a stretched, bent element keeps its slip to
/// second order, both sides of the beam; one that slides without turning slips. Rolling is
/// worked out here: the node's centre moved with the point of the axis it presses on,
/// c = c' + rim nu(t(xi')) for xi' a little further along (its contact kept), and turned
/// so that its rim's point at P is still along the surface, dphi = -(dc . tau) / (side r).
#[test]
fn a_rim_rolling_over_a_stretched_bent_element_does_not_slip() {
    let b = beam_of(0.1);
    // Stretched by a tenth along x and bent: the end rotations 0.2 apart.
    let (ends, phi) = (([0.0, 0.0], [1.1, 0.0]), [-0.1, 0.1]);
    let opts = ContactOptions::default();
    let (face, r) = (0.05, 0.15);
    for side in [1.0, -1.0] {
        let rim = side * (face + r);
        // The node where it touches at fraction xi of the chord (the chord along x).
        let at = |xi: f64| {
            let t = crate::solver::element::contact_law::surface_turn(phi[0], phi[1], xi);
            [1.1 * xi - rim * t.sin(), rim * t.cos()]
        };
        let t0 = crate::solver::element::contact_law::surface_turn(phi[0], phi[1], 0.4);
        let tau = [t0.cos(), t0.sin()];
        let slip = |dxi: f64, turning: bool| {
            let (c0, c) = (at(0.4), at(0.4 + dxi));
            let along = (c[0] - c0[0]) * tau[0] + (c[1] - c0[1]) * tau[1];
            let turn = 0.3 - if turning { along / (side * r) } else { 0.0 };
            let mut g = grip(None, Some(turn));
            g.side = side;
            // The roll measured from the start, as at an accepted state.
            g.roll = roll(phi, (rim, face, Some(0.3)), (g.span, g.stick));
            let out = rim_outcome(&b, ends, phi, &[c], &[rim], opts, &[Some(g)], false);
            out.friction[0].unwrap().slip
        };
        let s0 = slip(0.0, true);
        for dxi in [1e-4, 1e-3] {
            let rolled = slip(dxi, true) - s0;
            let slid = slip(dxi, false) - s0;
            assert!(
                rolled.abs() < 1e-2 * dxi,
                "side {side}, {dxi}: rolls {rolled:e}"
            );
            assert!(slid.abs() > 0.5 * dxi, "side {side}: slides {slid:e}");
        }
        // Second order: ten times the roll, a hundred times the slip left.
        let ratio = (slip(1e-3, true) - s0) / (slip(1e-4, true) - s0);
        assert!(ratio.abs() > 50.0, "side {side}: {ratio}");
    }
}

/// The element's forces balance as a force at P where the faces touch: their resultant
/// moment about the origin, with each nodal force at its node and the moments as they
/// are, is that of the contact's force on the node put at P and on the beam at P, i.e. 0.
#[test]
fn the_friction_acts_where_the_faces_touch() {
    let b = beam_of(0.1);
    let (ends, phi) = (([0.01, -0.02], [0.98, 0.07]), [0.06, 0.16]);
    let c = [0.43, 0.31];
    let rim = 0.2;
    let grips = [Some(grip(None, Some(0.12)))];
    let opts = ContactOptions::default();
    let out = rim_outcome(&b, ends, phi, &[c], &[rim], opts, &grips, false);
    let f = &out.response.nodal;
    let at = [ends.0, ends.1, c];
    let mut moment = f[2] + f[5] + f[8];
    for (k, x) in at.iter().enumerate() {
        let o = [0, 3, 6][k];
        moment += x[0] * f[o + 1] - x[1] * f[o];
    }
    let size = f.amax();
    assert!(
        moment.abs() < 1e-12 * size,
        "the element's forces turn by {moment:e}"
    );
    // The force on the node has a friction part: the moment is not trivially 0.
    let (p, ..) = rim_point(&b, ends, phi, c, rim);
    let arm = [c[0] - p[0], c[1] - p[1]];
    let cross = f[6] * arm[1] - f[7] * arm[0];
    assert!(cross.abs() > 1e-3 * size, "{cross:e}");
}
