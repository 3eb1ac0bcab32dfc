//! The visualiser driven through its accessibility tree (egui_kittest, the real `TsmApp` on the
//! built-in Example 3.2, wgpu on whatever adapter exists, Mesa's lavapipe in CI): Step clicks
//! advance the shown increment one by one, the shown residual is below the tolerance, the shown
//! number of active contacts matches a direct headless `Solver` run, the "Increment" slider
//! selects earlier states, and the rendered viewport shows the moment-coloured beams on both
//! the wgpu path and the egui-painter fallback.
#![cfg(feature = "gui")]

use std::time::Duration;

use egui_kittest::kittest::{NodeT, Queryable};
use egui_kittest::Harness;
use tsm_contact::app::TsmApp;
use tsm_contact::scene::builtin::builtin;
use tsm_contact::solver::{IncrementRecord, IncrementStatus, Silent};

use crate::gui_support;
use gui_support::{
    harness_on, harness_sized, label, loaded, shown_increment, solving, wait, wait_each,
};

const SCENE: &str = "example_3_2";

fn harness(no_gpu: bool) -> Harness<'static, TsmApp> {
    harness_on(SCENE, no_gpu)
}

/// Where the details panel starts (the y of its "Increment k / n" line), and whether the app
/// shows that it is solving: the panels sit under the top bar, so this moves if the bar does.
fn panel_top(h: &Harness<'static, TsmApp>) -> (bool, f32) {
    let top = h
        .query_all_by_label_contains("Increment ")
        .find(|n| {
            let a = n.accesskit_node();
            a.label()
                .or_else(|| a.value())
                .is_some_and(|l| l.contains(" / "))
        })
        .map_or(f32::NAN, |n| n.rect().min.y);
    (solving(h), top)
}

/// The details panel's residual line for record `r`: "(converged)" within the tolerance, the
/// round-off acceptance or the snap spelled out otherwise.
fn residual_label(r: &IncrementRecord) -> String {
    match r.status {
        IncrementStatus::Converged => format!("residual {:.1e} (converged)", r.relative_residual),
        IncrementStatus::RoundOff { ratio } => format!(
            "residual {:.1e}: accepted at the round-off floor, {ratio:.0} x the tolerance",
            r.relative_residual
        ),
        IncrementStatus::Snapping { residual } => {
            format!("residual {residual:.1e}: on the way of a snap, not in equilibrium")
        }
    }
}

/// The number after a label prefix, e.g. "residual 3.2e-11" -> 3.2e-11.
fn shown_number(h: &Harness<'static, TsmApp>, prefix: &str) -> f64 {
    let text = label(h, prefix).unwrap_or_else(|| panic!("no label starting with {prefix:?}"));
    text[prefix.len()..]
        .split_whitespace()
        .next()
        .unwrap_or_default()
        .trim_end_matches(':')
        .parse()
        .unwrap_or_else(|e| panic!("{text:?}: {e}"))
}

/// A direct headless run of the same scene: the records of the first `steps` steps.
fn reference(steps: usize) -> Vec<IncrementRecord> {
    direct(&builtin(SCENE).unwrap().unwrap(), steps)
}

/// A direct headless run of `scene`: the records of its first `steps` steps.
fn direct(scene: &tsm_contact::scene::Scene, steps: usize) -> Vec<IncrementRecord> {
    let mut solver = scene.solver().unwrap();
    let mut out = Vec::new();
    for _ in 0..steps {
        out.extend(solver.step(&mut Silent).unwrap());
    }
    out
}

/// Click Run and wait until every step of `steps` is shown.
fn run_all(h: &mut Harness<'static, TsmApp>, steps: usize, limit: Duration) {
    h.get_by_label("Run").click();
    wait(h, "the run", limit, |h| {
        shown_increment(h).is_some_and(|(k, n)| k == n && n >= steps)
    });
}

#[test]
fn step_clicks_advance_the_increment_counter() {
    let mut h = harness(false);
    loaded(&mut h);
    let tolerance = builtin(SCENE).unwrap().unwrap().params.tolerance;
    let clicks = 8;
    for k in 1..=clicks {
        h.get_by_label("Next").click();
        wait(&mut h, "the next increment", Duration::from_secs(60), |h| {
            shown_increment(h) == Some((k, k))
        });
        let residual = shown_number(&h, "residual ");
        assert!(
            residual <= tolerance,
            "increment {k}: shown residual {residual}"
        );
    }
    let reference = reference(clicks);
    assert_eq!(
        reference.len(),
        clicks,
        "the reference run cut back; the test assumes one increment per step"
    );
    let last = reference.last().unwrap();
    assert_eq!(
        shown_number(&h, "Active contacts: ") as usize,
        last.contacts.len()
    );
    assert!(
        !last.contacts.is_empty(),
        "Example 3.2 touches within {clicks} steps"
    );
    assert_eq!(label(&h, "residual ").unwrap(), residual_label(last));
}

#[test]
fn increment_slider_and_step_back_select_earlier_states() {
    let mut h = harness(false);
    loaded(&mut h);
    let steps = 14;
    h.state_mut()
        .worker_command(tsm_contact::worker::Command::RunSteps(steps));
    wait(&mut h, "the run", Duration::from_secs(120), |h| {
        shown_increment(h).is_some_and(|(_, n)| n >= steps)
    });
    let reference = reference(steps);
    let n = reference.len();
    assert_eq!(shown_increment(&h), Some((n, n)));
    for pick in [3, 9, 12] {
        h.get_by_role_and_label(egui::accesskit::Role::Slider, "Increment")
            .set_value_accesskit(pick as f64);
        wait(&mut h, "the selection", Duration::from_secs(10), |h| {
            shown_increment(h) == Some((pick, n))
        });
        let r = &reference[pick - 1];
        assert_eq!(
            shown_number(&h, "Active contacts: ") as usize,
            r.contacts.len(),
            "increment {pick}"
        );
        assert_eq!(label(&h, "residual ").unwrap(), residual_label(r));
    }
    h.get_by_label("Previous").click();
    wait(&mut h, "step back", Duration::from_secs(10), |h| {
        shown_increment(h) == Some((11, n))
    });
}

/// Pixels in the viewport that are clearly moment-coloured (red or blue dominant).
fn coloured_pixels(h: &mut Harness<'static, TsmApp>) -> usize {
    let img = h.render().expect("render");
    let (w, ht) = img.dimensions();
    // The viewport is the upper left part (right panel ~330 px, bottom panel ~300 px).
    let mut count = 0;
    for y in 60..(ht - 340) {
        for x in 220..(w - 360) {
            let p = img.get_pixel(x, y).0;
            let (r, g, b) = (i32::from(p[0]), i32::from(p[1]), i32::from(p[2]));
            if (r - g > 60 && r - b > 60) || (b - r > 60 && b - g > 20) {
                count += 1;
            }
        }
    }
    count
}

#[test]
fn beams_are_drawn_on_the_gpu_and_by_the_fallback() {
    let mut counts = Vec::new();
    for no_gpu in [false, true] {
        let mut h = harness(no_gpu);
        assert_eq!(h.state().uses_gpu(), !no_gpu);
        loaded(&mut h);
        h.state_mut()
            .worker_command(tsm_contact::worker::Command::RunSteps(20));
        wait(&mut h, "the run", Duration::from_secs(120), |h| {
            shown_increment(h).is_some_and(|(_, n)| n >= 20)
        });
        for _ in 0..3 {
            h.step();
        }
        counts.push(coloured_pixels(&mut h));
    }
    // Three bent cantilevers, 6 px wide: thousands of coloured pixels either way, and the two
    // paths draw the same strips.
    assert!(
        counts[0] > 3000,
        "wgpu path drew {} coloured pixels",
        counts[0]
    );
    let ratio = counts[0] as f64 / counts[1] as f64;
    assert!(
        (0.8..1.25).contains(&ratio),
        "wgpu {} vs fallback {}",
        counts[0],
        counts[1]
    );
}

#[test]
fn formulation_toggle_reloads_and_exports_write_the_shown_run() {
    // Mattiasson's cantilever (load control) starts Bernoulli-Euler; switch it to Timoshenko.
    let mut h = harness_on("mattiasson", false);
    loaded(&mut h);
    h.get_by_label("Next").click();
    wait(&mut h, "increment 1", Duration::from_secs(60), |h| {
        shown_increment(h) == Some((1, 1))
    });
    h.get_by_label("Timoshenko").click();
    wait(&mut h, "the reload", Duration::from_secs(30), |h| {
        h.query_by_label_contains("(Timoshenko)").is_some() && shown_increment(h) == Some((0, 0))
    });
    let mut scene = builtin("mattiasson").unwrap().unwrap();
    run_all(&mut h, scene.steps, Duration::from_secs(120));
    // Independent reference: the same scene solved directly with the Timoshenko element.
    scene.model.formulation = tsm_contact::solver::Formulation::Timoshenko;
    let reference = direct(&scene, scene.steps);
    let n = reference.len();
    assert_eq!(shown_increment(&h), Some((n, n)));
    let last = reference.last().unwrap();
    assert_eq!(label(&h, "residual ").unwrap(), residual_label(last));

    let dir = std::env::temp_dir().join(format!("tsm-gui-test-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let stem = dir.join("run");
    gui_support::export_as(&mut h, &stem);
    gui_support::export(&mut h, "Export CSV");
    gui_support::export(&mut h, "Export JSON");
    let csv = std::fs::read_to_string(stem.with_extension("csv")).expect("CSV written");
    let rows: Vec<&str> = csv.lines().collect();
    assert!(rows[0].starts_with("increment,load_factor,"), "{}", rows[0]);
    assert_eq!(rows.len(), 1 + n);
    for (row, r) in rows[1..].iter().zip(&reference) {
        let cells: Vec<&str> = row.split(',').collect();
        assert_eq!(cells[0].parse::<usize>().unwrap(), r.increment);
        assert!((cells[1].parse::<f64>().unwrap() - r.load_factor).abs() < 1e-12);
    }
    let json = std::fs::read_to_string(stem.with_extension("json")).expect("JSON written");
    // Read as plain JSON: the params hold f64::INFINITY (max_step), written as null.
    let history: serde_json::Value = serde_json::from_str(&json).unwrap();
    assert_eq!(history["formulation"], "Timoshenko");
    let incs = history["increments"].as_array().unwrap();
    assert_eq!(incs.len(), n);
    let nodes: Vec<[f64; 3]> = serde_json::from_value(incs[n - 1]["nodes"].clone()).unwrap();
    for (a, b) in nodes.iter().zip(&last.nodes) {
        assert!(
            (0..3).all(|i| (a[i] - b[i]).abs() < 1e-12),
            "{a:?} vs {b:?}"
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// The shown value of the prescribed dof ("node 34 v = -0.04300").
fn shown_prescribed(h: &Harness<'static, TsmApp>) -> f64 {
    shown_number(h, "node 34 v = ")
}

#[test]
fn slider_and_handle_drive_the_prescribed_dof() {
    let mut h = harness(false);
    loaded(&mut h);
    let per_step = builtin(SCENE).unwrap().unwrap().model.prescribed[0]
        .per_step
        .abs();
    // Where the panels start, in every frame, busy or not (checked at the end).
    let mut tops = vec![panel_top(&h)];

    // The slider: -0.043 needs ceil(4.3) = 5 increments of at most |per_step|.
    let target = -0.043;
    h.get_by_role_and_label(egui::accesskit::Role::Slider, "node 34 v")
        .set_value_accesskit(target);
    wait_each(
        &mut h,
        "the march to the slider target",
        Duration::from_secs(60),
        |h| {
            shown_increment(h).is_some_and(|(k, n)| k == n && n > 0)
                && (shown_prescribed(h) - target).abs() < 1e-9
                && !solving(h)
        },
        |h| tops.push(panel_top(h)),
    );
    let (_, n) = shown_increment(&h).unwrap();
    assert_eq!(n, (target.abs() / per_step).ceil() as usize);

    // The handle: drag it 60 points down; the node follows until it sits under the pointer.
    let handle = "drag to set the target of this prescribed dof";
    let start = h.get_by_label(handle).rect().center();
    let end = start + egui::vec2(0.0, 60.0);
    h.hover_at(start);
    h.step();
    h.drag_at(start);
    h.step();
    for k in 1..=6 {
        h.hover_at(start + egui::vec2(0.0, 10.0 * k as f32));
        h.step();
        tops.push(panel_top(&h));
    }
    h.drop_at(end);
    h.step();
    wait_each(
        &mut h,
        "the march to the handle",
        Duration::from_secs(60),
        |h| {
            h.query_by_label_contains("(Timoshenko)").is_some()
                && shown_increment(h).is_some_and(|(k, m)| k == m && m > n)
                && (h.get_by_label(handle).rect().center().y - end.y).abs() < 1.0
                && h.state().increments() == shown_increment(h).unwrap().1
                && !solving(h)
        },
        |h| tops.push(panel_top(h)),
    );
    let reached = shown_prescribed(&h);
    assert!(
        reached < target - 2.0 * per_step,
        "the drag moved the target to {reached}"
    );
    let (_, m) = shown_increment(&h).unwrap();
    let needed = ((reached - target).abs() / per_step - 1e-9).ceil() as usize;
    assert!(
        m - n >= needed,
        "{} increments for {}",
        m - n,
        reached - target
    );

    // The top bar keeps its height while the solver runs (the beams and the handle under the
    // pointer must not jump): the panels start at the same y in every frame, busy or not.
    let busy_frames = tops.iter().filter(|t| t.0).count();
    eprintln!(
        "{busy_frames} of {} frames showed the solver busy",
        tops.len()
    );
    let y0 = tops[0].1;
    assert!(y0.is_finite(), "no details panel");
    for (busy, y) in &tops {
        assert!(
            (y - y0).abs() < 0.5,
            "panels start at {y} (solving: {busy}), at {y0} at first"
        );
    }
}

/// In a narrow window (1100 x 800 points) the convergence plot's keys wrap within their column:
/// each lies left of the reaction plot's title and clear of it, and inside the window (not in
/// one row under the title, with the plot as wide as the row).
#[test]
fn plot_keys_stay_in_their_column_in_a_narrow_window() {
    let mut h = harness_sized(SCENE, true, [1100.0, 800.0]);
    loaded(&mut h);
    let title = h
        .get_by_label_contains("Reaction against displacement")
        .rect();
    for key in [
        "residual",
        "selected",
        "contact event",
        "cut-back",
        "tolerance",
    ] {
        let r = h.get_by_label(key).rect();
        assert!(
            r.max.x <= title.min.x && r.max.x <= 1100.0 && r.max.y <= 800.0,
            "key {key:?} at {r:?}, the reaction plot's title at {title:?}"
        );
    }
}

#[test]
fn stretch_correction_selector_reloads_in_the_chosen_mode() {
    // The roll-up never cuts back: the default corrects its updates where they turn the stiff
    // chords (2 iterations an increment); chosen "after a cut-back", it runs plain Newton (6),
    // what a direct run in that mode takes.
    let mut h = harness_on("end_moment", false);
    loaded(&mut h);
    h.get_by_label("Stretch correction").click();
    h.run();
    h.get_by_label("after a cut-back").click();
    wait(&mut h, "the reload", Duration::from_secs(30), |h| {
        h.query_by_label("after a cut-back").is_some() && shown_increment(h) == Some((0, 0))
    });
    let mut scene = builtin("end_moment").unwrap().unwrap();
    run_all(&mut h, scene.steps, Duration::from_secs(60));
    let default = direct(&scene, scene.steps);
    scene.params.stretch_correction = tsm_contact::solver::StretchCorrection::AfterCutBack;
    let chosen = direct(&scene, scene.steps);
    let (c, d) = (chosen.last().unwrap(), default.last().unwrap());
    assert_ne!(c.iterations, d.iterations, "the modes must differ here");
    let shown = label(&h, "iterations ").unwrap();
    assert!(
        shown.starts_with(&format!("iterations {} ", c.iterations)),
        "{shown} (after a cut-back: {}, default: {})",
        c.iterations,
        d.iterations
    );
}
