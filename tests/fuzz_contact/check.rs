//! The campaign's independent checks of one run, made from its history (read back from JSON)
//! and the generator's own description of the scene, never from the solver's model or residual:
//! every accepted increment is in equilibrium body by body (loads, reactions and contact forces:
//! forces and moment) within the bound the stated tolerance gives, and no candidate node passes
//! through an element chord of a body it is not in contact with.

use tsm_contact::history::History;
use tsm_contact::solver::{IncrementRecord, IncrementStatus};

use super::generate::Spec;

/// Sub-steps of the linear sweep between two accepted states.
const SWEEP: usize = 32;

/// The first violation found in `history`, if any, as a located message.
pub fn violation(spec: &Spec, history: &History) -> Option<String> {
    let params = history
        .params
        .as_ref()
        .expect("the history has its parameters");
    let slot = |id: u32| history.node_ids.iter().position(|&n| n == id).unwrap();
    for rec in &history.increments {
        let (tol, bound, floor) = (params.tolerance, params.roundoff_bound, params.force_floor);
        if let Some(why) = equilibrium(spec, rec, tol, bound, floor, &slot) {
            return Some(format!("increment {}: {why}", rec.increment));
        }
    }
    first_crossing(spec, history)
}

/// The first crossing of an element chord by a candidate node not in contact with its body,
/// from one accepted state to the next (the undeformed state first), if any.
pub fn first_crossing(spec: &Spec, history: &History) -> Option<String> {
    let slot = |id: u32| history.node_ids.iter().position(|&n| n == id).unwrap();
    let mut before: Vec<[f64; 3]> = (history.node_ids.iter())
        .map(|id| [spec.coords[id][0], spec.coords[id][1], 0.0])
        .collect();
    let mut contacts_before: Vec<(u32, usize)> = Vec::new();
    for rec in &history.increments {
        let after = rec.nodes.clone();
        let active: Vec<(u32, usize)> = (rec.contacts.iter())
            .map(|c| (c.node, spec.elements[c.element].0))
            .collect();
        if let Some(why) = crossing(spec, &before, &after, &contacts_before, &active, &slot) {
            return Some(format!("increment {}: {why}", rec.increment));
        }
        before = after;
        contacts_before = active;
    }
    None
}

/// Body-by-body equilibrium of one increment. For a body (or a free pin), the loads and
/// reactions on its nodes balance the contact forces on it; the beams' own element forces
/// cancel within the body. The unbalanced force `r` of the free dofs sums, over any set of
/// them, to at most `sqrt(n) |r|`, and `|r| <= tol * reference`.
fn equilibrium(
    spec: &Spec,
    rec: &IncrementRecord,
    tolerance: f64,
    roundoff_bound: f64,
    force_floor: f64,
    slot: &dyn Fn(u32) -> usize,
) -> Option<String> {
    let tol = match rec.status {
        IncrementStatus::Converged => tolerance,
        IncrementStatus::RoundOff { .. } => roundoff_bound,
    };
    if rec.relative_residual > tol {
        return Some(format!(
            "relative residual {:e} above {tol:e}",
            rec.relative_residual
        ));
    }
    let pos = |id: u32| {
        let p = rec.nodes[slot(id)];
        [p[0], p[1]]
    };
    // External forces on each node: loads times the load factor, and reactions.
    let mut ext: std::collections::HashMap<u32, [f64; 3]> = Default::default();
    let (mut load2, mut reac2) = (0.0, 0.0);
    for (n, f) in &spec.loads {
        let e = ext.entry(*n).or_default();
        for k in 0..3 {
            e[k] += rec.load_factor * f[k];
            load2 += (rec.load_factor * f[k]).powi(2);
        }
    }
    // Distributed loads: half of each element's share on each of its nodes (a fixed load per
    // undeformed length, or a follower's along and across the current chord).
    for &(body, q, follower) in &spec.distributed {
        for &(_, i, j) in spec.elements.iter().filter(|e| e.0 == body) {
            let f = if follower {
                let (a, c) = (pos(i), pos(j));
                let d = [c[0] - a[0], c[1] - a[1]];
                [q[0] * d[0] - q[1] * d[1], q[0] * d[1] + q[1] * d[0]]
            } else {
                let (a, c) = (spec.coords[&i], spec.coords[&j]);
                let l0 = (c[0] - a[0]).hypot(c[1] - a[1]);
                [q[0] * l0, q[1] * l0]
            };
            for n in [i, j] {
                let e = ext.entry(n).or_default();
                for k in 0..2 {
                    e[k] += rec.load_factor * f[k] / 2.0;
                }
            }
            load2 += (rec.load_factor * f[0]).powi(2) + (rec.load_factor * f[1]).powi(2);
        }
    }
    for r in &rec.reactions {
        let k = match r.dof.as_str() {
            "u" => 0,
            "v" => 1,
            _ => 2,
        };
        ext.entry(r.node).or_default()[k] += r.value;
        reac2 += r.value * r.value;
    }
    // The largest EA of the scene, for the reference's floor: read from the scene text.
    let ea = section_ea(&spec.text);
    let reference = load2.sqrt().max(reac2.sqrt()).max(force_floor * ea);
    let r_bound = tol * reference;
    // Contact forces: Yc along the chord normal of the touched element, on the node; the
    // opposite force, on the same line, on the touched body.
    let group_of = |id: u32| spec.groups.iter().position(|g| g.contains(&id)).unwrap();
    let mut contact = vec![[0.0; 3]; spec.groups.len()];
    for c in &rec.contacts {
        let (body, i, j) = spec.elements[c.element];
        let (xi, xj, xc) = (pos(i), pos(j), pos(c.node));
        let (dx, dy) = (xj[0] - xi[0], xj[1] - xi[1]);
        let l = dx.hypot(dy);
        let f = [-dy / l * c.force, dx / l * c.force];
        let m = xc[0] * f[1] - xc[1] * f[0];
        let a = group_of(c.node);
        for (g, sign) in [(a, 1.0), (body, -1.0)] {
            contact[g][0] += sign * f[0];
            contact[g][1] += sign * f[1];
            contact[g][2] += sign * m;
        }
    }
    let dofs: usize = history_dofs(spec);
    let spread = (dofs as f64).sqrt();
    for (g, ids) in spec.groups.iter().enumerate() {
        // Moments about the group's centroid keep the lever arms small.
        let centre = ids.iter().fold([0.0, 0.0], |a, &n| {
            let p = pos(n);
            [
                a[0] + p[0] / ids.len() as f64,
                a[1] + p[1] / ids.len() as f64,
            ]
        });
        let mut sum = [0.0; 3];
        let mut size = 0.0f64;
        let mut arm2 = 0.0;
        for &n in ids {
            let p = pos(n);
            let (x, y) = (p[0] - centre[0], p[1] - centre[1]);
            arm2 += x * x + y * y + 1.0;
            if let Some(f) = ext.get(&n) {
                sum[0] += f[0];
                sum[1] += f[1];
                sum[2] += x * f[1] - y * f[0] + f[2];
                size = size.max(f[0].abs()).max(f[1].abs()).max(f[2].abs());
            }
        }
        // The contact forces' moment about the centre instead of the origin.
        let cm = contact[g][2] - (centre[0] * contact[g][1] - centre[1] * contact[g][0]);
        let unbalanced = [sum[0] - contact[g][0], sum[1] - contact[g][1], sum[2] - cm];
        size = size.max(contact[g][0].abs()).max(contact[g][1].abs());
        // Round-off of the sums themselves.
        let slack = 1e-12 * size * (1.0 + arm2.sqrt()) * ids.len() as f64;
        let force_bound = spread * r_bound + slack;
        let moment_bound = arm2.sqrt() * r_bound + slack;
        for (k, what) in ["x force", "y force", "moment"].iter().enumerate() {
            let bound = if k < 2 { force_bound } else { moment_bound };
            if unbalanced[k].abs() > bound || !unbalanced[k].is_finite() {
                return Some(format!(
                    "group {} ({} nodes from {}): unbalanced {what} {:e} above the bound {bound:e}",
                    g + 1,
                    ids.len(),
                    ids[0],
                    unbalanced[k]
                ));
            }
        }
    }
    None
}

/// Degrees of freedom of the scene (two or three per node), for the spread of sums.
fn history_dofs(spec: &Spec) -> usize {
    spec.groups
        .iter()
        .map(|g| if g.len() == 1 { 2 } else { 3 * g.len() })
        .sum()
}

/// E A of the scene's one section, read from its text.
fn section_ea(text: &str) -> f64 {
    let num = |key: &str| -> f64 {
        let at = text.find(key).unwrap() + key.len();
        let end = text[at..].find([',', ')']).unwrap();
        text[at..at + end].trim().parse().unwrap()
    };
    num("E: ") * num("A: ")
}

/// A candidate node that passes through an element of a body it is not in contact with,
/// between two accepted states, with everything moving linearly between them: clear of the
/// element on one side before, clear of it or of a neighbour it projects onto on the other side
/// after, having passed the chord's line between its ends. (A node that passes the line beyond
/// an end, or ends past a free end, went round it.) The element's
/// shape is the cubic its end rotations give against the chord; a node counts as clear of it
/// beyond `shape_margin`, which covers the shear and contact compliance the cubic leaves out.
fn crossing(
    spec: &Spec,
    before: &[[f64; 3]],
    after: &[[f64; 3]],
    active_before: &[(u32, usize)],
    active_after: &[(u32, usize)],
    slot: &dyn Fn(u32) -> usize,
) -> Option<String> {
    for &(node, body) in &spec.candidates {
        if active_before.contains(&(node, body)) || active_after.contains(&(node, body)) {
            continue;
        }
        for (e, &(b, ni, nj)) in spec.elements.iter().enumerate() {
            if b != body || ni == node || nj == node {
                continue;
            }
            let (c, i, j) = (slot(node), slot(ni), slot(nj));
            // (distance from the chord, fraction along it, chord length) at s of the increment.
            let place = |s: f64| {
                let at = |k: usize| {
                    [
                        before[k][0] + s * (after[k][0] - before[k][0]),
                        before[k][1] + s * (after[k][1] - before[k][1]),
                    ]
                };
                let (pc, pi, pj) = (at(c), at(i), at(j));
                let (dx, dy) = (pj[0] - pi[0], pj[1] - pi[1]);
                let l = dx.hypot(dy);
                let (ax, ay) = (pc[0] - pi[0], pc[1] - pi[1]);
                ((ay * dx - ax * dy) / l, (ax * dx + ay * dy) / (l * l), l)
            };
            // Distance from element f's shape at an accepted state, the fraction along its
            // chord, and the margin.
            let off_shape = |st: &[[f64; 3]], f: usize| {
                let (_, fi, fj) = spec.elements[f];
                let (p, q) = (spec.coords[&fi], spec.coords[&fj]);
                let alpha0 = (q[1] - p[1]).atan2(q[0] - p[0]);
                let (pi, pj, pc) = (st[slot(fi)], st[slot(fj)], st[c]);
                let (dx, dy) = (pj[0] - pi[0], pj[1] - pi[1]);
                let l = dx.hypot(dy);
                let (ax, ay) = (pc[0] - pi[0], pc[1] - pi[1]);
                let (h, x) = ((ay * dx - ax * dy) / l, (ax * dx + ay * dy) / (l * l));
                let beta = dy.atan2(dx);
                let turn = |phi: f64| {
                    let a = phi + alpha0 - beta + std::f64::consts::PI;
                    a.rem_euclid(std::f64::consts::TAU) - std::f64::consts::PI
                };
                let (ti, tj) = (turn(pi[2]), turn(pj[2]));
                let xc = x.clamp(0.0, 1.0);
                let w = l * (ti * xc * (1.0 - xc).powi(2) - tj * xc * xc * (1.0 - xc));
                (h - w, x, shape_margin(l, ti, tj))
            };
            // Clear of e on one side before; after, clear of e or of a neighbour it projects
            // onto, on the other side (the body's elements all run the same way).
            let (d0, _, m0) = off_shape(before, e);
            let neighbours = (e.saturating_sub(1)..=e + 1)
                .filter(|&f| f < spec.elements.len() && spec.elements[f].0 == body);
            let through = neighbours
                .map(|f| off_shape(after, f))
                .find(|&(d1, x1, m1)| {
                    (0.0..=1.0).contains(&x1) && d1.abs() > m1 && d1.signum() != d0.signum()
                });
            let Some((d1, _, _)) = through else { continue };
            if d0.abs() <= m0 {
                continue;
            }
            let mut last = place(0.0);
            for step in 1..=SWEEP {
                let s = step as f64 / SWEEP as f64;
                let next = place(s);
                if last.0 * next.0 <= 0.0 && last.0 != next.0 {
                    let t = last.0 / (last.0 - next.0);
                    let along = last.1 + t * (next.1 - last.1);
                    if (0.0..=1.0).contains(&along) {
                        return Some(format!(
                            "node {node} passes through element {} ({ni}-{nj}) of body {} at {along:.3} of its length, from {d0:e} to {d1:e} off its shape",
                            e + 1,
                            body + 1
                        ));
                    }
                }
                last = next;
            }
        }
    }
    None
}

/// How far off an element's cubic shape a node may lie and still count as touching it: 1e-9
/// of the length, plus a twentieth of the cubic's own reach (shear and the contact compliance).
fn shape_margin(l: f64, ti: f64, tj: f64) -> f64 {
    l * (1e-9 + 0.05 * (ti.abs() + tj.abs()))
}
