//! The built-in scenes, compiled into the binary from `assets/scenes/`.

use super::format::{LoadDef, SupportDef};
use super::remesh::remesh;
use super::validate::{from_scene_file, load_file, parse, Scene, SceneError};

/// (file name, RON text) of every built-in scene, default first.
pub const BUILTIN: &[(&str, &str)] = &[
    (
        "example_3_2.ron",
        include_str!("../../assets/scenes/example_3_2.ron"),
    ),
    (
        "example_3_2_friction.ron",
        include_str!("../../assets/scenes/example_3_2_friction.ron"),
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
    (
        "heavy_strip.ron",
        include_str!("../../assets/scenes/heavy_strip.ron"),
    ),
    ("roller.ron", include_str!("../../assets/scenes/roller.ron")),
    (
        "cylinder_wrap.ron",
        include_str!("../../assets/scenes/cylinder_wrap.ron"),
    ),
    (
        "table_lift.ron",
        include_str!("../../assets/scenes/table_lift.ron"),
    ),
    (
        "rolled_past_a_turn.ron",
        include_str!("../../assets/scenes/rolled_past_a_turn.ron"),
    ),
    (
        "channel.ron",
        include_str!("../../assets/scenes/channel.ron"),
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

/// A built-in scene of one body (Mattiasson's cantilever, the end moment, the pin on a
/// cantilever, Lee's frame) divided into `n` elements per path segment instead of its own
/// (`remesh::remesh`). `None` for an unknown name or a scene that cannot be re-meshed so.
pub fn with_elements(name: &str, n: usize) -> Option<Result<Scene, SceneError>> {
    let scene = match builtin(name)? {
        Ok(scene) => scene,
        Err(e) => return Some(Err(e)),
    };
    let file = remesh(&scene.file, n)?;
    let label = format!(
        "assets/scenes/{}.ron on {n} elements",
        name.trim_end_matches(".ron")
    );
    Some(from_scene_file(file, &label))
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
/// per span and, beyond about 500 spans, falls below 1e-308, where subnormal arithmetic makes
/// each operation many times slower (about 1.6 us per element per iteration at 10^5 elements
/// against 0.46 us with subnormals flushed to zero).
pub fn long_beam(n: usize) -> Scene {
    let span = n.min(100);
    let mut file = builtin("mattiasson")
        .expect("built-in")
        .expect("valid")
        .file;
    file.bodies[0].path[1] = (n as f64, 0.0);
    file.bodies[0].elements = n;
    file.loads[0].node = n as u32 + 1;
    for k in 1..n / span {
        file.supports.push(SupportDef {
            node: (1 + k * span) as u32,
            u: false,
            v: true,
            phi: false,
        });
    }
    let spans = (0..n / span).map(|k| LoadDef {
        node: (1 + k * span + span / 2) as u32,
        fx: 0.0,
        fy: -1.0,
        m: 0.0,
        group: None,
    });
    file.loads.splice(0..0, spans);
    let mut sc = from_scene_file(file, "long beam").expect("valid");
    sc.model.load_per_step = 0.1 / (span * span) as f64;
    sc.params.tolerance = 1e-5;
    sc
}

/// Open a scene by path, or (where no file of that name exists) a built-in by name: what the
/// CLI and the app accept wherever a scene is named.
pub fn open(name: &str) -> Result<Scene, SceneError> {
    let path = std::path::Path::new(name);
    // A link that leads nowhere (or round a loop) is still a file the user named: reading it
    // says why it cannot be read.
    if std::fs::symlink_metadata(path).is_ok() {
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
