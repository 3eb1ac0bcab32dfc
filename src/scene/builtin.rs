//! The built-in scenes, compiled into the binary from `assets/scenes/`.

use super::validate::{load_file, parse, Scene, SceneError};

/// (file name, RON text) of every built-in scene, default first.
pub const BUILTIN: &[(&str, &str)] = &[
    (
        "example_3_2.ron",
        include_str!("../../assets/scenes/example_3_2.ron"),
    ),
    (
        "example_3_1.ron",
        include_str!("../../assets/scenes/example_3_1.ron"),
    ),
    (
        "mattiasson.ron",
        include_str!("../../assets/scenes/mattiasson.ron"),
    ),
    (
        "end_moment.ron",
        include_str!("../../assets/scenes/end_moment.ron"),
    ),
    (
        "williams_toggle.ron",
        include_str!("../../assets/scenes/williams_toggle.ron"),
    ),
    (
        "lee_frame.ron",
        include_str!("../../assets/scenes/lee_frame.ron"),
    ),
    ("comb.ron", include_str!("../../assets/scenes/comb.ron")),
    (
        "pin_on_cantilever.ron",
        include_str!("../../assets/scenes/pin_on_cantilever.ron"),
    ),
];

/// The RON text of a built-in scene by file name (with or without `.ron`).
pub fn text(name: &str) -> Option<&'static str> {
    let want = name.trim_end_matches(".ron");
    BUILTIN
        .iter()
        .find(|(f, _)| f.trim_end_matches(".ron") == want)
        .map(|(_, t)| *t)
}

/// A built-in scene of one straight body numbered from 1 (Mattiasson's cantilever, the end
/// moment, the pin on a cantilever) divided into `n` elements instead of its own K: the
/// body's `elements` and every reference to its last node (`(node: K + 1,`, where loads and
/// supports name it) follow. `None` for an unknown name or any other kind of scene (more
/// than one body, or a polyline whose element count is not the body's).
pub fn with_elements(name: &str, n: usize) -> Option<Result<Scene, SceneError>> {
    let text = text(name)?;
    let mut counts = text.match_indices("elements: ").map(|(at, key)| {
        let digits = &text[at + key.len()..];
        let end = digits
            .find(|c: char| !c.is_ascii_digit())
            .unwrap_or(digits.len());
        digits[..end].parse::<usize>().ok()
    });
    let own = match (counts.next(), counts.next()) {
        (Some(Some(k)), None) => k,
        _ => return None,
    };
    let text = text
        .replace(&format!("elements: {own}"), &format!("elements: {n}"))
        .replace(
            &format!("(node: {},", own + 1),
            &format!("(node: {},", n + 1),
        );
    let file = format!("assets/scenes/{}.ron", name.trim_end_matches(".ron"));
    match parse(&text, &format!("{file} on {n} elements")) {
        Ok(sc) if sc.model.beams.len() != n => None,
        parsed => Some(parsed),
    }
}

/// Parse a built-in scene by file name (with or without `.ron`).
pub fn builtin(name: &str) -> Option<Result<Scene, SceneError>> {
    let want = name.trim_end_matches(".ron");
    BUILTIN
        .iter()
        .find(|(f, _)| f.trim_end_matches(".ron") == want)
        .map(|(f, text)| parse(text, &format!("assets/scenes/{f}")))
}

/// A long beam of `n` elements 1 m long (the Mattiasson section: EI = 1, EA = 1e6), clamped at
/// one end, on roller supports every 100 elements and free at the other end, with a transverse
/// load at the middle of every span and at the tip (P L^2 / EI = 0.1 over a span).
///
/// A plain cantilever's stiffness matrix has a condition number growing like n^4 (1e20 at 1e5
/// elements: numerically a mechanism); the spans keep every size equally well conditioned, so
/// the timing measures the solver, not round-off trouble. Every span is loaded so that every
/// element does the same work: with the tip load alone, the response decays by a constant factor
/// per span and, beyond about 500 spans, falls below 1e-308, where subnormal arithmetic made
/// each operation many times slower (1.6 us per element per iteration at 10^5 elements against
/// 0.46 us with subnormals flushed to zero, session 4).
pub fn long_beam(n: usize) -> Scene {
    let len = n as f64;
    let span = n.min(100);
    let rollers: String = (1..n / span)
        .map(|k| format!(", (node: {}, v: true)", 1 + k * span))
        .collect();
    let loads: String = (0..n / span)
        .map(|k| format!("(node: {}, fy: -1.0), ", 1 + k * span + span / 2))
        .collect();
    let text = text("mattiasson")
        .expect("built-in")
        .replace(
            "(1.0, 0.0)], elements: 32",
            &format!("({len:?}, 0.0)], elements: {n}"),
        )
        .replace("phi: true)]", &format!("phi: true){rollers}]"))
        .replace(
            "loads: [(node: 33,",
            &format!("loads: [{loads}(node: {},", n + 1),
        );
    let mut sc = parse(&text, "long beam").expect("valid");
    sc.model.load_per_step = 0.1 / (span * span) as f64;
    sc.params.tolerance = 1e-5;
    sc
}

/// Open a scene by path, or (where no file of that name exists) a built-in by name: what the
/// CLI and the app accept wherever a scene is named.
pub fn open(name: &str) -> Result<Scene, SceneError> {
    let path = std::path::Path::new(name);
    if path.exists() {
        return load_file(path);
    }
    match builtin(name) {
        Some(r) => r,
        None => Err(SceneError {
            file: name.into(),
            line: None,
            field: "(file)".into(),
            message: "no such file and no built-in scene of that name (try `tsm-contact scenes`)"
                .into(),
        }),
    }
}
