//! What the worker works out from a solver: the next target of a drag (no further than one
//! scene step per increment), whether the targets are reached, how far along the scene's steps
//! a state is, the record of the initial state, and the text of a caught panic.

use crate::solver::{IncrementRecord, Solver};

/// The next prescribed values on the way to `targets`: the whole way if every dof is within its
/// `|per_step|`, else scaled so that no dof moves more than its `|per_step|`.
pub fn next_target(solver: &Solver, targets: &[f64]) -> Vec<f64> {
    let cur = solver.prescribed_values();
    let mut f = 1.0f64;
    for ((p, c), t) in solver
        .structure
        .model
        .prescribed
        .iter()
        .zip(cur)
        .zip(targets)
    {
        let d = (t - c).abs();
        let h = p.per_step.abs();
        if d > h && h > 0.0 {
            f = f.min(h / d);
        }
    }
    if f >= 1.0 {
        return targets.to_vec();
    }
    cur.iter()
        .zip(targets)
        .map(|(c, t)| c + f * (t - c))
        .collect()
}

/// Whether the prescribed values are at the targets (to a negligible fraction of a step).
pub(super) fn reached(solver: &Solver, targets: &[f64]) -> bool {
    solver
        .structure
        .model
        .prescribed
        .iter()
        .zip(solver.prescribed_values())
        .zip(targets)
        .all(|((p, c), t)| (t - c).abs() <= 1e-12 * p.per_step.abs().max(t.abs()).max(1e-300))
}

/// How many of the scene's `steps` the solver's state lies along: the steps of its load path
/// completed, or the largest share of its total reached by any prescribed dof or by the load
/// factor, in whole steps (for an arc-length run, its increments). What "Run" counts the remaining steps from after a
/// restore.
pub(super) fn steps_along(solver: &Solver, steps: usize) -> usize {
    if solver.structure.params.arc_length.is_some() {
        return solver.increment().min(steps);
    }
    if solver.structure.model.path.is_some() {
        return solver.path_step().min(steps);
    }
    let mut along = 0.0f64;
    for (p, v) in solver
        .structure
        .model
        .prescribed
        .iter()
        .zip(solver.prescribed_values())
    {
        if p.per_step != 0.0 {
            along = along.max(v / p.per_step);
        }
    }
    if solver.structure.model.load_per_step != 0.0 {
        along = along.max(solver.load_factor() / solver.structure.model.load_per_step);
    }
    // Reached to round-off counts as reached.
    ((along + 1e-9).floor().max(0.0) as usize).min(steps)
}

/// The undeformed state of a fresh solver as increment 0.
pub fn initial_record(solver: &Solver) -> IncrementRecord {
    let model = &solver.structure.model;
    IncrementRecord {
        increment: 0,
        prescribed: solver.prescribed_values().to_vec(),
        load_factor: solver.load_factor(),
        load_factors: if model.load_groups.len() > 1 {
            solver.load_factors().to_vec()
        } else {
            Vec::new()
        },
        stage: None,
        partial: false,
        iterations: 0,
        iterations_8_orders: None,
        relative_residual: 0.0,
        reference: 0.0,
        roundoff_floor: 0.0,
        status: Default::default(),
        cutbacks: 0,
        residuals: Vec::new(),
        nodes: solver.structure.node_states(solver.displacements()),
        element_forces: vec![[0.0; 3]; model.beams.len()],
        reactions: Vec::new(),
        contacts: Vec::new(),
        obstacle_contacts: Vec::new(),
        max_penetration: 0.0,
        events: Vec::new(),
        seconds: 0.0,
    }
}

pub(super) fn panic_text(p: &Box<dyn std::any::Any + Send>) -> String {
    if let Some(s) = p.downcast_ref::<&str>() {
        (*s).to_string()
    } else if let Some(s) = p.downcast_ref::<String>() {
        s.clone()
    } else {
        "unknown panic".into()
    }
}
