//! Driving the app in tests: a harness on a scene, waiting for what it shows, and reading its
//! labels through the accessibility tree.
#![allow(dead_code)]

use std::time::{Duration, Instant};

use egui_kittest::kittest::{NodeT, Queryable};
use egui_kittest::Harness;
use tsm_contact::app::{Startup, TsmApp};

/// A 2 m cantilever of 10 elements in kN and m, clamped at node 1, with a 0.01 kN tip load
/// (small: the deflection is a millionth of the length, so statics on the undeformed shape holds
/// to six digits).
pub const CANTILEVER: &str = r#"(
    name: "cantilever",
    units: kN_m,
    sections: [(name: "s", E: 2.0e8, A: 1.0e-2, I: 1.0e-4)],
    bodies: [(name: "beam", section: "s", path: [(0.0, 0.0), (2.0, 0.0)], elements: 10, first_node: 1)],
    supports: [(node: 1, u: true, v: true, phi: true)],
    loads: [(node: 11, fy: -0.01)],
    control: (steps: 1),
)"#;

pub fn harness_on(scene: &str, no_gpu: bool) -> Harness<'static, TsmApp> {
    harness_sized(scene, no_gpu, [1400.0, 900.0])
}

pub fn harness_sized(scene: &str, no_gpu: bool, size: [f32; 2]) -> Harness<'static, TsmApp> {
    let startup = Startup {
        no_gpu,
        ..Startup::scene(scene)
    };
    Harness::builder()
        .with_size(size)
        .wgpu()
        .build_eframe(move |cc| TsmApp::new(cc, startup))
}

/// Step frames until `done` holds (panics after `limit`).
pub fn wait(
    h: &mut Harness<'static, TsmApp>,
    what: &str,
    limit: Duration,
    done: impl Fn(&Harness<'static, TsmApp>) -> bool,
) {
    wait_each(h, what, limit, done, |_| {});
}

/// `wait`, calling `each` after every frame.
pub fn wait_each(
    h: &mut Harness<'static, TsmApp>,
    what: &str,
    limit: Duration,
    done: impl Fn(&Harness<'static, TsmApp>) -> bool,
    mut each: impl FnMut(&Harness<'static, TsmApp>),
) {
    let t0 = Instant::now();
    loop {
        h.step();
        each(h);
        if done(h) {
            return;
        }
        assert!(
            t0.elapsed() < limit,
            "timed out waiting for {what}; the app shows: {}",
            describe(h)
        );
        std::thread::sleep(Duration::from_millis(5));
    }
}

/// Whether the app shows that it is solving.
pub fn solving(h: &Harness<'static, TsmApp>) -> bool {
    h.query_by_label("solving...").is_some()
}

/// What the app shows, for a timeout message: every text node of the top bar, the details
/// and the handles, and the number of converged states it holds.
pub fn describe(h: &Harness<'static, TsmApp>) -> String {
    let texts: Vec<String> = h
        .query_all_by_label_contains("")
        .filter_map(|n| {
            let a = n.accesskit_node();
            let text = a.label().or_else(|| a.value())?;
            let keep = [
                "Increment ",
                " = ",
                "residual ",
                "solving",
                "elements",
                "error",
                "failed",
                "drag to set",
            ];
            keep.iter()
                .any(|k| text.contains(k))
                .then(|| format!("{text:?} at {:?}", n.rect().center()))
        })
        .collect();
    format!(
        "{} converged states; {}",
        h.state().increments(),
        texts.join("; ")
    )
}

/// Text of the first label that starts with `prefix`.
pub fn label(h: &Harness<'static, TsmApp>, prefix: &str) -> Option<String> {
    h.query_all_by_label_contains(prefix)
        .filter_map(|n| {
            n.accesskit_node()
                .label()
                .or_else(|| n.accesskit_node().value())
        })
        .find(|l| l.starts_with(prefix))
}

/// The shown "Increment k / n" as (k, n).
pub fn shown_increment(h: &Harness<'static, TsmApp>) -> Option<(usize, usize)> {
    let text = label(h, "Increment ")?;
    let mut it = text
        .trim_start_matches("Increment ")
        .split(" / ")
        .map(|s| s.trim().parse::<usize>());
    Some((it.next()?.ok()?, it.next()?.ok()?))
}

pub fn loaded(h: &mut Harness<'static, TsmApp>) {
    wait(h, "the scene to load", Duration::from_secs(30), |h| {
        shown_increment(h) == Some((0, 0))
    });
}

/// Open the Export menu unless it is open.
pub fn open_export_menu(h: &mut Harness<'static, TsmApp>) {
    if h.query_by_label("Export CSV").is_none() {
        h.get_by_label("Export").click();
        h.run_steps(2);
    }
}

/// Type `stem` into the Export menu's "Export as" field.
pub fn export_as(h: &mut Harness<'static, TsmApp>, stem: &std::path::Path) {
    open_export_menu(h);
    h.get_by_role_and_label(egui::accesskit::Role::TextInput, "Export as")
        .set_text_value_accesskit(&stem.display().to_string());
    h.step();
}

/// Click `button` of the Export menu.
pub fn export(h: &mut Harness<'static, TsmApp>, button: &str) {
    open_export_menu(h);
    h.get_by_label(button).click();
    h.step();
    h.step();
}
