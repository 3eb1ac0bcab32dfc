//! The real `view --screenshot` run under Xvfb (the release-or-debug binary, wgpu on
//! `WGPU_BACKEND`, default Vulkan: Mesa's lavapipe in CI): the beams of Example 3.2 after 20
//! steps are drawn where a direct headless `Solver` run puts them (mapped to pixels through the
//! PNG's `.json` sidecar), empty space between the bodies stays background, and the convergence
//! plot shows the residual line.
#![cfg(feature = "gui")]

use std::path::{Path, PathBuf};
use std::process::Command;

use image::{Rgb, RgbImage};
use serde_json::Value;
use tsm_contact::scene::builtin::builtin;
use tsm_contact::solver::{IncrementRecord, Model, Silent};

const SCENE: &str = "example_3_2";
const STEPS: usize = 20;

/// Viewport background, ghost (undeformed shape) and residual line colours of `src/app`.
const BACKGROUND: [u8; 3] = [251, 251, 253];
const GHOST: [u8; 3] = [175, 178, 186];
const RESIDUAL: [u8; 3] = [40, 90, 170];

/// Whether `xvfb-run` is on PATH.
fn have_xvfb() -> bool {
    std::env::var_os("PATH")
        .is_some_and(|paths| std::env::split_paths(&paths).any(|d| d.join("xvfb-run").is_file()))
}

/// Whether the Xvfb tests can run: false (after saying so) only where `TSM_ALLOW_NO_XVFB=1`
/// allows skipping them; without xvfb-run otherwise, a failure naming what to install.
fn xvfb_or_skip() -> bool {
    if have_xvfb() {
        return true;
    }
    if std::env::var("TSM_ALLOW_NO_XVFB").as_deref() == Ok("1") {
        eprintln!("\n!!!!!! SKIPPED: xvfb-run is not on PATH (TSM_ALLOW_NO_XVFB=1) !!!!!!\n");
        return false;
    }
    panic!(
        "xvfb-run is not on PATH: install xvfb (apt-get install xvfb xauth; .ci/run does), \
         or set TSM_ALLOW_NO_XVFB=1 to skip this test"
    );
}

fn dist(a: [u8; 3], b: [u8; 3]) -> f64 {
    (0..3)
        .map(|i| (f64::from(a[i]) - f64::from(b[i])).powi(2))
        .sum::<f64>()
        .sqrt()
}

/// Distance of a colour from the moment colour map (slate at zero, red and blue at the ends;
/// `shapes::moment_color`).
fn from_colour_map(c: [u8; 3]) -> f64 {
    let zero = [70.0, 78.0, 92.0];
    let ends = [[214.0, 39.0, 40.0], [31.0, 119.0, 220.0]];
    let mut best = f64::INFINITY;
    for end in ends {
        for k in 0..=50 {
            let a = f64::from(k) / 50.0;
            let m: Vec<u8> = (0..3)
                .map(|i| (zero[i] + (end[i] - zero[i]) * a).round() as u8)
                .collect();
            best = best.min(dist(c, [m[0], m[1], m[2]]));
        }
    }
    best
}

/// A beam pixel: on the colour map, clearly neither background nor ghost.
fn beam_coloured(c: [u8; 3]) -> bool {
    from_colour_map(c) < 40.0 && dist(c, BACKGROUND) > 100.0 && dist(c, GHOST) > 80.0
}

/// The 3x3 neighbourhood of pixel (x, y).
fn around(img: &RgbImage, p: [f64; 2]) -> Vec<[u8; 3]> {
    let (x, y) = (p[0].round() as i64, p[1].round() as i64);
    let mut out = Vec::new();
    for dy in -1..=1 {
        for dx in -1..=1 {
            let (u, v) = (x + dx, y + dy);
            if u >= 0 && v >= 0 && (u as u32) < img.width() && (v as u32) < img.height() {
                let Rgb(c) = *img.get_pixel(u as u32, v as u32);
                out.push(c);
            }
        }
    }
    out
}

/// Render the screenshot into `dir`; returns the PNG's path.
fn render(dir: &Path) -> PathBuf {
    let png = dir.join("shot.png");
    let backend = std::env::var("WGPU_BACKEND").unwrap_or_else(|_| "vulkan".into());
    let out = Command::new("xvfb-run")
        .args(["-a", "-s", "-screen 0 1600x1000x24"])
        .arg(env!("CARGO_BIN_EXE_tsm-contact"))
        .args(["view", SCENE, "--steps", &STEPS.to_string(), "--screenshot"])
        .arg(&png)
        .env("WGPU_BACKEND", &backend)
        .output()
        .expect("run xvfb-run");
    assert!(
        out.status.success() && png.is_file(),
        "screenshot run failed ({}, WGPU_BACKEND={backend}):\n{}\n{}",
        out.status,
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    png
}

/// The last record of a direct headless run of the same steps, and the model.
fn reference() -> (Model, IncrementRecord) {
    let scene = builtin(SCENE).expect("built-in").expect("valid");
    let mut solver = scene.solver().expect("solver");
    let mut last = None;
    for _ in 0..STEPS {
        last = solver.step(&mut Silent).expect("converges").pop().or(last);
    }
    (scene.model, last.expect("at least one increment"))
}

/// Pixel rect `[xmin, ymin, xmax, ymax]` of a sidecar entry.
fn rect(v: &Value) -> [f64; 4] {
    let f = |k: &str, i: usize| v[k][i].as_f64().expect("rect corner");
    [f("min", 0), f("min", 1), f("max", 0), f("max", 1)]
}

/// Distance from `p` to segment a-b.
fn to_segment(p: [f64; 2], a: [f64; 2], b: [f64; 2]) -> f64 {
    let d = [b[0] - a[0], b[1] - a[1]];
    let len2 = (d[0] * d[0] + d[1] * d[1]).max(1e-30);
    let t = (((p[0] - a[0]) * d[0] + (p[1] - a[1]) * d[1]) / len2).clamp(0.0, 1.0);
    (p[0] - a[0] - t * d[0]).hypot(p[1] - a[1] - t * d[1])
}

#[test]
fn screenshot_shows_the_solver_state_where_the_sidecar_says() {
    if !xvfb_or_skip() {
        return;
    }
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR"))
        .join(format!("screenshot-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let png = render(&dir);
    let img = image::open(&png).expect("read the PNG").to_rgb8();
    let text = std::fs::read_to_string(dir.join("shot.png.json")).expect("read the sidecar");
    let side: Value = serde_json::from_str(&text).expect("sidecar JSON");

    let (model, r) = reference();
    assert_eq!(
        side["increment"].as_u64(),
        Some(r.increment as u64),
        "shown increment"
    );
    let scale = side["scale_px_per_m"].as_f64().expect("scale");
    let origin = [
        side["origin_px"][0].as_f64().expect("origin x"),
        side["origin_px"][1].as_f64().expect("origin y"),
    ];
    let px = |w: [f64; 2]| [origin[0] + scale * w[0], origin[1] - scale * w[1]];
    let vp = rect(&side["viewport"]);
    let inside = |p: [f64; 2]| p[0] > vp[0] && p[0] < vp[2] && p[1] > vp[1] && p[1] < vp[3];
    let at = |n: usize| [r.nodes[n][0], r.nodes[n][1]];

    // Points along every element's chord (the curve is within a pixel of it).
    let mut hits = 0;
    let mut misses = Vec::new();
    for (e, b) in model.beams.iter().enumerate() {
        let (a, c) = (at(b.i), at(b.j));
        for t in [0.25, 0.5, 0.75] {
            let p = px([a[0] + t * (c[0] - a[0]), a[1] + t * (c[1] - a[1])]);
            assert!(
                inside(p),
                "element {e} at {t} maps outside the viewport: {p:?}"
            );
            if around(&img, p).into_iter().any(beam_coloured) {
                hits += 1;
            } else {
                misses.push((e, t, p, around(&img, p)[4]));
            }
        }
    }
    let total = hits + misses.len();
    eprintln!("{hits} of {total} beam samples beam-coloured; misses: {misses:?}");
    assert!(
        hits * 10 >= total * 9,
        "only {hits} of {total} beam samples are beam-coloured; misses: {misses:?}"
    );

    // Midway between A (body 0) and C (body 2) near the clamps, far from everything drawn.
    let segments: Vec<([f64; 2], [f64; 2])> = model
        .beams
        .iter()
        .flat_map(|b| {
            let ghost = (model.position(b.i), model.position(b.j));
            [(px(at(b.i)), px(at(b.j))), (px(ghost.0), px(ghost.1))]
        })
        .collect();
    for k in [1, 2, 3] {
        let (ea, ec) = (model.bodies[0].elements[k], model.bodies[2].elements[k]);
        let (a, c) = (at(model.beams[ea].j), at(model.beams[ec].j));
        let p = px([(a[0] + c[0]) / 2.0, (a[1] + c[1]) / 2.0]);
        let clear = segments
            .iter()
            .map(|(s, t)| to_segment(p, *s, *t))
            .fold(f64::INFINITY, f64::min);
        assert!(
            inside(p) && clear > 25.0,
            "background probe {p:?} is {clear:.0} px from a beam"
        );
        for c in around(&img, p) {
            assert!(
                dist(c, BACKGROUND) < 8.0,
                "background probe {p:?} has colour {c:?}"
            );
        }
    }

    // The convergence plot draws the residual line.
    let plot = rect(&side["convergence_plot"]);
    let mut line = 0;
    for y in plot[1].ceil() as u32..plot[3].floor() as u32 {
        for x in plot[0].ceil() as u32..plot[2].floor() as u32 {
            let Rgb(c) = *img.get_pixel(x, y);
            line += usize::from(dist(c, RESIDUAL) < 30.0);
        }
    }
    eprintln!("{line} residual-coloured pixels in the convergence plot");
    assert!(
        line >= 200,
        "only {line} residual-coloured pixels in the plot {plot:?}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// A screenshot run that does not do its job exits with status 1 and says why: the scene named
/// does not exist (the picture, showing the error, is still saved).
#[test]
fn a_screenshot_run_whose_scene_does_not_load_fails() {
    if !xvfb_or_skip() {
        return;
    }
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("screenshot-missing-scene");
    std::fs::create_dir_all(&dir).unwrap();
    let png = dir.join("shot.png");
    let backend = std::env::var("WGPU_BACKEND").unwrap_or_else(|_| "vulkan".into());
    let out = Command::new("xvfb-run")
        .args(["-a", "-s", "-screen 0 1600x1000x24"])
        .arg(env!("CARGO_BIN_EXE_tsm-contact"))
        .args(["view", "no_such_scene", "--screenshot"])
        .arg(&png)
        .env("WGPU_BACKEND", &backend)
        .output()
        .expect("run xvfb-run");
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(err.contains("no such file and no built-in scene"), "{err}");
}
