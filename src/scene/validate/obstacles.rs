//! The `obstacles` of a scene: each a named curve (line, polyline, circle or arc) with the
//! nodes that may touch it (every node of the named bodies, and nodes by id) and, if it moves,
//! its pilot node, whose u and v must be supported or prescribed. No candidate node may start
//! inside its obstacle.

use std::collections::{HashMap, HashSet};

use super::errors::{sized, Ctx, SceneError};
use super::geometry::Geometry;
use crate::scene::format::{ObstacleDef, SceneFile, Touches};
use crate::solver::model::Reach;
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
) -> Result<(Vec<Obstacle>, Vec<Roller>), SceneError> {
    let mut out = Vec::new();
    let mut rollers = Vec::new();
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
        let shape = (o.shape.to_shape()).map_err(|m| ctx.err(leaf("shape"), here.clone(), m))?;
        let mut nodes = Vec::new();
        let mut bodies = Vec::new();
        for (m, name) in o.bodies.iter().enumerate() {
            let b = g.body_of(ctx, format!("obstacles[{k}].bodies[{m}]"), name)?;
            bodies.push(b);
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
        let roller = match o.touches {
            Touches::Nodes => None,
            Touches::Elements => Some(roller(ctx, (k, o), &shape, pilot, bodies, g)?),
        };
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
        if let Some(r) = roller {
            // The bodies' nodes touch a circle through their elements, but for their ends (a
            // free tip's corner): there the element ends, and the node keeps touching.
            let mut count: HashMap<usize, usize> = HashMap::new();
            for e in r.bodies.iter().flat_map(|&b| &g.bodies[b].elements) {
                for n in [g.beams[*e].i, g.beams[*e].j] {
                    *count.entry(n).or_default() += 1;
                }
            }
            let on: HashSet<usize> = (count.into_iter())
                .filter(|&(_, k)| k > 1)
                .map(|(n, _)| n)
                .collect();
            if r.circle {
                nodes.retain(|n| !on.contains(n));
            }
            rollers.push(r);
        }
        out.push(Obstacle {
            name: o.name.clone(),
            shape,
            pilot,
            nodes,
            mu: o.mu,
            touches_elements: o.touches == Touches::Elements,
        });
    }
    Ok((out, rollers))
}

/// An obstacle that touches its bodies' elements (`Touches::Elements`), through points that
/// act as pins on them (`Model::contact_distance`), the contact element carrying the force at
/// the point of the element's deformed shape touched, sliding along the element and on to the
/// next: a solid circle's centre with its radius (its pilot, which sits there, or for a fixed
/// circle a centre node of its own, held, whose reactions are the force on it), a solid arc's
/// the same way, touching only within the arc's angles, or each convex corner of a polyline (a
/// node of its own, held where the polyline is fixed and moving with its pilot where it has
/// one; its faces keep touching the nodes).
pub(super) struct Roller {
    /// Index of the obstacle.
    pub(super) obstacle: usize,
    /// The obstacle's pilot node (index), if it has one: a circle's centre node, or the node
    /// a polyline's corners move with.
    pub(super) pilot: Option<usize>,
    /// The points that touch: a circle's or an arc's centre (first), an arc's ends, a
    /// polyline's convex corners.
    pub(super) points: Vec<TouchPoint>,
    /// Whether it is a solid circle or arc (its pilot is its centre's node; its bodies' nodes
    /// touch it only through the contact element, but for their free ends).
    pub(super) circle: bool,
    /// The bodies it touches (indices).
    pub(super) bodies: Vec<usize>,
    /// The friction of its contacts: the obstacle's `mu`.
    pub(super) mu: f64,
}

/// A point of an obstacle that touches elements as a contact node of its own.
pub(super) struct TouchPoint {
    /// Where it is at rest (m).
    pub(super) at: [f64; 2],
    /// The radius it touches with (m): a circle's or an arc's at its centre, 0 at a corner.
    pub(super) radius: f64,
    /// The directions its contacts hold in: an arc's angles at its centre (`None`: every
    /// direction).
    pub(super) reach: Option<Reach>,
    /// Whether it is the centre of a circle or arc (its pilot's node, where it has one).
    pub(super) centre: bool,
}

impl TouchPoint {
    /// A corner: a point of radius 0 that touches in every direction.
    fn corner(at: [f64; 2]) -> TouchPoint {
        TouchPoint {
            at,
            radius: 0.0,
            reach: None,
            centre: false,
        }
    }
}

/// Obstacle `k` (`o`, of shape `shape` and pilot `pilot`, touching `bodies`) as a `Roller`:
/// a solid circle, its pilot, if any, at its centre, or a polyline with a convex corner,
/// touching bodies.
fn roller(
    ctx: &Ctx,
    (k, o): (usize, &ObstacleDef),
    shape: &Shape,
    pilot: Option<usize>,
    bodies: Vec<usize>,
    g: &Geometry,
) -> Result<Roller, SceneError> {
    let here = Some(format!("name: \"{}\"", o.name));
    let field = format!("obstacles[{k}].touches (obstacle \"{}\")", o.name);
    let corners = shape.convex_corners();
    let round = shape.disk().is_some() || shape.solid_arc().is_some();
    let why = if !round && corners.is_empty() {
        Some(
            "only a solid circle (a roller, a peg), a solid arc or a polyline's convex corners \
             touch elements: other shapes touch the nodes"
                .to_string(),
        )
    } else if bodies.is_empty() {
        Some("it touches the elements of the bodies it names: name at least one".to_string())
    } else {
        None
    };
    if let Some(why) = why {
        return Err(ctx.err(field, here, why));
    }
    // A solid arc touches with its centre within its angles, and with its two ends, corners
    // beyond which the way from the centre leaves them.
    let (centre, radius, reach, ends) = match (shape.disk(), shape.solid_arc()) {
        (Some((centre, radius)), _) => (centre, radius, None, Vec::new()),
        (_, Some((centre, radius, [from, to]))) => {
            // Each end touches where the way from the centre has left the arc: over the
            // quarter turn between the arc's normal there and the normal of the radius to it.
            let end = |a: f64, reach: Reach| TouchPoint {
                at: [centre[0] + radius * a.cos(), centre[1] + radius * a.sin()],
                radius: 0.0,
                reach: Some(reach),
                centre: false,
            };
            let quarter = std::f64::consts::FRAC_PI_2;
            let ends = vec![
                end(
                    from,
                    Reach {
                        from: from - quarter,
                        to: from,
                    },
                ),
                end(
                    to,
                    Reach {
                        from: to,
                        to: to + quarter,
                    },
                ),
            ];
            (centre, radius, Some(Reach { from, to }), ends)
        }
        _ => {
            return Ok(Roller {
                obstacle: k,
                pilot,
                points: corners.into_iter().map(TouchPoint::corner).collect(),
                circle: false,
                bodies,
                mu: o.mu,
            })
        }
    };
    if let Some(p) = pilot {
        let at = [g.nodes[p].x, g.nodes[p].y];
        let off = (at[0] - centre[0]).hypot(at[1] - centre[1]);
        if off > 1e-12 * radius.max(model_size(g)) {
            return Err(ctx.err(
                field,
                here,
                format!(
                    "its pilot, node {}, must sit at its centre ({}, {}) to carry it: it is {off:e} m from it",
                    g.nodes[p].id, centre[0], centre[1]
                ),
            ));
        }
    }
    Ok(Roller {
        obstacle: k,
        pilot,
        points: std::iter::once(TouchPoint {
            at: centre,
            radius,
            reach,
            centre: true,
        })
        .chain(ends)
        .collect(),
        circle: true,
        bodies,
        mu: o.mu,
    })
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

/// An element of a body that may touch obstacle `o` whose chord at rest passes through the
/// obstacle between its two nodes, both clear of it (`Shape::chord_through`): the element
/// and how deep its chord goes.
fn chord_through(shape: &Shape, o: &ObstacleDef, g: &Geometry) -> Option<(usize, f64)> {
    let bodies = (o.bodies.iter()).filter_map(|name| g.body_index.get(name.as_str()));
    let elements = bodies.flat_map(|&b| g.bodies[b].elements.iter().copied());
    elements
        .filter_map(|e| {
            let (p, q) = (&g.nodes[g.beams[e].i], &g.nodes[g.beams[e].j]);
            Some((e, shape.chord_through([p.x, p.y], [q.x, q.y])?))
        })
        .next()
}
