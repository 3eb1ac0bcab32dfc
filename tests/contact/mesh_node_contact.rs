//! A pin pressed straight onto a mesh node: the midspan node of a pinned-pinned beam, meshed
//! with 8 to 128 elements, both formulations, with and without friction. Every run completes,
//! the oracle finds nothing in its history, its recorded contact force (turn included) is the
//! size of the pin's reactions, and the pin's force follows the elastica of the
//! beam (Reissner's plane beam with axial and shear strain, solved by shooting in this file),
//! to the mesh's O(h^2). Drawn back past its start in long steps, the pin lets go and the beam
//! springs straight. Also Example 3.2 at the two step sizes where A's tip lands on a mesh node
//! of B.

use crate::common;

use tsm_contact::history::History;
use tsm_contact::scene::{builtin::builtin, parse, Scene};
use tsm_contact::solver::{IncrementRecord, SolveError};

/// Span, EI, EA, G Ae of the beam (E = 1, A = 1e3, I = 1, G = 400, Ae = A).
const SPAN: f64 = 1.0;
const EI: f64 = 1.0;
const EA: f64 = 1.0e3;
const GAE: f64 = 4.0e5;
/// The pin starts this far above the beam and goes down 0.01 a step for 20 steps.
const START: f64 = 0.001;
const STEPS: usize = 20;

fn scene(n: usize, formulation: &str, mu: f64) -> Scene {
    parse(&scene_text(n, formulation, mu, ""), "pin on a mesh node").expect("a valid scene")
}

/// The text of `scene`, with `extra` entries (stages) at its end.
fn scene_text(n: usize, formulation: &str, mu: f64, extra: &str) -> String {
    format!(
        r#"(
    name: "pin on a mesh node", formulation: {formulation},
    sections: [(name: "s", E: 1.0, A: 1.0e3, I: 1.0, G: 400.0)],
    nodes: [(id: 100000, x: 0.5, y: {START}, rotation: false)],
    bodies: [(name: "beam", section: "s", path: [(0.0, 0.0), (1.0, 0.0)], elements: {n}, first_node: 1)],
    supports: [(node: 1, u: true, v: true), (node: {last}, u: true, v: true), (node: 100000, u: true)],
    prescribed: [(node: 100000, dof: V, per_step: -0.01)],
    contacts: [(nodes: [100000], bodies: ["beam"], mu: {mu})],
    control: (steps: {STEPS}),
    {extra}
)"#,
        last = n + 1
    )
}

/// The same beam with its midspan node driven down as the pin is (no pin, no contact).
fn node_driven(n: usize, formulation: &str) -> Scene {
    let text = format!(
        r#"(
    name: "midspan node driven", formulation: {formulation},
    sections: [(name: "s", E: 1.0, A: 1.0e3, I: 1.0, G: 400.0)],
    bodies: [(name: "beam", section: "s", path: [(0.0, 0.0), (1.0, 0.0)], elements: {n}, first_node: 1)],
    supports: [(node: 1, u: true, v: true), (node: {last}, u: true, v: true)],
    prescribed: [(node: {mid}, dof: V, per_step: {step})],
    control: (steps: {STEPS}),
)"#,
        last = n + 1,
        mid = n / 2 + 1,
        step = (START - 0.01 * STEPS as f64) / STEPS as f64
    );
    parse(&text, "midspan node driven").expect("a valid scene")
}

fn solve(scene: &Scene) -> (Vec<IncrementRecord>, Option<SolveError>) {
    let mut solver = scene.solver().expect("a stable scene");
    let mut history = History::default();
    for _ in 0..scene.steps {
        if let Err(e) = solver.step(&mut history) {
            return (history.increments, Some(e));
        }
    }
    (history.increments, None)
}

/// The half beam from its pinned end (s = 0, at the origin, no moment) to midspan (s = L/2),
/// where symmetry holds its section level (t = 0) at x = L/2 and the pin holds it at y. With
/// R = (Rx, Ry) the support's force on the beam, the section force on [0, s] from beyond is
/// -R: tension N = -R . a1, shear Q = -R . a2 (a1 = (cos t, sin t), a2 = (-sin t, cos t)),
/// moment M = x Ry - y Rx, and `x' = (1 + N/EA) cos t - (Q/GAe) sin t`,
/// `y' = (1 + N/EA) sin t + (Q/GAe) cos t`, `t' = M / EI`. Returns (x, y, t) at L/2.
fn shoot(r: [f64; 2], t0: f64, gae: f64) -> [f64; 3] {
    let f = |z: [f64; 3]| {
        let (x, y, t) = (z[0], z[1], z[2]);
        let (c, s) = (t.cos(), t.sin());
        let n = -(r[0] * c + r[1] * s);
        let q = -(-r[0] * s + r[1] * c);
        let (e, g) = (n / EA, q / gae);
        [
            (1.0 + e) * c - g * s,
            (1.0 + e) * s + g * c,
            (x * r[1] - y * r[0]) / EI,
        ]
    };
    let steps = 2000;
    let h = 0.5 * SPAN / steps as f64;
    let mut z = [0.0, 0.0, t0];
    let add =
        |z: [f64; 3], k: [f64; 3], w: f64| [z[0] + w * k[0], z[1] + w * k[1], z[2] + w * k[2]];
    for _ in 0..steps {
        let k1 = f(z);
        let k2 = f(add(z, k1, 0.5 * h));
        let k3 = f(add(z, k2, 0.5 * h));
        let k4 = f(add(z, k3, h));
        for k in 0..3 {
            z[k] += h / 6.0 * (k1[k] + 2.0 * k2[k] + 2.0 * k3[k] + k4[k]);
        }
    }
    z
}

/// The pin's force on the beam (downward, N) with the pin at depth `y` (< 0) below the
/// beam's line: Newton on (Rx, Ry, t0) over the three midspan conditions, with a central
/// difference Jacobian, continued from the small-deflection solution in 40 steps of depth.
fn elastica_force(y: f64, gae: f64) -> f64 {
    // Small deflection: y = -P L^3 / (48 EI), Ry = P / 2, t0 = -P L^2 / (16 EI).
    let first = y / 40.0;
    let p = -first * 48.0 * EI / SPAN.powi(3);
    let mut u = [0.0, 0.5 * p, -p * SPAN * SPAN / (16.0 * EI)];
    for k in 1..=40 {
        let depth = first * k as f64;
        let miss = |u: [f64; 3]| {
            let z = shoot([u[0], u[1]], u[2], gae);
            [z[0] - 0.5 * SPAN, z[1] - depth, z[2]]
        };
        for _ in 0..30 {
            let r = miss(u);
            if r.iter().map(|v| v.abs()).fold(0.0, f64::max) < 1e-13 {
                break;
            }
            let mut j = nalgebra::Matrix3::<f64>::zeros();
            for q in 0..3 {
                let h = 1e-7 * u[q].abs().max(1e-3);
                let (mut up, mut um) = (u, u);
                up[q] += h;
                um[q] -= h;
                let (rp, rm) = (miss(up), miss(um));
                for k in 0..3 {
                    j[(k, q)] = (rp[k] - rm[k]) / (2.0 * h);
                }
            }
            let du = j.lu().solve(&nalgebra::Vector3::from(r)).expect("regular");
            for q in 0..3 {
                u[q] -= du[q];
            }
        }
        let r = miss(u);
        assert!(
            r.iter().all(|v| v.abs() < 1e-10),
            "shooting misses by {r:?} at {depth}"
        );
    }
    2.0 * u[1]
}

/// The pin's force on the beam at the last increment (downward, N): the beam pushes the pin
/// up by as much as its driven dof's reaction pulls it down.
fn pin_force(r: &IncrementRecord) -> f64 {
    let v = (r.reactions.iter())
        .find(|x| x.node == 100000 && x.dof == "v")
        .expect("the pin's reaction");
    -v.value
}

#[test]
fn a_pin_pressed_onto_a_mesh_node_completes_on_every_mesh_with_both_formulations() {
    for formulation in ["BernoulliEuler", "Timoshenko"] {
        for n in [8, 16, 32, 64, 128] {
            for mu in [0.0, 0.2] {
                let s = scene(n, formulation, mu);
                let (records, error) = solve(&s);
                assert!(
                    error.is_none(),
                    "{formulation}, {n} elements, mu {mu}: {}",
                    error.map(|e| e.to_string()).unwrap_or_default()
                );
                common::assert_audited(&s, &records);
                // The recorded contact force (Yc along the chord's normal, Yc tan(turn) and
                // the friction along the chord) is what holds the pin: its size is that of
                // the pin's reactions, the only other forces on it.
                let last = records.last().expect("records");
                let c = &last.contacts[0];
                let size = c.force.hypot(c.force * c.turn.tan() + c.tangential);
                let held = (last.reactions.iter())
                    .filter(|r| r.node == 100000)
                    .fold(0.0f64, |a, r| a.hypot(r.value));
                assert!(
                    (size - held).abs() < 1e-8 * held,
                    "{formulation}, {n} elements, mu {mu}: contact {size}, reactions {held}"
                );
            }
        }
    }
}

#[test]
fn the_pin_force_on_a_mesh_node_converges_to_the_elastica() {
    let depth = START - 0.01 * STEPS as f64;
    for (formulation, gae) in [("BernoulliEuler", f64::INFINITY), ("Timoshenko", GAE)] {
        let reference = elastica_force(depth, gae);
        let mut errors = Vec::new();
        for n in [8, 16, 32, 64] {
            let (records, error) = solve(&scene(n, formulation, 0.0));
            assert!(error.is_none(), "{formulation}, {n} elements: {error:?}");
            let f = pin_force(records.last().expect("records"));
            errors.push((f - reference) / reference);
            // The pin on the node is the node driven to the pin's depth.
            let (driven, error) = solve(&node_driven(n, formulation));
            assert!(
                error.is_none(),
                "{formulation}, {n} elements driven: {error:?}"
            );
            let mid = (n / 2 + 1) as u32;
            let r = driven.last().expect("records");
            let v = r
                .reactions
                .iter()
                .find(|x| x.node == mid && x.dof == "v")
                .expect("reaction");
            // The contact spring (`SolverParams::contact_stiffness`, 1e4 EI / l^3) lets the pin
            // into the beam by delta = f l^3 / (1e4 EI); the force grows about as the depth
            // cubed (the beam acts as a cable), so the pin's force is short by up to 3 delta /
            // depth: O(h^3).
            let l = SPAN / n as f64;
            let delta = f * l.powi(3) / (1e4 * EI);
            let short = (f + v.value) / -v.value;
            assert!(
                short.abs() <= 3.0 * delta / (0.01 * STEPS as f64 - START),
                "{formulation}, {n} elements: pin {f}, node driven {}",
                -v.value
            );
        }
        eprintln!("{formulation}: reference {reference:.9e}, relative errors {errors:?}");
        // O(h^2): each halving of h cuts the error by about 4 (3.5 to 4.5), and Richardson's
        // extrapolation of the two finest meshes, (4 e_64 - e_32) / 3, leaves a small part of
        // the finest mesh's error: a hundredth for Bernoulli-Euler; for Timoshenko 3 %, which
        // the node driven without a pin leaves too (1.5e-5 of the force): the element's shear
        // strain in its chord frame against Reissner's in the section's, not the contact.
        for w in errors.windows(2) {
            let ratio = w[0] / w[1];
            assert!(
                (3.5..4.5).contains(&ratio),
                "{formulation}: errors {errors:?}"
            );
        }
        let extrapolated = (4.0 * errors[3] - errors[2]) / 3.0;
        let share = if gae.is_finite() { 0.05 } else { 0.01 };
        assert!(
            extrapolated.abs() < share * errors[3].abs(),
            "{formulation}: errors {errors:?}, extrapolated {extrapolated:e}"
        );
    }
}

#[test]
fn example_3_2_completes_where_a_tip_lands_on_a_mesh_node() {
    let base = builtin("example_3_2").expect("built in").expect("valid");
    for step in [0.0101, 0.0105] {
        let mut s = base.clone();
        s.model.prescribed[0].per_step = -step;
        s.steps = (0.8 / step).ceil() as usize;
        let (records, error) = solve(&s);
        assert!(error.is_none(), "step {step}: {error:?}");
        common::assert_audited(&s, &records);
    }
}

/// The pin pressed onto the node in three long steps and drawn back past its start in three:
/// every run completes, the oracle finds nothing, and at the end the pin has let go and the
/// beam lies straight again (the unloaded beam's exact state).
#[test]
fn a_pin_drawn_back_off_a_mesh_node_lets_go_and_the_beam_springs_straight() {
    for formulation in ["BernoulliEuler", "Timoshenko"] {
        for n in [8, 16, 32] {
            let stages = r#"stages: [
        (name: "down", steps: 3, prescribed: [(node: 100000, dof: V, by: -0.21282)]),
        (name: "up", steps: 3, prescribed: [(node: 100000, dof: V, by: 0.21282)]),
    ],"#;
            let text = scene_text(n, formulation, 0.0, stages);
            let s = parse(&text, "pin down and up").expect("a valid scene");
            let (records, error) = solve(&s);
            assert!(
                error.is_none(),
                "{formulation}, {n} elements: {}",
                error.map(|e| e.to_string()).unwrap_or_default()
            );
            common::assert_audited(&s, &records);
            let last = records.last().expect("records");
            assert!(
                last.contacts.is_empty(),
                "{formulation}, {n} elements: still touching"
            );
            // Straight: every beam node back on y = 0 (to the solver's tolerance of 1e-8 of
            // the force, a displacement far below 1e-9 on this beam), the pin force zero.
            let worst = (s.model.nodes.iter().zip(&last.nodes))
                .filter(|(node, _)| node.id != 100000)
                .map(|(_, p)| p[1].abs())
                .fold(0.0, f64::max);
            assert!(worst < 1e-9, "{formulation}, {n} elements: |y| {worst:e}");
            assert!(pin_force(last).abs() < 1e-9, "{formulation}, {n} elements");
        }
    }
}

/// A pin inside the kink of a body, driven straight down through the kink's mesh node in one
/// step: there it lies in the wedge outside that convex node, projecting onto neither element
/// meeting at it, and nearest the body's far segment beneath. No accepted state may have it
/// there: the step is cut back until the pin is caught while it still projects onto the body,
/// or the run stops with a typed error where it cannot be (a pin landed on the node itself).
/// The oracle audits every accepted state, both formulations.
#[test]
fn a_pin_driven_through_a_kink_of_a_body_is_never_accepted_beyond_it() {
    for formulation in ["BernoulliEuler", "Timoshenko"] {
        let text = format!(
            r#"(
    name: "pin through a kink",
    units: N_m,
    formulation: {formulation},
    sections: [(name: "s", E: 2.0e5, A: 1.0e2, I: 1.0e-5, G: 8.0e4)],
    nodes: [(id: 500, x: 1.0, y: 0.05, rotation: false)],
    bodies: [(name: "w", section: "s", path: [(0.0, 1.0), (1.0, 0.0), (2.0, 1.0), (2.0, -0.2), (0.5, -0.2)], elements: 10, first_node: 1)],
    supports: [(node: 1, u: true, v: true, phi: true), (node: 21, u: true, v: true, phi: true), (node: 41, u: true, v: true, phi: true)],
    prescribed: [(node: 500, dof: U, per_step: 0.0), (node: 500, dof: V, per_step: -0.1)],
    contacts: [(nodes: [500], bodies: ["w"])],
    control: (steps: 1),
)"#
        );
        let s = parse(&text, "pin through a kink").expect("a valid scene");
        let (records, _) = solve(&s);
        common::assert_audited(&s, &records);
    }
}
