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

impl Ctx<'_> {
    /// The error for `field`, located at the line where entry `k` (from 0) of the scene's
    /// top-level list `section` opens (entries without a name of their own, such as
    /// `contacts`).
    pub(super) fn err_entry(
        &self,
        field: impl Into<String>,
        (section, k): (&str, usize),
        message: impl Into<String>,
    ) -> SceneError {
        SceneError {
            file: self.file.into(),
            line: entry_line(self.text, section, k),
            field: field.into(),
            message: message.into(),
        }
    }
}

impl Ctx<'_> {
    /// `e`, placed at the line where entry `k` of the top-level list `section` opens if it has
    /// no line of its own.
    pub(super) fn in_entry(&self, mut e: SceneError, (section, k): (&str, usize)) -> SceneError {
        if e.line.is_none() {
            e.line = entry_line(self.text, section, k);
        }
        e
    }
}

/// The line where entry `k` (from 0) of the top-level list `section` opens: the text scanned
/// for brackets outside strings and comments, the key `section` found at the scene's own level
/// and its list's entries counted at the level below.
pub(super) fn entry_line(text: &str, section: &str, k: usize) -> Option<usize> {
    let (mut depth, mut line, mut in_string, mut escaped) = (0usize, 1usize, false, false);
    let (mut key_line, mut list_depth, mut entries) = (None, None, 0usize);
    let mut word = String::new();
    let mut chars = text.chars().peekable();
    while let Some(c) = chars.next() {
        if in_string {
            match c {
                _ if escaped => escaped = false,
                '\\' => escaped = true,
                '"' => in_string = false,
                '\n' => line += 1,
                _ => {}
            }
            continue;
        }
        match c {
            '\n' => line += 1,
            '"' => in_string = true,
            '/' if chars.peek() == Some(&'/') => {
                for c in chars.by_ref() {
                    if c == '\n' {
                        line += 1;
                        break;
                    }
                }
            }
            '(' | '[' => {
                depth += 1;
                if list_depth == Some(depth - 1) && c == '(' {
                    if entries == k {
                        return Some(line);
                    }
                    entries += 1;
                }
                if c == '[' && key_line.is_some() && list_depth.is_none() && depth == 2 {
                    list_depth = Some(depth);
                }
            }
            ')' | ']' => {
                if list_depth == Some(depth) {
                    return None;
                }
                depth = depth.saturating_sub(1);
            }
            ':' if depth == 1 && word == section => key_line = Some(line),
            _ => {}
        }
        if c.is_alphanumeric() || c == '_' {
            word.push(c);
        } else if !c.is_whitespace() {
            word.clear();
        }
    }
    None
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

pub(super) use crate::scene::units::sized;

/// An optional size `v` (a thickness, a radius) must be zero or positive, finite and below
/// `MAGNITUDE`; absent, it is 0.
pub(super) fn size_or_zero(
    ctx: &Ctx,
    field: String,
    needle: Option<String>,
    v: Option<f64>,
) -> Result<f64, SceneError> {
    match v {
        None => Ok(0.0),
        Some(v) if sized(v) && v >= 0.0 => Ok(v),
        Some(v) => Err(ctx.err(
            field,
            needle,
            format!("must be zero or positive and finite (below 1e100), got {v:e}"),
        )),
    }
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
