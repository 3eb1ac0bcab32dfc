//! Errors of scene validation, located by file, line and field (`SceneError`), and the
//! context that finds the line of a field in the scene text.

use std::fmt;

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

/// Where the scene text came from, for locating errors.
pub(super) struct Ctx<'a> {
    pub(super) text: &'a str,
    pub(super) file: &'a str,
}

impl Ctx<'_> {
    /// The error for `field`, located at the first line holding `needle`.
    pub(super) fn err(
        &self,
        field: impl Into<String>,
        needle: Option<String>,
        message: impl Into<String>,
    ) -> SceneError {
        let field = field.into();
        let line = needle.and_then(|n| locate(self.text, &field, &n));
        SceneError {
            file: self.file.into(),
            line,
            field,
            message: message.into(),
        }
    }
}

/// The line of `needle` (whitespace-insensitive) in the section of the scene that `field`
/// names (`prescribed[0] ...` looks from the `prescribed:` line on, so that a node named in
/// the supports and the prescribed displacements is found where the error is); the first line
/// holding it anywhere when the section cannot be found.
fn locate(text: &str, field: &str, needle: &str) -> Option<usize> {
    let squash = |s: &str| s.chars().filter(|c| !c.is_whitespace()).collect::<String>();
    let n = squash(needle);
    let lines: Vec<String> = text.lines().map(squash).collect();
    let section = field.split(['[', '.', ' ']).next().unwrap_or("");
    let key = format!("{section}:");
    let from = (!section.is_empty())
        .then(|| {
            lines.iter().position(|l| {
                l.starts_with(&key)
                    || l.contains(&format!(",{key}"))
                    || l.contains(&format!("({key}"))
            })
        })
        .flatten()
        .unwrap_or(0);
    let after = lines[from..]
        .iter()
        .position(|l| l.contains(&n))
        .map(|i| i + from);
    after
        .or_else(|| lines.iter().position(|l| l.contains(&n)))
        .map(|i| i + 1)
}

/// The largest size a number of a scene may have: beyond it, the products the solver forms of
/// them (stiffness times displacement, load times steps) would leave double precision.
pub(super) const MAGNITUDE: f64 = 1e100;

/// Whether `v` is finite and below `MAGNITUDE` in size.
pub(super) fn sized(v: f64) -> bool {
    v.is_finite() && v.abs() < MAGNITUDE
}

/// `v` must be positive, finite and below `MAGNITUDE`.
pub(super) fn positive(
    ctx: &Ctx,
    field: String,
    needle: Option<String>,
    v: f64,
) -> Result<(), SceneError> {
    if sized(v) && v > 0.0 {
        Ok(())
    } else {
        Err(ctx.err(
            field,
            needle,
            format!("must be positive and finite (below 1e100), got {v:e}"),
        ))
    }
}

/// `v` must lie in (`lo`, `hi`]: what a relative residual bound can sensibly be.
pub(super) fn within(
    ctx: &Ctx,
    field: &str,
    v: f64,
    (lo, hi): (f64, f64),
) -> Result<(), SceneError> {
    if v > lo && v <= hi {
        Ok(())
    } else {
        let key = field.rsplit('.').next().unwrap_or(field).to_string();
        Err(ctx.err(
            field,
            Some(key),
            format!("must lie in ({lo:e}, {hi:e}], got {v:e}"),
        ))
    }
}
