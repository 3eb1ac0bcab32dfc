//! Unit tests of the Newton iteration: the reused converged assembly, the stretch correction
//! and the round-off floor's bound, each against an independent computation.

use super::stretch::Correction;
use crate::solver::assembly::Ordering;
use crate::solver::linear::BandMatrix;
use crate::solver::Silent;
use std::sync::Arc;

/// The ordering of `s`'s accepted state, its displacements and its tangent there, factored.
fn factored_at_rest(s: &crate::solver::Solver) -> (Arc<Ordering>, Vec<f64>, BandMatrix) {
    use crate::solver::assembly::assemble;
    let ord = s.newton().ordering_for(&s.state.contacts);
    let rest = s.state.d.clone();
    let mut tangent = assemble(&s.structure.context(&ord), &rest, true, None)
        .tangent
        .expect("tangent");
    tangent.factor(0.0).expect("regular");
    (ord, rest, tangent)
}

/// The predictor of a load-driven increment starts from the assembly kept at the last
/// converged state instead of assembling that state again: the increment must come out
/// identical, residual for residual and bit for bit, to one that assembles afresh.
#[test]
fn reusing_the_converged_assembly_changes_nothing() {
    let mut warm = crate::scene::builtin::long_beam(300)
        .solver()
        .expect("stable");
    warm.step(&mut Silent).expect("converges");
    let kept = |s: &crate::solver::Solver| {
        s.work
            .converged_assembly
            .0
            .borrow()
            .as_ref()
            .is_some_and(|(i, asm)| *i == s.increment() && asm.tangent.is_some())
    };
    assert!(kept(&warm), "no assembly kept at the converged state");
    let mut fresh = warm.clone();
    fresh.work.converged_assembly = Default::default();
    for _ in 0..2 {
        let a = warm.step(&mut Silent).expect("converges");
        let b = fresh.step(&mut Silent).expect("converges");
        let (a, b) = (a.last().expect("record"), b.last().expect("record"));
        assert_eq!(a.iterations, b.iterations);
        let bits = |r: &crate::solver::IncrementRecord| {
            r.residuals
                .iter()
                .map(|i| i.residual.to_bits())
                .collect::<Vec<_>>()
        };
        assert_eq!(bits(a), bits(b));
        assert_eq!(warm.state.d, fresh.state.d);
        fresh.work.converged_assembly = Default::default();
    }
}

/// The stretch correction on a tree at rest (its tangent the elastic stiffness): a linear
/// update that turns every chord by its own angle (up to 0.3 rad; the update alone leaves
/// the chords up to 4.4% too long and turned by atan t) comes out with every chord at its
/// length and turned by exactly its angle, to 1e-12. Bernoulli-Euler (Mattiasson's
/// cantilever) and Timoshenko (the pin's cantilever, G = 0.4 E) elements.
#[test]
fn stretch_correction_turns_the_chords_of_a_tree_exactly() {
    for scene in ["mattiasson", "pin_on_cantilever"] {
        let s = crate::test_support::solver_after(scene, 0);
        let (ord, rest, tangent) = factored_at_rest(&s);
        let first = &s.structure.dofs.first;
        let at = |d: &[f64], n: usize| {
            let node = &s.structure.model.nodes[n];
            [node.x + d[first[n]], node.y + d[first[n] + 1]]
        };
        let turns: Vec<f64> = (0..s.structure.model.beams.len())
            .map(|e| 0.3 * (((e * 7) % 11) as f64 / 5.0 - 1.0))
            .collect();
        let mut d = rest.clone();
        let mut offset = [0.0, 0.0];
        for (b, t) in s.structure.model.beams.iter().zip(&turns) {
            let (pi, pj) = (at(&rest, b.i), at(&rest, b.j));
            offset[0] -= t * (pj[1] - pi[1]);
            offset[1] += t * (pj[0] - pi[0]);
            d[first[b.j]] = offset[0];
            d[first[b.j] + 1] = offset[1];
        }
        let chord = |d: &[f64], b: &crate::solver::Beam| {
            let (i, j) = (at(d, b.i), at(d, b.j));
            [j[0] - i[0], j[1] - i[1]]
        };
        let chords = |d: &[f64]| -> Vec<(f64, f64)> {
            let beams = s.structure.model.beams.iter();
            beams
                .map(|b| {
                    let (c0, c1) = (chord(&rest, b), chord(d, b));
                    let l0 = c0[0].hypot(c0[1]);
                    let turn = (c0[0] * c1[1] - c0[1] * c1[0]).atan2(c0[0] * c1[0] + c0[1] * c1[1]);
                    (c1[0].hypot(c1[1]) / l0 - 1.0, turn)
                })
                .collect()
        };
        let worst = |d: &[f64]| {
            (chords(d).iter().zip(&turns))
                .map(|(&(strain, turn), t)| strain.abs().max((turn - t).abs()))
                .fold(0.0f64, f64::max)
        };
        assert!(
            worst(&d) > 0.04,
            "{scene}: the update alone is off by {}",
            worst(&d)
        );
        let mut buf = Vec::new();
        let mut residue = vec![0.0; d.len()];
        s.newton().take_out_stretch(
            &rest,
            (&mut d, &mut residue),
            (&ord, &tangent),
            Correction::Every,
            (&mut buf, &mut Vec::new()),
        );
        assert!(worst(&d) < 1e-12, "{scene}: {}", worst(&d));
    }
}

/// The round-off floor's bound stands in for the floor where the floor cannot decide
/// anything; it must never fall below it. From a loaded state of the Mattiasson cantilever,
/// the coordinates move by random corrections (recorded by their largest entry) and the
/// tangent is assembled again: the bound holds at every step, and is tight (within 1e-9)
/// before any move, where the diagonal peak and the coordinate scale are exact. With a snap's
/// viscous stiffness on the diagonal (from step 10 on, a thousand times the tangent's peak),
/// both count it, and the floor grows by eps times it.
#[test]
fn the_floor_bound_never_falls_below_the_floor() {
    use super::convergence::FloorBound;
    use crate::solver::assembly::assemble;
    let s = crate::test_support::solver_after("mattiasson", 3);
    let ord = s.newton().ordering_for(&s.state.contacts);
    let mut d = s.state.d.clone();
    let mut bound = FloorBound::new(s.structure.coordinate_scale(&d));
    let mut rng = crate::test_support::Rng(0x5eed_f100);
    for step in 0..20 {
        let asm = assemble(&s.structure.context(&ord), &d, true, None);
        let tangent = asm.tangent.expect("tangent");
        let reference = 3.0;
        if step == 10 {
            bound.add_diagonal(1e3 * tangent.max_diagonal());
        }
        let extra = bound.extra_diagonal();
        let (scale, floor) = s.newton().roundoff_floor(&tangent, &d, reference, extra);
        let (_, plain) = s.newton().roundoff_floor(&tangent, &d, reference, 0.0);
        let grown = f64::EPSILON * extra * scale / reference;
        assert!(
            (floor - plain - grown).abs() <= 1e-12 * floor,
            "step {step}"
        );
        let (scale_bound, floor_bound) = bound.get(&tangent, reference);
        assert!(scale <= scale_bound && floor <= floor_bound, "step {step}");
        if step == 0 {
            assert!(
                floor_bound <= floor * (1.0 + 1e-9),
                "{floor_bound} vs {floor}"
            );
        }
        let size = 0.05 * (step % 4) as f64;
        let mut largest = 0.0f64;
        for v in d.iter_mut() {
            let dv = size * (rng.unit() - 0.5);
            *v += dv;
            largest = largest.max(dv.abs());
        }
        bound.moved(largest);
    }
}

/// A pass at the round-off floor is told stalled after one iteration without halving its
/// residual where the correction before it was round-off itself (16 units in the last place of
/// the coordinates in each of its entries: a norm of 16 eps sqrt(n) times their size), and
/// after three where the correction was larger.
#[test]
fn a_stall_is_told_after_one_iteration_once_the_correction_is_round_off() {
    use super::convergence::Stall;
    let (floor, n_eq, scale) = (1e-9, 100, 2.0);
    let roundoff = 16.0 * f64::EPSILON * 10.0 * scale;
    let at_floor = [1.0e-8, 1.1e-8, 0.9e-8, 1.2e-8];
    let mut stall = Stall::new();
    assert!(!stall.at_floor(at_floor[0], floor, n_eq, 1e-6, scale));
    assert!(stall.at_floor(at_floor[1], floor, n_eq, 0.9 * roundoff, scale));
    // Corrections that do not contract: the extrapolation says nothing.
    let mut stall = Stall::new();
    assert!(!stall.at_floor(at_floor[0], floor, n_eq, 1.1 * roundoff, scale));
    for (k, &rel) in at_floor[1..].iter().enumerate() {
        let told = stall.at_floor(rel, floor, n_eq, 1.1 * roundoff, scale);
        assert_eq!(told, k == 2, "iteration {} after the first", k + 1);
    }
}

/// A pass whose corrections contract so fast that the next one, extrapolated at their rate
/// (`step^2 / previous`), would be round-off is told stalled after one iteration without
/// halving its residual; not where the residual has just halved (a residual in the stiff
/// directions of contact still falls while the corrections are tiny), nor where the
/// extrapolated correction is larger, the corrections grow, the last correction is above
/// `STALL_STEP` (1e-10) of the coordinates, or the residual lies beyond the floor's band.
#[test]
fn a_stall_is_told_once_the_next_correction_would_be_round_off() {
    use super::convergence::Stall;
    let (floor, n_eq, scale) = (1e-9, 100, 2.0);
    let roundoff = 16.0 * f64::EPSILON * 10.0 * scale;
    // 1e-6, then 1e-12: the next would be 1e-18, far below round-off (7e-14).
    let mut stall = Stall::new();
    assert!(!stall.at_floor(4.0e-8, floor, n_eq, 1e-6, scale));
    assert!(stall.at_floor(3.0e-8, floor, n_eq, 1e-12, scale));
    // The same corrections, the residual halved.
    let mut stall = Stall::new();
    assert!(!stall.at_floor(4.0e-8, floor, n_eq, 1e-6, scale));
    assert!(!stall.at_floor(1.5e-8, floor, n_eq, 1e-12, scale));
    // 1e-6, then 3e-9: the next would be 9e-12, above it.
    let mut stall = Stall::new();
    assert!(!stall.at_floor(4.0e-8, floor, n_eq, 1e-6, scale));
    assert!(!stall.at_floor(3.0e-8, floor, n_eq, 3e-9, scale));
    // The first correction of a pass has nothing to extrapolate from.
    let mut stall = Stall::new();
    assert!(!stall.at_floor(3.0e-8, floor, n_eq, 2.0 * roundoff, scale));
    // 1, then 1e-7: the next would be 1e-14, but the correction has not vanished.
    let mut stall = Stall::new();
    assert!(!stall.at_floor(4.0e-8, floor, n_eq, 1.0, scale));
    assert!(!stall.at_floor(3.0e-8, floor, n_eq, 1e-7, scale));
    // Growing corrections do not extrapolate.
    let mut stall = Stall::new();
    assert!(!stall.at_floor(4.0e-8, floor, n_eq, 1e-13, scale));
    assert!(!stall.at_floor(3.0e-8, floor, n_eq, 2.0 * roundoff, scale));
    // A residual beyond STAGNATION sqrt(n) times the floor is not round-off.
    let mut stall = Stall::new();
    assert!(!stall.at_floor(4.0e-6, floor, n_eq, 1e-6, scale));
    assert!(!stall.at_floor(3.0e-6, floor, n_eq, 1e-12, scale));
}

/// The contact gap correction on the pin's cantilever in contact (16 and 64 elements, after 6
/// steps): a linear update that slides the beam under the pin by 0.2 of an element and turns
/// the contact element's chord and every element beyond it by 6 mrad leaves the pin off its
/// linearised offset from the turned chord (w - li turn) by about 0.2 l times the turn. With
/// the chords alone corrected it stays at least half as far off; with the contact gaps taken
/// out in the same solve it ends within 10% of that error on 16 elements and 4% on 64 (what
/// is left falls with the element: the beam around it takes a share of the gap's force that
/// shrinks as the element's stiffness against its contact force grows).
#[test]
fn the_contact_gap_correction_puts_a_sliding_node_at_its_linearised_offset() {
    for (n, within) in [(16, 0.1), (64, 0.04)] {
        let mut s = crate::scene::builtin::with_elements("pin_on_cantilever.ron", n)
            .expect("one body")
            .expect("valid")
            .solver()
            .expect("stable");
        for _ in 0..6 {
            s.step(&mut Silent).expect("converges");
        }
        let contact = *s
            .state
            .contacts
            .beams
            .active
            .first()
            .expect("the pin rests on the beam");
        let (ord, rest, tangent) = factored_at_rest(&s);
        let first = &s.structure.dofs.first;
        let model = &s.structure.model;
        let at = |d: &[f64], n: usize| {
            [
                model.nodes[n].x + d[first[n]],
                model.nodes[n].y + d[first[n] + 1],
            ]
        };
        let beam = &model.beams[contact.beam];
        // The offset of the pin from the element's chord, and its place along it.
        let offset = |d: &[f64]| {
            let (i, j, c) = (at(d, beam.i), at(d, beam.j), at(d, contact.node));
            let chord = [j[0] - i[0], j[1] - i[1]];
            let l = chord[0].hypot(chord[1]);
            let a = [c[0] - i[0], c[1] - i[1]];
            (
                (chord[0] * a[1] - chord[1] * a[0]) / l,
                (chord[0] * a[0] + chord[1] * a[1]) / l,
                l,
            )
        };
        let (w, li, l) = offset(&rest);
        let xi = li / l;
        let (pi, pj) = (at(&rest, beam.i), at(&rest, beam.j));
        let t = [(pj[0] - pi[0]) / l, (pj[1] - pi[1]) / l];
        let ds = if xi < 0.5 { 0.2 * l } else { -0.2 * l };
        let turn = 6e-3;
        // The update: every node from the element's end i on toward the tip slid back by ds along
        // the chord and turned by `turn` about i, linearly; the pin held.
        let mut d = rest.clone();
        let from = beam.i.min(beam.j);
        for n in (0..model.nodes.len()).filter(|&n| n >= from && n != contact.node) {
            let p = at(&rest, n);
            let r = [p[0] - pi[0], p[1] - pi[1]];
            d[first[n]] += -ds * t[0] - turn * r[1];
            d[first[n] + 1] += -ds * t[1] + turn * r[0];
            if model.nodes[n].rotation {
                d[first[n] + 2] += turn;
            }
        }
        let linearised = w - li * turn;
        let error = |d: &[f64]| (offset(d).0 - linearised).abs();
        let plain = error(&d);
        assert!(
            plain > 0.5 * ds.abs() * turn && plain < 2.0 * ds.abs() * turn,
            "the update alone: {plain:.3e} off, against ds turn = {:.3e}",
            ds.abs() * turn
        );
        let corrected = |correction: Correction| {
            let mut d = d.clone();
            let mut buf = Vec::new();
            let mut residue = vec![0.0; d.len()];
            s.newton().take_out_stretch(
                &rest,
                (&mut d, &mut residue),
                (&ord, &tangent),
                correction,
                (&mut buf, &mut Vec::new()),
            );
            error(&d)
        };
        let chords = corrected(Correction::Chords);
        assert!(
            chords > 0.5 * plain,
            "chords alone: {chords:.3e} of {plain:.3e}"
        );
        let every = corrected(Correction::Every);
        assert!(
            every < within * plain,
            "{n} elements, with the contact gaps: {every:.3e} of {plain:.3e}"
        );
    }
}

/// A chattering attempt is located at the contact with the most changes among its events,
/// counted here by hand: node 12 on the cantilever's element 30 touches, lets go and touches
/// again (3), node 5 on the same element slips twice (2); obstacle events count apart from beam
/// ones.
#[test]
fn chattering_names_the_contact_that_changed_most() {
    use super::failure::Chatter;
    use crate::solver::report::{ContactChange, ContactEvent, Event, ObstacleEvent};
    let solver = (crate::scene::builtin::builtin("rolled_past_a_turn"))
        .expect("a built-in scene")
        .expect("valid")
        .solver()
        .expect("stable");
    let model = &solver.structure.model;
    let beam = |node: u32, change: ContactChange| {
        Event::Contact(ContactEvent {
            change,
            increment: 1,
            iteration: 0,
            node,
            element: 29,
            body: "cantilever".into(),
            xi: 0.0,
            force: 0.0,
        })
    };
    let floor = Event::Obstacle(ObstacleEvent {
        change: ContactChange::Activated,
        increment: 1,
        iteration: 0,
        node: 12,
        obstacle: "floor".into(),
        force: 0.0,
    });
    let events = [
        beam(5, ContactChange::Slips),
        beam(12, ContactChange::Activated),
        floor.clone(),
        beam(12, ContactChange::Released),
        beam(5, ContactChange::Slips),
        floor,
        beam(12, ContactChange::Activated),
    ];
    let most = Chatter::most_changed(&events, model).expect("contact events");
    assert_eq!(
        most,
        Chatter {
            node: 12,
            surface: "cantilever element 30".into(),
            changes: 3,
            kinds: vec![ContactChange::Activated, ContactChange::Released],
        }
    );
    assert_eq!(
        most.to_string(),
        "3 of them by node 12 on cantilever element 30 (touches, releases from)"
    );
    assert_eq!(Chatter::most_changed(&events[..0], model), None);
}
