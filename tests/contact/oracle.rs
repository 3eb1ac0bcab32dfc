//! The oracle (`tsm_contact::audit`) on the histories users make: every built-in contact scene
//! at step sizes from half to three times its own, Example 3.2 at 200 step sizes, steps that
//! land exactly on a beam's line or an obstacle's, and the oracle's teeth: pass-throughs and
//! a contact from the far side planted in real histories, and a stored history with the pin
//! through beam A.

use crate::common;

use common::findings;
use tsm_contact::audit::audit_history;
use tsm_contact::history::{History, Topology};
use tsm_contact::scene::{builtin::builtin, parse, Scene};
use tsm_contact::solver::{IncrementRecord, SolveError};

/// The records of a run of `scene` over `steps` steps (up to the first error), and the error.
fn solve(scene: &Scene, steps: usize) -> (Vec<IncrementRecord>, Option<SolveError>) {
    let mut solver = scene.solver().expect("a stable scene");
    let mut history = History::default();
    let mut error = None;
    for _ in 0..steps {
        if let Err(e) = solver.step(&mut history) {
            error = Some(e);
            break;
        }
    }
    (history.increments, error)
}

/// Panics listing every finding in `bad` (one line each), if any.
fn assert_none(bad: &[String]) {
    assert!(
        bad.is_empty(),
        "{} finding(s):\n{}",
        bad.len(),
        bad.join("\n")
    );
}

/// `scene` with every prescribed step and the load step scaled by `f`, and as many steps as
/// cover the same path.
fn scaled(scene: &Scene, f: f64) -> Scene {
    let mut s = scene.clone();
    for p in &mut s.model.prescribed {
        p.per_step *= f;
    }
    s.model.load_per_step *= f;
    s.steps = ((scene.steps as f64) / f).ceil() as usize;
    s
}

/// Runs `scene` at each step factor. Returns how many runs completed, and every finding.
fn sweep(name: &str, scene: &Scene, factors: &[f64]) -> (usize, Vec<String>) {
    let mut done = 0;
    let mut bad = Vec::new();
    for &f in factors {
        let s = scaled(scene, f);
        let (records, error) = solve(&s, s.steps);
        done += usize::from(error.is_none());
        for x in findings(&s, &records) {
            bad.push(format!("{name} at {f:.4}x: {x}"));
        }
    }
    (done, bad)
}

/// `n` factors spread evenly over [lo, hi].
fn spread(n: usize, lo: f64, hi: f64) -> Vec<f64> {
    (0..n)
        .map(|k| lo + (hi - lo) * k as f64 / (n - 1) as f64)
        .collect()
}

/// A stored history of Example 3.2 with the pin driven 0.0098 m a step, every increment marked
/// converged, in which beam A springs back up through the pin at increment 13 (the pin rests
/// inside the sag of A's element 9, then A is straight above it). The oracle finds the pin
/// through A there.
#[test]
fn the_oracle_finds_the_stored_pass_through() {
    let text = include_str!("../fixtures/example_3_2_pin_through_a.json");
    let h: History = serde_json::from_str(text).expect("a history");
    let scene = builtin("example_3_2").unwrap().unwrap();
    let found = audit_history(&h, Some(&Topology::of(&scene.model))).expect("audited");
    let through = found
        .iter()
        .find(|f| f.body.as_deref() == Some("A") && f.what.contains("went through"))
        .unwrap_or_else(|| panic!("no pass-through found: {found:?}"));
    assert_eq!(through.increment, 13, "{through}");
    // Without a topology, a version 1 history cannot be audited.
    assert!(audit_history(&h, None).is_err());
}

/// Planted pass-throughs: in a clean run of Example 3.2 the oracle finds nothing; moved below
/// beam A, or with its contact taken out of the record while pressed into A, the pin is found.
#[test]
fn the_oracle_finds_planted_pass_throughs() {
    let scene = builtin("example_3_2").unwrap().unwrap();
    let (records, error) = solve(&scene, 20);
    assert!(error.is_none(), "{error:?}");
    assert!(
        findings(&scene, &records).is_empty(),
        "{:?}",
        findings(&scene, &records)
    );
    let pin = (scene.model.nodes.iter())
        .position(|n| n.id == 34)
        .expect("the pin is node 34");
    // A's tip (node 11) moved 0.05 m under beam B (at y = -0.1) in the first record, where it
    // is clear above B.
    let tip = (scene.model.nodes.iter())
        .position(|n| n.id == 11)
        .expect("A's tip is node 11");
    let mut planted = records.clone();
    assert!(planted[0].contacts.iter().all(|c| c.node != 11));
    planted[0].nodes[tip][1] = -0.15;
    let found = findings(&scene, &planted[..1]);
    assert!(
        found
            .iter()
            .any(|f| f.node == Some(11) && f.body.as_deref() == Some("B")),
        "{found:?}"
    );
    // A record with the pin resting on A, its contact taken out and the pin moved 0.01 m below
    // A's line: a release through the beam.
    let k = records
        .iter()
        .position(|r| !r.contacts.is_empty())
        .expect("a record in contact");
    let mut planted = records.clone();
    planted[k].contacts.clear();
    planted[k].nodes[pin][1] -= 0.01;
    let y_a = planted[k].nodes[pin][1];
    let found = findings(&scene, &planted[..=k]);
    assert!(
        found
            .iter()
            .any(|f| f.node == Some(34) && f.what.contains("went through")),
        "pin at y = {y_a}: {found:?}"
    );
}

/// A planted contact from the far side: in a clean run of Example 3.2, the pin's contact on A
/// in one record with its force turned round (the contact pulling the pin onto A's underside,
/// the side the pin never came from). The oracle finds the pin held on the far side of A there,
/// and nothing in the record as solved.
#[test]
fn the_oracle_finds_a_contact_pressing_from_the_far_side() {
    let scene = builtin("example_3_2").unwrap().unwrap();
    let (records, error) = solve(&scene, 20);
    assert!(error.is_none(), "{error:?}");
    let k = (records.iter())
        .position(|r| r.contacts.iter().any(|c| c.node == 34 && c.force != 0.0))
        .expect("a record with the pin pressing on A");
    assert!(findings(&scene, &records[..=k]).is_empty());
    let mut planted = records[..=k].to_vec();
    for c in planted[k].contacts.iter_mut().filter(|c| c.node == 34) {
        c.force = -c.force;
        c.pressure = -c.pressure;
    }
    let found = findings(&scene, &planted);
    assert!(
        found.iter().any(|f| f.node == Some(34)
            && f.increment == planted[k].increment
            && f.what.contains("far side")),
        "{found:?}"
    );
}

/// A stiff arm whose clamp turns 1 degree a step: its tip lands on the line y = -0.5 at step 30
/// to within round-off (1 m at 30 degrees), on a clamped beam or on a `Line` obstacle. The
/// contact is recorded, and the oracle finds nothing.
#[test]
fn a_tip_landing_exactly_on_a_line_is_a_contact() {
    let turn = -std::f64::consts::PI / 180.0;
    for floor in ["beam", "line"] {
        let (body, contact, obstacle) = if floor == "beam" {
            (
                r#", (name: "floor", section: "s", path: [(0.0, -0.5), (2.0, -0.5)], elements: 8, first_node: 101)"#,
                r#"contacts: [(nodes: [11], bodies: ["floor"])],"#,
                "",
            )
        } else {
            (
                "",
                "",
                r#"obstacles: [(name: "floor", shape: Line(from: (0.0, -0.5), to: (2.0, -0.5)), nodes: [11])],"#,
            )
        };
        let text = format!(
            r#"(
            name: "landing", formulation: BernoulliEuler,
            sections: [(name: "s", E: 1.0e3, A: 1.0e3, I: 1.0, G: 400.0)],
            bodies: [(name: "arm", section: "s", path: [(0.5, 0.0), (1.5, 0.0)], elements: 10, first_node: 1){body}],
            supports: [(node: 1, u: true, v: true){extra}],
            prescribed: [(node: 1, dof: Phi, per_step: {turn:?})],
            {contact}
            {obstacle}
            control: (steps: 34),
        )"#,
            extra = if floor == "beam" {
                ", (node: 101, u: true, v: true, phi: true), (node: 109, u: true, v: true, phi: true)"
            } else {
                ""
            },
        );
        let scene = parse(&text, "landing").unwrap_or_else(|e| panic!("{e}"));
        let (records, error) = solve(&scene, 34);
        assert!(error.is_none(), "{floor}: {error:?}");
        let touched = records
            .iter()
            .position(|r| !r.contacts.is_empty() || !r.obstacle_contacts.is_empty());
        assert!(
            touched.is_some_and(|k| (29..=30).contains(&k)),
            "{floor}: contact at {touched:?}"
        );
        // On the rigid line the tip stays on it; the beam floor gives under it.
        let tip = scene.model.nodes.iter().position(|n| n.id == 11).unwrap();
        let last = records.last().unwrap();
        if floor == "line" {
            assert!(
                last.nodes[tip][1] >= -0.5 - 1e-6,
                "the tip at {:?}",
                last.nodes[tip]
            );
        }
        let found = findings(&scene, &records);
        assert!(found.is_empty(), "{floor}: {found:?}");
    }
}

/// A load on a held dof goes into its support and changes nothing else: Example 3.2 with 1e6 N
/// on clamped node 1 has the same positions, element forces, contact forces and other
/// reactions as without it, to 1e-9 relative.
#[test]
fn a_load_on_a_held_dof_changes_nothing() {
    let plain = builtin("example_3_2").unwrap().unwrap();
    let mut loaded = plain.clone();
    let node = loaded.model.nodes.iter().position(|n| n.id == 1).unwrap();
    loaded.model.loads.push(tsm_contact::solver::Load {
        node,
        force: [0.0, 1.0e6, 0.0],
        group: 0,
    });
    assert!(plain.model.loads.is_empty() && plain.model.distributed.is_empty());
    // The load factor grows 0.1 a step: the held load reaches 3e6 N.
    loaded.model.load_per_step = 0.1;
    let (a, ea) = solve(&plain, 30);
    let (b, eb) = solve(&loaded, 30);
    assert!(ea.is_none() && eb.is_none(), "{ea:?} {eb:?}");
    assert_eq!(a.len(), b.len());
    let close = |x: f64, y: f64, scale: f64| (x - y).abs() <= 1e-9 * scale;
    // Positions against the scene's size (1 m).
    let size = 1.0;
    for (ra, rb) in a.iter().zip(&b) {
        for (p, q) in ra.nodes.iter().zip(&rb.nodes) {
            assert!(
                close(p[0], q[0], size) && close(p[1], q[1], size),
                "increment {}: {p:?} vs {q:?}",
                ra.increment
            );
        }
        let fmax = ra
            .element_forces
            .iter()
            .flatten()
            .fold(1e-30f64, |m, v| m.max(v.abs()));
        for (p, q) in ra.element_forces.iter().zip(&rb.element_forces) {
            for k in 0..3 {
                assert!(
                    close(p[k], q[k], fmax),
                    "increment {}: forces {p:?} vs {q:?}",
                    ra.increment
                );
            }
        }
        assert_eq!(
            ra.contacts.len(),
            rb.contacts.len(),
            "increment {}",
            ra.increment
        );
        for (p, q) in ra.contacts.iter().zip(&rb.contacts) {
            assert!(
                close(p.force, q.force, fmax),
                "increment {}: contact {p:?} vs {q:?}",
                ra.increment
            );
        }
        // The loaded support's reaction takes the load; the others are unchanged.
        for (p, q) in ra.reactions.iter().zip(&rb.reactions) {
            let load = if (p.node, p.dof.as_str()) == (1, "v") {
                1.0e6 * rb.load_factor
            } else {
                0.0
            };
            assert!(
                close(p.value, q.value + load, fmax),
                "increment {}: reaction {p:?} vs {q:?}",
                ra.increment
            );
        }
    }
}

/// Example 3.2 at 200 step sizes from 0.005 to 0.05 m: the oracle finds nothing in any run,
/// and the runs complete.
#[test]
fn example_3_2_at_200_step_sizes_never_passes_through() {
    let scene = builtin("example_3_2").unwrap().unwrap();
    let own = scene.model.prescribed[0].per_step.abs();
    let factors: Vec<f64> = spread(200, 0.005, 0.05)
        .into_iter()
        .map(|s| s / own)
        .collect();
    let (done, bad) = sweep("example_3_2", &scene, &factors);
    assert_none(&bad);
    eprintln!("example_3_2: {done} of 200 runs complete");
    assert!(done >= 191, "{done} of 200 runs complete");
}

/// Every built-in contact scene at 40 step sizes from 0.5 to 3 times its own: the oracle
/// finds nothing.
#[test]
fn every_builtin_contact_scene_at_40_step_sizes_never_passes_through() {
    let mut bad = Vec::new();
    for (file, _) in tsm_contact::scene::builtin::BUILTIN {
        let name = file.trim_end_matches(".ron");
        if name == "example_3_2" {
            continue;
        }
        let scene = builtin(name).unwrap().unwrap();
        if scene.model.contacts.is_empty() && scene.model.obstacles.is_empty() {
            continue;
        }
        let (done, found) = sweep(name, &scene, &spread(40, 0.5, 3.0));
        eprintln!("{name}: {done} of 40 complete, {} finding(s)", found.len());
        bad.extend(found);
    }
    assert_none(&bad);
}

/// One-step loads onto small circles: a roller (R = 20 mm, pilot-driven) pushed 0.1 m down in
/// one step onto strips of 10 to 40 elements over a node and between nodes, and a fixed peg
/// (R = 20 mm) under cantilevers of 10 to 40 elements loaded in one step. The roller never
/// ends below the strip nor the strip below the peg: the oracle finds nothing, and a run that
/// stops does so with a located error.
#[test]
fn one_step_loads_onto_small_circles_never_pass_through() {
    let strip = |n: usize, extra: &str| {
        format!(
            r#"(
            name: "small circle", units: N_m, formulation: BernoulliEuler,
            sections: [(name: "strip", E: 2.0e11, A: 2.0e-4, I: 1.6667e-9)],
            bodies: [(name: "strip", section: "strip", path: [(0.0, 0.0), (1.0, 0.0)], elements: {n}, first_node: 1)],
            {extra}
            control: (steps: 1),
        )"#
        )
    };
    let mut bad = Vec::new();
    for n in [10, 20, 40] {
        for x in [0.5, 0.5 + 0.5 / n as f64] {
            let roller = strip(
                n,
                &format!(
                    r#"nodes: [(id: 1000, x: {x:?}, y: 0.03, rotation: false)],
                    supports: [(node: 1, u: true, v: true, phi: true), (node: {last}, u: true, v: true)],
                    prescribed: [(node: 1000, dof: U, per_step: 0.0), (node: 1000, dof: V, per_step: -0.1)],
                    obstacles: [(name: "roller", shape: Circle(centre: ({x:?}, 0.03), radius: 0.02), bodies: ["strip"], pilot: 1000)],"#,
                    last = n + 1
                ),
            );
            let peg = strip(
                n,
                &format!(
                    r#"supports: [(node: 1, u: true, v: true, phi: true)],
                    loads: [(node: {last}, fy: -30.0)],
                    obstacles: [(name: "peg", shape: Circle(centre: ({x:?}, -0.05), radius: 0.02), bodies: ["strip"])],"#,
                    last = n + 1
                ),
            );
            for (what, text) in [("roller", roller), ("peg", peg)] {
                let scene = parse(&text, what).unwrap_or_else(|e| panic!("{what}: {e}"));
                let (records, error) = solve(&scene, 1);
                for f in findings(&scene, &records) {
                    bad.push(format!("{what} on {n} elements at x = {x}: {f}"));
                }
                if let Some(e) = error {
                    eprintln!("{what} on {n} elements at x = {x}: {e}");
                }
            }
        }
    }
    assert_none(&bad);
}

/// Every built-in scene, in both formulations, at its own step: the oracle finds nothing (the
/// scenes without contact are audited for equilibrium and status).
#[test]
fn every_builtin_scene_in_both_formulations_passes_the_audit() {
    use tsm_contact::solver::Formulation;
    let mut bad = Vec::new();
    for (file, _) in tsm_contact::scene::builtin::BUILTIN {
        let name = file.trim_end_matches(".ron");
        for f in [Formulation::Timoshenko, Formulation::BernoulliEuler] {
            let mut scene = builtin(name).unwrap().unwrap();
            scene.model.formulation = f;
            let (records, error) = solve(&scene, scene.steps);
            if let Some(e) = error {
                eprintln!("{name} ({f:?}): {e}");
            }
            for x in findings(&scene, &records) {
                bad.push(format!("{name} ({f:?}): {x}"));
            }
        }
    }
    assert_none(&bad);
}

/// A plank laid on a floor beam (zero gap over a metre) is refused without a side, since no
/// rule tells which side of the floor its nodes are on; declared `side: Left` (above the floor,
/// drawn left to right), it rests on the floor under a load at its tip: the run completes, its
/// nodes stay above the floor, and the oracle finds nothing.
#[test]
fn a_plank_laid_on_a_floor_declared_above_it_rests_on_it() {
    let text = |side: &str| {
        format!(
            r#"(
            name: "plank", formulation: Timoshenko,
            sections: [(name: "s", E: 1.0e3, A: 1.0e3, I: 1.0, G: 400.0)],
            bodies: [
                (name: "floor", section: "s", path: [(0.0, 0.0), (2.0, 0.0)], elements: 8, first_node: 1),
                (name: "plank", section: "s", path: [(-0.4, 0.0), (1.6, 0.0)], elements: 8, first_node: 101),
            ],
            supports: [(node: 1, u: true, v: true, phi: true), (node: 9, u: true, v: true, phi: true),
                       (node: 101, u: true, v: true, phi: true)],
            loads: [(node: 109, fy: -1.0)],
            contacts: [(node_bodies: ["plank"], bodies: ["floor"]{side})],
            control: (steps: 10),
        )"#
        )
    };
    let plain = parse(&text(""), "plank");
    assert!(
        plain.is_err() || plain.as_ref().unwrap().solver().is_err(),
        "a plank on the floor's line without a side"
    );
    let scene = parse(&text(", side: Left"), "plank").unwrap_or_else(|e| panic!("{e}"));
    let (records, error) = solve(&scene, scene.steps);
    assert!(error.is_none(), "{error:?}");
    assert!(
        !records.last().unwrap().contacts.is_empty(),
        "the plank rests on the floor"
    );
    let found = findings(&scene, &records);
    assert!(found.is_empty(), "{found:?}");
    // Each plank node over the floor is at or above the floor's chord under it.
    let last = records.last().unwrap();
    let at = |id: u32| last.nodes[scene.model.nodes.iter().position(|n| n.id == id).unwrap()];
    for id in 103..=109 {
        let p = at(id);
        let k = ((p[0] / 0.25).floor() as u32).min(7);
        let (a, b) = (at(1 + k), at(2 + k));
        let off = ((b[0] - a[0]) * (p[1] - a[1]) - (b[1] - a[1]) * (p[0] - a[0]))
            / (b[0] - a[0]).hypot(b[1] - a[1]);
        assert!(
            off > -1e-3,
            "plank node {id} {off:e} below the floor's chord"
        );
    }
}

/// A record whose prescribed node stayed where it was while the record says it moved is in
/// equilibrium from its own forces; the oracle finds it by the held dofs, and a support that
/// moved likewise. Each tamper is well above the check's slack (1e-9 of the model's size) and
/// far below anything the other checks see.
#[test]
fn the_oracle_finds_a_prescribed_node_left_behind_and_a_support_that_moved() {
    let scene = builtin("example_3_2").unwrap().unwrap();
    let (records, error) = solve(&scene, 6);
    assert!(error.is_none(), "{error:?}");
    assert!(findings(&scene, &records).is_empty());
    let topology = Topology::of(&scene.model);
    let ids: Vec<u32> = scene.model.nodes.iter().map(|n| n.id).collect();
    let last = records.len() - 1;

    let (pin, dof) = topology.prescribed[0].clone();
    let mut left_behind = records.clone();
    left_behind[last].prescribed[0] -= 1e-6;
    let found = findings(&scene, &left_behind);
    assert!(
        found.iter().any(|f| f.increment == records[last].increment
            && f.node == Some(pin)
            && f.what.contains(&format!("{dof} is"))
            && f.what.contains("prescribed value")),
        "{found:?}"
    );

    let (held, dof) = (topology.held.iter())
        .find(|h| !topology.prescribed.contains(h) && h.1 != "phi")
        .expect("a support")
        .clone();
    let slot = ids.iter().position(|&i| i == held).expect("a node");
    let k = if dof == "u" { 0 } else { 1 };
    let mut moved = records.clone();
    moved[last].nodes[slot][k] += 1e-6;
    let found = findings(&scene, &moved);
    assert!(
        found
            .iter()
            .any(|f| f.node == Some(held) && f.what.contains("its support")),
        "{found:?}"
    );
}
