//! The keyboard and Stop (egui_kittest on the real `TsmApp`): Right at the last increment
//! solves one more step, Left, Home and End move through the stored increments, ? opens the
//! list of shortcuts, F fits the view again after a pan, and Esc stops an arc-length run of
//! Lee's frame at once, keeping its accepted increments.
#![cfg(feature = "gui")]

use std::time::{Duration, Instant};

use egui::Key;
use egui_kittest::kittest::Queryable;
use egui_kittest::Harness;
use tsm_contact::app::{Startup, TsmApp};

use crate::gui_support;
use gui_support::{label, loaded, shown_increment, solving, wait};

fn harness_on(scene: &str) -> Harness<'static, TsmApp> {
    let mut h = Harness::builder()
        .with_size([1400.0, 900.0])
        .wgpu()
        .build_eframe(move |cc| TsmApp::new(cc, Startup::scene(scene)));
    loaded(&mut h);
    h
}

/// Press `key` and let the app see it.
fn press(h: &mut Harness<'static, TsmApp>, key: Key) {
    h.key_press(key);
    h.step();
}

#[test]
fn arrows_home_and_end_walk_the_increments_and_question_mark_lists_the_keys() {
    let mut h = harness_on("example_3_2");
    for k in 1..=3 {
        press(&mut h, Key::ArrowRight);
        wait(&mut h, "one more step", Duration::from_secs(60), |h| {
            shown_increment(h) == Some((k, k)) && !solving(h)
        });
    }
    press(&mut h, Key::ArrowLeft);
    assert_eq!(shown_increment(&h), Some((2, 3)));
    press(&mut h, Key::Home);
    assert_eq!(shown_increment(&h), Some((0, 3)));
    press(&mut h, Key::End);
    assert_eq!(shown_increment(&h), Some((3, 3)));
    assert!(h.query_by_label("Shortcuts").is_none());
    press(&mut h, Key::Questionmark);
    h.step();
    assert!(h.query_by_label("Shortcuts").is_some(), "the window opens");
    assert!(label(&h, "stop the solver").is_some());
}

/// Lee's frame on 60 elements a member, traced in 3,000 short arcs: a run long enough to be
/// stopped in the middle on any machine.
const LONG_LEE: &str = r#"(
    name: "Lee's frame, fine",
    formulation: BernoulliEuler,
    sections: [(name: "member", E: 720.0, A: 6.0, I: 2.0, nu: 0.3)],
    bodies: [(name: "frame", section: "member", path: [(0.0, 0.0), (0.0, 120.0), (120.0, 120.0)], elements: 60, first_node: 1)],
    supports: [(node: 1, u: true, v: true), (node: 121, u: true, v: true)],
    loads: [(node: 73, fy: -1.0)],
    control: (steps: 3000, arc_length: 0.05),
)"#;

/// Lee's frame is traced by arc length (load control): Space starts the run, and Esc ends it
/// at once (within the Newton iteration under way; the bound of a second is one a loaded
/// machine meets too), with every increment accepted before it kept.
#[test]
fn esc_stops_an_arc_length_run_at_once() {
    let path = std::env::temp_dir().join(format!("tsm-long-lee-{}.ron", std::process::id()));
    std::fs::write(&path, LONG_LEE).unwrap();
    let mut h = harness_on(&path.to_string_lossy());
    press(&mut h, Key::Space);
    wait(&mut h, "the run to start", Duration::from_secs(60), |h| {
        solving(h) && h.state().increments() >= 3
    });
    let t0 = Instant::now();
    h.key_press(Key::Escape);
    h.step();
    while solving(&h) {
        assert!(
            t0.elapsed() < Duration::from_secs(5),
            "the run did not stop"
        );
        h.step();
    }
    let took = t0.elapsed();
    let kept = h.state().increments();
    assert!(took < Duration::from_secs(1), "stopped after {took:?}");
    assert!(kept >= 3);
    // Nothing goes on after the stop.
    for _ in 0..20 {
        h.step();
    }
    assert_eq!(h.state().increments(), kept);
    assert!(kept < 3000, "stopped before the end");
    std::fs::remove_file(path).ok();
}

/// F fits the view again after a pan: node 1 of Example 3.2 returns to where the fitted view
/// drew it on loading, to a tenth of a point.
#[test]
fn f_fits_the_view_again_after_a_pan() {
    let mut h = harness_on("example_3_2");
    h.run_steps(3);
    let (rect, fitted) = h.state().node_on_screen(1).expect("node 1 is drawn");
    // A drag on empty space near the viewport's bottom-left corner pans the view.
    let from = rect.left_bottom() + egui::vec2(60.0, -60.0);
    h.drag_at(from);
    h.step();
    for k in 1..=10 {
        h.hover_at(from + egui::vec2(8.0 * k as f32, -5.0 * k as f32));
        h.step();
    }
    h.drop_at(from + egui::vec2(80.0, -50.0));
    h.run_steps(2);
    let (_, panned) = h.state().node_on_screen(1).unwrap();
    assert!(
        (panned - fitted).length() > 40.0,
        "the drag pans: {fitted:?} -> {panned:?}"
    );
    press(&mut h, Key::F);
    h.run_steps(2);
    let (_, again) = h.state().node_on_screen(1).unwrap();
    assert!((again - fitted).length() < 0.1, "{fitted:?} -> {again:?}");
}
