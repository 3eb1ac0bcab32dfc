//! A run kept as the scene's load path: the steps a history went through (Run and Step, each
//! increment of a drag toward the handle's moving target) written as stages of the scene, so
//! that the scene replays them headless to the same states: the scene's own stages the run
//! went through whole, as written, then one stage that lists, step by step, the prescribed
//! values and load factors the run went to.

use super::format::{DofChangeDef, GroupChangeDef, SceneFile, StageDef};
use super::validate::group_names;
use crate::solver::{IncrementRecord, Model};

/// The name of the stage a kept drive becomes.
pub const KEPT_STAGE: &str = "kept drive";

/// The increments of `records` that end a step: every increment but those of a step that was
/// cut back and went on toward its target. An increment of a cut-back step after which the next
/// step starts afresh (fewer cut-backs counted) ended its step where the run was stopped.
fn step_ends(records: &[IncrementRecord]) -> Vec<&IncrementRecord> {
    (records.iter().enumerate())
        .filter(|(k, r)| {
            !r.partial || (records.get(k + 1)).is_none_or(|next| next.cutbacks < r.cutbacks)
        })
        .map(|(_, r)| r)
        .collect()
}

/// The factor of load group `g` in record `r` (its one load factor where it has no groups).
fn factor(r: &IncrementRecord, g: usize) -> f64 {
    r.load_factors.get(g).copied().unwrap_or(r.load_factor)
}

/// `file`, whose validated model is `model`, with the run `records` (increments 1 on, in order)
/// as its load path: the scene's stages the run went through whole and exactly, then a stage
/// named `KEPT_STAGE` listing the values of every prescribed dof and load factor that moved
/// after them, one per step. The scene's later stages are left out (the run left them).
pub fn kept_path(
    file: &SceneFile,
    model: &Model,
    records: &[IncrementRecord],
) -> Result<SceneFile, String> {
    if file.control.arc_length.is_some() {
        return Err(
            "an arc-length run finds its load factor as it goes: it is not a path to keep".into(),
        );
    }
    let steps = step_ends(records);
    if steps.is_empty() {
        return Err("nothing to keep: the run has no increments yet".into());
    }
    // The scene's stages the run followed from the start, whole.
    let (mut whole, mut done) = (0usize, 0usize);
    if let Some(path) = &model.path {
        'stages: for (s, stage) in path.stages.iter().enumerate() {
            for k in done..done + stage.steps {
                let (Some(r), Some(p)) = (steps.get(k), path.point(k)) else {
                    break 'stages;
                };
                let factors: Vec<f64> = (0..p.factors.len()).map(|g| factor(r, g)).collect();
                if r.stage != Some(s) || r.prescribed != p.prescribed || factors != p.factors {
                    break 'stages;
                }
            }
            whole += 1;
            done += stage.steps;
        }
    }
    let groups = if model.load_groups.is_empty() {
        group_names(file)
    } else {
        model.load_groups.clone()
    };
    let (start_p, start_f) = match done.checked_sub(1) {
        None => (vec![0.0; model.prescribed.len()], vec![0.0; groups.len()]),
        Some(k) => (
            steps[k].prescribed.clone(),
            (0..groups.len()).map(|g| factor(steps[k], g)).collect(),
        ),
    };
    let rest = &steps[done..];
    let mut kept = file.clone();
    kept.stages.truncate(whole);
    kept.control.load_per_step = None;
    if !rest.is_empty() {
        let moved = |start: f64, values: &[f64]| values.iter().any(|&v| v != start);
        let loads = (groups.iter().enumerate())
            .map(|(g, name)| (name, rest.iter().map(|r| factor(r, g)).collect::<Vec<_>>()))
            .zip(&start_f)
            .filter(|((_, values), &start)| moved(start, values))
            .map(|((name, values), _)| GroupChangeDef {
                group: name.clone(),
                to: None,
                by: None,
                values: Some(values),
            })
            .collect();
        let prescribed = (model.prescribed.iter().enumerate())
            .map(|(k, p)| (p, rest.iter().map(|r| r.prescribed[k]).collect::<Vec<_>>()))
            .zip(&start_p)
            .filter(|((_, values), &start)| moved(start, values))
            .map(|((p, values), _)| DofChangeDef {
                node: model.nodes[p.node].id,
                dof: p.dof,
                to: None,
                by: None,
                values: Some(values),
            })
            .collect();
        kept.stages.push(StageDef {
            name: Some(KEPT_STAGE.into()),
            steps: Some(rest.len()),
            loads,
            prescribed,
        });
    }
    Ok(kept)
}
