//! The robustness campaign (`tsm-contact robust`): seeded random drives of every built-in scene
//! (the scene's own mesh or, for a one-body scene, half or twice as many elements; either
//! formulation; steps from 3e-4 to 50 times the scene's; down only, or down and back up; friction
//! mu in [0, 1] on every contact the model can carry it on), and of seven families with a plain
//! answer (`FAMILIES`: a pin pressed onto the midspan node of a pinned-pinned beam, two
//! cantilevers pressed onto each other, a bar on a rough beam floor and on a rough line, a pin
//! pressing one cantilever far onto another, a pin with a radius on a cantilever, two thick
//! strips pressed together; on 8 to 128 elements) counted by how they end, with the Newton iterations of every
//! increment (its failed attempts and cut-backs included) and what the independent audit
//! (`crate::audit`) finds in every accepted state. A measurement, not a test: it reports.

use std::collections::BTreeMap;

mod count;
mod families;
mod shipped;

use crate::audit::{audit, Run};
use crate::history::{History, Topology};
use crate::scene::builtin::{builtin, with_elements, BUILTIN};
use crate::scene::Scene;
use crate::solver::{Formulation, IncrementRecord};
use count::{spread, Count};
pub use families::{Family, FAMILIES};
pub use shipped::{shipped, shipped_report, validation, validation_report, Shipped};

/// The most increments one drive takes (each way): a drive at 3e-4 of a scene's step covers
/// that many of its small steps, not the scene's whole path.
const MAX_INCREMENTS: usize = 120;

/// The smallest and largest step, as multiples of the scene's.
const STEP_RANGE: (f64, f64) = (3e-4, 50.0);

/// One drive of the campaign.
#[derive(Clone, Debug)]
pub struct Case {
    /// Built-in scene name.
    pub scene: String,
    /// The seed it was drawn from.
    pub seed: u64,
    /// Element formulation.
    pub formulation: Formulation,
    /// Elements per path segment of a one-body scene (`None`: the scene's own mesh).
    pub elements: Option<usize>,
    /// The step as a multiple of the scene's (prescribed values and load factor alike).
    pub factor: f64,
    /// Steps down.
    pub steps: usize,
    /// Whether the drive goes back up to the start afterwards.
    pub reverse: bool,
    /// Friction coefficient on every contact pair and obstacle.
    pub mu: f64,
    /// The scene's text, for a family that is no built-in scene.
    pub text: Option<String>,
}

/// How one drive ended.
#[derive(Clone, Debug)]
pub struct Outcome {
    /// The drive.
    pub case: Case,
    /// `None`: every step done; else the error's kind and text.
    pub stop: Option<(String, String)>,
    /// Newton iterations of each accepted increment, its failed attempts included.
    pub iterations: Vec<usize>,
    /// What the audit found in the accepted states.
    pub findings: Vec<String>,
    /// For a drive that stops without converging: the least real part of the eigenvalues of
    /// the tangent over the free dofs (the drive held, the contacts of the state), after the
    /// drive's first step and at the last accepted state. One falling towards zero marks a limit
    /// point of the drive (the structure snaps) rather than a failure of the solve.
    pub stiffness: Option<(f64, f64)>,
    /// The accepted states, where asked for ([`run_keeping`]; else empty).
    pub records: Vec<IncrementRecord>,
}

/// Models of more free dofs than this get no eigenvalues in the report (a dense solve).
const EIGEN_MAX_DOFS: usize = 1500;

/// The least real part of the eigenvalues of `solver`'s tangent over the free dofs at its
/// state, if the model is small enough.
fn least_eigenvalue(solver: &crate::solver::Solver) -> Option<f64> {
    let (_, k, free) = solver.unbalanced_force_and_tangent(solver.displacements());
    if free.is_empty() || free.len() > EIGEN_MAX_DOFS {
        return None;
    }
    let re = k
        .complex_eigenvalues()
        .iter()
        .map(|z| z.re)
        .fold(f64::INFINITY, f64::min);
    re.is_finite().then_some(re)
}

/// A small reproducible random sequence (xorshift) in [0, 1).
struct Draw(u64);

impl Draw {
    fn next(&mut self) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// `per_scene` drives of every built-in scene and of every family, drawn from `seed`.
pub fn cases(per_scene: usize, seed: u64) -> Vec<Case> {
    let mut out = Vec::new();
    for (k, (file, _)) in BUILTIN.iter().enumerate() {
        let name = file.trim_end_matches(".ron").to_string();
        for j in 0..per_scene {
            let s =
                seed ^ ((k as u64 + 1) << 32) ^ (j as u64 + 1).wrapping_mul(0x9e37_79b9_7f4a_7c15);
            let mut d = Draw(s | 1);
            for _ in 0..4 {
                d.next();
            }
            let (lo, hi) = STEP_RANGE;
            let factor = lo * (hi / lo).powf(d.next());
            let own = builtin(&name).and_then(Result::ok).map_or(1, |sc| sc.steps);
            let steps = ((own as f64 / factor).ceil() as usize).clamp(1, MAX_INCREMENTS);
            let elements = match (d.next() * 3.0) as usize {
                0 => None,
                m => {
                    single_body_elements(&name).map(|n| if m == 1 { (n / 2).max(1) } else { 2 * n })
                }
            };
            out.push(Case {
                scene: name.clone(),
                seed: s,
                formulation: if d.next() < 0.5 {
                    Formulation::Timoshenko
                } else {
                    Formulation::BernoulliEuler
                },
                elements,
                factor,
                steps,
                reverse: d.next() < 0.5,
                mu: if d.next() < 0.5 { 0.0 } else { d.next() },
                text: None,
            });
        }
    }
    for (k, family) in FAMILIES.iter().enumerate() {
        let (name, own) = (family.name, family.steps);
        for j in 0..per_scene {
            let s = seed
                ^ ((k as u64 + 101) << 32)
                ^ (j as u64 + 1).wrapping_mul(0x9e37_79b9_7f4a_7c15);
            let mut d = Draw(s | 1);
            for _ in 0..4 {
                d.next();
            }
            let (lo, hi) = STEP_RANGE;
            let factor = lo * (hi / lo).powf(d.next());
            let n = 8 << ((d.next() * 5.0) as usize).min(4);
            out.push(Case {
                scene: name.to_string(),
                seed: s,
                formulation: if d.next() < 0.5 {
                    Formulation::Timoshenko
                } else {
                    Formulation::BernoulliEuler
                },
                elements: Some(n),
                factor,
                steps: ((own as f64 / factor).ceil() as usize).clamp(1, MAX_INCREMENTS),
                reverse: d.next() < 0.5,
                mu: family.mu.unwrap_or(if d.next() < 0.5 { 0.0 } else { 0.2 }),
                text: Some((family.scene)(n)),
            });
        }
    }
    out
}

/// The elements per segment of a one-body built-in scene.
fn single_body_elements(name: &str) -> Option<usize> {
    let scene = builtin(name)?.ok()?;
    match scene.file.bodies.as_slice() {
        [body] => Some(body.elements),
        _ => None,
    }
}

/// The scene of `case`: re-meshed, its formulation and friction set; or why there is none
/// (the kind, `Refused` where validation refuses it, and the text).
fn scene_of(case: &Case) -> Result<Scene, (String, String)> {
    let refused = |e: crate::scene::SceneError| ("Refused".to_string(), e.to_string());
    let unknown = || {
        (
            "NoMesh".to_string(),
            "the scene cannot be re-meshed so".to_string(),
        )
    };
    let mut scene = match (&case.text, case.elements) {
        (Some(text), _) => crate::scene::parse(text, &case.scene).map_err(refused)?,
        (None, Some(n)) => with_elements(&case.scene, n)
            .ok_or_else(unknown)?
            .map_err(refused)?,
        (None, None) => builtin(&case.scene).ok_or_else(unknown)?.map_err(refused)?,
    };
    scene.model.formulation = case.formulation;
    for pair in scene.model.contacts.iter_mut() {
        pair.mu = case.mu;
    }
    for ob in scene.model.obstacles.iter_mut() {
        ob.mu = case.mu;
    }
    Ok(scene)
}

/// Drive `case` and audit what it accepted.
pub fn run(case: &Case) -> Outcome {
    run_keeping(case, false)
}

/// `run`, the accepted states kept in the outcome where `keep`.
pub fn run_keeping(case: &Case, keep: bool) -> Outcome {
    let mut outcome = Outcome {
        case: case.clone(),
        stop: None,
        iterations: Vec::new(),
        findings: Vec::new(),
        stiffness: None,
        records: Vec::new(),
    };
    let scene = match scene_of(case) {
        Ok(scene) => scene,
        Err(stop) => {
            outcome.stop = Some(stop);
            return outcome;
        }
    };
    let mut solver = match scene.solver() {
        Ok(s) => s,
        Err(e) => {
            outcome.stop = Some((kind(&e), e.to_string()));
            return outcome;
        }
    };
    let per_step: Vec<f64> = (scene.model.prescribed.iter())
        .map(|p| p.per_step * case.factor)
        .collect();
    let load_step = scene.model.load_per_step * case.factor;
    let mut count = Count::default();
    let legs = if case.reverse { 2 } else { 1 };
    let mut first = None;
    'drive: for leg in 0..legs {
        let sign = if leg == 0 { 1.0 } else { -1.0 };
        for _ in 0..case.steps {
            let targets: Vec<f64> = (solver.prescribed_values().iter())
                .zip(&per_step)
                .map(|(v, s)| v + sign * s)
                .collect();
            let lambda = solver.load_factor() + sign * load_step;
            let factors = solver.structure.model.uniform_factors(lambda);
            match solver.advance_to(&targets, &factors, &mut count) {
                Ok(_) => {
                    if first.is_none() && !count.accepted.is_empty() {
                        first = Some(solver.checkpoint());
                    }
                }
                Err(e) => {
                    if matches!(e, crate::solver::SolveError::NoConvergence { .. }) {
                        let last = least_eigenvalue(&solver);
                        if let Some(c) = &first {
                            solver.restore(c);
                        }
                        outcome.stiffness = least_eigenvalue(&solver).zip(last);
                    }
                    outcome.stop = Some((kind(&e), e.to_string()));
                    break 'drive;
                }
            }
        }
    }
    let records = std::mem::take(&mut count.accepted);
    outcome.iterations = count.iterations_of(&records);
    let topology = Topology::of(&scene.model);
    let ids: Vec<u32> = scene.model.nodes.iter().map(|n| n.id).collect();
    let audit_run = Run {
        topology: &topology,
        node_ids: &ids,
        params: &scene.params,
    };
    outcome.findings = (audit(&audit_run, None, &records).iter())
        .map(|f| f.to_string())
        .collect();
    if keep {
        outcome.records = records;
    }
    outcome
}

/// The history of a drive run with its states kept ([`run_keeping`]): what `check` audits and
/// the app reads.
pub fn history(case: &Case, outcome: &Outcome) -> History {
    let mut h = match scene_of(case) {
        Ok(scene) => History::of_model(
            &case.scene,
            &scene.model,
            Some(case.formulation),
            Some(scene.params),
        ),
        Err(_) => History::default(),
    };
    h.increments = outcome.records.clone();
    h.error = outcome.stop.as_ref().map(|(_, text)| text.clone());
    h
}

/// The kind of an error: its variant's name.
fn kind(e: &crate::solver::SolveError) -> String {
    let debug = format!("{e:?}");
    debug.chars().take_while(|c| c.is_alphanumeric()).collect()
}

/// The report: a summary, a line per scene and every stop, as Markdown.
pub fn report(outcomes: &[Outcome], per_scene: usize, seed: u64) -> String {
    let mut text = String::new();
    let done = outcomes.iter().filter(|o| o.stop.is_none()).count();
    let all: Vec<usize> = outcomes
        .iter()
        .flat_map(|o| o.iterations.iter().copied())
        .collect();
    let accepted = all.len();
    let (median, p99, largest) = spread(all);
    let findings: usize = outcomes.iter().map(|o| o.findings.len()).sum();
    text += &format!(
        "{} drives ({per_scene} per built-in scene and family, seed {seed}): {done} complete ({:.1} %), {} accepted increments, {findings} audit finding(s).\n\n",
        outcomes.len(),
        100.0 * done as f64 / outcomes.len().max(1) as f64,
        accepted
    );
    text += &format!(
        "Newton iterations per accepted increment, failed attempts and cut-backs included: median {median}, 99th percentile {p99}, largest {largest}.\n\n",
    );
    text += "| scene | drives | complete | stops (kind: count) | iterations median / p99 / max | findings |\n|---|---|---|---|---|---|\n";
    let mut scenes: Vec<&str> = outcomes.iter().map(|o| o.case.scene.as_str()).collect();
    scenes.dedup();
    for name in scenes {
        let of: Vec<&Outcome> = outcomes.iter().filter(|o| o.case.scene == name).collect();
        let mut stops: BTreeMap<&str, usize> = BTreeMap::new();
        for o in &of {
            if let Some((k, _)) = &o.stop {
                *stops.entry(k.as_str()).or_default() += 1;
            }
        }
        let its: Vec<usize> = of
            .iter()
            .flat_map(|o| o.iterations.iter().copied())
            .collect();
        let (median, p99, largest) = spread(its);
        let stops: Vec<String> = stops.iter().map(|(k, n)| format!("{k}: {n}")).collect();
        text += &format!(
            "| {name} | {} | {} | {} | {median} / {p99} / {largest} | {} |\n",
            of.len(),
            of.iter().filter(|o| o.stop.is_none()).count(),
            if stops.is_empty() {
                "-".into()
            } else {
                stops.join(", ")
            },
            of.iter().map(|o| o.findings.len()).sum::<usize>()
        );
    }
    text += "\nEvery stop, with its drive (seed, formulation, elements per segment, step factor, steps, down and up, mu; `tsm-contact robust --drive SEED` runs one again). A stop without convergence also gives the least real part of the eigenvalues of the tangent over the free dofs (the drive held, models of up to 1500 free dofs): one that falls towards zero, or below, from the drive's first step to the last accepted state marks a limit point of the drive (where the structure snaps, or a snap that found no stable state); one that does not, a failure of the solve. States on the way of a snap are counted among the accepted increments and audited like every state:\n\n";
    for o in outcomes
        .iter()
        .filter(|o| o.stop.is_some() || !o.findings.is_empty())
    {
        let c = &o.case;
        let why = o
            .stop
            .as_ref()
            .map_or("completes".to_string(), |s| s.1.clone());
        text += &format!(
            "- {} seed {:#x} {:?} {} x{:.3e} {} steps{} mu {:.2}: {why}{}{}\n",
            c.scene,
            c.seed,
            c.formulation,
            c.elements.map_or("own mesh".into(), |n| format!("{n} el.")),
            c.factor,
            c.steps,
            if c.reverse { " and back" } else { "" },
            c.mu,
            o.stiffness.map_or(String::new(), |(a, b)| format!(
                "; least eigenvalue of the tangent {a:.2e} after the first step, {b:.2e} at the last accepted state"
            )),
            o.findings
                .first()
                .map_or(String::new(), |f| format!("; audit: {f}"))
        );
    }
    text
}
