//! The load path of a scene: its load groups (each load's `group`, "loads" for those that name
//! none, "gravity" for the self-weight) and its `stages`, each checked (at least one step; a
//! group the scene has; a dof the scene prescribes; exactly one of `to`, `by` and `values`;
//! finite values) and resolved into the solver's `LoadPath` of stage-end values.

use super::errors::{entry_line, sized, Ctx, SceneError};
use super::geometry::Geometry;
use crate::scene::format::{SceneFile, StageDef};
use crate::solver::{LoadPath, Prescribed, Stage, StageMotion};

/// The group of the loads that name none.
pub const DEFAULT_GROUP: &str = "loads";
/// The group of the self-weight under `control.gravity`.
pub const GRAVITY_GROUP: &str = "gravity";

/// The load groups of `sf` its model has: none where the scene has no stages (every load then
/// has the one load factor), else `group_names`.
pub(super) fn load_groups(sf: &SceneFile) -> Vec<String> {
    if sf.stages.is_empty() {
        return Vec::new();
    }
    group_names(sf)
}

/// The names of the load groups of `sf`, in order of first appearance (nodal loads, distributed
/// loads, then gravity).
pub fn group_names(sf: &SceneFile) -> Vec<String> {
    let named = (sf.loads.iter().map(|l| l.group.as_deref()))
        .chain(sf.distributed.iter().map(|d| d.group.as_deref()))
        .map(|g| g.unwrap_or(DEFAULT_GROUP))
        .chain(sf.control.gravity.map(|_| GRAVITY_GROUP));
    let mut groups: Vec<String> = Vec::new();
    for g in named {
        if !groups.iter().any(|h| h == g) {
            groups.push(g.to_string());
        }
    }
    groups
}

/// The index of the load group `name` (default "loads") among `groups`; 0 where the scene has
/// one load factor.
pub(super) fn group_index(groups: &[String], name: Option<&str>) -> usize {
    let name = name.unwrap_or(DEFAULT_GROUP);
    groups.iter().position(|g| g == name).unwrap_or(0)
}

/// The load path of `sf` (none without stages), over its load groups `groups` and prescribed
/// dofs `prescribed`.
pub(super) fn load_path(
    ctx: &Ctx,
    sf: &SceneFile,
    g: &Geometry,
    groups: &[String],
    prescribed: &[Prescribed],
) -> Result<Option<LoadPath>, SceneError> {
    if sf.stages.is_empty() {
        return Ok(None);
    }
    let mut factors = vec![0.0; groups.len().max(1)];
    let mut values = vec![0.0; prescribed.len()];
    let mut stages = Vec::with_capacity(sf.stages.len());
    for (k, st) in sf.stages.iter().enumerate() {
        // Errors inside a stage are located from the line where it opens.
        let from = entry_line(ctx.text, "stages", k);
        let start = from.map_or(0, |l| line_offset(ctx.text, l));
        let here = Ctx {
            text: &ctx.text[start..],
            file: ctx.file,
        };
        let stage = one_stage(
            &here,
            k,
            st,
            (g, groups, prescribed),
            (&mut factors, &mut values),
        )
        .map_err(|mut e| {
            e.line = match (e.line, from) {
                (Some(l), Some(f)) => Some(l + f - 1),
                _ => from,
            };
            e
        })?;
        stages.push(stage);
    }
    Ok(Some(LoadPath { stages }))
}

/// Stage `k` of the scene, `st`, checked and resolved from the load factors and prescribed
/// values where the stage before it ended (`factors`, `values`, moved to where it ends).
fn one_stage(
    ctx: &Ctx,
    k: usize,
    st: &StageDef,
    (g, groups, prescribed): (&Geometry, &[String], &[Prescribed]),
    (factors, values): (&mut Vec<f64>, &mut Vec<f64>),
) -> Result<Stage, SceneError> {
    let at = format!("stages[{k}]");
    let lists: Vec<usize> = (st.prescribed.iter().map(|p| &p.values))
        .chain(st.loads.iter().map(|l| &l.values))
        .filter_map(|v| v.as_ref().map(Vec::len))
        .collect();
    let steps = match (st.steps, lists.first()) {
        (Some(n), _) => n,
        (None, Some(&n)) => n,
        (None, None) => {
            return Err(at_stage(
                ctx,
                format!("{at}.steps"),
                "a stage needs its number of steps (or listed values)",
            ))
        }
    };
    if steps == 0 {
        return Err(at_stage(
            ctx,
            format!("{at}.steps"),
            "a stage needs at least one step",
        ));
    }
    if let Some(&n) = lists.iter().find(|&&n| n != steps) {
        return Err(ctx.err(
            format!("{at}.values"),
            Some("values".into()),
            format!("{n} values for a stage of {steps} steps: give one value per step"),
        ));
    }
    let mut named = vec![false; factors.len()];
    let mut ramps: Vec<StageMotion> = factors.iter().map(|&v| StageMotion::To(v)).collect();
    for (j, c) in st.loads.iter().enumerate() {
        let field = format!("{at}.loads[{j}] (group \"{}\")", c.group);
        let needle = Some(format!("\"{}\"", c.group));
        let Some(gi) = groups.iter().position(|h| *h == c.group) else {
            let known = if groups.is_empty() {
                "the scene has no loads".to_string()
            } else {
                format!("the scene's groups are {}", groups.join(", "))
            };
            return Err(ctx.err(
                format!("{at}.loads[{j}].group (group \"{}\")", c.group),
                needle,
                format!("no load group \"{}\": {known}", c.group),
            ));
        };
        if std::mem::replace(&mut named[gi], true) {
            return Err(ctx.err(field, needle, "named twice in one stage"));
        }
        ramps[gi] = motion(ctx, (&field, &needle), factors[gi], (c.to, c.by, &c.values))?;
        factors[gi] = ramps[gi].end();
    }
    let mut motions: Vec<StageMotion> = values.iter().map(|&v| StageMotion::To(v)).collect();
    let mut moved = vec![false; prescribed.len()];
    for (j, c) in st.prescribed.iter().enumerate() {
        let field = format!("{at}.prescribed[{j}] (node {} {})", c.node, c.dof.name());
        let needle = Some(format!("node:{}", c.node));
        let n = g.node_of(ctx, field.clone(), c.node)?;
        let Some(pk) = (prescribed.iter()).position(|p| p.node == n && p.dof == c.dof) else {
            return Err(ctx.err(
                field,
                needle,
                format!(
                    "node {} {} is not prescribed: list it in `prescribed` to drive it",
                    c.node,
                    c.dof.name()
                ),
            ));
        };
        if std::mem::replace(&mut moved[pk], true) {
            return Err(ctx.err(field, needle, "named twice in one stage"));
        }
        motions[pk] = motion(ctx, (&field, &needle), values[pk], (c.to, c.by, &c.values))?;
        values[pk] = motions[pk].end();
    }
    Ok(Stage {
        name: st
            .name
            .clone()
            .unwrap_or_else(|| format!("stage {}", k + 1)),
        steps,
        factors: ramps,
        prescribed: motions,
    })
}

/// How a value that stands at `start` moves over a stage: to `to`, by `by`, or through the
/// listed `values` (exactly one of them, each finite).
fn motion(
    ctx: &Ctx,
    (field, needle): (&str, &Option<String>),
    start: f64,
    (to, by, values): (Option<f64>, Option<f64>, &Option<Vec<f64>>),
) -> Result<StageMotion, SceneError> {
    Ok(match (to, by, values) {
        (Some(v), None, None) => StageMotion::To(finite(ctx, field, "to", v)?),
        (None, Some(d), None) => StageMotion::To(start + finite(ctx, field, "by", d)?),
        (None, None, Some(list)) => {
            for &v in list {
                finite(ctx, field, "values", v)?;
            }
            StageMotion::Values(list.clone())
        }
        _ => {
            return Err(ctx.err(
                field,
                needle.clone(),
                "give exactly one of `to`, `by` and `values`",
            ))
        }
    })
}

/// The error `message` for `field` of a stage, located at the line where it opens (the first
/// of `ctx`'s text).
fn at_stage(ctx: &Ctx, field: String, message: &str) -> SceneError {
    let mut e = ctx.err(field, None, message);
    e.line = Some(1);
    e
}

/// The byte offset where line `line` (from 1) of `text` starts.
fn line_offset(text: &str, line: usize) -> usize {
    (text.match_indices('\n').nth(line.saturating_sub(2))).map_or(0, |(i, _)| {
        if line <= 1 {
            0
        } else {
            i + 1
        }
    })
}

/// `v` if finite, else the error for `key` of `field`.
fn finite(ctx: &Ctx, field: &str, key: &str, v: f64) -> Result<f64, SceneError> {
    if sized(v) {
        Ok(v)
    } else {
        // `path (label)` becomes `path.key (label)`.
        let (path, label) = field.split_at(field.find(" (").unwrap_or(field.len()));
        Err(ctx.err(
            format!("{path}.{key}{label}"),
            Some(key.into()),
            format!("must be finite (below 1e100 in size), got {v:e}"),
        ))
    }
}
