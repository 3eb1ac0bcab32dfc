//! The hard cases of the stability suite, each a scene written out in full and run
//! (`run::run`): pins near element ends, sliding across a mesh, a strip pressed flat, slender
//! and stubby cantilevers, stacked beams, short elements next to long ones, a beam rolled up by
//! an end moment, and Lee's frame by arc length.

use super::run::{first_peak, run, run_scene, Path, Run};
use crate::scene::builtin::builtin;
use crate::scene::from_scene_file;
use crate::scene::remesh::remesh;
use crate::solver::Formulation;

/// The paper's strip section (E = 2.0e7 N/m^2, A = 3.0e-4 m^2, I = 2.2e-8 m^4, G = 7.142e6).
const STRIP: &str = r#"(name: "strip", E: 2.0e7, A: 3.0e-4, I: 2.2e-8, G: 7.142e6)"#;

/// A pin above a 10-element, 1 m cantilever at li/l = `xi` of element 5, pushed down 0.01 m
/// per step for 10 steps.
pub fn pin_near_end(xi: f64, f: Formulation) -> Run {
    let text = format!(
        r#"(
        name: "pin near an element end", formulation: {f:?},
        sections: [{STRIP}],
        nodes: [(id: 100, x: {x}, y: 0.001, rotation: false)],
        bodies: [(name: "beam", section: "strip", path: [(0.0, 0.0), (1.0, 0.0)], elements: 10, first_node: 1)],
        supports: [(node: 1, u: true, v: true, phi: true), (node: 100, u: true)],
        prescribed: [(node: 100, dof: V, per_step: -0.01)],
        contacts: [(nodes: [100], bodies: ["beam"])],
        control: (steps: 10),
    )"#,
        x = 0.5 + 0.1 * xi
    );
    run(
        &format!("pin pushed at li/l = {xi} of an element"),
        &text,
        &Path::Steps(10),
    )
}

/// A pin pressed onto a 1 m cantilever of `n` elements next to the clamp, dragged along the
/// whole beam and off its free tip while it descends, lifted, brought back over the middle and
/// pressed on again. Increments: `per_leg` times the legs' relative lengths.
pub fn slide_across(n: usize, f: Formulation) -> Run {
    let text = format!(
        r#"(
        name: "pin sliding along a cantilever", formulation: {f:?},
        sections: [{STRIP}],
        nodes: [(id: 1000, x: 0.01, y: 0.0005, rotation: false)],
        bodies: [(name: "beam", section: "strip", path: [(0.0, 0.0), (1.0, 0.0)], elements: {n}, first_node: 1)],
        supports: [(node: 1, u: true, v: true, phi: true)],
        prescribed: [(node: 1000, dof: U, per_step: 0.0), (node: 1000, dof: V, per_step: 0.0)],
        contacts: [(nodes: [1000], bodies: ["beam"])],
    )"#,
    );
    // Two increments per element on the way out.
    let out = 2 * n;
    let legs = vec![
        (vec![0.0, -0.0025], 0.0, 5),
        (vec![1.09, -0.25], 0.0, out),
        (vec![1.09, 0.1], 0.0, 10),
        (vec![0.5, 0.1], 0.0, 10),
        (vec![0.5, -0.1], 0.0, 10),
    ];
    run(
        &format!("pin slid across a {n}-element cantilever, off the tip and back on"),
        &text,
        &Path::Legs(legs),
    )
}

/// A 0.9 m cantilever (20 elements) 5 mm above a clamped-clamped base beam (17 elements, 100
/// times stiffer), loaded on every node and pressed flat onto it, unloaded (released), and
/// loaded again (re-contact).
pub fn pressed_flat(f: Formulation, per_leg: usize) -> Run {
    let loads: Vec<String> = (2..=21)
        .map(|id| format!("(node: {id}, fy: -1.0)"))
        .collect();
    let text = format!(
        r#"(
        name: "beam pressed flat onto another", formulation: {f:?},
        sections: [{STRIP}, (name: "base", E: 2.0e7, A: 3.0e-2, I: 2.2e-6, G: 7.142e6)],
        bodies: [
            (name: "strip", section: "strip", path: [(0.0, 0.005), (0.9, 0.005)], elements: 20, first_node: 1),
            (name: "base", section: "base", path: [(-0.05, 0.0), (1.0, 0.0)], elements: 17, first_node: 101),
        ],
        supports: [(node: 1, u: true, v: true, phi: true), (node: 101, u: true, v: true, phi: true), (node: 118, u: true, v: true, phi: true)],
        loads: [{loads}],
        contacts: [(node_bodies: ["strip"], bodies: ["base"])],
        control: (load_per_step: 0.0),
    )"#,
        loads = loads.join(", "),
    );
    let peak = 0.5;
    let legs = vec![
        (vec![], peak, per_leg),
        (vec![], 0.0, per_leg),
        (vec![], peak, per_leg),
    ];
    run(
        "beam pressed flat onto a base beam, released and pressed again",
        &text,
        &Path::Legs(legs),
    )
}

/// Mattiasson cantilever (k = 5, 32 elements) with a square section of slenderness `l_over_h`
/// (so E A L^2 / E I = 12 (L/h)^2). Measure: tip deflection w/L against the elastica.
pub fn slender(l_over_h: f64, f: Formulation) -> Run {
    let (k, _, w_ref) = crate::reports::work_precision::MATTIASSON[1];
    let h = 1.0 / l_over_h;
    let (a, i) = (h * h, h.powi(4) / 12.0);
    // E chosen so that E I = 1: P = k.
    let e = 1.0 / i;
    let text = format!(
        r#"(
        name: "slender cantilever", formulation: {f:?},
        sections: [(name: "square", E: {e:e}, A: {a:e}, I: {i:e}, nu: 0.3, Ae: {ae:e})],
        bodies: [(name: "cantilever", section: "square", path: [(0.0, 0.0), (1.0, 0.0)], elements: 32, first_node: 1)],
        supports: [(node: 1, u: true, v: true, phi: true)],
        loads: [(node: 33, fy: -1.0)],
        control: (steps: 10, load_per_step: {step}),
    )"#,
        ae = a * 5.0 / 6.0,
        step = k / 10.0,
    );
    let mut r = run(
        &format!("Mattiasson k = 5, L/h = {l_over_h:e}"),
        &text,
        &Path::Steps(10),
    );
    if r.row.converged {
        let w = -r.records.last().expect("increments").nodes[32][1];
        r.row.measure = Some(("tip w/L".into(), w, w_ref));
    }
    r
}

/// A stubby cantilever (L/h = `l_over_h`, square section, nu = 0.3, shear area 5/6 A) under a
/// small tip load: tip deflection against the exact linear Timoshenko value
/// P L^3 / (3 E I) + P L / (G Ae) (Bernoulli-Euler: the first term only).
pub fn stubby(l_over_h: f64, f: Formulation) -> Run {
    let h = 1.0 / l_over_h;
    let (a, i, e, nu) = (h * h, h.powi(4) / 12.0, 1.0e6, 0.3);
    let g = e / (2.0 * (1.0 + nu));
    let ae = a * 5.0 / 6.0;
    // A load small enough that the response is linear to 1e-9.
    let p = 1e-9 * 3.0 * e * i;
    let text = format!(
        r#"(
        name: "stubby cantilever", formulation: {f:?},
        sections: [(name: "block", E: {e:e}, A: {a:e}, I: {i:e}, G: {g:e}, Ae: {ae:e})],
        bodies: [(name: "cantilever", section: "block", path: [(0.0, 0.0), (1.0, 0.0)], elements: 4, first_node: 1)],
        supports: [(node: 1, u: true, v: true, phi: true)],
        loads: [(node: 5, fy: {fy:e})],
        control: (steps: 1, load_per_step: 1.0),
    )"#,
        fy = -p,
    );
    let mut r = run(
        &format!("stubby cantilever, L/h = {l_over_h}"),
        &text,
        &Path::Steps(1),
    );
    let exact = p / (3.0 * e * i)
        + match f {
            Formulation::Timoshenko => p / (g * ae),
            Formulation::BernoulliEuler => 0.0,
        };
    if r.row.converged {
        let w = -r.records.last().expect("increment").nodes[4][1];
        r.row.measure = Some(("tip deflection".into(), w, exact));
    }
    r
}

/// Two equal strips stacked face to face on [0, 4] m, 1e-4 m apart, clamps at opposite ends,
/// every node a candidate on the other strip; A's clamp driven down 1 mm in 4 steps. With
/// `b_elements` = 16 B's nodes lie right under A's (node on node), with 17 between them. Nearly
/// every node touches in the first increment and nearly all must let go. Measure: the total
/// contact force against the closed form (they touch at x = L/2 only; each strip is a cantilever
/// loaded there).
pub fn stacked(b_elements: usize, f: Formulation) -> Run {
    let (d, gap, a) = (1e-3, 1e-4, 2.0);
    let text = format!(
        r#"(
        name: "stacked strips", formulation: {f:?},
        sections: [{STRIP}],
        bodies: [
            (name: "A", section: "strip", path: [(0.0, 0.0), (4.0, 0.0)], elements: 16, first_node: 1),
            (name: "B", section: "strip", path: [(0.0, {y}), (4.0, {y})], elements: {b_elements}, first_node: 101),
        ],
        supports: [(node: 1, u: true, phi: true), (node: {clamp}, u: true, v: true, phi: true)],
        prescribed: [(node: 1, dof: V, per_step: {step})],
        contacts: [(node_bodies: ["A"], bodies: ["B"]), (node_bodies: ["B"], bodies: ["A"])],
        control: (steps: 4),
    )"#,
        y = -gap,
        clamp = 101 + b_elements,
        step = -d / 4.0,
    );
    let layout = if b_elements == 16 {
        "node on node"
    } else {
        "nodes interleaved"
    };
    let mut r = run(
        &format!("strips stacked face to face, {layout}"),
        &text,
        &Path::Steps(4),
    );
    let (ei, gae) = (2.0e7 * 2.2e-8, 7.142e6 * 3.0e-4);
    let shear = match f {
        Formulation::Timoshenko => a / gae,
        Formulation::BernoulliEuler => 0.0,
    };
    let exact = (d - gap) / (2.0 * (a * a * a / (3.0 * ei) + shear));
    if r.row.converged {
        let last = r.records.last().expect("increment");
        let total: f64 = last.contacts.iter().map(|c| c.pressure.max(0.0)).sum();
        r.row.measure = Some(("contact force (N)".into(), total, exact));
    }
    r
}

/// Mattiasson k = 5 on a graded mesh: 16 elements whose lengths alternate in the ratio
/// `ratio` : 1 (very short elements next to long ones). Measure: w/L against the elastica.
pub fn short_next_to_long(ratio: f64, f: Formulation) -> Run {
    let (k, _, w_ref) = crate::reports::work_precision::MATTIASSON[1];
    let unit = 1.0 / (8.0 * (1.0 + ratio));
    let mut x = 0.0;
    let mut path = vec!["(0.0, 0.0)".to_string()];
    for s in 0..16 {
        x += if s % 2 == 0 { unit * ratio } else { unit };
        let x = if s == 15 { 1.0 } else { x };
        path.push(format!("({x:e}, 0.0)"));
    }
    let text = format!(
        r#"(
        name: "graded cantilever", formulation: {f:?},
        sections: [(name: "inextensible", E: 1.0, A: 1.0e6, I: 1.0, G: 1.0e12)],
        bodies: [(name: "cantilever", section: "inextensible", path: [{path}], elements: 1, first_node: 1)],
        supports: [(node: 1, u: true, v: true, phi: true)],
        loads: [(node: 17, fy: -1.0)],
        control: (steps: 10, load_per_step: {step}),
    )"#,
        path = path.join(", "),
        step = k / 10.0,
    );
    let mut r = run(
        &format!("Mattiasson k = 5, element lengths alternating {ratio:e} : 1"),
        &text,
        &Path::Steps(10),
    );
    if r.row.converged {
        let w = -r.records.last().expect("increments").nodes[16][1];
        r.row.measure = Some(("tip w/L".into(), w, w_ref));
    }
    r
}

/// A 1 m cantilever (EI = 1, EA = 1e6, `n` elements) rolled up by an end moment of
/// `turns` * 2 pi EI/L in `steps` increments. Measure: the tip's distance from the exact circle
/// position (R sin t, R (1 - cos t)), R = L/t, t = 2 pi turns.
pub fn roll_up(turns: f64, n: usize, steps: usize, f: Formulation) -> Run {
    let m = turns * std::f64::consts::TAU;
    let text = format!(
        r#"(
        name: "roll-up", formulation: {f:?},
        sections: [(name: "inextensible", E: 1.0, A: 1.0e6, I: 1.0, G: 1.0e12)],
        bodies: [(name: "cantilever", section: "inextensible", path: [(0.0, 0.0), (1.0, 0.0)], elements: {n}, first_node: 1)],
        supports: [(node: 1, u: true, v: true, phi: true)],
        loads: [(node: {tip}, m: {m:e})],
        control: (steps: {steps}, load_per_step: {step:e}),
    )"#,
        tip = n + 1,
        step = 1.0 / steps as f64,
    );
    let mut r = run(
        &format!("cantilever rolled up {turns} turns by an end moment"),
        &text,
        &Path::Steps(steps),
    );
    if r.row.converged {
        let tip = r.records.last().expect("increments").nodes[n];
        let radius = 1.0 / m;
        let exact = [radius * m.sin(), radius * (1.0 - m.cos())];
        let err = (tip[0] - exact[0]).hypot(tip[1] - exact[1]);
        r.row.measure = Some(("tip position error (m)".into(), err, 0.0));
    }
    r
}

/// Lee's frame (built-in scene) with `n` elements per member, arc-length `ds`, `steps` arcs.
/// Measure: the first limit load (parabola through the peak) against `reference` if given.
pub fn lee_frame(n: usize, ds: f64, steps: usize, f: Formulation) -> Run {
    assert!(n.is_multiple_of(5), "the load sits at 1/5 of the beam");
    let scene = builtin("lee_frame").expect("built-in").expect("valid");
    let mut file = remesh(&scene.file, n).expect("one body, the load at a node of the new mesh");
    file.control.arc_length = Some(ds);
    file.control.steps = steps;
    file.formulation = f;
    let case = format!("Lee's frame, {n} elements per member, arc length {ds}");
    let scene = from_scene_file(file, &case).expect("valid");
    let mut r = run_scene(&case, &scene, &Path::Steps(steps));
    let curve: Vec<(f64, f64)> = r
        .records
        .iter()
        .map(|x| (x.increment as f64, x.load_factor))
        .collect();
    if let Some(p) = first_peak(&curve) {
        r.row.measure = Some((
            "limit load P (reference: converged mesh)".into(),
            p,
            f64::NAN,
        ));
    }
    r
}
