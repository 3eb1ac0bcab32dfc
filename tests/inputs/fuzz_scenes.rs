//! Property tests over generated scenes: valid ones solve without panicking and every converged
//! increment is in equilibrium (residual recomputed independently of the Newton loop); invalid
//! ones are rejected with an error that names the offending field. `PROPTEST_CASES` scales the
//! run (default 1000 scenes per property).

use proptest::prelude::*;
use tsm_contact::scene::parse;
use tsm_contact::solver::{Silent, SolveError};

/// A cantilever-like body: clamp at the first point, a polyline of 1-3 segments.
fn body(name: &str, first: u32, pts: &[(f64, f64)], n: usize) -> String {
    let path: Vec<String> = pts
        .iter()
        .map(|(x, y)| format!("({x:.6}, {y:.6})"))
        .collect();
    format!(
        r#"(name: "{name}", section: "s", path: [{}], elements: {n}, first_node: {first})"#,
        path.join(", ")
    )
}

#[derive(Debug, Clone)]
struct Gen {
    e: f64,
    i: f64,
    a: f64,
    formulation: bool,
    pts: Vec<(f64, f64)>,
    n: usize,
    load: (f64, f64, f64),
    drive: Option<f64>,
    steps: usize,
}

fn gen() -> impl Strategy<Value = Gen> {
    (
        1e5f64..1e8,
        1e-9f64..1e-7,
        1e-5f64..1e-3,
        any::<bool>(),
        prop::collection::vec((0.2f64..1.0, -1.0f64..1.0), 1..4),
        1usize..6,
        (-1.0f64..1.0, -1.0f64..1.0, -0.2f64..0.2),
        prop::option::of(-0.05f64..0.05),
        1usize..4,
    )
        .prop_map(|(e, i, a, formulation, segs, n, load, drive, steps)| {
            let mut pts = vec![(0.0, 0.0)];
            let mut ang: f64 = 0.0;
            for (len, turn) in segs {
                ang += turn;
                let (x, y) = *pts.last().unwrap();
                pts.push((x + len * ang.cos(), y + len * ang.sin()));
            }
            Gen {
                e,
                i,
                a,
                formulation,
                pts,
                n,
                load,
                drive,
                steps,
            }
        })
}

fn scene_text(g: &Gen) -> (String, u32) {
    let nodes = (g.pts.len() - 1) * g.n + 1;
    let tip = nodes as u32;
    let f = if g.formulation {
        "Timoshenko"
    } else {
        "BernoulliEuler"
    };
    // Loads scaled to the beam so that each step is a moderate rotation.
    let ei = g.e * g.i;
    let len: f64 = g
        .pts
        .windows(2)
        .map(|w| (w[1].0 - w[0].0).hypot(w[1].1 - w[0].1))
        .sum();
    let p = ei / (len * len);
    let (loads, prescribed) = match g.drive {
        Some(d) => (
            String::new(),
            format!(
                "prescribed: [(node: {tip}, dof: V, per_step: {:.6})],",
                d * len
            ),
        ),
        None => (
            format!(
                "loads: [(node: {tip}, fx: {:.6e}, fy: {:.6e}, m: {:.6e})],",
                g.load.0 * p,
                g.load.1 * p,
                g.load.2 * p * len
            ),
            String::new(),
        ),
    };
    let text = format!(
        r#"(
        name: "generated", formulation: {f},
        sections: [(name: "s", E: {:.6e}, A: {:.6e}, I: {:.6e}, nu: 0.3)],
        bodies: [{}],
        supports: [(node: 1, u: true, v: true, phi: true)],
        {loads}
        {prescribed}
        control: (steps: {}),
    )"#,
        g.e,
        g.a,
        g.i,
        body("b", 1, &g.pts, g.n),
        g.steps
    );
    (text, tip)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(
        std::env::var("PROPTEST_CASES").ok().and_then(|v| v.parse().ok()).unwrap_or(1000)
    ))]

    #[test]
    fn valid_scenes_solve_and_converged_states_are_in_equilibrium(g in gen()) {
        let (text, _) = scene_text(&g);
        let sc = parse(&text, "generated").expect("generated scenes are valid");
        let mut solver = sc.solver().expect("no mechanism");
        for _ in 0..sc.steps {
            match solver.step(&mut Silent) {
                Ok(recs) => {
                    let last = recs.last().unwrap();
                    // Equilibrium evaluated afresh at the committed state (its displacements
                    // with the residues the solver carries).
                    let (r, _, _) = solver.state_unbalanced_force_and_tangent();
                    let norm = r.iter().map(|v| v * v).sum::<f64>().sqrt();
                    prop_assert!(norm <= 1.0001 * last.relative_residual * last.reference + 1e-300,
                        "residual {norm:e} vs reported {:e}", last.relative_residual * last.reference);
                    prop_assert!(last.relative_residual <= 1e-8);
                }
                // A typed error is an acceptable outcome for an extreme generated scene.
                Err(SolveError::NoConvergence { .. }) => break,
                Err(e) => prop_assert!(false, "unexpected error {e}"),
            }
        }
    }

    #[test]
    fn invalid_scenes_are_rejected_with_a_named_problem(g in gen(), which in 0usize..6) {
        let (text, tip) = scene_text(&g);
        let (bad, expect) = match which {
            0 => (text.replace("(node: 1, u: true", "(node: 99999, u: true"), "unknown node id 99999"),
            1 => (text.replace(&format!("E: {:.6e}", g.e), "E: -1.0"), "sections[0].E"),
            2 => (text.replace("supports: [(node: 1, u: true, v: true, phi: true)],", ""), "mechanism"),
            3 => (text.replace("path: [(0.000000, 0.000000)", "path: [(0.000000, 0.000000), (0.000000, 0.000000)"), "zero length"),
            4 => (text.replace(&format!("elements: {},", g.n), "elements: 0,"), "bodies[0].elements"),
            _ => (text.replace(&format!("node: {tip},"), &format!("node: {},", tip + 1000)), "unknown node id"),
        };
        let err = parse(&bad, "bad.ron").expect_err("must be rejected").to_string();
        prop_assert!(err.starts_with("bad.ron"), "{err}");
        prop_assert!(err.contains(expect), "expected {expect:?} in: {err}");
    }
}
