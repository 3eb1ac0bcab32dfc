//! The built-in scenes as they ship and the validation problems, each solved through its own
//! steps: the Newton iterations of every increment (failed attempts and cut-backs included),
//! for the report's tables beside the campaign's random drives.

use super::count::{spread, Count};
use crate::reports::work_precision::problems;
use crate::scene::builtin::{builtin, BUILTIN};
use crate::scene::Scene;
use crate::solver::{Formulation, SolverParams};

/// How one built-in scene solves in its own steps.
#[derive(Clone, Debug)]
pub struct Shipped {
    /// Built-in scene name.
    pub scene: String,
    /// Newton iterations of each accepted increment, its failed attempts included.
    pub iterations: Vec<usize>,
    /// The error it stopped with, if any.
    pub stop: Option<String>,
}

/// Every built-in scene solved in its own steps.
pub fn shipped() -> Vec<Shipped> {
    (BUILTIN.iter())
        .map(|(file, _)| solve(file.trim_end_matches(".ron")))
        .collect()
}

/// The meshes the validation problems are solved on.
const VALIDATION_MESHES: [usize; 4] = [4, 16, 64, 256];

/// The reference problems of the work-precision report and `docs/validation.md` (Mattiasson's
/// cantilever at three loads, the end moment, the pin on a cantilever), each formulation and
/// mesh of `VALIDATION_MESHES`, at the default tolerance, solved in their own steps.
pub fn validation() -> Vec<Shipped> {
    let mut out = Vec::new();
    let tolerance = SolverParams::default().tolerance;
    for f in [Formulation::BernoulliEuler, Formulation::Timoshenko] {
        for n in VALIDATION_MESHES {
            for (name, scene) in problems(n, f, tolerance) {
                out.push(solve_scene(format!("{name}, {f:?}, {n} el."), Ok(scene)));
            }
        }
    }
    out
}

/// Built-in scene `name` solved in its own steps.
fn solve(name: &str) -> Shipped {
    let scene = match builtin(name) {
        Some(Ok(scene)) => Ok(scene),
        Some(Err(e)) => Err(e.to_string()),
        None => Err("no such scene".into()),
    };
    solve_scene(name.to_string(), scene)
}

/// `scene` (or the error reading it) solved in its own steps, under the name `label`.
fn solve_scene(label: String, scene: Result<Scene, String>) -> Shipped {
    let mut out = Shipped {
        scene: label,
        iterations: Vec::new(),
        stop: None,
    };
    let scene = match scene {
        Ok(scene) => scene,
        Err(e) => {
            out.stop = Some(e);
            return out;
        }
    };
    let mut count = Count::default();
    match scene.solver() {
        Ok(mut solver) => {
            for _ in 0..scene.steps {
                if let Err(e) = solver.step(&mut count) {
                    out.stop = Some(e.to_string());
                    break;
                }
            }
        }
        Err(e) => out.stop = Some(e.to_string()),
    }
    out.iterations = count.iterations_of(&count.accepted);
    out
}

/// The table of `shipped`: each scene's increments and the median, 99th percentile and largest
/// number of Newton iterations of one.
pub fn shipped_report(shipped: &[Shipped]) -> String {
    let text = String::from(
        "The built-in scenes as they ship, each solved through its own steps (`tsm-contact solve NAME`); Newton iterations per accepted increment, failed attempts and cut-backs included:\n\n",
    );
    text + &iterations_table(shipped)
}

/// The table of `validation`, as `shipped_report`'s.
pub fn validation_report(problems: &[Shipped]) -> String {
    let all = problems.iter().flat_map(|p| p.iterations.iter().copied());
    let (median, p99, largest) = spread(all.collect());
    let text = format!(
        "The reference problems of `docs/validation.md` and the work-precision report (`tsm-contact bench`), each formulation and mesh, at the default tolerance, each solved through its own steps; Newton iterations per accepted increment, failed attempts and cut-backs included (all together: median {median}, 99th percentile {p99}, largest {largest}):\n\n",
    );
    text + &iterations_table(problems)
}

/// The rows of runs `runs`: each one's increments, the median, 99th percentile and largest
/// number of Newton iterations of one, and how it ends.
fn iterations_table(runs: &[Shipped]) -> String {
    let mut text = String::from(
        "| scene | increments | iterations median / p99 / max | ends |\n|---|---|---|---|\n",
    );
    for s in runs {
        let (median, p99, largest) = spread(s.iterations.clone());
        text += &format!(
            "| {} | {} | {median} / {p99} / {largest} | {} |\n",
            s.scene,
            s.iterations.len(),
            s.stop.as_deref().unwrap_or("complete")
        );
    }
    text
}
