//! Scene validation: every built-in scene parses; bad input is rejected with an error that
//! names the file, the line and the field or node, and never panics.

use tsm_contact::scene::{builtin::BUILTIN, parse};

const GOOD: &str = r#"(
    name: "t",
    sections: [(name: "s", E: 1.0, A: 1.0, I: 1.0)],
    bodies: [(name: "b", section: "s", path: [(0.0, 0.0), (1.0, 0.0)], elements: 2, first_node: 1)],
    supports: [(node: 1, u: true, v: true, phi: true)],
    loads: [(node: 3, fy: 1.0)],
)"#;

fn err(text: &str) -> String {
    parse(text, "bad.ron")
        .expect_err("must be rejected")
        .to_string()
}

#[test]
fn every_builtin_scene_is_valid() {
    for (f, text) in BUILTIN {
        let sc = parse(text, f).unwrap_or_else(|e| panic!("{e}"));
        assert!(!sc.model.beams.is_empty());
    }
    assert!(parse(GOOD, "good.ron").is_ok());
}

#[test]
fn malformed_ron_names_the_line() {
    let text = GOOD.replace("elements: 2,", "elements: 2,,");
    let e = err(&text);
    assert!(e.starts_with("bad.ron:4:"), "{e}");
}

#[test]
fn unknown_node_id_is_named() {
    let e = err(&GOOD.replace("(node: 3, fy", "(node: 99, fy"));
    assert!(
        e.contains("loads[0].node")
            && e.contains("unknown node id 99")
            && e.starts_with("bad.ron:6:"),
        "{e}"
    );
}

#[test]
fn zero_length_element_is_named() {
    let e = err(&GOOD.replace("[(0.0, 0.0), (1.0, 0.0)]", "[(0.0, 0.0), (0.0, 0.0)]"));
    assert!(e.contains("zero length") && e.contains("body \"b\""), "{e}");
}

#[test]
fn non_positive_stiffness_is_named() {
    let e = err(&GOOD.replace("E: 1.0", "E: -3.0"));
    assert!(e.contains("sections[0].E") && e.contains("-3"), "{e}");
    let e = err(&GOOD.replace("I: 1.0", "I: 0.0"));
    assert!(e.contains("sections[0].I"), "{e}");
}

#[test]
fn mechanism_names_what_can_move_and_what_holds_it() {
    // Only u and v held: the cantilever can spin about node 1.
    let e = err(&GOOD.replace("phi: true", "phi: false"));
    assert!(e.contains("mechanism"), "{e}");
    assert!(
        e.contains("body \"b\" can move rigidly (1 rigid motion not"),
        "{e}"
    );
    assert!(e.contains("held only at node 1 u, node 1 v)"), "{e}");
    // A pin that nothing holds.
    let text = GOOD.replace(
        "bodies:",
        "nodes: [(id: 50, x: 0.5, y: 1.0, rotation: false)],\n    bodies:",
    );
    let e = err(&text);
    assert!(
        e.contains("node 50 can move rigidly (2 rigid motions"),
        "{e}"
    );
}

/// Many parts that can move are summed up: how many, the first eight, and the motions over
/// all of them. Five pins that nothing holds are named with their ten motions; 110 of them are
/// counted, and the first eight named.
#[test]
fn a_long_mechanism_is_summed_up() {
    let pins: String = (0..5)
        .map(|k| format!("(id: {}, x: 0.{k}, y: 1.0, rotation: false), ", 50 + k))
        .collect();
    let text = GOOD.replace("bodies:", &format!("nodes: [{pins}],\n    bodies:"));
    let e = err(&text);
    assert!(
        e.contains("node 50, node 51, node 52, node 53, node 54 can move rigidly (10 rigid motions not stopped; nothing holds them)"),
        "{e}"
    );
    let many: String = (0..110)
        .map(|k| format!("(id: {}, x: {k}.5, y: 1.0, rotation: false), ", 100 + k))
        .collect();
    let e = err(&GOOD.replace("bodies:", &format!("nodes: [{many}],\n    bodies:")));
    assert!(
        e.contains("110 parts, among them node 100, node 101,"),
        "{e}"
    );
    assert!(e.contains("(220 rigid motions not stopped"), "{e}");
    assert_eq!(e.matches("node 1").count(), 8, "the first eight: {e}");
}

/// Two contact nodes at one point, and a path through infinity, are refused with what is
/// wrong with them (not a NaN residual, not a "zero-length element").
#[test]
fn coinciding_contact_nodes_and_infinite_coordinates_are_named() {
    let pins = GOOD.replace(
        "bodies:",
        "nodes: [(id: 50, x: 0.5, y: 0.1, rotation: false), (id: 51, x: 0.5, y: 0.1, rotation: false)],\n    bodies:",
    )
    .replace(
        "supports: [",
        "contacts: [(nodes: [50, 51], bodies: [\"b\"])],\n    supports: [(node: 50, u: true, v: true), (node: 51, u: true, v: true), ",
    );
    let e = err(&pins);
    assert!(e.contains("nodes 50 and 51 start at the same point"), "{e}");
    let e = err(&GOOD.replace("(1.0, 0.0)]", "(inf, 0.0)]"));
    assert!(
        e.contains("path[1]") && e.contains("coordinates must be finite"),
        "{e}"
    );
}

#[test]
fn unknown_fields_and_sections_are_rejected() {
    let e = err(&GOOD.replace("elements: 2,", "elements: 2, colour: 3,"));
    assert!(e.contains("colour"), "{e}");
    let e = err(&GOOD.replace("section: \"s\"", "section: \"steel\""));
    assert!(e.contains("unknown section \"steel\""), "{e}");
}

#[test]
fn garbage_never_panics() {
    for text in [
        "",
        "(",
        "()",
        "[1,2",
        "(name: 3)",
        "\u{0}\u{1}",
        "(name: \"x\", sections: [], bodies: [])",
    ] {
        assert!(parse(text, "garbage.ron").is_err(), "{text:?} accepted");
    }
}

/// Inputs the parser fuzzer found (fuzz/artifacts): an id overflow that panicked and element
/// counts that exhausted memory. Each is now a typed error naming the field.
#[test]
fn fuzzer_findings_are_typed_errors() {
    let base = r#"(name:"",sections:[(name:"s",E:1,A:1,I:1)],bodies:[(name:"b",section:"s",path:[(0,0),(1,0)],elements:ELEMENTS,first_node:FIRST)])"#;
    let cases = [
        ("1", "4294967295", "first_node"),
        ("2342949672952", "1", "elements"),
        ("18446744073709551615", "1", "elements"),
    ];
    for (elements, first, field) in cases {
        let text = base.replace("ELEMENTS", elements).replace("FIRST", first);
        let err = tsm_contact::scene::parse(&text, "fuzz.ron").expect_err("must be rejected");
        assert!(err.field.contains(field), "{err}");
    }
}

/// Stiffnesses out of floating-point range, and elements too short to have distinct ends, are
/// named as such (not passed on to the solver, which would call them "a mechanism").
#[test]
fn out_of_range_stiffness_and_vanishing_elements_name_the_field() {
    let base = r#"(name:"",sections:[(name:"s",E:EVAL,A:AVAL,I:1)],bodies:[(name:"b",section:"s",path:[(0,0),(LEN,0)],elements:4,first_node:1)],supports:[(node:1,u:true,v:true,phi:true)])"#;
    let cases = [
        ("1e60", "1e60", "1", "sections[0].E", "E A"),
        ("1e300", "1", "1", "sections[0].E", "below 1e100"),
        ("1e-200", "1e-200", "1", "sections[0].E", "E A"),
        ("1", "1", "5e-324", "bodies[0].path[1]", "too short"),
    ];
    for (e, a, len, field, says) in cases {
        let text = base
            .replace("EVAL", e)
            .replace("AVAL", a)
            .replace("LEN", len);
        let err = tsm_contact::scene::parse(&text, "range.ron").expect_err("must be rejected");
        assert!(
            err.field.starts_with(field) && err.to_string().contains(says),
            "{err}"
        );
    }
}

/// `control.stretch_correction` takes a mode or, as scenes written before the automatic mode
/// did, a flag; it defaults to `WhereNeeded`, and anything else names the field's line.
#[test]
fn stretch_correction_takes_a_mode_or_a_flag() {
    use tsm_contact::solver::StretchCorrection as S;
    let with = |v: &str| {
        GOOD.replace(
            "loads: [(node: 3, fy: 1.0)],",
            &format!("loads: [(node: 3, fy: 1.0)],\n    control: (stretch_correction: {v}),"),
        )
    };
    let mode = |v: &str| {
        parse(&with(v), "t.ron")
            .unwrap_or_else(|e| panic!("{v}: {e}"))
            .params
            .stretch_correction
    };
    assert_eq!(
        parse(GOOD, "t.ron")
            .expect("good")
            .params
            .stretch_correction,
        S::WhereNeeded
    );
    assert_eq!(mode("Never"), S::Never);
    assert_eq!(mode("WhereNeeded"), S::WhereNeeded);
    assert_eq!(mode("AfterCutBack"), S::AfterCutBack);
    assert_eq!(mode("Always"), S::Always);
    assert_eq!(mode("true"), S::Always);
    assert_eq!(mode("false"), S::Never);
    let e = err(&with("Sometimes"));
    assert!(
        e.starts_with("bad.ron:7:") && e.contains("Sometimes"),
        "{e}"
    );
}

/// A tiny area is named as what it is: an axial stiffness lost to round-off against the
/// bending stiffness (not "a mechanism"); a small one that the tangent still holds solves.
#[test]
fn a_stiffness_lost_to_round_off_is_named() {
    let e = err(&GOOD.replace("A: 1.0,", "A: 1.0e-20,"));
    assert!(
        e.contains("span more than 15 orders") && e.contains("E A / l") && !e.contains("mechanism"),
        "{e}"
    );
    assert!(parse(&GOOD.replace("A: 1.0,", "A: 1.0e-12,"), "small.ron").is_ok());
}

/// An error in a section is located in that section: node 34 of Example 3.2 is named in the
/// supports and in the prescribed displacements, and a rotation prescribed on it (a pin has
/// none) is reported at the prescribed line, not at the support's.
#[test]
fn an_error_is_located_in_its_own_section() {
    let text = tsm_contact::scene::builtin::text("example_3_2").unwrap();
    let bad = text.replace("dof: V, per_step", "dof: Phi, per_step");
    let line = 1 + bad
        .lines()
        .position(|l| l.trim_start().starts_with("prescribed:"))
        .expect("a prescribed line");
    let support = 1 + bad
        .lines()
        .position(|l| l.contains("(node: 34, u: true)"))
        .expect("the pin's support");
    assert_ne!(line, support);
    let e = err(&bad);
    assert!(
        e.starts_with(&format!("bad.ron:{line}: prescribed[0]")),
        "{e}"
    );
}

/// A strip scene with `obstacles` (and, before them, `extra`) for the error tests.
fn strip_with(extra: &str, obstacles: &str) -> String {
    format!(
        r#"(
    name: "strip",
    sections: [(name: "s", E: 2.0e5, A: 1.0e2, I: 1.0e-5)],
    nodes: [(id: 100, x: 0.5, y: 0.5, rotation: false)],
    bodies: [(name: "strip", section: "s", path: [(0.0, 0.0), (1.0, 0.0)], elements: 10, first_node: 1)],
    supports: [(node: 1, u: true, v: true, phi: true)],
    {extra}
    obstacles: [
        {obstacles}
    ],
)"#
    )
}

/// Bad obstacles are refused with the file, the line of the obstacle and what is wrong: a
/// node that starts inside, a pilot left free, a shape without size, an unknown body.
#[test]
fn bad_obstacles_are_refused_with_their_line_and_reason() {
    let cases = [
        (
            strip_with(
                "",
                r#"(name: "floor", shape: Line(from: (0.0, 0.01), to: (1.0, 0.01)), bodies: ["strip"]),"#,
            ),
            "node 1 starts 1.000e-2 inside it",
        ),
        (
            strip_with(
                "prescribed: [(node: 100, dof: U, per_step: 0.01)],",
                r#"(name: "roller", shape: Circle(centre: (0.5, 0.5), radius: 0.1), bodies: ["strip"], pilot: 100),"#,
            ),
            "node 100 moves the obstacle, so its u and v must be supported or prescribed",
        ),
        (
            strip_with(
                "",
                r#"(name: "drum", shape: Circle(centre: (0.5, -1.0), radius: 0.0), bodies: ["strip"]),"#,
            ),
            "a circle needs a centre and a positive radius, finite and below 1e100 in size",
        ),
        (
            strip_with(
                "",
                r#"(name: "wall", shape: Polyline(points: [(2.0, 0.0), (2.0, 0.0)]), bodies: ["strip"]),"#,
            ),
            "points 1 and 2 of the polyline are the same",
        ),
        (
            strip_with(
                "",
                r#"(name: "wall", shape: Polyline(points: [(2.0, 0.0), (2.0, 1e-310)]), bodies: ["strip"]),"#,
            ),
            "points 1 and 2 of the polyline are the same to round-off",
        ),
        (
            strip_with(
                "",
                r#"(name: "wall", shape: Polyline(points: [(2.0, -1.0), (2.0, 1.0), (2.0, 0.0)]), bodies: ["strip"]),"#,
            ),
            "folds straight back on itself at point 2",
        ),
        (
            strip_with(
                "",
                r#"(name: "floor", shape: Line(from: (0.0, -1.0), to: (1.0, -1.0)), bodies: ["rod"]),"#,
            ),
            "rod",
        ),
    ];
    for (text, reason) in cases {
        let e = parse(&text, "bad.ron").expect_err("refused");
        let shown = e.to_string();
        assert!(shown.contains(reason), "{shown}");
        assert!(
            shown.starts_with("bad.ron:9:"),
            "located at the obstacle's line: {shown}"
        );
    }
}

/// A contact entry that can never act is refused, saying why: no body to touch, no candidate,
/// every candidate on the bodies it may touch without `own`, and `own` on bodies too short for a
/// node to reach past its own elements and the two beyond them.
#[test]
fn contact_entries_that_can_never_act_are_refused() {
    let scene = |elements: usize, contact: &str| {
        format!(
            r#"(
    name: "t",
    sections: [(name: "s", E: 1.0, A: 1.0, I: 1.0)],
    bodies: [(name: "b", section: "s", path: [(0.0, 0.0), (1.0, 0.0)], elements: {elements}, first_node: 1)],
    supports: [(node: 1, u: true, v: true, phi: true)],
    loads: [(node: 2, fy: 1.0)],
    contacts: [{contact}],
)"#
        )
    };
    for (elements, contact, says) in [
        (4, r#"(nodes: [2], bodies: [])"#, "no body to touch"),
        (4, r#"(bodies: ["b"])"#, "no candidate node"),
        (
            4,
            r#"(node_bodies: ["b"], bodies: ["b"])"#,
            "set `own: true`",
        ),
        (
            3,
            r#"(node_bodies: ["b"], bodies: ["b"], own: true)"#,
            "too short",
        ),
    ] {
        let e = parse(&scene(elements, contact), "contact.ron").expect_err(contact);
        assert!(e.field.starts_with("contacts[0]"), "{contact}: {e}");
        assert!(e.message.contains(says), "{contact}: {e}");
        assert!(e.line.is_some(), "{contact}: {e}");
    }
    // Four elements are enough for self-contact from an end.
    assert!(parse(
        &scene(4, r#"(node_bodies: ["b"], bodies: ["b"], own: true)"#),
        "contact.ron"
    )
    .is_ok());
}

/// Bodies that start through what they may touch are refused, naming the elements: a disk
/// cutting an element's chord between its two nodes (both outside it), two bodies that may
/// touch crossing between their nodes, and a body with self-contact whose path folds across
/// itself. Bodies that merely touch, or cross without a contact pair, pass.
#[test]
fn bodies_that_start_through_what_they_may_touch_are_refused() {
    let disk = strip_with(
        "",
        r#"(name: "peg", shape: Circle(centre: (0.05, -0.01), radius: 0.02), bodies: ["strip"]),"#,
    );
    let e = parse(&disk, "disk.ron").expect_err("the chord passes through the peg");
    assert!(e.field.starts_with("obstacles[0]"), "{e}");
    assert!(e.message.contains("element 1 of body strip"), "{e}");
    let beside = disk.replace("(0.05, -0.01)", "(0.05, -0.03)");
    if let Err(e) = parse(&beside, "disk.ron") {
        assert!(!e.field.starts_with("obstacles"), "clear of the peg: {e}");
    }
    let two = |contacts: &str| {
        format!(
            r#"(
    name: "cross",
    sections: [(name: "s", E: 1.0, A: 1.0, I: 1.0)],
    bodies: [
        (name: "a", section: "s", path: [(0.0, 0.0), (1.0, 0.0)], elements: 4, first_node: 1),
        (name: "b", section: "s", path: [(0.55, -0.5), (0.55, 0.5)], elements: 3, first_node: 10),
    ],
    supports: [(node: 1, u: true, v: true, phi: true), (node: 10, u: true, v: true, phi: true)],
    loads: [(node: 5, fy: 1.0)],
    contacts: [{contacts}],
)"#
        )
    };
    let e = parse(&two(r#"(node_bodies: ["a"], bodies: ["b"])"#), "cross.ron")
        .expect_err("the bodies cross");
    assert!(e.field.starts_with("contacts[0]"), "{e}");
    assert!(
        e.message.contains("element 3 of body a") && e.message.contains("element 2 of body b"),
        "{e}"
    );
    // A frame's members crossing without a contact pair between them are not checked.
    let no_pair = two(r#"(nodes: [5], bodies: ["a"], own: true)"#);
    assert!(parse(&no_pair, "cross.ron").is_ok());
    let folded = r#"(
    name: "folded",
    sections: [(name: "s", E: 1.0, A: 1.0, I: 1.0)],
    bodies: [(name: "b", section: "s", path: [(0.0, 0.0), (1.0, 0.0), (0.5, 0.5), (0.5, -0.5)], elements: 3, first_node: 1)],
    supports: [(node: 1, u: true, v: true, phi: true)],
    loads: [(node: 10, fy: 1.0)],
    contacts: [(node_bodies: ["b"], bodies: ["b"], own: true)],
)"#;
    let e = parse(folded, "folded.ron").expect_err("the path folds across itself");
    assert!(e.message.contains("cross where the scene starts"), "{e}");
}

/// Syntax errors name their cause where the parser's words would point elsewhere: a string left
/// open on line 3 is reported at line 3 (the parser stumbles lines later, where the string
/// happens to end), and a decimal in a whole-number field says so.
#[test]
fn syntax_errors_name_the_real_cause() {
    let open_string = "(\n    name: \"x\",\n    description: \"oops,\n    sections: [(name: \"s\", E: 1.0, A: 1.0, I: 1.0)],\n    bodies: [(name: \"b\", section: \"s\", path: [(0.0, 0.0), (1.0, 0.0)], elements: 2, first_node: 1)],\n)";
    let e = parse(open_string, "open.ron").expect_err("refused");
    assert_eq!(e.line, Some(3), "{e}");
    assert!(e.message.contains("not closed"), "{e}");
    let decimal = GOOD.replace("elements: 2,", "elements: 2.5,");
    let e = parse(&decimal, "decimal.ron").expect_err("refused");
    assert_eq!(e.line, Some(4), "{e}");
    assert!(e.message.contains("whole number"), "{e}");
}
