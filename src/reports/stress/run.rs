//! Running one case of the stability suite: its scene text solved step by step, tallied
//! (increments, iterations, cut-backs, transfers, the contact point closest to an element end)
//! into a `Run`, and the `StressRow` a case becomes in the table.

use crate::scene::{parse, Scene};
use crate::solver::{ContactChange, Event, IncrementRecord, IterationRecord, Observer, Solver};

/// One case of the suite, as run.
#[derive(Clone, Debug, Default)]
pub struct StressRow {
    /// What was run.
    pub case: String,
    /// Element formulation.
    pub formulation: String,
    /// Whether every increment converged.
    pub converged: bool,
    /// Converged increments (sub-increments included).
    pub increments: usize,
    /// Newton iterations in all, over every attempt (failed attempts included).
    pub iterations: usize,
    /// Most iterations in one converged increment.
    pub max_iterations: usize,
    /// Cut-backs (halved increments).
    pub cutbacks: usize,
    /// Automatic contact transfers to a neighbouring element.
    pub transfers: usize,
    /// Contact activations, releases and slide-offs.
    pub activations: usize,
    /// Releases and slide-offs.
    pub releases: usize,
    /// Largest relative residual of a converged increment.
    pub max_residual: f64,
    /// Increments accepted at the round-off floor rather than at the tolerance.
    pub at_roundoff: usize,
    /// Most contacts carrying load at once.
    pub max_contacts: usize,
    /// li/l of the contact point that came closest to an element end (if any contact).
    pub furthest_xi: Option<f64>,
    /// A measured quantity and its reference: (name, value, reference).
    pub measure: Option<(String, f64, f64)>,
    /// The typed error that stopped the run, if any.
    pub error: Option<String>,
    /// Wall time (s).
    pub seconds: f64,
}

/// Counts iterations and cut-backs as they happen.
#[derive(Default)]
struct Tally {
    iterations: usize,
    cutbacks: usize,
}

impl Observer for Tally {
    fn iteration(&mut self, _r: &IterationRecord) -> crate::solver::Flow {
        self.iterations += 1;
        crate::solver::Flow::Continue
    }
    fn event(&mut self, e: &Event) {
        if matches!(e, Event::CutBack { .. }) {
            self.cutbacks += 1;
        }
    }
}

/// A run through a list of targets (prescribed values, load factor), or scene steps.
pub struct Run {
    /// The summary row.
    pub row: StressRow,
    /// Every converged increment.
    pub records: Vec<IncrementRecord>,
    /// The solver at the end.
    pub solver: Solver,
}

/// How a run advances.
pub enum Path {
    /// The scene's own steps (or arc lengths), this many.
    Steps(usize),
    /// Piecewise-linear legs: (prescribed targets, load factor, increments for the leg).
    Legs(Vec<(Vec<f64>, f64, usize)>),
}

/// Run scene text along a path and summarise it.
pub fn run(case: &str, text: &str, path: &Path) -> Run {
    let sc = parse(text, case).unwrap_or_else(|e| panic!("stress scene {case}: {e}"));
    run_scene(case, &sc, path)
}

/// `run` of a scene already validated.
pub fn run_scene(case: &str, sc: &Scene, path: &Path) -> Run {
    let mut solver = sc.solver().expect("stable scene");
    let tolerance = sc.params.tolerance;
    let mut row = StressRow {
        case: case.to_string(),
        formulation: sc.model.formulation.name().to_string(),
        converged: true,
        ..StressRow::default()
    };
    let mut tally = Tally::default();
    let mut records = Vec::new();
    let clock = std::time::Instant::now();
    let mut targets: Vec<(Vec<f64>, f64)> = Vec::new();
    match path {
        Path::Steps(n) => targets.extend((0..*n).map(|_| (Vec::new(), f64::NAN))),
        Path::Legs(legs) => {
            let mut from = (solver.prescribed_values().to_vec(), solver.load_factor());
            for (p, l, n) in legs {
                for k in 1..=*n {
                    let t = k as f64 / *n as f64;
                    let pk = from.0.iter().zip(p).map(|(a, b)| a + t * (b - a)).collect();
                    targets.push((pk, from.1 + t * (l - from.1)));
                }
                from = (p.clone(), *l);
            }
        }
    }
    for (p, l) in targets {
        let result = if l.is_nan() {
            solver.step(&mut tally)
        } else {
            solver.advance_to(&p, &solver.structure.model.uniform_factors(l), &mut tally)
        };
        match result {
            Ok(recs) => records.extend(recs),
            Err(e) => {
                row.converged = false;
                row.error = Some(e.to_string());
                break;
            }
        }
    }
    row.seconds = clock.elapsed().as_secs_f64();
    row.increments = records.len();
    row.iterations = tally.iterations;
    row.cutbacks = tally.cutbacks;
    for r in &records {
        row.max_iterations = row.max_iterations.max(r.iterations);
        row.max_residual = row.max_residual.max(r.relative_residual);
        if r.relative_residual > tolerance {
            row.at_roundoff += 1;
        }
        row.max_contacts = row
            .max_contacts
            .max(r.contacts.iter().filter(|c| c.pressure > 0.0).count());
        for c in &r.contacts {
            let end = c.xi.min(1.0 - c.xi);
            if row.furthest_xi.is_none_or(|x| end < x.min(1.0 - x)) {
                row.furthest_xi = Some(c.xi);
            }
        }
        for e in &r.events {
            if let Event::Contact(c) = e {
                match c.change {
                    ContactChange::Transferred => row.transfers += 1,
                    ContactChange::Activated => row.activations += 1,
                    ContactChange::Released | ContactChange::SlidOff => row.releases += 1,
                    ContactChange::Slips | ContactChange::Sticks => {}
                }
            }
        }
    }
    if std::env::var_os("TSM_STRESS_LOG").is_some() {
        eprintln!(
            "{}: converged {}, {} increments, {} iterations, {:.2} s {}",
            row.case,
            row.converged,
            row.increments,
            row.iterations,
            row.seconds,
            row.error.as_deref().unwrap_or("")
        );
    }
    Run {
        row,
        records,
        solver,
    }
}

/// The first local maximum of y over a curve, refined by a parabola through its neighbours.
pub fn first_peak(curve: &[(f64, f64)]) -> Option<f64> {
    let k = (1..curve.len().saturating_sub(1))
        .find(|&k| curve[k].1 >= curve[k - 1].1 && curve[k].1 > curve[k + 1].1)?;
    let ((x0, y0), (x1, y1), (x2, y2)) = (curve[k - 1], curve[k], curve[k + 1]);
    let d = (x0 - x1) * (x0 - x2) * (x1 - x2);
    let a = (x2 * (y1 - y0) + x1 * (y0 - y2) + x0 * (y2 - y1)) / d;
    let b = (x2 * x2 * (y0 - y1) + x1 * x1 * (y2 - y0) + x0 * x0 * (y1 - y2)) / d;
    let c = y1 - a * x1 * x1 - b * x1;
    let xm = -b / (2.0 * a);
    Some(a * xm * xm + b * xm + c)
}
