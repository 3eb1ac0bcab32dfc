//! Rigid motions the supports leave free are mechanisms, found from the geometry of the held
//! dofs whatever the size of the model: each case's count of free rigid motions is worked out by
//! hand from the kinematics of a rigid body in the plane.

use tsm_contact::scene::parse;

/// A straight beam from (0, 0) to (`dx`, `dy`) in `n` elements, with `supports` (RON).
fn beam(n: usize, dx: f64, dy: f64, supports: &str) -> String {
    format!(
        r#"(
    name: "beam",
    sections: [(name: "s", E: 2.0e11, A: 1.0e-3, I: 1.0e-7)],
    bodies: [(name: "beam", section: "s", path: [(0.0, 0.0), ({dx}, {dy})], elements: {n}, first_node: 1)],
    supports: [{supports}],
    loads: [(node: {}, fy: -100.0)],
)"#,
        n + 1
    )
}

/// The message of a scene that validation refuses, or None if it loads.
fn refusal(text: &str) -> Option<String> {
    parse(text, "beam.ron").err().map(|e| e.to_string())
}

/// A cantilever of 100 elements held only in translation at its root spins about it (one free
/// motion): found, and the body and its held dofs named, although its tangent's pivots look no
/// smaller than those of a long, slender, well-supported cantilever.
#[test]
fn a_long_cantilever_free_to_spin_about_its_root_is_a_mechanism() {
    let text = beam(100, 10.0, 0.0, "(node: 1, u: true, v: true)");
    let why = refusal(&text).expect("refused");
    assert!(
        why.contains("supports: the structure is a mechanism"),
        "{why}"
    );
    assert!(
        why.contains("body \"beam\" can move rigidly (1 rigid motion not"),
        "{why}"
    );
    assert!(why.contains("held only at node 1 u, node 1 v"), "{why}");
    // Clamped, the same beam loads.
    let clamped = beam(100, 10.0, 0.0, "(node: 1, u: true, v: true, phi: true)");
    assert_eq!(refusal(&clamped), None);
}

/// The count of free rigid motions for supports whose kinematics are plain: pins at both ends
/// stop all three; a roller at the far end of a horizontal beam stops the spin about a pinned
/// root only if it holds v (the far end moves along y when the beam turns), and a vertical
/// beam's far end moves along x; rollers alone leave the slide along the beam free; nothing
/// held leaves all three.
#[test]
fn free_rigid_motions_are_counted_from_the_supports_geometry() {
    let cases = [
        (
            10.0,
            0.0,
            "(node: 1, u: true, v: true), (node: 51, u: true, v: true)",
            0,
        ),
        (
            10.0,
            0.0,
            "(node: 1, u: true, v: true), (node: 51, v: true)",
            0,
        ),
        (
            10.0,
            0.0,
            "(node: 1, u: true, v: true), (node: 51, u: true)",
            1,
        ),
        (
            0.0,
            10.0,
            "(node: 1, u: true, v: true), (node: 51, u: true)",
            0,
        ),
        (
            0.0,
            10.0,
            "(node: 1, u: true, v: true), (node: 51, v: true)",
            1,
        ),
        (10.0, 0.0, "(node: 1, v: true), (node: 51, v: true)", 1),
        (10.0, 0.0, "(node: 26, phi: true)", 2),
        (10.0, 0.0, "", 3),
    ];
    for (dx, dy, supports, free) in cases {
        let why = refusal(&beam(50, dx, dy, supports));
        match free {
            0 => assert_eq!(why, None, "{supports}"),
            k => {
                let why = why.unwrap_or_default();
                let motions = if k == 1 { "motion" } else { "motions" };
                let expect = format!("({k} rigid {motions} not stopped");
                assert!(why.contains(&expect), "{supports}: {why}");
            }
        }
    }
}
