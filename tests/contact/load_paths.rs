//! Load paths written as stages in a scene, against independent references: a bar pressed onto
//! a rigid frictional floor, pulled, unloaded, reloaded and pushed back, against the closed form
//! of a bar on a Coulomb foundation; a pin pressed onto a pinned-pinned beam and dragged to and
//! fro, against the hand calculation of its stick-slip loop; Example 3.2 driven down and back
//! up, against the order of its lifts and a 4x finer mesh; the steps of a path landing where its
//! stages say; and stages that cannot be run, refused with located errors. Every history is
//! audited by the independent checker.

use crate::common;

use tsm_contact::scene::{parse, Scene};
use tsm_contact::solver::report::ContactState;
use tsm_contact::solver::{
    ContactChange, Event, Friction, IncrementRecord, Observer, SolverParams,
};

/// Every increment of a run of `scene` to the end of its path.
fn run(scene: &Scene) -> Vec<IncrementRecord> {
    struct Keep(Vec<IncrementRecord>);
    impl Observer for Keep {
        fn increment(&mut self, r: &IncrementRecord) -> tsm_contact::solver::Flow {
            self.0.push(r.clone());
            tsm_contact::solver::Flow::Continue
        }
    }
    let mut solver = scene.solver().expect("the scene sets up");
    let mut keep = Keep(Vec::new());
    for _ in 0..scene.steps {
        solver.step(&mut keep).expect("every step converges");
    }
    assert!(solver.step(&mut keep).unwrap().is_empty(), "the path ends");
    keep.0
}

/// A bar of `n` elements (EA = 100 N, 1 m) lying on a rigid floor with mu = 0.3: pressed by
/// q = 1 N/m, then pulled at its left end by P, unloaded, pulled again and pushed to -P.
fn bar_on_a_rough_floor(n: usize, pull: f64) -> String {
    format!(
        r#"(
    name: "bar on a rough floor",
    sections: [(name: "bar", E: 1.0e4, A: 1.0e-2, I: 1.0e-4, G: 4.0e6)],
    bodies: [(name: "bar", section: "bar", path: [(0.0, 0.0), (1.0, 0.0)], elements: {n}, first_node: 1)],
    loads: [(node: 1, fx: -1.0, group: "pull")],
    distributed: [(body: "bar", q: (0.0, -1.0), group: "press")],
    obstacles: [(name: "floor", shape: Line(from: (-1.0, 0.0), to: (2.0, 0.0)), bodies: ["bar"], mu: 0.3)],
    stages: [
        (name: "press", steps: 4, loads: [(group: "press", to: 1.0)]),
        (name: "pull", steps: 10, loads: [(group: "pull", to: {pull})]),
        (name: "unload", steps: 10, loads: [(group: "pull", by: -{pull})]),
        (name: "reload", steps: 10, loads: [(group: "pull", to: {pull})]),
        (name: "push", steps: 20, loads: [(group: "pull", to: -{pull})]),
    ],
)"#
    )
}

/// The bar on a Coulomb foundation (friction f = mu q per length, the far part held by it):
/// pulled by P, the part within a = P / f of the end slips and the end moves P^2 / (2 f EA);
/// unloaded to 0, the first a / 2 slips back and P^2 / (4 f EA) remains; pulled again to P, the
/// state of the first pull comes back; pushed to -P, the first pull's mirror. Each checked on
/// 20, 40 and 80 elements: the end displacement within 1% (the friction acts at the nodes),
/// the last slipping node within an element of the slip front, and every state audited.
#[test]
fn a_bar_on_a_rough_floor_pulled_unloaded_and_reversed_follows_the_coulomb_foundation() {
    let (ea, mu, q, pull) = (100.0, 0.3, 1.0, 0.15);
    let f = mu * q;
    for n in [20, 40, 80] {
        let h = 1.0 / n as f64;
        let scene = parse(&bar_on_a_rough_floor(n, pull), "bar.ron").unwrap();
        assert_eq!(scene.steps, 54);
        let records = run(&scene);
        common::assert_audited(&scene, &records);
        let cut = records
            .iter()
            .filter(|r| r.cutbacks > 0 && r.stage >= Some(1))
            .count();
        eprintln!("bar of {n} elements: {cut} increments after a cut-back once pulled");
        // The end of each stage: (stage, pull, end displacement, slipping length).
        let ends: Vec<(usize, f64, f64)> = (0..5)
            .map(|s| {
                let r = records.iter().rev().find(|r| r.stage == Some(s)).unwrap();
                assert_eq!(r.load_factors.len(), 2, "pull and press");
                (s, r.load_factors[0], -r.nodes[0][0])
            })
            .collect();
        let peak = pull * pull / (2.0 * f * ea);
        let expect = [0.0, peak, peak / 2.0, peak, -peak];
        for ((s, p, u), e) in ends.iter().zip(expect) {
            let tol = if e == 0.0 { 1e-12 } else { 1e-2 * e.abs() };
            assert!(
                (u - e).abs() <= tol,
                "n {n}, stage {s} (P = {p}): end moved {u:.6e}, closed form {e:.6e}"
            );
            eprintln!("bar of {n} elements, stage {s}: end {u:.6e} m, closed form {e:.6e} m");
        }
        // Slipping at the end of the first pull: the nodes within a = P / f of the end.
        let first = records.iter().rev().find(|r| r.stage == Some(1)).unwrap();
        let slipping = (first.obstacle_contacts.iter())
            .filter(|c| c.friction == Friction::Slipping)
            .map(|c| (c.node - 1) as f64 * h)
            .fold(0.0f64, f64::max);
        let a = pull / f;
        eprintln!("bar of {n} elements: last slipping node at {slipping:.4} m, slip length {a} m");
        assert!(
            slipping <= a + 1e-12 && a <= slipping + h + 1e-12,
            "n {n}: slipping to {slipping}, slip length {a}"
        );
    }
}

/// A pin pressed onto a pinned-pinned beam (EA = 100 N, 8 elements), then dragged along it to
/// +U, back to -U and again to +U, written as stages. The hand calculation: while it sticks,
/// the friction force changes by k per metre dragged, where 1 / k is the stick spring's
/// compliance 1 / kt (kt = friction penalty EA / element length) plus the bar's axial
/// compliance at the stick point (the Green's function x (L - x) / (EA L) of the bar at the
/// element's ends, interpolated as the element shares the force); while it slips, the force is
/// mu N against the drag; after a reversal it sticks until dragged 2 mu N / k back.
#[test]
fn a_pin_dragged_to_and_fro_on_a_pinned_beam_traces_the_hand_calculated_loop() {
    let (mu, ea, n, big_u, fine) = (0.3, 100.0, 8usize, 0.02, 2e-5);
    let le = 1.0 / n as f64;
    let kt = SolverParams::default().friction_penalty * ea / le;
    let mut stages = vec![
        r#"(name: "press", steps: 5, prescribed: [(node: 100, dof: V, to: -1.1e-4)])"#.to_string(),
    ];
    for (k, (from, to)) in [(0.0f64, big_u), (big_u, -big_u), (-big_u, big_u)]
        .iter()
        .enumerate()
    {
        let dir: f64 = if to > from { 1.0 } else { -1.0 };
        let turn = 60.0 * fine;
        let rest = ((to - from).abs() - turn) / 2e-3;
        stages.push(format!(
            r#"(name: "leg {k}, turning", steps: 60, prescribed: [(node: 100, dof: U, by: {})])"#,
            dir * turn
        ));
        stages.push(format!(
            r#"(name: "leg {k}", steps: {}, prescribed: [(node: 100, dof: U, to: {to})])"#,
            rest.ceil()
        ));
    }
    let text = format!(
        r#"(
    name: "pin dragged to and fro",
    sections: [(name: "beam", E: {ea}, A: 1.0, I: 1.0, G: 40000.0)],
    nodes: [(id: 100, x: 0.37, y: 1.0e-5, rotation: false)],
    bodies: [(name: "beam", section: "beam", path: [(0.0, 0.0), (1.0, 0.0)], elements: {n}, first_node: 1)],
    supports: [(node: 1, u: true, v: true), (node: {last}, u: true, v: true)],
    prescribed: [(node: 100, dof: V, per_step: -2.0e-5), (node: 100, dof: U, per_step: 2.0e-3)],
    contacts: [(nodes: [100], bodies: ["beam"], mu: {mu})],
    stages: [{stages}],
)"#,
        last = n + 1,
        stages = stages.join(",\n")
    );
    let scene = parse(&text, "drag.ron").unwrap();
    let records = run(&scene);
    common::assert_audited(&scene, &records);
    // The bar's axial compliance at place s: its Green's function at the element's ends.
    let green = |a: f64, b: f64| a.min(b) * (1.0 - a.max(b)) / ea;
    let compliance = |s: f64| {
        let e = ((s / le).floor() as usize).min(n - 1);
        let xi = s / le - e as f64;
        let (a, b) = (e as f64 * le, (e + 1) as f64 * le);
        let w = [1.0 - xi, xi];
        let c = [[green(a, a), green(a, b)], [green(b, a), green(b, b)]];
        (0..2)
            .flat_map(|i| (0..2).map(move |j| (i, j)))
            .map(|(i, j)| w[i] * w[j] * c[i][j])
            .sum::<f64>()
            + 1.0 / kt
    };
    let states: Vec<(f64, ContactState, Option<usize>)> =
        (records.iter().filter(|r| r.stage != Some(0)))
            .map(|r| (r.prescribed[1], r.contacts[0].clone(), r.stage))
            .collect();
    let (mut sticking, mut reversals, mut slipping) = (0, 0, 0);
    let mut worst_slope = 0.0f64;
    let mut turned_at: Option<(f64, f64, f64)> = None;
    for w in states.windows(2) {
        let ((u0, c0, _), (u, c, _)) = (&w[0], &w[1]);
        let du = u - u0;
        let limit = mu * c.pressure;
        assert!(c.pressure > 0.1, "u = {u}: pressed ({} N)", c.pressure);
        match c.friction {
            Friction::Slipping => {
                assert!(
                    (c.tangential.abs() - limit).abs() <= 1e-9 * limit,
                    "u = {u}: {c:?}"
                );
                assert!(c.tangential * du < 0.0, "u = {u}: against the drag");
                if let Some((at, n_at, k)) = turned_at.take() {
                    let (travel, hand) = ((u - at).abs(), 2.0 * mu * n_at * k);
                    assert!(
                        travel >= hand * (1.0 - 1e-3) && travel <= hand * (1.0 + 1e-3) + fine,
                        "u = {u}: slips after {travel:.4e} m back, hand {hand:.4e} m"
                    );
                    eprintln!("reversal at u = {at:+.5} m: slips after {travel:.4e} m back, hand 2 mu N / k = {hand:.4e} m");
                    reversals += 1;
                }
                slipping += 1;
            }
            Friction::Sticking if c0.friction == Friction::Sticking => {
                let k = 1.0 / compliance(c.stick.unwrap());
                let slope = (c.tangential - c0.tangential) / du;
                assert!(
                    (slope + k).abs() <= 1e-3 * k,
                    "u = {u}: sticking slope {slope:.6e}, hand -{k:.6e}"
                );
                worst_slope = worst_slope.max((slope + k).abs() / k);
                sticking += 1;
            }
            Friction::Sticking => {
                let s = c.stick.unwrap();
                turned_at = Some((*u0, c0.pressure, compliance(s)));
            }
            Friction::Frictionless => panic!("u = {u}: a frictional contact"),
        }
    }
    eprintln!(
        "pin dragged to and fro: {sticking} sticking steps (slope within {worst_slope:.1e} of the hand k), {slipping} slipping, {reversals} reversals against the hand calculation"
    );
    assert_eq!(reversals, 2, "both reversals checked");
    assert!(sticking >= 60, "sticking steps checked: {sticking}");
}

/// The steps of a path land on their stage's values: a ramp reaches its target exactly at the
/// stage's last step, listed values are taken one per step, what a stage does not name holds,
/// and each record carries its stage.
#[test]
fn each_step_of_a_path_lands_where_its_stage_says() {
    let text = r#"(
    name: "cantilever driven through stages",
    sections: [(name: "s", E: 1000.0, A: 1.0, I: 0.01)],
    bodies: [(name: "c", section: "s", path: [(0.0, 0.0), (1.0, 0.0)], elements: 4, first_node: 1)],
    supports: [(node: 1, u: true, v: true, phi: true)],
    loads: [(node: 5, fy: -1.0)],
    prescribed: [(node: 3, dof: U, per_step: 1.0e-3)],
    stages: [
        (name: "weigh", steps: 3, loads: [(group: "loads", to: 0.3)]),
        (steps: 2, prescribed: [(node: 3, dof: U, by: 1.0e-3)]),
        (prescribed: [(node: 3, dof: U, values: [5.0e-4, -2.0e-4, 0.0])]),
        (name: "unload", steps: 2, loads: [(group: "loads", to: 0.0)]),
    ],
)"#;
    let scene = parse(text, "stages.ron").unwrap();
    assert_eq!(scene.steps, 10);
    let records = run(&scene);
    common::assert_audited(&scene, &records);
    let at_ends: Vec<(Option<usize>, f64, f64)> = (records.iter())
        .map(|r| (r.stage, r.prescribed[0], r.load_factor))
        .collect();
    let expect = [
        (0, 0.0, 0.1),
        (0, 0.0, 0.2),
        (0, 0.0, 0.3),
        (1, 5e-4, 0.3),
        (1, 1e-3, 0.3),
        (2, 5e-4, 0.3),
        (2, -2e-4, 0.3),
        (2, 0.0, 0.3),
        (3, 0.0, 0.15),
        (3, 0.0, 0.0),
    ];
    // Only the cut-backs add records: the last of each step is where the step lands.
    let mut k = 0;
    for (s, u, l) in expect {
        while k + 1 < at_ends.len() && at_ends[k].0 == Some(s) && at_ends[k + 1].0 == Some(s) {
            if (at_ends[k].1 - u).abs() < 1e-15 && (at_ends[k].2 - l).abs() < 1e-15 {
                break;
            }
            k += 1;
        }
        let (got_s, got_u, got_l) = at_ends[k];
        assert_eq!(got_s, Some(s));
        assert!(
            (got_u - u).abs() <= 1e-15,
            "stage {s}: u {got_u}, expected {u}"
        );
        assert!(
            (got_l - l).abs() <= 1e-15,
            "stage {s}: load {got_l}, expected {l}"
        );
        k += 1;
    }
    assert_eq!(records.last().unwrap().prescribed[0], 0.0, "lands exactly");
    assert_eq!(records.last().unwrap().load_factor, 0.0, "unloads exactly");
    let tip = records.last().unwrap().nodes[4];
    assert!(
        tip[1].abs() < 1e-12,
        "unloaded, the cantilever is straight: {tip:?}"
    );
}

/// A stage the scene cannot run is refused, naming the stage, the field and the line.
#[test]
fn stages_that_cannot_be_run_are_refused_with_located_errors() {
    let scene = |stages: &str, control: &str| {
        format!(
            r#"(
    name: "refused",
    sections: [(name: "s", E: 1000.0, A: 1.0, I: 0.01)],
    bodies: [(name: "c", section: "s", path: [(0.0, 0.0), (1.0, 0.0)], elements: 4, first_node: 1)],
    supports: [(node: 1, u: true, v: true, phi: true)],
    loads: [(node: 5, fy: -1.0, group: "tip")],
    prescribed: [(node: 3, dof: U, per_step: 1.0e-3)],
    control: ({control}),
    stages: [
        (name: "first", steps: 2, loads: [(group: "tip", to: 1.0)]),
        {stages}
    ],
)"#
        )
    };
    for (stages, control, field, says) in [
        ("(steps: 0)", "", "stages[1].steps", "at least one step"),
        ("()", "", "stages[1].steps", "number of steps"),
        (
            "(steps: 2, loads: [(group: \"pull\", to: 1.0)])",
            "",
            "stages[1].loads[0]",
            "no load group \"pull\"",
        ),
        (
            "(steps: 2, loads: [(group: \"tip\", to: 1.0, by: 1.0)])",
            "",
            "stages[1].loads[0]",
            "exactly one",
        ),
        (
            "(steps: 2, prescribed: [(node: 4, dof: V, to: 1.0)])",
            "",
            "stages[1].prescribed[0]",
            "not prescribed",
        ),
        (
            "(steps: 2, prescribed: [(node: 3, dof: U, values: [1.0])])",
            "",
            "stages[1].values",
            "one value per step",
        ),
        (
            "(steps: 2, prescribed: [(node: 3, dof: U, to: 1.0e300)])",
            "",
            "stages[1].prescribed[0]",
            "finite",
        ),
        (
            "(steps: 1)",
            "arc_length: 0.1",
            "control.arc_length",
            "cannot follow stages",
        ),
        (
            "(steps: 1)",
            "load_per_step: 0.1",
            "control.load_per_step",
            "set by the stages",
        ),
    ] {
        let text = scene(stages, control);
        let e = parse(&text, "refused.ron").expect_err(stages);
        assert!(
            e.field.starts_with(field) && e.message.contains(says),
            "{stages} / {control}: {e}"
        );
        // Where the stage (or the control) is written.
        let needle = if field.starts_with("control") {
            format!("control: ({control}),")
        } else {
            stages.to_string()
        };
        let line = text.lines().position(|l| l.trim() == needle).unwrap() + 1;
        assert_eq!(e.line, Some(line), "{stages} / {control}: located: {e}");
    }
}

/// Example 3.2 on `n` elements a body, its pin (node 1000) driven down 0.8 m in 80 steps and
/// back up in 80 more.
fn example_3_2_down_and_up(n: usize) -> String {
    format!(
        r#"(
    name: "Example 3.2 down and up",
    sections: [(name: "strip", E: 2.0e7, A: 3.0e-4, I: 2.2e-8, G: 7.142e6)],
    nodes: [(id: 1000, x: 0.8, y: 0.002, rotation: false)],
    bodies: [
        (name: "A", section: "strip", path: [(0.0, 0.0), (1.0, 0.0)], elements: {n}, first_node: 1),
        (name: "B", section: "strip", path: [(0.6, -0.1), (1.6, -0.1)], elements: {n}, first_node: {b}),
        (name: "C", section: "strip", path: [(-0.05, -0.2), (0.95, -0.2)], elements: {n}, first_node: {c}),
    ],
    supports: [
        (node: 1, u: true, v: true, phi: true),
        (node: {b_end}, u: true, v: true, phi: true),
        (node: {c}, u: true, v: true, phi: true),
        (node: 1000, u: true),
    ],
    prescribed: [(node: 1000, dof: V, per_step: -0.01)],
    contacts: [
        (nodes: [1000], bodies: ["A", "B", "C"]),
        (node_bodies: ["A"], bodies: ["B", "C"]),
        (node_bodies: ["B"], bodies: ["A", "C"]),
        (node_bodies: ["C"], bodies: ["A", "B"]),
    ],
    control: (max_step: 1.0),
    stages: [
        (name: "down", steps: 80, prescribed: [(node: 1000, dof: V, by: -0.8)]),
        (name: "up", steps: 80, prescribed: [(node: 1000, dof: V, by: 0.8)]),
    ],
)"#,
        b = n + 2,
        b_end = 2 * n + 2,
        c = 2 * n + 3,
    )
}

/// Example 3.2 driven to the end and back up, on 10, 20 and 40 elements a body. Every history
/// passes the independent audit (no node on the wrong side of a beam, equilibrium). On the way
/// up the pin, now under every strip, lifts C first, C's tip then lifts B and B's tip lifts A.
/// The way up converges with the mesh: at every tenth step of it, the pin's force and the three
/// tips' heights on 10 elements differ from those on 40 by no more than the discretisation
/// error of the 10-element mesh as Richardson extrapolation estimates it from 10 and 20
/// elements (4/3 of their difference, for second-order convergence), beyond the states'
/// tolerance.
#[test]
fn example_3_2_down_and_back_up_lifts_c_then_b_then_a_on_every_mesh() {
    let mut way_up = Vec::new();
    for n in [10usize, 20, 40] {
        let scene = parse(&example_3_2_down_and_up(n), "example_3_2_up.ron").unwrap();
        let records = run(&scene);
        common::assert_audited(&scene, &records);
        let up: Vec<&IncrementRecord> = records.iter().filter(|r| r.stage == Some(1)).collect();
        let touches: Vec<(u32, String)> = (up.iter().flat_map(|r| &r.events))
            .filter_map(|e| match e {
                Event::Contact(c) if c.change == ContactChange::Activated => {
                    Some((c.node, c.body.clone()))
                }
                _ => None,
            })
            .collect();
        let (tip_a, tip_b, tip_c) = (n as u32 + 1, n as u32 + 2, 3 * n as u32 + 3);
        assert_eq!(
            touches[..3],
            [
                (1000, "C".to_string()),
                (tip_c, "B".to_string()),
                (tip_b, "A".to_string())
            ],
            "{n} elements: on the way up {touches:?}"
        );
        let slot = |id: u32| scene.model.nodes.iter().position(|x| x.id == id).unwrap();
        let at: Vec<[f64; 4]> = (1..=8)
            .map(|k| {
                let v = -0.8 + 0.1 * k as f64;
                let r = (up.iter())
                    .rfind(|r| (r.prescribed[0] - v).abs() < 1e-9)
                    .expect("a step lands there");
                let force = (r.reactions.iter())
                    .find(|x| x.node == 1000 && x.dof == "v")
                    .unwrap()
                    .value;
                let height = |id: u32| r.nodes[slot(id)][1];
                [force, height(tip_a), height(tip_b), height(tip_c)]
            })
            .collect();
        way_up.push(at);
    }
    let (h10, h20, h40) = (&way_up[0], &way_up[1], &way_up[2]);
    let mut compared = 0;
    for k in 0..8 {
        for q in 0..4 {
            let (a, b, c) = (h10[k][q], h20[k][q], h40[k][q]);
            let estimate = 4.0 / 3.0 * (a - b).abs();
            let floor = 1e-6 * a.abs().max(1e-3);
            assert!(
                (a - c).abs() <= estimate + floor,
                "step {k}, quantity {q}: 10 elements {a}, 20 {b}, 40 {c}"
            );
            compared += usize::from(estimate > floor);
        }
    }
    assert!(compared >= 6, "quantities that moved: {compared}");
    eprintln!(
        "the way up: pin force at the top {:.6} N on 10 elements, {:.6} on 20, {:.6} on 40",
        h10[7][0], h20[7][0], h40[7][0]
    );
}

/// The load paths `docs/scene-format.md` shows (weight then pull; indent then drag to and fro;
/// load, unload, reload, reverse) run to the end of their stages, every state audited, and end
/// where their last stages say.
#[test]
fn the_documented_load_paths_run_to_their_end() {
    let text = std::fs::read_to_string(
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("docs/scene-format.md"),
    )
    .unwrap();
    let blocks: Vec<&str> = (text.split("```ron\n").skip(1))
        .filter_map(|b| b.split("```").next())
        .filter(|b| b.contains("stages:"))
        .collect();
    assert_eq!(blocks.len(), 3, "three documented paths");
    for block in blocks {
        let scene = parse(block, "scene-format.md").unwrap();
        let records = run(&scene);
        common::assert_audited(&scene, &records);
        let path = scene.model.path.as_ref().unwrap();
        let end = path.point(path.total_steps() - 1).unwrap();
        let last = records.last().unwrap();
        assert_eq!(last.prescribed, end.prescribed, "{}", scene.file.name);
        let factors = if last.load_factors.is_empty() {
            vec![last.load_factor; end.factors.len()]
        } else {
            last.load_factors.clone()
        };
        assert_eq!(factors, end.factors, "{}", scene.file.name);
        assert_eq!(last.stage, Some(path.stages.len() - 1));
    }
}
