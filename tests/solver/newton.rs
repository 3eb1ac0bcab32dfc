//! The one Newton iteration under arc-length control: a Stop from the observer ends the run at
//! once (no further iteration, the converged state untouched), and each iteration's record
//! carries the norm of that iteration's correction, as under displacement control.

use std::time::{Duration, Instant};

use tsm_contact::scene::builtin::builtin;
use tsm_contact::solver::{Event, Flow, IncrementRecord, IterationRecord, Observer, SolveError};
use tsm_contact::solver::{Silent, Solver};

/// Stops the run at iteration `at` of increment `increment`, and counts the iterations
/// reported after that.
struct StopAt {
    increment: usize,
    at: usize,
    stopped: Option<Instant>,
    after: usize,
}

impl Observer for StopAt {
    fn iteration(&mut self, r: &IterationRecord) -> Flow {
        if self.stopped.is_some() {
            self.after += 1;
            return Flow::Stop;
        }
        if r.increment == self.increment && r.iteration >= self.at {
            self.stopped = Some(Instant::now());
            return Flow::Stop;
        }
        Flow::Continue
    }

    fn increment(&mut self, _r: &IncrementRecord) -> Flow {
        Flow::Continue
    }

    fn event(&mut self, _e: &Event) {}
}

fn lee_frame() -> Solver {
    builtin("lee_frame")
        .expect("built-in")
        .expect("valid")
        .solver()
        .expect("stable")
}

/// Lee's frame by arc length, five increments on: a Stop at the second iteration of the sixth
/// ends `step` with `SolveError::Stopped` within 50 ms, with no iteration after it and the
/// converged state (increment count, displacements, load factor) as it was.
#[test]
fn an_arc_length_run_stops_on_stop_within_50_ms() {
    let mut solver = lee_frame();
    assert!(
        solver.structure().params.arc_length.is_some(),
        "an arc-length scene"
    );
    for _ in 0..5 {
        solver.step(&mut Silent).expect("converges");
    }
    let (d, lambda) = (solver.displacements().to_vec(), solver.load_factor());
    let mut obs = StopAt {
        increment: 6,
        at: 2,
        stopped: None,
        after: 0,
    };
    let result = solver.step(&mut obs);
    let returned = Instant::now();
    assert!(matches!(result, Err(SolveError::Stopped)), "{result:?}");
    let stopped = obs.stopped.expect("the observer was asked");
    let took = returned - stopped;
    assert!(took < Duration::from_millis(50), "stopped after {took:?}");
    assert_eq!(obs.after, 0, "iterations after the Stop");
    assert_eq!(solver.increment(), 5);
    assert_eq!(solver.displacements(), &d[..]);
    assert_eq!(solver.load_factor(), lambda);
}

/// Each iteration record's `step_norm` is the norm of that iteration's correction, whatever the
/// control: Newton converges quadratically, so the last correction of a converged increment is
/// far smaller than the increment itself (the arc length over the free dofs), under arc-length
/// control as under displacement control.
#[test]
fn the_last_correction_of_an_arc_length_increment_is_small() {
    let mut solver = lee_frame();
    let ds = solver.structure().params.arc_length.expect("arc length");
    let free = solver
        .structure()
        .dofs()
        .kind
        .iter()
        .filter(|k| **k == tsm_contact::solver::assembly::DofKind::Free)
        .count();
    let arc = ds * (free as f64).sqrt();
    for _ in 0..10 {
        let before = solver.displacements().to_vec();
        let rec = solver.step(&mut Silent).expect("converges").remove(0);
        let moved: f64 = (solver.displacements().iter().zip(&before))
            .map(|(a, b)| (a - b) * (a - b))
            .sum::<f64>()
            .sqrt();
        // The increment is the arc (or a cut-back share of it).
        assert!(
            moved <= arc * (1.0 + 1e-9),
            "moved {moved} on an arc of {arc}"
        );
        let last = rec.residuals.last().expect("iterations").step_norm;
        assert!(
            last < 1e-3 * moved,
            "increment {}: last correction {last:e}, increment {moved:e}",
            rec.increment
        );
    }
}
