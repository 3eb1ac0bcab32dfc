//! A column in a channel: a pinned-pinned strip with a small kink at midspan (its halves
//! rising and falling at beta0), between two walls (line obstacles a distance c either side of
//! its axis), shortened by a prescribed end displacement. Until it touches a wall each half is
//! an elastica, solved here by shooting: from the pinned end (theta = alpha, no moment)
//! EI theta'' = -P sin theta up to midspan, where the tangent is the stress-free kink's
//! beta0 (the midspan node does not turn, by symmetry); alpha by bisection on that, P by
//! bisection on the midspan deflection. The column's thrust at each deflection is that
//! elastica's, the error falling as h^2; its first contact is its midspan node on the wall
//! it bows towards, in the increment where its deflection reaches c; that point contact is
//! alone until the thrust at which it turns into a line contact (`line_contact_thrust`), and
//! the contacts stay symmetric about midspan; no node crosses a wall.

use crate::common;

use tsm_contact::scene::parse;
use tsm_contact::solver::{Event, IncrementRecord, Silent};

/// Half the channel's width and the kink's rise at midspan (L = 1, EI = 1).
const C: f64 = 0.05;
const E0: f64 = 0.002;

/// The half column's end state (y, theta) at midspan for thrust `p` and end slope `alpha`, by
/// RK4 on 400 steps.
fn half(p: f64, alpha: f64) -> (f64, f64) {
    let steps = 400;
    let h = 0.5 / steps as f64;
    // [y, theta, theta']
    let f = |y: [f64; 3]| [y[1].sin(), y[2], -p * y[1].sin()];
    let mut y = [0.0, alpha, 0.0];
    for _ in 0..steps {
        let add = |y: [f64; 3], k: [f64; 3], c: f64| std::array::from_fn(|i| y[i] + c * k[i]);
        let k1 = f(y);
        let k2 = f(add(y, k1, h / 2.0));
        let k3 = f(add(y, k2, h / 2.0));
        let k4 = f(add(y, k3, h));
        y = std::array::from_fn(|i| y[i] + h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]));
    }
    (y[0], y[1])
}

/// The midspan deflection of the kinked column under thrust `p` (alpha found by bisection
/// so that the tangent at midspan is the kink's).
fn deflection(p: f64) -> f64 {
    let beta0 = (2.0 * E0).atan();
    let (mut lo, mut hi) = (beta0, 1.5);
    for _ in 0..56 {
        let mid = 0.5 * (lo + hi);
        // On this branch the tangent at midspan grows with alpha.
        if half(p, mid).1 > beta0 {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    half(p, 0.5 * (lo + hi)).0
}

/// The thrust at midspan deflection `delta` (bisection: the deflection grows with the thrust
/// on this branch).
fn thrust(delta: f64) -> f64 {
    let (mut lo, mut hi) = (1.0, 4.0 * std::f64::consts::PI.powi(2));
    for _ in 0..48 {
        let mid = 0.5 * (lo + hi);
        if deflection(mid) < delta {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

/// The kinked column on `n` elements (n even) shortened 0.5 mm a step for `steps` steps.
fn column(n: usize, steps: usize) -> Vec<IncrementRecord> {
    let text = format!(
        r#"(
    name: "channel",
    formulation: BernoulliEuler,
    sections: [(name: "s", E: 1.0, A: 1.0e7, I: 1.0, G: 1.0e12)],
    bodies: [(name: "column", section: "s", path: [(0.0, 0.0), (0.5, {E0}), (1.0, 0.0)], elements: {half}, first_node: 1)],
    supports: [(node: 1, u: true, v: true), (node: {end}, v: true)],
    prescribed: [(node: {end}, dof: U, per_step: -0.0005)],
    obstacles: [
        (name: "lower wall", shape: Line(from: (0.0, -{C}), to: (1.0, -{C})), bodies: ["column"]),
        (name: "upper wall", shape: Line(from: (1.0, {C}), to: (0.0, {C})), bodies: ["column"]),
    ],
    control: (steps: {steps}),
)"#,
        half = n / 2,
        end = n + 1,
    );
    let scene = parse(&text, "channel.ron").expect("a valid scene");
    let mut solver = scene.solver().unwrap();
    let mut out = Vec::new();
    for _ in 0..steps {
        out.extend(solver.step(&mut Silent).expect("converges"));
    }
    common::assert_audited(&scene, &out);
    out
}

#[test]
fn a_column_in_a_channel_bows_as_the_elastica_and_touches_at_midspan_first() {
    let p2 = line_contact_thrust();
    let mut worst = Vec::new();
    for n in [8, 16, 32] {
        let records = column(n, 20);
        let mid = n / 2;
        let mut error: f64 = 0.0;
        let mut first = None;
        for r in &records {
            let delta = r.nodes[mid][1];
            let p = (r.reactions.iter())
                .find(|q| q.node == n as u32 + 1 && q.dof == "u")
                .map_or(0.0, |q| q.value)
                .abs();
            for x in &r.nodes {
                assert!(
                    x[1].abs() <= C + 1e-9,
                    "n {n}: a node beyond a wall: {}",
                    x[1]
                );
            }
            if first.is_none() && !r.obstacle_contacts.is_empty() {
                first = Some(r);
            }
            // The contacts mirror about midspan (node k and node n + 2 - k), and below the
            // thrust of the line contact only the midspan node touches.
            let mut nodes: Vec<u32> = r.obstacle_contacts.iter().map(|c| c.node).collect();
            let mut mirrored: Vec<u32> = nodes.iter().map(|&k| n as u32 + 2 - k).collect();
            nodes.sort_unstable();
            mirrored.sort_unstable();
            assert_eq!(
                nodes, mirrored,
                "n {n}, increment {}: not symmetric",
                r.increment
            );
            if p < p2 {
                assert!(
                    nodes.len() <= 1,
                    "n {n}: {nodes:?} touch at thrust {p} below {p2}"
                );
            }
            if first.is_none() {
                let reference = thrust(delta);
                error = error.max((p - reference).abs() / reference);
            }
        }
        let first = first.expect("the column touches a wall");
        let contacts: Vec<(u32, &str)> = (first.obstacle_contacts.iter())
            .map(|c| (c.node, c.obstacle.as_str()))
            .collect();
        assert_eq!(
            contacts,
            vec![(mid as u32 + 1, "upper wall")],
            "n {n}: first contact"
        );
        let before = &records[first.increment - 2];
        assert!(
            before.nodes[mid][1] < C,
            "n {n}: the increment before reached the wall"
        );
        assert!(first.events.iter().any(|e| matches!(e, Event::Obstacle(_))));
        eprintln!(
            "n {n}: thrust against the elastica {error:.2e}; first contact in increment {}",
            first.increment
        );
        worst.push(error);
    }
    assert!(
        worst[1] < worst[0] / 3.5 && worst[2] < worst[1] / 3.5,
        "not h^2: {worst:?}"
    );
    assert!(worst[2] < 1e-3, "{worst:?}");
}

/// The thrust at which the midspan's point contact turns into a line contact: the moment at
/// the contact point vanishes, so each half is an elastica between two inflection points (its
/// pinned end and the contact point) whose force runs along the chord between them, at
/// gamma = atan(2 c / L) to the axis. Its tangent at the contact point is the kink's beta0, one
/// extreme of its angle to the force; the other extreme is at the pinned end, so the half is
/// half a wave of amplitude alpha = gamma - beta0: L / 2 = 2 K(k) / lambda with
/// k = sin(alpha / 2) and F = lambda^2 EI, of which the thrust is F cos gamma.
fn line_contact_thrust() -> f64 {
    let gamma = (2.0 * C).atan();
    let alpha = gamma - (2.0 * E0).atan();
    let (mut a, mut b) = (1.0f64, (1.0 - (alpha / 2.0).sin().powi(2)).sqrt());
    for _ in 0..40 {
        (a, b) = (0.5 * (a + b), (a * b).sqrt());
    }
    let k = std::f64::consts::PI / (2.0 * a);
    let lambda = 2.0 * k / 0.5;
    lambda * lambda * gamma.cos()
}
