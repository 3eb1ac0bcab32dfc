//! A moving polyline whose convex corner touches elements (`touches: Elements` with a pilot):
//! a rigid wedge driven down onto a coarse beam between two of its nodes presses it as a point
//! load there, against the simply supported beam's deflection under a point load, with every
//! state audited by the oracle (`tsm_contact::audit`), which checks the corner where its pilot
//! puts it.

use crate::common;

use tsm_contact::scene::parse;
use tsm_contact::solver::{IncrementRecord, Silent, SolveError};

/// The wedge's corner stands this far above the beam at rest (m).
const CLEAR: f64 = 0.01;

/// A beam of 1 m on `n` elements (EI = 1 N m^2, EA = 1e6 N), pinned at x = 0 and on a roller
/// at x = 1, and a wedge with its corner at x = `a`, `CLEAR` above it, moved by its pilot (node
/// 100) down by `CLEAR + depth` in 8 steps.
fn wedge(formulation: &str, n: usize, a: f64, depth: f64, touches: &str) -> String {
    format!(
        r#"(
        name: "wedge on a beam", formulation: {formulation},
        sections: [(name: "beam", E: 1.0, A: 1.0e6, I: 1.0, G: 1.0e6)],
        nodes: [(id: 100, x: {a:?}, y: 0.3, rotation: false)],
        bodies: [(name: "beam", section: "beam", path: [(0.0, 0.0), (1.0, 0.0)], elements: {n}, first_node: 1)],
        supports: [(node: 1, u: true, v: true), (node: {end}, v: true), (node: 100, u: true)],
        prescribed: [(node: 100, dof: V, per_step: {step:?})],
        obstacles: [(name: "wedge", shape: Polyline(points: [({r:?}, 0.2), ({a:?}, {CLEAR:?}), ({l:?}, 0.2)]),
                     bodies: ["beam"], pilot: 100, touches: {touches})],
        control: (steps: 8),
    )"#,
        end = n + 1,
        step = -(CLEAR + depth) / 8.0,
        r = a + 0.1,
        l = a - 0.1,
    )
}

/// The wedge's corner at x = 0.4 (inside an element of 4 and of 8) pushed 0.1 mm into the
/// beam, both formulations: the corner gets a node of its own that moves with the pilot,
/// touches the element it stands over, and presses the beam as a point load there. Its force
/// against the deflection under it is that of Euler-Bernoulli's simply supported beam,
/// `P = 3 EI L w / (a^2 b^2)`, within 1e-4 on 4 elements and falling at least as h^2 to 8
/// (shear is held stiff; the beam's rotation under 0.1 mm is of order 1e-3); the force on the
/// wedge (the corner's reaction) balances the supports'. Touching the nodes alone, the corner
/// passes between them and the run stops, naming the obstacle.
#[test]
fn a_moving_wedge_presses_a_coarse_beam_between_its_nodes_as_a_point_load() {
    let (a, depth) = (0.4, 1e-4);
    let (b, l) = (1.0 - a, 1.0);
    let expected = 3.0 * l * depth / (a * a * b * b);
    for f in ["BernoulliEuler", "Timoshenko"] {
        let mut errors = Vec::new();
        for n in [4, 8] {
            let sc = parse(&wedge(f, n, a, depth, "Elements"), "wedge.ron").unwrap();
            let corner = sc.model.nodes.len() - 1;
            let pilot = sc.model.nodes.iter().position(|n| n.id == 100).unwrap();
            assert_eq!(
                sc.model.nodes[corner].id, 101,
                "the corner's node: the next id"
            );
            assert_eq!(sc.model.nodes[corner].moves_with, Some(pilot));
            let mut solver = sc.solver().unwrap();
            let mut recs: Vec<IncrementRecord> = Vec::new();
            for _ in 0..sc.steps {
                recs.extend(solver.step(&mut Silent).expect("converges"));
            }
            common::assert_audited(&sc, &recs);
            let last = recs.last().unwrap();
            // The corner is where the pilot puts it.
            let (c, p) = (last.nodes[corner], last.nodes[pilot]);
            assert!((c[0] - a).abs() < 1e-12, "{f}: corner at {c:?}");
            assert!((c[1] - (p[1] - 0.3 + CLEAR)).abs() < 1e-12 && (c[1] + depth).abs() < 1e-12);
            let [contact] = last.contacts.as_slice() else {
                panic!("{f}: contacts {:?}", last.contacts);
            };
            let under = (a * n as f64).floor() as usize;
            assert_eq!(
                (contact.node, contact.element),
                (101, under),
                "{f}: {contact:?}"
            );
            let force = |id: u32| {
                (last.reactions.iter())
                    .find(|r| r.node == id && r.dof == "v")
                    .map_or(0.0, |r| r.value)
            };
            let on_wedge = force(101);
            // Within the solver's tolerance (1e-8 of the forces).
            assert!(
                (on_wedge + force(1) + force(n as u32 + 1)).abs() < 1e-7 * expected,
                "{f}: the supports balance the wedge"
            );
            // The pilot itself carries nothing: the wedge's faces are clear of the beam. The
            // force that drives it, its corners' included, is the corner's.
            assert_eq!(force(100), 0.0);
            assert_eq!(last.held_force(&sc.model.moving_with(pilot), "v"), on_wedge);
            // A corner recorded away from where its pilot puts it is found by the oracle.
            let mut moved = recs.clone();
            moved.last_mut().unwrap().nodes[corner][0] += 1e-6;
            let found = common::findings(&sc, &moved);
            assert!(
                found
                    .iter()
                    .any(|x| x.what.contains("off its pilot 100's u")),
                "{f}: {found:?}"
            );
            errors.push((on_wedge.abs() / expected - 1.0).abs());
        }
        assert!(errors[0] < 1e-4, "{f}: {errors:?}");
        assert!(errors[1] < errors[0] / 4.0, "{f}: {errors:?}");

        let nodes_only = parse(&wedge(f, 4, a, depth, "Nodes"), "wedge.ron").unwrap();
        let mut solver = nodes_only.solver().unwrap();
        let stopped = (0..8).find_map(|_| solver.step(&mut Silent).err());
        assert!(
            matches!(stopped, Some(SolveError::ObstacleThrough { .. })),
            "{f}: {stopped:?}"
        );
    }
}
