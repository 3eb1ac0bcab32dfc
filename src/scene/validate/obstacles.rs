//! The `obstacles` of a scene: each a named curve (line, polyline, circle or arc) with the
//! nodes that may touch it (every node of the named bodies, and nodes by id) and, if it moves,
//! its pilot node, whose u and v must be supported or prescribed. No candidate node may start
//! inside its obstacle.

use std::collections::HashSet;

use super::errors::{sized, Ctx, SceneError};
use super::geometry::Geometry;
use crate::scene::format::{SceneFile, ShapeDef};
use crate::solver::{Dof, Obstacle, Prescribed, Shape, Support};

/// How far inside its obstacle (in units of the model's size) a candidate node may start:
/// round-off of a node placed on the curve, no more.
const START_INSIDE: f64 = 1e-9;

/// The obstacles of `sf` on geometry `g`, with the supports and prescribed displacements that
/// hold their pilots.
pub(super) fn obstacles(
    ctx: &Ctx,
    sf: &SceneFile,
    g: &Geometry,
    held: (&[Support], &[Prescribed]),
) -> Result<Vec<Obstacle>, SceneError> {
    let mut out = Vec::new();
    let mut names = HashSet::new();
    let size = model_size(g);
    for (k, o) in sf.obstacles.iter().enumerate() {
        let field = format!("obstacles[{k}] ({})", o.name);
        let here = Some(format!("name: \"{}\"", o.name));
        if o.name.trim().is_empty() || !names.insert(o.name.as_str()) {
            return Err(ctx.err(
                format!("obstacles[{k}].name"),
                here,
                format!("\"{}\" is empty or names another obstacle too", o.name),
            ));
        }
        let shape =
            shape(&o.shape).map_err(|m| ctx.err(format!("{field}.shape"), here.clone(), m))?;
        let mut nodes = Vec::new();
        for (m, name) in o.bodies.iter().enumerate() {
            let b = g.body_of(ctx, format!("obstacles[{k}].bodies[{m}]"), name)?;
            for &e in &g.bodies[b].elements {
                nodes.extend([g.beams[e].i, g.beams[e].j]);
            }
        }
        for (m, &id) in o.nodes.iter().enumerate() {
            nodes.push(g.node_of(ctx, format!("obstacles[{k}].nodes[{m}]"), id)?);
        }
        nodes.sort_unstable();
        nodes.dedup();
        let pilot = match o.pilot {
            None => None,
            Some(id) => Some(pilot(ctx, g, &field, id, held)?),
        };
        nodes.retain(|&n| Some(n) != pilot);
        if nodes.is_empty() {
            return Err(ctx.err(field, here, "no node may touch it: name bodies or nodes"));
        }
        for &n in &nodes {
            let node = &g.nodes[n];
            let gap = shape.gap([node.x, node.y]).map_or(0.0, |gap| gap.g);
            if gap < -START_INSIDE * size {
                return Err(ctx.err(
                    field,
                    here,
                    format!(
                        "node {} starts {:.3e} inside it: every node that may touch an obstacle starts on its free side",
                        node.id, -gap
                    ),
                ));
            }
        }
        if !(o.mu.is_finite() && o.mu >= 0.0) {
            return Err(ctx.err(
                format!("obstacles[{k}].mu"),
                here,
                format!(
                    "the friction coefficient is {}: it must be a finite number >= 0",
                    o.mu
                ),
            ));
        }
        out.push(Obstacle {
            name: o.name.clone(),
            shape,
            pilot,
            nodes,
            mu: o.mu,
        });
    }
    Ok(out)
}

/// The pilot node `id` of obstacle `field`: a node with u and v held.
fn pilot(
    ctx: &Ctx,
    g: &Geometry,
    field: &str,
    id: u32,
    (supports, prescribed): (&[Support], &[Prescribed]),
) -> Result<usize, SceneError> {
    let n = g.node_of(ctx, format!("{field}.pilot"), id)?;
    let held = |dof: Dof| {
        supports.iter().any(|s| s.node == n && s.dof == dof)
            || prescribed.iter().any(|p| p.node == n && p.dof == dof)
    };
    if !(held(Dof::U) && held(Dof::V)) {
        return Err(ctx.err(
            format!("{field}.pilot"),
            Some(format!("pilot: {id}")),
            format!("node {id} moves the obstacle, so its u and v must be supported or prescribed"),
        ));
    }
    Ok(n)
}

/// The larger side of the bounding box of the nodes.
fn model_size(g: &Geometry) -> f64 {
    let (mut lo, mut hi) = ([f64::MAX; 2], [f64::MIN; 2]);
    for n in &g.nodes {
        lo = [lo[0].min(n.x), lo[1].min(n.y)];
        hi = [hi[0].max(n.x), hi[1].max(n.y)];
    }
    (hi[0] - lo[0]).max(hi[1] - lo[1]).max(0.0)
}

/// The solver's shape of `def`, or what is wrong with it.
fn shape(def: &ShapeDef) -> Result<Shape, String> {
    let pt = |p: (f64, f64)| [p.0, p.1];
    let finite = |v: &[f64]| v.iter().all(|&x| sized(x));
    match def {
        ShapeDef::Line { from, to } => {
            if !finite(&[from.0, from.1, to.0, to.1]) || from == to {
                return Err("a line needs two different finite points".into());
            }
            Ok(Shape::Line {
                from: pt(*from),
                to: pt(*to),
            })
        }
        ShapeDef::Polyline { points } => {
            let flat: Vec<f64> = points.iter().flat_map(|p| [p.0, p.1]).collect();
            if points.len() < 2 || !finite(&flat) || points.windows(2).any(|w| w[0] == w[1]) {
                return Err(
                    "a polyline needs at least two finite points, no two in a row the same".into(),
                );
            }
            Ok(Shape::Polyline {
                points: points.iter().map(|&p| pt(p)).collect(),
            })
        }
        ShapeDef::Circle {
            centre,
            radius,
            hollow,
        } => {
            if !finite(&[centre.0, centre.1, *radius]) || *radius <= 0.0 {
                return Err("a circle needs a finite centre and a positive radius".into());
            }
            Ok(Shape::Circle {
                centre: pt(*centre),
                radius: *radius,
                hollow: *hollow,
            })
        }
        ShapeDef::Arc {
            centre,
            radius,
            from_deg,
            to_deg,
            hollow,
        } => {
            let ok = finite(&[centre.0, centre.1, *radius, *from_deg, *to_deg]);
            if !ok || *radius <= 0.0 || (to_deg - from_deg).rem_euclid(360.0) == 0.0 {
                return Err(
                    "an arc needs a finite centre, a positive radius and two different angles"
                        .into(),
                );
            }
            Ok(Shape::Arc {
                centre: pt(*centre),
                radius: *radius,
                from: from_deg.to_radians(),
                to: to_deg.to_radians(),
                hollow: *hollow,
            })
        }
    }
}
