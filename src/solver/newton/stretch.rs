//! The stretch correction of a Newton update: the chords' second-order gaps that a linear
//! update leaves (a turned chord comes out too long and turned by less) taken out with the
//! tangent just factored, and after them the contact gaps of `contact_gap.rs`.

use super::constraint::Path;
use super::iteration::Newton;
use crate::solver::assembly::Ordering;
use crate::solver::linear::reduce::sum_squares;
use crate::solver::linear::{BandMatrix, NOT_FREE};
use crate::solver::params::StretchCorrection;

/// The largest turn of a chord (rad) a judged update is corrected for: beyond, the update is a
/// direction (a buckling mode's at a bifurcation), not a turn meant.
const JUDGED_TURN: f64 = 1.0;

/// Which updates the stretch correction is made for.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Correction {
    /// Every update: the chords and the contact gaps (`contact_gap_correction`).
    Every,
    /// Every update, the chords only: the first update of a pass, which follows the predictor
    /// or a change of the contact set (a contact's offset there moves by the penetration the
    /// update removes, and its linearisation is no closer than the gap), and every update on
    /// the way of a snap, where the contacts move with the damped path. Measured on the
    /// robustness campaign (`tsm-contact robust`), correcting their gaps costs cut-backs.
    Chords,
    /// A judged update (`StretchCorrection::WhereNeeded`): only where the gaps' loads (their
    /// norm) exceed this unbalanced force, the one the update came to remove, and no chord
    /// turns by more than `JUDGED_TURN`.
    Beyond(f64),
}

/// An element's chord before an update and what a linear update does to it.
pub(super) struct ChordUpdate {
    /// The chord's unit vector before the update.
    pub(super) e: [f64; 2],
    /// Its length before the update.
    pub(super) l: f64,
    /// The update's move of end j relative to end i.
    pub(super) dc: [f64; 2],
    /// The update's linear turn of the chord: its move across the chord over l (rad).
    pub(super) turn: f64,
}

impl ChordUpdate {
    /// The chord from `pi` to `pj` and the update that moves its ends to `qi` and `qj`.
    pub(super) fn new(pi: [f64; 2], pj: [f64; 2], qi: [f64; 2], qj: [f64; 2]) -> ChordUpdate {
        let c = [pj[0] - pi[0], pj[1] - pi[1]];
        let l = c[0].hypot(c[1]);
        let e = [c[0] / l, c[1] / l];
        let dc = [qj[0] - qi[0] - c[0], qj[1] - qi[1] - c[1]];
        let turn = (e[0] * dc[1] - e[1] * dc[0]) / l;
        ChordUpdate { e, l, dc, turn }
    }
}

impl Newton<'_> {
    /// The position of node `n` at the displacements `d`: its initial coordinates plus its
    /// displacement.
    pub(super) fn node_at(&self, d: &[f64], n: usize) -> [f64; 2] {
        let (node, first) = (&self.structure.model.nodes[n], self.structure.dofs.first[n]);
        [node.x + d[first], node.y + d[first + 1]]
    }

    /// Which updates of this attempt the stretch correction is made for
    /// (`SolverParams::stretch_correction`): every one, or (`WhereNeeded` before the run's
    /// first cut-back, in a model without contact, under prescribed displacements and loads
    /// with no step limit to cut an update to a direction) those whose gaps' loads exceed
    /// `unbalanced`, the force the update is solved from; `None`: no update.
    ///
    /// `contact_gaps`: whether this update may have its contact gaps taken out too (not the
    /// first of a pass, not on the way of a snap: `Correction::Chords`).
    pub(super) fn correction(
        &self,
        path: &Path,
        max_step: f64,
        unbalanced: &[f64],
        contact_gaps: bool,
    ) -> Option<Correction> {
        let s = self.structure;
        let judged = s.params.stretch_correction == StretchCorrection::WhereNeeded
            && s.candidates.is_empty()
            && s.obstacle_candidates.is_empty()
            && !path.counts_moves()
            && max_step == f64::MAX;
        if self.stretch_correcting() {
            Some(if contact_gaps {
                Correction::Every
            } else {
                Correction::Chords
            })
        } else if judged {
            Some(Correction::Beyond(sum_squares(unbalanced).sqrt()))
        } else {
            None
        }
    }

    /// Take the chords' second-order errors out of the update from `before` to `d`.
    ///
    /// A linear update moves an element's end j by dc relative to i: dl along the old chord e
    /// and l dpsi across it (n). The element meant by that is the old chord turned by dpsi and
    /// stretched by dl; the update instead puts the chord at `(l + dl) e + l dpsi n`, which is
    /// longer by about l dpsi^2 / 2 and turned by less (atan). Times EA/L and 12 EI / l^3, those
    /// gaps are spurious forces that on fine meshes of stiff beams dwarf the residual the
    /// update came to remove: Newton zig-zags (every other iterate is stretched), and load
    /// steps fail. The correction loads the tangent just factored with each element's elastic
    /// forces for its gap (its end j moved by the gap, rotations held) and adds the
    /// displacements they produce: on a structure free to take them up (a tree), the turned
    /// chords exactly, up to the geometric stiffness; where supports hold the chords, what
    /// the structure really gives; a judged update (`Correction::Beyond`) only where it needs
    /// it. With `Correction::Every`, a solve of its own takes out the contact gaps, measured
    /// on the same update (`contact_gap_correction`). `buf` is scratch (the right-hand side's
    /// storage, assembled afresh before it is read again, so an update left plain may leave it
    /// part filled); `gap_buf` the contact gaps' (any contents). Returns a bound on the norm of
    /// the displacements added: the sum of the two solves' norms.
    pub(crate) fn take_out_stretch(
        &self,
        before: &[f64],
        (d, residue): (&mut [f64], &mut [f64]),
        (ordering, factors): (&Ordering, &BandMatrix),
        correction: Correction,
        (buf, gap_buf): (&mut Vec<f64>, &mut Vec<f64>),
    ) -> f64 {
        let at = |d: &[f64], n: usize| self.node_at(d, n);
        buf.clear();
        buf.resize(ordering.n_eq, 0.0);
        let mut any = false;
        let beams = self
            .structure
            .model
            .beams
            .iter()
            .zip(&self.structure.elements);
        for ((beam, el), eqs) in beams.zip(&ordering.beam_eqs) {
            let ChordUpdate { e, l, dc, turn } = ChordUpdate::new(
                at(before, beam.i),
                at(before, beam.j),
                at(d, beam.i),
                at(d, beam.j),
            );
            let stretched = l + e[0] * dc[0] + e[1] * dc[1];
            if turn == 0.0 || !turn.is_finite() {
                continue;
            }
            if matches!(correction, Correction::Beyond(_)) && turn.abs() > JUDGED_TURN {
                return 0.0;
            }
            // The gap from the update's chord, `stretched e + l turn n`, to the meant one,
            // `stretched (cos turn e + sin turn n)`, along e and across it (written without
            // cancellation).
            let half = (0.5 * turn).sin();
            let gap_along = -2.0 * stretched * half * half;
            let sin = turn.sin();
            let gap_across = l * (sin - turn) + (stretched - l) * sin;
            // The element's elastic forces for its end j moved by the gap, rotations held.
            let k = el.constants();
            let axial = k.ka * gap_along;
            let moment = -(k.k11 + k.k12) * gap_across / l;
            let shear = -2.0 * moment / l;
            let force = [axial * e[0] - shear * e[1], axial * e[1] + shear * e[0]];
            for (slot, value) in [
                (0, -force[0]),
                (1, -force[1]),
                (2, moment),
                (3, force[0]),
                (4, force[1]),
                (5, moment),
            ] {
                if eqs[slot] != NOT_FREE {
                    buf[eqs[slot] as usize] += value;
                }
            }
            any = true;
        }
        let needed = match correction {
            Correction::Every | Correction::Chords => any,
            Correction::Beyond(force) => any && sum_squares(buf).sqrt() > force,
        };
        // The contact gaps, measured on the update itself, before the chords move it.
        let gaps = matches!(correction, Correction::Every)
            && self.contact_gap_correction(before, d, (ordering, factors), gap_buf);
        // The two moves' norms add up to a bound on the norm of their sum.
        let mut moved = 0.0;
        if needed {
            factors.solve(buf);
            ordering.add_scaled((&mut *d, &mut *residue), 1.0, buf);
            moved += sum_squares(buf).sqrt();
        }
        if gaps {
            ordering.add_scaled((&mut *d, &mut *residue), 1.0, gap_buf);
            moved += sum_squares(gap_buf).sqrt();
        }
        moved
    }
}
