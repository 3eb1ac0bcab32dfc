//! Friction at a face off the axis, where a rim rolls: a pin's radius or a beam's half
//! thickness touching a rigid obstacle. Against independent references: the slip of a rim
//! against rolling kinematics worked out in the test, and a post whose rim rests on a rough
//! floor against the linear cantilever lengthened by a rigid arm to the point that touches,
//! and the Coulomb limit once it slips.

use crate::common;

use tsm_contact::scene::parse;
use tsm_contact::solver::element::friction::{obstacle_friction, ObstacleGrip};
use tsm_contact::solver::{Friction, IncrementRecord, Shape, Silent};

/// The slip of a rim of radius r on an obstacle, against rolling kinematics worked out here:
/// a rim that rolls without slipping (on a line, round the outside of a disk with angular
/// velocity (R + r)/r times its centre's, and pivoting about a polyline's corner with its
/// centre's angle) keeps a slip of 0; one that does not turn slips by its centre's path
/// length along the tangent. (Each path turns the rim by less than half a turn: between
/// increments the solver measures the turn afresh from the rim as it is.)
#[test]
fn a_rim_that_rolls_without_slipping_does_not_slip() {
    let r = 0.05;
    let (big, c) = (0.7, [0.2, -0.9]);
    let disk = Shape::Circle {
        centre: c,
        radius: big,
        hollow: false,
    };
    let line = Shape::Line {
        from: [0.0, 0.0],
        to: [1.0, 0.0],
    };
    let corner = Shape::Polyline {
        points: vec![[-1.0, 0.0], [0.0, 0.0], [1.0, -1.0]],
    };
    // Paths of the centre (x, y) and of the rolling rim's rotation, by a parameter in [0, 1],
    // and the centre's path length along the tangent (the slip of a rim that does not turn).
    type Path = Box<dyn Fn(f64) -> [f64; 3]>;
    let cases: Vec<(&Shape, Path, f64)> = vec![
        (
            &line,
            Box::new(move |s| [0.3 + 0.1 * s, r, -0.1 * s / r]),
            0.1,
        ),
        (
            &disk,
            Box::new(move |s| {
                let a = 0.9 + 0.2 * s;
                let d = big + r;
                [c[0] + d * a.cos(), c[1] + d * a.sin(), 0.2 * s * d / r]
            }),
            -0.2 * (big + r),
        ),
        (
            &corner,
            Box::new(move |s| {
                // From straight above the corner, turning clockwise onto the second face.
                let a = std::f64::consts::FRAC_PI_2 - 0.6 * s;
                [r * a.cos(), r * a.sin(), -0.6 * s]
            }),
            0.6 * r,
        ),
    ];
    for (shape, path, length) in cases {
        let slip_at = |s: f64, turning: bool| {
            let [x0, y0, _] = path(0.0);
            let [x, y, phi] = path(s);
            let start = shape.gap([x0, y0]).unwrap();
            let mut gap = shape.gap([x, y]).unwrap();
            gap.g -= r;
            let grip = ObstacleGrip {
                mu: 0.4,
                stiffness: 1.0,
                stick: shape.place(start.point),
                slip: None,
                period: shape.period(),
                reach: r,
                roll: -start.n[1].atan2(start.n[0]),
            };
            let phi = if turning { phi } else { 0.0 };
            let place = shape.place(gap.point);
            obstacle_friction(&gap, (place, phi), (1.0, 1.0), &grip)
                .0
                .slip
        };
        for k in 1..=10 {
            let s = k as f64 / 10.0;
            let rolling = slip_at(s, true);
            assert!(
                rolling.abs() < 1e-12,
                "{shape:?} at {s}: a rolling rim slips {rolling:e}"
            );
            let sliding = slip_at(s, false);
            let expected = length * s;
            assert!(
                (sliding - expected).abs() < 1e-12,
                "{shape:?} at {s}: a rim that does not turn slips {sliding:e}, not {expected:e}"
            );
        }
    }
}

/// A post of length L hanging from a clamp, the point that touches a rough floor a distance r
/// below its tip (a pin's radius at the tip, or the post's half thickness), pressed down onto
/// the floor and then pushed sideways at the clamp in 12 steps of 1e-4 m, on 10 elements of
/// `formulation`. The floor is a rigid `Line` obstacle or, `on_a_beam`, a held beam 0.1 m
/// thick (its axis 0.05 m below the line, its face on it). Returns the records and the place
/// of the clamp's node in their node states.
fn pushed_post(
    r: f64,
    thickness: bool,
    on_a_beam: bool,
    formulation: &str,
) -> (Vec<IncrementRecord>, usize) {
    let (tip, thick) = if thickness {
        (String::new(), format!(", thickness: {:?}", 2.0 * r))
    } else {
        (
            format!("nodes: [(id: 11, x: 0.0, y: {r:?}, radius: {r:?})],"),
            String::new(),
        )
    };
    let (floor_body, floor_held, floor) = if on_a_beam {
        (
            r#"(name: "floor", section: "floor", path: [(-0.6, -0.05), (0.4, -0.05)], elements: 4, first_node: 101),"#,
            (101..=105)
                .map(|k| format!("(node: {k}, u: true, v: true, phi: true), "))
                .collect::<String>(),
            r#"contacts: [(nodes: [11], bodies: ["floor"], mu: 0.5)],"#,
        )
    } else {
        (
            "",
            String::new(),
            r#"obstacles: [(name: "floor", shape: Line(from: (-1.0, 0.0), to: (1.0, 0.0)), bodies: ["post"], mu: 0.5)],"#,
        )
    };
    let text = format!(
        r#"(
    name: "a post whose rim rests on a rough floor",
    sections: [
        (name: "post", E: 1.0e6, A: 1.0e-2, I: 1.0e-4, G: 4.0e5{thick}),
        (name: "floor", E: 1.0e6, A: 1.0e-1, I: 1.0e-2, thickness: 0.1),
    ],
    {tip}
    bodies: [
        (name: "post", section: "post", path: [(0.0, {top:?}), (0.0, {r:?})], elements: 10, first_node: 1),
        {floor_body}
    ],
    supports: [{floor_held}(node: 1, phi: true)],
    prescribed: [(node: 1, dof: U, per_step: 0.0), (node: 1, dof: V, per_step: 0.0)],
    {floor}
    stages: [
        (name: "press", steps: 2, prescribed: [(node: 1, dof: V, by: -2.5e-5)]),
        (name: "push", steps: 12, prescribed: [(node: 1, dof: U, by: 1.2e-3)]),
    ],
    formulation: {formulation},
)"#,
        top = 1.0 + r,
    );
    let scene = parse(&text, "post.ron").unwrap();
    let mut solver = scene.solver().unwrap();
    let mut records = Vec::new();
    for _ in 0..scene.steps {
        records.extend(solver.step(&mut Silent).unwrap());
    }
    common::assert_audited(&scene, &records);
    let clamp = (scene.model.nodes.iter()).position(|n| n.id == 1).unwrap();
    (records, clamp)
}

/// The post of `pushed_post` (EI = 100 N m^2, GA = 4e3 N, L = 1 m, r = 0.1 m, mu = 0.5) on a
/// rigid floor and on a thick beam: while the rim sticks, the push Delta at the clamp and the
/// force F on the floor are those of a cantilever whose tip carries F at a rigid arm r below
/// it, Delta = F ((L^3/3 + r L^2 + r^2 L) / EI + L / GA) (the shear term for Timoshenko), to
/// 1 % (the axial force's effect on the bending, N / P_cr = 1e-3, and the geometry's change
/// are far below); a rim taken not to turn with the tip would give 3 EI Delta / L^3, 25 %
/// off. Once the friction force reaches mu N the rim slips, and the force stays there.
#[test]
fn a_post_whose_rim_rests_on_a_rough_floor_pushes_as_a_cantilever_with_an_arm_to_the_rim() {
    let (ei, ga, l, r, mu) = (100.0, 4.0e3, 1.0f64, 0.1, 0.5);
    for (thickness, on_a_beam) in [(false, false), (true, false), (false, true), (true, true)] {
        for formulation in ["BernoulliEuler", "Timoshenko"] {
            let shear = if formulation == "Timoshenko" {
                l / ga
            } else {
                0.0
            };
            let compliance = (l.powi(3) / 3.0 + r * l * l + r * r * l) / ei + shear;
            let (records, clamp) = pushed_post(r, thickness, on_a_beam, formulation);
            let (mut stuck, mut slipped, mut worst) = (0, 0, 0.0f64);
            for rec in &records[2..] {
                let push = rec.nodes[clamp][0];
                let (tangential, normal, friction) = if on_a_beam {
                    let c = rec.contacts.first().expect("the rim stays on the floor");
                    (c.tangential, c.pressure, c.friction)
                } else {
                    let floor = (rec.obstacle_contacts.iter()).find(|c| c.obstacle == "floor");
                    let c = floor.expect("the rim stays on the floor");
                    (c.tangential, c.force, c.friction)
                };
                let held = |dof: &str| {
                    (rec.reactions.iter())
                        .find(|x| x.node == 1 && x.dof == dof)
                        .unwrap()
                        .value
                };
                // The clamp's reaction balances the floor's friction force, to the solver's
                // tolerance (1e-8 of forces of the size of the normal force) and a margin.
                let force = held("u").abs();
                assert!(
                    (force - tangential.abs()).abs() < 1e-7 * normal,
                    "{force:e} against {tangential:e} {friction:?}"
                );
                match friction {
                    Friction::Sticking => {
                        let expected = push / compliance;
                        let error = (force - expected).abs() / expected;
                        assert!(
                            error < 1e-2,
                            "{formulation}, thickness {thickness}, on a beam {on_a_beam}: push \
                             {push:e}, force {force:e}, the cantilever with its arm {expected:e}"
                        );
                        worst = worst.max(error);
                        stuck += 1;
                    }
                    Friction::Slipping => {
                        let ratio = force / (mu * normal);
                        assert!((ratio - 1.0).abs() < 1e-6, "slipping at {ratio} mu N");
                        slipped += 1;
                    }
                    Friction::Frictionless => panic!("the floor has friction"),
                }
            }
            assert!(
                stuck >= 4 && slipped >= 4,
                "sticks {stuck}, slips {slipped}"
            );
            eprintln!(
                "{formulation}, thickness {thickness}, on a beam {on_a_beam}: sticking within \
                 {worst:.1e} of the cantilever with its arm, {stuck} sticking and {slipped} \
                 slipping states"
            );
        }
    }
}
