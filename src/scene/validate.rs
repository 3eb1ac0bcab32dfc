//! Scene validation: parse RON, check every reference and value, and build the solver `Model`.
//! Every error names the file, the line where it could be located, the field and the node,
//! element or body concerned. Never panics on user input.

use std::collections::HashMap;
use std::fmt;
use std::path::Path;

use super::format::SceneFile;
use crate::solver::{
    Beam, Body, ContactPair, Dof, Load, Model, Node, Prescribed, Section, SolveError, Solver,
    SolverParams, Support,
};

/// The most beam elements a scene may generate (bad input must not exhaust memory).
pub const MAX_ELEMENTS: usize = 2_000_000;

/// A problem with a scene, located as precisely as possible.
#[derive(Clone, Debug, PartialEq)]
pub struct SceneError {
    /// File name (or `"<memory>"`).
    pub file: String,
    /// 1-based line, when known.
    pub line: Option<usize>,
    /// Field path, e.g. `bodies[1].section`.
    pub field: String,
    /// What is wrong.
    pub message: String,
}

impl fmt::Display for SceneError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.line {
            Some(l) => write!(f, "{}:{}: {}: {}", self.file, l, self.field, self.message),
            None => write!(f, "{}: {}: {}", self.file, self.field, self.message),
        }
    }
}

impl std::error::Error for SceneError {}

/// A validated scene: the file as written, the model and the run settings.
#[derive(Clone, Debug)]
pub struct Scene {
    /// The file contents as parsed.
    pub file: SceneFile,
    /// The solver model.
    pub model: Model,
    /// Solver parameters (defaults plus the scene's control settings).
    pub params: SolverParams,
    /// Steps a run makes.
    pub steps: usize,
}

impl Scene {
    /// A solver at the scene's initial state.
    pub fn solver(&self) -> Result<Solver, SolveError> {
        Solver::new(self.model.clone(), self.params)
    }
}

/// Read and validate a scene file.
pub fn load_file(path: &Path) -> Result<Scene, SceneError> {
    let name = path.display().to_string();
    let text = std::fs::read_to_string(path).map_err(|e| SceneError {
        file: name.clone(),
        line: None,
        field: "(file)".into(),
        message: format!("cannot read: {e}"),
    })?;
    parse(&text, &name)
}

/// Parse and validate scene text; `file` is used in messages.
pub fn parse(text: &str, file: &str) -> Result<Scene, SceneError> {
    let options =
        ron::Options::default().with_default_extension(ron::extensions::Extensions::IMPLICIT_SOME);
    let sf: SceneFile = options.from_str(text).map_err(|e| SceneError {
        file: file.into(),
        line: Some(e.span.start.line),
        field: "(syntax)".into(),
        message: format!("{} (column {})", e.code, e.span.start.col),
    })?;
    build(sf, text, file)
}

struct Ctx<'a> {
    text: &'a str,
    file: &'a str,
}

impl Ctx<'_> {
    fn err(
        &self,
        field: impl Into<String>,
        needle: Option<String>,
        message: impl Into<String>,
    ) -> SceneError {
        let line = needle.and_then(|n| locate(self.text, &n));
        SceneError {
            file: self.file.into(),
            line,
            field: field.into(),
            message: message.into(),
        }
    }
}

/// First line containing `needle` (whitespace-insensitive around ':').
fn locate(text: &str, needle: &str) -> Option<usize> {
    let squash = |s: &str| s.chars().filter(|c| !c.is_whitespace()).collect::<String>();
    let n = squash(needle);
    text.lines()
        .position(|l| squash(l).contains(&n))
        .map(|i| i + 1)
}

fn positive(ctx: &Ctx, field: String, needle: Option<String>, v: f64) -> Result<(), SceneError> {
    if v.is_finite() && v > 0.0 {
        Ok(())
    } else {
        Err(ctx.err(
            field,
            needle,
            format!("must be positive and finite, got {v}"),
        ))
    }
}

fn build(sf: SceneFile, text: &str, file: &str) -> Result<Scene, SceneError> {
    let ctx = Ctx { text, file };
    // Sections.
    let mut sections: HashMap<&str, Section> = HashMap::new();
    for (k, s) in sf.sections.iter().enumerate() {
        let f = |n: &str| format!("sections[{k}].{n} (section \"{}\")", s.name);
        let nd = Some(format!("name:\"{}\"", s.name));
        positive(&ctx, f("E"), nd.clone(), s.e)?;
        positive(&ctx, f("A"), nd.clone(), s.a)?;
        positive(&ctx, f("I"), nd.clone(), s.i)?;
        let nu = s.nu.unwrap_or(0.3);
        if !(nu > -1.0 && nu < 0.5) {
            return Err(ctx.err(
                f("nu"),
                nd,
                format!("Poisson's ratio must lie in (-1, 0.5), got {nu}"),
            ));
        }
        let g = s.g.unwrap_or(s.e / (2.0 * (1.0 + nu)));
        positive(&ctx, f("G"), nd.clone(), g)?;
        let ae = s.ae.unwrap_or(s.a);
        positive(&ctx, f("Ae"), nd.clone(), ae)?;
        // Each factor may be fine and the stiffness still overflow or underflow.
        for (field, what, v) in [
            ("E", "E A", s.e * s.a),
            ("E", "E I", s.e * s.i),
            ("G", "G Ae", g * ae),
        ] {
            if !(v.is_finite() && v > 0.0) {
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
                },
            )
            .is_some()
        {
            return Err(ctx.err(f("name"), nd, "duplicate section name"));
        }
    }
    // Explicit nodes.
    let mut nodes: Vec<Node> = Vec::new();
    let mut index: HashMap<u32, usize> = HashMap::new();
    for (k, n) in sf.nodes.iter().enumerate() {
        let nd = Some(format!("id:{}", n.id));
        if !(n.x.is_finite() && n.y.is_finite()) {
            return Err(ctx.err(
                format!("nodes[{k}] (node {})", n.id),
                nd,
                "coordinates must be finite",
            ));
        }
        if index.insert(n.id, nodes.len()).is_some() {
            return Err(ctx.err(
                format!("nodes[{k}].id"),
                nd,
                format!("duplicate node id {}", n.id),
            ));
        }
        nodes.push(Node {
            id: n.id,
            x: n.x,
            y: n.y,
            rotation: n.rotation,
        });
    }
    let explicit = nodes.len();
    // Bodies.
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
            return Err(ctx.err(field("name"), nd, "duplicate body name"));
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
                        let whose = if n < explicit {
                            "an explicit node"
                        } else {
                            "another body's node"
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
    let node_of = |field: String, id: u32| -> Result<usize, SceneError> {
        index.get(&id).copied().ok_or_else(|| {
            ctx.err(
                field,
                Some(format!("node:{id}")),
                format!("unknown node id {id}"),
            )
        })
    };
    let check_dof = |field: String, n: usize, dof: Dof| -> Result<(), SceneError> {
        if dof == Dof::Phi && !nodes[n].rotation {
            let id = nodes[n].id;
            return Err(ctx.err(
                field,
                Some(format!("node:{id}")),
                format!("node {id} has no rotation dof"),
            ));
        }
        Ok(())
    };
    // Supports.
    let mut supports = Vec::new();
    for (k, s) in sf.supports.iter().enumerate() {
        let n = node_of(format!("supports[{k}].node"), s.node)?;
        for (on, dof) in [(s.u, Dof::U), (s.v, Dof::V), (s.phi, Dof::Phi)] {
            if on {
                check_dof(format!("supports[{k}].phi (node {})", s.node), n, dof)?;
                if !supports.contains(&Support { node: n, dof }) {
                    supports.push(Support { node: n, dof });
                }
            }
        }
    }
    // Loads.
    let mut loads = Vec::new();
    for (k, l) in sf.loads.iter().enumerate() {
        let n = node_of(format!("loads[{k}].node"), l.node)?;
        if l.m != 0.0 {
            check_dof(format!("loads[{k}].m (node {})", l.node), n, Dof::Phi)?;
        }
        if ![l.fx, l.fy, l.m].iter().all(|v| v.is_finite()) {
            return Err(ctx.err(
                format!("loads[{k}] (node {})", l.node),
                Some(format!("node:{}", l.node)),
                "load must be finite",
            ));
        }
        loads.push(Load {
            node: n,
            force: [l.fx, l.fy, l.m],
        });
    }
    // Prescribed displacements.
    let mut prescribed: Vec<Prescribed> = Vec::new();
    for (k, p) in sf.prescribed.iter().enumerate() {
        let field = format!("prescribed[{k}] (node {} {})", p.node, p.dof.name());
        let n = node_of(field.clone(), p.node)?;
        check_dof(field.clone(), n, p.dof)?;
        let nd = Some(format!("node:{}", p.node));
        if !p.per_step.is_finite() {
            return Err(ctx.err(field, nd, "per_step must be finite"));
        }
        if supports.iter().any(|s| s.node == n && s.dof == p.dof) {
            return Err(ctx.err(field, nd, "a dof cannot be both supported and prescribed"));
        }
        if prescribed.iter().any(|q| q.node == n && q.dof == p.dof) {
            return Err(ctx.err(field, nd, "prescribed twice"));
        }
        prescribed.push(Prescribed {
            node: n,
            dof: p.dof,
            per_step: p.per_step,
        });
    }
    // Contacts.
    let mut contacts = Vec::new();
    for (k, c) in sf.contacts.iter().enumerate() {
        let mut cn = Vec::new();
        for (m, &id) in c.nodes.iter().enumerate() {
            cn.push(node_of(format!("contacts[{k}].nodes[{m}]"), id)?);
        }
        let body_of = |field: String, name: &str| -> Result<usize, SceneError> {
            body_index.get(name).copied().ok_or_else(|| {
                ctx.err(
                    field,
                    Some(format!("\"{name}\"")),
                    format!("unknown body \"{name}\""),
                )
            })
        };
        for (m, name) in c.node_bodies.iter().enumerate() {
            let b = body_of(format!("contacts[{k}].node_bodies[{m}]"), name)?;
            for &e in &bodies[b].elements {
                let beam: &Beam = &beams[e];
                for n in [beam.i, beam.j] {
                    if !cn.contains(&n) {
                        cn.push(n);
                    }
                }
            }
        }
        let mut cb = Vec::new();
        for (m, name) in c.bodies.iter().enumerate() {
            cb.push(body_of(format!("contacts[{k}].bodies[{m}]"), name)?);
        }
        contacts.push(ContactPair {
            nodes: cn,
            bodies: cb,
        });
    }
    // Control.
    let c = &sf.control;
    let mut params = SolverParams::default();
    if let Some(t) = c.tolerance {
        positive(
            &ctx,
            "control.tolerance".into(),
            Some("tolerance".into()),
            t,
        )?;
        params.tolerance = t;
    }
    if let Some(b) = c.roundoff_bound {
        positive(
            &ctx,
            "control.roundoff_bound".into(),
            Some("roundoff_bound".into()),
            b,
        )?;
        params.roundoff_bound = b;
    }
    if let Some(s) = c.max_step {
        positive(&ctx, "control.max_step".into(), Some("max_step".into()), s)?;
        params.max_step = s;
    }
    params.stretch_correction = c.stretch_correction;
    if let Some(s) = c.arc_length {
        positive(
            &ctx,
            "control.arc_length".into(),
            Some("arc_length".into()),
            s,
        )?;
        if loads.is_empty() {
            return Err(ctx.err(
                "control.arc_length",
                Some("arc_length".into()),
                "arc-length control needs at least one load (the load factor is what it solves for)",
            ));
        }
        if let Some(k) = prescribed.iter().position(|p| p.per_step != 0.0) {
            return Err(ctx.err(
                format!("prescribed[{k}].per_step"),
                Some("per_step".into()),
                "with control.arc_length, prescribed displacements are held: per_step must be 0",
            ));
        }
        params.arc_length = Some(s);
    }
    let steps = c.steps.max(1);
    let load_per_step = match c.load_per_step {
        Some(v) if v.is_finite() => v,
        Some(v) => {
            return Err(ctx.err(
                "control.load_per_step",
                Some("load_per_step".into()),
                format!("must be finite, got {v}"),
            ))
        }
        None if loads.is_empty() => 0.0,
        None => 1.0 / steps as f64,
    };
    if beams.is_empty() {
        return Err(ctx.err("bodies", None, "the scene has no beam elements"));
    }
    let model = Model {
        nodes,
        beams,
        bodies,
        supports,
        loads,
        prescribed,
        load_per_step,
        formulation: sf.formulation,
        contacts,
    };
    let scene = Scene {
        file: sf,
        model,
        params,
        steps,
    };
    if let Err(e) = scene.solver() {
        if let SolveError::AmbiguousSide { .. } = e {
            return Err(ctx.err("contacts", None, e.to_string()));
        }
        let message = match e {
            SolveError::Mechanism { dofs } => {
                format!(
                    "the structure is a mechanism; these free dofs have no stiffness: {}",
                    dofs.join(", ")
                )
            }
            other => other.to_string(),
        };
        return Err(ctx.err("supports", None, message));
    }
    Ok(scene)
}
