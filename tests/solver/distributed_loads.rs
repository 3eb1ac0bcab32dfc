//! Distributed loads, checked against references computed here independently: the closed
//! forms of linear beam theory for small loads (a uniform load, a load over part of the span,
//! a triangular load, self-weight from a density), and for large deflection the elastica of a
//! cantilever under a uniform load per length, integrated by shooting, with the error falling
//! as h^2 under mesh refinement for both element formulations. The sections are stiff in
//! stretch and shear (EA and G A a million times EI / L^2), as the elastica assumes.

use tsm_contact::scene::parse;
use tsm_contact::solver::Silent;

const EI: f64 = 2.0e2;
const L: f64 = 2.0;

/// A cantilever of `n` elements along x, clamped at node 1, with `extra` scene text (loads),
/// solved in `steps` steps of load factor 1/steps with `formulation`; returns the free tip's
/// (x, y).
fn tip(n: usize, formulation: &str, extra: &str, steps: usize) -> [f64; 2] {
    let text = format!(
        r#"(
    name: "cantilever",
    formulation: {formulation},
    sections: [(name: "s", E: 2.0e5, A: 1.0e3, I: 1.0e-3, G: 1.0e12)],
    bodies: [(name: "beam", section: "s", path: [(0.0, 0.0), ({L}, 0.0)], elements: {n}, first_node: 1)],
    supports: [(node: 1, u: true, v: true, phi: true)],
    {extra}
    control: (steps: {steps}),
)"#
    );
    let scene = parse(&text, "cantilever.ron").expect("a valid scene");
    let mut solver = scene.solver().unwrap();
    for _ in 0..steps {
        solver.step(&mut Silent).expect("converges");
    }
    let (p, _) = solver.node_state(n);
    p
}

/// The tip deflection (downward positive) of `tip` for a uniform load.
fn deflection(n: usize, formulation: &str, w: f64, steps: usize) -> f64 {
    let extra = format!("distributed: [(body: \"beam\", q: (0.0, {}))],", -w);
    -tip(n, formulation, &extra, steps)[1]
}

/// The elastica of a cantilever of length `L` and stiffness `EI` under a vertical load `w` per
/// length: theta' = -M / EI, M' = -w (L - s) cos(theta), theta(0) = 0, M(L) = 0, by RK4 with
/// `steps` steps and bisection on M(0). Returns the tip's (x, y).
fn elastica(w: f64, steps: usize) -> [f64; 2] {
    let run = |m0: f64| {
        let h = L / steps as f64;
        // y = [x, y, theta, M].
        let g = |s: f64, y: [f64; 4]| {
            [
                y[2].cos(),
                y[2].sin(),
                -y[3] / EI,
                -w * (L - s) * y[2].cos(),
            ]
        };
        let mut y = [0.0, 0.0, 0.0, m0];
        for k in 0..steps {
            let s = k as f64 * h;
            let k1 = g(s, y);
            let a = |y: [f64; 4], k: [f64; 4], c: f64| {
                [
                    y[0] + c * k[0],
                    y[1] + c * k[1],
                    y[2] + c * k[2],
                    y[3] + c * k[3],
                ]
            };
            let k2 = g(s + h / 2.0, a(y, k1, h / 2.0));
            let k3 = g(s + h / 2.0, a(y, k2, h / 2.0));
            let k4 = g(s + h, a(y, k3, h));
            for i in 0..4 {
                y[i] += h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
            }
        }
        y
    };
    // M(0) lies between 0 and the linear value w L^2 / 2 (the arm shortens as the beam bends).
    let (mut lo, mut hi) = (0.0, w * L * L / 2.0 * 1.000001);
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if run(mid)[3] > 0.0 {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    let y = run(0.5 * (lo + hi));
    [y[0], y[1]]
}

#[test]
fn the_elastica_reference_is_linear_theory_for_a_small_load() {
    let w = 1e-4;
    let exact = w * L.powi(4) / (8.0 * EI);
    let e = elastica(w, 4000);
    assert!(
        ((-e[1]) - exact).abs() < 1e-6 * exact,
        "{} vs {exact}",
        -e[1]
    );
}

/// A small uniform load: the tip deflection w L^4 / (8 EI) of linear theory.
#[test]
fn a_small_uniform_load_bends_a_cantilever_as_linear_theory_says() {
    let w = 1e-3;
    let exact = w * L.powi(4) / (8.0 * EI);
    for f in ["BernoulliEuler", "Timoshenko"] {
        let d = deflection(32, f, w, 1);
        assert!((d - exact).abs() < 2e-3 * exact, "{f}: {d} vs {exact}");
    }
}

/// A uniform load over the first half of the span only (elements 1 to 16 of 32): the tip
/// deflection w a^3 (4 L - a) / (24 EI) with a = L / 2.
#[test]
fn a_load_over_part_of_the_span_bends_as_linear_theory_says() {
    let (w, a) = (1e-3, L / 2.0);
    let exact = w * a.powi(3) * (4.0 * L - a) / (24.0 * EI);
    let extra = format!(
        "distributed: [(body: \"beam\", elements: (1, 16), q: (0.0, {}))],",
        -w
    );
    let d = -tip(32, "BernoulliEuler", &extra, 1)[1];
    assert!((d - exact).abs() < 2e-3 * exact, "{d} vs {exact}");
}

/// A load falling linearly from q0 at the clamp to 0 at the tip: the tip deflection
/// q0 L^4 / (30 EI).
#[test]
fn a_triangular_load_bends_as_linear_theory_says() {
    let q0 = 1e-3;
    let exact = q0 * L.powi(4) / (30.0 * EI);
    let extra = format!(
        "distributed: [(body: \"beam\", q: (0.0, {}), q_end: (0.0, 0.0))],",
        -q0
    );
    let d = -tip(32, "BernoulliEuler", &extra, 1)[1];
    assert!((d - exact).abs() < 3e-3 * exact, "{d} vs {exact}");
}

/// Self-weight from the section's density and the scene's gravity is the distributed load
/// density A g, per length.
#[test]
fn self_weight_is_density_times_area_times_gravity() {
    let (rho, g) = (2.0e-7, 5.0);
    let w = rho * 1.0e3 * g;
    let exact = w * L.powi(4) / (8.0 * EI);
    let text = format!(
        r#"(
    name: "heavy",
    formulation: BernoulliEuler,
    sections: [(name: "s", E: 2.0e5, A: 1.0e3, I: 1.0e-3, density: {rho})],
    bodies: [(name: "beam", section: "s", path: [(0.0, 0.0), ({L}, 0.0)], elements: 32, first_node: 1)],
    supports: [(node: 1, u: true, v: true, phi: true)],
    control: (steps: 1, gravity: (0.0, {})),
)"#,
        -g
    );
    let mut solver = parse(&text, "heavy.ron").unwrap().solver().unwrap();
    solver.step(&mut Silent).unwrap();
    let d = -solver.node_state(32).0[1];
    assert!((d - exact).abs() < 2e-3 * exact, "{d} vs {exact}");
}

/// A heavy cantilever, w L^3 / EI = 3: the tip against the elastica on 8, 16 and 32
/// elements, for both formulations; the error falls by about 4 with each halving of h (3 to 5)
/// and is under 0.2% of L on 32 elements.
#[test]
fn a_heavy_cantilever_converges_to_the_elastica_as_h_squared() {
    let w = 3.0 * EI / L.powi(3);
    let reference = elastica(w, 20_000);
    assert!(
        -reference[1] > 0.25 * L,
        "a large deflection: {reference:?}"
    );
    let load = format!("distributed: [(body: \"beam\", q: (0.0, {}))],", -w);
    converges_as_h_squared("fixed load", &load, reference);
}

/// The tip of the cantilever under `load` (scene text) in 10 steps against `reference`, on 8,
/// 16 and 32 elements, both formulations: the error over L falls by 3 to 5 with each halving
/// (h^2), and is under 2e-3 on 32 elements. Prints the errors.
fn converges_as_h_squared(what: &str, load: &str, reference: [f64; 2]) {
    for f in ["BernoulliEuler", "Timoshenko"] {
        let errors: Vec<f64> = [8, 16, 32]
            .iter()
            .map(|&n| {
                let p = tip(n, f, load, 10);
                (p[0] - reference[0]).hypot(p[1] - reference[1])
            })
            .collect();
        eprintln!(
            "{f}, {what}: tip error / L on 8, 16, 32 elements: {:.3e} {:.3e} {:.3e}",
            errors[0] / L,
            errors[1] / L,
            errors[2] / L
        );
        for k in 0..2 {
            let ratio = errors[k] / errors[k + 1];
            assert!((3.0..5.0).contains(&ratio), "{f}: errors {errors:?}");
        }
        assert!(errors[2] < 2e-3 * L, "{f}: errors {errors:?}");
    }
}

/// Inside an element the moment and shear diagrams follow the distributed load: on a cantilever
/// of two elements under a small uniform load w, M(s) = w (L - s)^2 / 2 and V(s) = w (L - s)
/// in size at every quarter of the element at the clamp (the end values come from the solver,
/// the parabola between them from the load), to 1e-3 of the clamp's values.
#[cfg(feature = "figures")]
#[test]
fn the_diagrams_follow_the_load_inside_an_element() {
    use tsm_contact::figure::value_at;
    use tsm_contact::figure::Diagram;
    let w = 1e-3;
    let text = format!(
        r#"(
    name: "cantilever",
    formulation: BernoulliEuler,
    sections: [(name: "s", E: 2.0e5, A: 1.0e3, I: 1.0e-3)],
    bodies: [(name: "beam", section: "s", path: [(0.0, 0.0), ({L}, 0.0)], elements: 2, first_node: 1)],
    supports: [(node: 1, u: true, v: true, phi: true)],
    distributed: [(body: "beam", q: (0.0, {}))],
    control: (steps: 1),
)"#,
        -w
    );
    let scene = parse(&text, "cantilever.ron").unwrap();
    let mut solver = scene.solver().unwrap();
    let r = solver.step(&mut Silent).unwrap().pop().unwrap();
    let model = &scene.model;
    let (m0, v0) = (w * L * L / 2.0, w * L);
    for k in 0..=4 {
        let x = k as f64 / 4.0;
        let s = x * L / 2.0;
        let m = value_at(model, &r, Diagram::Moment, 0, x);
        let v = value_at(model, &r, Diagram::Shear, 0, x);
        assert!(
            (m.abs() - w * (L - s).powi(2) / 2.0).abs() < 1e-3 * m0,
            "M at s = {s}: {m}"
        );
        assert!(
            (v.abs() - w * (L - s)).abs() < 1e-3 * v0,
            "V at s = {s}: {v}"
        );
    }
}

/// The planar elastica of an inextensible cantilever along x, clamped at s = 0 and free at
/// s = L, under a load per length p(s, theta) (its x and y components): x' = cos theta,
/// y' = sin theta, theta' = M / EI, F' = -p, M' = -(cos theta F_y - sin theta F_x), with F and
/// M what the part beyond s exerts on the part before it; F(L) = 0 and M(L) = 0 are met by
/// Newton on (F_x, F_y, M) at the clamp (differences for the Jacobian), RK4 on `steps` steps.
/// Returns the tip's (x, y).
fn elastica_general(p: &dyn Fn(f64, f64) -> [f64; 2], guess: [f64; 3], steps: usize) -> [f64; 2] {
    let run = |u: [f64; 3]| {
        let h = L / steps as f64;
        let g = |s: f64, y: &[f64; 6]| {
            let (c, sn) = (y[2].cos(), y[2].sin());
            let load = p(s, y[2]);
            [
                c,
                sn,
                y[5] / EI,
                -load[0],
                -load[1],
                -(c * y[4] - sn * y[3]),
            ]
        };
        let mut y = [0.0, 0.0, 0.0, u[0], u[1], u[2]];
        for k in 0..steps {
            let s = k as f64 * h;
            let add = |y: &[f64; 6], k: &[f64; 6], c: f64| std::array::from_fn(|i| y[i] + c * k[i]);
            let k1 = g(s, &y);
            let k2 = g(s + h / 2.0, &add(&y, &k1, h / 2.0));
            let k3 = g(s + h / 2.0, &add(&y, &k2, h / 2.0));
            let k4 = g(s + h, &add(&y, &k3, h));
            for i in 0..6 {
                y[i] += h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
            }
        }
        y
    };
    let mut u = guess;
    for _ in 0..50 {
        let y = run(u);
        let r = [y[3], y[4], y[5]];
        if r.iter().map(|v| v.abs()).fold(0.0, f64::max) < 1e-12 {
            return [y[0], y[1]];
        }
        let mut jac = [[0.0; 3]; 3];
        for c in 0..3 {
            let mut v = u;
            let dh = 1e-7 * (1.0 + u[c].abs());
            v[c] += dh;
            let yv = run(v);
            for (row, rv) in [yv[3], yv[4], yv[5]].iter().enumerate() {
                jac[row][c] = (rv - r[row]) / dh;
            }
        }
        let m = nalgebra::Matrix3::from_fn(|i, j| jac[i][j]);
        let du = m
            .lu()
            .solve(&nalgebra::Vector3::new(-r[0], -r[1], -r[2]))
            .unwrap();
        for c in 0..3 {
            u[c] += du[c];
        }
    }
    panic!("the shooting does not converge");
}

/// The general shooting meets the fixed-direction shooting: a fixed load (0, -w) gives the same
/// tip.
#[test]
fn the_general_elastica_meets_the_fixed_load_one() {
    let w = 3.0 * EI / L.powi(3);
    let fixed = elastica(w, 4000);
    let general = elastica_general(&|_, _| [0.0, -w], [0.0, w * L, -w * L * L / 2.0], 4000);
    assert!((fixed[0] - general[0]).hypot(fixed[1] - general[1]) < 1e-9 * L);
}

/// A cantilever under a uniform follower pressure across it (q_n = -w per current length,
/// w L^3 / EI = 4): the tip against the elastica whose load turns with the section,
/// p = -w (-sin theta, cos theta), on 8, 16 and 32 elements, both formulations; the error falls
/// as h^2.
#[test]
fn a_follower_pressure_converges_to_its_elastica_as_h_squared() {
    let w = 4.0 * EI / L.powi(3);
    let reference = elastica_general(
        &|_, theta| [w * theta.sin(), -w * theta.cos()],
        [0.0, w * L, -w * L * L / 2.0],
        20_000,
    );
    let fixed = elastica(w, 20_000);
    eprintln!(
        "follower and fixed elastica tips {:.3} L apart",
        (reference[0] - fixed[0]).hypot(reference[1] - fixed[1]) / L
    );
    assert!(
        (reference[0] - fixed[0]).hypot(reference[1] - fixed[1]) > 0.02 * L,
        "the follower load bends the beam otherwise than a fixed one: {reference:?} {fixed:?}"
    );
    let load = format!(
        "distributed: [(body: \"beam\", q: (0.0, {}), follower: true)],",
        -w
    );
    converges_as_h_squared("follower", &load, reference);
}

/// The solver's tangent with a follower load is the derivative of its unbalanced force:
/// central differences at a deformed state of a cantilever under a pressure varying along it.
#[test]
fn the_tangent_with_a_follower_load_is_the_derivative_of_the_unbalanced_force() {
    let text = format!(
        r#"(
    name: "pressed",
    sections: [(name: "s", E: 2.0e5, A: 1.0, I: 1.0e-3)],
    bodies: [(name: "beam", section: "s", path: [(0.0, 0.0), ({L}, 0.0)], elements: 6, first_node: 1)],
    supports: [(node: 1, u: true, v: true, phi: true)],
    distributed: [(body: "beam", q: (20.0, -60.0), q_end: (-10.0, -20.0), follower: true)],
    control: (steps: 4),
)"#
    );
    let mut solver = parse(&text, "pressed.ron").unwrap().solver().unwrap();
    for _ in 0..2 {
        solver.step(&mut Silent).unwrap();
    }
    let d = solver.displacements().to_vec();
    assert!(d.iter().any(|v| v.abs() > 0.05), "deformed");
    let (_, k, free) = solver.unbalanced_force_and_tangent(&d);
    let h = 1e-7;
    let mut worst = 0.0f64;
    for (c, &g) in free.iter().enumerate() {
        let (mut p, mut m) = (d.clone(), d.clone());
        p[g] += h;
        m[g] -= h;
        let (rp, _, _) = solver.unbalanced_force_and_tangent(&p);
        let (rm, _, _) = solver.unbalanced_force_and_tangent(&m);
        for r in 0..free.len() {
            // The unbalanced force is loads minus internal forces: its derivative is -K.
            let fd = -(rp[r] - rm[r]) / (2.0 * h);
            worst = worst.max((fd - k[(r, c)]).abs() / k[(c, c)].abs().max(1.0));
        }
    }
    assert!(worst < 1e-5, "worst relative difference {worst:.2e}");
    // And without the follower part of the tangent, the difference is not small.
    let unsym = (0..free.len())
        .flat_map(|r| (0..free.len()).map(move |c| (r, c)))
        .map(|(r, c)| (k[(r, c)] - k[(c, r)]).abs())
        .fold(0.0, f64::max);
    assert!(
        unsym > 1.0,
        "the pressure makes the tangent unsymmetric: {unsym}"
    );
}

/// Errors name the entry and field: a follower load under arc-length control, a range outside
/// the body, a density without gravity.
#[test]
fn bad_distributed_loads_are_refused_with_their_field() {
    let scene = |extra: &str, section: &str, control: &str| {
        format!(
            r#"(
    name: "bad",
    sections: [(name: "s", E: 2.0e5, A: 1.0, I: 1.0e-3{section})],
    bodies: [(name: "beam", section: "s", path: [(0.0, 0.0), (2.0, 0.0)], elements: 4, first_node: 1)],
    supports: [(node: 1, u: true, v: true, phi: true)],
    {extra}
    control: ({control}),
)"#
        )
    };
    let cases = [
        (
            scene(
                "distributed: [(body: \"beam\", q: (0.0, -1.0), follower: true)],",
                "",
                "steps: 4, arc_length: 0.1",
            ),
            "distributed[0].follower (body \"beam\")",
            6,
        ),
        (
            scene(
                "distributed: [(body: \"beam\", elements: (2, 9), q: (0.0, -1.0))],",
                "",
                "steps: 4",
            ),
            "distributed[0].elements (body \"beam\")",
            6,
        ),
        (
            scene("", ", density: 7850.0", "steps: 4"),
            "control.gravity",
            3,
        ),
    ];
    for (text, field, line) in cases {
        let e = parse(&text, "bad.ron").expect_err("refused");
        assert_eq!(e.field, field, "{e}");
        assert_eq!(e.line, Some(line), "{e}");
    }
}

/// The clamp's reactions balance the load, computed here from the accepted node positions
/// alone: for a follower pressure q_n across each deformed chord D (the force q_n R D at the
/// chord's middle, R the quarter turn) and for a fixed load w per undeformed length (w l0 at
/// the middle of each chord), forces and moment about the clamp, at every increment, to 1e-7
/// of the load.
#[test]
fn the_reactions_balance_the_distributed_load_at_every_increment() {
    for (follower, q) in [(true, -40.0), (false, -40.0)] {
        let text = format!(
            r#"(
    name: "loaded",
    sections: [(name: "s", E: 2.0e5, A: 1.0e3, I: 1.0e-3)],
    bodies: [(name: "beam", section: "s", path: [(0.0, 0.0), ({L}, 0.0)], elements: 12, first_node: 1)],
    supports: [(node: 1, u: true, v: true, phi: true)],
    distributed: [(body: "beam", q: (0.0, {q}), follower: {follower})],
    control: (steps: 5),
)"#
        );
        let mut solver = parse(&text, "loaded.ron").unwrap().solver().unwrap();
        for _ in 0..5 {
            for r in solver.step(&mut Silent).unwrap() {
                let x0 = r.nodes[0];
                let (mut f, mut m) = ([0.0; 2], 0.0);
                for k in 0..12 {
                    let (a, b) = (r.nodes[k], r.nodes[k + 1]);
                    let dd = [b[0] - a[0], b[1] - a[1]];
                    let load = if follower {
                        [-q * dd[1], q * dd[0]]
                    } else {
                        [0.0, q * L / 12.0]
                    };
                    let load = load.map(|v| v * r.load_factor);
                    let mid = [(a[0] + b[0]) / 2.0 - x0[0], (a[1] + b[1]) / 2.0 - x0[1]];
                    f[0] += load[0];
                    f[1] += load[1];
                    m += mid[0] * load[1] - mid[1] * load[0];
                }
                let reaction = |dof: &str| {
                    r.reactions
                        .iter()
                        .find(|x| x.node == 1 && x.dof == dof)
                        .unwrap()
                        .value
                };
                let size = f[0].hypot(f[1]);
                assert!(
                    (reaction("u") + f[0]).abs() < 1e-7 * size,
                    "follower {follower}"
                );
                assert!(
                    (reaction("v") + f[1]).abs() < 1e-7 * size,
                    "follower {follower}"
                );
                assert!(
                    (reaction("phi") + m).abs() < 1e-7 * size * L,
                    "follower {follower}: moment {} vs {m}",
                    reaction("phi")
                );
            }
        }
    }
}
