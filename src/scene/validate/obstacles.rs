//! The `obstacles` of a scene: each a named curve (line, polyline, circle or arc) with the
//! nodes that may touch it (every node of the named bodies, and nodes by id) and, if it moves,
//! its pilot node, whose u and v must be supported or prescribed. No candidate node may start
//! inside its obstacle.

use std::collections::HashSet;

use super::errors::{sized, Ctx, SceneError};
use super::geometry::Geometry;
use crate::scene::format::{ObstacleDef, SceneFile, ShapeDef};
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
        let field = format!("obstacles[{k}] (obstacle \"{}\")", o.name);
        let leaf = |n: &str| format!("obstacles[{k}].{n} (obstacle \"{}\")", o.name);
        let here = Some(format!("name: \"{}\"", o.name));
        if o.name.trim().is_empty() || !names.insert(o.name.as_str()) {
            return Err(ctx.err(
                format!("obstacles[{k}].name"),
                here,
                format!("\"{}\" is empty or names another obstacle too", o.name),
            ));
        }
        let shape = shape(&o.shape).map_err(|m| ctx.err(leaf("shape"), here.clone(), m))?;
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
            Some(id) => Some(pilot(ctx, g, &leaf("pilot"), id, held)?),
        };
        nodes.retain(|&n| Some(n) != pilot);
        if nodes.is_empty() {
            return Err(ctx.err(field, here, "no node may touch it: name bodies or nodes"));
        }
        for &n in &nodes {
            let node = &g.nodes[n];
            // Its face, at its clearance (radius, half thickness) from it.
            let gap = shape.gap([node.x, node.y]).map_or(0.0, |gap| gap.g) - node.clearance;
            if gap < -START_INSIDE * size {
                let face = if node.clearance > 0.0 {
                    format!(" (its face, {:e} m from it)", node.clearance)
                } else {
                    String::new()
                };
                return Err(ctx.err(
                    field,
                    here,
                    format!(
                        "node {}{face} starts {:.3e} inside it: every node that may touch an obstacle starts on its free side",
                        node.id, -gap
                    ),
                ));
            }
        }
        if let Some((e, depth)) = chord_through(&shape, o, g) {
            let b = &g.bodies[g.beams[e].body];
            let place = b.elements.iter().position(|&x| x == e).map_or(0, |p| p + 1);
            return Err(ctx.err(
                field,
                here,
                format!(
                    "element {place} of body {} passes {depth:.3e} through it between its nodes: \
                     the body must start on its free side (mesh finer there, or move it)",
                    b.name
                ),
            ));
        }
        if !(sized(o.mu) && o.mu >= 0.0) {
            return Err(ctx.err(
                leaf("mu"),
                here,
                format!(
                    "the friction coefficient is {:e}: it must be finite, >= 0 and below 1e100",
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

/// The pilot node `id` named in `field` (an obstacle's `pilot`): a node with u and v held.
fn pilot(
    ctx: &Ctx,
    g: &Geometry,
    field: &str,
    id: u32,
    (supports, prescribed): (&[Support], &[Prescribed]),
) -> Result<usize, SceneError> {
    let n = g.node_of(ctx, field.to_string(), id)?;
    let held = |dof: Dof| {
        supports.iter().any(|s| s.node == n && s.dof == dof)
            || prescribed.iter().any(|p| p.node == n && p.dof == dof)
    };
    if !(held(Dof::U) && held(Dof::V)) {
        return Err(ctx.err(
            field.to_string(),
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
                return Err(
                    "a line needs two different points, finite and below 1e100 in size".into(),
                );
            }
            Ok(Shape::Line {
                from: pt(*from),
                to: pt(*to),
            })
        }
        ShapeDef::Polyline { points } => {
            let flat: Vec<f64> = points.iter().flat_map(|p| [p.0, p.1]).collect();
            if points.len() < 2 || !finite(&flat) {
                return Err(
                    "a polyline needs at least two points, finite and below 1e100 in size".into(),
                );
            }
            // Two points in a row closer than the round-off of their coordinates make a segment
            // with no direction; a segment that turns straight back makes a spike with no free
            // side.
            let scale = flat.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            let seg = |k: usize| [points[k + 1].0 - points[k].0, points[k + 1].1 - points[k].1];
            let len = |d: [f64; 2]| d[0].hypot(d[1]);
            if let Some(k) = (0..points.len() - 1).find(|&k| len(seg(k)) <= 1e-12 * scale) {
                return Err(format!(
                    "points {} and {} of the polyline are the same to round-off",
                    k + 1,
                    k + 2
                ));
            }
            if let Some(k) = (1..points.len() - 1).find(|&k| {
                let (a, b) = (seg(k - 1), seg(k));
                let cross = a[0] * b[1] - a[1] * b[0];
                let dot = a[0] * b[0] + a[1] * b[1];
                dot < 0.0 && cross.abs() <= 1e-9 * len(a) * len(b)
            }) {
                return Err(format!(
                    "the polyline folds straight back on itself at point {}",
                    k + 1
                ));
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
                return Err(
                    "a circle needs a centre and a positive radius, finite and below 1e100 in size"
                        .into(),
                );
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
                    "an arc needs a centre, a positive radius and two different angles, finite and below 1e100 in size"
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

/// An element of a body that may touch obstacle `o` (a solid circle) whose chord passes through
/// the disk between its two nodes, both clear of it: the element and how deep its chord goes.
fn chord_through(shape: &Shape, o: &ObstacleDef, g: &Geometry) -> Option<(usize, f64)> {
    let Shape::Circle {
        centre,
        radius,
        hollow: false,
    } = *shape
    else {
        return None;
    };
    let bodies = (o.bodies.iter()).filter_map(|name| g.body_index.get(name.as_str()));
    let elements = bodies.flat_map(|&b| g.bodies[b].elements.iter().copied());
    elements
        .filter_map(|e| {
            let (p, q) = (&g.nodes[g.beams[e].i], &g.nodes[g.beams[e].j]);
            let (dx, dy) = (q.x - p.x, q.y - p.y);
            let l2 = dx * dx + dy * dy;
            let t = (((centre[0] - p.x) * dx + (centre[1] - p.y) * dy) / l2).clamp(0.0, 1.0);
            let (cx, cy) = (p.x + t * dx - centre[0], p.y + t * dy - centre[1]);
            let depth = radius - cx.hypot(cy);
            // Nodes resting on the disk (a band laid round a drum) touch it at the nodes, where
            // contact acts: their chords dip inside by the sagitta, as they must.
            let clear =
                |x: f64, y: f64| (x - centre[0]).hypot(y - centre[1]) - radius > 1e-9 * radius;
            let through = clear(p.x, p.y) && clear(q.x, q.y) && t > 0.0 && t < 1.0;
            (through && depth > 1e-9 * radius).then_some((e, depth))
        })
        .next()
}
