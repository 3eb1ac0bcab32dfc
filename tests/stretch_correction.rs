//! The stretch correction of Newton's update (`SolverParams::stretch_correction`, the scene's
//! `control: (stretch_correction: true)`): it changes how an increment converges, not where.
//! Each figure is checked against the same run without it (plain Newton) and, for the
//! roll-up, against the regular polygon.

use tsm_contact::scene::{builtin, parse, Scene};
use tsm_contact::solver::{IncrementRecord, Silent};

/// Built-in scene `file` on `n` elements (its default mesh `default_n`), with the
/// correction `on` or off (the default).
fn variant(file: &str, default_n: usize, n: usize, on: bool) -> Scene {
    let mut text = builtin::text(file)
        .expect("built-in")
        .replace(&format!("elements: {default_n}"), &format!("elements: {n}"))
        .replace(
            &format!("(node: {},", default_n + 1),
            &format!("(node: {},", n + 1),
        );
    if on {
        text = text.replace("control: (", "control: (stretch_correction: true, ");
    }
    parse(&text, file).expect("valid variant")
}

fn run(sc: &Scene) -> Vec<IncrementRecord> {
    let mut s = sc.solver().expect("stable");
    (0..sc.steps)
        .flat_map(|_| s.step(&mut Silent).expect("converges"))
        .collect()
}

fn iterations(recs: &[IncrementRecord]) -> usize {
    recs.iter().map(|r| r.iterations).sum()
}

/// Mattiasson's cantilever, k = 10 in 10 steps, on 1000 elements. Plain Newton zig-zags and
/// needs 12 increments and 145 iterations (measured; at least 130 asserted, so that the test
/// fails if the correction stops doing anything); with the correction on, 11 and 88
/// (at most 11 and 100 asserted). The tip lands on the same place both ways, to 1e-8 L
/// (measured 1e-16; the increments are accepted at relative residuals up to 5e-6, the
/// round-off floor of 1 mm elements).
#[test]
fn mattiasson_on_1000_elements_converges_in_fewer_iterations() {
    let recs = |on| run(&variant("mattiasson.ron", 32, 1000, on));
    let (plain, always) = (recs(false), recs(true));
    assert!(iterations(&plain) >= 130, "plain {}", iterations(&plain));
    assert!(
        always.len() <= 11 && iterations(&always) <= 100,
        "always: {} increments, {} iterations",
        always.len(),
        iterations(&always)
    );
    let tip = |r: &[IncrementRecord]| r.last().expect("record").nodes[1000];
    let (a, b) = (tip(&plain), tip(&always));
    assert!(
        (a[0] - b[0]).abs() < 1e-8 && (a[1] - b[1]).abs() < 1e-8,
        "{a:?} {b:?}"
    );
}

/// The roll-up by 2 pi EI/L on 16 elements in 10 steps: 60 iterations of plain Newton
/// (measured; at least 50 asserted), 20 with the correction on (at most 30), and the
/// same regular polygon either way: the middle node within 1e-12 L of plain Newton's
/// (measured 2e-15).
#[test]
fn roll_up_converges_in_a_third_of_the_iterations() {
    let plain = run(&variant("end_moment.ron", 16, 16, false));
    let always = run(&variant("end_moment.ron", 16, 16, true));
    assert!(iterations(&plain) >= 50, "plain {}", iterations(&plain));
    assert!(iterations(&always) <= 30, "always {}", iterations(&always));
    let middle = |r: &[IncrementRecord]| r.last().expect("record").nodes[8];
    let (a, b) = (middle(&plain), middle(&always));
    assert!(
        (a[0] - b[0]).abs() < 1e-12 && (a[1] - b[1]).abs() < 1e-12,
        "{a:?} {b:?}"
    );
}

/// The Bernoulli-Euler pin on 1024 elements with the correction on: near element ends its
/// contact force is round-off (K44 ~ 3 EI / li^3), and at li/l = 0.9988 a spurious tensile
/// force once released the pin and let the beam spring back through it, two elements from
/// where its side was remembered, undetected. The crossing test now catches a swept crossing
/// of any element of the body: the increment is cut back, and the run ends with the pin on
/// the beam, against Reissner's beam (`pin_elastica`, no shear) with the contact point to
/// 1e-7 L (measured 2.4e-8, the h^2 level) and the force to 5e-6 of its size (measured
/// 1.7e-6; increments near element ends are accepted at residuals up to 2e-3).
#[test]
fn bernoulli_euler_pin_on_1024_elements_stays_on_the_beam() {
    use tsm_contact::solver::Formulation;
    use tsm_contact::work_precision::pin_errors;
    let mut sc = variant("pin_on_cantilever.ron", 16, 1024, true);
    sc.model.formulation = Formulation::BernoulliEuler;
    sc.params.roundoff_factor = 0.0;
    let recs = run(&sc);
    let [force, arc] = pin_errors(&sc, &recs).expect("the pin ends on the beam");
    assert!(arc < 1e-7 && force < 5e-6, "arc {arc:e}, force {force:e}");
}
