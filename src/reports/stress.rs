//! The stability suite: hard cases run for both element formulations, each summarised as one
//! row (converged or not, increments, iterations, cut-backs, transfers, the contact point
//! closest to an element end, and an error against an independent reference where there is
//! one). `tsm-contact stress` prints the table and writes `docs/stress.md`; the tests in
//! `tests/stability.rs` check the numbers.

use crate::scene::parse;
use crate::solver::{
    ContactChange, Event, Formulation, IncrementRecord, IterationRecord, Observer, Solver,
};

/// One case of the suite, as run.
#[derive(Clone, Debug, Default)]
pub struct StressRow {
    /// What was run.
    pub case: String,
    /// Element formulation.
    pub formulation: String,
    /// Whether every increment converged.
    pub converged: bool,
    /// Converged increments (sub-increments included).
    pub increments: usize,
    /// Newton iterations in all, over every attempt (failed attempts included).
    pub iterations: usize,
    /// Most iterations in one converged increment.
    pub max_iterations: usize,
    /// Cut-backs (halved increments).
    pub cutbacks: usize,
    /// Automatic contact transfers to a neighbouring element.
    pub transfers: usize,
    /// Contact activations, releases and slide-offs.
    pub activations: usize,
    /// Releases and slide-offs.
    pub releases: usize,
    /// Largest relative residual of a converged increment.
    pub max_residual: f64,
    /// Increments accepted at the round-off floor rather than at the tolerance.
    pub at_roundoff: usize,
    /// Most contacts carrying load at once.
    pub max_contacts: usize,
    /// li/l of the contact point that came closest to an element end (if any contact).
    pub furthest_xi: Option<f64>,
    /// A measured quantity and its reference: (name, value, reference).
    pub measure: Option<(String, f64, f64)>,
    /// The typed error that stopped the run, if any.
    pub error: Option<String>,
    /// Wall time (s).
    pub seconds: f64,
}

/// Counts iterations and cut-backs as they happen.
#[derive(Default)]
struct Tally {
    iterations: usize,
    cutbacks: usize,
}

impl Observer for Tally {
    fn iteration(&mut self, _r: &IterationRecord) -> crate::solver::Flow {
        self.iterations += 1;
        crate::solver::Flow::Continue
    }
    fn event(&mut self, e: &Event) {
        if matches!(e, Event::CutBack { .. }) {
            self.cutbacks += 1;
        }
    }
}

/// A run through a list of targets (prescribed values, load factor), or scene steps.
pub struct Run {
    /// The summary row.
    pub row: StressRow,
    /// Every converged increment.
    pub records: Vec<IncrementRecord>,
    /// The solver at the end.
    pub solver: Solver,
}

fn name(f: Formulation) -> &'static str {
    match f {
        Formulation::BernoulliEuler => "Bernoulli-Euler",
        Formulation::Timoshenko => "Timoshenko",
    }
}

fn ron_name(f: Formulation) -> &'static str {
    match f {
        Formulation::BernoulliEuler => "BernoulliEuler",
        Formulation::Timoshenko => "Timoshenko",
    }
}

/// How a run advances.
pub enum Path {
    /// The scene's own steps (or arc lengths), this many.
    Steps(usize),
    /// Piecewise-linear legs: (prescribed targets, load factor, increments for the leg).
    Legs(Vec<(Vec<f64>, f64, usize)>),
}

/// Run scene text along a path and summarise it.
pub fn run(case: &str, text: &str, path: &Path) -> Run {
    let sc = parse(text, case).unwrap_or_else(|e| panic!("stress scene {case}: {e}"));
    let mut solver = sc.solver().expect("stable scene");
    let tolerance = sc.params.tolerance;
    let mut row = StressRow {
        case: case.to_string(),
        formulation: name(sc.model.formulation).to_string(),
        converged: true,
        ..StressRow::default()
    };
    let mut tally = Tally::default();
    let mut records = Vec::new();
    let clock = std::time::Instant::now();
    let mut targets: Vec<(Vec<f64>, f64)> = Vec::new();
    match path {
        Path::Steps(n) => targets.extend((0..*n).map(|_| (Vec::new(), f64::NAN))),
        Path::Legs(legs) => {
            let mut from = (solver.prescribed_values().to_vec(), solver.load_factor());
            for (p, l, n) in legs {
                for k in 1..=*n {
                    let t = k as f64 / *n as f64;
                    let pk = from.0.iter().zip(p).map(|(a, b)| a + t * (b - a)).collect();
                    targets.push((pk, from.1 + t * (l - from.1)));
                }
                from = (p.clone(), *l);
            }
        }
    }
    for (p, l) in targets {
        let result = if l.is_nan() {
            solver.step(&mut tally)
        } else {
            solver.advance_to(&p, l, &mut tally)
        };
        match result {
            Ok(recs) => records.extend(recs),
            Err(e) => {
                row.converged = false;
                row.error = Some(e.to_string());
                break;
            }
        }
    }
    row.seconds = clock.elapsed().as_secs_f64();
    row.increments = records.len();
    row.iterations = tally.iterations;
    row.cutbacks = tally.cutbacks;
    for r in &records {
        row.max_iterations = row.max_iterations.max(r.iterations);
        row.max_residual = row.max_residual.max(r.relative_residual);
        if r.relative_residual > tolerance {
            row.at_roundoff += 1;
        }
        row.max_contacts = row
            .max_contacts
            .max(r.contacts.iter().filter(|c| c.pressure > 0.0).count());
        for c in &r.contacts {
            let end = c.xi.min(1.0 - c.xi);
            if row.furthest_xi.is_none_or(|x| end < x.min(1.0 - x)) {
                row.furthest_xi = Some(c.xi);
            }
        }
        for e in &r.events {
            if let Event::Contact(c) = e {
                match c.change {
                    ContactChange::Transferred => row.transfers += 1,
                    ContactChange::Activated => row.activations += 1,
                    ContactChange::Released | ContactChange::SlidOff => row.releases += 1,
                }
            }
        }
    }
    if std::env::var_os("TSM_STRESS_LOG").is_some() {
        eprintln!(
            "{}: converged {}, {} increments, {} iterations, {:.2} s {}",
            row.case,
            row.converged,
            row.increments,
            row.iterations,
            row.seconds,
            row.error.as_deref().unwrap_or("")
        );
    }
    Run {
        row,
        records,
        solver,
    }
}

/// The paper's strip section (E = 2.0e7 N/m^2, A = 3.0e-4 m^2, I = 2.2e-8 m^4, G = 7.142e6).
const STRIP: &str = r#"(name: "strip", E: 2.0e7, A: 3.0e-4, I: 2.2e-8, G: 7.142e6)"#;

/// A pin above a 10-element, 1 m cantilever at li/l = `xi` of element 5, pushed down 0.01 m
/// per step for 10 steps.
pub fn pin_near_end(xi: f64, f: Formulation) -> Run {
    let text = format!(
        r#"(
        name: "pin near an element end", formulation: {fm},
        sections: [{STRIP}],
        nodes: [(id: 100, x: {x}, y: 0.001, rotation: false)],
        bodies: [(name: "beam", section: "strip", path: [(0.0, 0.0), (1.0, 0.0)], elements: 10, first_node: 1)],
        supports: [(node: 1, u: true, v: true, phi: true), (node: 100, u: true)],
        prescribed: [(node: 100, dof: V, per_step: -0.01)],
        contacts: [(nodes: [100], bodies: ["beam"])],
        control: (steps: 10),
    )"#,
        fm = ron_name(f),
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
        name: "pin sliding along a cantilever", formulation: {fm},
        sections: [{STRIP}],
        nodes: [(id: 1000, x: 0.01, y: 0.0005, rotation: false)],
        bodies: [(name: "beam", section: "strip", path: [(0.0, 0.0), (1.0, 0.0)], elements: {n}, first_node: 1)],
        supports: [(node: 1, u: true, v: true, phi: true)],
        prescribed: [(node: 1000, dof: U, per_step: 0.0), (node: 1000, dof: V, per_step: 0.0)],
        contacts: [(nodes: [1000], bodies: ["beam"])],
    )"#,
        fm = ron_name(f),
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
        name: "beam pressed flat onto another", formulation: {fm},
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
        fm = ron_name(f),
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
        name: "slender cantilever", formulation: {fm},
        sections: [(name: "square", E: {e:e}, A: {a:e}, I: {i:e}, nu: 0.3, Ae: {ae:e})],
        bodies: [(name: "cantilever", section: "square", path: [(0.0, 0.0), (1.0, 0.0)], elements: 32, first_node: 1)],
        supports: [(node: 1, u: true, v: true, phi: true)],
        loads: [(node: 33, fy: -1.0)],
        control: (steps: 10, load_per_step: {step}),
    )"#,
        fm = ron_name(f),
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
        name: "stubby cantilever", formulation: {fm},
        sections: [(name: "block", E: {e:e}, A: {a:e}, I: {i:e}, G: {g:e}, Ae: {ae:e})],
        bodies: [(name: "cantilever", section: "block", path: [(0.0, 0.0), (1.0, 0.0)], elements: 4, first_node: 1)],
        supports: [(node: 1, u: true, v: true, phi: true)],
        loads: [(node: 5, fy: {fy:e})],
        control: (steps: 1, load_per_step: 1.0),
    )"#,
        fm = ron_name(f),
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
        name: "stacked strips", formulation: {fm},
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
        fm = ron_name(f),
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
        name: "graded cantilever", formulation: {fm},
        sections: [(name: "inextensible", E: 1.0, A: 1.0e6, I: 1.0, G: 1.0e12)],
        bodies: [(name: "cantilever", section: "inextensible", path: [{path}], elements: 1, first_node: 1)],
        supports: [(node: 1, u: true, v: true, phi: true)],
        loads: [(node: 17, fy: -1.0)],
        control: (steps: 10, load_per_step: {step}),
    )"#,
        fm = ron_name(f),
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
        name: "roll-up", formulation: {fm},
        sections: [(name: "inextensible", E: 1.0, A: 1.0e6, I: 1.0, G: 1.0e12)],
        bodies: [(name: "cantilever", section: "inextensible", path: [(0.0, 0.0), (1.0, 0.0)], elements: {n}, first_node: 1)],
        supports: [(node: 1, u: true, v: true, phi: true)],
        loads: [(node: {tip}, m: {m:e})],
        control: (steps: {steps}, load_per_step: {step:e}),
    )"#,
        fm = ron_name(f),
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
    let text = builtin_text("lee_frame.ron")
        .replace("elements: 10", &format!("elements: {n}"))
        .replace("(node: 21,", &format!("(node: {},", 2 * n + 1))
        .replace("(node: 13,", &format!("(node: {},", n + 1 + n / 5))
        .replace("arc_length: 0.5", &format!("arc_length: {ds:e}"))
        .replace("steps: 160", &format!("steps: {steps}"))
        .replace(
            "formulation: BernoulliEuler",
            &format!("formulation: {}", ron_name(f)),
        );
    let mut r = run(
        &format!("Lee's frame, {n} elements per member, arc length {ds}"),
        &text,
        &Path::Steps(steps),
    );
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

/// The first local maximum of y over a curve, refined by a parabola through its neighbours.
pub fn first_peak(curve: &[(f64, f64)]) -> Option<f64> {
    let k = (1..curve.len().saturating_sub(1))
        .find(|&k| curve[k].1 >= curve[k - 1].1 && curve[k].1 > curve[k + 1].1)?;
    let ((x0, y0), (x1, y1), (x2, y2)) = (curve[k - 1], curve[k], curve[k + 1]);
    let d = (x0 - x1) * (x0 - x2) * (x1 - x2);
    let a = (x2 * (y1 - y0) + x1 * (y0 - y2) + x0 * (y2 - y1)) / d;
    let b = (x2 * x2 * (y0 - y1) + x1 * x1 * (y2 - y0) + x0 * x0 * (y1 - y2)) / d;
    let c = y1 - a * x1 * x1 - b * x1;
    let xm = -b / (2.0 * a);
    Some(a * xm * xm + b * xm + c)
}

fn builtin_text(file: &str) -> &'static str {
    crate::scene::builtin::text(file).expect("built-in scene")
}

/// Every case of the suite, both formulations. `long` adds the expensive variants.
pub fn suite(long: bool) -> Vec<StressRow> {
    let mut rows = Vec::new();
    for f in [Formulation::Timoshenko, Formulation::BernoulliEuler] {
        for xi in [0.9, 0.97, 0.99, 0.999, 0.9999] {
            rows.push(pin_near_end(xi, f).row);
        }
        rows.push(slide_across(50, f).row);
        rows.push(pressed_flat(f, if long { 40 } else { 10 }).row);
        rows.push(stacked(16, f).row);
        rows.push(stacked(17, f).row);
        for s in [1e1, 1e2, 1e3, 1e4] {
            rows.push(slender(s, f).row);
        }
        for s in [1.0, 2.0, 5.0] {
            rows.push(stubby(s, f).row);
        }
        for ratio in [1e1, 1e2, 1e3] {
            rows.push(short_next_to_long(ratio, f).row);
        }
        rows.push(roll_up(2.25, 32, 20, f).row);
        if long {
            rows.push(roll_up(5.0, 64, 50, f).row);
        }
        rows.push(lee_frame(10, 0.5, 160, f).row);
    }
    rows
}

/// The suite as a Markdown table.
pub fn markdown(rows: &[StressRow]) -> String {
    let mut s = String::from(
        "| case | formulation | converged | increments | iterations (max per increment) | cut-backs | largest residual (increments at round-off) | transfers | contacts (max loaded) | li/l nearest an end | measure | error |\n|---|---|---|---|---|---|---|---|---|---|---|---|\n",
    );
    for r in rows {
        let measure = match &r.measure {
            Some((n, v, refv)) if refv.is_finite() && *refv != 0.0 => {
                format!(
                    "{n}: {v:.6e} (ref {refv:.6e}, rel. err {:.1e})",
                    (v - refv).abs() / refv.abs()
                )
            }
            Some((n, v, _)) => format!("{n}: {v:.4e}"),
            None => String::new(),
        };
        s.push_str(&format!(
            "| {} | {} | {} | {} | {} ({}) | {} | {:.1e} ({}) | {} | {} | {} | {} | {} |\n",
            r.case,
            r.formulation,
            if r.converged { "yes" } else { "**no**" },
            r.increments,
            r.iterations,
            r.max_iterations,
            r.cutbacks,
            r.max_residual,
            r.at_roundoff,
            r.transfers,
            r.max_contacts,
            r.furthest_xi.map(|x| format!("{x:.5}")).unwrap_or_default(),
            measure,
            r.error.clone().unwrap_or_default().replace('|', "/"),
        ));
    }
    s
}
