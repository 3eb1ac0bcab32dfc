//! The step-range part of the acceptance check: an increment whose Newton iteration converges
//! to an equilibrium far from the path (here a beam folded flat around a pin) is cut back, and
//! the run follows the path instead.

use tsm_contact::scene::parse;
use tsm_contact::solver::Silent;

/// A pin driven down and along onto a simply supported, kinked beam, close to its pinned end.
/// Taken in one increment, Newton converges to the beam folded into a flat zig-zag between its
/// supports (elements stretched by a quarter, turned by radians), with the pin below the beam.
const PIN_NEAR_A_PINNED_END: &str = r#"(
    name: "pin near a pinned end", formulation: BernoulliEuler,
    sections: [(name: "s", E: 2.4703353730418e5, A: 5.193779949187989e-3, I: 5.630694631751299e-7, G: 9.501289896314616e4)],
    nodes: [(id: 100000, x: 1.1745005288050847e-1, y: 6.340770115284978e-6, rotation: false)],
    bodies: [(name: "beam", section: "s", path: [(0.0, 0.0), (3.285040299143986, 0.0), (5.936209165410658, 1.5194697600779514)], elements: 4, first_node: 1)],
    supports: [(node: 1, u: true, v: true), (node: 9, v: true)],
    prescribed: [(node: 100000, dof: U, per_step: 1.0773125912717328e-1), (node: 100000, dof: V, per_step: -2.5045166960651305e-1)],
    contacts: [(nodes: [100000], bodies: ["beam"])],
    control: (steps: 6),
)"#;

/// In every accepted increment the beam runs left to right, node after node, as it does at the
/// start: it bends under the pin (its roller end slides in by a metre and more) but does not
/// fold back on itself, as the far equilibrium does (every node there within 1 cm of x = 0).
#[test]
fn an_equilibrium_far_from_the_path_is_cut_back_and_the_path_followed() {
    let scene = parse(PIN_NEAR_A_PINNED_END, "pin.ron").unwrap();
    let mut solver = scene.solver().unwrap();
    let ids: Vec<u32> = solver
        .structure()
        .model
        .nodes
        .iter()
        .map(|n| n.id)
        .collect();
    for _ in 0..scene.steps {
        let records = solver.step(&mut Silent).expect("the run follows the path");
        for rec in records {
            let x = |id: u32| rec.nodes[ids.iter().position(|&n| n == id).unwrap()][0];
            for id in 1..9 {
                assert!(
                    x(id + 1) > x(id),
                    "increment {}: node {} at x = {} is not right of node {id} at x = {}",
                    rec.increment,
                    id + 1,
                    x(id + 1),
                    x(id)
                );
            }
        }
    }
}
