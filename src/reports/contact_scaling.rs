//! Contact scaling report: a bed of n beam elements (0.1 m each, clamped at both ends, pinned
//! every 10 elements) pressed by a row of n/10 pins, one in every span, each pin a
//! contact candidate on the bed. Three steps: the pins come down 2 mm a step (closing a 1 mm gap
//! in the first) while sliding 0.3 elements along. Every pin is near the one long body, so the
//! body-level broad phase passes every pair, and without the element grid each probe tries all
//! n elements (quadratic). Timed with the broad phase on (body boxes plus the element grid)
//! and off, release build, median of repeats.

use crate::reports::work_precision::timed_on;
use crate::scene::parse;
use crate::solver::Silent;

/// One size of the report.
#[derive(Clone, Debug)]
pub struct ContactScaleRow {
    /// Elements of the bed (the pins are a tenth of that).
    pub elements: usize,
    /// Contacts carrying load after the increment.
    pub loaded: usize,
    /// Newton iterations of the three steps (all active-set passes).
    pub iterations: usize,
    /// Median wall time of the three steps with the broad phase (s).
    pub with_broad_phase: f64,
    /// Median wall time without it (s), if measured.
    pub without: Option<f64>,
}

/// The bed of `n` elements (a multiple of 10) and its n/10 pins.
pub fn pins_on_bed(n: usize, broad_phase: bool) -> crate::solver::Solver {
    let len = n as f64 * 0.1;
    let spans = n / 10;
    let mut nodes = Vec::new();
    let mut supports = vec![
        "(node: 1, u: true, v: true, phi: true)".to_string(),
        format!("(node: {}, u: true, v: true, phi: true)", n + 1),
    ];
    let mut prescribed = Vec::new();
    let mut pins = Vec::new();
    for k in 0..spans {
        let id = 1_000_001 + k;
        nodes.push(format!(
            "(id: {id}, x: {:?}, y: 1e-3, rotation: false)",
            k as f64 + 0.43
        ));
        prescribed.push(format!("(node: {id}, dof: V, per_step: -2e-3)"));
        prescribed.push(format!("(node: {id}, dof: U, per_step: 0.03)"));
        pins.push(id.to_string());
        if k > 0 {
            supports.push(format!("(node: {}, u: true, v: true)", 1 + 10 * k));
        }
    }
    let text = format!(
        r#"(
        name: "pins on a bed of {n}", formulation: Timoshenko,
        sections: [(name: "s", E: 2.0e7, A: 3.0e-4, I: 2.2e-8, G: 7.142e6)],
        nodes: [{nodes}],
        bodies: [(name: "bed", section: "s", path: [(0.0, 0.0), ({len:?}, 0.0)], elements: {n}, first_node: 1)],
        supports: [{supports}],
        prescribed: [{prescribed}],
        contacts: [(nodes: [{pins}], bodies: ["bed"])],
        control: (steps: 3),
    )"#,
        nodes = nodes.join(", "),
        supports = supports.join(", "),
        prescribed = prescribed.join(", "),
        pins = pins.join(", "),
    );
    let mut sc = parse(&text, "pins on a bed").expect("valid");
    sc.params.broad_phase = broad_phase;
    sc.solver().expect("stable")
}

/// Median time of the three steps, with the loaded contacts at the end and the iterations.
fn median_step(fresh: &crate::solver::Solver, repeats: usize) -> (f64, usize, usize) {
    let (seconds, (loaded, iterations)) = timed_on(
        repeats,
        || fresh.clone(),
        |mut s| {
            let (mut loaded, mut iterations) = (0, 0);
            for _ in 0..3 {
                let recs = s.step(&mut Silent).expect("the step converges");
                iterations += recs.iter().map(|r| r.iterations).sum::<usize>();
                let last = recs.last().expect("one increment");
                loaded = last.contacts.iter().filter(|c| c.pressure > 0.0).count();
            }
            (loaded, iterations)
        },
    );
    (seconds, loaded, iterations)
}

/// Run the sizes; the broad phase off only up to `max_without` elements (it is quadratic).
pub fn measure(sizes: &[usize], max_without: usize) -> Vec<ContactScaleRow> {
    sizes
        .iter()
        .map(|&n| {
            let repeats = if n >= 10_000 { 3 } else { 7 };
            let (with_broad_phase, loaded, iterations) =
                median_step(&pins_on_bed(n, true), repeats);
            let without =
                (n <= max_without).then(|| median_step(&pins_on_bed(n, false), repeats).0);
            ContactScaleRow {
                elements: n,
                loaded,
                iterations,
                with_broad_phase,
                without,
            }
        })
        .collect()
}

/// The report as a Markdown table.
pub fn table(rows: &[ContactScaleRow]) -> String {
    let mut s = String::from(
        "| bed elements | pins | loaded contacts | iterations | 3 steps (ms) | per element per iteration (us) | without broad phase (ms) |\n|---|---|---|---|---|---|---|\n",
    );
    for r in rows {
        let pins = r.elements / 10;
        s.push_str(&format!(
            "| {} | {} | {} | {} | {:.2} | {:.3} | {} |\n",
            r.elements,
            pins,
            r.loaded,
            r.iterations,
            r.with_broad_phase * 1e3,
            r.with_broad_phase * 1e6 / (r.elements * r.iterations.max(1)) as f64,
            r.without
                .map(|t| format!("{:.2}", t * 1e3))
                .unwrap_or_default()
        ));
    }
    s
}
