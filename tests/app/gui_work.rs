//! Working in the app (egui_kittest on the real `TsmApp`): opening a scene through the path the
//! Open dialog's answer takes and by dropping it on the window, a bad file keeping the current
//! scene with its located error shown in full, start-up with a remembered scene that is gone,
//! branching at increment 20 of Example 3.2 and Undo bringing the old history back exactly, a
//! changed setting set aside and brought back, and the Ctrl shortcuts' files.
#![cfg(feature = "gui")]

use std::path::{Path, PathBuf};
use std::time::Duration;

use egui::{Key, Modifiers};
use egui_kittest::kittest::Queryable;
use egui_kittest::Harness;
use tsm_contact::app::{Startup, TsmApp};
use tsm_contact::scene::builtin::{builtin, open, BUILTIN};
use tsm_contact::solver::{IncrementRecord, Silent};

use crate::gui_support;
use gui_support::{label, loaded, shown_increment, solving, wait, CANTILEVER};

/// A folder of this test's own.
fn folder(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("tsm-gui-work-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn harness(startup: Startup) -> Harness<'static, TsmApp> {
    Harness::builder()
        .with_size([1400.0, 900.0])
        .wgpu()
        .build_eframe(move |cc| TsmApp::new(cc, startup))
}

/// Wait until the app shows scene `name` (the details panel's heading) at increment 0.
fn shows_scene(h: &mut Harness<'static, TsmApp>, name: &str) {
    wait(h, name, Duration::from_secs(30), |h| {
        h.query_by_label(name).is_some() && shown_increment(h) == Some((0, 0))
    });
}

/// Every record's results, wall time left out.
fn results(records: &[IncrementRecord]) -> Vec<String> {
    records
        .iter()
        .map(|r| {
            let mut r = r.clone();
            r.seconds = 0.0;
            format!("{r:?}")
        })
        .collect()
}

/// Solve `n` steps through the Run of `RunSteps`.
fn solve_steps(h: &mut Harness<'static, TsmApp>, n: usize) {
    h.state_mut()
        .worker_command(tsm_contact::worker::Command::RunSteps(n));
    wait(h, "the steps", Duration::from_secs(120), |h| {
        h.state().increments() >= n && !solving(h)
    });
    h.run_steps(2);
}

/// A scene file opened through the path the Open dialog's answer takes replaces the built-in
/// scene and joins the recent files; a file with an error in line 5 then leaves it in place and
/// shows the error with its file, line and field, whole, in the error panel.
#[test]
fn an_opened_file_replaces_the_scene_and_a_bad_one_keeps_it_with_its_error() {
    let dir = folder("open");
    let good = dir.join("cantilever.ron");
    std::fs::write(&good, CANTILEVER).unwrap();
    let mut h = harness(Startup::scene("example_3_2"));
    shows_scene(&mut h, "Example 3.2: three cantilevers and a pin");
    h.state_mut().open(&good.to_string_lossy());
    shows_scene(&mut h, "cantilever");
    let canonical = std::fs::canonicalize(&good).unwrap();
    assert_eq!(
        h.state().recent_files(),
        std::slice::from_ref(&canonical),
        "a recent file"
    );
    let bad = dir.join("bad.ron");
    let long_name = "x".repeat(2000);
    std::fs::write(
        &bad,
        CANTILEVER.replace("section: \"s\"", &format!("section: \"{long_name}\"")),
    )
    .unwrap();
    h.state_mut().open(&bad.to_string_lossy());
    h.run_steps(3);
    let e = h.state().error().expect("an error").to_string();
    assert!(
        e.contains("bad.ron") && e.contains("bodies[0].section"),
        "{e}"
    );
    assert!(e.contains(&long_name), "the error names the section whole");
    let shown = label(&h, &e[..40]).expect("the error panel shows it");
    assert_eq!(shown, e, "shown whole");
    assert!(h.query_by_label("Copy").is_some());
    assert!(h.query_by_label("cantilever").is_some(), "the scene stays");
    assert_eq!(h.state().scene_name(), good.to_string_lossy());
    assert_eq!(
        h.state().recent_files(),
        [canonical],
        "a file that fails is not recent"
    );
    let _ = std::fs::remove_dir_all(dir);
}

/// A file dropped on the window.
#[derive(Debug)]
struct Dropped(PathBuf);

impl egui::DroppedFile for Dropped {
    fn path(&self) -> &Path {
        &self.0
    }
    fn bytes(&self) -> Result<Vec<u8>, String> {
        std::fs::read(&self.0).map_err(|e| e.to_string())
    }
}

/// A .ron file dropped on the window is opened; another file is refused with the reason.
#[test]
fn a_scene_dropped_on_the_window_opens() {
    let dir = folder("drop");
    let path = dir.join("dropped.ron");
    std::fs::write(&path, CANTILEVER).unwrap();
    let mut h = harness(Startup::scene("example_3_2"));
    loaded(&mut h);
    let txt = dir.join("notes.txt");
    h.input_mut()
        .dropped_files
        .push(std::sync::Arc::new(Dropped(txt)));
    h.run_steps(2);
    assert!(h.state().error().is_some_and(|e| e.contains("not a scene")));
    h.input_mut()
        .dropped_files
        .push(std::sync::Arc::new(Dropped(path.clone())));
    h.step();
    shows_scene(&mut h, "cantilever");
    assert_eq!(h.state().scene_name(), path.to_string_lossy());
    let _ = std::fs::remove_dir_all(dir);
}

/// The remembered scene is gone: the app opens the default scene and says why.
#[test]
fn a_missing_remembered_scene_opens_the_default_and_says_why() {
    let mut h = harness(Startup {
        remembered: Some("/no/such/folder/gone.ron".into()),
        ..Startup::default()
    });
    shows_scene(&mut h, "Example 3.2: three cantilevers and a pin");
    let e = h.state().error().expect("the reason").to_string();
    assert!(
        e.contains("gone.ron") && e.contains("example_3_2 is open instead"),
        "{e}"
    );
    assert!(label(&h, "the last scene cannot be opened").is_some());
}

/// Example 3.2 solved to increment 30, viewed at 20 and its drive moved: the run goes on from
/// 20 (the increments 1 to 20 stay as they were, the new ones follow the new target), and
/// Ctrl+Z brings the old 30 increments and their events back exactly; Ctrl+Y brings the branch
/// back exactly, and Undo the old path again. Going on from there gives increment 31 exactly as
/// an unbroken run of 31 steps does.
#[test]
fn a_branch_at_increment_20_is_undone_exactly() {
    let mut h = harness(Startup::scene("example_3_2"));
    loaded(&mut h);
    solve_steps(&mut h, 30);
    let old = results(h.state().history());
    let old_events = h.state().events().to_vec();
    assert_eq!(old.len(), 31);
    h.get_by_role_and_label(egui::accesskit::Role::Slider, "Increment")
        .set_value_accesskit(20.0);
    h.run_steps(2);
    assert_eq!(shown_increment(&h), Some((20, 30)));
    h.get_by_role_and_label(egui::accesskit::Role::Slider, "node 34 v")
        .set_value_accesskit(-0.19);
    wait(&mut h, "the branch", Duration::from_secs(60), |h| {
        !solving(h)
            && h.state()
                .history()
                .last()
                .is_some_and(|r| (r.prescribed[0] + 0.19).abs() < 1e-12)
    });
    let branch = results(h.state().history());
    assert_eq!(branch[..21], old[..21], "increments 0 to 20 are kept");
    assert_ne!(branch[21..], old[21..], "the branch goes its own way");
    assert!(h.state().status().contains("going on from increment 20"));
    h.key_press_modifiers(Modifiers::COMMAND, Key::Z);
    wait(&mut h, "the undo", Duration::from_secs(30), |h| {
        h.state().increments() == 30 && !solving(h)
    });
    assert_eq!(results(h.state().history()), old);
    assert_eq!(h.state().events(), old_events);
    // Redo brings the branch back exactly, and Undo the old path again.
    h.key_press_modifiers(Modifiers::COMMAND, Key::Y);
    wait(&mut h, "the redo", Duration::from_secs(30), |h| {
        h.state().increments() == branch.len() - 1 && !solving(h)
    });
    assert_eq!(results(h.state().history()), branch);
    h.get_by_label("Undo").click();
    wait(&mut h, "the second undo", Duration::from_secs(30), |h| {
        h.state().increments() == 30 && !solving(h)
    });
    assert_eq!(results(h.state().history()), old);
    h.get_by_label("Next").click();
    wait(&mut h, "increment 31", Duration::from_secs(60), |h| {
        h.state().increments() == 31 && !solving(h)
    });
    let mut solver = builtin("example_3_2").unwrap().unwrap().solver().unwrap();
    let mut direct = Vec::new();
    for _ in 0..31 {
        direct.extend(solver.step(&mut Silent).unwrap());
    }
    assert_eq!(
        results(&h.state().history()[31..]),
        results(&direct[30..]),
        "the old path goes on as the unbroken run"
    );
}

/// Switching the element with a history starts again from increment 0; Undo brings the
/// Timoshenko run back exactly, and its element with it; Redo the Bernoulli-Euler one.
#[test]
fn a_changed_element_sets_the_run_aside_and_undo_brings_it_back() {
    let mut h = harness(Startup::scene("example_3_2"));
    loaded(&mut h);
    solve_steps(&mut h, 5);
    let old = results(h.state().history());
    h.get_by_label("Bernoulli-Euler").click();
    wait(&mut h, "the reload", Duration::from_secs(30), |h| {
        shown_increment(h) == Some((0, 0)) && h.state().status().contains("(BernoulliEuler)")
    });
    h.get_by_label("Undo").click();
    wait(&mut h, "the undo", Duration::from_secs(30), |h| {
        h.state().increments() == 5 && !solving(h) && !h.state().status().is_empty()
    });
    h.run_steps(3);
    assert_eq!(results(h.state().history()), old);
    assert!(h.query_by_label("Timoshenko").is_some());
    // Redo goes back to the Bernoulli-Euler run.
    h.get_by_label("Redo").click();
    wait(&mut h, "the redo", Duration::from_secs(30), |h| {
        h.state().status().contains("(BernoulliEuler)") && h.state().increments() == 0
    });
}

/// Ctrl+S writes the view's PNG at the size set in the Export menu, Ctrl+E the history as
/// JSON and CSV, each confirmed with its path; Ctrl+O opens the file dialog.
#[test]
fn ctrl_s_and_ctrl_e_write_their_files_and_ctrl_o_opens_the_dialog() {
    let dir = folder("keys");
    let stem = dir.join("run");
    let mut h = harness(Startup::scene("example_3_2"));
    loaded(&mut h);
    solve_steps(&mut h, 3);
    gui_support::export_as(&mut h, &stem);
    h.get_by_label("width").set_value_accesskit(640.0);
    h.get_by_label("height").set_value_accesskit(360.0);
    h.run_steps(2);
    // Close the menu (a click on the timeline's empty space), then the keys.
    h.key_press(Key::Escape);
    h.run_steps(2);
    h.key_press_modifiers(Modifiers::COMMAND, Key::S);
    h.run_steps(2);
    let png = std::fs::read(stem.with_extension("png")).expect("PNG written");
    let img = image::load_from_memory(&png).unwrap();
    assert_eq!((img.width(), img.height()), (640, 360));
    let rgb = img.to_rgb8();
    let dark = rgb.pixels().filter(|p| p.0.iter().all(|&c| c < 60)).count();
    assert!(dark > 300, "the beams are drawn: {dark} dark pixels");
    assert!(
        h.state().status().contains("run.png"),
        "{}",
        h.state().status()
    );
    h.key_press_modifiers(Modifiers::COMMAND, Key::E);
    h.run_steps(2);
    let json = std::fs::read_to_string(stem.with_extension("json")).expect("JSON written");
    let csv = std::fs::read_to_string(stem.with_extension("csv")).expect("CSV written");
    assert_eq!(csv.lines().count(), 4, "a header and three increments");
    assert!(json.contains("\"increments\""));
    assert_eq!(h.state().dialogs_shown(), 0);
    h.key_press_modifiers(Modifiers::COMMAND, Key::O);
    h.step();
    assert_eq!(h.state().dialogs_shown(), 1, "Ctrl+O shows the Open dialog");
    // Where no dialog can be shown (no desktop portal or zenity, as on CI), the app says so
    // and how to open a file instead.
    let t0 = std::time::Instant::now();
    while h.state().dialog_open() && t0.elapsed() < Duration::from_secs(2) {
        h.step();
        std::thread::sleep(Duration::from_millis(5));
    }
    if !h.state().dialog_open() && t0.elapsed() < Duration::from_millis(250) {
        assert!(
            h.state().status().contains("no file dialog can be shown"),
            "{}",
            h.state().status()
        );
    }
    let _ = std::fs::remove_dir_all(dir);
}

/// Save scene as writes a file that opens to the same model, for every built-in scene, and
/// with the element in use.
#[test]
fn a_saved_scene_opens_to_the_same_model() {
    let dir = folder("save");
    for (file, _) in BUILTIN {
        let name = file.trim_end_matches(".ron");
        let scene = builtin(name).unwrap().unwrap();
        let path = dir.join(file);
        tsm_contact::app::files::scenes::save_scene(&path, &scene).unwrap();
        let again = open(&path.to_string_lossy()).unwrap();
        assert_eq!(
            format!("{:?}", again.model),
            format!("{:?}", scene.model),
            "{name}"
        );
        assert_eq!(again.params, scene.params, "{name}");
    }
    let mut h = harness(Startup::scene("example_3_1"));
    loaded(&mut h);
    h.get_by_label("Bernoulli-Euler").click();
    wait(&mut h, "the reload", Duration::from_secs(30), |h| {
        h.state().status().contains("(BernoulliEuler)")
    });
    let path = dir.join("saved.ron");
    h.state_mut().save_scene_as(&path);
    assert!(h.state().status().starts_with("wrote "));
    let saved = open(&path.to_string_lossy()).unwrap();
    assert_eq!(
        saved.model.formulation,
        tsm_contact::solver::Formulation::BernoulliEuler
    );
    let _ = std::fs::remove_dir_all(dir);
}

/// A drive made in the app kept as the scene's path: Example 3.2 run 8 steps, then its pin
/// dragged down by uneven amounts and back up (as the handle sends its targets), "Keep the
/// drive as a path" in the File menu, the scene saved, read back from the file as a fresh start
/// would, and solved headless to the end of its path: every state the app showed comes back
/// bit for bit.
#[test]
fn a_drive_kept_in_the_app_replays_headless_from_the_saved_scene() {
    use tsm_contact::worker::Command;
    let dir = folder("kept");
    let mut h = harness(Startup::scene("example_3_2"));
    loaded(&mut h);
    solve_steps(&mut h, 8);
    let per_step = -0.01;
    for f in [11.3, 14.9, 13.2, 17.5, 9.1] {
        h.state_mut().worker_command(Command::SetTarget {
            index: 0,
            value: f * per_step,
        });
        h.run_steps(2);
        wait(&mut h, "the drag", Duration::from_secs(120), |h| {
            !solving(h)
        });
    }
    let shown: Vec<IncrementRecord> = h.state().history()[1..].to_vec();
    assert!(shown.len() > 20, "{} increments", shown.len());
    h.get_by_label("File").click();
    h.run_steps(2);
    h.get_by_label("Keep the drive as a path").click();
    h.run_steps(2);
    assert!(
        h.state().status().contains("kept as the scene's path"),
        "{}",
        h.state().status()
    );
    let path = dir.join("kept.ron");
    h.state_mut().save_scene_as(&path);
    assert!(h.state().status().starts_with("wrote "));
    let again = open(&path.to_string_lossy()).unwrap();
    let mut solver = again.solver().unwrap();
    let mut replay = Vec::new();
    for _ in 0..again.steps {
        replay.extend(solver.step(&mut Silent).unwrap());
    }
    assert_eq!(replay.len(), shown.len());
    for (a, b) in shown.iter().zip(&replay) {
        assert_eq!(a.nodes, b.nodes, "increment {}", a.increment);
        assert_eq!(a.prescribed, b.prescribed, "increment {}", a.increment);
    }
    let _ = std::fs::remove_dir_all(dir);
}
