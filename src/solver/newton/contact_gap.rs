//! The contact gaps of a Newton update: a contact node's offset from its element's chord
//! that a linear update leaves off its linearised value (the node slides along a chord that
//! turns), taken out with the tangent just factored, after the chords' stretch
//! (`stretch.rs`).

use super::iteration::Newton;
use super::stretch::ChordUpdate;
use crate::solver::assembly::Ordering;
use crate::solver::element::contact_element::{contact_compliance, contact_stiffness};
use crate::solver::linear::reduce::sum_squares;
use crate::solver::linear::{BandMatrix, NOT_FREE};

/// The largest turn of a contact element's chord (rad) in an update whose contact gaps are
/// taken out: beyond, the update is far from the solution, and its second-order gap no measure
/// of its error (measured on the robustness campaign, `tsm-contact robust`: corrected there,
/// drives of two cantilevers pressed by a pin cut back more often).
const CONTACT_TURN: f64 = 1e-2;

/// The largest share of an update a contact gap correction may add (norms over every dof):
/// a correction that moves the structure more than half as far as the update is no
/// second-order one but the tangent's soft direction near a limit point, which a small force
/// moves far (a pin pressing two cantilevers, just past a snap: `tests/contact/snap.rs`).
const GAP_SHARE: f64 = 0.5;

impl Newton<'_> {
    /// Solve into `gaps` for the displacements that take the contact gaps of the update from
    /// `before` to `d` out (`take_out_contact_gaps`), with the tangent just factored; returns
    /// whether they are to be added: not where no contact has a gap, nor where they would move
    /// the structure by more than `GAP_SHARE` of the update.
    pub(super) fn contact_gap_correction(
        &self,
        before: &[f64],
        d: &[f64],
        (ordering, factors): (&Ordering, &BandMatrix),
        gaps: &mut Vec<f64>,
    ) -> bool {
        gaps.clear();
        gaps.resize(ordering.n_eq, 0.0);
        if !self.take_out_contact_gaps(before, d, ordering, gaps) {
            return false;
        }
        factors.solve(gaps);
        let update: f64 = (ordering.free_dofs())
            .map(|(g, _)| (d[g] - before[g]).powi(2))
            .sum();
        sum_squares(gaps) <= GAP_SHARE * GAP_SHARE * update
    }

    /// The contact gaps of the update from `before` to `d`, loaded into `buf` as the contact
    /// elements' forces for them: returns whether any contact had one.
    ///
    /// A contact node's offset from its element's chord, w = (c - i) . n, is linear in the
    /// positions only for a chord that does not turn. A linear update that turns the chord by
    /// dpsi while the node slides along it by ds leaves the node off the turned chord by about
    /// ds dpsi (and w dpsi^2 / 2): times the contact element's stiffness against its contact
    /// force (3 EI / li^3 near an end), a spurious force far above the residual the update came
    /// to remove on fine meshes. The gap is measured from the chord turned as meant (the chord
    /// correction turns it so), and its forces are the element's for its contact node moved
    /// by the gap, end rotations held. The gap is that of the offset from the chord; with the
    /// surface normal (`SolverParams::surface_normal`), the turn of the force along the
    /// chord is left to Newton's next iteration. Left as they are: contacts at a distance from the axis
    /// (a radius, a thickness), frictional ones (whose stick spring has gaps of its own),
    /// self-contacts (measured on the robustness campaign, coils rolled on themselves stop
    /// more often with them corrected), a node that leaves its element or comes nearer its
    /// end than it slid (the transfer takes it on), and chords turned by more than
    /// `CONTACT_TURN`.
    fn take_out_contact_gaps(
        &self,
        before: &[f64],
        d: &[f64],
        ordering: &Ordering,
        buf: &mut [f64],
    ) -> bool {
        let s = self.structure;
        let mut any = false;
        for &e in &ordering.contact_beams {
            let body = s.model.beams[e].body;
            let left_as_is = |&k: &usize| {
                let pair = (ordering.links[k].node, body);
                ordering.links[k].rim != 0.0
                    || s.friction.contains_key(&pair)
                    || s.self_windows.contains_key(&pair)
            };
            if ordering.on_beam[e].iter().any(left_as_is) {
                continue;
            }
            let Some(gaps) = self.element_gaps(e, before, d, ordering) else {
                continue;
            };
            let el = &s.elements[e];
            let kb = contact_stiffness(
                el,
                &gaps.xi,
                contact_compliance(el, s.params.contact_stiffness),
            );
            let m = gaps.gap.len();
            // The bending forces (Mi, Mj, Y_1..Y_k) of the gaps.
            let forces: Vec<f64> = (0..2 + m)
                .map(|p| (0..m).map(|q| kb[(p, 2 + q)] * gaps.gap[q]).sum())
                .collect();
            if forces.iter().all(|f| f.is_finite()) {
                self.load_gap_forces(e, &gaps, &forces, ordering, buf);
                any = true;
            }
        }
        any
    }

    /// The gaps of the contacts on element `e` in the update from `before` to `d`, with the
    /// element's chord before it; `None` where the chord does not turn, turns by more than
    /// `CONTACT_TURN`, no contact has a gap, or a node leaves the element or comes nearer its
    /// end than it slid (the transfer takes it on, and the element's stiffness against its
    /// contact force, steep there, is no guide to the gap's).
    fn element_gaps(
        &self,
        e: usize,
        before: &[f64],
        d: &[f64],
        ordering: &Ordering,
    ) -> Option<ElementGaps> {
        let s = self.structure;
        let at = |d: &[f64], n: usize| self.node_at(d, n);
        let beam = &s.model.beams[e];
        let (pi, qi, qj) = (at(before, beam.i), at(d, beam.i), at(d, beam.j));
        let chord = ChordUpdate::new(pi, at(before, beam.j), qi, qj);
        let (t, l, turn) = (chord.e, chord.l, chord.turn);
        let n = [-t[1], t[0]];
        if turn == 0.0 || !turn.is_finite() || turn.abs() > CONTACT_TURN {
            return None;
        }
        let (cos, sin) = (turn.cos(), turn.sin());
        let turned = [n[0] * cos - t[0] * sin, n[1] * cos - t[1] * sin];
        let q = [qj[0] - qi[0], qj[1] - qi[1]];
        let on = &ordering.on_beam[e];
        let mut out = ElementGaps {
            normal: n,
            length: l,
            xi: Vec::with_capacity(on.len()),
            gap: Vec::with_capacity(on.len()),
        };
        for &k in on {
            let node = ordering.links[k].node;
            let (pc, qc) = (at(before, node), at(d, node));
            let a = [pc[0] - pi[0], pc[1] - pi[1]];
            let b = [qc[0] - qi[0], qc[1] - qi[1]];
            let along = a[0] * t[0] + a[1] * t[1];
            let along_after = (b[0] * q[0] + b[1] * q[1]) / (q[0] * q[0] + q[1] * q[1]);
            let slide = (along_after - along / l).abs();
            if !(0.0..=l).contains(&along) || along_after.min(1.0 - along_after) <= slide {
                return None;
            }
            // The linearised offset, less the offset from the chord turned as meant.
            let linear = b[0] * n[0] + b[1] * n[1] - along * turn;
            out.gap.push(linear - (b[0] * turned[0] + b[1] * turned[1]));
            out.xi
                .push((along / l).clamp(s.params.xi_min, 1.0 - s.params.xi_min));
        }
        let some = out.gap.iter().any(|g| *g != 0.0 && g.is_finite());
        some.then_some(out)
    }

    /// Load `buf` with the nodal forces U = B^T S of element `e`'s bending forces `forces`
    /// (Mi, Mj, Y_1..Y_k) for its gaps: the end moments, the contact forces along the chord's
    /// normal n on the nodes and against them at i, and the chord's turn,
    /// l dbeta/du = z = (-n at i, +n at j).
    fn load_gap_forces(
        &self,
        e: usize,
        gaps: &ElementGaps,
        forces: &[f64],
        ordering: &Ordering,
        buf: &mut [f64],
    ) {
        let (n, l) = (gaps.normal, gaps.length);
        let push: f64 = forces[2..].iter().sum();
        let turn_force = -(forces[0] + forces[1]) / l
            - (gaps.xi.iter().zip(&forces[2..]))
                .map(|(xi, y)| y * xi)
                .sum::<f64>();
        let eqs = &ordering.beam_eqs[e];
        for (slot, value) in [
            (0, -n[0] * (push + turn_force)),
            (1, -n[1] * (push + turn_force)),
            (2, forces[0]),
            (3, n[0] * turn_force),
            (4, n[1] * turn_force),
            (5, forces[1]),
        ] {
            if eqs[slot] != NOT_FREE {
                buf[eqs[slot] as usize] += value;
            }
        }
        let first = &self.structure.dofs.first;
        for (&k, y) in ordering.on_beam[e].iter().zip(&forces[2..]) {
            let node = ordering.links[k].node;
            for (o, along_n) in n.iter().enumerate() {
                if let Some(eq) = ordering.equation(first[node] + o) {
                    buf[eq] += along_n * y;
                }
            }
        }
    }
}

/// The contact gaps on one element: its chord's normal and length before the update, and
/// each contact's fraction along it (within the stiffness's bounds) and gap.
struct ElementGaps {
    normal: [f64; 2],
    length: f64,
    xi: Vec<f64>,
    gap: Vec<f64>,
}
