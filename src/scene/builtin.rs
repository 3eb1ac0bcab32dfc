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

/// Parse a built-in scene by file name (with or without `.ron`).
pub fn builtin(name: &str) -> Option<Result<Scene, SceneError>> {
    let want = name.trim_end_matches(".ron");
    BUILTIN
        .iter()
        .find(|(f, _)| f.trim_end_matches(".ron") == want)
        .map(|(f, text)| parse(text, &format!("assets/scenes/{f}")))
}
