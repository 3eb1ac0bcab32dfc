//! Reading results in the app (egui_kittest on the real `TsmApp`): the scene's units label the
//! numbers, a hovered node shows its values, a click pins them in the details panel, the moment
//! diagram of a cantilever peaks at P L at the clamp, and a scene opens fitted to the view.
#![cfg(feature = "gui")]

use std::time::Duration;

use egui_kittest::kittest::{NodeT, Queryable};
use egui_kittest::Harness;
use tsm_contact::app::canvas::diagrams::Diagram;
use tsm_contact::app::units::num;
use tsm_contact::app::{Startup, TsmApp};

mod gui_support;
use gui_support::{label, loaded, shown_increment, wait};

/// A 2 m cantilever of 10 elements in kN and m, clamped at node 1, with a 0.01 kN tip load
/// (small: the deflection is a millionth of the length, so statics on the undeformed shape holds
/// to six digits).
const CANTILEVER: &str = r#"(
    name: "cantilever",
    units: kN_m,
    sections: [(name: "s", E: 2.0e8, A: 1.0e-2, I: 1.0e-4)],
    bodies: [(name: "beam", section: "s", path: [(0.0, 0.0), (2.0, 0.0)], elements: 10, first_node: 1)],
    supports: [(node: 1, u: true, v: true, phi: true)],
    loads: [(node: 11, fy: -0.01)],
    control: (steps: 1),
)"#;

/// The app on `scene` (a path or built-in name) with `diagram`, its first step solved.
fn solved(scene: &str, diagram: Option<Diagram>) -> Harness<'static, TsmApp> {
    let startup = Startup {
        diagram,
        ..Startup::scene(scene)
    };
    let mut h = Harness::builder()
        .with_size([1400.0, 900.0])
        .wgpu()
        .build_eframe(move |cc| TsmApp::new(cc, startup));
    loaded(&mut h);
    h.get_by_label("Step").click();
    wait(&mut h, "the first step", Duration::from_secs(60), |h| {
        shown_increment(h) == Some((1, 1))
    });
    h
}

/// The cantilever written to a file of its own.
fn cantilever_file(name: &str) -> String {
    let path = std::env::temp_dir().join(format!("tsm-gui-{name}-{}.ron", std::process::id()));
    std::fs::write(&path, CANTILEVER).unwrap();
    path.to_string_lossy().into_owned()
}

/// Williams' toggle is written in pounds and inches: the details panel says so, and labels its
/// reactions, prescribed displacement and step in lb, lb in and in.
#[test]
fn an_lb_in_scene_labels_its_numbers_in_lb_and_in() {
    let h = solved("williams_toggle", None);
    assert!(label(&h, "units: lb, in").is_some());
    let v = label(&h, "node 11 v = ").expect("the prescribed displacement");
    assert!(v.ends_with(" in"), "{v}");
    for (dof, unit) in [("node 1 u", "lb"), ("node 1 phi", "lb in")] {
        let row: Vec<String> = h
            .query_all_by_label_contains(unit)
            .filter_map(|n| {
                let a = n.accesskit_node();
                a.label().or_else(|| a.value())
            })
            .collect();
        assert!(
            row.iter().any(|l| l.ends_with(&format!(" {unit}"))),
            "no value in {unit} for {dof}: {row:?}"
        );
    }
    assert!(label(&h, "increments of at most 0.0300 in").is_some());
}

/// Hovering node 6 (mid-span) shows its values; a click pins them under "Selected". The shown
/// deflection is the Timoshenko cantilever's own at x = 1 m under the tip load: bending,
/// P x^2 (3 L - x) / (6 E I), plus shear, P x / (G A) with G = E / (2 (1 + 0.3)) and the shear
/// area A (the scene's defaults), down.
#[test]
fn a_hovered_node_shows_its_values_and_a_click_pins_them() {
    let path = cantilever_file("hover");
    let mut h = solved(&path, None);
    let (_, at) = h.state().node_on_screen(6).expect("node 6 is drawn");
    h.hover_at(at);
    h.step();
    h.step();
    assert!(
        label(&h, "node 6 of beam").is_some(),
        "no tooltip at {at:?}"
    );
    let (p, x, l, e, i, a) = (0.01, 1.0, 2.0, 2.0e8, 1.0e-4, 1.0e-2);
    let g = e / 2.6;
    let v_exact = -(p * x * x * (3.0 * l - x) / (6.0 * e * i) + p * x / (g * a));
    let shown = label(&h, "u = ").expect("the displacements");
    assert!(
        shown.ends_with(&format!("v = {} m", num(v_exact))),
        "{shown} against v = {v_exact:e}"
    );
    assert!(h.query_by_label("Selected").is_none());
    // A press and a release on the spot.
    h.drag_at(at);
    h.step();
    h.drop_at(at);
    h.step();
    h.step();
    assert!(
        h.query_by_label("Selected").is_some(),
        "the click pins the node"
    );
    std::fs::remove_file(path).ok();
}

/// The moment diagram of the cantilever peaks at P L = 0.01 kN x 2 m at the clamp, on element
/// 1, and the details panel says so in kN m.
#[test]
fn the_moment_diagram_of_a_cantilever_peaks_at_p_l_at_the_clamp() {
    let path = cantilever_file("moment");
    let h = solved(&path, Some(Diagram::Moment));
    let text = label(&h, "M extreme ").expect("the diagram's extreme");
    let value: f64 = text["M extreme ".len()..]
        .split_whitespace()
        .next()
        .unwrap()
        .parse()
        .unwrap();
    assert!((value.abs() - 0.02).abs() < 1e-6, "{text}");
    assert!(text.contains("kN m on beam element 1 at 0.00"), "{text}");
    std::fs::remove_file(path).ok();
}

/// Example 3.1 opens with every node inside the viewport.
#[test]
fn a_scene_opens_fitted_to_the_view() {
    let mut h = Harness::builder()
        .with_size([1400.0, 900.0])
        .wgpu()
        .build_eframe(|cc| TsmApp::new(cc, Startup::scene("example_3_1")));
    loaded(&mut h);
    h.step();
    for id in 1..=18 {
        let (rect, at) = h.state().node_on_screen(id).expect("drawn");
        assert!(rect.contains(at), "node {id} at {at:?} outside {rect:?}");
    }
}
