//! Reading a scene: the RON text parsed and validated section by section into the solver's
//! `Model` and the run settings (`Scene`), and the final check that the structure is not a
//! mechanism.

use std::path::Path;

use super::conditions::conditions;
use super::contacts::contacts;
use super::control::control;
use super::errors::{Ctx, SceneError};
use super::geometry::{geometry, sections};
use super::obstacles::obstacles;
use super::stages::{load_groups, load_path};
use crate::scene::format::SceneFile;
use crate::solver::{ContactPair, Dof, Model, Node, SolveError, Solver, SolverParams, Support};

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

/// The largest scene file read (bytes): a scene of `MAX_ELEMENTS` elements written out takes
/// far less; a larger file is refused before it is read.
pub const MAX_SCENE_BYTES: u64 = 64 << 20;

/// Read and validate a scene file: a regular file of at most `MAX_SCENE_BYTES`, in UTF-8.
pub fn load_file(path: &Path) -> Result<Scene, SceneError> {
    use std::io::Read;
    let name = path.display().to_string();
    let error = |message: String| SceneError {
        file: name.clone(),
        line: None,
        field: "(file)".into(),
        message,
    };
    let meta = std::fs::metadata(path).map_err(|e| error(format!("cannot read: {e}")))?;
    if !meta.is_file() {
        return Err(error(
            "not a regular file (a folder, a FIFO or a device): a scene is a RON file".into(),
        ));
    }
    if meta.len() > MAX_SCENE_BYTES {
        return Err(error(format!(
            "{} bytes, more than the {MAX_SCENE_BYTES} a scene may have",
            meta.len()
        )));
    }
    let mut bytes = Vec::new();
    std::fs::File::open(path)
        .and_then(|f| f.take(MAX_SCENE_BYTES + 1).read_to_end(&mut bytes))
        .map_err(|e| error(format!("cannot read: {e}")))?;
    if bytes.len() as u64 > MAX_SCENE_BYTES {
        return Err(error(format!(
            "more than the {MAX_SCENE_BYTES} bytes a scene may have"
        )));
    }
    let text = String::from_utf8(bytes).map_err(|e| {
        error(format!(
            "not UTF-8 text (invalid byte at offset {})",
            e.utf8_error().valid_up_to()
        ))
    })?;
    parse(&text, &name)
}

/// Parse and validate scene text; `file` is used in messages.
pub fn parse(text: &str, file: &str) -> Result<Scene, SceneError> {
    // A byte-order mark some editors write is not part of the text.
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let options =
        ron::Options::default().with_default_extension(ron::extensions::Extensions::IMPLICIT_SOME);
    let sf: SceneFile = options.from_str(text).map_err(|e| {
        let (at, col) = (e.span.start.line, e.span.start.col);
        let (line, message) = syntax_cause(text, at, col)
            .unwrap_or_else(|| (at, format!("{} (column {col})", e.code)));
        // The field whose value the parser stopped in, where the error is where it stopped.
        let key = (line == at).then(|| key_at(text, at, col)).flatten();
        SceneError {
            file: file.into(),
            line: Some(line),
            field: key.map_or("(syntax)".into(), |k| format!("{k} (syntax)")),
            message,
        }
    })?;
    build(sf, text, file)
}

/// What a syntax error found at `line` and `col` (from 1) really comes from, where the parser's
/// own words would point elsewhere: a string left open on an earlier line (the parser finds
/// the error where the string ends, lines later), or a decimal number where a whole one is
/// expected. Returns the line to report and the message.
fn syntax_cause(text: &str, line: usize, col: usize) -> Option<(usize, String)> {
    // A string that runs over a line end before the error: report where it opens.
    let (mut in_string, mut opened, mut escaped) = (false, 0usize, false);
    for (k, l) in text.lines().enumerate().take(line.saturating_sub(1)) {
        let mut chars = l.chars().peekable();
        while let Some(c) = chars.next() {
            match c {
                _ if escaped => escaped = false,
                '\\' if in_string => escaped = true,
                '"' => {
                    in_string = !in_string;
                    opened = k + 1;
                }
                '/' if !in_string && chars.peek() == Some(&'/') => break,
                _ => {}
            }
        }
        if in_string {
            return Some((
                opened,
                "a string opened on this line is not closed on it (add the closing quote)".into(),
            ));
        }
    }
    // A decimal point where the parser wanted the number to end.
    let here = text.lines().nth(line.checked_sub(1)?)?;
    let at: Vec<char> = here.chars().collect();
    let k = col.checked_sub(1)?;
    let before = k.checked_sub(1).and_then(|b| at.get(b));
    if at.get(k) == Some(&'.') && before.is_some_and(|c| c.is_ascii_digit()) {
        return Some((
            line,
            format!("a whole number is expected here, not a decimal (column {col})"),
        ));
    }
    None
}

/// The key of the field at `line` and `col` (from 1) of `text`: the name there if one starts
/// there and is followed by a colon, else the last `name:` before it on that line.
fn key_at(text: &str, line: usize, col: usize) -> Option<String> {
    let here: Vec<char> = text.lines().nth(line.checked_sub(1)?)?.chars().collect();
    let word = |c: &char| c.is_alphanumeric() || *c == '_';
    let start = col.checked_sub(1)?.min(here.len());
    let named_at = |k: usize| -> Option<String> {
        let name: String = here[k..].iter().take_while(|c| word(c)).collect();
        let rest = here[k + name.chars().count()..]
            .iter()
            .find(|c| !c.is_whitespace());
        (!name.is_empty() && rest == Some(&':')).then_some(name)
    };
    if let Some(name) = named_at(start) {
        return Some(name);
    }
    let colon = here[..start].iter().rposition(|&c| c == ':')?;
    let end = here[..colon].iter().rposition(|c| !c.is_whitespace())? + 1;
    let begin = here[..end]
        .iter()
        .rposition(|c| !word(c))
        .map_or(0, |k| k + 1);
    (begin < end).then(|| here[begin..end].iter().collect())
}

/// Validate a scene already parsed (or built in code), `sf`; `file` names it in messages
/// (which cannot give lines: there is no text).
pub fn from_scene_file(sf: SceneFile, file: &str) -> Result<Scene, SceneError> {
    build(sf, "", file)
}

/// Validate parsed scene `sf` (from `text` of `file`) and build its model.
fn build(sf: SceneFile, text: &str, file: &str) -> Result<Scene, SceneError> {
    let ctx = Ctx { text, file };
    let sections = sections(&ctx, &sf)?;
    let g = geometry(&ctx, &sf, &sections)?;
    let groups = load_groups(&sf);
    let c = conditions(&ctx, &sf, &g, &groups)?;
    let mut contacts = contacts(&ctx, &sf, &g)?;
    let (mut obstacles, rollers) = obstacles(&ctx, &sf, &g, (&c.supports, &c.prescribed))?;
    let (mut g, mut c) = (g, c);
    for r in rollers {
        for point in &r.points {
            // A circle's or arc's pilot, or a node of its own for a fixed one's centre, an
            // arc's end or a polyline's corner: the next id after the scene's largest, held, or
            // moving with the obstacle's pilot.
            let node = r.pilot.filter(|_| point.centre).unwrap_or_else(|| {
                let id = g.nodes.iter().map(|n| n.id).max().unwrap_or(0) + 1;
                g.nodes.push(Node {
                    id,
                    x: point.at[0],
                    y: point.at[1],
                    rotation: false,
                    clearance: 0.0,
                    moves_with: r.pilot,
                    reach: None,
                });
                let n = g.nodes.len() - 1;
                if r.pilot.is_none() {
                    c.supports
                        .extend([Dof::U, Dof::V].map(|dof| Support { node: n, dof }));
                }
                if point.centre {
                    obstacles[r.obstacle].pilot = Some(n);
                }
                n
            });
            g.nodes[node].clearance += point.radius;
            g.nodes[node].reach = point.reach;
            contacts.push(ContactPair {
                nodes: vec![node],
                bodies: r.bodies.clone(),
                own: false,
                mu: r.mu,
                side: None,
            });
        }
    }
    let path = load_path(&ctx, &sf, &g, &groups, &c.prescribed)?;
    let run = control(&ctx, &sf, &c, path.as_ref())?;
    if g.beams.is_empty() {
        return Err(ctx.err("bodies", None, "the scene has no beam elements"));
    }
    let model = Model {
        nodes: g.nodes,
        beams: g.beams,
        bodies: g.bodies,
        supports: c.supports,
        loads: c.loads,
        distributed: c.distributed,
        prescribed: c.prescribed,
        load_per_step: run.load_per_step,
        formulation: sf.formulation,
        contacts,
        obstacles,
        load_groups: groups,
        path,
    };
    let scene = Scene {
        file: sf,
        model,
        params: run.params,
        steps: run.steps,
    };
    stiffness_span(&ctx, &scene.model)?;
    if let Err(e) = scene.solver() {
        if let SolveError::AmbiguousSide { .. } = e {
            return Err(ctx.err("contacts", None, e.to_string()));
        }
        return Err(ctx.err("supports", None, e.to_string()));
    }
    Ok(scene)
}

/// The widest span of element stiffnesses a double-precision tangent can hold: below this
/// fraction of the stiffest term, a stiffness is round-off of the others.
const STIFFNESS_SPAN: f64 = 1e-15;

/// The element stiffnesses (axial EA / l and bending 12 EI / l^3) must lie within
/// `STIFFNESS_SPAN` of each other: a term far below the others is lost to round-off and the
/// structure would be reported as a mechanism, which it is not. (A large shear stiffness G Ae
/// only brings the element to its Bernoulli-Euler limit.)
fn stiffness_span(ctx: &Ctx, model: &Model) -> Result<(), SceneError> {
    let terms = |b: &crate::solver::Beam| {
        let (pi, pj) = (model.position(b.i), model.position(b.j));
        let l = (pj[0] - pi[0]).hypot(pj[1] - pi[1]);
        let s = b.section;
        [
            ("E A / l", s.ea / l),
            ("12 E I / l^3", 12.0 * s.ei / (l * l * l)),
        ]
    };
    let mut lo = (f64::INFINITY, "", 0);
    let mut hi = (0.0f64, "", 0);
    for (e, b) in model.beams.iter().enumerate() {
        for (what, v) in terms(b) {
            if v < lo.0 {
                lo = (v, what, e);
            }
            if v > hi.0 {
                hi = (v, what, e);
            }
        }
    }
    if lo.0 < STIFFNESS_SPAN * hi.0 {
        // Placed at the body of the stiffness lost (its section, or its elements' length).
        let b = model.beams[lo.2].body;
        let name = &model.bodies[b].name;
        return Err(ctx.err(
            format!("bodies[{b}] (body \"{name}\")"),
            Some(format!("name:\"{name}\"")),
            format!(
                "the element stiffnesses span more than 15 orders of magnitude ({} = {:e} on {} against {} = {:e} on {}): the smaller is lost to round-off",
                lo.1,
                lo.0,
                model.element_label(lo.2),
                hi.1,
                hi.0,
                model.element_label(hi.2)
            ),
        ));
    }
    Ok(())
}
