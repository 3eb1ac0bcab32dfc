//! A solid arc that touches elements (`touches: Elements`): its centre touches a beam at its
//! radius while the way from the centre to the beam lies within the arc's angles, and its two
//! ends touch as corners beyond them, the contact handed from the one to the other where the
//! beam wraps round the arc's end. Against independent references worked out here: the full
//! circle's run within the arc, the beam's deformed shape from the recorded node states (a
//! cubic per element), and the direction of a frictionless contact's force, normal to the
//! beam and within the angles of the point that carries it.

use crate::common;
use crate::rims::nearest_on_strip;

use tsm_contact::scene::{parse, Scene};
use tsm_contact::solver::{ContactChange, Event, IncrementRecord, Silent};

/// A 1 m cantilever of 10 elements (EI = 1, EA = 1e6) above an obstacle `shape` that touches
/// its elements: its tip loaded 1 N down (`drive` "load"), driven down 0.02 m a step ("drag"),
/// or ("down and up") driven 0.24 m down in 12 steps and back up in 12.
fn cantilever_over(formulation: &str, shape: &str, drive: &str, steps: usize) -> Scene {
    let drive = match drive {
        "load" => "loads: [(node: 11, fy: -1.0)],",
        "drag" => "prescribed: [(node: 11, dof: V, per_step: -0.02)],",
        _ => {
            r#"prescribed: [(node: 11, dof: V, per_step: -0.02)],
            stages: [(name: "down", steps: 12, prescribed: [(node: 11, dof: V, to: -0.24)]),
                     (name: "up", steps: 12, prescribed: [(node: 11, dof: V, to: 0.0)])],"#
        }
    };
    let text = format!(
        r#"(
        name: "cantilever over an arc", formulation: {formulation},
        sections: [(name: "strip", E: 1.0, A: 1.0e6, I: 1.0, G: 0.4)],
        bodies: [(name: "beam", section: "strip", path: [(0.0, 0.0), (1.0, 0.0)], elements: 10, first_node: 1)],
        supports: [(node: 1, u: true, v: true, phi: true)],
        {drive}
        obstacles: [(name: "shoulder", shape: {shape}, bodies: ["beam"], touches: Elements)],
        control: (steps: {steps}),
    )"#
    );
    parse(&text, "arc.ron").expect("a valid scene")
}

/// `scene` solved in its own steps, every increment audited by the oracle, and its events.
fn solved(scene: &Scene) -> (Vec<IncrementRecord>, Vec<Event>) {
    let mut solver = scene.solver().expect("stable");
    let (mut out, mut events) = (Vec::new(), Vec::new());
    for _ in 0..scene.steps {
        let recs = solver.step(&mut Silent).expect("converges");
        events.extend(recs.iter().flat_map(|r| r.events.iter().cloned()));
        out.extend(recs);
    }
    common::assert_audited(scene, &out);
    (out, events)
}

/// The polar angle (degrees, in [0, 360)) of the force the obstacle's node `id` carries: its
/// reactions (u, v), the force holding it against the beam, which points from it to the beam.
fn reaction_angle(r: &IncrementRecord, id: u32) -> f64 {
    let at = |dof: &str| {
        (r.reactions.iter())
            .find(|x| x.node == id && x.dof == dof)
            .map_or(0.0, |x| x.value)
    };
    at("v").atan2(at("u")).to_degrees().rem_euclid(360.0)
}

/// Pressed onto an arc from 30 to 150 degrees near its top, the cantilever touches it between
/// its nodes exactly as it touches the full circle: node states and contact force equal to
/// round-off, both formulations. The contact's force points from the centre along its way to
/// the beam, inside the arc's angles, and the centre lies the radius from the beam's deformed
/// shape worked out here (within the deflection the point load adds inside the element).
#[test]
fn within_its_angles_an_arc_touches_the_elements_as_its_circle_does() {
    for f in ["BernoulliEuler", "Timoshenko"] {
        let arc = "Arc(centre: (0.65, -0.06), radius: 0.05, from_deg: 30.0, to_deg: 150.0)";
        let circle = "Circle(centre: (0.65, -0.06), radius: 0.05)";
        let (on_arc, _) = solved(&cantilever_over(f, arc, "load", 1));
        let (on_circle, _) = solved(&cantilever_over(f, circle, "load", 1));
        let (a, c) = (on_arc.last().unwrap(), on_circle.last().unwrap());
        for k in 0..11 {
            for x in 0..3 {
                assert!(
                    (a.nodes[k][x] - c.nodes[k][x]).abs() <= 1e-12,
                    "{f}: node {}",
                    k + 1
                );
            }
        }
        let ([ca], [cc]) = (a.contacts.as_slice(), c.contacts.as_slice()) else {
            panic!("{f}: one contact each: {:?} {:?}", a.contacts, c.contacts);
        };
        assert!(ca.node == 12 && (ca.pressure - cc.pressure).abs() <= 1e-9 * cc.pressure);
        let angle = reaction_angle(a, 12);
        assert!(
            (30.0..=150.0).contains(&angle),
            "{f}: force at {angle} degrees"
        );
        let slot = |id: u32| (id - 1) as usize;
        let (dist, _) = nearest_on_strip(a, &slot, (1, 10), [0.65, -0.06]);
        let within = ca.pressure * 0.1f64.powi(3) / 48.0;
        assert!(
            (dist - 0.05).abs() < within,
            "{f}: the centre {dist} m from the beam"
        );
    }
}

/// The cantilever's tip driven down 0.24 m past an arc from 80 to 150 degrees: the beam wraps
/// round the arc's start, and the contact of the arc's centre slides off there onto the arc's
/// end (its corner at 80 degrees), in one change, both formulations. Every state is audited.
/// Before the hand-over the force on the arc is its centre's, at 80 to 90 degrees; after it
/// the end's, between the normal of the radius to it (-10 degrees) and the arc's normal there
/// (80), and normal to the beam where the end presses within 1% of the force: the beam's slope
/// there worked out from the element's recorded end rotations (a cubic) and the slope its point
/// load adds in linear beam theory.
#[test]
fn a_beam_bent_round_an_arcs_end_is_handed_from_its_centre_to_the_end() {
    for f in ["BernoulliEuler", "Timoshenko"] {
        let arc = "Arc(centre: (0.65, -0.06), radius: 0.05, from_deg: 80.0, to_deg: 150.0)";
        let scene = cantilever_over(f, arc, "drag", 12);
        let (recs, events) = solved(&scene);
        assert!(
            (recs.last().unwrap().prescribed[0] + 0.24).abs() < 1e-12,
            "{f}"
        );
        // The centre is node 12, the ends 13 (at 80 degrees) and 14.
        let changes: Vec<(u32, ContactChange, usize, usize)> = (events.iter())
            .filter_map(|e| match e {
                Event::Contact(c) => Some((c.node, c.change, c.increment, c.iteration)),
                _ => None,
            })
            .collect();
        let off = (changes.iter())
            .position(|c| c.0 == 12 && c.1 == ContactChange::SlidOff)
            .unwrap_or_else(|| panic!("{f}: {changes:?}"));
        let on = changes[off + 1];
        assert!(
            on.0 == 13
                && on.1 == ContactChange::Activated
                && (on.2, on.3) == (changes[off].2, changes[off].3),
            "{f}: {changes:?}"
        );
        let holding = |r: &IncrementRecord| r.contacts.first().map(|c| c.node);
        let handed = changes[off].2;
        for r in &recs {
            match holding(r) {
                Some(12) => {
                    assert!(r.increment < handed);
                    let angle = reaction_angle(r, 12);
                    assert!(
                        (80.0..=90.0).contains(&angle),
                        "{f} {}: {angle}",
                        r.increment
                    );
                }
                Some(13) => {
                    assert!(r.increment >= handed);
                    let angle = reaction_angle(r, 13);
                    assert!(
                        angle <= 80.0 || angle >= 350.0,
                        "{f} {}: {angle}",
                        r.increment
                    );
                    // Normal to the beam where the end presses: the element's slope there,
                    // its chord's turned by the cubic of its end rotations and by the slope
                    // its point load adds (a beam fixed at both ends, loaded at a = xi l:
                    // P a^2 b^2 (b - a) / (2 EI l^3), b = l - a).
                    let c = &r.contacts[0];
                    let (p, q) = (r.nodes[c.element], r.nodes[c.element + 1]);
                    let (dx, dy) = (q[0] - p[0], q[1] - p[1]);
                    let (l, chord) = (dx.hypot(dy), dy.atan2(dx));
                    let (ti, tj, s) = (p[2] - chord, q[2] - chord, c.xi);
                    let cubic = ti * (1.0 - s) * (1.0 - 3.0 * s) - tj * s * (2.0 - 3.0 * s);
                    let force = angle.to_radians();
                    let across = c.pressure * (force - chord).sin();
                    let (a, b) = (s * l, (1.0 - s) * l);
                    let load = across * a * a * b * b * (b - a) / (2.0 * l.powi(3));
                    let slope = chord + (cubic + load).atan();
                    let along = (force - slope).cos().abs();
                    assert!(
                        along <= 0.01,
                        "{f} {}: {along} of the force along the beam",
                        r.increment
                    );
                }
                _ => {}
            }
        }
        assert_eq!(holding(recs.last().unwrap()), Some(13), "{f}");
    }
}

/// The same cantilever driven 0.24 m down round the arc's end in 12 steps and back up in 12
/// (stages), both formulations: the run completes with every state audited, the arc's end
/// holding the beam at the bottom and the arc's centre holding it again on the way up, and
/// the tip back at rest at the end.
#[test]
fn a_beam_unwrapped_from_an_arcs_end_comes_back_onto_the_arc() {
    for f in ["BernoulliEuler", "Timoshenko"] {
        let arc = "Arc(centre: (0.65, -0.06), radius: 0.05, from_deg: 80.0, to_deg: 150.0)";
        let scene = cantilever_over(f, arc, "down and up", 24);
        let (recs, _) = solved(&scene);
        let holding = |r: &IncrementRecord| r.contacts.first().map(|c| c.node);
        let bottom = (recs.iter())
            .position(|r| (r.prescribed[0] + 0.24).abs() < 1e-12)
            .expect("the bottom of the drive");
        assert_eq!(holding(&recs[bottom]), Some(13), "{f}");
        assert!(recs[bottom..].iter().any(|r| holding(r) == Some(12)), "{f}");
        assert!(recs.last().unwrap().prescribed[0].abs() < 1e-12, "{f}");
    }
}
