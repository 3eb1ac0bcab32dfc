//! Contact acceptance: two cantilevers pressed together at small displacement give the
//! closed-form springs-in-series force (bending plus shear), and the paper's Example 3.2 keeps every contact compressive, no node through a beam, residuals below 1e-8,
//! events in the paper's order and few Newton iterations.

use crate::common;

use tsm_contact::scene::{builtin::builtin, parse};
use tsm_contact::solver::report::ContactChange;
use tsm_contact::solver::{Event, Formulation, IncrementRecord, Silent};

const EI: f64 = 2.0e7 * 2.2e-8;
const GAE: f64 = 7.142e6 * 3.0e-4;

/// A (clamped at x = 0) and B (clamped at x = 1.63, tip at x = 0.63, a gap `gap` below A). B's
/// clamp is driven up by `lift`; B's tip touches A inside A's 7th element.
fn crossed(formulation: &str, gap: f64, lift: f64) -> String {
    format!(
        r#"(
        name: "crossed cantilevers", formulation: {formulation},
        sections: [(name: "s", E: 2.0e7, A: 3.0e-4, I: 2.2e-8, G: 7.142e6)],
        bodies: [
            (name: "A", section: "s", path: [(0.0, 0.0), (1.0, 0.0)], elements: 10, first_node: 1),
            (name: "B", section: "s", path: [(0.63, {y}), (1.63, {y})], elements: 10, first_node: 12),
        ],
        supports: [(node: 1, u: true, v: true, phi: true), (node: 22, u: true, phi: true)],
        prescribed: [(node: 22, dof: V, per_step: {lift})],
        contacts: [(nodes: [12], bodies: ["A"])],
        control: (steps: 1),
    )"#,
        y = -gap
    )
}

#[test]
fn crossed_cantilevers_act_as_springs_in_series() {
    let (gap, lift) = (2e-6, 1e-5);
    for (name, shear) in [("Timoshenko", 1.0), ("BernoulliEuler", 0.0)] {
        let sc = parse(&crossed(name, gap, lift), "crossed").unwrap();
        let mut solver = sc.solver().unwrap();
        let recs = solver.step(&mut Silent).unwrap();
        let last = recs.last().unwrap();
        assert_eq!(last.contacts.len(), 1, "{name}: one contact");
        // Closed form: A loaded at a = 0.63, B at its tip (length 1), compliances in series,
        // and for Bernoulli-Euler the contact spring of A's element (1e4 EI / l^3, l = 0.1).
        let (a, l) = (0.63, 1.0);
        let c_a = a * a * a / (3.0 * EI) + shear * a / GAE;
        let c_b = l * l * l / (3.0 * EI) + shear * l / GAE;
        let c_s = (1.0 - shear) * 0.1f64.powi(3) / (1e4 * EI);
        let exact = (lift - gap) / (c_a + c_b + c_s);
        let f = last.contacts[0].pressure;
        assert!(
            ((f - exact) / exact).abs() < 1e-6,
            "{name}: contact force {f} vs closed form {exact}"
        );
        // The reaction at B's driven clamp carries the same force.
        let rv = last
            .reactions
            .iter()
            .find(|r| r.node == 22 && r.dof == "v")
            .unwrap()
            .value;
        assert!(
            ((rv.abs() - exact) / exact).abs() < 1e-6,
            "{name}: clamp reaction {rv}"
        );
    }
}

fn run_example_3_2(steps: usize) -> Vec<IncrementRecord> {
    let sc = builtin("example_3_2").unwrap().unwrap();
    assert_eq!(sc.model.formulation, Formulation::Timoshenko);
    let mut solver = sc.solver().unwrap();
    let mut out = Vec::new();
    for _ in 0..steps {
        let recs = solver.step(&mut Silent).expect("converges");
        // Every active contact node lies on its beam's deformed shape, sunk into it by the
        // contact spring alone: Yc l^3 / (1e4 EI), here l = 0.1 m and EI = 0.44 N m^2, which
        // is Yc l^2 / (1e4 EI) element lengths.
        let gaps = solver
            .contacts()
            .active_gaps(&solver.view(), solver.displacements());
        let last = recs.last().expect("an increment");
        let sink = |yc: f64| yc.abs() * 0.01 / (1e4 * 0.44) + 1e-9;
        for (g, c) in gaps.iter().zip(&last.contacts) {
            assert!(g.abs() <= sink(c.force), "gap {g:e} with Yc {:e}", c.force);
        }
        for r in &recs {
            // Every converged increment: contacts compressive, nobody through a beam.
            for c in &r.contacts {
                assert!(
                    c.pressure >= 0.0,
                    "increment {}: tensile contact {c:?}",
                    r.increment
                );
            }
            let pen = r.max_penetration;
            assert!(
                pen < 1e-9,
                "increment {}: penetration {pen:e} of an element length",
                r.increment
            );
            assert!(
                r.relative_residual <= 1e-8,
                "increment {}: residual {:e}",
                r.increment,
                r.relative_residual
            );
        }
        out.extend(recs);
    }
    common::assert_audited(&sc, &out);
    out
}

fn contact_events(recs: &[IncrementRecord]) -> Vec<(ContactChange, u32, String, usize)> {
    recs.iter()
        .flat_map(|r| r.events.iter())
        .filter_map(|e| match e {
            Event::Contact(c) => Some((c.change, c.node, c.body.clone(), c.element)),
            _ => None,
        })
        .collect()
}

#[test]
fn example_3_2_events_in_the_papers_order_and_a_stress_free_end() {
    let recs = run_example_3_2(80);
    let ev = contact_events(&recs);
    let at = |change: ContactChange, node: u32, body: &str| {
        ev.iter()
            .position(|(c, n, b, _)| *c == change && *n == node && b == body)
            .unwrap_or_else(|| panic!("no {change:?} of node {node} on {body}: {ev:?}"))
    };
    use ContactChange::*;
    // The paper's order: pin touches A; node 11 touches B; node 12 touches C; node 12 passes
    // node 30 (transfer from C's element 29-30, index 26, to 30-31, index 27); the pin slides off
    // A onto B (A's tip lets go of B), off B onto C (B's tip lets go of C), and off C.
    let order = [
        at(Activated, 34, "A"),
        at(Activated, 11, "B"),
        at(Activated, 12, "C"),
        ev.iter()
            .position(|(c, n, b, e)| *c == Transferred && *n == 12 && b == "C" && *e == 27)
            .expect("node 12 passes node 30"),
        at(SlidOff, 34, "A"),
        at(Activated, 34, "B"),
        at(Released, 11, "B"),
        at(SlidOff, 34, "B"),
        at(Activated, 34, "C"),
        at(Released, 12, "C"),
        at(SlidOff, 34, "C"),
    ];
    assert!(
        order.windows(2).all(|w| w[0] < w[1]),
        "events out of order: {order:?} in {ev:?}"
    );
    // Every contact released; the end state is stress-free (element forces below 1e-9 of peak).
    let last = recs.last().unwrap();
    assert!(last.contacts.is_empty());
    let peak = recs
        .iter()
        .flat_map(|r| r.element_forces.iter().flatten())
        .fold(0.0f64, |m, v| m.max(v.abs()));
    let end = last
        .element_forces
        .iter()
        .flatten()
        .fold(0.0f64, |m, v| m.max(v.abs()));
    assert!(end < 1e-9 * peak, "end forces {end:e}, peak {peak:e}");
}

#[test]
fn example_3_2_newton_iterations_beat_the_paper() {
    let recs = run_example_3_2(80);
    let median = |mut v: Vec<usize>| {
        v.sort();
        v[v.len() / 2]
    };
    // Iterations to cut the unbalanced force by 8 orders (the paper's measure: 9 and 12).
    let quiet: Vec<usize> = recs
        .iter()
        .filter(|r| r.events.is_empty())
        .map(|r| r.iterations_8_orders.unwrap_or(r.iterations))
        .collect();
    let busy: Vec<usize> = recs
        .iter()
        .filter(|r| !r.events.is_empty())
        .map(|r| r.iterations)
        .collect();
    assert!(
        median(quiet.clone()) <= 5,
        "increments without events: {quiet:?}"
    );
    assert!(
        quiet.iter().all(|&n| n <= 8),
        "increments without events: {quiet:?}"
    );
    assert!(
        median(busy.clone()) <= 12,
        "increments with events: {busy:?}"
    );
}

/// A pin driven down onto a cantilever near its tip until the cantilever slips off.
fn pin_across(n: usize) -> Vec<IncrementRecord> {
    let text = format!(
        r#"(
        name: "pin across a cantilever", formulation: Timoshenko,
        sections: [(name: "strip", E: 2.0e7, A: 3.0e-4, I: 2.2e-8, G: 7.142e6)],
        nodes: [(id: 1000, x: 0.87, y: 0.001, rotation: false)],
        bodies: [(name: "beam", section: "strip", path: [(0.0, 0.0), (1.0, 0.0)], elements: {n}, first_node: 1)],
        supports: [(node: 1, u: true, v: true, phi: true), (node: 1000, u: true)],
        prescribed: [(node: 1000, dof: V, per_step: -0.01)],
        contacts: [(nodes: [1000], bodies: ["beam"])],
        control: (steps: 50),
    )"#
    );
    let sc = parse(&text, "pin-across").unwrap();
    let mut solver = sc.solver().unwrap();
    let mut out = Vec::new();
    for _ in 0..50 {
        out.extend(solver.step(&mut Silent).expect("converges"));
    }
    common::assert_audited(&sc, &out);
    for r in &out {
        for c in &r.contacts {
            assert!(
                c.pressure >= 0.0,
                "n {n}, increment {}: tensile {c:?}",
                r.increment
            );
        }
        assert!(r.max_penetration < 1e-9, "n {n}, increment {}", r.increment);
        assert!(
            r.relative_residual <= 1e-8,
            "n {n}, increment {}: residual {:e} (floor {:e})",
            r.increment,
            r.relative_residual,
            r.roundoff_floor
        );
    }
    out
}

#[test]
fn pin_reaction_converges_under_refinement_and_slip_off_depth_is_mesh_independent() {
    let runs: Vec<Vec<IncrementRecord>> = [10, 20, 40, 80].iter().map(|&n| pin_across(n)).collect();
    let reaction = |recs: &[IncrementRecord], depth: f64| {
        let r = recs
            .iter()
            .find(|r| (r.prescribed[0] + depth).abs() < 1e-9)
            .expect("increment at depth");
        let of = |dof: &str| {
            r.reactions
                .iter()
                .find(|x| x.node == 1000 && x.dof == dof)
                .unwrap()
                .value
        };
        (of("u"), of("v"))
    };
    for depth in [0.1, 0.2, 0.3, 0.4] {
        let r: Vec<(f64, f64)> = runs.iter().map(|recs| reaction(recs, depth)).collect();
        // The magnitude of the pin reaction (= |Yc|) converges as O(h^2): successive differences
        // fall about 4x per halving (observed 3.1 to 4.2; order >= 1.5 required).
        let mag: Vec<f64> = r.iter().map(|(u, v)| u.hypot(*v)).collect();
        for k in 0..2 {
            let ratio = (mag[k] - mag[k + 1]) / (mag[k + 1] - mag[k + 2]);
            assert!(
                (2.8..5.7).contains(&ratio),
                "depth {depth}: |R| = {mag:?}, ratio {ratio}"
            );
        }
        // Its direction does not: the force is normal to the surface the element's end
        // rotations interpolate, not to the deflected beam at c, an O(h) error that changes
        // with where c falls in its element (about 1e-5 of the force on every mesh here, with
        // no trend above it). The components still agree: within 1e-4 relative of the finest
        // mesh at 40 elements.
        for comp in [0, 1] {
            let c: Vec<f64> = r
                .iter()
                .map(|x| if comp == 0 { x.0 } else { x.1 })
                .collect();
            let e: Vec<f64> = c[..3].iter().map(|v| (v - c[3]).abs()).collect();
            assert!(
                e[2] < 1e-4 * mag[3],
                "depth {depth}: component {comp}: {c:?}"
            );
        }
    }
    // Slip-off: the last increment in contact is the same for every mesh.
    let last_contact: Vec<f64> = runs
        .iter()
        .map(|recs| {
            recs.iter()
                .rfind(|r| !r.contacts.is_empty())
                .unwrap()
                .prescribed[0]
        })
        .collect();
    assert!(
        last_contact.windows(2).all(|w| (w[0] - w[1]).abs() < 1e-12),
        "slip-off depths {last_contact:?}"
    );
    for recs in &runs {
        assert!(
            recs.last().unwrap().contacts.is_empty(),
            "the pin must end free"
        );
    }
}

/// B's tip starts exactly on A (gap 0), B inclined above A; B's clamp is driven down.
fn touching(gap: f64) -> IncrementRecord {
    let text = format!(
        r#"(
        name: "touching", formulation: Timoshenko,
        sections: [(name: "s", E: 2.0e7, A: 3.0e-4, I: 2.2e-8, G: 7.142e6)],
        bodies: [
            (name: "A", section: "s", path: [(0.0, 0.0), (1.0, 0.0)], elements: 10, first_node: 1),
            (name: "B", section: "s", path: [(0.63, {gap}), (1.5, 0.3)], elements: 10, first_node: 12),
        ],
        supports: [(node: 1, u: true, v: true, phi: true), (node: 22, u: true, phi: true)],
        prescribed: [(node: 22, dof: V, per_step: -0.02)],
        contacts: [(node_bodies: ["B"], bodies: ["A"])],
        control: (steps: 3),
    )"#
    );
    last_of_steps(&text, 3)
}

/// Run `steps` steps of a scene, checking that no node is through a beam at any converged
/// increment; the last increment.
fn last_of_steps(text: &str, steps: usize) -> IncrementRecord {
    let sc = parse(text, "scene").unwrap();
    let mut solver = sc.solver().unwrap();
    let mut last = None;
    for _ in 0..steps {
        let recs = solver.step(&mut Silent).expect("converges");
        assert!(recs.iter().all(|r| r.max_penetration < 1e-9));
        last = recs.last().cloned();
    }
    last.unwrap()
}

#[test]
fn a_node_starting_on_a_beam_takes_the_side_of_its_own_beam() {
    // Exactly touching: the side comes from B's next node (above A). The reference is the same
    // scene with a 1e-9 m gap, where the side is measured directly.
    let (on, near) = (touching(0.0), touching(1e-9));
    assert_eq!(on.contacts.len(), 1, "the touching tip must be in contact");
    assert_eq!(near.contacts.len(), 1);
    let (f0, f1) = (on.contacts[0].pressure, near.contacts[0].pressure);
    assert!(
        f0 > 0.0 && ((f0 - f1) / f1).abs() < 1e-5,
        "pressure {f0} vs {f1}"
    );
}

/// The comb (50 teeth of 20 elements, 50 pins, every pin a candidate on every tooth): 50 contacts
/// carry load at once, every increment converges, every pin slides off its tooth and reaches the
/// next one. The broad phase must not change anything: a 10-tooth comb solved with and without
/// it gives the same contacts and positions (to round-off).
#[test]
fn comb_brushes_fifty_teeth_and_broad_phase_changes_nothing() {
    use tsm_contact::scene::builtin::builtin;
    let sc = builtin("comb").unwrap().unwrap();
    let mut solver = sc.solver().unwrap();
    let mut most = 0;
    let mut slid_off = 0;
    for _ in 0..sc.steps {
        for r in solver.step(&mut Silent).expect("comb step") {
            assert!(r.relative_residual <= 1e-8);
            most = most.max(r.contacts.iter().filter(|c| c.pressure > 0.0).count());
            slid_off += r
                .events
                .iter()
                .filter(|e| matches!(e, Event::Contact(c) if c.change == ContactChange::SlidOff))
                .count();
        }
    }
    assert_eq!(most, 50);
    assert_eq!(slid_off, 50);
    // At the end, 49 pins press on the next tooth (the last pin has none).
    assert_eq!(solver.contacts().beams.active.len(), 49);

    let text = tsm_contact::scene::builtin::BUILTIN
        .iter()
        .find(|(f, _)| *f == "comb.ron")
        .unwrap()
        .1;
    // Ten teeth: drop teeth 11-50 and their pins from every list.
    let keep = |line: &str| {
        let big = (11..=50).any(|k| {
            line.contains(&format!("\"tooth {k}\", section"))
                || line.contains(&format!("(node: {}, u: true", 1 + 21 * (k - 1)))
                || line.contains(&format!("id: {}", 5000 + k))
                || line.contains(&format!("(node: {}, dof: U", 5000 + k))
        });
        !big
    };
    let mut small: String = text
        .lines()
        .filter(|l| keep(l))
        .collect::<Vec<_>>()
        .join("\n");
    let pins: Vec<String> = (1..=10).map(|k| (5000 + k).to_string()).collect();
    let teeth: Vec<String> = (1..=10).map(|k| format!("\"tooth {k}\"")).collect();
    let start = small.find("contacts: [").unwrap();
    let end = start + small[start..].find("\n").unwrap();
    small.replace_range(
        start..end,
        &format!(
            "contacts: [(nodes: [{}], bodies: [{}])],",
            pins.join(", "),
            teeth.join(", ")
        ),
    );
    let run = |broad: bool| {
        let sc = tsm_contact::scene::parse(&small, "comb10").unwrap();
        let mut s = sc.solver().unwrap();
        s.params_mut().broad_phase = broad;
        let mut out = Vec::new();
        for _ in 0..sc.steps {
            out.extend(s.step(&mut Silent).unwrap());
        }
        out
    };
    let (with, without) = (run(true), run(false));
    assert_eq!(with.len(), without.len());
    for (a, b) in with.iter().zip(&without) {
        assert_eq!(a.contacts.len(), b.contacts.len());
        for (p, q) in a.nodes.iter().zip(&b.nodes) {
            assert!((p[0] - q[0]).abs() < 1e-12 && (p[1] - q[1]).abs() < 1e-12);
        }
    }
}

/// Stacked beams: nearly every node touches at the first increment and nearly all must let go
/// again (an active set that can cycle there, and node-on-node pairs that would make the
/// tangent singular). Small-deflection theory: by point symmetry the beams touch at x = L/2 only, where
/// A has a node, and each acts as a cantilever loaded there: force (d - gap) / (2 c) with
/// c = a^3/(3 EI) + a/(G Ae), a = L/2. Tolerance 1e-4 (the geometric nonlinearity at d/L =
/// 2.5e-4 is far below it).
#[cfg(feature = "reports")]
#[test]
fn stacked_beams_touch_at_one_point_with_the_closed_form_force() {
    let (d, gap, a) = (1e-3, 1e-4, 2.0);
    let exact = (d - gap) / (2.0 * (a * a * a / (3.0 * EI) + a / GAE));
    for b_elements in [16, 17] {
        // The scene of the stability suite: B with 16 elements puts its nodes straight under
        // A's (node on node), 17 between them; A's clamp driven down d in 4 steps.
        let run = tsm_contact::reports::stress::stacked(b_elements, Formulation::Timoshenko);
        assert!(run.row.converged, "{:?}", run.row.error);
        assert!(run.records.iter().all(|r| r.max_penetration < 1e-9));
        let last = run.records.last().unwrap();
        let loaded: Vec<_> = last.contacts.iter().filter(|c| c.pressure > 0.0).collect();
        let total: f64 = loaded.iter().map(|c| c.pressure).sum();
        assert!(
            ((total - exact) / exact).abs() < 1e-4,
            "B with {b_elements} elements: contact force {total} vs closed form {exact}"
        );
        // All of it at A's middle node 9 (x = 2), or at B's node right under it.
        for c in &loaded {
            assert!(
                c.node == 9 || (b_elements == 16 && c.node == 109),
                "B with {b_elements} elements: load at node {}",
                c.node
            );
        }
    }
}

/// Pins pressing and sliding on one long bed (`tsm-contact scale --contact`): the element grid
/// hands each probe only the elements near the pin, and must find exactly what probing every
/// element of the bed finds. Reference: the same run with the broad phase off, to 1e-12 m.
#[cfg(feature = "reports")]
#[test]
fn element_grid_finds_what_probing_every_element_finds() {
    let mut runs = [true, false].map(|bp| {
        let mut s = tsm_contact::reports::contact_scaling::pins_on_bed(200, bp);
        let mut recs = Vec::new();
        for _ in 0..3 {
            recs.extend(s.step(&mut Silent).expect("converges"));
        }
        recs
    });
    let (off, on) = (runs[1].split_off(0), runs[0].split_off(0));
    assert_eq!(on.len(), off.len());
    let last = on.last().unwrap();
    assert_eq!(
        last.contacts.iter().filter(|c| c.pressure > 0.0).count(),
        20
    );
    for (a, b) in on.iter().zip(&off) {
        let ca: Vec<_> = a.contacts.iter().map(|c| (c.node, c.element)).collect();
        let cb: Vec<_> = b.contacts.iter().map(|c| (c.node, c.element)).collect();
        assert_eq!(ca, cb, "increment {}", a.increment);
        for (p, q) in a.nodes.iter().zip(&b.nodes) {
            assert!((p[0] - q[0]).abs() < 1e-12 && (p[1] - q[1]).abs() < 1e-12);
        }
    }
}
