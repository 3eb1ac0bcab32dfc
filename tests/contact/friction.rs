//! Coulomb friction at node-to-beam contacts, against independent references: the friction
//! element's tangent against central differences of its nodal forces, in stick and in slip; a
//! pin dragged to and fro along a bar against the hand calculation of its hysteresis loop; a
//! strip pulled on a frictional floor (of beams, and a rigid obstacle) against the closed form
//! of a bar on a frictional support; a band slipping over a frictional drum against the
//! capstan equation; Example 3.2 with mu = 0 against its frictionless history, bit for bit, and
//! with mu = 0.3 against the friction law and the frictionless iteration count; the friction
//! of a node on an obstacle against central differences; and the acceptance check of the
//! friction law against states made to break it.

use crate::common;

use nalgebra::DMatrix;
use tsm_contact::scene::builtin::BUILTIN;
use tsm_contact::scene::parse;
use tsm_contact::solver::acceptance::{friction_law, FrictionRecord};
use tsm_contact::solver::element::beam::BeamElement;
use tsm_contact::solver::element::contact_element::ContactOptions;
use tsm_contact::solver::element::contact_law::contact_outcome;
use tsm_contact::solver::element::friction::{obstacle_friction, Grip, ObstacleGrip, Traction};
use tsm_contact::solver::report::ContactState;
use tsm_contact::solver::{
    ContactChange, Event, Friction, IncrementRecord, Section, Shape, Silent, SolverParams,
};

/// Nodal forces and tangent of a Timoshenko contact element with one frictional contact, at
/// dofs `x` = (u_i, v_i, phi_i, u_j, v_j, phi_j, x_c, y_c) as positions and rotations.
fn response(el: &BeamElement, x: &[f64; 8], grip: Grip) -> (Vec<f64>, DMatrix<f64>, bool) {
    let (pi, pj, pc) = ([x[0], x[1]], [x[3], x[4]], [x[6], x[7]]);
    let opts = ContactOptions::default();
    let out = contact_outcome(el, (pi, pj), [x[2], x[5]], &[pc], opts, &[Some(grip)], true);
    let r = out.response;
    let t = out.friction[0].expect("frictional");
    // The mode evaluated is the one the return mapping asks for.
    assert_eq!(t.mode(grip.slip, false, 0.0), grip.slip);
    let slipping = t.slipping;
    (
        r.nodal.iter().copied().collect(),
        r.tangent.unwrap(),
        slipping,
    )
}

#[test]
fn friction_tangent_matches_central_differences_in_stick_and_slip() {
    let s = Section {
        ea: 6.0e3,
        ei: 4.4e-4,
        gae: 2.1e3,
        thickness: 0.0,
    };
    let len = 0.1;
    let el = BeamElement::new([0.0, 0.0], [len, 0.0], s, s.ei / s.gae);
    // A turned, bent and stretched element with the node pressed into it (side +1: the node
    // came from above, so a downward deflection at c is compressive).
    let (rot, t) = (0.6f64, [0.2, -0.1]);
    let (c, sn) = (rot.cos(), rot.sin());
    let map = |p: [f64; 2]| [t[0] + c * p[0] - sn * p[1], t[1] + sn * p[0] + c * p[1]];
    let (pi, pj) = (map([0.0, 0.0]), map([len * 1.001, 0.0]));
    let pc = map([0.4 * len, -5e-2 * len]);
    let x = [
        pi[0],
        pi[1],
        rot + 0.01,
        pj[0],
        pj[1],
        rot - 0.02,
        pc[0],
        pc[1],
    ];
    // Stick: the stick point a little behind the node; slip: far behind it.
    for (stick, expect_slip) in [(0.4002, false), (0.2, true)] {
        let grip = Grip {
            mu: 0.3,
            stiffness: 0.01 * s.ea / len,
            stick,
            span: -len,
            side: 1.0,
            slip: expect_slip.then_some(-1.0),
            face: 0.0,
            roll: 0.0,
            turn: None,
            rolled: (0.0, 0.0),
        };
        let (f0, k, slipping) = response(&el, &x, grip);
        assert_eq!(slipping, expect_slip, "stick point {stick}");
        let h = 1e-7 * len;
        let mut fd = DMatrix::zeros(8, 8);
        for q in 0..8 {
            let (mut xp, mut xm) = (x, x);
            xp[q] += h;
            xm[q] -= h;
            let (fp, _, sp) = response(&el, &xp, grip);
            let (fm, _, sm) = response(&el, &xm, grip);
            assert_eq!((sp, sm), (slipping, slipping));
            for p in 0..8 {
                fd[(p, q)] = (fp[p] - fm[p]) / (2.0 * h);
            }
        }
        let scale = k.abs().max();
        let err = (&k - &fd).abs().max() / scale;
        assert!(
            err < 1e-6,
            "stick point {stick}: tangent off by {err:e} of {scale:e}"
        );
        assert!(f0.iter().all(|v| v.is_finite()));
    }
}

/// A pin pressed onto a clamped bar whose nodes are held along it, then dragged along the
/// bar and back twice: the hand calculation of the loop. The stick spring kt is the only
/// tangential compliance (the bar's nodes cannot move along it), so while the pin sticks its
/// friction force changes by -kt per metre dragged; it slips at mu N, against the drag; after a
/// reversal it sticks until it has been dragged 2 mu N / kt back; and the second loop retraces
/// the first. The bar bends by a ten-thousandth of its length, so that the moment of
/// the friction force about the bar's axis, which the hand calculation leaves out, stays below
/// its tolerance.
#[test]
fn a_pin_dragged_along_a_bar_traces_the_hand_calculated_hysteresis_loop() {
    let (mu, ea, le) = (0.3, 100.0, 0.25);
    let kt = SolverParams::default().friction_penalty * ea / le;
    let text = format!(
        r#"(
    name: "pin dragged along a bar",
    sections: [(name: "bar", E: {ea}, A: 1.0, I: 1.0, G: 40000.0)],
    nodes: [(id: 100, x: 0.37, y: 1.0e-5, rotation: false)],
    bodies: [(name: "bar", section: "bar", path: [(0.0, 0.0), (1.0, 0.0)], elements: 4, first_node: 1)],
    supports: [
        (node: 1, u: true, v: true, phi: true),
        (node: 2, u: true),
        (node: 3, u: true),
        (node: 4, u: true),
        (node: 5, u: true, v: true, phi: true),
    ],
    prescribed: [(node: 100, dof: V, per_step: -0.002), (node: 100, dof: U, per_step: 0.0)],
    contacts: [(nodes: [100], bodies: ["bar"], mu: {mu})],
    control: (steps: 1),
)"#
    );
    let scene = parse(&text, "drag.ron").unwrap();
    let model = scene.model.clone();
    let mut solver = scene.solver().unwrap();
    let v = -1.1e-4;
    for k in 1..=5 {
        solver
            .advance_to(&[v * k as f64 / 5.0, 0.0], &[0.0], &mut Silent)
            .unwrap();
    }
    // The drag: legs 0 -> +U -> -U -> +U, fine steps after each reversal.
    let big_u = 0.02;
    let mut path = vec![0.0];
    for &(from, to) in &[(0.0, big_u), (big_u, -big_u), (-big_u, big_u)] {
        let dir: f64 = if to > from { 1.0 } else { -1.0 };
        let mut u = from;
        for _ in 0..30 {
            u += dir * 2e-5;
            path.push(u);
        }
        while dir * (to - u) > 1e-12 {
            u = if dir * (to - u) > 2e-3 {
                u + dir * 2e-3
            } else {
                to
            };
            path.push(u);
        }
    }
    let mut states = Vec::new();
    for w in path.windows(2) {
        let records = solver.advance_to(&[v, w[1]], &[0.0], &mut Silent).unwrap();
        let r = records.last().unwrap();
        assert_eq!(
            r.contacts.len(),
            1,
            "u = {}: the pin rests on the bar",
            w[1]
        );
        // The spring acts along the chord of the element the pin rests on, at angle theta to
        // the drag: dragging the pin by du moves it along the chord by du cos(theta), that is
        // by du cos(theta) L0 / l of the bar's length, and changes the force along the chord
        // by kt (L0 / l)^2 cos(theta) du.
        let beam = &model.beams[r.contacts[0].element];
        let (a, b) = (r.nodes[beam.i], r.nodes[beam.j]);
        let l = (b[0] - a[0]).hypot(b[1] - a[1]);
        let stretch = (le / l).powi(2) * (b[0] - a[0]) / l;
        states.push((w[1], w[1] - w[0], r.contacts[0].clone(), stretch));
    }
    let mut checked = [0usize; 3];
    let mut reversal = None;
    for k in 0..states.len() {
        let (u, du, c, stretch) = &states[k];
        let kt = kt * stretch;
        let limit = mu * c.pressure;
        assert!(c.pressure > 1.0, "u = {u}: pressed ({} N)", c.pressure);
        assert!(c.tangential.abs() <= limit * (1.0 + 1e-9), "u = {u}: {c:?}");
        if k > 0 && states[k - 1].1 * du < 0.0 {
            reversal = Some((states[k - 1].0, states[k - 1].2.pressure));
        }
        match c.friction {
            Friction::Slipping => {
                // Exactly mu N, against the drag.
                assert!(
                    (c.tangential.abs() - limit).abs() <= 1e-9 * limit,
                    "u = {u}: {c:?}"
                );
                assert!(
                    c.tangential * du < 0.0,
                    "u = {u}: friction against the drag"
                );
                if let Some((at, n)) = reversal.take() {
                    // The first slip after a reversal: dragged 2 mu N / kt back, to a step.
                    let travel = (u - at).abs();
                    let hand = 2.0 * mu * n / kt;
                    assert!(
                        travel >= hand * (1.0 - 1e-4) && travel <= hand * (1.0 + 1e-4) + 2e-5,
                        "u = {u}: slips after {travel:.4e} m back, hand {hand:.4e} m"
                    );
                    checked[0] += 1;
                }
            }
            Friction::Sticking if k > 0 && states[k - 1].2.friction == Friction::Sticking => {
                let slope = (c.tangential - states[k - 1].2.tangential) / du;
                assert!(
                    (slope + kt).abs() <= 1e-4 * kt,
                    "u = {u}: sticking slope {slope:.6e}, hand -{kt:e}"
                );
                checked[1] += 1;
            }
            Friction::Sticking => {}
            Friction::Frictionless => panic!("u = {u}: frictional contact"),
        }
    }
    // The loop closes: at u = +U the second time, the state of the first time.
    let ends: Vec<&ContactState> = (states.iter())
        .filter(|s| (s.0 - big_u).abs() < 1e-12)
        .map(|s| &s.2)
        .collect();
    assert_eq!(ends.len(), 2);
    for (a, b) in [
        (ends[0].tangential, ends[1].tangential),
        (ends[0].pressure, ends[1].pressure),
        (ends[0].stick.unwrap(), ends[1].stick.unwrap()),
    ] {
        assert!(
            (a - b).abs() <= 1e-9 * a.abs(),
            "the loop closes: {a} and {b}"
        );
        checked[2] += 1;
    }
    eprintln!(
        "pin dragged to and fro: {} sticking steps and {} reversals against the hand calculation",
        checked[1], checked[0]
    );
    assert_eq!(checked[0], 2, "two reversals checked");
    assert!(checked[1] >= 20, "sticking steps checked: {}", checked[1]);
}

/// A strip lying on a rigid floor under its weight q per length, pulled at one end by u0:
/// the scene, with `n` elements on the strip.
fn strip_on_floor(n: usize, mu: f64) -> String {
    let h = 1.0 / n as f64;
    // The floor's nodes lie half an element off the strip's, all held; the strip starts a
    // hair above it and its pulled end (node 1) is held at that height.
    let supports: String = (0..=n + 1)
        .map(|k| format!("(node: {}, u: true, v: true, phi: true),", 1001 + k))
        .collect();
    format!(
        r#"(
    name: "strip on a floor",
    sections: [
        (name: "strip", E: 1.0e4, A: 1.0e-2, I: 1.0e-4, G: 4.0e6),
        (name: "floor", E: 1.0e6, A: 1.0, I: 1.0, G: 4.0e5),
    ],
    bodies: [
        (name: "strip", section: "strip", path: [(0.0, 1.0e-9), (1.0, 1.0e-9)], elements: {n}, first_node: 1),
        (name: "floor", section: "floor", path: [({a}, 0.0), ({b}, 0.0)], elements: {m}, first_node: 1001),
    ],
    supports: [(node: 1, v: true, phi: true), {supports}],
    prescribed: [(node: 1, dof: U, per_step: -1.0e-4)],
    distributed: [(body: "strip", q: (0.0, -1.0))],
    contacts: [(node_bodies: ["strip"], bodies: ["floor"], mu: {mu})],
    control: (steps: 1),
)"#,
        a = -h / 2.0,
        b = 1.0 + h / 2.0,
        m = n + 1,
    )
}

/// The strip of `strip_on_floor` lying on a rigid floor (a frictional `Line` obstacle), its
/// pulled end (node 1) on the floor too.
fn strip_on_obstacle(n: usize, mu: f64) -> String {
    format!(
        r#"(
    name: "strip on an obstacle",
    sections: [(name: "strip", E: 1.0e4, A: 1.0e-2, I: 1.0e-4, G: 4.0e6)],
    bodies: [(name: "strip", section: "strip", path: [(0.0, 0.0), (1.0, 0.0)], elements: {n}, first_node: 1)],
    prescribed: [(node: 1, dof: U, per_step: -1.0e-4)],
    distributed: [(body: "strip", q: (0.0, -1.0))],
    obstacles: [(name: "floor", shape: Line(from: (-1.0, 0.0), to: (2.0, 0.0)), bodies: ["strip"], mu: {mu})],
    control: (steps: 1),
)"#
    )
}

/// The pull P and the place of the last slipping node of the strip on the floor, pulled by
/// each of `pulls`: on a floor of beams, or on a rigid `obstacle`.
fn pulled_strip(n: usize, pulls: &[f64], obstacle: bool) -> Vec<(f64, f64)> {
    let text = if obstacle {
        strip_on_obstacle(n, 0.3)
    } else {
        strip_on_floor(n, 0.3)
    };
    let scene = parse(&text, "strip.ron").unwrap();
    let mut solver = scene.solver().unwrap();
    let mut all = Vec::new();
    // The weight first, at rest; the strip settles onto the floor.
    for k in 1..=20 {
        all.extend(
            solver
                .advance_to(&[0.0], &[k as f64 / 20.0], &mut Silent)
                .unwrap(),
        );
    }
    let h = 1.0 / n as f64;
    let mut out = Vec::new();
    for &u0 in pulls {
        let records = solver.advance_to(&[-u0], &[1.0], &mut Silent).unwrap();
        all.extend(records.iter().cloned());
        let r = records.last().unwrap();
        let pull = (r.reactions.iter())
            .find(|x| x.node == 1 && x.dof == "u")
            .unwrap()
            .value
            .abs();
        let (slipping, resting) = if obstacle {
            let on = &r.obstacle_contacts;
            let slipping = on.iter().filter(|c| c.friction == Friction::Slipping);
            // Node 1 at x = 0 slips too: the last slipping node lies one fewer along.
            (slipping.count().saturating_sub(1), on.len())
        } else {
            let on = &r.contacts;
            let slipping = on.iter().filter(|c| c.friction == Friction::Slipping);
            (slipping.count(), on.len() + 1)
        };
        assert_eq!(
            resting,
            n + 1,
            "every node rests on the floor, or is held over it"
        );
        out.push((pull, slipping as f64 * h));
    }
    common::assert_audited(&scene, &all);
    out
}

/// A bar on a frictional support pulled at one end (linear theory): the part within
/// Ls = sqrt(2 EA u0 / (mu q)) of the pulled end slips, carrying mu q per length, and the
/// pull is P = mu q Ls. The strip's slip front follows Ls to within an element, and its pull
/// converges to P as the mesh is refined.
#[test]
fn a_strip_pulled_on_a_frictional_floor_slips_over_the_length_of_the_closed_form() {
    let errors = pull_errors(false);
    // The pull's error falls with the element length (first order: the friction acts at the
    // nodes).
    assert!(errors[3] < 0.05, "errors {errors:?}");
    for w in errors.windows(2) {
        assert!(w[0] > 1.5 * w[1], "errors {errors:?}");
    }
}

/// The pulled strip on 10, 20, 40 and 80 elements, on a floor of beams or an `obstacle`,
/// against the bar on a frictional support (EA = 100 N, mu = 0.3, q = 1 N/m): the slip front
/// (between the last slipping node and the first sticking one) lies within an element of
/// Ls = sqrt(2 EA u0 / (mu q)) either way, as the friction acts at the nodes, each for the
/// element's length about it. Returns the largest relative error of the pull against
/// mu q Ls on each mesh.
fn pull_errors(obstacle: bool) -> Vec<f64> {
    let (ea, mu, q) = (100.0, 0.3, 1.0);
    let pulls: Vec<f64> = (1..=6).map(|k| 1.0e-4 * k as f64).collect();
    let mut errors = Vec::new();
    for n in [10, 20, 40, 80] {
        let h = 1.0 / n as f64;
        let got = pulled_strip(n, &pulls, obstacle);
        let mut worst = 0.0f64;
        for (&u0, &(pull, slipping)) in pulls.iter().zip(&got) {
            let ls = (2.0 * ea * u0 / (mu * q)).sqrt();
            assert!(ls < 0.9, "the slip stays on the strip");
            assert!(
                slipping - h <= ls + 1e-12 && ls <= slipping + 2.0 * h,
                "n {n}, u0 {u0:e}: slipping to {slipping:.4}, closed form {ls:.4}"
            );
            worst = worst.max((pull - mu * q * ls).abs() / (mu * q * ls));
        }
        let on = if obstacle { " on an obstacle" } else { "" };
        eprintln!("strip of {n} elements{on}: pull within {worst:.2e} of mu q Ls (relative)");
        errors.push(worst);
    }
    errors
}

/// Example 3.2, built in, or with `mu` given on every contact.
fn example_3_2(mu: Option<f64>) -> (Vec<IncrementRecord>, usize) {
    let text = (BUILTIN.iter())
        .find(|(f, _)| *f == "example_3_2.ron")
        .unwrap()
        .1
        .to_string();
    let text = match mu {
        None => text,
        Some(mu) => text.replace("\"])", &format!("\"], mu: {mu:?})")),
    };
    let scene = parse(&text, "example_3_2.ron").unwrap();
    assert_eq!(
        mu.is_some(),
        scene.model.contacts.iter().all(|c| Some(c.mu) == mu)
    );
    let mut solver = scene.solver().unwrap();
    let mut records = Vec::new();
    for _ in 0..scene.steps {
        records.extend(solver.step(&mut Silent).unwrap());
    }
    common::assert_audited(&scene, &records);
    for r in &mut records {
        r.seconds = 0.0;
    }
    let iterations = records.iter().map(|r| r.iterations).sum();
    (records, iterations)
}

/// With mu = 0 written out, every contact is frictionless: the history is the built-in
/// scene's, bit for bit; with friction it is not.
#[test]
fn zero_friction_reproduces_the_frictionless_history_bit_for_bit() {
    let json = |r: &[IncrementRecord]| serde_json::to_string(r).unwrap();
    let (plain, _) = example_3_2(None);
    let (zero, _) = example_3_2(Some(0.0));
    assert_eq!(json(&plain), json(&zero));
    let (rough, _) = example_3_2(Some(0.3));
    assert_ne!(json(&plain), json(&rough));
}

/// Example 3.2 with mu = 0.3: its contacts slip, the friction law holds at every accepted
/// increment (mu N exactly where slipping, against the slip of the increment), the stick
/// points follow the nodes along the bodies across transfers to the next element, and Newton
/// needs at most 1.5 times the frictionless iterations per increment.
#[test]
fn example_3_2_with_friction_slips_within_the_friction_law() {
    let (plain, plain_iterations) = example_3_2(None);
    let (rough, rough_iterations) = example_3_2(Some(0.3));
    let per = |its: usize, r: &[IncrementRecord]| its as f64 / r.len() as f64;
    let ratio = per(rough_iterations, &rough) / per(plain_iterations, &plain);
    eprintln!(
        "Example 3.2: {} increments, {plain_iterations} iterations without friction; {} increments, {rough_iterations} iterations with mu = 0.3: {ratio:.3} times the iterations per increment",
        plain.len(),
        rough.len()
    );
    assert!(
        ratio <= 1.5,
        "iterations per increment {ratio:.3} times frictionless"
    );
    let mut slipping = 0;
    for r in &rough {
        for c in &r.contacts {
            let limit = 0.3 * c.pressure;
            assert!(
                c.tangential.abs() <= limit * (1.0 + 1e-9),
                "{}: {c:?}",
                r.increment
            );
            if c.friction == Friction::Slipping {
                assert!((c.tangential.abs() - limit).abs() <= 1e-9 * limit);
                slipping += 1;
            }
        }
    }
    assert!(slipping > 10, "contacts slip: {slipping}");
    // A slipping contact's stick point trails the node's place along the body, (place - 1 +
    // li/l) 0.1 m on these bodies of 0.1 m elements, by its spring's stretch mu N / kt (under
    // 2e-6 m here), on whichever element it rests: also at the increments where it moved onto
    // the next element.
    let kt = SolverParams::default().friction_penalty * 6.0e3 / 0.1;
    let mut across = 0;
    for r in &rough {
        let moved = |c: &ContactState| {
            r.events.iter().any(|e| {
                matches!(e, Event::Contact(x) if x.change == ContactChange::Transferred
                    && x.node == c.node && x.body == c.body)
            })
        };
        for c in r
            .contacts
            .iter()
            .filter(|c| c.friction == Friction::Slipping)
        {
            let place = (c.place as f64 - 1.0 + c.xi) * 0.1;
            let stretch = 0.3 * c.pressure / kt;
            let off = (c.stick.unwrap() - place).abs();
            assert!(
                (off - stretch).abs() < 1e-9,
                "{}: node {} {off:e} from its place, spring {stretch:e}",
                r.increment,
                c.node
            );
            across += usize::from(moved(c));
        }
    }
    assert!(
        across >= 5,
        "stick points checked across transfers: {across}"
    );
    let events: Vec<ContactChange> = (rough.iter())
        .flat_map(|r| &r.events)
        .filter_map(|e| match e {
            Event::Contact(c) => Some(c.change),
            _ => None,
        })
        .collect();
    assert!(events.contains(&ContactChange::Slips));
    // The pin still jumps from A to B to C and lets go: the frictionless story's events.
    let (touches, plain_touches) = (
        events
            .iter()
            .filter(|&&c| c == ContactChange::Activated)
            .count(),
        (plain.iter())
            .flat_map(|r| &r.events)
            .filter(|e| matches!(e, Event::Contact(c) if c.change == ContactChange::Activated))
            .count(),
    );
    assert_eq!(touches, plain_touches);
    assert!(
        rough.last().unwrap().contacts.is_empty(),
        "every contact lets go"
    );
}

/// The acceptance check of the friction law finds a force beyond mu N, a slip below it, and
/// a slip the force does not oppose, and passes the states the law allows.
#[test]
fn the_friction_law_check_finds_each_kind_of_violation() {
    let ok = FrictionRecord {
        node: 3,
        body: 1,
        obstacle: false,
        mu: 0.5,
        pressure: 10.0,
        tangential: -5.0,
        stick_before: Some(0.2),
        stick_after: 0.25,
        period: 0.0,
        scale: 0.0,
    };
    assert_eq!(friction_law(&[ok]), None);
    // A sticking rim whose stick point is worked from a roll of 1 m: a move of two units in
    // the last place of that is its round-off, and a sticking contact may make it; without
    // the roll, it is a slip below the limit.
    let rolled = FrictionRecord {
        tangential: 4.0,
        stick_before: Some(1e-3),
        stick_after: 1e-3 + 2.0 * f64::EPSILON,
        scale: 1.0,
        ..ok
    };
    assert_eq!(friction_law(&[rolled]), None);
    assert!(friction_law(&[FrictionRecord {
        scale: 0.0,
        ..rolled
    }])
    .is_some());
    let sticking = FrictionRecord {
        tangential: 4.0,
        stick_after: 0.2,
        ..ok
    };
    assert_eq!(friction_law(&[sticking]), None);
    // At the limit, its stick point found again one unit in the last place along the force:
    // round-off, not a slip the force does not oppose.
    let at_limit = FrictionRecord {
        tangential: 5.0,
        stick_after: 0.2 + 0.2 * f64::EPSILON,
        ..ok
    };
    assert_eq!(friction_law(&[at_limit]), None);
    // On a circle of circumference 2 pi its places are taken modulo 2 pi: a stick point near
    // place 0 found again a unit in the last place of 2 pi along the force is round-off too,
    // and four units in the last place of its place alone are not that.
    let on_a_circle = FrictionRecord {
        tangential: 5.0,
        stick_before: Some(1e-3),
        stick_after: 1e-3 + std::f64::consts::TAU * f64::EPSILON,
        period: std::f64::consts::TAU,
        ..ok
    };
    assert_eq!(friction_law(&[on_a_circle]), None);
    let off_the_circle = FrictionRecord {
        period: 0.0,
        ..on_a_circle
    };
    assert!(friction_law(&[off_the_circle]).is_some());
    for bad in [
        FrictionRecord {
            stick_after: 0.2 + 1e-12,
            ..at_limit
        },
        FrictionRecord {
            tangential: 5.001,
            stick_after: 0.2,
            ..ok
        },
        FrictionRecord {
            tangential: -4.9,
            ..ok
        },
        FrictionRecord {
            tangential: 5.0,
            ..ok
        },
    ] {
        let found = friction_law(&[ok, bad]).expect("a violation");
        assert_eq!((found.node, found.body), (3, 1));
    }
}

/// The same bar on a rigid frictional floor (a `Line` obstacle), every node of the strip on
/// it, the pulled one too: the slip front follows Ls to within an element, and the pull
/// converges to P = mu q Ls as the mesh is refined.
#[test]
fn a_strip_pulled_on_a_frictional_obstacle_slips_over_the_length_of_the_closed_form() {
    let errors = pull_errors(true);
    assert!(errors[3] < 0.05, "errors {errors:?}");
    for w in errors.windows(2) {
        assert!(w[0] > 1.5 * w[1], "errors {errors:?}");
    }
}

/// The friction of a node on an obstacle: its tangent against central differences of its
/// forces, about a disk, a hole, a line and a polyline's segment, sticking and slipping (with
/// the place of the nearest point and the normal force following the node).
#[test]
fn obstacle_friction_tangent_matches_central_differences() {
    let shapes = [
        Shape::Circle {
            centre: [0.2, -0.9],
            radius: 0.7,
            hollow: false,
        },
        Shape::Circle {
            centre: [0.1, 0.3],
            radius: 1.3,
            hollow: true,
        },
        Shape::Line {
            from: [0.0, -0.1],
            to: [1.0, 0.2],
        },
        Shape::Polyline {
            points: vec![[-1.0, 0.0], [0.0, 0.0], [0.5, 0.6], [1.5, 0.4]],
        },
    ];
    let (multiplier, penalty) = (3.0, 1.0e3);
    // On the axis, and a rim of radius 0.05 (the node 0.05 off the curve) with a rotation.
    for reach in [0.0, 0.05] {
        for shape in &shapes {
            // A node whose face lies just inside the shape, near its curve.
            let near = shape.gap([0.8, 0.1]).unwrap();
            let (on, n) = (near.point, near.n);
            let off = reach - 1e-4;
            let x = [on[0] + off * n[0], on[1] + off * n[1], 0.3];
            let place = shape.place(on);
            let roll = 0.3 - n[1].atan2(n[0]);
            for (stick, slip) in [(place + 1e-4, None), (place - 0.3, Some(1.0))] {
                let grip = ObstacleGrip {
                    mu: 0.4,
                    stiffness: 50.0,
                    stick,
                    slip,
                    period: shape.period(),
                    reach,
                    roll: roll + 0.01,
                };
                let at = |x: [f64; 3]| {
                    let mut gap = shape.gap([x[0], x[1]]).unwrap();
                    gap.g -= reach;
                    let normal = multiplier - penalty * gap.g;
                    let place = shape.place(gap.point);
                    obstacle_friction(&gap, (place, x[2]), (normal, penalty), &grip)
                };
                let (t, _, k) = at(x);
                assert_eq!(t.mode(slip, false, 0.0), slip, "{shape:?}: the mode holds");
                let h = 1e-7;
                let mut worst = 0.0f64;
                // The node's u, v and rotation (entries 0, 1 and 4 of the forces).
                for (q, kq) in [(0, 0), (1, 1), (2, 4)] {
                    let (mut xp, mut xm) = (x, x);
                    xp[q] += h;
                    xm[q] -= h;
                    let (fp, fm) = (at(xp).1, at(xm).1);
                    for p in [0, 1, 4] {
                        let fd = (fp[p] - fm[p]) / (2.0 * h);
                        worst = worst.max((fd - k[p][kq]).abs());
                    }
                }
                let scale = k.iter().flatten().fold(1e-30f64, |a, v| a.max(v.abs()));
                assert!(
                    worst < 1e-6 * scale,
                    "{shape:?} {slip:?} reach {reach}: tangent off by {worst:e} of {scale:e}"
                );
            }
        }
    }
}

/// A band over a frictional drum (the capstan): n elements with their nodes on the top half of
/// a circle of radius 1, a weight W = 1 N hanging at the left end, the right end pulled down.
fn band_on_drum(n: usize, mu: f64) -> String {
    let points: String = (0..=n)
        .map(|k| {
            let theta = std::f64::consts::PI * (1.0 - k as f64 / n as f64);
            format!("({:.17}, {:.17}), ", theta.cos(), theta.sin())
        })
        .collect();
    format!(
        r#"(
    name: "capstan",
    sections: [(name: "band", E: 1.0e6, A: 1.0e-2, I: 1.0e-8, G: 4.0e8)],
    bodies: [(name: "band", section: "band", path: [{points}], elements: 1, first_node: 1)],
    loads: [(node: 1, fy: -1.0)],
    prescribed: [(node: {last}, dof: V, per_step: -1.0e-5)],
    obstacles: [(name: "drum", shape: Circle(centre: (0.0, 0.0), radius: 1.0), bodies: ["band"], mu: {mu})],
    control: (steps: 1),
)"#,
        last = n + 1
    )
}

/// The capstan equation: a band slipping over a drum through the angle pi pulls with
/// P = W e^(mu pi) against the weight W. With the friction at n nodes, each node passes on
/// the tension times r = (1 + mu tan(pi / 2n)) / (1 - mu tan(pi / 2n)), so P / W = r^n
/// exactly (both ends included). At the first pull where every node slips, P / W is r^n, and
/// r^n converges to e^(mu pi) as the band is refined.
#[test]
fn a_band_slipping_over_a_frictional_drum_pulls_as_the_capstan_equation() {
    let mu = 0.2;
    let mut errors = Vec::new();
    for n in [8, 16, 32] {
        let mut solver = parse(&band_on_drum(n, mu), "capstan.ron")
            .unwrap()
            .solver()
            .unwrap();
        for k in 1..=10 {
            solver
                .advance_to(&[0.0], &[k as f64 / 10.0], &mut Silent)
                .unwrap();
        }
        let mut pull = 0.0;
        let ratio = loop {
            pull += 2.0e-5;
            assert!(
                pull < 1e-2,
                "n {n}: the band slips before it is pulled 1 cm"
            );
            let records = solver.advance_to(&[-pull], &[1.0], &mut Silent).unwrap();
            let r = records.last().unwrap();
            let on = &r.obstacle_contacts;
            assert_eq!(on.len(), n + 1, "n {n}: every node on the drum");
            if on.iter().all(|c| c.friction == Friction::Slipping) {
                let p = (r.reactions.iter())
                    .find(|x| x.node == n as u32 + 1 && x.dof == "v")
                    .unwrap()
                    .value;
                break p.abs();
            }
        };
        let half = (std::f64::consts::PI / (2.0 * n as f64)).tan();
        let discrete = ((1.0 + mu * half) / (1.0 - mu * half)).powi(n as i32);
        let capstan = (mu * std::f64::consts::PI).exp();
        eprintln!(
            "band of {n} elements: P / W = {ratio:.6}, r^n = {discrete:.6}, e^(mu pi) = {capstan:.6}"
        );
        assert!(
            (ratio - discrete).abs() < 2e-5 * discrete,
            "n {n}: P / W = {ratio}, discrete capstan {discrete}"
        );
        errors.push((ratio - capstan).abs() / capstan);
    }
    for w in errors.windows(2) {
        assert!(w[0] > 3.0 * w[1], "second order in the element: {errors:?}");
    }
}

/// A heavy strip (weight w = 20 N/m, EI = 2 N m^2, 1 m) on a frictional table (mu = 0.3), its
/// end lifted far (0.05 m in 10 steps, slopes of 0.1 rad) with its rotation free and held along
/// the table: the lifted part's foreshortening drags the strip on the table towards the lift,
/// and the table's friction pulls back. Returns the lifting force, the pull along the table
/// at the lifted end, and the nodes on the table and how many of them slip.
fn lifted_on_rough_table(n: usize) -> (f64, f64, usize, usize) {
    let text = format!(
        r#"(
    name: "strip",
    formulation: BernoulliEuler,
    sections: [(name: "s", E: 2.0e5, A: 1.0e2, I: 1.0e-5)],
    bodies: [(name: "strip", section: "s", path: [(0.0, 0.0), (1.0, 0.0)], elements: {n}, first_node: 1)],
    supports: [(node: 1, u: true)],
    prescribed: [(node: 1, dof: V, per_step: 0.005)],
    distributed: [(body: "strip", q: (0.0, -20.0))],
    obstacles: [(name: "table", shape: Line(from: (0.0, 0.0), to: (1.0, 0.0)), bodies: ["strip"], mu: 0.3)],
    control: (steps: 10),
)"#
    );
    let mut solver = parse(&text, "lifted.ron").unwrap().solver().unwrap();
    let mut last = None;
    for _ in 0..10 {
        last = solver.step(&mut Silent).unwrap().pop();
    }
    let r = last.unwrap();
    let at = |dof: &str| {
        (r.reactions.iter())
            .find(|x| x.node == 1 && x.dof == dof)
            .unwrap()
            .value
    };
    let on = &r.obstacle_contacts;
    let slipping = on.iter().filter(|c| c.friction == Friction::Slipping);
    (at("v").abs(), at("u").abs(), on.len(), slipping.count())
}

/// The heavy strip lifted far off a frictional table (the elastica with friction), 10 to 80
/// elements: the strip on the table, axially stiff, slides as one towards the lift with every
/// node on it slipping, so that the pull at the lifted end is mu times the weight the table
/// carries, mu (w L - lift), to 1e-6; and the lifting force and the pull converge under
/// refinement at second order, each difference between meshes at most a third of the one
/// before.
#[test]
fn a_heavy_strip_lifted_far_off_a_frictional_table_converges_under_refinement() {
    let meshes = [10, 20, 40, 80];
    let mut lifts = Vec::new();
    let mut pulls = Vec::new();
    for n in meshes {
        let (lift, pull, on, slipping) = lifted_on_rough_table(n);
        eprintln!("strip of {n} elements lifted off a rough table: lift {lift:.6} N, pull {pull:.6} N, {slipping} of {on} nodes on the table slipping");
        assert_eq!(slipping, on, "n {n}: the strip on the table slides as one");
        let carried = 20.0 - lift;
        assert!(
            (pull - 0.3 * carried).abs() < 1e-6 * pull,
            "n {n}: pull {pull}, mu times the weight on the table {}",
            0.3 * carried
        );
        lifts.push(lift);
        pulls.push(pull);
    }
    for values in [&lifts, &pulls] {
        let d: Vec<f64> = values.windows(2).map(|w| (w[0] - w[1]).abs()).collect();
        for w in d.windows(2) {
            assert!(w[1] <= w[0] / 3.0, "differences {d:?} of {values:?}");
        }
    }
}

/// The return mapping's modes against the Coulomb law written out here: within the attempt's
/// first passes a slip whose trial force falls below the limit sticks; once the modes have
/// come back (cautious), it goes on slipping while the trial force lies within the slack (what
/// the forces are known to) of the limit, and sticks beyond it; a stick whose trial force is
/// within the limit sticks, whatever the slack.
#[test]
fn a_slip_within_the_slack_of_the_limit_goes_on_once_the_modes_come_back() {
    let t = |trial: f64| Traction {
        force: 0.0,
        slip: 0.0,
        slipping: true,
        trial,
        limit: 1.0,
        tangential: 0.0,
        normal: 1.0,
        rolled: 0.0,
        rim_roll: 0.0,
    };
    let slack = 0.1;
    for (trial, first, cautious) in [
        (1.5, Some(1.0), Some(1.0)),
        (0.95, None, Some(1.0)),
        (0.85, None, None),
        (-0.95, None, None),
    ] {
        assert_eq!(
            t(trial).mode(Some(1.0), false, slack),
            first,
            "trial {trial}"
        );
        assert_eq!(
            t(trial).mode(Some(1.0), true, slack),
            cautious,
            "trial {trial}, cautious"
        );
    }
    assert_eq!(t(0.95).mode(None, true, slack), None);
    assert_eq!(t(1.05).mode(None, true, slack), Some(1.0));
}
