//! Input and output files: the history never overwrites the input scene, a symbolic link, a
//! FIFO or a folder, and a bad output path is refused before the run; a scene that is not a
//! regular file is refused before it is read; a byte-order mark is accepted; a tolerance out of
//! range is refused with the range.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use tsm_contact::scene::parse;

fn tsm(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_tsm-contact"))
        .args(args)
        .output()
        .expect("runs")
}

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("tsm-files-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn text(o: &Output) -> (String, String) {
    (
        String::from_utf8_lossy(&o.stdout).into_owned(),
        String::from_utf8_lossy(&o.stderr).into_owned(),
    )
}

/// An increment line of `solve` (it starts with the increment number).
fn increments(stdout: &str) -> usize {
    (stdout.lines())
        .filter(|l| {
            l.split_whitespace()
                .next()
                .is_some_and(|w| w.parse::<usize>().is_ok())
        })
        .count()
}

#[test]
fn the_history_never_overwrites_the_input_scene() {
    let dir = scratch("input");
    let scene = dir.join("m.ron");
    let original = tsm_contact::scene::builtin::text("mattiasson").unwrap();
    std::fs::write(&scene, original).unwrap();
    let s = scene.to_str().unwrap();
    let o = tsm(&["solve", s, "--json", s]);
    let (out, err) = text(&o);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(err.contains("input scene"), "{err}");
    assert_eq!(increments(&out), 0, "refused before the run");
    assert_eq!(std::fs::read_to_string(&scene).unwrap(), original);
}

#[cfg(unix)]
#[test]
fn links_fifos_folders_and_missing_folders_are_refused_before_the_run() {
    let dir = scratch("outputs");
    let target = dir.join("target.json");
    std::fs::write(&target, "keep").unwrap();
    let link = dir.join("link.json");
    std::os::unix::fs::symlink(&target, &link).unwrap();
    let fifo = dir.join("fifo");
    assert!(Command::new("mkfifo")
        .arg(&fifo)
        .status()
        .unwrap()
        .success());
    let cases: [(&Path, &str); 4] = [
        (&link, "symbolic link"),
        (&fifo, "not a regular file"),
        (&dir, "not a regular file"),
        (&dir.join("missing/h.json"), "does not exist"),
    ];
    for (path, why) in cases {
        let o = tsm(&["solve", "mattiasson", "--json", path.to_str().unwrap()]);
        let (out, err) = text(&o);
        assert_eq!(o.status.code(), Some(2), "{}: {err}", path.display());
        assert!(err.contains(why), "{}: {err}", path.display());
        assert_eq!(
            increments(&out),
            0,
            "{}: refused before the run",
            path.display()
        );
    }
    assert_eq!(std::fs::read_to_string(&target).unwrap(), "keep");
    assert!(std::fs::symlink_metadata(&link)
        .unwrap()
        .file_type()
        .is_symlink());
    let leftovers: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .filter_map(|e| e.ok())
        .filter(|e| e.file_name().to_string_lossy().ends_with(".tmp"))
        .collect();
    assert!(leftovers.is_empty(), "{leftovers:?}");
}

/// `/dev/zero` would be read without end: a scene that is not a regular file is refused at
/// once.
#[cfg(unix)]
#[test]
fn a_scene_that_is_not_a_regular_file_is_refused_before_it_is_read() {
    let started = std::time::Instant::now();
    let o = tsm(&["solve", "/dev/zero"]);
    let (_, err) = text(&o);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(err.contains("not a regular file"), "{err}");
    assert!(started.elapsed().as_secs() < 10);
}

#[test]
fn a_byte_order_mark_is_not_part_of_the_scene() {
    let text = tsm_contact::scene::builtin::text("mattiasson").unwrap();
    let plain = parse(text, "plain").expect("valid");
    let marked = parse(&format!("\u{feff}{text}"), "marked").expect("valid with a BOM");
    assert_eq!(plain.model, marked.model);
}

#[test]
fn a_tolerance_out_of_range_is_refused_with_the_range() {
    let text = tsm_contact::scene::builtin::text("mattiasson").unwrap();
    for (field, value) in [
        ("tolerance", "1e10"),
        ("roundoff_bound", "0.5"),
        ("tolerance", "0.0"),
    ] {
        let bad = text.replace(
            "control: (steps: 10,",
            &format!("control: ({field}: {value}, steps: 10,"),
        );
        assert_ne!(bad, text, "the control line is where it was");
        let e = parse(&bad, "bad.ron")
            .expect_err("out of range")
            .to_string();
        assert!(
            e.contains(&format!("control.{field}")) && e.contains("must lie in (0e0, 1e-2]"),
            "{e}"
        );
    }
    let fine = text.replace(
        "control: (steps: 10,",
        "control: (tolerance: 1e-6, steps: 10,",
    );
    assert!(parse(&fine, "fine.ron").is_ok());
}

/// The history is streamed: the file written as the run goes is `History`'s JSON (read back
/// whole, it holds every increment `solve` printed and every event), and a writer dropped
/// unfinished leaves neither the file nor its temporary beside it.
#[test]
fn the_history_is_streamed_and_an_unfinished_one_leaves_nothing() {
    use tsm_contact::history::{History, HistoryWriter};
    let dir = scratch("stream");
    let path = dir.join("h.json");
    let o = tsm(&[
        "solve",
        "example_3_2",
        "--steps",
        "15",
        "--json",
        path.to_str().unwrap(),
    ]);
    let (out, err) = text(&o);
    assert_eq!(o.status.code(), Some(0), "{err}");
    let h: History = serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
    assert_eq!(h.increments.len(), increments(&out));
    assert_eq!(h.increments.len(), 15);
    assert!(h
        .increments
        .windows(2)
        .all(|w| w[1].increment == w[0].increment + 1));
    assert_eq!(h.events.len(), out.matches("event:").count());
    assert!(h.error.is_none());
    let other = dir.join("unfinished.json");
    let w = HistoryWriter::create(&other, &History::default(), 1 << 30).unwrap();
    drop(w);
    let left: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .filter_map(|e| e.ok())
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .filter(|n| n.contains("unfinished"))
        .collect();
    assert!(left.is_empty(), "{left:?}");
}

/// The names in `dir`, sorted.
fn names(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = (std::fs::read_dir(dir).unwrap())
        .filter_map(|e| e.ok())
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

/// A link put where a history's temporary file was once named (`OUT.tmp`, pointing at another
/// file) is never written through: the history goes to a fresh name of its own, created
/// exclusively, and lands whole at `OUT`; the file the link points to keeps its contents, and no
/// temporary file is left.
#[cfg(unix)]
#[test]
fn a_link_beside_the_output_is_never_written_through() {
    let dir = scratch("link-tmp");
    let victim = dir.join("victim.txt");
    std::fs::write(&victim, "keep me").unwrap();
    let out = dir.join("h.json");
    std::os::unix::fs::symlink(&victim, dir.join("h.json.tmp")).unwrap();
    let o = tsm(&[
        "solve",
        "example_3_1",
        "--steps",
        "3",
        "--json",
        out.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(0), "{:?}", text(&o));
    assert_eq!(std::fs::read_to_string(&victim).unwrap(), "keep me");
    let h: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&out).unwrap()).unwrap();
    assert_eq!(h["increments"].as_array().unwrap().len(), 3);
    assert_eq!(names(&dir), ["h.json", "h.json.tmp", "victim.txt"]);
    let _ = std::fs::remove_dir_all(dir);
}

/// Two runs writing the same history at once, five times over: both succeed, and the file is
/// always one whole history (each writes its own temporary file and renames it into place).
#[test]
fn two_runs_writing_one_history_at_once_leave_it_whole() {
    let dir = scratch("concurrent");
    let out = dir.join("h.json");
    for _ in 0..5 {
        let spawn = || {
            Command::new(env!("CARGO_BIN_EXE_tsm-contact"))
                .args(["solve", "example_3_2", "--steps", "20", "--json"])
                .arg(&out)
                .stdout(std::process::Stdio::null())
                .spawn()
                .expect("runs")
        };
        let (mut a, mut b) = (spawn(), spawn());
        assert!(a.wait().unwrap().success());
        assert!(b.wait().unwrap().success());
        let h: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(&out).unwrap()).expect("whole JSON");
        assert_eq!(h["increments"].as_array().unwrap().len(), 20);
        assert_eq!(names(&dir), ["h.json"], "no temporary file left");
    }
    let _ = std::fs::remove_dir_all(dir);
}

/// SIGINT, SIGTERM and SIGHUP stop a long run at its next increment: the unfinished history is
/// removed (no file is left in its folder), and the exit status is 128 plus the signal
/// (130, 143, 129).
#[cfg(unix)]
#[test]
fn a_signal_stops_the_run_and_leaves_no_file() {
    use std::io::{BufRead, BufReader};
    for (signal, code) in [("INT", 130), ("TERM", 143), ("HUP", 129)] {
        let dir = scratch(&format!("signal-{signal}"));
        let out = dir.join("h.json");
        let mut child = Command::new(env!("CARGO_BIN_EXE_tsm-contact"))
            .args(["solve", "mattiasson", "--steps", "100000000", "--json"])
            .arg(&out)
            .stdout(std::process::Stdio::piped())
            .stderr(std::process::Stdio::piped())
            .spawn()
            .expect("runs");
        let mut lines = BufReader::new(child.stdout.take().unwrap()).lines();
        // Well into the run: past the header and a few increments.
        for _ in 0..6 {
            lines.next().expect("a line").unwrap();
        }
        let killed = Command::new("kill")
            .args([&format!("-{signal}"), &child.id().to_string()])
            .status()
            .unwrap();
        assert!(killed.success());
        // Keep reading, so that the run is never blocked on a full pipe.
        for _ in lines {}
        let status = child.wait().unwrap();
        let mut err = String::new();
        std::io::Read::read_to_string(&mut child.stderr.take().unwrap(), &mut err).unwrap();
        assert_eq!(status.code(), Some(code), "SIG{signal}: {err}");
        assert!(err.contains(&format!("stopped by SIG{signal}")), "{err}");
        assert!(
            names(&dir).is_empty(),
            "SIG{signal}: left {:?}",
            names(&dir)
        );
        let _ = std::fs::remove_dir_all(dir);
    }
}

/// A history that would take more than `--max-output` bytes stops the run at that increment
/// with an error naming the limit; nothing is left behind.
#[test]
fn a_history_beyond_its_bound_stops_the_run() {
    let dir = scratch("max-output");
    let out = dir.join("h.json");
    let o = tsm(&[
        "solve",
        "mattiasson",
        "--steps",
        "1000",
        "--max-output",
        "20000",
        "--json",
        out.to_str().unwrap(),
    ]);
    let (stdout, stderr) = text(&o);
    assert_eq!(o.status.code(), Some(2), "{stderr}");
    assert!(
        stderr.contains("would take more than 20000 bytes"),
        "{stderr}"
    );
    let solved = increments(&stdout);
    assert!(solved > 0 && solved < 1000, "stopped at once: {solved}");
    assert!(names(&dir).is_empty(), "left {:?}", names(&dir));
    let _ = std::fs::remove_dir_all(dir);
}

/// `control: (steps: 0)` is refused at its line: a run needs at least one step.
#[test]
fn zero_steps_are_refused() {
    let text = r#"(
    name: "no steps",
    sections: [(name: "s", E: 1.0, A: 1.0, I: 1.0)],
    bodies: [(name: "b", section: "s", path: [(0.0, 0.0), (1.0, 0.0)], elements: 2, first_node: 1)],
    supports: [(node: 1, u: true, v: true, phi: true)],
    loads: [(node: 3, fy: -1.0)],
    control: (steps: 0),
)"#;
    let e = parse(text, "steps.ron").expect_err("refused");
    assert_eq!(e.field, "control.steps");
    assert_eq!(e.line, Some(7), "{e}");
    assert!(e.message.contains("at least one step"), "{e}");
}

/// A scene named through a link that loops is refused with the reason the system gives (too
/// many levels of links), not as a file that does not exist.
#[cfg(unix)]
#[test]
fn a_link_loop_is_not_called_missing() {
    let dir = scratch("loop");
    let (a, b) = (dir.join("a.ron"), dir.join("b.ron"));
    std::os::unix::fs::symlink(&b, &a).unwrap();
    std::os::unix::fs::symlink(&a, &b).unwrap();
    let o = tsm(&["solve", a.to_str().unwrap()]);
    let (_, stderr) = text(&o);
    assert_eq!(o.status.code(), Some(2), "{stderr}");
    assert!(stderr.contains("symbolic links"), "{stderr}");
    assert!(!stderr.contains("no such file"), "{stderr}");
    let _ = std::fs::remove_dir_all(dir);
}

/// `--every 5` on 12 increments keeps increments 5 and 10 and the last, 12, each the same
/// record as the full history's (JSON text for JSON text), and says so in the file; `check`
/// audits what it can of it and says it cannot judge pass-through. `--every 0` is refused.
#[test]
fn a_thinned_history_keeps_every_nth_increment_and_the_last_and_says_so() {
    let dir = scratch("every");
    let (full, thin) = (dir.join("full.json"), dir.join("thin.json"));
    for (path, every) in [(&full, None), (&thin, Some("5"))] {
        let mut args = vec!["solve", "example_3_2", "--steps", "12"];
        args.extend(["--json", path.to_str().unwrap()]);
        if let Some(n) = every {
            args.extend(["--every", n]);
        }
        let o = tsm(&args);
        assert_eq!(o.status.code(), Some(0), "{}", text(&o).1);
    }
    let read = |p: &Path| -> serde_json::Value {
        serde_json::from_str(&std::fs::read_to_string(p).unwrap()).unwrap()
    };
    let (full_h, thin_h) = (read(&full), read(&thin));
    assert_eq!(thin_h["every"], 5);
    assert!(full_h.get("every").is_none());
    let kept: Vec<&serde_json::Value> = thin_h["increments"].as_array().unwrap().iter().collect();
    let numbers: Vec<u64> = kept
        .iter()
        .map(|r| r["increment"].as_u64().unwrap())
        .collect();
    assert_eq!(numbers, [5, 10, 12]);
    // The same record but for its wall time.
    let timeless = |r: &serde_json::Value| {
        let mut r = r.clone();
        r.as_object_mut().unwrap().remove("seconds");
        r
    };
    for r in kept {
        let k = r["increment"].as_u64().unwrap() as usize;
        let whole = &full_h["increments"][k - 1];
        assert!(timeless(r) == timeless(whole), "increment {k}");
    }
    let o = tsm(&["check", thin.to_str().unwrap()]);
    let (stdout, stderr) = text(&o);
    assert_eq!(o.status.code(), Some(0), "{stdout}{stderr}");
    assert!(
        stdout.contains("3 increment(s) audited, 0 finding(s)"),
        "{stdout}"
    );
    assert!(stdout.contains("pass-through is not checked"), "{stdout}");
    let o = tsm(&["check", full.to_str().unwrap()]);
    assert!(!text(&o).0.contains("pass-through is not checked"));
    let o = tsm(&["solve", "example_3_2", "--every", "0"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(text(&o).1.contains("--every"), "{}", text(&o).1);
    let _ = std::fs::remove_dir_all(dir);
}
