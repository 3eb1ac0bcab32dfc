//! The independent audit of a run's history: every accepted increment is in equilibrium from
//! its recorded forces, every support and prescribed dof is where it is held, no candidate
//! node changed its side of a body except round an end, none that stands off the axes (a
//! radius, a thickness) overlaps a body it does not touch, no node is inside an obstacle, every
//! frictional contact is within the friction law, and every contact presses. It reads only the
//! history (its topology, node states, forces and contact records) and shares no code with the
//! solver's contact, acceptance, element, assembly or Newton code
//! (`tests/inputs/architecture.rs` bars those imports): it is the oracle of the tests and of
//! `tsm-contact check`.

pub mod equilibrium;
pub mod finding;
pub mod geometry;
pub mod obstacles;
pub mod rims;
pub mod sides;
pub mod supports;

use std::collections::HashMap;

use crate::history::{History, Topology};
use crate::solver::{IncrementRecord, IncrementStatus, SolverParams};
pub use finding::Finding;
use geometry::Chains;
use sides::SideAudit;

/// Round-off units of the largest coordinate that an obstacle gap may be off by.
const ROUNDOFF_ULPS: f64 = 64.0;

/// Slack of the friction law: a friction force may exceed mu times the pressure by this
/// fraction, the law's stated tolerance (`docs/acceptance.md`: the stick spring and the
/// obstacles' penalty leave a slipping contact's ratio within it of 1, not at 1 exactly).
const FRICTION_SLACK: f64 = 1e-6;

/// What the audit needs of a run: its topology, node order and parameters.
pub struct Run<'a> {
    /// The model's topology.
    pub topology: &'a Topology,
    /// The node ids in the order of [`IncrementRecord::nodes`].
    pub node_ids: &'a [u32],
    /// The solver parameters of the run (tolerances).
    pub params: &'a SolverParams,
}

/// Every finding of the audit of `records`, which follow one another from the state `start`
/// (None: the model at rest, increment 0).
pub fn audit(
    run: &Run<'_>,
    start: Option<&IncrementRecord>,
    records: &[IncrementRecord],
) -> Vec<Finding> {
    audit_with(run, start, records, true)
}

/// `audit`, with the sides of the candidate nodes judged between consecutive records only
/// where `sides` (records that skip increments cannot tell a node that went through a body
/// and back between them).
fn audit_with(
    run: &Run<'_>,
    start: Option<&IncrementRecord>,
    records: &[IncrementRecord],
    sides_judged: bool,
) -> Vec<Finding> {
    let topology = run.topology;
    let chains = Chains::new(topology, run.node_ids);
    let rest: HashMap<u32, [f64; 2]> = topology.nodes.iter().map(|n| (n.id, [n.x, n.y])).collect();
    let rest_state: Vec<[f64; 3]> = (run.node_ids.iter())
        .map(|id| rest.get(id).map_or([0.0; 3], |p| [p[0], p[1], 0.0]))
        .collect();
    let group = equilibrium::groups(topology, &chains.slot, run.node_ids.len());
    let size = {
        let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
        for p in rest.values() {
            for k in 0..2 {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
        }
        (hi[0] - lo[0]).max(hi[1] - lo[1]).max(0.0)
    };
    let obstacle_tol =
        run.params.obstacle_gap * size + ROUNDOFF_ULPS * f64::EPSILON * size.max(1.0);
    let mut sides = SideAudit::new(topology, &chains, run.params.xi_min);
    let mut found = Vec::new();
    // Where each contact presses on its element: the node, or for a node off the axis (a
    // radius, a thickness) the point of the axis it presses on.
    let contacts_of = |r: &IncrementRecord| -> Vec<(u32, usize, [f64; 2])> {
        (r.contacts.iter())
            .filter_map(|c| {
                let s = chains.slot.get(&c.node)?;
                let at = c.point.unwrap_or([r.nodes[*s][0], r.nodes[*s][1]]);
                Some((c.node, c.element, at))
            })
            .collect()
    };
    let (mut before, mut c_before) = match start {
        Some(r) => (r.nodes.clone(), contacts_of(r)),
        None => (rest_state, Vec::new()),
    };
    match start {
        // Sides are learnt from the start state: a record with its contacts.
        Some(r) => {
            let _ = sides.step(&before, &[], r, &|_| 0.0);
        }
        None => sides.start(&before),
    }
    for r in records {
        let at = |what: String| Finding {
            increment: r.increment,
            node: None,
            body: None,
            element: None,
            what,
        };
        if let Some(why) = status(run.params, r) {
            found.push(at(why));
        }
        if let Some(why) = equilibrium::unbalanced(topology, run.params, &chains.slot, &group, r) {
            found.push(at(why));
        }
        let sag = load_sag(topology, &chains, r);
        if sides_judged {
            found.extend(sides.step(&before, &c_before, r, &|e| sag[e]));
        }
        found.extend(rims::overlapping(topology, &chains, r, &|e| sag[e]));
        let slot = &chains.slot;
        if let Some((n, o, depth)) =
            obstacles::deepest_inside(topology, slot, &rest, &r.nodes, obstacle_tol)
        {
            found.push(Finding {
                increment: r.increment,
                node: Some(n),
                body: Some(o.clone()),
                element: None,
                what: format!("node {n} is {depth:.3e} m inside obstacle {o} (its face, at its clearance from it; accepted gap {obstacle_tol:.1e} m)"),
            });
        }
        found.extend(supports::out_of_place(
            topology,
            slot,
            &rest,
            r,
            (size, chains.roundoff),
        ));
        found.extend(friction_and_pressure(topology, r));
        before = r.nodes.clone();
        c_before = contacts_of(r);
    }
    found
}

/// The audit of a whole history, with `topology` standing in for the one it lacks (a version 1
/// history); an error where there is none, or no parameters. On a thinned history
/// ([`History::every`]) the sides of the candidate nodes are not judged: between the increments
/// it keeps a node may have gone through a body and back (`check` says so).
pub fn audit_history(h: &History, topology: Option<&Topology>) -> Result<Vec<Finding>, String> {
    let topology = (h.topology.as_ref().or(topology))
        .ok_or("the history carries no topology (format version 1): name its scene with --scene")?;
    let params = h
        .params
        .as_ref()
        .ok_or("the history carries no solver parameters")?;
    let known: std::collections::HashSet<u32> = topology.nodes.iter().map(|n| n.id).collect();
    if let Some(id) = h.node_ids.iter().find(|id| !known.contains(id)) {
        return Err(format!(
            "node {id} of the history is not a node of the scene"
        ));
    }
    if let Some(r) = h
        .increments
        .iter()
        .find(|r| r.nodes.len() != h.node_ids.len())
    {
        return Err(format!(
            "increment {} has {} node states for {} nodes",
            r.increment,
            r.nodes.len(),
            h.node_ids.len()
        ));
    }
    let run = Run {
        topology,
        node_ids: &h.node_ids,
        params,
    };
    let thinned = h.every.is_some_and(|n| n > 1);
    Ok(audit_with(&run, None, &h.increments, !thinned))
}

/// Why the status of record `r` is not what its residual says, if it is not.
fn status(params: &SolverParams, r: &IncrementRecord) -> Option<String> {
    let (bound, named) = match r.status {
        IncrementStatus::Converged => (params.tolerance, "converged"),
        IncrementStatus::RoundOff { .. } => (
            params.roundoff_bound.max(params.tolerance),
            "accepted at the round-off floor",
        ),
        IncrementStatus::Snapping { residual } => {
            (residual.max(params.tolerance) * (1.0 + 1e-9), "snapping")
        }
    };
    // Within the bound (a NaN residual is not).
    let within = matches!(
        r.relative_residual.partial_cmp(&bound),
        Some(std::cmp::Ordering::Less | std::cmp::Ordering::Equal)
    );
    (!within).then(|| {
        format!(
            "called {named} with a relative residual of {:.3e}, above {bound:.0e}",
            r.relative_residual
        )
    })
}

/// What the loads across each element may bend it beyond its end-loaded shape (m): the
/// midspan deflection q l^4 / (384 E I) of a clamped span under its transverse load q, and with
/// Timoshenko elements its shear part q l^2 / (8 G Ae).
fn load_sag(topology: &Topology, chains: &Chains, r: &IncrementRecord) -> Vec<f64> {
    let mut sag = vec![0.0; topology.elements.len()];
    let timoshenko = topology.formulation == Some(crate::solver::Formulation::Timoshenko);
    for d in &topology.distributed {
        let e = &topology.elements[d.element];
        let (a, b) = (r.nodes[chains.slot[&e.i]], r.nodes[chains.slot[&e.j]]);
        let l = (b[0] - a[0]).hypot(b[1] - a[1]);
        let lam = r
            .load_factors
            .get(d.group)
            .copied()
            .unwrap_or(r.load_factor);
        let q = lam.abs() * d.q.iter().fold(0.0f64, |m, q| m.max(q[0].hypot(q[1])));
        let q = if d.follower { q * l } else { q };
        if e.ei > 0.0 {
            sag[d.element] += q * l.powi(4) / (384.0 * e.ei);
        }
        if timoshenko && e.gae > 0.0 {
            sag[d.element] += q * l * l / (8.0 * e.gae);
        }
    }
    sag
}

/// The contacts of `r` that pull, or whose friction force is beyond mu times their pressure.
fn friction_and_pressure(topology: &Topology, r: &IncrementRecord) -> Vec<Finding> {
    let mut found = Vec::new();
    let mut law = |node: u32, surface: &str, mu: f64, pressure: f64, t: f64| {
        let what = if pressure < 0.0 {
            format!("the contact of node {node} on {surface} pulls ({pressure:.3e} N)")
        } else if t.abs() > mu * pressure * (1.0 + FRICTION_SLACK) + f64::MIN_POSITIVE {
            format!(
                "the friction force on node {node} on {surface} is {:.6e} N, beyond mu N = {:.6e} N",
                t.abs(),
                mu * pressure
            )
        } else {
            return;
        };
        found.push(Finding {
            increment: r.increment,
            node: Some(node),
            body: Some(surface.to_string()),
            element: None,
            what,
        });
    };
    for c in &r.contacts {
        let mu = (topology.candidates.iter())
            .find(|p| p.node == c.node && p.body == c.body)
            .map_or(0.0, |p| p.mu);
        law(c.node, &c.body, mu, c.pressure, c.tangential);
    }
    for c in &r.obstacle_contacts {
        let mu = (topology.obstacles.iter())
            .find(|o| o.name == c.obstacle)
            .map_or(0.0, |o| o.mu);
        law(
            c.node,
            &format!("obstacle {}", c.obstacle),
            mu,
            c.force.max(0.0),
            c.tangential,
        );
    }
    found
}
