//! `solve`: a scene run headless, one line per increment and contact events as they happen,
//! the full history written as JSON on request, and a closing line on how the increments met
//! the equilibrium test.

use std::path::Path;
use std::time::Instant;

use super::args::{FormulationArg, SolveArgs, StretchArg};
use super::signals;
use tsm_contact::history::{History, HistoryWriter};
use tsm_contact::scene;
use tsm_contact::solver::report::Flow;
use tsm_contact::solver::{
    Event, Formulation, IncrementRecord, IncrementStatus, Model, Observer, SolveError,
    StretchCorrection,
};

/// Prints the run, tallies it, and streams it into the history file (if one is asked for).
struct Printer {
    /// The model, for naming elements.
    model: Model,
    /// The history file being written, and the first error writing it.
    history: Option<HistoryWriter>,
    write_error: Option<std::io::Error>,
    tally: Tally,
    verbose: bool,
    /// The stage of the last increment printed.
    stage: Option<usize>,
}

/// What the closing lines say of the increments: how many, their iterations, how many were
/// accepted at the round-off floor, and the worst relative residual.
#[derive(Default)]
struct Tally {
    increments: usize,
    iterations: usize,
    roundoff: usize,
    /// States on the way of a snap (not in equilibrium, so not in `worst`).
    snapping: usize,
    worst: f64,
}

impl Observer for Printer {
    fn iteration(&mut self, r: &tsm_contact::solver::IterationRecord) -> Flow {
        if self.verbose {
            out!(
                "      iter {:>3}  |R| = {:.3e}  |R|/ref = {:.3e}  |du| = {:.3e}  contacts {}",
                r.iteration,
                r.residual,
                r.relative_residual,
                r.step_norm,
                r.active_contacts
            );
        }
        if signals::caught().is_some() {
            return Flow::Stop;
        }
        Flow::Continue
    }
    fn increment(&mut self, r: &IncrementRecord) -> Flow {
        if let (Some(s), Some(path)) = (r.stage, &self.model.path) {
            if self.stage != Some(s) {
                let st = &path.stages[s];
                out!("# stage {}: {} ({} steps)", s + 1, st.name, st.steps);
            }
        }
        self.stage = r.stage;
        let driven = if !r.load_factors.is_empty() {
            let factors = (r.load_factors.iter()).map(|v| format!("{v:>7.4}"));
            let values = r.prescribed.iter().map(|v| format!("{v:>+10.5}"));
            values.chain(factors).collect::<Vec<_>>().join(" ")
        } else if r.prescribed.is_empty() {
            format!("lambda {:>9.4}", r.load_factor)
        } else {
            r.prescribed
                .iter()
                .map(|v| format!("{v:>+10.5}"))
                .collect::<Vec<_>>()
                .join(" ")
        };
        let it8 = r.iterations_8_orders.map_or("-".into(), |v| v.to_string());
        // A relative residual accepted at the round-off floor (above the tolerance) is marked.
        let mark = match r.status {
            IncrementStatus::Converged => ' ',
            IncrementStatus::RoundOff { .. } => 'r',
            IncrementStatus::Snapping { .. } => 's',
        };
        out!(
            "{:>5}  {}  {:>4}  {:>4}  {:>9.2e}{}  {:>3}  {:>3}  {:>8.2}",
            r.increment,
            driven,
            r.iterations,
            it8,
            r.relative_residual,
            mark,
            r.cutbacks,
            r.contacts.len() + r.obstacle_contacts.len(),
            r.seconds * 1e3
        );
        let t = &mut self.tally;
        t.increments += 1;
        t.iterations += r.iterations;
        match r.status {
            IncrementStatus::Converged => t.worst = t.worst.max(r.relative_residual),
            IncrementStatus::RoundOff { .. } => {
                t.worst = t.worst.max(r.relative_residual);
                t.roundoff += 1;
            }
            IncrementStatus::Snapping { .. } => t.snapping += 1,
        }
        if let Some(w) = &mut self.history {
            if let Err(e) = w.increment(r) {
                // A history that cannot be written stops the run at once.
                self.write_error.get_or_insert(e);
                return Flow::Stop;
            }
        }
        if signals::caught().is_some() {
            return Flow::Stop;
        }
        Flow::Continue
    }
    fn event(&mut self, e: &Event) {
        out!("      event: {}", e.describe(&self.model));
        if let Some(w) = &mut self.history {
            w.event(e);
        }
    }
}

pub(super) fn solve(args: SolveArgs) -> i32 {
    let SolveArgs {
        scene: name,
        steps,
        formulation,
        json,
        verbose,
        unsymmetric_from,
        stretch_correction,
        max_output,
        every,
    } = args;
    let name = name.as_str();
    // The output is checked before the run: a long solve must not end in "cannot write".
    if let Some(path) = &json {
        if let Some(why) = tsm_contact::history::output_problem(path, &[Path::new(name)]) {
            eprintln!(
                "error: cannot write the history to {}: {why}",
                path.display()
            );
            return 2;
        }
    }
    let mut scene = match scene::builtin::open(name) {
        Ok(s) => s,
        Err(e) => {
            eprintln!("error: {e}");
            return 2;
        }
    };
    if let Some(f) = formulation {
        scene.model.formulation = match f {
            FormulationArg::Timoshenko => Formulation::Timoshenko,
            FormulationArg::BernoulliEuler => Formulation::BernoulliEuler,
        };
    }
    if let Some(k) = unsymmetric_from {
        scene.params.unsymmetric_from = if k == 0 { usize::MAX } else { k };
    }
    if let Some(m) = stretch_correction {
        scene.params.stretch_correction = match m {
            StretchArg::Never => StretchCorrection::Never,
            StretchArg::WhereNeeded => StretchCorrection::WhereNeeded,
            StretchArg::AfterCutBack => StretchCorrection::AfterCutBack,
            StretchArg::Always => StretchCorrection::Always,
        };
    }
    let steps = steps.unwrap_or(scene.steps);
    let mut solver = match scene.solver() {
        Ok(s) => s,
        Err(e) => {
            eprintln!("error: {e}");
            return 2;
        }
    };
    out!(
        "# {} ({:?}), {} steps, tolerance {:.0e}",
        scene.file.name,
        scene.model.formulation,
        steps,
        scene.params.tolerance
    );
    out!("# incr  prescribed/load  iter  it8  rel.resid   cut  act   ms   (r: accepted at the round-off floor; s: on the way of a snap)");
    let header = History {
        every: every.filter(|&n| n > 1).map(|n| n as usize),
        ..History::of_model(
            &scene.file.name,
            &scene.model,
            Some(scene.model.formulation),
            Some(scene.params),
        )
    };
    let history = match (json.as_deref()).map(|p| HistoryWriter::create(p, &header, max_output)) {
        None => None,
        Some(Ok(w)) => Some(w),
        Some(Err(e)) => {
            let path = json.as_deref().unwrap_or(Path::new(""));
            eprintln!("error: cannot write {}: {e}", path.display());
            return 2;
        }
    };
    let mut printer = Printer {
        model: scene.model.clone(),
        history,
        write_error: None,
        tally: Tally::default(),
        verbose,
        stage: None,
    };
    let t0 = Instant::now();
    let mut code = 0;
    let mut error = None;
    signals::catch();
    for _ in 0..steps {
        match solver.step(&mut printer) {
            Err(SolveError::Stopped) => break,
            Err(e) => {
                eprintln!("error: {e}");
                error = Some(e.to_string());
                code = 1;
                break;
            }
            Ok(_) if printer.write_error.is_some() || signals::caught().is_some() => break,
            Ok(_) => {}
        }
    }
    if let Some(s) = signals::caught() {
        // Stopped by a signal: the unfinished history is removed with its writer.
        drop(printer.history.take());
        eprintln!(
            "stopped by {} after {} increments; no history written",
            signals::name(s),
            printer.tally.increments
        );
        return 128 + s;
    }
    let t = &printer.tally;
    out!(
        "# {} increments, {} iterations, {:.1} ms",
        t.increments,
        t.iterations,
        t0.elapsed().as_secs_f64() * 1e3
    );
    out!("# {}", acceptance_summary(t, code != 0));
    if let (Some(path), Some(w)) = (&json, printer.history.take()) {
        let written = match printer.write_error.take() {
            Some(e) => Err(e),
            None => w.finish(error),
        };
        if let Err(e) = written {
            eprintln!("error: cannot write {}: {e}", path.display());
            return 2;
        }
    }
    code
}

/// One line on how the increments met the acceptance rule: how many converged to the tolerance,
/// how many were accepted at the round-off floor, the worst relative residual, and whether the
/// run stopped on a failure.
fn acceptance_summary(t: &Tally, failed: bool) -> String {
    format!(
        "{} increments converged, {} accepted at round-off{}, worst relative residual {:.2e}{}",
        t.increments - t.roundoff - t.snapping,
        t.roundoff,
        if t.snapping > 0 {
            format!(", {} on the way of a snap (not in equilibrium)", t.snapping)
        } else {
            String::new()
        },
        t.worst,
        if failed {
            "; the run stopped on a failure"
        } else {
            ""
        }
    )
}
