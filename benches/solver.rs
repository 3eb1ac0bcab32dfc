//! Benchmarks: one Newton increment of an n-element cantilever (Mattiasson load k = 1), reported
//! per element and per iteration, and the paper's Example 3.2 up to the pin nearing A's tip.
//! Run with `cargo bench --no-default-features --bench solver`.

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use tsm_contact::scene::{builtin::builtin, builtin::BUILTIN, parse};
use tsm_contact::solver::Silent;

fn cantilever(n: usize) -> tsm_contact::scene::Scene {
    let text = BUILTIN
        .iter()
        .find(|(f, _)| *f == "mattiasson.ron")
        .unwrap()
        .1;
    let text = text
        .replace("elements: 32", &format!("elements: {n}"))
        .replace("loads: [(node: 33,", &format!("loads: [(node: {},", n + 1));
    let mut sc = parse(&text, "bench").unwrap();
    // EA/l grows with n: accept convergence to 10x the round-off floor (reported per increment).
    sc.params.roundoff_factor = 10.0;
    sc
}

fn newton(c: &mut Criterion) {
    let mut g = c.benchmark_group("cantilever_increment");
    for n in [100usize, 1000, 10_000] {
        let sc = cantilever(n);
        let mut probe = sc.solver().unwrap();
        let iters = probe.step(&mut Silent).unwrap()[0].iterations;
        eprintln!("cantilever {n} elements: {iters} Newton iterations for k = 1");
        let fresh = sc.solver().unwrap();
        g.bench_with_input(BenchmarkId::from_parameter(n), &n, |b, _| {
            b.iter_batched(
                || fresh.clone(),
                |mut s| s.step(&mut Silent).unwrap(),
                criterion::BatchSize::LargeInput,
            )
        });
    }
    g.finish();
}

fn example_3_2(c: &mut Criterion) {
    let sc = builtin("example_3_2").unwrap().unwrap();
    c.bench_function("example_3_2_53_steps", |b| {
        let fresh = sc.solver().unwrap();
        b.iter_batched(
            || fresh.clone(),
            |mut s| {
                for _ in 0..53 {
                    s.step(&mut Silent).unwrap();
                }
            },
            criterion::BatchSize::LargeInput,
        )
    });
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(10);
    targets = newton, example_3_2
}
criterion_main!(benches);
