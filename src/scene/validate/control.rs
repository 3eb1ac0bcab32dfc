//! The `control` section of a scene: solver parameters, steps and the load per step, with
//! arc-length control only for a load-driven scene whose prescribed displacements are held.

use super::conditions::Conditions;
use super::errors::{positive, sized, within, Ctx, SceneError};
use crate::scene::format::{ContactNormal, SceneFile};
use crate::solver::{LoadPath, SolverParams};

/// The range of a bound on the relative residual (the tolerance, the round-off bound): above
/// 1e-2 an increment a hundredth out of equilibrium would count as converged.
const RELATIVE_RESIDUAL: (f64, f64) = (0.0, 1e-2);

/// The range of the obstacle gap (a fraction of the model's size): below 1e-15 it is under the
/// round-off of the positions, above 1e-3 a node would rest visibly inside its obstacle.
const OBSTACLE_GAP: (f64, f64) = (1e-15, 1e-3);

/// The run settings of a scene.
pub(super) struct Control {
    pub(super) params: SolverParams,
    pub(super) steps: usize,
    pub(super) load_per_step: f64,
}

/// The control settings of `sf`, whose conditions are `c_` and load path `path`.
pub(super) fn control(
    ctx: &Ctx,
    sf: &SceneFile,
    c_: &Conditions,
    path: Option<&LoadPath>,
) -> Result<Control, SceneError> {
    let c = &sf.control;
    let mut params = parameters(ctx, sf)?;
    if let Some(path) = path {
        return staged(ctx, sf, params, path);
    }
    if let Some(s) = c.arc_length {
        positive(
            ctx,
            "control.arc_length".into(),
            Some("arc_length".into()),
            s,
        )?;
        if c_.loads.is_empty() && c_.distributed.is_empty() {
            return Err(ctx.err(
                "control.arc_length",
                Some("arc_length".into()),
                "arc-length control needs at least one load (the load factor is what it solves for)",
            ));
        }
        if let Some(k) = c_.prescribed.iter().position(|p| p.per_step != 0.0) {
            return Err(ctx.err(
                format!("prescribed[{k}].per_step"),
                Some("per_step".into()),
                "with control.arc_length, prescribed displacements are held: per_step must be 0",
            ));
        }
        params.arc_length = Some(s);
    }
    if c.steps == 0 {
        return Err(ctx.err(
            "control.steps",
            Some("steps".into()),
            "a run needs at least one step",
        ));
    }
    let steps = c.steps;
    let load_per_step = match c.load_per_step {
        Some(v) if sized(v) => v,
        Some(v) => {
            return Err(ctx.err(
                "control.load_per_step",
                Some("load_per_step".into()),
                format!("must be finite and below 1e100 in size, got {v:e}"),
            ))
        }
        None if c_.loads.is_empty() && c_.distributed.is_empty() => 0.0,
        None => 1.0 / steps as f64,
    };
    Ok(Control {
        params,
        steps,
        load_per_step,
    })
}

/// The solver parameters `control` sets, whatever drives the run.
fn parameters(ctx: &Ctx, sf: &SceneFile) -> Result<SolverParams, SceneError> {
    let c = &sf.control;
    let mut params = SolverParams::default();
    if let Some(t) = c.tolerance {
        within(ctx, "control.tolerance", t, RELATIVE_RESIDUAL)?;
        params.tolerance = t;
    }
    if let Some(b) = c.roundoff_bound {
        within(ctx, "control.roundoff_bound", b, RELATIVE_RESIDUAL)?;
        params.roundoff_bound = b;
    }
    if let Some(g) = c.obstacle_gap {
        within(ctx, "control.obstacle_gap", g, OBSTACLE_GAP)?;
        params.obstacle_gap = g;
    }
    if let Some(s) = c.max_step {
        positive(ctx, "control.max_step".into(), Some("max_step".into()), s)?;
        params.max_step = s;
    }
    params.stretch_correction = c.stretch_correction;
    params.surface_normal = c.contact_normal == ContactNormal::Surface;
    params.snap = c.snap;
    Ok(params)
}

/// The control of a scene driven by its stages: as many steps as the path has; arc length and
/// `load_per_step`, which drive a run by one load factor, are refused.
fn staged(
    ctx: &Ctx,
    sf: &SceneFile,
    params: SolverParams,
    path: &LoadPath,
) -> Result<Control, SceneError> {
    let c = &sf.control;
    if c.arc_length.is_some() {
        return Err(ctx.err(
            "control.arc_length",
            Some("arc_length".into()),
            "arc-length control solves for one load factor and cannot follow stages: remove \
             `arc_length`, or the stages",
        ));
    }
    if c.load_per_step.is_some() {
        return Err(ctx.err(
            "control.load_per_step",
            Some("load_per_step".into()),
            "a scene with stages has its load factors set by the stages: remove `load_per_step`",
        ));
    }
    Ok(Control {
        params,
        steps: path.total_steps(),
        load_per_step: 0.0,
    })
}
