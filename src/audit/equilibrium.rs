//! Equilibrium from the recorded forces: every connected group of nodes (a body or a chain of
//! bodies sharing nodes, a lone pin, an obstacle's pilot) is in balance under its loads, its
//! reactions and the contact forces on it, to the bound the increment's stated tolerance gives.
//! The element forces cancel within a group, so the sums need no element code.

use std::collections::HashMap;

use crate::history::Topology;
use crate::solver::{Friction, IncrementRecord, IncrementStatus, SolverParams};

/// The external and contact forces of one record, by node slot, and the reference force.
struct Forces {
    /// Force (x, y) and moment on each node slot.
    on: Vec<[f64; 3]>,
    /// Force (x, y) applied at a point, by group, with the point (contact forces).
    at_points: Vec<Vec<([f64; 2], [f64; 2])>>,
    /// The reference: the norm of the loads on free dofs, of the held dofs' internal forces
    /// (reaction plus load there), and the force floor.
    reference: f64,
    /// What the round-off of the positions makes of the contact forces' directions (N): a
    /// chord's direction from positions of size X is uncertain by 64 eps X / l.
    slack: f64,
}

/// The groups of node slots joined by elements; a node on no element is a group of its own.
pub fn groups(topology: &Topology, slot: &HashMap<u32, usize>, nodes: usize) -> Vec<usize> {
    let mut parent: Vec<usize> = (0..nodes).collect();
    fn root(p: &mut [usize], mut k: usize) -> usize {
        while p[k] != k {
            p[k] = p[p[k]];
            k = p[k];
        }
        k
    }
    for e in &topology.elements {
        let (a, b) = (root(&mut parent, slot[&e.i]), root(&mut parent, slot[&e.j]));
        parent[a] = b;
    }
    (0..nodes).map(|k| root(&mut parent, k)).collect()
}

/// The first group out of balance in `r`, as a message.
pub fn unbalanced(
    topology: &Topology,
    params: &SolverParams,
    slot: &HashMap<u32, usize>,
    group: &[usize],
    r: &IncrementRecord,
) -> Option<String> {
    let tol = match r.status {
        IncrementStatus::Converged => params.tolerance,
        IncrementStatus::RoundOff { .. } => params.roundoff_bound.max(params.tolerance),
        // A state of a snap is out of balance by its viscous force: by no more than it says.
        IncrementStatus::Snapping { residual } => residual.max(params.tolerance) * (1.0 + 1e-9),
    };
    let f = forces(topology, params, slot, group, r);
    let dofs = 3.0 * r.nodes.len() as f64;
    let bound = dofs.sqrt() * tol * f.reference;
    let pilots: Vec<usize> = (topology.obstacles.iter())
        .filter_map(|o| o.pilot.and_then(|p| slot.get(&p)).map(|&s| group[s]))
        .collect();
    let mut roots: Vec<usize> = group.to_vec();
    roots.sort_unstable();
    roots.dedup();
    for g in roots {
        let members: Vec<usize> = (0..group.len()).filter(|&k| group[k] == g).collect();
        let n = members.len() as f64;
        let centre = members.iter().fold([0.0, 0.0], |c, &k| {
            [c[0] + r.nodes[k][0] / n, c[1] + r.nodes[k][1] / n]
        });
        let (mut sum, mut size, mut arm) = ([0.0; 3], 0.0f64, 1.0f64);
        let mut add = |p: [f64; 2], v: [f64; 3]| {
            let (x, y) = (p[0] - centre[0], p[1] - centre[1]);
            sum[0] += v[0];
            sum[1] += v[1];
            sum[2] += x * v[1] - y * v[0] + v[2];
            size = size.max(v[0].abs()).max(v[1].abs()).max(v[2].abs());
            arm = arm.max(x.hypot(y));
        };
        for &k in &members {
            add([r.nodes[k][0], r.nodes[k][1]], f.on[k]);
        }
        for &(p, v) in &f.at_points[g] {
            add(p, [v[0], v[1], 0.0]);
        }
        // Round-off of the sums themselves, and of the contact forces' directions.
        let slack =
            1e-12 * size * arm * (members.len() + f.at_points[g].len()) as f64 + f.slack * arm;
        // An obstacle turns with nothing: its pilot holds no moment.
        let checks = if pilots.contains(&g) { 2 } else { 3 };
        for (k, what) in ["x force", "y force", "moment"]
            .iter()
            .enumerate()
            .take(checks)
        {
            let b = if k < 2 { bound } else { arm * bound } + slack;
            // Within the bound (a NaN sum is not).
            let within = matches!(
                sum[k].abs().partial_cmp(&b),
                Some(std::cmp::Ordering::Less | std::cmp::Ordering::Equal)
            );
            if !within {
                let first = topology.nodes.get(members[0]).map_or(0, |nd| nd.id);
                return Some(format!(
                    "the group of {} node(s) from node {first} is out of balance: {what} {:.3e} above the bound {b:.3e} (tolerance {tol:.0e} of the reference {:.3e})",
                    members.len(),
                    sum[k],
                    f.reference
                ));
            }
        }
    }
    None
}

/// The loads, reactions and contact forces of record `r`.
fn forces(
    topology: &Topology,
    params: &SolverParams,
    slot: &HashMap<u32, usize>,
    group: &[usize],
    r: &IncrementRecord,
) -> Forces {
    let n = r.nodes.len();
    // A load's factor: its group's where the record carries one per group.
    let lam = |group: usize| r.load_factors.get(group).copied().unwrap_or(r.load_factor);
    let mut on = vec![[0.0; 3]; n];
    let mut at_points = vec![Vec::new(); n];
    let dof = |d: &str| super::geometry::dof_place(d).unwrap_or(2);
    let held: std::collections::HashSet<(u32, usize)> =
        topology.held.iter().map(|(n, d)| (*n, dof(d))).collect();
    let (mut free2, mut held_at): (f64, HashMap<(u32, usize), f64>) = (0.0, HashMap::new());
    for l in &topology.loads {
        let at = slot[&l.node];
        for (k, f) in l.force.iter().enumerate() {
            let v = lam(l.group) * f;
            on[at][k] += v;
            if held.contains(&(l.node, k)) {
                *held_at.entry((l.node, k)).or_default() += v;
            } else {
                free2 += v * v;
            }
        }
    }
    let pos = |id: u32| {
        let p = r.nodes[slot[&id]];
        [p[0], p[1]]
    };
    let rest: HashMap<u32, [f64; 2]> = topology.nodes.iter().map(|n| (n.id, [n.x, n.y])).collect();
    // The angle from element (i, j)'s chord to the beam's surface at fraction xi: each end's
    // rotation relative to the chord, interpolated linearly, within 45 degrees. The chord's
    // turn since rest is taken on the branch nearest the mean of the end rotations.
    let surface_turn = |i: u32, j: u32, xi: f64| {
        let (a, b, ra, rb) = (pos(i), pos(j), rest[&i], rest[&j]);
        let (pi, pj) = (r.nodes[slot[&i]][2], r.nodes[slot[&j]][2]);
        let turned = (b[1] - a[1]).atan2(b[0] - a[0]) - (rb[1] - ra[1]).atan2(rb[0] - ra[0]);
        let tau = std::f64::consts::TAU;
        let mean = 0.5 * (pi + pj);
        let chord = turned + tau * ((mean - turned) / tau).round();
        let quarter = std::f64::consts::FRAC_PI_4;
        ((1.0 - xi) * (pi - chord) + xi * (pj - chord)).clamp(-quarter, quarter)
    };
    for d in &topology.distributed {
        let e = &topology.elements[d.element];
        let (a, b) = (pos(e.i), pos(e.j));
        // Consistent nodal shares of a linearly varying load: (2 qi + qj) l / 6 and
        // (qi + 2 qj) l / 6, placed at the nodes of the current chord.
        let (qi, qj) = if d.follower {
            let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
            let turn = |q: [f64; 2]| [q[0] * dx - q[1] * dy, q[0] * dy + q[1] * dx];
            (turn(d.q[0]), turn(d.q[1]))
        } else {
            let (ra, rb) = (rest[&e.i], rest[&e.j]);
            let l0 = (rb[0] - ra[0]).hypot(rb[1] - ra[1]);
            (
                [d.q[0][0] * l0, d.q[0][1] * l0],
                [d.q[1][0] * l0, d.q[1][1] * l0],
            )
        };
        for k in 0..2 {
            let fi = lam(d.group) * (2.0 * qi[k] + qj[k]) / 6.0;
            let fj = lam(d.group) * (qi[k] + 2.0 * qj[k]) / 6.0;
            on[slot[&e.i]][k] += fi;
            on[slot[&e.j]][k] += fj;
            free2 += fi * fi + fj * fj;
        }
    }
    let mut held2 = 0.0;
    for re in &r.reactions {
        let k = dof(&re.dof);
        on[slot[&re.node]][k] += re.value;
        let internal = re.value + held_at.get(&(re.node, k)).copied().unwrap_or(0.0);
        held2 += internal * internal;
    }
    let scale = r
        .nodes
        .iter()
        .fold(0.0f64, |m, p| m.max(p[0].abs()).max(p[1].abs()));
    let mut slack = 0.0;
    // Which node slots turn with a moment: a node with a rotation on an element or held in
    // it. A 2-dof pin (a rigid circle's centre) does not: what holds it holds the moment of a
    // friction at its rim (and so for a node of a history that does not say, on no element).
    let turns: Vec<bool> = {
        let mut t = vec![false; n];
        for e in &topology.elements {
            for id in [e.i, e.j] {
                if let Some(&k) = slot.get(&id) {
                    t[k] = true;
                }
            }
        }
        for node in &topology.nodes {
            if let Some(&k) = slot.get(&node.id) {
                t[k] = node.rotation && (t[k] || held.contains(&(node.id, 2)));
            }
        }
        t
    };
    let clearance: HashMap<u32, f64> = (topology.nodes.iter())
        .map(|node| (node.id, node.clearance))
        .collect();
    for c in &r.contacts {
        let e = &topology.elements[c.element];
        let (a, b) = (pos(e.i), pos(e.j));
        let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
        let l = dx.hypot(dy);
        // Yc is the force on the beam along its chord's left normal: the node takes -Yc
        // there, and the friction force along the chord from end i to end j. Normal to the
        // surface, the frictionless force leans along the chord by Yc tan(t).
        let along = if params.surface_normal {
            let turn = surface_turn(e.i, e.j, c.xi);
            c.tangential + c.force * turn.tan()
        } else {
            c.tangential
        };
        slack += c.force.hypot(along) * 64.0 * f64::EPSILON * scale / l;
        let f = [
            (dy * c.force + dx * along) / l,
            (-dx * c.force + dy * along) / l,
        ];
        let s = slot[&c.node];
        on[s][0] += f[0];
        on[s][1] += f[1];
        // On the beam where it presses: the node, or the point of the axis under a node
        // that stands off it; with friction, where the faces touch, the beam's half
        // thickness from its axis towards the node (and the node turns with the friction
        // there, if it can turn).
        let x = pos(c.node);
        let mut at = c.point.unwrap_or(x);
        if c.point.is_some() && c.friction != Friction::Frictionless {
            let arm = [x[0] - at[0], x[1] - at[1]];
            let reach = arm[0].hypot(arm[1]);
            let share = if reach > 0.0 {
                0.5 * e.thickness / reach
            } else {
                0.0
            };
            at = [at[0] + share * arm[0], at[1] + share * arm[1]];
            if turns[s] {
                let to = [at[0] - x[0], at[1] - x[1]];
                on[s][2] += to[0] * f[1] - to[1] * f[0];
            }
        }
        at_points[group[slot[&e.i]]].push((at, [-f[0], -f[1]]));
    }
    for c in &r.obstacle_contacts {
        let t = [c.normal[1], -c.normal[0]];
        let f = [
            c.force * c.normal[0] + c.tangential * t[0],
            c.force * c.normal[1] + c.tangential * t[1],
        ];
        // It acts where the node's face touches the obstacle: off the node by the node's
        // radius and half thickness, its friction there turns the node (one that turns).
        let s = slot[&c.node];
        let x = pos(c.node);
        let arm = [c.point[0] - x[0], c.point[1] - x[1]];
        on[s][0] += f[0];
        on[s][1] += f[1];
        let rim = clearance.get(&c.node).copied().unwrap_or(0.0) > 0.0;
        if turns[s] && rim && c.friction != Friction::Frictionless {
            on[s][2] += arm[0] * f[1] - arm[1] * f[0];
        }
        let pilot = (topology.obstacles.iter())
            .find(|o| o.name == c.obstacle)
            .and_then(|o| o.pilot);
        if let Some(p) = pilot {
            at_points[group[slot[&p]]].push((c.point, [-f[0], -f[1]]));
        }
    }
    let ea = topology.elements.iter().fold(0.0f64, |m, e| m.max(e.ea));
    Forces {
        on,
        at_points,
        reference: free2
            .sqrt()
            .max(held2.sqrt())
            .max(params.force_floor * ea.max(f64::MIN_POSITIVE)),
        slack,
    }
}
