//! Self-contact: a body touching itself, away from each node's own and neighbouring elements.
//! The reference is the same structure cut into two bodies at the bend and solved with contact
//! between the bodies: the same nodes, elements and loads, another path through the code (no
//! self-contact windows). A folded strip pressed shut gives the same state, contacts and
//! forces at the end of every step both ways.

use crate::common;

use tsm_contact::scene::parse;
use tsm_contact::solver::{IncrementRecord, Silent};

/// Elements per segment of the fold.
const N: usize = 20;

/// A strip folded into a U: the lower arm from the clamp at (0, 0) to (1, 0), a bend up to
/// (1, 0.05) and the upper arm back to (0.01, 0.05) (so that its nodes sit between the lower
/// arm's), its free end pushed down 7 mm a step for 10 steps. `bodies` and `contacts` model
/// it as one body or as two. Each is solved to its round-off floor (tolerance 1e-12), so that
/// the two states agree to what the model decides, not to where each Newton pass stopped: at
/// the default tolerance two solves of one structure may stop 1e-8 of the load apart, and at
/// step 8 (the tip meeting the lower arm by the clamp) a pass of 55 iterations with
/// corrections the size of the strip may land on another equilibrium (the tip wedged at the
/// clamp under 5.7 kN) where the other model cuts the step back and follows the path.
fn folded(bodies: &str, nodes: &str, contacts: &str) -> Vec<IncrementRecord> {
    // Records with the nodes in id order (an explicit node comes first in the model).
    let text = format!(
        r#"(
    name: "fold",
    formulation: BernoulliEuler,
    sections: [(name: "s", E: 2.0e11, A: 2.0e-5, I: 6.6667e-13)],
    nodes: [{nodes}],
    bodies: [{bodies}],
    supports: [(node: 1, u: true, v: true, phi: true)],
    prescribed: [(node: {tip}, dof: V, per_step: -0.007)],
    contacts: [{contacts}],
    control: (steps: 10, tolerance: 1e-12),
)"#,
        tip = 3 * N + 1
    );
    let scene = parse(&text, "fold.ron").expect("a valid scene");
    let mut order: Vec<usize> = (0..scene.model.nodes.len()).collect();
    order.sort_by_key(|&k| scene.model.nodes[k].id);
    let mut solver = scene.solver().unwrap();
    let mut out = Vec::new();
    let mut records = Vec::new();
    for _ in 0..10 {
        let step = solver.step(&mut Silent).expect("converges");
        records.extend(step.iter().cloned());
        // The state at the end of the step: the cut-backs on the way (their failed attempts
        // are iterates far from equilibrium) may differ between two models of one structure.
        let mut r = step.last().expect("an increment").clone();
        r.nodes = order.iter().map(|&k| r.nodes[k]).collect();
        out.push(r);
    }
    common::assert_audited(&scene, &records);
    out
}

#[test]
fn a_strip_folded_shut_touches_itself_as_two_bodies_touch_each_other() {
    let one = folded(
        &format!(
            r#"(name: "fold", section: "s", path: [(0.0, 0.0), (1.0, 0.0), (1.0, 0.05), (0.01, 0.05)], elements: {N}, first_node: 1)"#
        ),
        "",
        r#"(node_bodies: ["fold"], bodies: ["fold"], own: true)"#,
    );
    let corner = 2 * N + 1;
    let two = folded(
        &format!(
            r#"(name: "lower", section: "s", path: [(0.0, 0.0), (1.0, 0.0), (1.0, 0.05)], elements: {N}, first_node: 1),
        (name: "upper", section: "s", path: [(1.0, 0.05), (0.01, 0.05)], elements: {N}, first_node: {corner})"#
        ),
        &format!("(id: {corner}, x: 1.0, y: 0.05)"),
        r#"(node_bodies: ["upper"], bodies: ["lower"]), (node_bodies: ["lower"], bodies: ["upper"])"#,
    );
    assert_eq!(one.len(), two.len(), "the same steps");
    let mut touched = 0;
    for (a, b) in one.iter().zip(&two) {
        let scale = 0.07;
        for (p, q) in a.nodes.iter().zip(&b.nodes) {
            let d = (p[0] - q[0]).hypot(p[1] - q[1]);
            assert!(
                d < 1e-9 * scale,
                "increment {}: nodes {d:e} apart",
                a.increment
            );
        }
        let pairs = |r: &IncrementRecord| {
            let mut v: Vec<(u32, usize)> = r.contacts.iter().map(|c| (c.node, c.element)).collect();
            v.sort_unstable();
            v
        };
        assert_eq!(
            pairs(a),
            pairs(b),
            "increment {}: the same contacts",
            a.increment
        );
        for (c, d) in a.contacts.iter().zip(&b.contacts) {
            assert!((c.force - d.force).abs() < 1e-8 * c.force.abs().max(1e-3));
        }
        touched = touched.max(a.contacts.len());
        // No node of the upper arm below the lower arm's chord under it.
        for n in (2 * N + 1)..=(3 * N) {
            let [x, y, _] = a.nodes[n];
            for e in 0..N {
                let (p, q) = (a.nodes[e], a.nodes[e + 1]);
                let t = (x - p[0]) / (q[0] - p[0]);
                if (0.0..=1.0).contains(&t) {
                    let under = p[1] + t * (q[1] - p[1]);
                    assert!(
                        y > under - 1e-9,
                        "increment {}: node {} below the lower arm",
                        a.increment,
                        n + 1
                    );
                }
            }
        }
    }
    assert!(touched > 0, "the fold never shut");
}

/// No two chords of the one-body chain `x` (node states in order), other than neighbours,
/// cross beyond their sagittas (`overlap`) by more than 1e-9 m; `at` names the state.
fn assert_no_chords_cross(x: &[[f64; 3]], at: &str) {
    for e in 0..x.len() - 1 {
        for f in e + 2..x.len() - 1 {
            let o = overlap(x[e], x[e + 1], x[f], x[f + 1]);
            assert!(
                o <= 1e-9,
                "{at}: elements {} and {} cross by {o:e}",
                e + 1,
                f + 1
            );
        }
    }
}

/// How far the chords p0-p1 and q0-q1 (node states x, y, phi) cross, beyond what their
/// elements' bulges allow: 0 where they do not cross. Where they cross, the overlap is the
/// least distance of an end from the other chord; an element's curve leaves its chord by its
/// sagitta, about l |phi_j - phi_i| / 8 (a node resting on an element's curve may lie across
/// its chord by that much).
fn overlap(p0: [f64; 3], p1: [f64; 3], q0: [f64; 3], q1: [f64; 3]) -> f64 {
    let side = |a: [f64; 3], b: [f64; 3], c: [f64; 3]| {
        (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
    };
    let crossing =
        side(p0, p1, q0) * side(p0, p1, q1) < 0.0 && side(q0, q1, p0) * side(q0, q1, p1) < 0.0;
    if !crossing {
        return 0.0;
    }
    let len = |a: [f64; 3], b: [f64; 3]| (b[0] - a[0]).hypot(b[1] - a[1]);
    let off = |a: [f64; 3], b: [f64; 3], c: [f64; 3]| (side(a, b, c) / len(a, b)).abs();
    let least = [
        off(p0, p1, q0),
        off(p0, p1, q1),
        off(q0, q1, p0),
        off(q0, q1, p1),
    ]
    .into_iter()
    .fold(f64::MAX, f64::min);
    let bulge = |a: [f64; 3], b: [f64; 3]| len(a, b) * (b[2] - a[2]).abs() / 8.0;
    (least - bulge(p0, p1) - bulge(q0, q1)).max(0.0)
}

/// The built-in cantilever rolled past a turn: beyond one turn its tip presses on the beam's
/// own root. At every accepted increment no two deformed elements cross by more than their
/// curves' sagittas (the beam does not pass through itself; checked here on the node
/// positions and rotations alone), the contacts
/// press, and the clamp's reactions balance the tip's moment and force (the contact forces,
/// internal to the body, cancel in pairs), to the residual tolerance.
#[test]
fn a_cantilever_rolled_past_a_turn_presses_on_itself_and_never_passes_through() {
    let scene = tsm_contact::scene::open("rolled_past_a_turn").expect("built in");
    let steps = scene.steps;
    let mut solver = scene.solver().unwrap();
    let mut pressed = 0;
    let mut records = Vec::new();
    for _ in 0..steps {
        for r in solver.step(&mut Silent).expect("converges") {
            records.push(r.clone());
            let x = &r.nodes;
            assert_no_chords_cross(x, &format!("increment {}", r.increment));
            for c in &r.contacts {
                assert!(
                    c.pressure >= 0.0,
                    "increment {}: a contact pulls",
                    r.increment
                );
            }
            pressed = pressed.max(r.contacts.len());
            // Reactions at the clamp against the load: moment 2 pi lambda about the tip, force
            // -0.5 lambda down at the tip, whose moment about the clamp is -0.5 lambda x_tip.
            let lambda = r.load_factor;
            let at = |dof: &str| {
                (r.reactions.iter())
                    .find(|q| q.node == 1 && q.dof == dof)
                    .map_or(0.0, |q| q.value)
            };
            let tip = x[x.len() - 1];
            let tol = 10.0 * r.reference * r.relative_residual.max(1e-8);
            assert!((at("u")).abs() <= tol, "increment {}: u", r.increment);
            assert!(
                (at("v") - 0.5 * lambda).abs() <= tol,
                "increment {}: v",
                r.increment
            );
            let moment = 2.0 * std::f64::consts::PI * lambda - 0.5 * lambda * tip[0];
            assert!(
                (at("phi") + moment).abs() <= tol,
                "increment {}: phi {} against {}",
                r.increment,
                at("phi"),
                -moment
            );
        }
    }
    assert!(pressed > 0, "the tip never touched the root");
    common::assert_audited(&scene, &records);
}

/// A cantilever of 40 elements (EI = 1, L = 1) rolled up by an end moment of `turns` x 2 pi
/// EI / L in 20 steps, touching itself (`own`), in `formulation`: every record.
fn rolled_up(formulation: &str, turns: f64) -> (tsm_contact::scene::Scene, Vec<IncrementRecord>) {
    let text = format!(
        r#"(
    name: "roll-up",
    formulation: {formulation},
    sections: [(name: "s", E: 1.0, A: 1.0e4, I: 1.0, G: 1.0e4)],
    bodies: [(name: "cantilever", section: "s", path: [(0.0, 0.0), (1.0, 0.0)], elements: 40, first_node: 1)],
    supports: [(node: 1, u: true, v: true, phi: true)],
    loads: [(node: 41, m: {m})],
    contacts: [(node_bodies: ["cantilever"], bodies: ["cantilever"], own: true)],
    control: (steps: 20, load_per_step: 0.05),
)"#,
        m = turns * 2.0 * std::f64::consts::PI
    );
    let scene = parse(&text, "roll-up.ron").expect("a valid scene");
    let mut solver = scene.solver().unwrap();
    let mut records = Vec::new();
    for _ in 0..20 {
        let step = solver.step(&mut Silent);
        let step = step.unwrap_or_else(|e| panic!("{formulation}, {turns} turns: {e}"));
        records.extend(step);
    }
    (scene, records)
}

/// Rolled up one and a half and two turns on 40 elements, both formulations: every step
/// completes. Before the beam touches itself (the moment below one turn's 2 pi EI / L) its
/// nodes are the vertices of the regular polygon of the exact solution (sides L / 40, each
/// turned by M (L / 40) / EI from the last; no axial or shear force) to 1e-9 L; at every
/// increment, touching or not, the clamp holds the end moment and no force (the contact forces
/// are internal and cancel) to ten times the residual tolerance, no two elements cross beyond
/// their curves' sagittas (`overlap`, on the node states alone), and the oracle finds nothing.
#[test]
fn a_cantilever_rolled_up_two_turns_onto_itself_completes_in_both_formulations() {
    for formulation in ["BernoulliEuler", "Timoshenko"] {
        for turns in [1.5, 2.0] {
            let (scene, records) = rolled_up(formulation, turns);
            let at = format!("{formulation}, {turns} turns");
            assert!(
                records
                    .last()
                    .is_some_and(|r| (r.load_factor - 1.0).abs() < 1e-12),
                "{at}: the roll-up stops short"
            );
            let mut touched = false;
            for r in &records {
                let m = r.load_factor * turns * 2.0 * std::f64::consts::PI;
                touched |= !r.contacts.is_empty();
                if m < 2.0 * std::f64::consts::PI && !touched {
                    let h = 1.0 / 40.0;
                    let (mut x, mut y) = (0.0f64, 0.0f64);
                    for (k, node) in r.nodes.iter().enumerate().skip(1) {
                        let angle = (k as f64 - 0.5) * m * h;
                        x += h * angle.cos();
                        y += h * angle.sin();
                        let off = (node[0] - x).hypot(node[1] - y);
                        assert!(
                            off < 1e-9,
                            "{at}, increment {}: node {} off the polygon by {off:e}",
                            r.increment,
                            k + 1
                        );
                    }
                }
                let reaction = |dof: &str| {
                    (r.reactions.iter())
                        .find(|q| q.node == 1 && q.dof == dof)
                        .map_or(0.0, |q| q.value)
                };
                let tol = 10.0 * r.reference * r.relative_residual.max(1e-8);
                assert!(
                    reaction("u").abs() <= tol,
                    "{at}, increment {}: u",
                    r.increment
                );
                assert!(
                    reaction("v").abs() <= tol,
                    "{at}, increment {}: v",
                    r.increment
                );
                assert!(
                    (reaction("phi") + m).abs() <= tol,
                    "{at}, increment {}: phi {} against {}",
                    r.increment,
                    reaction("phi"),
                    -m
                );
                assert_no_chords_cross(&r.nodes, &format!("{at}, increment {}", r.increment));
            }
            assert!(touched, "{at}: the beam never touched itself");
            common::assert_audited(&scene, &records);
        }
    }
}

/// The built-in cantilever rolled past a turn at 1.7821 times its load step (7 steps, to a
/// load factor of 1.25): between two states its tip glides over a mesh node of the root under
/// it, lying for one state in the wedge outside that convex node, projecting onto neither
/// element there, and nearer another layer of the coil. The side it came from is then read in
/// that wedge, not from the other layer: the tip is not made to rest on the root from the far
/// side (a contact that would hold it through the body), and the oracle finds nothing in any
/// state up to the last step's load factor.
#[test]
fn a_tip_gliding_over_a_mesh_node_of_the_root_keeps_the_side_it_came_from() {
    let mut scene = tsm_contact::scene::open("rolled_past_a_turn").expect("built in");
    let f = 1.7821;
    scene.model.load_per_step *= f;
    scene.steps = (scene.steps as f64 / f).ceil() as usize;
    let mut solver = scene.solver().unwrap();
    let mut records = Vec::new();
    for _ in 0..scene.steps {
        records.extend(solver.step(&mut Silent).expect("converges"));
    }
    crate::common::assert_audited(&scene, &records);
    let last = records.last().unwrap().load_factor;
    assert!((last - 7.0 * 0.1 * f).abs() < 1e-12, "{last}");
}
