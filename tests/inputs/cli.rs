//! The command line: output piped into a reader that stops early (`| head`) ends the program
//! quietly, with exit status 0 and nothing on stderr. The comb prints more than a pipe holds
//! (64 KiB), so the solver is still writing when the pipe closes. The report commands make their
//! output folder, and name it where it cannot be made. The history numbers contact elements as
//! the scene does. `figure` draws a state as a PNG of the asked size or an SVG. `check` audits
//! a history: nothing in a clean run, the pin through beam A in the stored history.

use std::io::{BufRead, BufReader};
use std::process::{Command, Stdio};

#[test]
fn solve_piped_into_head_exits_quietly() {
    let mut child = Command::new(env!("CARGO_BIN_EXE_tsm-contact"))
        .args(["solve", "comb"])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("runs");
    let mut first = String::new();
    {
        let mut out = BufReader::new(child.stdout.take().expect("stdout"));
        out.read_line(&mut first).expect("a line");
        // `out` dropped here: the pipe closes while the solver still prints.
    }
    let result = child.wait_with_output().expect("exits");
    assert!(first.starts_with("# "), "{first}");
    let stderr = String::from_utf8_lossy(&result.stderr);
    assert_eq!(result.status.code(), Some(0), "stderr: {stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
}

/// `bench --quick --out DIR` makes DIR (two levels that do not exist yet) and writes the CSV
/// there, one line per measured point after the header (40 points in the quick report: 5
/// problems, 2 formulations, 4 meshes). An output path below a regular file cannot be a folder:
/// exit status 2 and an error that names the path, before any measuring.
#[test]
fn bench_makes_its_output_folder_or_names_it() {
    let root = std::env::temp_dir().join(format!("tsm-bench-out-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&root);
    let out = root.join("reports").join("quick");
    let run = |out: &std::path::Path| {
        Command::new(env!("CARGO_BIN_EXE_tsm-contact"))
            .args(["bench", "--quick", "--out"])
            .arg(out)
            .output()
            .expect("runs")
    };
    let made = run(&out);
    let stderr = String::from_utf8_lossy(&made.stderr);
    assert_eq!(made.status.code(), Some(0), "stderr: {stderr}");
    let csv = std::fs::read_to_string(out.join("work-precision.csv")).expect("CSV written");
    assert_eq!(csv.lines().count(), 1 + 40, "{csv}");
    assert!(out.join("work-precision.svg").is_file());
    let file = root.join("a-file");
    std::fs::write(&file, "not a folder").expect("writable");
    let below = file.join("out");
    let refused = run(&below);
    let stderr = String::from_utf8_lossy(&refused.stderr);
    assert_eq!(refused.status.code(), Some(2), "stderr: {stderr}");
    assert!(
        stderr.contains("cannot make the output folder") && stderr.contains("a-file"),
        "{stderr}"
    );
    std::fs::remove_dir_all(&root).expect("cleaned up");
}

/// `solve` ends with the acceptance summary and writes each increment's `status` into the JSON
/// history: the pin on a cantilever converges to the tolerance in every increment (10 steps,
/// no cut-back), so the summary counts 10 converged, 0 at round-off, and every status is
/// "converged"; the exit status is 0.
#[test]
fn solve_summarises_how_each_increment_was_accepted() {
    let json = std::env::temp_dir().join(format!("tsm-status-{}.json", std::process::id()));
    let out = Command::new(env!("CARGO_BIN_EXE_tsm-contact"))
        .args(["solve", "pin_on_cantilever", "--json"])
        .arg(&json)
        .output()
        .expect("runs");
    assert_eq!(out.status.code(), Some(0));
    let text = String::from_utf8_lossy(&out.stdout);
    let history: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&json).expect("written")).expect("JSON");
    let _ = std::fs::remove_file(&json);
    let incs = history["increments"].as_array().expect("increments");
    let line = format!(
        "# {} increments converged, 0 accepted at round-off",
        incs.len()
    );
    assert!(text.contains(&line), "{text}");
    assert!(incs.iter().all(|r| r["status"] == "converged"), "{incs:?}");
}

/// The history names each contact's element by the scene's own numbering too: Example 3.2's
/// bodies A, B and C have 10 elements each, numbered in that order, so the element at global
/// index g on body k (0, 1, 2) is its body's element g - 10 k + 1.
#[test]
fn contacts_in_the_history_carry_their_place_in_their_body() {
    let json = std::env::temp_dir().join(format!("tsm-place-{}.json", std::process::id()));
    let out = Command::new(env!("CARGO_BIN_EXE_tsm-contact"))
        .args(["solve", "example_3_2", "--json"])
        .arg(&json)
        .output()
        .expect("runs");
    assert!(out.status.success());
    let history: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&json).expect("written")).expect("JSON");
    let mut seen = 0;
    for inc in history["increments"].as_array().unwrap() {
        for c in inc["contacts"].as_array().unwrap() {
            let body = ["A", "B", "C"]
                .iter()
                .position(|b| c["body"] == *b)
                .expect("a body of the scene") as u64;
            let g = c["element"].as_u64().unwrap();
            assert_eq!(c["place"].as_u64().unwrap(), g - 10 * body + 1, "{c}");
            seen += 1;
        }
    }
    assert!(seen > 50, "{seen} contacts");
    let _ = std::fs::remove_file(json);
}

/// `figure` writes the state after the steps without a window: a PNG of the asked size with the
/// beams drawn, an SVG with one path per body (Example 3.2 has three), and a clear error for a
/// size it cannot draw or a format it does not write.
#[cfg(feature = "figures")]
#[test]
fn figure_draws_the_state_as_a_png_of_the_asked_size_or_an_svg() {
    let dir = std::env::temp_dir().join(format!("tsm-cli-figure-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let run = |args: &[&str]| {
        Command::new(env!("CARGO_BIN_EXE_tsm-contact"))
            .args(args)
            .output()
            .expect("runs")
    };
    let png = dir.join("f.png");
    let p = png.to_str().unwrap();
    let r = run(&[
        "figure",
        "example_3_2",
        "--steps",
        "12",
        "--diagram",
        "m",
        "--out",
        p,
        "--size",
        "640x360",
    ]);
    assert_eq!(
        r.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&r.stderr)
    );
    let img = image::open(&png).unwrap().to_rgb8();
    assert_eq!(img.dimensions(), (640, 360));
    // The three beams, each about half the width long: at least 600 pixels of ink.
    let ink = img
        .pixels()
        .filter(|q| q.0.iter().all(|&c| c < 128))
        .count();
    assert!(ink > 600, "the beams are drawn: {ink} pixels of ink");
    let svg = dir.join("f.svg");
    let r = run(&[
        "figure",
        "example_3_2",
        "--steps",
        "12",
        "--out",
        svg.to_str().unwrap(),
    ]);
    assert_eq!(r.status.code(), Some(0));
    let text = std::fs::read_to_string(&svg).unwrap();
    assert_eq!(text.lines().filter(|l| l.starts_with("<path ")).count(), 3);
    let r = run(&["figure", "example_3_2", "--out", p, "--size", "10x10"]);
    assert_eq!(r.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&r.stderr).contains("--size 10x10"));
    let r = run(&[
        "figure",
        "example_3_2",
        "--out",
        dir.join("f.jpg").to_str().unwrap(),
    ]);
    assert_eq!(r.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&r.stderr).contains(".png or .svg"));
    let _ = std::fs::remove_dir_all(dir);
}

/// `check` on a history `solve` wrote: format version 2 with its topology, exit 0 and nothing
/// found. On the stored version 1 history of Example 3.2 driven 0.0098 m a step (the pin
/// through beam A at increment 13): exit 2 without `--scene` (no topology), and with it exit 1,
/// the line naming the increment, the node and the body.
#[test]
fn check_audits_a_history_and_names_what_is_wrong() {
    let json = std::env::temp_dir().join(format!("tsm-check-{}.json", std::process::id()));
    let tsm = || Command::new(env!("CARGO_BIN_EXE_tsm-contact"));
    let solved = tsm()
        .args(["solve", "example_3_2", "--json"])
        .arg(&json)
        .output()
        .expect("runs");
    assert_eq!(solved.status.code(), Some(0));
    let history: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&json).expect("written")).expect("JSON");
    assert_eq!(history["format_version"], 2);
    assert_eq!(
        history["topology"]["bodies"].as_array().map(Vec::len),
        Some(3)
    );
    let clean = tsm().arg("check").arg(&json).output().expect("runs");
    let _ = std::fs::remove_file(&json);
    let text = String::from_utf8_lossy(&clean.stdout);
    assert_eq!(clean.status.code(), Some(0), "{text}");
    assert!(
        text.contains("81 increment(s) audited, 0 finding(s)"),
        "{text}"
    );

    let fixture = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/fixtures/example_3_2_pin_through_a.json"
    );
    let bare = tsm().args(["check", fixture]).output().expect("runs");
    assert_eq!(bare.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&bare.stderr).contains("--scene"));
    let found = tsm()
        .args(["check", fixture, "--scene", "example_3_2"])
        .output()
        .expect("runs");
    let text = String::from_utf8_lossy(&found.stdout);
    assert_eq!(found.status.code(), Some(1), "{text}");
    assert!(
        text.lines()
            .any(|l| l.starts_with("increment 13: node 34 went through A element 9")),
        "{text}"
    );
}

/// `robust --per-scene 1` drives every built-in scene and family once, writes robustness.md into
/// its output folder with one row per built-in scene, and the audit finds nothing in what it
/// accepted.
#[cfg(feature = "reports")]
#[test]
fn robust_writes_a_row_per_scene_and_an_audit_count() {
    let out = std::env::temp_dir().join(format!("tsm-robust-{}", std::process::id()));
    let run = Command::new(env!("CARGO_BIN_EXE_tsm-contact"))
        .args(["robust", "--per-scene", "1", "--out"])
        .arg(&out)
        .output()
        .expect("runs");
    assert_eq!(run.status.code(), Some(0));
    let page = std::fs::read_to_string(out.join("robustness.md")).expect("written");
    let _ = std::fs::remove_dir_all(&out);
    let scenes = tsm_contact::scene::builtin::BUILTIN.len();
    let families = tsm_contact::reports::robust::FAMILIES.len();
    let drives = format!(
        "{} drives (1 per built-in scene and family",
        scenes + families
    );
    assert!(page.contains(&drives), "{page}");
    assert!(page.contains(", 0 audit finding(s)"), "{page}");
    for (file, _) in tsm_contact::scene::builtin::BUILTIN {
        let row = format!("| {} | 1 |", file.trim_end_matches(".ron"));
        assert!(page.contains(&row), "no row {row}");
    }
}

/// `robust --drive SEED` runs the one drive of the campaign with that seed and says how it
/// ends (exit 0: complete and audited); a seed no drive has is an error that names it.
#[cfg(feature = "reports")]
#[test]
fn robust_drive_reruns_one_drive_by_its_seed() {
    let drive = |seed: &str| {
        Command::new(env!("CARGO_BIN_EXE_tsm-contact"))
            .args(["robust", "--per-scene", "1", "--drive", seed])
            .output()
            .expect("runs")
    };
    let case = &tsm_contact::reports::robust::cases(1, 1)[0];
    let found = drive(&format!("{:#x}", case.seed));
    let text = String::from_utf8_lossy(&found.stdout);
    assert_eq!(found.status.code(), Some(0), "{text}");
    assert!(text.starts_with(&format!("{} ", case.scene)), "{text}");
    assert!(text.trim_end().ends_with("complete"), "{text}");
    let missing = drive("0x1");
    let err = String::from_utf8_lossy(&missing.stderr);
    assert_eq!(missing.status.code(), Some(1));
    assert!(
        err.contains("no drive of the campaign") && err.contains("0x1"),
        "{err}"
    );
    let bad = drive("zz");
    assert_eq!(
        bad.status.code(),
        Some(2),
        "{}",
        String::from_utf8_lossy(&bad.stderr)
    );
}

/// `solve` on a scene with stages names each stage as its first increment comes, prints every
/// load group's factor, makes the stages' steps (15: 5 + 10), and ends where the last stage
/// says; `figure` draws the state after the path.
#[test]
fn solve_and_figure_follow_the_stages() {
    let dir = std::env::temp_dir().join(format!("tsm-cli-stages-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let scene = dir.join("weight_then_pull.ron");
    std::fs::write(
        &scene,
        r#"(
    name: "weight, then a pull",
    sections: [(name: "s", E: 2.0e11, A: 1.0e-4, I: 3.3e-11, density: 7850.0)],
    bodies: [(name: "beam", section: "s", path: [(0.0, 0.0), (1.0, 0.0)], elements: 10, first_node: 1)],
    supports: [(node: 1, u: true, v: true, phi: true)],
    loads: [(node: 11, fy: 1.0, group: "pull")],
    control: (gravity: (0.0, -9.81)),
    stages: [
        (name: "weight", steps: 5, loads: [(group: "gravity", to: 1.0)]),
        (name: "pull", steps: 10, loads: [(group: "pull", to: 12.0)]),
    ],
)"#,
    )
    .unwrap();
    let json = dir.join("h.json");
    let out = Command::new(env!("CARGO_BIN_EXE_tsm-contact"))
        .args(["solve"])
        .arg(&scene)
        .arg("--json")
        .arg(&json)
        .output()
        .expect("runs");
    let text = String::from_utf8_lossy(&out.stdout);
    assert_eq!(out.status.code(), Some(0), "{text}");
    assert!(text.contains("# stage 1: weight (5 steps)"), "{text}");
    assert!(text.contains("# stage 2: pull (10 steps)"), "{text}");
    assert!(text.contains("15 steps"), "{text}");
    let h: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    let last = h["increments"].as_array().unwrap().last().unwrap().clone();
    assert_eq!(last["stage"], 1);
    assert_eq!(last["load_factors"][0].as_f64(), Some(12.0), "pull");
    assert_eq!(last["load_factors"][1].as_f64(), Some(1.0), "gravity");
    assert_eq!(h["topology"]["load_groups"][1], "gravity");
    let png = dir.join("f.png");
    let drawn = Command::new(env!("CARGO_BIN_EXE_tsm-contact"))
        .args(["figure"])
        .arg(&scene)
        .arg("--out")
        .arg(&png)
        .output()
        .expect("runs");
    assert_eq!(
        drawn.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&drawn.stderr)
    );
    assert!(png.is_file());
    let _ = std::fs::remove_dir_all(dir);
}
