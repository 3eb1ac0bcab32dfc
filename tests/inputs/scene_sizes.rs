//! Scene sizes: numbers beyond what the solver can form are refused at their own field and
//! line, and a one-body built-in scene re-meshes to any element count with every node
//! reference moved to its place.

use tsm_contact::scene::parse;

/// A number no product the solver forms could hold (1e100 and beyond: a load, a distributed
/// load, a density, a stiffness, a coordinate, a path, an obstacle, gravity, a step) is refused
/// at its own field and line, before any solve; just below the bound the same fields pass
/// this check.
#[test]
fn numbers_beyond_the_solvers_range_are_refused_at_their_field() {
    let scene = |section: &str, extra: &str, control: &str| {
        format!(
            r#"(
    name: "t",
    sections: [(name: "s", {section})],
    nodes: [(id: 10, x: 0.5, y: 1.0, rotation: false)],
    bodies: [(name: "b", section: "s", path: [(0.0, 0.0), (1.0, 0.0)], elements: 2, first_node: 1)],
    supports: [(node: 1, u: true, v: true, phi: true), (node: 10, u: true, v: true)],
    {extra},
    control: ({control}),
)"#
        )
    };
    let plain = "E: 1.0, A: 1.0, I: 1.0";
    for (section, extra, control, field) in [
        (plain, "loads: [(node: 3, fy: 1e300)]", "", "loads[0]"),
        (plain, "distributed: [(body: \"b\", q: (0.0, -1e300))]", "", "distributed[0]"),
        (plain, "prescribed: [(node: 3, dof: V, per_step: -1e300)]", "", "prescribed[0]"),
        ("E: 1e300, A: 1.0, I: 1.0", "loads: [(node: 3, fy: 1.0)]", "", "sections[0].E"),
        ("E: 1.0, A: 1.0, I: 1.0, density: 1e300", "loads: [(node: 3, fy: 1.0)]", "gravity: (0.0, -9.81)", "sections"),
        (plain, "loads: [(node: 3, fy: 1.0)]", "gravity: (0.0, -1e300)", "control.gravity"),
        (plain, "loads: [(node: 3, fy: 1.0)]", "load_per_step: 1e300", "control.load_per_step"),
        (
            plain,
            "obstacles: [(name: \"o\", shape: Line(from: (-1.7e308, -1.0), to: (1.7e308, -1.0)), bodies: [\"b\"])], loads: [(node: 3, fy: 1.0)]",
            "",
            "obstacles[0]",
        ),
        (
            plain,
            "obstacles: [(name: \"o\", shape: Circle(centre: (0.5, -1e300), radius: 1e300), bodies: [\"b\"])], loads: [(node: 3, fy: 1.0)]",
            "",
            "obstacles[0]",
        ),
    ] {
        let text = scene(section, extra, control);
        let e = parse(&text, "big.ron").expect_err(extra);
        assert!(e.field.starts_with(field), "{extra} {control}: {e}");
        assert!(e.line.is_some(), "{extra} {control}: located: {e}");
        assert!(
            e.message.contains("1e100") || e.message.contains("finite"),
            "{extra} {control}: {e}"
        );
        // Just below the bound, the field itself is accepted.
        let small = text.replace("1e300", "1e90").replace("1.7e308", "1e90");
        if let Err(e) = parse(&small, "big.ron") {
            assert!(!e.field.starts_with(field), "{small}: {e}");
        }
    }
    // A node far out and a path beyond the range.
    for (from, to, field) in [
        (
            "(id: 10, x: 1e300, y: 1.0, rotation: false)",
            "(id: 10, x: 0.5, y: 1.0, rotation: false)",
            "nodes[0]",
        ),
        (
            "path: [(0.0, 0.0), (1.0, 0.0)]",
            "path: [(-1e308, 0.0), (1e308, 0.0)]",
            "bodies[0]",
        ),
    ] {
        let text = scene(plain, "loads: [(node: 3, fy: 1.0)]", "");
        let text = if field == "nodes[0]" {
            text.replace(to, from)
        } else {
            text.replace(from, to)
        };
        let e = parse(&text, "far.ron").expect_err(field);
        assert!(e.field.starts_with(field), "{e}");
        assert!(e.message.contains("1e100"), "{e}");
    }
}

/// `builtin::with_elements` re-meshes a one-body scene: 1000 elements of Mattiasson's 1 m
/// cantilever, its tip load moved to the new last node at x = 1 m (to 1e-12); its own count
/// gives the scene back unchanged; a scene of several bodies is refused.
#[test]
fn one_body_scenes_re_mesh() {
    use tsm_contact::scene::builtin::{builtin, with_elements};
    let sc = with_elements("mattiasson", 1000)
        .expect("one body")
        .expect("valid");
    assert_eq!(sc.model.beams.len(), 1000);
    let load = &sc.model.loads[0];
    let tip = sc.model.position(load.node);
    assert!(
        (tip[0] - 1.0).abs() < 1e-12 && tip[1].abs() < 1e-12,
        "{tip:?}"
    );
    let own = with_elements("pin_on_cantilever", 16)
        .expect("one body")
        .expect("valid");
    assert_eq!(
        own.model,
        builtin("pin_on_cantilever").unwrap().unwrap().model
    );
    assert!(with_elements("example_3_2", 10).is_none());
}

/// Re-meshing works on the parsed scene, following every reference to a node of the body:
/// Lee's frame (one body of two 10-element members, pinned at nodes 1 and 21, loaded at node
/// 13, two elements into the beam) on 20 elements per member is the scene written out with
/// 20 elements, the supports at nodes 1 and 41 and the load at node 25; on 7 per member the
/// load has no node at its place (2/10 of the beam) and the re-mesh is refused.
#[test]
fn re_meshing_moves_every_node_reference_to_its_place() {
    use tsm_contact::scene::builtin::{text, with_elements};
    let remeshed = with_elements("lee_frame", 20)
        .expect("one body")
        .expect("valid");
    let written = text("lee_frame")
        .unwrap()
        .replace("elements: 10", "elements: 20")
        .replace("(node: 21,", "(node: 41,")
        .replace("(node: 13,", "(node: 25,");
    let written = parse(&written, "lee_frame on 20").expect("valid");
    assert_eq!(remeshed.model, written.model);
    assert_eq!(remeshed.model.beams.len(), 40);
    let load = remeshed.model.position(remeshed.model.loads[0].node);
    assert!(
        (load[0] - 24.0).abs() < 1e-12 && (load[1] - 120.0).abs() < 1e-12,
        "{load:?}"
    );
    assert!(with_elements("lee_frame", 7).is_none());
}
