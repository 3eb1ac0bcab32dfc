//! Snapshot images of the main views (egui_kittest rendering the real `TsmApp` on wgpu; Mesa's
//! lavapipe in CI): Example 3.2 at increment 12 with its moment diagram, Example 3.1 as it
//! opens (fitted), the table of a cantilever's elements, and the roller driven along a
//! cantilever (an obstacle, its contact and the nodes-on-obstacles list). Each is compared with its image in
//! `tests/snapshots/` pixel by pixel; up to 0.25% of the pixels may differ (the iteration
//! times the details panel prints, and the rasteriser's anti-aliasing). `UPDATE_SNAPSHOTS=1`
//! writes new references; a failing comparison leaves `.new.png` and `.diff.png` beside them.
#![cfg(feature = "gui")]

use std::time::Duration;

use egui_kittest::kittest::Queryable;
use egui_kittest::{Harness, SnapshotOptions};
use tsm_contact::app::{Startup, TsmApp};
use tsm_contact::figure::Diagram;

use crate::gui_support;
use gui_support::{loaded, solving, wait};

const SIZE: [f32; 2] = [1400.0, 900.0];

fn options() -> SnapshotOptions {
    let pixels = (SIZE[0] * SIZE[1]) as usize;
    SnapshotOptions::new()
        .threshold(0.6)
        .max_failed_pixels(pixels / 400)
}

/// Fit the view to the viewed increment (F) and let it settle: the picture then does not
/// depend on when, during the run, the view was last fitted.
fn fit(h: &mut Harness<'static, TsmApp>) {
    h.key_press(egui::Key::F);
    h.run_steps(4);
}

fn harness(startup: Startup) -> Harness<'static, TsmApp> {
    Harness::builder()
        .with_size(SIZE)
        .with_theme(egui::Theme::Light)
        .wgpu()
        .build_eframe(move |cc| TsmApp::new(cc, startup))
}

#[test]
fn example_3_2_at_increment_12_with_its_moment_diagram() {
    let mut h = harness(Startup {
        diagram: Some(Diagram::Moment),
        steps: Some(12),
        ..Startup::scene("example_3_2")
    });
    wait(&mut h, "12 increments", Duration::from_secs(60), |h| {
        h.state().increments() == 12 && !solving(h)
    });
    fit(&mut h);
    h.snapshot_options("example_3_2_moment", &options());
}

#[test]
fn the_roller_pressing_on_a_cantilever() {
    let mut h = harness(Startup {
        steps: Some(16),
        ..Startup::scene("roller")
    });
    wait(&mut h, "16 increments", Duration::from_secs(60), |h| {
        h.state().increments() >= 16 && !solving(h)
    });
    fit(&mut h);
    // The roller touches the strip's elements: a contact of its pilot on the strip.
    assert!(h.query_by_label_contains("Active contacts: 1").is_some());
    h.snapshot_options("roller", &options());
}

#[test]
fn example_3_1_opens_fitted_to_the_view() {
    let mut h = harness(Startup::scene("example_3_1"));
    loaded(&mut h);
    h.run_steps(4);
    h.snapshot_options("example_3_1_opened", &options());
}

#[test]
fn the_table_of_lee_frames_nodes() {
    let mut h = harness(Startup {
        steps: Some(5),
        ..Startup::scene("lee_frame")
    });
    wait(&mut h, "5 increments", Duration::from_secs(60), |h| {
        h.state().increments() >= 5 && !solving(h)
    });
    h.get_by_label("Table").click();
    h.run_steps(5);
    h.snapshot_options("lee_frame_table", &options());
}

/// Example 3.2 solved to increment 30, branched at 20 with the drive moved on: the branch
/// point is marked over the timeline, and Undo is offered.
#[test]
fn example_3_2_branched_at_increment_20() {
    let mut h = harness(Startup {
        steps: Some(30),
        ..Startup::scene("example_3_2")
    });
    wait(&mut h, "30 increments", Duration::from_secs(60), |h| {
        h.state().increments() == 30 && !solving(h)
    });
    h.get_by_role_and_label(egui::accesskit::Role::Slider, "Increment")
        .set_value_accesskit(20.0);
    h.run_steps(2);
    h.get_by_role_and_label(egui::accesskit::Role::Slider, "node 34 v")
        .set_value_accesskit(-0.23);
    wait(&mut h, "the branch", Duration::from_secs(60), |h| {
        !solving(h) && h.state().increments() == 23
    });
    fit(&mut h);
    h.snapshot_options("example_3_2_branched", &options());
}

/// A scene file with an error: the error panel shows the whole message, located.
#[test]
fn a_scene_error_in_the_error_panel() {
    let path = std::env::temp_dir().join("tsm-snapshot-bad.ron");
    std::fs::write(
        &path,
        "(\n    name: \"bad\",\n    sections: [(name: \"s\", E: 1.0, A: 1.0, I: 1.0)],\n    bodies: [(name: \"b\", section: \"steel\", path: [(0.0, 0.0), (1.0, 0.0)], elements: 2, first_node: 1)],\n)\n",
    )
    .unwrap();
    let mut h = harness(Startup::scene("example_3_1"));
    loaded(&mut h);
    h.state_mut().open(&path.to_string_lossy());
    h.run_steps(4);
    let name = path.display().to_string();
    h.snapshot_options("error_panel", &options());
    assert!(h.state().error().is_some_and(|e| e.contains(&name)));
    std::fs::remove_file(path).ok();
}
