//! A steel bar laid on a floor beam (zero gap, declared above it) under its own weight, held
//! sideways by friction alone: its nodes start in contact, so the floor holds it from the
//! first iteration, as a rigid floor (an obstacle) does. Every run completes on 8 and 32
//! elements in both formulations, the floor carries exactly the bar's weight (statics: density
//! A L g), and the oracle finds nothing. Without friction nothing holds the bar sideways, and
//! the scene is refused as a rigid motion of the bar.

use crate::common;

use tsm_contact::history::History;
use tsm_contact::scene::{parse, Scene};

/// Density, area and length of the bar, and gravity.
const RHO: f64 = 7850.0;
const AREA: f64 = 1.0e-4;
const LENGTH: f64 = 1.0;
const G: f64 = 9.81;

fn bar(n: usize, formulation: &str, mu: f64) -> Scene {
    parse(&bar_text(n, formulation, mu), "bar on a floor").expect("a valid scene")
}

fn bar_text(n: usize, formulation: &str, mu: f64) -> String {
    format!(
        r#"(
    name: "bar on a floor", formulation: {formulation},
    sections: [(name: "bar", E: 2.0e11, A: {AREA:?}, I: 8.3333e-10, density: {RHO:?}),
               (name: "floor", E: 2.0e11, A: 1.0e-3, I: 8.3333e-8)],
    bodies: [(name: "bar", section: "bar", path: [(0.1, 0.0), (1.1, 0.0)], elements: {n}, first_node: 1),
             (name: "floor", section: "floor", path: [(0.0, 0.0), (1.2, 0.0)], elements: 12, first_node: 1001)],
    supports: [(node: 1001, u: true, v: true, phi: true), (node: 1013, u: true, v: true, phi: true)],
    contacts: [(node_bodies: ["bar"], bodies: ["floor"], side: Left, mu: {mu:?})],
    control: (steps: 5, gravity: (0.0, -{G:?})),
)"#
    )
}

#[test]
fn a_bar_on_a_rough_beam_floor_rests_there_under_its_weight() {
    let weight = RHO * AREA * LENGTH * G;
    for formulation in ["BernoulliEuler", "Timoshenko"] {
        for n in [8, 32] {
            let scene = bar(n, formulation, 0.3);
            let mut solver = scene.solver().expect("friction holds the bar");
            let mut history = History::default();
            for _ in 0..scene.steps {
                solver.step(&mut history).expect("converges");
            }
            let last = history.increments.last().expect("increments");
            assert!(
                !last.contacts.is_empty(),
                "{formulation} {n}: the bar rests"
            );
            let carried: f64 = last.contacts.iter().map(|c| c.pressure).sum();
            assert!(
                (carried - weight).abs() < 1e-8 * weight,
                "{formulation} {n}: the floor carries {carried} N of {weight} N"
            );
            common::assert_audited(&scene, &history.increments);
        }
    }
}

#[test]
fn a_bar_on_a_smooth_beam_floor_is_refused_as_a_rigid_motion() {
    let text = bar_text(8, "BernoulliEuler", 0.0);
    let e = parse(&text, "bar on a floor").expect_err("nothing holds the bar sideways");
    assert_eq!(e.field, "supports");
    assert!(
        e.message
            .contains("body \"bar\" can move rigidly (1 rigid motion not stopped"),
        "{}",
        e.message
    );
}
