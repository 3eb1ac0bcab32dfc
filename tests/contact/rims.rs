//! Contact between beams at a distance from their axes: a pin with a radius pressed onto a
//! cantilever against Reissner's beam with the contact on the parallel curve at that radius
//! (`pin_elastica::rim_on_cantilever`, solved by shooting, independent of the elements), and
//! two strips with a thickness pressed onto each other, their axes kept the thickness apart.
//! Every history is audited by the oracle (`tsm_contact::audit`), which checks that no node
//! comes nearer a body than its contact distance without touching it.

use crate::common;

use tsm_contact::scene::{parse, Scene};
use tsm_contact::solver::{IncrementRecord, Silent};

/// A pin of radius `radius` whose rim starts 1 mm above a 1 m cantilever of `n` elements at
/// x = `x` (EI = 1 N m^2, EA = 1e6 N, G A = 4e5 N), driven 0.03 m down a step.
fn rim_pin(formulation: &str, n: usize, x: f64, radius: f64) -> String {
    format!(
        r#"(
        name: "pin with a radius", formulation: {formulation},
        sections: [(name: "strip", E: 1.0, A: 1.0e6, I: 1.0, G: 0.4)],
        nodes: [(id: 100000, x: {x:?}, y: {y:?}, rotation: false, radius: {radius:?})],
        bodies: [(name: "cantilever", section: "strip", path: [(0.0, 0.0), (1.0, 0.0)],
                  elements: {n}, first_node: 1)],
        supports: [(node: 1, u: true, v: true, phi: true), (node: 100000, u: true)],
        prescribed: [(node: 100000, dof: V, per_step: -0.03)],
        contacts: [(nodes: [100000], bodies: ["cantilever"])],
        control: (steps: 10),
    )"#,
        y = radius + 0.001,
    )
}

/// `scene` solved in its own steps, every increment audited by the oracle.
fn solved(scene: &Scene) -> Vec<IncrementRecord> {
    let mut solver = scene.solver().expect("stable");
    let mut out = Vec::new();
    for _ in 0..scene.steps {
        out.extend(solver.step(&mut Silent).expect("converges"));
    }
    common::assert_audited(scene, &out);
    out
}

/// A pin of radius 0.1 m pressed 0.3 m down onto the cantilever at 0.7 m, both formulations:
/// its force and the arc length to the contact point match Reissner's beam with the contact
/// on the parallel curve at 0.1 m, the error falling as h^2 from 10 to 160 elements (order
/// 1.8 to 2.3, as the point pin's), 160 elements within 1e-4. The parallel curve matters: the
/// point pin on the beam translated by the radius is further off than the coarsest mesh.
#[cfg(feature = "reports")]
#[test]
fn a_pin_with_a_radius_converges_to_the_parallel_curve_elastica_as_h_squared() {
    use tsm_contact::reports::pin_elastica::{pin_on_cantilever, rim_on_cantilever, Stiffness};
    use tsm_contact::reports::work_precision::pin_errors;
    let radius = 0.1;
    for f in ["Timoshenko", "BernoulliEuler"] {
        let mut errors = Vec::new();
        for n in [10, 20, 40, 80, 160] {
            let sc = parse(&rim_pin(f, n, 0.7, radius), "rim_pin.ron").unwrap();
            let recs = solved(&sc);
            assert!(
                !recs.last().unwrap().contacts.is_empty(),
                "{f} {n}: no contact"
            );
            let [force, arc] = pin_errors(&sc, &recs).expect("the pin on the beam");
            errors.push(force.max(arc));
        }
        eprintln!("{f}: pin of radius {radius} m, errors against the parallel curve for 10..160 elements: {errors:?}");
        let order = (errors[0] / errors[4]).ln() / 16f64.ln();
        assert!(
            (1.8..2.3).contains(&order),
            "{f}: order {order}, errors {errors:?}"
        );
        assert!(errors[4] < 1e-4, "{f}: errors {errors:?}");
        // The point pin at the same depth below the beam's translated axis.
        let k = Stiffness {
            ea: 1e6,
            ei: 1.0,
            gae: f64::INFINITY,
        };
        let centre = [0.7, radius + 0.001 - 0.3];
        let parallel = rim_on_cantilever((centre, radius), 1.0, k, 0.0).unwrap();
        let translated = pin_on_cantilever([0.7, centre[1] - radius], 1.0, k, 0.0).unwrap();
        let size = parallel.force[0].hypot(parallel.force[1]);
        let apart = (parallel.force[0] - translated.force[0])
            .hypot(parallel.force[1] - translated.force[1])
            / size;
        assert!(
            apart > errors[0],
            "{f}: translated beam {apart:e}, errors {errors:?}"
        );
    }
}

/// Two strips of thickness 20 mm, clamped at the left, the upper (0.6 m) 1 mm clear of the
/// lower (1 m), the upper's tip driven 0.1 m down: its tip touches the lower strip's upper
/// face and presses it down, both formulations. At every increment in contact the upper's tip
/// node lies the thickness (two half thicknesses) from the lower strip's axis, measured on
/// the lower strip's deformed shape (a cubic per element from the recorded end rotations,
/// sampled) to 1e-3 of the thickness; without the thickness it would lie on the axis.
#[test]
fn two_strips_with_a_thickness_press_with_their_axes_the_thickness_apart() {
    let t = 0.02;
    for f in ["BernoulliEuler", "Timoshenko"] {
        let text = format!(
            r#"(
            name: "stacked strips", formulation: {f},
            sections: [(name: "strip", E: 1.0, A: 1.0e6, I: 1.0, G: 0.4, thickness: {t:?})],
            bodies: [
                (name: "lower", section: "strip", path: [(0.0, 0.0), (1.0, 0.0)], elements: 16, first_node: 1),
                (name: "upper", section: "strip", path: [(0.0, {y:?}), (0.6, {y:?})], elements: 8, first_node: 101),
            ],
            supports: [(node: 1, u: true, v: true, phi: true), (node: 101, u: true, v: true, phi: true)],
            prescribed: [(node: 109, dof: V, per_step: -0.01)],
            contacts: [(nodes: [109], bodies: ["lower"])],
            control: (steps: 10),
        )"#,
            y = t + 0.001,
        );
        let sc = parse(&text, "strips.ron").unwrap();
        let recs = solved(&sc);
        let ids: Vec<u32> = sc.model.nodes.iter().map(|n| n.id).collect();
        let slot = |id: u32| ids.iter().position(|&k| k == id).unwrap();
        let (mut touched, mut worst) = (0, 0.0f64);
        for r in &recs {
            if r.contacts.is_empty() {
                continue;
            }
            touched += 1;
            let tip = r.nodes[slot(109)];
            let (nearest, _) = nearest_on_strip(r, &slot, (1, 16), [tip[0], tip[1]]);
            worst = worst.max((nearest - t).abs());
            assert!(
                (nearest - t).abs() < 1e-3 * t,
                "{f} increment {}: the tip {nearest:e} m from the lower axis, not {t}",
                r.increment
            );
        }
        assert!(touched >= 5, "{f}: in contact in {touched} increments");
        eprintln!("stacked strips ({f}): the tip's distance from the lower axis off t = {t} m by at most {worst:.1e} m over {touched} increments");
    }
}

/// The nearest point to `p` of the deformed body whose elements run from node id `first` to
/// `first + n` along x, each a cubic through its end nodes with their recorded rotations
/// (sampled): the distance and the slope angle of the beam there.
pub(crate) fn nearest_on_strip(
    r: &IncrementRecord,
    slot: &dyn Fn(u32) -> usize,
    (first, n): (u32, u32),
    p: [f64; 2],
) -> (f64, f64) {
    let mut best = (f64::INFINITY, 0.0);
    for e in 0..n {
        let (a, b) = (r.nodes[slot(first + e)], r.nodes[slot(first + e + 1)]);
        let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
        let l = dx.hypot(dy);
        let chord = dy.atan2(dx);
        let (ti, tj) = (a[2] - chord, b[2] - chord);
        for k in 0..=2000 {
            let s = k as f64 / 2000.0;
            let w = l * (ti * s * (1.0 - s).powi(2) - tj * s * s * (1.0 - s));
            let slope = ti * (1.0 - s) * (1.0 - 3.0 * s) - tj * s * (2.0 - 3.0 * s);
            let q = [a[0] + s * dx - w * dy / l, a[1] + s * dy + w * dx / l];
            let dist = (p[0] - q[0]).hypot(p[1] - q[1]);
            if dist < best.0 {
                best = (dist, chord + slope.atan());
            }
        }
    }
    best
}

/// The built-in roller (radius 50 mm, frictionless) rolled along the cantilever on 10, 20, 50
/// and 100 elements: wherever it presses, its centre lies its radius from the beam's deformed
/// shape (within the deflection its point load adds inside the element), its horizontal force is its normal force times the slope of
/// the beam under it (H = -V tan(slope), within 1% of the normal force; the slope taken from
/// the node states, a cubic per element), and the force curve is smooth: no increment's
/// horizontal force leaves the mean of its neighbours' by more than 1% of the normal force
/// (a roller resting on the nodes alone makes a sawtooth of the element's period, of 20% of
/// it).
#[test]
fn the_roller_force_follows_the_slope_under_it_smoothly_on_every_mesh() {
    use tsm_contact::scene::{builtin::builtin, from_scene_file, remesh::remesh};
    let base = builtin("roller").unwrap().unwrap();
    for n in [10u32, 20, 50, 100] {
        let file = remesh(&base.file, n as usize).expect("one body");
        let sc = from_scene_file(file, "roller").unwrap();
        let recs = solved(&sc);
        assert_eq!(recs.len(), 48, "{n}: every step");
        let ids: Vec<u32> = sc.model.nodes.iter().map(|node| node.id).collect();
        let slot = |id: u32| ids.iter().position(|&k| k == id).unwrap();
        let force = |r: &IncrementRecord, dof: &str| {
            (r.reactions.iter())
                .find(|x| x.node == 1000 && x.dof == dof)
                .map_or(0.0, |x| x.value)
        };
        let mut curve = Vec::new();
        let mut worst_slope: f64 = 0.0;
        for r in recs.iter().filter(|r| !r.contacts.is_empty()) {
            let (h, v) = (force(r, "u"), force(r, "v"));
            let centre = r.nodes[slot(1000)];
            let (dist, slope) = nearest_on_strip(r, &slot, (1, n), [centre[0], centre[1]]);
            let normal = h.hypot(v);
            // The cubic through the end rotations leaves out what the roller's point load adds
            // inside the element, at most that of a simply supported span under a central
            // load, N l^3 / (48 EI).
            let (l, ei) = (1.0 / n as f64, sc.model.beams[0].section.ei);
            let within = normal * l.powi(3) / (48.0 * ei);
            assert!(
                (dist - 0.05).abs() < within,
                "{n} increment {}: the centre {dist} m from the beam, not within {within:e} of 0.05",
                r.increment
            );
            let expected = -v * slope.tan();
            assert!(
                (h - expected).abs() < 0.01 * normal,
                "{n} increment {}: H {h} against {expected} (N {normal})",
                r.increment
            );
            worst_slope = worst_slope.max((h - expected).abs() / normal);
            curve.push((h, normal));
        }
        assert!(
            curve.len() >= 30,
            "{n}: {} increments in contact",
            curve.len()
        );
        let mut worst_smooth: f64 = 0.0;
        for w in curve.windows(3).skip(1) {
            let mean = 0.5 * (w[0].0 + w[2].0);
            worst_smooth = worst_smooth.max((w[1].0 - mean).abs() / w[1].1);
            assert!(
                (w[1].0 - mean).abs() < 0.01 * w[1].1,
                "{n}: H {} off the mean of its neighbours {mean} (N {})",
                w[1].0,
                w[1].1
            );
        }
        eprintln!(
            "roller on {n} elements: |H + V tan(slope)| / N at most {worst_slope:.1e}, H off the mean of its neighbours / N at most {worst_smooth:.1e}"
        );
    }
}

/// One-step loads onto a fixed peg and a roller on 10-element meshes, both formulations: a
/// cantilever's tip loaded at once onto a peg of radius 5 cm standing under it between two
/// nodes, and the built-in roller driven in one step 0.25 m along and 0.025 m down (into the
/// strip by 15 mm). Each completes; the circle presses on one element with a positive
/// pressure; its centre lies its radius from the beam's deformed shape (within the deflection
/// its point load adds inside the element) and on its own side (the peg below the beam, the
/// roller above); the peg's centre node carries the force on it, the load less the clamp's.
#[test]
fn one_step_loads_onto_a_peg_and_a_roller_on_ten_elements_touch_on_the_right_side() {
    use tsm_contact::scene::{builtin::builtin, from_scene_file, remesh::remesh};
    for f in ["BernoulliEuler", "Timoshenko"] {
        let peg = format!(
            r#"(
            name: "cantilever onto a peg", formulation: {f},
            sections: [(name: "strip", E: 1.0, A: 1.0e6, I: 1.0, G: 0.4)],
            bodies: [(name: "beam", section: "strip", path: [(0.0, 0.0), (1.0, 0.0)], elements: 10, first_node: 1)],
            supports: [(node: 1, u: true, v: true, phi: true)],
            loads: [(node: 11, fy: -1.0)],
            obstacles: [(name: "peg", shape: Circle(centre: (0.65, -0.06), radius: 0.05), bodies: ["beam"], touches: Elements)],
            control: (steps: 1),
        )"#
        );
        let peg = parse(&peg, "peg.ron").unwrap();
        // The peg's centre node: the next id after the scene's largest (11), held.
        assert_eq!(peg.model.nodes.last().map(|n| n.id), Some(12));
        let mut roller = builtin("roller").unwrap().unwrap().file;
        roller.formulation = if f == "Timoshenko" {
            tsm_contact::solver::Formulation::Timoshenko
        } else {
            tsm_contact::solver::Formulation::BernoulliEuler
        };
        let mut roller = remesh(&roller, 10).unwrap();
        for p in &mut roller.prescribed {
            p.per_step *= 20.0;
        }
        roller.control.steps = 1;
        let roller = from_scene_file(roller, "roller").unwrap();
        for (sc, centre_id, above) in [(&peg, 12u32, false), (&roller, 1000, true)] {
            let recs = solved(sc);
            let last = recs.last().unwrap();
            assert!(last.load_factor == 1.0 || !last.prescribed.is_empty());
            let [contact] = last.contacts.as_slice() else {
                panic!("{f} {centre_id}: contacts {:?}", last.contacts);
            };
            assert!(
                contact.node == centre_id && contact.pressure > 0.0,
                "{contact:?}"
            );
            let ids: Vec<u32> = sc.model.nodes.iter().map(|n| n.id).collect();
            let slot = |id: u32| ids.iter().position(|&k| k == id).unwrap();
            let c = last.nodes[slot(centre_id)];
            let (dist, _) = nearest_on_strip(last, &slot, (1, 10), [c[0], c[1]]);
            let ei = sc.model.beams[0].section.ei;
            let within = contact.pressure * 0.1f64.powi(3) / (48.0 * ei);
            assert!(
                (dist - 0.05).abs() < within,
                "{f} {centre_id}: {dist} m from the beam"
            );
            // Its side: the beam's deflection under the centre against the centre's height.
            let e = contact.element;
            let (a, b) = (
                last.nodes[slot(1 + e as u32)],
                last.nodes[slot(2 + e as u32)],
            );
            let s = ((c[0] - a[0]) / (b[0] - a[0])).clamp(0.0, 1.0);
            let under = a[1] + s * (b[1] - a[1]);
            assert_eq!(
                c[1] > under,
                above,
                "{f} {centre_id}: centre {c:?}, beam at {under}"
            );
        }
        let last = solved(&peg).pop().unwrap();
        let v = |id: u32| {
            (last.reactions.iter())
                .find(|r| r.node == id && r.dof == "v")
                .map_or(0.0, |r| r.value)
        };
        assert!(
            (v(12) + v(1) - 1.0).abs() < 1e-7,
            "peg {} clamp {}",
            v(12),
            v(1)
        );
        assert!(v(12) > 0.5, "the peg holds the tip up: {}", v(12));
    }
}

/// `touches: Elements` is refused, naming the obstacle's field, on a shape other than a solid
/// circle, a solid arc or a polyline (a line, a hollow arc), and with its pilot off its centre.
#[test]
fn touching_elements_is_refused_where_it_cannot_be_carried() {
    let scene = |obstacle: &str| {
        format!(
            r#"(
            name: "bad", sections: [(name: "s", E: 1.0, A: 1.0, I: 1.0, thickness: 0.01)],
            nodes: [(id: 100, x: 0.5, y: 0.3, rotation: false)],
            bodies: [(name: "beam", section: "s", path: [(0.0, 0.0), (1.0, 0.0)], elements: 4, first_node: 1)],
            supports: [(node: 1, u: true, v: true, phi: true), (node: 100, u: true, v: true)],
            obstacles: [{obstacle}],
        )"#
        )
    };
    for (obstacle, says) in [
        (
            r#"(name: "floor", shape: Line(from: (0.0, -0.1), to: (1.0, -0.1)), bodies: ["beam"], touches: Elements)"#,
            "only a solid circle",
        ),
        (
            r#"(name: "peg", shape: Circle(centre: (0.5, 0.2), radius: 0.1), bodies: ["beam"], pilot: 100, touches: Elements)"#,
            "must sit at its centre",
        ),
        (
            r#"(name: "ring", shape: Arc(centre: (0.5, 0.0), radius: 0.4, from_deg: 200.0, to_deg: 340.0, hollow: true), bodies: ["beam"], touches: Elements)"#,
            "only a solid circle",
        ),
    ] {
        let err = parse(&scene(obstacle), "bad.ron").unwrap_err().to_string();
        assert!(
            err.contains("obstacles[0].touches") && err.contains(says),
            "{obstacle}: {err}"
        );
    }
}

/// A cantilever of 8 elements loaded at its tip over a table's edge that stands between two of
/// its nodes (a polyline's convex corner), both formulations. With `touches: Elements` the edge
/// is a held node of its own that touches the strip's elements: every step completes, the edge
/// presses on the element it stands under, the strip lies on it (the edge within the
/// deflection its point load adds inside the element of the strip's shape), and the edge's
/// node and the clamp carry the load between them. A rough edge (mu 0.3) holds the strip's
/// tip pulled along within mu N, at mu N where it slips. Touching the nodes alone, the strip cannot
/// hold the edge between its nodes and the run stops, naming the obstacle.
#[test]
fn a_strip_bends_over_a_table_edge_between_its_nodes() {
    use tsm_contact::solver::SolveError;
    for f in ["BernoulliEuler", "Timoshenko"] {
        let text = |touches: &str| {
            format!(
                r#"(
            name: "strip over a table edge", formulation: {f},
            sections: [(name: "strip", E: 1.0, A: 1.0e6, I: 1.0, G: 0.4)],
            bodies: [(name: "strip", section: "strip", path: [(0.0, 0.001), (1.0, 0.001)], elements: 8, first_node: 1)],
            supports: [(node: 1, u: true, v: true, phi: true)],
            loads: [(node: 9, fy: -1.0)],
            obstacles: [(name: "table", shape: Polyline(points: [(-1.0, 0.0), (0.55, 0.0), (0.55, -1.0)]),
                         bodies: ["strip"], touches: {touches})],
            control: (steps: 4),
        )"#
            )
        };
        let sc = parse(&text("Elements"), "edge.ron").unwrap();
        let edge = sc.model.nodes.last().unwrap().id;
        assert_eq!(edge, 10, "the edge's node: the next id");
        let recs = solved(&sc);
        let last = recs.last().unwrap();
        assert_eq!(last.load_factor, 1.0);
        let [contact] = last.contacts.as_slice() else {
            panic!("{f}: contacts {:?}", last.contacts);
        };
        assert!(contact.node == edge && contact.element == 4 && contact.pressure > 0.0);
        let ids: Vec<u32> = sc.model.nodes.iter().map(|n| n.id).collect();
        let slot = |id: u32| ids.iter().position(|&k| k == id).unwrap();
        let (dist, _) = nearest_on_strip(last, &slot, (1, 8), [0.55, 0.0]);
        let within = contact.pressure * 0.125f64.powi(3) / (48.0 * 1.0);
        assert!(dist < within, "{f}: the edge {dist} m from the strip");
        let v = |id: u32| {
            (last.reactions.iter())
                .find(|r| r.node == id && r.dof == "v")
                .map_or(0.0, |r| r.value)
        };
        assert!(
            (v(edge) + v(1) - 1.0).abs() < 1e-7,
            "edge {} clamp {}",
            v(edge),
            v(1)
        );
        // A rough edge (mu 0.3, the strip's tip pulled along too): the corner's contact takes
        // the table's friction, slipping at mu N or sticking within it.
        let rough = text("Elements, mu: 0.3").replace("fy: -1.0)", "fx: 0.5, fy: -1.0)");
        let rough = parse(&rough, "edge.ron").unwrap();
        let last = solved(&rough).pop().unwrap();
        let [c] = last.contacts.as_slice() else {
            panic!("{f}: contacts {:?}", last.contacts);
        };
        let limit = 0.3 * c.pressure;
        let slipping = c.friction == tsm_contact::solver::Friction::Slipping;
        assert!(c.tangential.abs() > 0.1 * limit, "{f}: no friction {c:?}");
        assert!(
            c.tangential.abs() <= limit * (1.0 + 1e-6),
            "{f}: beyond mu N {c:?}"
        );
        assert!(
            !slipping || c.tangential.abs() >= limit * (1.0 - 1e-6),
            "{f}: {c:?}"
        );
        let nodes_only = parse(&text("Nodes"), "edge.ron").unwrap();
        let mut solver = nodes_only.solver().unwrap();
        let stopped = (0..4).find_map(|_| solver.step(&mut Silent).err());
        assert!(
            matches!(stopped, Some(SolveError::ObstacleThrough { .. })),
            "{f}: {stopped:?}"
        );
    }
}

/// The oracle finds a pin sunk into the beam: the last state of the pin of radius 0.1 m on 16
/// elements, its centre moved 5 cm towards the beam, overlaps elements beyond the one it rests
/// on and their neighbours, and is found though its contact is recorded; with the contact
/// left out of the record, it is found as well. The history itself is clean.
#[test]
fn the_oracle_finds_a_pin_sunk_into_the_beam_beyond_its_contact() {
    let sc = parse(&rim_pin("BernoulliEuler", 16, 0.7, 0.1), "rim_pin.ron").unwrap();
    let recs = solved(&sc);
    let pin = sc.model.nodes.iter().position(|n| n.id == 100000).unwrap();
    let sunk = |keep_contact: bool| {
        let mut r = recs.clone();
        let last = r.last_mut().unwrap();
        last.nodes[pin][1] -= 0.05;
        if !keep_contact {
            last.contacts.clear();
        }
        common::findings(&sc, &r)
    };
    for keep in [true, false] {
        let found = sunk(keep);
        assert!(
            found
                .iter()
                .any(|f| f.what.contains("within its contact distance") && f.node == Some(100000)),
            "contact kept {keep}: {found:?}"
        );
    }
}

/// The built-in roller with friction (mu 0.3) on 20 elements: a rigid roller that does not
/// turn, dragged along the strip, slips with its friction force at mu N against the slip in
/// every increment after the first in contact, and the oracle finds every state in
/// equilibrium with the force on the strip where the roller presses on its axis (it would find
/// the friction's moment missing with the force put at the roller's centre), both
/// formulations; and so on the strip with its thickness, balanced where the faces touch.
#[test]
fn a_rough_roller_slips_along_the_strip_at_mu_n() {
    use tsm_contact::scene::{builtin::builtin, from_scene_file, remesh::remesh};
    use tsm_contact::solver::Friction;
    for f in [
        tsm_contact::solver::Formulation::BernoulliEuler,
        tsm_contact::solver::Formulation::Timoshenko,
    ] {
        let mut file = builtin("roller").unwrap().unwrap().file;
        file.formulation = f;
        file.obstacles[0].mu = 0.3;
        // With the strip's own thickness (10 mm, of its A and I), the friction at its face
        // also bends it: the oracle balances the strip with the force where the faces touch.
        let mut thick = file.clone();
        thick.sections[0].thickness = Some(0.01);
        let sc = from_scene_file(remesh(&thick, 20).unwrap(), "roller").unwrap();
        let recs = solved(&sc);
        let rubbing: Vec<_> = (recs.iter())
            .filter_map(|r| r.contacts.first())
            .skip(1)
            .collect();
        assert!(
            rubbing.len() > 30,
            "{f:?}, thick: {} in contact",
            rubbing.len()
        );
        for c in rubbing {
            assert_eq!(c.friction, Friction::Slipping, "{f:?}, thick: {c:?}");
            let ratio = c.tangential.abs() / (0.3 * c.pressure);
            assert!(
                (ratio - 1.0).abs() < 1e-6,
                "{f:?}, thick: T / mu N = {ratio}"
            );
        }
        let sc = from_scene_file(remesh(&file, 20).unwrap(), "roller").unwrap();
        let recs = solved(&sc);
        let last = recs.last().unwrap();
        assert!(
            (last.prescribed[0] - 0.6).abs() < 1e-12,
            "{f:?}: every step"
        );
        let rubbing: Vec<_> = (recs.iter())
            .filter_map(|r| r.contacts.first())
            .skip(1)
            .collect();
        assert!(rubbing.len() > 30, "{f:?}: {} in contact", rubbing.len());
        for c in rubbing {
            assert!(c.point.is_some(), "{c:?}");
            assert_eq!(c.friction, Friction::Slipping, "{f:?}: {c:?}");
            let ratio = c.tangential.abs() / (0.3 * c.pressure);
            assert!((ratio - 1.0).abs() < 1e-6, "{f:?}: T / mu N = {ratio}");
        }
        // The same history with the force on the strip put at the roller's centre is out of
        // balance by the friction's moment.
        let mut moved = recs.clone();
        for r in &mut moved {
            for c in &mut r.contacts {
                c.point = None;
            }
        }
        let found = common::findings(&sc, &moved);
        assert!(
            found.iter().any(|x| x.what.contains("out of balance")),
            "{f:?}: {found:?}"
        );
    }
}
