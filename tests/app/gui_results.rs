//! Reading results in the app (egui_kittest on the real `TsmApp`): the scene's units label the
//! numbers, a hovered node shows its values, a click pins them in the details panel, the moment
//! diagram of a cantilever peaks at P L at the clamp, a scene opens fitted to the view, and a
//! frictional contact is listed with its friction force and whether it slips.
#![cfg(feature = "gui")]

use std::time::Duration;

use egui_kittest::kittest::{NodeT, Queryable};
use egui_kittest::Harness;
use tsm_contact::app::display::num;
use tsm_contact::app::{Startup, TsmApp};
use tsm_contact::figure::Diagram;
use tsm_contact::solver::{Friction, Silent};

use crate::gui_support;
use gui_support::{label, loaded, shown_increment, wait, CANTILEVER};

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
    h.get_by_label("Next").click();
    wait(&mut h, "the first step", Duration::from_secs(60), |h| {
        shown_increment(h) == Some((1, 1))
    });
    h
}

/// A click at `at`: the pointer there, a press and a release on the spot, and the frames that
/// show what it did.
fn click_at(h: &mut Harness<'static, TsmApp>, at: egui::Pos2) {
    h.hover_at(at);
    h.step();
    h.drag_at(at);
    h.step();
    h.drop_at(at);
    h.step();
    h.step();
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
    click_at(&mut h, at);
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

/// The path of `stem` with `ext`, as a string.
fn with_ext(stem: &std::path::Path, ext: &str) -> std::path::PathBuf {
    stem.with_extension(ext)
}

/// Exports from the buttons: with node 11 selected, the CSV's headers carry the scene's units
/// and its u, v of node 11 and its reactions are those of the JSON export, row by row; the SVG
/// of Example 3.2 holds one path per body (three) with numbers for coordinates, and each save
/// confirms with its full path.
#[test]
fn exports_write_what_the_run_holds_in_its_units() {
    let path = cantilever_file("export");
    let mut h = solved(&path, None);
    let dir = std::env::temp_dir().join(format!("tsm-gui-export-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let stem = dir.join("run");
    gui_support::export_as(&mut h, &stem);
    let (_, at) = h.state().node_on_screen(11).expect("node 11 is drawn");
    click_at(&mut h, at);
    for button in ["Export CSV", "Export JSON"] {
        gui_support::export(&mut h, button);
    }
    let wrote = label(&h, "wrote ").expect("a confirmation");
    assert!(
        wrote.ends_with("run.json") && wrote.contains('/'),
        "{wrote}"
    );
    let csv = std::fs::read_to_string(with_ext(&stem, "csv")).expect("CSV written");
    let rows: Vec<Vec<&str>> = csv.lines().map(|l| l.split(',').collect()).collect();
    let column = |name: &str| rows[0].iter().position(|c| *c == name).expect(name);
    let (u, v, ry) = (
        column("u_node_11 [m]"),
        column("v_node_11 [m]"),
        column("R_node_1_v [kN]"),
    );
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(with_ext(&stem, "json")).unwrap()).unwrap();
    let ids: Vec<u64> = serde_json::from_value(json["node_ids"].clone()).unwrap();
    let slot = ids.iter().position(|&id| id == 11).unwrap();
    let incs = json["increments"].as_array().unwrap();
    assert_eq!(rows.len(), 1 + incs.len());
    for (row, inc) in rows[1..].iter().zip(incs) {
        let node = &inc["nodes"][slot];
        let num = |k: usize| row[k].parse::<f64>().unwrap();
        assert!((num(u) - (node[0].as_f64().unwrap() - 2.0)).abs() < 1e-15);
        assert!((num(v) - node[1].as_f64().unwrap()).abs() < 1e-15);
        let r_v = (inc["reactions"].as_array().unwrap().iter())
            .find(|x| x["node"] == 1 && x["dof"] == "v")
            .unwrap()["value"]
            .as_f64()
            .unwrap();
        assert!((num(ry) - r_v).abs() <= 1e-12 * r_v.abs());
    }
    std::fs::remove_file(path).ok();

    let mut h = Harness::builder()
        .with_size([1400.0, 900.0])
        .wgpu()
        .build_eframe(|cc| TsmApp::new(cc, Startup::scene("example_3_2")));
    loaded(&mut h);
    gui_support::export_as(&mut h, &stem);
    gui_support::export(&mut h, "Export SVG");
    let svg = std::fs::read_to_string(with_ext(&stem, "svg")).expect("SVG written");
    assert!(svg.starts_with("<svg ") && svg.trim_end().ends_with("</svg>"));
    let paths: Vec<&str> = svg.lines().filter(|l| l.starts_with("<path ")).collect();
    assert_eq!(paths.len(), 3, "{svg}");
    for p in paths {
        let d = p.split(" d=\"").nth(1).unwrap().split('"').next().unwrap();
        for pair in d.split(['M', 'L']).filter(|s| !s.trim().is_empty()) {
            let xy: Vec<f64> = pair
                .split_whitespace()
                .map(|v| v.parse().unwrap())
                .collect();
            assert_eq!(xy.len(), 2, "{pair}");
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// With a node selected in the view, the response plot is drawn against that node's
/// displacement, v first, and its u or phi on a click.
#[test]
fn the_response_plot_follows_the_selected_node_and_dof() {
    let path = cantilever_file("plot");
    let mut h = solved(&path, None);
    assert!(label(&h, "Load factor against displacement of the loaded dof").is_some());
    let (_, at) = h.state().node_on_screen(6).expect("node 6 is drawn");
    click_at(&mut h, at);
    assert!(
        label(
            &h,
            "Load factor against node 6 v, the node selected in the view"
        )
        .is_some(),
        "the plot follows node 6"
    );
    h.get_by_label("phi").click();
    h.step();
    h.step();
    assert!(label(&h, "Load factor against node 6 phi").is_some());
    std::fs::remove_file(path).ok();
}

/// The table lists the elements of the viewed increment; sorted by the size of M at end i,
/// largest first, its first row is element 1 at the clamp with M = P L = 0.02 kN m.
#[test]
fn the_table_sorts_the_elements_by_their_moment() {
    let path = cantilever_file("table");
    let mut h = solved(&path, None);
    h.get_by_label("Table").click();
    h.run_steps(3);
    h.get_by_label("Elements").click();
    h.run_steps(3);
    h.get_by_label("M at i (kN m)").click();
    h.step();
    h.step();
    assert_eq!(first_row(&h), "beam element 1");
    assert!(label(&h, "0.0200").is_some() || label(&h, "-0.0200").is_some());
    // Again: smallest first, element 10 at the free end (M at its end i is P L / 10, the
    // smallest of the ten).
    h.get_by_label("M at i (kN m) v").click();
    h.run_steps(2);
    assert_eq!(first_row(&h), "beam element 10");
    std::fs::remove_file(path).ok();
}

/// The element named in the table's top row.
fn first_row(h: &Harness<'static, TsmApp>) -> String {
    let mut rows: Vec<(f32, String)> = h
        .query_all_by_label_contains("beam element ")
        .filter_map(|n| {
            let a = n.accesskit_node();
            let text = a.label().or_else(|| a.value())?;
            Some((n.rect().min.y, text.to_string()))
        })
        .collect();
    rows.sort_by(|a, b| a.0.total_cmp(&b.0));
    rows.first().map(|r| r.1.clone()).unwrap_or_default()
}

/// A frictional contact is listed with its friction force and its mode: the first step of
/// Example 3.2 with friction, against the same step solved headless.
#[test]
fn a_slipping_contact_is_listed_with_its_friction_force() {
    let scene = tsm_contact::scene::builtin::builtin("example_3_2_friction")
        .unwrap()
        .unwrap();
    let mut solver = scene.solver().unwrap();
    let r = solver.step(&mut Silent).unwrap().pop().unwrap();
    let c = &r.contacts[0];
    assert_eq!(c.friction, Friction::Slipping);
    let h = solved("example_3_2_friction", None);
    assert!(h.query_by_label("T (N)").is_some(), "the friction column");
    assert!(h.query_by_label("slips").is_some(), "the mode");
    let t = num(c.tangential);
    assert!(h.query_by_label(&t).is_some(), "the friction force {t}");
}
