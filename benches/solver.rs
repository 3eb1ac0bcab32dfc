//! Benchmarks: one Newton increment of an n-element cantilever (Mattiasson load k = 0.1), reported
//! per element and per iteration, one increment of the scale report's long beam, the paper's
//! Example 3.2, all 80 steps, and a slider-driven update of the paper scenes (Examples 3.1 and
//! 3.2), and loading, validating and solving a scene of many separate bodies.
//! Run with `cargo bench --no-default-features --features reports --bench solver`.

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use tsm_contact::scene::builtin::{builtin, with_elements};
use tsm_contact::solver::Silent;

fn cantilever(n: usize) -> tsm_contact::scene::Scene {
    let mut sc = with_elements("mattiasson", n).unwrap().unwrap();
    // One increment of k = 0.1. EA/l grows with n and so does the round-off floor of the
    // residual (eps EA/l |x| / P ~ 2e-6 at n = 1000): a tolerance of 1e-5 is reachable at every
    // n, so no attempt is cut back and the time divides cleanly by the iterations.
    sc.model.load_per_step = 0.1;
    sc.params.tolerance = 1e-5;
    sc
}

/// Time one `step` of `fresh` (cloned for each sample, outside the timing), labelled `n`.
fn one_step(
    g: &mut criterion::BenchmarkGroup<criterion::measurement::WallTime>,
    n: usize,
    fresh: &tsm_contact::solver::Solver,
) {
    g.bench_with_input(BenchmarkId::from_parameter(n), &n, |b, _| {
        b.iter_batched(
            || fresh.clone(),
            |mut s| s.step(&mut Silent).unwrap(),
            criterion::BatchSize::LargeInput,
        )
    });
}

fn newton(c: &mut Criterion) {
    let mut g = c.benchmark_group("cantilever_increment");
    for n in [100usize, 1000] {
        let sc = cantilever(n);
        let mut probe = sc.solver().unwrap();
        let recs = probe.step(&mut Silent).unwrap();
        let (iters, cut) = (recs[0].iterations, recs[0].cutbacks);
        assert_eq!(
            (recs.len(), cut),
            (1, 0),
            "the benchmark increment must not be cut back"
        );
        eprintln!("cantilever {n} elements: {iters} Newton iterations for k = 0.1 (divide the time by {iters} x {n})");
        let fresh = sc.solver().unwrap();
        one_step(&mut g, n, &fresh);
    }
    g.finish();
}

/// The second increment of the scale report's long beam (`scaling::long_beam`), as the scale
/// report times it: divide by the iterations (4) and the elements for the time per element
/// per iteration.
fn long_beam(c: &mut Criterion) {
    let mut g = c.benchmark_group("long_beam_increment");
    for n in [1000usize, 10_000] {
        let mut warm = tsm_contact::scene::builtin::long_beam(n).solver().unwrap();
        warm.step(&mut Silent).unwrap();
        one_step(&mut g, n, &warm);
    }
    g.finish();
}

fn example_3_2(c: &mut Criterion) {
    let sc = builtin("example_3_2").unwrap().unwrap();
    c.bench_function("example_3_2_all_80_steps", |b| {
        let fresh = sc.solver().unwrap();
        b.iter_batched(
            || fresh.clone(),
            |mut s| {
                for _ in 0..80 {
                    s.step(&mut Silent).unwrap();
                }
            },
            criterion::BatchSize::LargeInput,
        )
    });
}

/// A slider drag in the GUI: from the converged state halfway through a paper scene, the
/// prescribed displacement moves one step's worth and the solver converges there
/// (`Solver::advance_to`, as the worker does for `SetTarget`). Target: within a 16 ms frame.
fn slider_update(c: &mut Criterion) {
    use tsm_contact::reports::interactive::converged_states;
    let mut g = c.benchmark_group("slider_update");
    for scene in tsm_contact::reports::interactive::SCENES {
        let states = converged_states(scene);
        let state = states[states.len() / 2].clone();
        let targets = state.step_targets().expect("a scene without stages").0;
        let factors = state.load_factors().to_vec();
        g.bench_function(scene, |b| {
            b.iter_batched(
                || state.clone(),
                |mut s| s.advance_to(&targets, &factors, &mut Silent).unwrap(),
                criterion::BatchSize::LargeInput,
            )
        });
    }
    g.finish();
}

/// A scene of `n` separate one-element cantilevers, each clamped and loaded at its tip by a force
/// small enough for one increment without a cut-back: what is measured is loading, validation,
/// ordering and one small Newton solve.
fn many_bodies_text(n: usize) -> String {
    let bodies: Vec<String> = (0..n)
        .map(|k| {
            format!(
                "(name: \"b{k}\", section: \"s\", path: [({x}.0, 0.0), ({x}.0, 1.0)], elements: 1, first_node: {id})",
                x = 2 * k,
                id = 2 * k + 1
            )
        })
        .collect();
    let supports: Vec<String> = (0..n)
        .map(|k| format!("(node: {}, u: true, v: true, phi: true)", 2 * k + 1))
        .collect();
    let loads: Vec<String> = (0..n)
        .map(|k| format!("(node: {}, fx: 1.0e-3)", 2 * k + 2))
        .collect();
    format!(
        "(name: \"many\", sections: [(name: \"s\", E: 1.0, A: 1.0, I: 1.0)], bodies: [{}], supports: [{}], loads: [{}], control: (steps: 1))",
        bodies.join(", "),
        supports.join(", "),
        loads.join(", ")
    )
}

/// Load, validate, order and solve the first increment of `n` separate bodies: the cost grows
/// linearly with `n` (ten times the bodies, about ten times the time), up to a million bodies
/// (two million nodes).
fn many_bodies(c: &mut Criterion) {
    let mut g = c.benchmark_group("many_bodies_first_increment");
    for n in [1_000usize, 10_000, 100_000, 1_000_000] {
        let text = many_bodies_text(n);
        g.bench_with_input(BenchmarkId::from_parameter(n), &text, |b, text| {
            b.iter(|| {
                let sc = tsm_contact::scene::parse(text, "many").unwrap();
                sc.solver().unwrap().step(&mut Silent).unwrap()
            })
        });
    }
    g.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(10);
    targets = newton, long_beam, example_3_2, slider_update, many_bodies
}
criterion_main!(benches);
