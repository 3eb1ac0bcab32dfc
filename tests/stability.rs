//! Hard cases: Williams' toggle driven through its limit point under apex displacement control.
//! The limit load of the shipped scene (10 elements per member, 0.03 in steps) must lie within
//! 1% of a converged reference computed here (40 elements per member, 0.003 in steps), each peak
//! located by a parabola through the first local maximum and its neighbours.

use tsm_contact::scene::{builtin::BUILTIN, parse};
use tsm_contact::solver::Silent;

fn apex_reactions(elements: usize, step: f64, steps: usize) -> Vec<(f64, f64)> {
    let text = BUILTIN
        .iter()
        .find(|(f, _)| *f == "williams_toggle.ron")
        .unwrap()
        .1;
    let apex = elements + 1;
    let text = text
        .replace("elements: 10", &format!("elements: {elements}"))
        .replace(
            "(node: 11, dof: V, per_step: -0.03)",
            &format!("(node: {apex}, dof: V, per_step: {})", -step),
        )
        .replace(
            "(node: 21, u: true",
            &format!("(node: {}, u: true", 2 * elements + 1),
        )
        .replace("steps: 40", &format!("steps: {steps}"));
    let sc = parse(&text, "toggle").unwrap();
    let mut solver = sc.solver().unwrap();
    let mut out = Vec::new();
    for _ in 0..steps {
        for r in solver
            .step(&mut Silent)
            .expect("displacement control passes the limit point")
        {
            let v = r
                .reactions
                .iter()
                .find(|x| x.node == apex as u32 && x.dof == "v")
                .unwrap()
                .value;
            out.push((-r.prescribed[0], v.abs()));
        }
    }
    out
}

/// Index of the first local maximum of the load.
fn first_max(curve: &[(f64, f64)]) -> usize {
    (1..curve.len() - 1)
        .find(|&k| curve[k].1 >= curve[k - 1].1 && curve[k].1 > curve[k + 1].1)
        .expect("a limit point")
}

/// The first local maximum of the load, refined by a parabola through its neighbours.
fn peak(curve: &[(f64, f64)]) -> f64 {
    let k = first_max(curve);
    let ((x0, y0), (x1, y1), (x2, y2)) = (curve[k - 1], curve[k], curve[k + 1]);
    // Parabola through three points: its maximum.
    let d = (x0 - x1) * (x0 - x2) * (x1 - x2);
    let a = (x2 * (y1 - y0) + x1 * (y0 - y2) + x0 * (y2 - y1)) / d;
    let b = (x2 * x2 * (y0 - y1) + x1 * x1 * (y2 - y0) + x0 * x0 * (y1 - y2)) / d;
    let c = y1 - a * x1 * x1 - b * x1;
    let xm = -b / (2.0 * a);
    a * xm * xm + b * xm + c
}

#[test]
fn toggle_limit_load_within_one_percent_of_a_converged_reference() {
    let coarse = apex_reactions(10, 0.03, 40);
    let reference = apex_reactions(40, 0.003, 400);
    let (pc, pr) = (peak(&coarse), peak(&reference));
    assert!(
        ((pc - pr) / pr).abs() < 0.01,
        "limit load {pc} vs converged {pr}"
    );
    // Past the limit point the load really falls (the snap-through under load control) before
    // the stretched toggle stiffens again.
    let dip = coarse
        .iter()
        .skip(first_max(&coarse))
        .map(|p| p.1)
        .fold(f64::MAX, f64::min);
    assert!(
        dip < 0.95 * pr,
        "no load drop after the limit point: minimum {dip}, peak {pr}"
    );
}
