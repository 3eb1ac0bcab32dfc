//! The step-range test of the acceptance check: within one increment, no beam element turns
//! against its chord by more than `MAX_TURN_STEP` at either end, nor changes its axial strain by
//! more than `MAX_STRAIN_STEP`. Newton can converge, within one increment, to an equilibrium of
//! the discrete model far from the path (a chain folded flat, its elements stretched by a
//! quarter and turned by radians against their chords). Such a state satisfies the equations
//! but is not where the structure goes: it is refused and the increment cut back, so that the
//! path is followed in steps each element can take. Nor does any node turn by a half turn or
//! more (`MAX_SPIN_STEP`): a beam that comes back to its place turned whole turns is a rigid
//! motion to its elements, and no straight-line sweep between the two states can follow it.
//! How far an element is bent at one state (`most_bent`) bounds a snap's path.

use super::chord::{wrapped, Chord};
use crate::solver::element::beam::BeamElement;
use crate::solver::model::Model;
use crate::solver::report::NodeState;

/// The largest change, within one increment, of an element's end rotation against its chord
/// (rad).
pub const MAX_TURN_STEP: f64 = 0.5;

/// The largest change, within one increment, of an element's axial strain.
pub const MAX_STRAIN_STEP: f64 = 0.05;

/// The largest change of a node's rotation within one increment (rad): a half turn.
pub const MAX_SPIN_STEP: f64 = std::f64::consts::PI;

/// The node of `model` (with a rotation dof) that turns furthest beyond `MAX_SPIN_STEP` from
/// node states `before` to `after`: (node index, its turn in rad), if any does.
pub fn spun(model: &Model, before: &[NodeState], after: &[NodeState]) -> Option<(usize, f64)> {
    (0..model.nodes.len())
        .filter(|&n| model.nodes[n].rotation)
        .map(|n| (n, after[n][2] - before[n][2]))
        .filter(|(_, t)| t.abs() >= MAX_SPIN_STEP)
        .max_by(|a, b| a.1.abs().total_cmp(&b.1.abs()))
}

/// The element of `model` whose end turns furthest against its chord at node states `s`, and
/// that turn (rad; `elements`: the beams' initial geometry); (0, 0) without elements.
pub fn most_bent(model: &Model, elements: &[BeamElement], s: &[NodeState]) -> (usize, f64) {
    (elements.iter().enumerate())
        .map(|(e, el)| {
            let t = Chord::at(model, el.alpha0, e, s).turns();
            (e, wrapped(t[0]).abs().max(wrapped(t[1]).abs()))
        })
        .fold((0, 0.0), |a, b| if b.1 > a.1 { b } else { a })
}

/// An element that moves too far within one increment.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OutOfRange {
    /// Element index.
    pub element: usize,
    /// The larger change of its end rotations against the chord (rad).
    pub turn: f64,
    /// The change of its axial strain.
    pub strain: f64,
}

/// The element of `model` that moves furthest beyond the step range from node states `before`
/// to `after` (`elements`: the beams' initial geometry), if any does.
pub fn out_of_range(
    model: &Model,
    elements: &[BeamElement],
    before: &[NodeState],
    after: &[NodeState],
) -> Option<OutOfRange> {
    let mut worst: Option<(f64, OutOfRange)> = None;
    for (e, el) in elements.iter().enumerate() {
        let (k0, k1) = (
            Chord::at(model, el.alpha0, e, before),
            Chord::at(model, el.alpha0, e, after),
        );
        let (t0, t1) = (k0.turns(), k1.turns());
        let turn = wrapped(t1[0] - t0[0])
            .abs()
            .max(wrapped(t1[1] - t0[1]).abs());
        let strain = (k1.l - k0.l) / el.length;
        let excess = (turn / MAX_TURN_STEP).max(strain.abs() / MAX_STRAIN_STEP);
        if excess > 1.0 && worst.is_none_or(|(w, _)| excess > w) {
            worst = Some((
                excess,
                OutOfRange {
                    element: e,
                    turn,
                    strain,
                },
            ));
        }
    }
    worst.map(|w| w.1)
}
