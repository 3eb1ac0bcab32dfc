//! The contacts of nodes with rigid obstacles in the assembly: where a node lies against an
//! obstacle that its pilot node has moved (`obstacle_gap`), and the adds of the force and
//! tangent of every active candidate pair (`add_obstacles`), made before the elements' so that
//! no equation is settled before they reach it.

use super::dofs::{DofMap, Ordering};
use super::internal::{add_element, Sink};
use crate::solver::element::friction::{obstacle_friction, ObstacleGrip, Traction};
use crate::solver::element::obstacle::{obstacle_response, Gap};
use crate::solver::model::Model;

/// A node that may touch a rigid obstacle, with the multiplier of its augmented Lagrangian
/// (the normal force it carries at a closed gap; 0 while it does not touch).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ObstacleLink {
    /// Node index.
    pub node: usize,
    /// Obstacle index.
    pub obstacle: usize,
    /// Multiplier (N).
    pub multiplier: f64,
    /// Whether the pair is in contact in the current pass (its force and tangent assembled).
    pub active: bool,
    /// Its friction while in contact (stick point and mode; `None`: frictionless).
    pub grip: Option<ObstacleGrip>,
}

/// How far obstacle `o`'s pilot node has moved it at displacements `d`.
pub fn obstacle_offset(model: &Model, dofs: &DofMap, d: &[f64], o: usize) -> [f64; 2] {
    match model.obstacles[o].pilot {
        Some(p) => {
            let f = dofs.first[p];
            [d[f], d[f + 1]]
        }
        None => [0.0, 0.0],
    }
}

/// Where node `n` lies against obstacle `o` at displacements `d` (`None`: out of its reach),
/// with the nearest point of the obstacle and the normal in the model's coordinates. The gap
/// is the node's surface's: its distance from the obstacle less its clearance (a pin's radius,
/// half a beam's thickness), so that the node's face touches where the gap closes.
pub fn obstacle_gap(model: &Model, dofs: &DofMap, d: &[f64], n: usize, o: usize) -> Option<Gap> {
    let t = obstacle_offset(model, dofs, d, o);
    let f = dofs.first[n];
    // The node's motion relative to the obstacle, apart from where it starts (`Shape::gap_at`).
    let w = [d[f] - t[0], d[f + 1] - t[1]];
    let x0 = model.position(n);
    let mut gap = model.obstacles[o].shape.gap_at(x0, w)?;
    gap.point = [gap.point[0] + t[0], gap.point[1] + t[1]];
    gap.g -= model.nodes[n].clearance;
    Some(gap)
}

/// Add the forces and tangents of the active pairs of `links` at penalty `penalty` (N/m) and
/// displacements `d`, their friction included; returns each pair's normal force
/// `multiplier - penalty g` (negative: tensile), 0 for an inactive pair and minus infinity for
/// an active one out of its obstacle's reach (an arc's node outside its angle range), which
/// adds nothing; and each pair's friction (`None`: none).
#[allow(clippy::too_many_arguments)]
pub(super) fn add_obstacles(
    model: &Model,
    dofs: &DofMap,
    ord: &Ordering,
    links: &[ObstacleLink],
    penalty: f64,
    d: &[f64],
    with_tangent: bool,
    dp: Option<&[f64]>,
    (forces, frictions): (&mut Vec<f64>, &mut Vec<Option<Traction>>),
    Sink {
        internal,
        held,
        tangent: mut band,
        coupling,
    }: Sink,
) {
    forces.clear();
    frictions.clear();
    let (mut gdofs, mut places) = (Vec::with_capacity(5), Vec::with_capacity(5));
    for link in links {
        if !link.active {
            forces.push(0.0);
            frictions.push(None);
            continue;
        }
        let Some(gap) = obstacle_gap(model, dofs, d, link.node, link.obstacle) else {
            forces.push(f64::NEG_INFINITY);
            frictions.push(None);
            continue;
        };
        let (f, normal_nodal, normal_k) = obstacle_response(&gap, link.multiplier, penalty);
        forces.push(f);
        let (mut nodal, mut k) = ([0.0; 5], [[0.0; 5]; 5]);
        for a in 0..4 {
            nodal[a] = normal_nodal[a];
            k[a][..4].copy_from_slice(&normal_k[a]);
        }
        let rotation = (model.nodes[link.node].rotation).then(|| dofs.dof(link.node, 2));
        frictions.push(link.grip.map(|grip| {
            let shape = &model.obstacles[link.obstacle].shape;
            let t = obstacle_offset(model, dofs, d, link.obstacle);
            let place = shape.place([gap.point[0] - t[0], gap.point[1] - t[1]]);
            let phi = rotation.map_or(0.0, |r| d[r]);
            let (traction, fnodal, fk) = obstacle_friction(&gap, (place, phi), (f, penalty), &grip);
            for a in 0..5 {
                nodal[a] += fnodal[a];
                for b in 0..5 {
                    k[a][b] += fk[a][b];
                }
            }
            traction
        }));
        // The dofs in the order of `nodal`: the node's (u, v), the pilot's, and the node's
        // rotation where its rim rolls under friction.
        gdofs.clear();
        places.clear();
        gdofs.extend((0..2).map(|o| dofs.dof(link.node, o)));
        places.extend([0, 1]);
        let pilot = model.obstacles[link.obstacle].pilot;
        if let Some(p) = pilot {
            gdofs.extend((0..2).map(|o| dofs.dof(p, o)));
            places.extend([2, 3]);
        }
        if let Some(r) = rotation.filter(|_| link.grip.is_some_and(|g| g.reach > 0.0)) {
            gdofs.push(r);
            places.push(4);
        }
        let mut local = [0.0; 5];
        for (l, &a) in local.iter_mut().zip(&places) {
            *l = nodal[a];
        }
        let at = &places;
        let k = with_tangent.then_some(move |a: usize, b: usize| k[at[a]][at[b]]);
        let sink = Sink {
            internal: &mut *internal,
            held: (held.0, &mut *held.1),
            tangent: band.as_deref_mut(),
            coupling: &mut *coupling,
        };
        add_element(&gdofs, &local[..places.len()], k, ord, dofs, dp, sink);
    }
}
