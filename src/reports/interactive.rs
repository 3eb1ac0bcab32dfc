//! Interactive response: how long a slider drag takes to re-solve a paper scene (target: one
//! 60 Hz frame, 16 ms). From every converged step of the scene the prescribed displacements move
//! by one step's worth at the current load factor, as the worker does for `SetTarget` (one
//! [`Solver::advance_to`]), and the time to converge there is measured (release builds; median of
//! repeats per state, then the median and the worst over the states).

use std::time::Instant;

use crate::scene::builtin::builtin;
use crate::solver::{Silent, Solver};

/// The paper scenes a slider drives.
pub const SCENES: [&str; 2] = ["example_3_1", "example_3_2"];

/// Frame budget of an interactive update (ms).
pub const BUDGET_MS: f64 = 16.0;

/// One scene's slider-update timings.
#[derive(Clone, Debug)]
pub struct SliderRow {
    /// Built-in scene name.
    pub scene: String,
    /// Converged states the update was timed from.
    pub states: usize,
    /// Median over the states of the update time (ms).
    pub median_ms: f64,
    /// Slowest state's update time (ms).
    pub max_ms: f64,
}

/// The converged states of a built-in scene after 0, 1, ... steps (as far as it solves).
pub fn converged_states(scene: &str) -> Vec<Solver> {
    let sc = builtin(scene).expect("built-in scene").expect("valid");
    let mut s = sc.solver().expect("stable");
    let mut out = vec![s.clone()];
    for _ in 0..sc.steps {
        if s.step(&mut Silent).is_err() {
            break;
        }
        out.push(s.clone());
    }
    out
}

/// Time one slider update from `state` (seconds); `None` if it does not converge.
pub fn time_update(state: &Solver) -> Option<f64> {
    // A slider step: the prescribed values one step on, at the current load factor.
    let targets = state.step_targets()?.0;
    let mut s = state.clone();
    let t = Instant::now();
    s.advance_to(&targets, state.load_factors(), &mut Silent)
        .ok()?;
    Some(t.elapsed().as_secs_f64())
}

/// Measure a scene: each state's update repeated `repeats` times (median kept).
pub fn measure(scene: &str, repeats: usize) -> SliderRow {
    let mut per_state: Vec<f64> = converged_states(scene)
        .iter()
        .filter_map(|state| {
            let mut t: Vec<f64> = (0..repeats.max(1))
                .filter_map(|_| time_update(state))
                .collect();
            t.sort_by(f64::total_cmp);
            t.get(t.len() / 2).copied()
        })
        .collect();
    per_state.sort_by(f64::total_cmp);
    let ms = |v: Option<&f64>| v.map_or(f64::NAN, |v| v * 1e3);
    SliderRow {
        scene: scene.to_string(),
        states: per_state.len(),
        median_ms: ms(per_state.get(per_state.len() / 2)),
        max_ms: ms(per_state.last()),
    }
}

/// The report as a Markdown table.
pub fn table(rows: &[SliderRow]) -> String {
    let mut s = format!(
        "| scene | states | slider update, median (ms) | slowest state (ms) | within {BUDGET_MS} ms |\n|---|---|---|---|---|\n"
    );
    for r in rows {
        s.push_str(&format!(
            "| {} | {} | {:.3} | {:.3} | {} |\n",
            r.scene,
            r.states,
            r.median_ms,
            r.max_ms,
            if r.max_ms < BUDGET_MS { "yes" } else { "no" }
        ));
    }
    s
}
