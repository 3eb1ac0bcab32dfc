//! The built-in scenes as they ship, each solved through its own steps: the Newton iterations
//! of every increment (failed attempts and cut-backs included), for the report's table beside
//! the campaign's random drives.

use super::count::{spread, Count};
use crate::scene::builtin::{builtin, BUILTIN};

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

/// Built-in scene `name` solved in its own steps.
fn solve(name: &str) -> Shipped {
    let mut out = Shipped {
        scene: name.to_string(),
        iterations: Vec::new(),
        stop: None,
    };
    let scene = match builtin(name) {
        Some(Ok(scene)) => scene,
        Some(Err(e)) => {
            out.stop = Some(e.to_string());
            return out;
        }
        None => {
            out.stop = Some("no such scene".into());
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
    let mut text = String::from(
        "The built-in scenes as they ship, each solved through its own steps (`tsm-contact solve NAME`); Newton iterations per accepted increment, failed attempts and cut-backs included:\n\n| scene | increments | iterations median / p99 / max | ends |\n|---|---|---|---|\n",
    );
    for s in shipped {
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
