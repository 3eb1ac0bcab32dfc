//! The solver worker thread, headless: increments arrive in order from `Run`, the prescribed
//! value after N steps is N * per_step, `SetTarget` marches in increments no larger than
//! `|per_step|` and stops exactly at the target, `Cancel` stops promptly, and a stop arrives as
//! the solver's typed error.

use crate::common;

use std::time::{Duration, Instant};

use tsm_contact::scene::builtin::builtin;
use tsm_contact::worker::{Command, Failure, Message, Worker};

fn scene(name: &str) -> tsm_contact::scene::Scene {
    builtin(name).expect("built-in scene").expect("valid scene")
}

/// Load a scene and wait for its `Loaded` and `Idle`.
fn load(w: &Worker, name: &str) -> usize {
    w.send(Command::LoadScene(Box::new(scene(name))));
    let t0 = Instant::now();
    let mut loaded = None;
    while t0.elapsed() < Duration::from_secs(20) {
        match w.recv_timeout(Duration::from_millis(50)) {
            Some(Message::Loaded(l)) => loaded = Some(l.scene.model.prescribed.len()),
            Some(Message::Error(e)) => panic!("load failed: {e}"),
            Some(Message::Idle) if loaded.is_some() => return loaded.unwrap(),
            _ => {}
        }
    }
    panic!("scene did not load");
}

#[test]
fn run_streams_increments_in_order() {
    let w = Worker::spawn(None);
    load(&w, "example_3_2");
    let s = scene("example_3_2");
    let steps = 12;
    w.send(Command::RunSteps(steps));
    let (incs, errors) = common::until_idle(&w, Duration::from_secs(120));
    assert!(errors.is_empty(), "{errors:?}");
    assert!(
        incs.len() >= steps,
        "{} increments for {steps} steps",
        incs.len()
    );
    for (k, r) in incs.iter().enumerate() {
        assert_eq!(r.increment, k + 1, "increments out of order");
        assert!(r.relative_residual <= s.params.tolerance);
    }
    let per_step = s.model.prescribed[0].per_step;
    let last = incs.last().unwrap().prescribed[0];
    assert!(
        (last - steps as f64 * per_step).abs() < 1e-12,
        "after {steps} steps: {last}"
    );
}

#[test]
fn set_target_marches_in_small_increments_and_stops_exactly() {
    let w = Worker::spawn(None);
    load(&w, "example_3_2");
    let per_step = scene("example_3_2").model.prescribed[0].per_step;
    let target = 4.37 * per_step;
    w.send(Command::SetTarget {
        index: 0,
        value: target,
    });
    let (incs, errors) = common::until_idle(&w, Duration::from_secs(120));
    assert!(errors.is_empty(), "{errors:?}");
    assert!(
        incs.len() >= 5,
        "4.37 steps need at least 5 increments, got {}",
        incs.len()
    );
    let mut prev = 0.0;
    for r in &incs {
        let step = (r.prescribed[0] - prev).abs();
        assert!(
            step <= per_step.abs() * (1.0 + 1e-12),
            "increment {} moved {step}",
            r.increment
        );
        prev = r.prescribed[0];
    }
    assert!(
        (prev - target).abs() < 1e-12,
        "stopped at {prev}, target {target}"
    );

    // A newer target replaces the old one: go back up part of the way.
    let back = 2.0 * per_step;
    w.send(Command::SetTarget {
        index: 0,
        value: 10.0 * per_step,
    });
    w.send(Command::SetTarget {
        index: 0,
        value: back,
    });
    let (incs, errors) = common::until_idle(&w, Duration::from_secs(120));
    assert!(errors.is_empty(), "{errors:?}");
    let last = incs.last().map_or(prev, |r| r.prescribed[0]);
    assert!(
        (last - back).abs() < 1e-12,
        "stopped at {last}, target {back}"
    );
}

#[test]
fn cancel_stops_promptly() {
    let w = Worker::spawn(None);
    load(&w, "example_3_2");
    // Far more steps than could finish during the test.
    w.send(Command::RunSteps(1_000_000));
    let t0 = Instant::now();
    let mut seen = 0;
    while seen < 20 && t0.elapsed() < Duration::from_secs(60) {
        if let Some(Message::Increment(_)) = w.recv_timeout(Duration::from_millis(20)) {
            seen += 1;
        }
    }
    assert!(seen >= 20);
    let sent = Instant::now();
    w.send(Command::Cancel);
    let mut last = 0;
    loop {
        match w.recv_timeout(Duration::from_secs(10)) {
            Some(Message::Idle) => break,
            Some(Message::Increment(r)) => last = r.increment,
            Some(_) => {}
            None => panic!("no Idle after Cancel"),
        }
    }
    let took = sent.elapsed();
    eprintln!("cancel took effect after {took:?}");
    // The solver thread checks for a newer command at every Newton iteration: a cancel takes
    // effect within the iteration under way (about a millisecond here). The bound is one a
    // loaded machine meets too: it tells a cancel that waits for the run from one that does not.
    assert!(took < Duration::from_secs(1), "cancel took {took:?}");
    assert!(last < 100_000, "ran on to increment {last}");
    // Nothing more arrives once idle.
    std::thread::sleep(Duration::from_millis(200));
    assert!(w
        .drain()
        .iter()
        .all(|m| !matches!(m, Message::Increment(_))));
}

#[test]
fn errors_do_not_kill_the_worker() {
    let w = Worker::spawn(None);
    // Commands before any scene are answered with Idle.
    w.send(Command::Step);
    assert!(matches!(
        w.recv_timeout(Duration::from_secs(5)),
        Some(Message::Idle)
    ));
    load(&w, "mattiasson");
    w.send(Command::Step);
    let (incs, errors) = common::until_idle(&w, Duration::from_secs(60));
    assert!(errors.is_empty(), "{errors:?}");
    assert_eq!(incs.first().map(|r| r.increment), Some(1));
    w.send(Command::Reset);
    let t0 = Instant::now();
    let mut reloaded = false;
    while !reloaded && t0.elapsed() < Duration::from_secs(10) {
        reloaded = matches!(
            w.recv_timeout(Duration::from_millis(50)),
            Some(Message::Loaded(_))
        );
    }
    assert!(reloaded);
}

/// An arc-length scene run from the worker follows the same path as the solver stepped directly
/// (the worker must not turn its steps into equal load steps): Lee's frame past its limit point.
#[test]
fn arc_length_scene_runs_as_arcs() {
    use tsm_contact::solver::Silent;
    let steps = 60;
    let mut direct = scene("lee_frame").solver().unwrap();
    let mut lambdas = Vec::new();
    for _ in 0..steps {
        lambdas.extend(
            direct
                .step(&mut Silent)
                .unwrap()
                .iter()
                .map(|r| r.load_factor),
        );
    }
    let w = Worker::spawn(None);
    load(&w, "lee_frame");
    w.send(Command::RunSteps(steps));
    let (incs, errors) = common::until_idle(&w, Duration::from_secs(120));
    assert!(errors.is_empty(), "{errors:?}");
    assert_eq!(incs.len(), lambdas.len());
    for (r, l) in incs.iter().zip(&lambdas) {
        assert!(
            (r.load_factor - l).abs() < 1e-12,
            "{} vs {l}",
            r.load_factor
        );
    }
    // Past the limit point: the load factor has come down from its maximum.
    let max = lambdas.iter().cloned().fold(f64::MIN, f64::max);
    assert!(max > 1.8 && *lambdas.last().unwrap() < max);
}

/// `SetStretchCorrection` reloads the scene in that mode: the roll-up (end moment, 16
/// elements, 10 steps) then takes the iterations a direct `Solver` run in that mode takes
/// (20 always, measured; 60 for plain Newton, the default's here since it never cuts back),
/// node for node the same states.
#[test]
fn stretch_correction_mode_reloads_and_runs_in_that_mode() {
    use tsm_contact::solver::{Silent, StretchCorrection};
    let direct = |mode| {
        let mut sc = scene("end_moment");
        sc.params.stretch_correction = mode;
        let mut s = sc.solver().expect("stable");
        (0..sc.steps)
            .flat_map(|_| s.step(&mut Silent).expect("converges"))
            .collect::<Vec<_>>()
    };
    let w = Worker::spawn(None);
    load(&w, "end_moment");
    for mode in [StretchCorrection::Always, StretchCorrection::Never] {
        w.send(Command::SetStretchCorrection(mode));
        let t0 = Instant::now();
        let mut loaded = None;
        while loaded.is_none() && t0.elapsed() < Duration::from_secs(20) {
            if let Some(Message::Loaded(l)) = w.recv_timeout(Duration::from_millis(50)) {
                loaded = Some(l.scene.params.stretch_correction);
            }
        }
        assert_eq!(loaded, Some(mode));
        w.send(Command::Run);
        let (incs, errors) = common::until_idle(&w, Duration::from_secs(60));
        assert!(errors.is_empty(), "{errors:?}");
        let want = direct(mode);
        assert_eq!(incs.len(), want.len());
        for (a, b) in incs.iter().zip(&want) {
            assert_eq!((a.iterations, &a.nodes), (b.iterations, &b.nodes));
        }
        let total: usize = incs.iter().map(|r| r.iterations).sum();
        match mode {
            StretchCorrection::Always => assert!(total <= 30, "always: {total}"),
            _ => assert!(total >= 50, "never: {total}"),
        }
    }
}

/// A pin driven 0.01 a step onto a fixed floor 0.025 below it, in the floor's candidates: it
/// cannot go on past the floor (its position is prescribed), so the run stops in the third step,
/// and the worker sends the solver's typed error, naming the increment after the last one it
/// sent, not words alone.
#[test]
fn a_stop_arrives_as_the_solvers_typed_error() {
    let text = r#"(
    name: "pin driven into a floor",
    sections: [(name: "s", E: 1.0, A: 1.0e3, I: 1.0)],
    nodes: [(id: 100, x: 0.5, y: 0.025, rotation: false)],
    bodies: [(name: "beam", section: "s", path: [(0.0, 1.0), (1.0, 1.0)], elements: 4, first_node: 1)],
    supports: [(node: 1, u: true, v: true, phi: true), (node: 100, u: true)],
    prescribed: [(node: 100, dof: V, per_step: -0.01)],
    obstacles: [(name: "floor", shape: Line(from: (0.0, 0.0), to: (1.0, 0.0)), nodes: [100])],
    control: (steps: 10),
)"#;
    let scene = tsm_contact::scene::parse(text, "pin driven into a floor").expect("valid");
    let w = Worker::spawn(None);
    w.send(Command::LoadScene(Box::new(scene)));
    w.send(Command::RunSteps(10));
    let t0 = Instant::now();
    let (mut failure, mut last) = (None, 0);
    while failure.is_none() && t0.elapsed() < Duration::from_secs(60) {
        match w.recv_timeout(Duration::from_millis(50)) {
            Some(Message::Error(e)) => failure = Some(e),
            Some(Message::Increment(r)) => last = r.increment,
            _ => {}
        }
    }
    let failure = failure.expect("the run stops");
    assert!(
        matches!(failure, Failure::Solve(_)),
        "a solver error: {failure}"
    );
    assert!(last >= 2, "the pin reached the floor first: {last}");
    assert_eq!(failure.increment(), Some(last + 1), "{failure}");
}
