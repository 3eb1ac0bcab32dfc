//! Friction between beams at a distance from the axes: a node whose rim (its radius, half its
//! own thickness) touches a beam's face (half the beam's thickness) at the point P between
//! them, `c - c' = rim nu` (`rim/mod.rs`: c' the point of the beam's axis the contact
//! element works on, nu the beam's surface normal there, `rim = side D` with D the contact
//! distance, the node's part r and the beam's part h).
//!
//! **What slips.** The contact element's tangential coordinate, s = s_i + xi' Ls at c', is the
//! place of c on the beam's parallel surface at D: the slip of the node's centre over that
//! surface. The faces meet at P, r short of c, so the rim's point at P slips by that less the
//! rim's turn relative to the surface normal: the slip gains `rho = sign(Ls) side r (phi_c -
//! a)`, phi_c the node's rotation (0 for a node without one, whose rim does not turn) and a the
//! normal's rotation since rest at c' (`(1 - xi') phi_i + xi' phi_j` within the turn's bound).
//! A rim rolling without slipping keeps s + rho: what sticks is its point that touches. rho is
//! measured from the stick point's, within half a turn, in length along the surface.
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

use super::point::{point_jacobian, rim_point};
use crate::solver::element::beam::{BeamElement, Chord};
use crate::solver::element::contact_element::ContactOptions;
use crate::solver::element::contact_law::{contact_outcome, ContactOutcome, MAX_TURN};
use crate::solver::element::friction::{xi_gradient, Grip};

/// Whether the contact of `grip` at signed contact distance `rim` takes the moment of its
/// friction on its node's rotation: frictional, off the axis by more than the beam's face,
/// and a node with a rotation. Such a contact's element has that rotation among its dofs,
/// after every contact node's (u, v), in the order of the contacts.
pub fn turns_node(rim: f64, grip: &Option<Grip>) -> bool {
    grip.is_some_and(|g| rim != 0.0 && g.turn.is_some() && rim.abs() > g.face)
}

/// The rim's roll `rho` of a contact node at `c` with signed contact distance `rim` on `beam`
/// (ends `ends`, rotations `phi`), the beam's face `face` of it, the node's rotation `turn` and
/// the element's body span `span` (`Grip::span`): `sign(span) side r (phi_c - a)` (m).
pub fn roll(
    beam: &BeamElement,
    (ends, phi): (([f64; 2], [f64; 2]), [f64; 2]),
    (c, rim): ([f64; 2], f64),
    (face, turn, span): (f64, Option<f64>, f64),
) -> f64 {
    let (_, _, t) = rim_point(beam, ends, phi, c, rim);
    let ch = Chord::new(ends.0, ends.1, beam.alpha0, 0.5 * (phi[0] + phi[1]));
    roll_at(ch.beta + t, rim, face, turn, span)
}

/// `roll` given the normal's rotation `a` at c'.
fn roll_at(a: f64, rim: f64, face: f64, turn: Option<f64>, span: f64) -> f64 {
    let r = (rim.abs() - face).max(0.0);
    span.signum() * rim.signum() * r * (turn.unwrap_or(0.0) - a)
}

/// `ContactOutcome` of `beam` for contact nodes at `xc` standing off the axis by the signed
/// distances `rims`, with the friction of `grips` acting where the faces touch (the module's
/// notes): the contact element on the axis points `points` (`rim_point`'s), the rims' rolls in
/// the slips, the friction's moments on the beam's end rotations and on the rotations of the
/// nodes that turn (`turns_node`), appended to the dofs.
#[allow(clippy::too_many_arguments)]
pub fn rim_friction_outcome(
    beam: &BeamElement,
    ends: ([f64; 2], [f64; 2]),
    phi: [f64; 2],
    points: &[([f64; 2], f64, f64)],
    rims: &[f64],
    opts: ContactOptions,
    grips: &[Option<Grip>],
    with_tangent: bool,
) -> ContactOutcome {
    let ch = Chord::new(ends.0, ends.1, beam.alpha0, 0.5 * (phi[0] + phi[1]));
    let mut grips = grips.to_vec();
    for (m, grip) in grips.iter_mut().enumerate() {
        if let Some(g) = grip.as_mut().filter(|_| rims[m] != 0.0) {
            let r = (rims[m].abs() - g.face).max(0.0);
            let rho = roll_at(ch.beta + points[m].2, rims[m], g.face, g.turn, g.span);
            let round = std::f64::consts::TAU * r;
            g.rolled = if r > 0.0 {
                let turned = rho - g.roll;
                turned - round * (turned / round).round()
            } else {
                0.0
            };
        }
    }
    let on: Vec<[f64; 2]> = points.iter().map(|p| p.0).collect();
    let mut out = contact_outcome(beam, ends, phi, &on, opts, &grips, with_tangent);
    let nd = out.response.nodal.len();
    let turning: Vec<usize> = (0..rims.len())
        .filter(|&m| turns_node(rims[m], &grips[m]))
        .collect();
    let total = nd + turning.len();
    let jacobian = with_tangent.then(|| point_jacobian(beam, ends, phi, points, rims));
    let r = &mut out.response;
    r.nodal = r.nodal.clone().resize_vertically(total, 0.0);
    if let (Some(k), Some(j)) = (r.tangent.take(), jacobian.as_ref()) {
        r.tangent = Some((k * j).resize(total, total, 0.0));
    }
    let (ti, tj) = (phi[0] - ch.beta, phi[1] - ch.beta);
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
        let (q_beam, q_node) = (side * g.face, side * (rims[m].abs() - g.face).max(0.0));
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
                // The stick force kt (s + rho - s0) follows the roll: along the friction's
                // direction in the forces, span grad xi' (rows of the ends and c).
                let mut grad_rho = -&grad_a * (g.span.signum() * q_node);
                if let Some(x) = extra {
                    grad_rho[x] += g.span.signum() * q_node;
                }
                let mut dir = DVector::zeros(total);
                dir.rows_mut(0, nd).copy_from(&(&gx * g.span));
                *k += dir * (grad_rho * g.stiffness).transpose();
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

/// The tangent's dofs for tests: nothing here but the functions above.
#[cfg(test)]
mod tests {
    use super::*;

    /// The element with rims `rims` at nodes `xc`: `rim_friction_outcome` on their points.
    #[allow(clippy::too_many_arguments)]
    fn rim_outcome(
        beam: &BeamElement,
        ends: ([f64; 2], [f64; 2]),
        phi: [f64; 2],
        xc: &[[f64; 2]],
        rims: &[f64],
        opts: ContactOptions,
        grips: &[Option<Grip>],
        with_tangent: bool,
    ) -> ContactOutcome {
        let points: Vec<_> = (xc.iter().zip(rims))
            .map(|(&c, &rim)| rim_point(beam, ends, phi, c, rim))
            .collect();
        rim_friction_outcome(beam, ends, phi, &points, rims, opts, grips, with_tangent)
    }
    use crate::solver::model::Section;

    fn beam() -> BeamElement {
        let section = Section {
            ea: 2e3,
            ei: 1.5,
            gae: 4e2,
            thickness: 0.1,
        };
        BeamElement::new([0.0, 0.0], [1.0, 0.0], section, 0.0)
    }

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
            rolled: 0.0,
        }
    }

    /// The tangent is the derivative of the forces (central differences over every dof, the
    /// node's rotation included), sticking and slipping, for a node whose rim turns and for
    /// one whose rim does not, with a second, frictionless contact on the element.
    #[test]
    fn the_tangent_with_friction_at_a_distance_is_the_derivative_of_the_forces() {
        let b = beam();
        let (ends, phi) = (([0.01, -0.02], [0.98, 0.07]), [0.06, 0.16]);
        let (c, c2) = ([0.43, 0.31], [0.71, -0.18]);
        let rims = [0.2, -0.15];
        let opts = ContactOptions::default();
        for slip in [None, Some(1.0)] {
            for turning in [true, false] {
                let eval = |u: &[f64]| {
                    let ends = ([u[0], u[1]], [u[3], u[4]]);
                    let phi = [u[2], u[5]];
                    let xc = [[u[6], u[7]], [u[8], u[9]]];
                    let turn = turning.then(|| u[10]);
                    let grips = [Some(grip(slip, turn)), None];
                    rim_outcome(&b, ends, phi, &xc, &rims, opts, &grips, true)
                };
                let mut u0 = vec![
                    ends.0[0], ends.0[1], phi[0], ends.1[0], ends.1[1], phi[1], c[0], c[1], c2[0],
                    c2[1],
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
                let h = 1e-6;
                let scale = k.amax();
                for q in 0..u0.len() {
                    let (mut up, mut um) = (u0.clone(), u0.clone());
                    up[q] += h;
                    um[q] -= h;
                    let fd = (eval(&up).response.nodal - eval(&um).response.nodal) / (2.0 * h);
                    for p in 0..u0.len() {
                        let err = (fd[p] - k[(p, q)]).abs();
                        assert!(
                            err < 1e-6 * scale,
                            "{slip:?}, turning {turning}: K[{p},{q}] {} against {}",
                            k[(p, q)],
                            fd[p]
                        );
                    }
                }
            }
        }
    }

    /// The element's forces balance as a force at P where the faces touch: their resultant
    /// moment about the origin, with each nodal force at its node and the moments as they
    /// are, is that of the contact's force on the node put at P and on the beam at P, i.e. 0.
    #[test]
    fn the_friction_acts_where_the_faces_touch() {
        let b = beam();
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
}
