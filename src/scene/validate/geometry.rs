//! The geometry of a scene: its `sections` (stiffnesses positive, finite and in range, names
//! unique), its explicit `nodes` and the `bodies` meshed along their paths into beam elements,
//! with every generated node checked against the nodes already there.

use std::collections::HashMap;

use super::errors::{positive, size_or_zero, sized, Ctx, SceneError};
use crate::scene::format::SceneFile;
use crate::solver::{Beam, Body, Dof, Node, Section};

/// The sections of `sf` by name.
pub(super) fn sections<'a>(
    ctx: &Ctx,
    sf: &'a SceneFile,
) -> Result<HashMap<&'a str, Section>, SceneError> {
    let mut sections: HashMap<&str, Section> = HashMap::new();
    for (k, s) in sf.sections.iter().enumerate() {
        let f = |n: &str| format!("sections[{k}].{n} (section \"{}\")", s.name);
        let nd = Some(format!("name:\"{}\"", s.name));
        positive(ctx, f("E"), nd.clone(), s.e)?;
        positive(ctx, f("A"), nd.clone(), s.a)?;
        positive(ctx, f("I"), nd.clone(), s.i)?;
        let nu = s.nu.unwrap_or(0.3);
        if !(nu > -1.0 && nu < 0.5) {
            return Err(ctx.err(
                f("nu"),
                nd,
                format!("Poisson's ratio must lie in (-1, 0.5), got {nu}"),
            ));
        }
        let g = s.g.unwrap_or(s.e / (2.0 * (1.0 + nu)));
        positive(ctx, f("G"), nd.clone(), g)?;
        let ae = s.ae.unwrap_or(s.a);
        positive(ctx, f("Ae"), nd.clone(), ae)?;
        let thickness = size_or_zero(ctx, f("thickness"), nd.clone(), s.thickness)?;
        // Each factor may be fine and the stiffness still overflow or underflow.
        for (field, what, v) in [
            ("E", "E A", s.e * s.a),
            ("E", "E I", s.e * s.i),
            ("G", "G Ae", g * ae),
        ] {
            if !(sized(v) && v > 0.0) {
                return Err(ctx.err(
                    f(field),
                    nd,
                    format!("the stiffness {what} = {v} is out of range (overflows or underflows)"),
                ));
            }
        }
        if sections
            .insert(
                &s.name,
                Section {
                    ea: s.e * s.a,
                    ei: s.e * s.i,
                    gae: g * ae,
                    thickness,
                },
            )
            .is_some()
        {
            return Err(ctx.err(f("name"), nd, "duplicate section name"));
        }
    }
    Ok(sections)
}

/// The most beam elements a scene may generate (bad input must not exhaust memory).
pub const MAX_ELEMENTS: usize = 2_000_000;

/// The meshed geometry: nodes, beams, bodies, and the indices of node ids and body names.
pub(super) struct Geometry<'a> {
    pub(super) nodes: Vec<Node>,
    pub(super) beams: Vec<Beam>,
    pub(super) bodies: Vec<Body>,
    pub(super) index: HashMap<u32, usize>,
    pub(super) body_index: HashMap<&'a str, usize>,
}

/// The nodes and meshed bodies of `sf`.
pub(super) fn geometry<'a>(
    ctx: &Ctx,
    sf: &'a SceneFile,
    sections: &HashMap<&str, Section>,
) -> Result<Geometry<'a>, SceneError> {
    let mut nodes: Vec<Node> = Vec::new();
    let mut index: HashMap<u32, usize> = HashMap::new();
    for (k, n) in sf.nodes.iter().enumerate() {
        let nd = Some(format!("id:{}", n.id));
        for (key, v) in [("x", n.x), ("y", n.y)] {
            if !sized(v) {
                return Err(ctx.err(
                    format!("nodes[{k}].{key} (node {})", n.id),
                    nd,
                    format!("must be finite and below 1e100 in size, got {v:e}"),
                ));
            }
        }
        if index.insert(n.id, nodes.len()).is_some() {
            return Err(ctx.err(
                format!("nodes[{k}].id"),
                nd,
                format!("duplicate node id {}", n.id),
            ));
        }
        let radius = size_or_zero(
            ctx,
            format!("nodes[{k}].radius (node {})", n.id),
            nd,
            n.radius,
        )?;
        nodes.push(Node {
            id: n.id,
            x: n.x,
            y: n.y,
            rotation: n.rotation,
            // The radius; half the thickest element's thickness is added once the bodies are
            // meshed (`clearances`).
            clearance: radius,
            moves_with: None,
            reach: None,
        });
    }
    let explicit = nodes.len();
    let mut beams = Vec::new();
    let mut bodies = Vec::new();
    let mut body_index: HashMap<&str, usize> = HashMap::new();
    let mut total_elements: usize = 0;
    for (b, body) in sf.bodies.iter().enumerate() {
        let nd = Some(format!("name:\"{}\"", body.name));
        let field = |n: &str| format!("bodies[{b}].{n} (body \"{}\")", body.name);
        let Some(&section) = sections.get(body.section.as_str()) else {
            return Err(ctx.err(
                field("section"),
                nd,
                format!("unknown section \"{}\"", body.section),
            ));
        };
        if body.path.len() < 2 {
            return Err(ctx.err(field("path"), nd, "needs at least two points"));
        }
        if body.elements == 0 {
            return Err(ctx.err(field("elements"), nd, "must be at least 1"));
        }
        // Bounded before anything is allocated (a typo of a few digits must not exhaust memory).
        let count = body.elements.saturating_mul(body.path.len() - 1);
        total_elements = total_elements.saturating_add(count);
        if total_elements > MAX_ELEMENTS {
            return Err(ctx.err(
                field("elements"),
                nd,
                format!("the scene would have more than {MAX_ELEMENTS} beam elements"),
            ));
        }
        if u32::try_from(count)
            .ok()
            .and_then(|c| body.first_node.checked_add(c))
            .is_none()
        {
            return Err(ctx.err(
                field("first_node"),
                nd,
                format!(
                    "node ids {} + {count} run past the largest id {}",
                    body.first_node,
                    u32::MAX
                ),
            ));
        }
        if body_index.insert(&body.name, b).is_some() {
            return Err(ctx.err_entry(field("name"), ("bodies", b), "duplicate body name"));
        }
        if let Some(k) = (body.path.iter()).position(|p| !(sized(p.0) && sized(p.1))) {
            return Err(ctx.err(
                format!("bodies[{b}].path[{k}] (body \"{}\")", body.name),
                nd,
                "coordinates must be finite and below 1e100 in size",
            ));
        }
        let mut pts = vec![body.path[0]];
        for (s, w) in body.path.windows(2).enumerate() {
            let (p, q) = (w[0], w[1]);
            let len = (q.0 - p.0).hypot(q.1 - p.1);
            if !(len.is_finite() && len > 0.0) {
                return Err(ctx.err(
                    format!("bodies[{b}].path[{}] (body \"{}\")", s + 1, body.name),
                    nd,
                    format!("segment {s} has zero length: zero-length elements"),
                ));
            }
            for t in 1..=body.elements {
                let f = t as f64 / body.elements as f64;
                let next = (p.0 + f * (q.0 - p.0), p.1 + f * (q.1 - p.1));
                if pts.last() == Some(&next) {
                    return Err(ctx.err(
                        format!("bodies[{b}].path[{}] (body \"{}\")", s + 1, body.name),
                        nd,
                        format!(
                            "segment {s} ({len:e} m) is too short for {} elements: element ends coincide in floating point",
                            body.elements
                        ),
                    ));
                }
                pts.push(next);
            }
        }
        let mut ids = Vec::with_capacity(pts.len());
        for (k, &(x, y)) in pts.iter().enumerate() {
            let id = body.first_node + k as u32;
            let n = match index.get(&id) {
                Some(&n) => {
                    let node = &nodes[n];
                    if (node.x - x).hypot(node.y - y) > 1e-9 * (1.0 + x.abs() + y.abs()) {
                        let owner = sf.bodies[..b].iter().find(|o| {
                            let count = (o.path.len().saturating_sub(1) * o.elements) as u64;
                            (o.first_node as u64..=o.first_node as u64 + count)
                                .contains(&(id as u64))
                        });
                        let whose = match owner {
                            _ if n < explicit => "an explicit node".to_string(),
                            Some(o) => format!("body \"{}\"'s node", o.name),
                            None => "another body's node".to_string(),
                        };
                        return Err(ctx.err(
                            field("first_node"),
                            nd,
                            format!(
                                "generated node {id} at ({x}, {y}) clashes with {whose} {id} at ({}, {})",
                                node.x, node.y
                            ),
                        ));
                    }
                    if !node.rotation {
                        return Err(ctx.err(
                            field("path"),
                            nd,
                            format!("node {id} has no rotation dof and cannot join beams"),
                        ));
                    }
                    n
                }
                None => {
                    index.insert(id, nodes.len());
                    nodes.push(Node {
                        id,
                        x,
                        y,
                        rotation: true,
                        clearance: 0.0,
                        moves_with: None,
                        reach: None,
                    });
                    nodes.len() - 1
                }
            };
            ids.push(n);
        }
        let mut elements = Vec::new();
        for w in ids.windows(2) {
            if w[0] == w[1] {
                return Err(ctx.err(
                    field("path"),
                    nd,
                    format!("element from node {0} to node {0}", nodes[w[0]].id),
                ));
            }
            elements.push(beams.len());
            beams.push(Beam {
                i: w[0],
                j: w[1],
                section,
                body: b,
            });
        }
        bodies.push(Body {
            name: body.name.clone(),
            elements,
        });
    }
    clearances(&mut nodes, &beams);
    Ok(Geometry {
        nodes,
        beams,
        bodies,
        index,
        body_index,
    })
}

impl Geometry<'_> {
    /// The index of the node of user id `id`, named in `field`.
    pub(super) fn node_of(&self, ctx: &Ctx, field: String, id: u32) -> Result<usize, SceneError> {
        self.index.get(&id).copied().ok_or_else(|| {
            ctx.err(
                field,
                Some(format!("node:{id}")),
                format!("unknown node id {id}"),
            )
        })
    }

    /// Node `n` must have `dof` (a rotation only where the node has one), named in `field`.
    pub(super) fn check_dof(
        &self,
        ctx: &Ctx,
        field: String,
        n: usize,
        dof: Dof,
    ) -> Result<(), SceneError> {
        if dof == Dof::Phi && !self.nodes[n].rotation {
            let id = self.nodes[n].id;
            return Err(ctx.err(
                field,
                Some(format!("node:{id}")),
                format!("node {id} has no rotation dof"),
            ));
        }
        Ok(())
    }

    /// The index of the body named `name`, named in `field`.
    pub(super) fn body_of(
        &self,
        ctx: &Ctx,
        field: String,
        name: &str,
    ) -> Result<usize, SceneError> {
        self.body_index.get(name).copied().ok_or_else(|| {
            ctx.err(
                field,
                Some(format!("\"{name}\"")),
                format!("unknown body \"{name}\""),
            )
        })
    }
}

/// Add to each node's clearance (its radius) half the thickness of its thickest element: the
/// face it touches obstacles with.
fn clearances(nodes: &mut [Node], beams: &[Beam]) {
    let mut half = vec![0.0f64; nodes.len()];
    for b in beams {
        for n in [b.i, b.j] {
            half[n] = half[n].max(0.5 * b.section.thickness);
        }
    }
    for (node, h) in nodes.iter_mut().zip(half) {
        node.clearance += h;
    }
}
