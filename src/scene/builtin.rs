//! The built-in scenes, compiled into the binary from `assets/scenes/`.

use super::validate::{parse, Scene, SceneError};

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
