//! Hard cases (the stability suite of `tsm_contact::reports::stress`), each checked against an
//! independent reference: Williams' toggle and Lee's frame limit loads against converged
//! references (and arc length against displacement control), contact near element ends,
//! a pin slid over a 50-element beam (one transfer per element boundary), a beam pressed flat
//! and released (path independence, stress-free when unloaded), slender and stubby members
//! against the elastica and the exact linear Timoshenko cantilever, short elements next to long
//! ones, a cantilever rolled up more than twice (exact circle), and a cantilever of a million
//! elements (ill-conditioned, not a mechanism) against linear theory.
#![cfg(feature = "reports")]

use tsm_contact::reports::stress;
use tsm_contact::scene::{builtin::BUILTIN, parse};
use tsm_contact::solver::{Formulation, Silent};

fn apex_reactions(elements: usize, step: f64, steps: usize) -> Vec<(f64, f64)> {
    let text = BUILTIN
        .iter()
        .find(|(f, _)| *f == "williams_toggle.ron")
        .unwrap()
        .1;
    let apex = elements + 1;
    let text = text
        .replace("elements: 10", &format!("elements: {elements}"))
        .replace(
            "(node: 11, dof: V, per_step: -0.03)",
            &format!("(node: {apex}, dof: V, per_step: {})", -step),
        )
        .replace(
            "(node: 21, u: true",
            &format!("(node: {}, u: true", 2 * elements + 1),
        )
        .replace("steps: 40", &format!("steps: {steps}"));
    let sc = parse(&text, "toggle").unwrap();
    let mut solver = sc.solver().unwrap();
    let mut out = Vec::new();
    for _ in 0..steps {
        for r in solver
            .step(&mut Silent)
            .expect("displacement control passes the limit point")
        {
            let v = r
                .reactions
                .iter()
                .find(|x| x.node == apex as u32 && x.dof == "v")
                .unwrap()
                .value;
            out.push((-r.prescribed[0], v.abs()));
        }
    }
    out
}

/// Index of the first local maximum of the load.
fn first_max(curve: &[(f64, f64)]) -> usize {
    (1..curve.len() - 1)
        .find(|&k| curve[k].1 >= curve[k - 1].1 && curve[k].1 > curve[k + 1].1)
        .expect("a limit point")
}

/// The first local maximum of the load, refined by a parabola through its neighbours.
fn peak(curve: &[(f64, f64)]) -> f64 {
    stress::first_peak(curve).expect("a limit point")
}

#[test]
fn toggle_limit_load_within_one_percent_of_a_converged_reference() {
    let coarse = apex_reactions(10, 0.03, 40);
    let reference = apex_reactions(40, 0.003, 400);
    let (pc, pr) = (peak(&coarse), peak(&reference));
    assert!(
        ((pc - pr) / pr).abs() < 0.01,
        "limit load {pc} vs converged {pr}"
    );
    // Past the limit point the load really falls (the snap-through under load control) before
    // the stretched toggle stiffens again.
    let dip = coarse
        .iter()
        .skip(first_max(&coarse))
        .map(|p| p.1)
        .fold(f64::MAX, f64::min);
    assert!(
        dip < 0.95 * pr,
        "no load drop after the limit point: minimum {dip}, peak {pr}"
    );
}

const BOTH: [Formulation; 2] = [Formulation::Timoshenko, Formulation::BernoulliEuler];

#[test]
fn toggle_limit_load_by_arc_length_matches_displacement_control() {
    // The same toggle, loaded at the apex and traced by arc length: the same equilibrium path,
    // so the same limit load as under displacement control (to the parabola fits' accuracy).
    let text = BUILTIN
        .iter()
        .find(|(f, _)| *f == "williams_toggle.ron")
        .unwrap()
        .1
        .replace(
            "prescribed: [(node: 11, dof: V, per_step: -0.03)]",
            "loads: [(node: 11, fy: -1.0)]",
        )
        .replace(
            "control: (steps: 40)",
            "control: (steps: 60, arc_length: 0.004)",
        );
    let run = stress::run("toggle, arc length", &text, &stress::Path::Steps(60));
    assert!(run.row.converged, "{:?}", run.row.error);
    let curve: Vec<(f64, f64)> = run
        .records
        .iter()
        .map(|r| (r.increment as f64, r.load_factor))
        .collect();
    let arc = stress::first_peak(&curve).expect("a limit point");
    let disp = peak(&apex_reactions(10, 0.003, 400));
    assert!(
        ((arc - disp) / disp).abs() < 1e-3,
        "arc-length limit {arc} vs displacement control {disp}"
    );
}

#[test]
fn lee_frame_limit_load_within_one_percent_and_both_limit_points_passed() {
    for f in BOTH {
        let coarse = stress::lee_frame(10, 0.5, 60, f);
        let fine = stress::lee_frame(40, 0.25, 120, f);
        let finer = stress::lee_frame(80, 0.125, 240, f);
        let value = |r: &stress::Run| r.row.measure.as_ref().expect("a limit point").1;
        let (pc, p40, p80) = (value(&coarse), value(&fine), value(&finer));
        // Converged reference: Richardson extrapolation of the O(h^2) mesh error.
        let reference = p80 + (p80 - p40) / 3.0;
        assert!(
            ((pc - reference) / reference).abs() < 0.01,
            "{f:?}: limit load {pc} vs converged {reference}"
        );
        assert!(((p80 - reference) / reference).abs() < 1e-3);
        // The path goes on through the load minimum (negative load) and up again.
        let long = stress::lee_frame(10, 0.5, 160, f);
        assert!(long.row.converged, "{:?}", long.row.error);
        let lambdas: Vec<f64> = long.records.iter().map(|r| r.load_factor).collect();
        let (kmin, min) = lambdas
            .iter()
            .enumerate()
            .fold((0, f64::MAX), |a, (k, &l)| if l < a.1 { (k, l) } else { a });
        assert!(min < -0.5, "{f:?}: load minimum {min}");
        assert!(
            lambdas[lambdas.len() - 1] > min + 0.5,
            "{f:?}: no rise after the minimum"
        );
        assert!(kmin > 50 && kmin < lambdas.len() - 5, "minimum at {kmin}");
        eprintln!("Lee's frame {f:?}: limit {pc:.5} (10 el.), {p40:.5} (40), {p80:.5} (80), extrapolated {reference:.5}; minimum {min:.4}");
    }
}

#[test]
fn timoshenko_contact_converges_near_element_ends_and_bernoulli_euler_fails_cleanly() {
    for xi in [0.9, 0.97, 0.99, 0.999, 0.9999] {
        let t = stress::pin_near_end(xi, Formulation::Timoshenko);
        assert!(
            t.row.converged,
            "Timoshenko at li/l = {xi}: {:?}",
            t.row.error
        );
        // Every increment to the tolerance itself, not to a round-off floor.
        assert!(
            t.row.max_residual <= 1e-8,
            "li/l = {xi}: {}",
            t.row.max_residual
        );
        // The contact starts on element 5 near its end and ends on 5 or, transferred, on 6.
        assert!(t.records.iter().all(|r| r.contacts.len() <= 1
            && r.contacts.iter().all(|c| c.element == 5 || c.element == 6)));
        if xi >= 0.97 {
            assert!(t.row.transfers >= 1, "li/l = {xi}: no transfer");
        }
        // Bernoulli-Euler: K44 ~ 3 EI / li^3 puts the residual's round-off floor far above the
        // tolerance near the element end. The run converges, or stops with a typed error (no
        // convergence, or a stall at a round-off floor above the bound); it never accepts a
        // state beyond the bound.
        let b = stress::pin_near_end(xi, Formulation::BernoulliEuler);
        assert!(
            b.row.max_residual <= 1e-5,
            "li/l = {xi}: {}",
            b.row.max_residual
        );
        match &b.row.error {
            None => assert!(b.row.increments >= 10),
            Some(e) => assert!(
                e.contains("no convergence") || e.contains("Newton stalls"),
                "{e}"
            ),
        }
        eprintln!(
            "li/l {xi}: Timoshenko {} increments, {} transfers; Bernoulli-Euler {}",
            t.row.increments,
            t.row.transfers,
            b.row.error.as_deref().unwrap_or("converged")
        );
    }
}

#[test]
fn pin_slides_over_every_element_off_the_tip_and_back_on() {
    for f in BOTH {
        let r = stress::slide_across(50, f);
        assert!(r.row.converged, "{f:?}: {:?}", r.row.error);
        // From element 0 to 49: one transfer per inner element boundary (49), plus none back.
        assert!(
            r.row.transfers >= 49,
            "{f:?}: {} transfers",
            r.row.transfers
        );
        assert!(
            r.row.releases >= 1 && r.row.activations >= 2,
            "{f:?}: {:?}",
            r.row
        );
        let last = r.records.last().unwrap();
        assert_eq!(
            last.contacts.len(),
            1,
            "{f:?}: pressed on again at mid-span"
        );
        assert!((last.contacts[0].element as f64 + last.contacts[0].xi) / 50.0 > 0.4);
        assert!(r.records.iter().all(|x| x.max_penetration < 1e-6));
    }
}

#[test]
fn beam_pressed_flat_releases_completely_and_recontacts_along_the_same_path() {
    for f in BOTH {
        let r = stress::pressed_flat(f, 10);
        assert!(r.row.converged, "{f:?}: {:?}", r.row.error);
        assert!(
            r.row.max_contacts >= 10,
            "{f:?}: {} contacts",
            r.row.max_contacts
        );
        // Unloaded: no contact left, stress-free.
        let peak_force = r
            .records
            .iter()
            .flat_map(|x| x.element_forces.iter().flatten())
            .fold(0.0f64, |a, v| a.max(v.abs()));
        let unloaded = r
            .records
            .iter()
            .find(|x| x.load_factor == 0.0)
            .expect("the unloaded state");
        assert!(unloaded.contacts.is_empty());
        let rest = unloaded
            .element_forces
            .iter()
            .flatten()
            .fold(0.0f64, |a, v| a.max(v.abs()));
        assert!(rest < 1e-9 * peak_force, "{f:?}: {rest} vs {peak_force}");
        // Elastic and frictionless: loaded again, the same state as the first time.
        let first = r.records.iter().find(|x| x.load_factor == 0.5).unwrap();
        let again = r.records.last().unwrap();
        assert_eq!(again.load_factor, 0.5);
        let diff = first
            .nodes
            .iter()
            .zip(&again.nodes)
            .map(|(a, b)| (a[0] - b[0]).hypot(a[1] - b[1]))
            .fold(0.0f64, f64::max);
        assert!(diff < 1e-9, "{f:?}: states differ by {diff} m");
        assert_eq!(first.contacts.len(), again.contacts.len());
    }
}

#[test]
fn slender_and_stubby_members_match_their_references() {
    for f in BOTH {
        for s in [1e3, 1e4] {
            let r = stress::slender(s, f);
            let (_, w, w_ref) = r.row.measure.clone().expect("converged");
            // 32 elements: the discretisation error of the Mattiasson scene (about 1e-4).
            assert!(
                (w - w_ref).abs() < 2e-4,
                "{f:?} L/h {s}: w/L {w} vs {w_ref}"
            );
        }
        for s in [1.0, 2.0, 5.0] {
            let r = stress::stubby(s, f);
            let (_, w, exact) = r.row.measure.clone().expect("converged");
            assert!(
                ((w - exact) / exact).abs() < 1e-9,
                "{f:?} L/h {s}: {w} vs {exact}"
            );
        }
        // Up to element lengths 1000 : 1: the short elements' relative positions come from
        // the differences of the carried coordinates (`assembly/coordinates.rs`), so their
        // stiffness (10^9 times the long ones') does not lift the residual's round-off floor
        // above the bound for acceptance at round-off (1e-5).
        for ratio in [1e1, 1e2, 1e3] {
            let r = stress::short_next_to_long(ratio, f);
            let (_, w, w_ref) = r.row.measure.clone().expect("converged");
            assert!(
                (w - w_ref).abs() < 3e-3,
                "{f:?} ratio {ratio}: w/L {w} vs {w_ref}"
            );
        }
    }
}

#[test]
fn cantilever_rolls_up_more_than_twice_onto_the_exact_circle() {
    for f in BOTH {
        // Two full turns: the tip is back at the clamp exactly (any mesh).
        let two = stress::roll_up(2.0, 32, 20, f);
        let tip = two.records.last().expect("converged").nodes[32];
        assert!(tip[0].hypot(tip[1]) < 1e-10, "{f:?}: tip at {tip:?}");
        assert!((tip[2] - 2.0 * std::f64::consts::TAU).abs() < 1e-9);
        // 2.25 turns: the error against the exact circle falls as O(h^2).
        let e32 = stress::roll_up(2.25, 32, 20, f).row.measure.unwrap().1;
        let e64 = stress::roll_up(2.25, 64, 20, f).row.measure.unwrap().1;
        assert!(
            e32 < 1e-3 && (3.5..4.5).contains(&(e32 / e64)),
            "{f:?}: {e32} {e64}"
        );
    }
}

/// A clamped cantilever of a million elements with EA / EI = 1e6 (l = 1e-6 m), loaded at its
/// tip: a stiff, ill-conditioned chain, not a mechanism. The scene is accepted, and the step
/// lands on linear theory's tip deflection P L^3 / (3 EI) to 1e-3 (the load is small: the
/// rotation 5e-4 rad), at the round-off floor at worst.
#[test]
fn a_cantilever_of_a_million_elements_is_no_mechanism_and_bends_as_theory_says() {
    let text = r#"(
    name: "long cantilever",
    sections: [(name: "s", E: 1.0, A: 1.0e6, I: 1.0)],
    bodies: [(name: "b", section: "s", path: [(0.0, 0.0), (1.0, 0.0)], elements: 1000000, first_node: 1)],
    supports: [(node: 1, u: true, v: true, phi: true)],
    loads: [(node: 1000001, fy: -1e-3)],
    control: (steps: 1),
)"#;
    let scene = parse(text, "long cantilever").expect("accepted: no mechanism");
    let mut solver = scene.solver().expect("a stable structure");
    solver.step(&mut Silent).expect("the step converges");
    let (tip, _) = solver.node_state(solver.structure().model.nodes.len() - 1);
    let exact = -1e-3 / 3.0;
    assert!(
        (tip[1] - exact).abs() < 1e-3 * exact.abs(),
        "tip {} against {exact}",
        tip[1]
    );
}
