//! The distributed loads of a scene: each `distributed` entry on a body's elements (all of
//! them, or a range), uniform or varying linearly from its first element's start to its last
//! element's end, per unit of undeformed length in fixed directions, or per unit of current
//! length along and across the deformed chord (`follower`); and the self-weight of every body
//! whose section has a `density`, under `control.gravity`.

use super::errors::{sized, Ctx, SceneError};
use super::geometry::Geometry;
use super::stages::{group_index, GRAVITY_GROUP};
use crate::scene::format::SceneFile;
use crate::solver::DistributedLoad;

/// The distributed loads of `sf` on geometry `g`, element by element.
pub(super) fn distributed(
    ctx: &Ctx,
    sf: &SceneFile,
    g: &Geometry,
    groups: &[String],
) -> Result<Vec<DistributedLoad>, SceneError> {
    let mut out = Vec::new();
    for (k, d) in sf.distributed.iter().enumerate() {
        let leaf = |n: &str| format!("distributed[{k}].{n} (body \"{}\")", d.body);
        let b = *g.body_index.get(d.body.as_str()).ok_or_else(|| {
            ctx.err(
                format!("distributed[{k}].body"),
                Some(format!("body: \"{}\"", d.body)),
                format!("no body named \"{}\"", d.body),
            )
        })?;
        let elements = &g.bodies[b].elements;
        let (first, last) = d.elements.unwrap_or((1, elements.len()));
        if first < 1 || last < first || last > elements.len() {
            return Err(ctx.err(
                leaf("elements"),
                Some("elements".into()),
                format!(
                    "({first}, {last}) is not a range of the body's elements 1 to {}",
                    elements.len()
                ),
            ));
        }
        if d.follower && sf.control.arc_length.is_some() {
            return Err(ctx.err(
                leaf("follower"),
                Some("follower".into()),
                "follower loads cannot be traced by arc length (the reference load would turn \
                 with the structure): use load control",
            ));
        }
        let q0 = [d.q.0, d.q.1];
        let q1 = d.q_end.map_or(q0, |q| [q.0, q.1]);
        for (key, q) in [("q", q0), ("q_end", q1)] {
            if !q.iter().all(|&v| sized(v)) {
                return Err(ctx.err(
                    leaf(key),
                    Some(key.into()),
                    "must be finite and below 1e100 in size",
                ));
            }
        }
        // The load varies linearly with the arc length along the range.
        let range = &elements[first - 1..last];
        let lengths: Vec<f64> = range.iter().map(|&e| length(g, e)).collect();
        let total: f64 = lengths.iter().sum();
        let at = |s: f64| {
            let t = if total > 0.0 { s / total } else { 0.0 };
            [q0[0] + t * (q1[0] - q0[0]), q0[1] + t * (q1[1] - q0[1])]
        };
        let mut s = 0.0;
        for (&e, l) in range.iter().zip(&lengths) {
            out.push(DistributedLoad {
                beam: e,
                q: [at(s), at(s + l)],
                follower: d.follower,
                group: group_index(groups, d.group.as_deref()),
            });
            s += l;
        }
    }
    self_weight(
        ctx,
        sf,
        g,
        group_index(groups, Some(GRAVITY_GROUP)),
        &mut out,
    )?;
    // By element (`Model::distributed_on` looks them up so).
    out.sort_by_key(|d| d.beam);
    Ok(out)
}

/// Undeformed length of element `e`.
fn length(g: &Geometry, e: usize) -> f64 {
    let b = &g.beams[e];
    let (p, q) = (&g.nodes[b.i], &g.nodes[b.j]);
    (q.x - p.x).hypot(q.y - p.y)
}

/// The self-weight density A g of every body whose section has a density, in load group
/// `group`.
fn self_weight(
    ctx: &Ctx,
    sf: &SceneFile,
    g: &Geometry,
    group: usize,
    out: &mut Vec<DistributedLoad>,
) -> Result<(), SceneError> {
    let heavy = sf.sections.iter().any(|s| s.density.is_some());
    let Some(gravity) = sf.control.gravity else {
        if heavy {
            return Err(ctx.err(
                "control.gravity",
                Some("density".into()),
                "a section has a density but control has no gravity: the self-weight needs both",
            ));
        }
        return Ok(());
    };
    if !(sized(gravity.0) && sized(gravity.1)) {
        return Err(ctx.err(
            "control.gravity",
            Some("gravity".into()),
            "gravity must be finite and below 1e100 in size",
        ));
    }
    for (b, body) in sf.bodies.iter().enumerate() {
        let Some(section) = sf.sections.iter().find(|s| s.name == body.section) else {
            continue;
        };
        let Some(rho) = section.density else { continue };
        if !(sized(rho) && rho >= 0.0) {
            let k = (sf.sections.iter()).position(|s| s.name == section.name);
            return Err(ctx.err(
                format!(
                    "sections[{}].density (section \"{}\")",
                    k.unwrap_or(0),
                    section.name
                ),
                Some(format!("name:\"{}\"", section.name)),
                "density must be finite, below 1e100 and not negative",
            ));
        }
        let q = [rho * section.a * gravity.0, rho * section.a * gravity.1];
        for &e in &g.bodies[b].elements {
            out.push(DistributedLoad {
                beam: e,
                q: [q, q],
                follower: false,
                group,
            });
        }
    }
    Ok(())
}
