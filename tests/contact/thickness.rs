//! Thickness and pin radii against rigid obstacles: a body of thickness t touches an obstacle
//! with its faces, t/2 from its axis, and a node of radius r with its rim. The references are
//! identities (the thick body on an obstacle is the thin body on the obstacle grown by t/2,
//! node for node) and closed forms; the oracle (`tsm_contact::audit`) audits every history and
//! is shown to catch a thick body whose axis sinks onto the obstacle.

use crate::common;

use tsm_contact::scene::{builtin, parse, Scene};
use tsm_contact::solver::{IncrementRecord, Silent};

/// `text` solved in its own steps, audited by the oracle; the scene and its records.
fn solved(text: &str) -> (Scene, Vec<IncrementRecord>) {
    let scene = parse(text, "scene.ron").expect("a valid scene");
    let mut solver = scene.solver().unwrap();
    let mut out = Vec::new();
    for _ in 0..scene.steps {
        out.extend(solver.step(&mut Silent).expect("converges"));
    }
    common::assert_audited(&scene, &out);
    (scene, out)
}

/// The largest difference of the node positions of two histories of the same mesh, the first
/// moved by `shift` (m).
fn largest_difference(a: &[IncrementRecord], b: &[IncrementRecord], shift: [f64; 2]) -> f64 {
    assert_eq!(a.len(), b.len(), "the same increments");
    let mut worst: f64 = 0.0;
    for (ra, rb) in a.iter().zip(b) {
        for (p, q) in ra.nodes.iter().zip(&rb.nodes) {
            worst = worst
                .max((p[0] - shift[0] - q[0]).abs())
                .max((p[1] - shift[1] - q[1]).abs())
                .max((p[2] - q[2]).abs());
        }
    }
    worst
}

/// The built-in `name` with `from` replaced by `to` (each once).
fn edited(name: &str, edits: &[(&str, &str)]) -> String {
    let mut text = builtin::text(name).expect("a built-in scene").to_string();
    for (from, to) in edits {
        assert_eq!(text.matches(from).count(), 1, "{from:?} once in {name}");
        text = text.replace(from, to);
    }
    text
}

const T: f64 = 0.02;

/// `table_lift` with its strip `T` thick and its axis `T / 2` above the table.
fn thick_table_lift() -> String {
    edited(
        "table_lift",
        &[
            ("I: 1.0e-5)", &format!("I: 1.0e-5, thickness: {T})")),
            (
                "[(0.0, 0.0), (1.0, 0.0)]",
                &format!("[(0.0, {h}), (1.0, {h})]", h = T / 2.0),
            ),
        ],
    )
}

/// The heavy strip of `table_lift`, 2 cm thick with its axis 1 cm above the table, lies and
/// lifts off as the thin strip does on the table: every state is the thin one 1 cm higher (to
/// round-off), the nodes on the table have their axis at t/2, and the lifting force is the
/// thin strip's, w a / 2 = 0.175 N within 1 %.
#[test]
fn a_thick_strip_rests_with_its_face_on_the_table_and_lifts_off_as_the_thin_one() {
    let (_, thin) = solved(&edited("table_lift", &[]));
    let thick = thick_table_lift();
    let (scene, records) = solved(&thick);
    let d = largest_difference(&records, &thin, [0.0, T / 2.0]);
    assert!(d < 1e-12, "thick minus thin, 1 cm lower: {d:e} m");
    let last = records.last().unwrap();
    let resting = &last.obstacle_contacts;
    assert!(resting.len() > 10, "{} nodes on the table", resting.len());
    let tol = scene.params.obstacle_gap + 1e-12;
    for c in resting {
        let k = scene
            .model
            .nodes
            .iter()
            .position(|n| n.id == c.node)
            .unwrap();
        let y = last.nodes[k][1];
        assert!((y - T / 2.0).abs() < tol, "node {} axis at {y:e} m", c.node);
    }
    let lift = (last.reactions.iter())
        .find(|r| r.dof == "v")
        .map(|r| r.value)
        .unwrap();
    assert!(
        (lift - 0.175).abs() < 0.01 * 0.175,
        "lifting force {lift} N"
    );
    println!("thick strip on a table: thick minus thin {d:.1e} m; lifting force {lift:.5} N");
}

/// The cantilever of `cylinder_wrap`, 4 cm thick, wraps the drum of radius 1 m as the thin
/// cantilever wraps a drum of radius 1.02 m, node for node, the thick one's axis 2 cm off the
/// drum: the face is a circle about the same centre.
#[test]
fn a_thick_cantilever_wraps_a_drum_as_the_thin_one_wraps_a_drum_grown_by_half_its_thickness() {
    let t = 2.0 * T;
    let thin = edited(
        "cylinder_wrap",
        &[
            (
                "centre: (0.0, -1.0), radius: 1.0",
                &format!("centre: (0.0, -1.0), radius: {}", 1.0 + t / 2.0),
            ),
            (
                "[(0.0, 0.0), (1.0, 0.0)]",
                &format!("[(0.0, {h}), (1.0, {h})]", h = t / 2.0),
            ),
        ],
    );
    let thick = edited(
        "cylinder_wrap",
        &[
            ("I: 1.0e-5)", &format!("I: 1.0e-5, thickness: {t})")),
            (
                "[(0.0, 0.0), (1.0, 0.0)]",
                &format!("[(0.0, {h}), (1.0, {h})]", h = t / 2.0),
            ),
        ],
    );
    let (_, thin) = solved(&thin);
    let (_, thick) = solved(&thick);
    let d = largest_difference(&thick, &thin, [0.0, 0.0]);
    assert!(
        d < 1e-9,
        "thick on the drum against thin on the grown drum: {d:e}"
    );
    println!("thick cantilever on a drum: thick minus thin on the grown drum {d:.1e} m");
    // And it does wrap: the tip comes down by more than 10 cm.
    let tip = thick.last().unwrap().nodes.last().unwrap()[1] - t / 2.0;
    assert!(tip < -0.1, "tip at {tip} m");
}

/// A cantilever's tip node with radius r = 5 mm, 3 cm above a floor, pushed down hard: it stops
/// with its rim on the floor, its centre r above it (the floor's closed form: the tip's gap
/// less r); the same pin without a radius goes r further down.
#[test]
fn a_pin_with_a_radius_stops_with_its_rim_on_the_floor() {
    let scene = |radius: f64| {
        format!(
            r#"(
    name: "pin",
    formulation: BernoulliEuler,
    sections: [(name: "s", E: 2.0e5, A: 1.0e2, I: 1.0e-5)],
    nodes: [(id: 11, x: 1.0, y: 0.0, radius: {radius})],
    bodies: [(name: "bar", section: "s", path: [(0.0, 0.0), (1.0, 0.0)], elements: 10, first_node: 1)],
    supports: [(node: 1, u: true, v: true, phi: true)],
    loads: [(node: 11, fy: -1.0)],
    obstacles: [(name: "floor", shape: Line(from: (0.0, -0.03), to: (2.0, -0.03)), nodes: [11])],
    control: (steps: 4, obstacle_gap: 1e-12),
)"#
        )
    };
    let r = 0.005;
    let (_, with) = solved(&scene(r));
    let (_, without) = solved(&scene(0.0));
    // Node 11 is listed first (an explicit node), so it comes first.
    let tip = |rs: &[IncrementRecord]| rs.last().unwrap().nodes[0][1];
    // The free tip would go EI-linear P L^3 / (3 EI) = 0.167 m down: far past the floor.
    assert!(
        (tip(&with) - (-0.03 + r)).abs() < 1e-9,
        "tip at {}",
        tip(&with)
    );
    assert!(
        (tip(&without) - (-0.03)).abs() < 1e-9,
        "tip at {}",
        tip(&without)
    );
    let error = (tip(&with) - (-0.03 + r)).abs();
    println!("pin of radius 5 mm on a floor: its centre off r above the floor by {error:.1e} m");
}

/// The oracle measures a thick body's depth in an obstacle at its face: the thick strip's
/// history with every node moved down by t/2 (its axis on the table, as a solver blind to
/// thickness would leave it) is found inside the table, though it is in equilibrium.
#[test]
fn the_oracle_finds_a_thick_strip_whose_axis_lies_on_the_table() {
    let thick = thick_table_lift();
    let (scene, mut records) = solved(&thick);
    for r in &mut records {
        for p in &mut r.nodes {
            p[1] -= T / 2.0;
        }
    }
    let found = common::findings(&scene, &records);
    assert!(
        found
            .iter()
            .any(|f| f.to_string().contains("inside obstacle table")),
        "{found:?}"
    );
}

/// A negative thickness or radius is refused, naming the field; a thick body laid with its
/// axis on an obstacle starts with its face inside it and is refused, naming its node.
#[test]
fn bad_thicknesses_and_radii_are_refused_with_their_fields() {
    let cases = [
        (
            "table_lift",
            "I: 1.0e-5)",
            "I: 1.0e-5, thickness: -0.01)",
            "sections[0].thickness (section \"strip\")",
        ),
        (
            "table_lift",
            "I: 1.0e-5)",
            "I: 1.0e-5, thickness: 0.01)",
            "node 1 (its face, 5e-3 m from it) starts",
        ),
        (
            "pin_on_cantilever",
            "rotation: false)",
            "rotation: false, radius: -1.0)",
            "nodes[0].radius",
        ),
    ];
    for (name, from, to, says) in cases {
        let e = parse(&edited(name, &[(from, to)]), "s.ron")
            .unwrap_err()
            .to_string();
        assert!(e.contains(says), "{name} with {to:?}: {e}");
    }
}
