//! A campaign of random obstacle scenes: a cantilever of either formulation driven down onto a
//! floor (a line, tilted or not), a drum (a circle) or the lower half of a ring (an arc), from a
//! gap of zero (resting) to large, by a load or a prescribed tip displacement. Every accepted
//! increment is checked here on the record alone: no node inside its obstacle beyond the
//! tolerance (with this file's own geometry), every reported contact pressing and closed to the
//! tolerance, and the strip in equilibrium under its reactions, its loads and the obstacle's
//! pushes. A run may stop, but only with a typed error.

use crate::common;

use common::Rng;
use tsm_contact::scene::parse;
use tsm_contact::solver::{IncrementRecord, Silent};

/// Uniform in [a, b).
fn uniform(rng: &mut Rng, a: f64, b: f64) -> f64 {
    a + (b - a) * 0.5 * (rng.next() + 1.0)
}

/// The obstacle of a scene, for this file's own depth.
enum Solid {
    /// Free above the line through `p` with direction `t` (unit).
    Floor { p: [f64; 2], t: [f64; 2] },
    /// A disk.
    Drum { c: [f64; 2], r: f64 },
    /// The lower half of a ring (a hollow arc from 180 to 360 degrees): free inside.
    Saddle { c: [f64; 2], r: f64 },
}

impl Solid {
    /// How far inside point `x` lies (<= 0: free).
    fn depth(&self, x: [f64; 2]) -> f64 {
        match *self {
            Solid::Floor { p, t } => -(t[0] * (x[1] - p[1]) - t[1] * (x[0] - p[0])),
            Solid::Drum { c, r } => r - (x[0] - c[0]).hypot(x[1] - c[1]),
            Solid::Saddle { c, r } if x[1] <= c[1] => (x[0] - c[0]).hypot(x[1] - c[1]) - r,
            Solid::Saddle { .. } => 0.0,
        }
    }
}

/// A random scene: its text, obstacle and tip node id.
fn scene(rng: &mut Rng) -> (String, Solid, usize) {
    let n = [8, 16, 32][((rng.next() + 1.0) * 1.5) as usize % 3];
    let formulation = if rng.next() > 0.0 {
        "Timoshenko"
    } else {
        "BernoulliEuler"
    };
    let gap = match ((rng.next() + 1.0) * 2.0) as usize {
        0 => 0.0,
        1 => 1e-6,
        _ => uniform(rng, 1e-3, 0.1),
    };
    let (shape, solid) = match ((rng.next() + 1.0) * 1.5) as usize {
        0 => {
            // Rising towards the tip, where it lies `gap` below the strip.
            let a: f64 = uniform(rng, 0.0, 0.2);
            let p = [1.0, -gap];
            let t = [a.cos(), a.sin()];
            let q = [p[0] + t[0], p[1] + t[1]];
            (
                format!(
                    "Line(from: ({:e}, {:e}), to: ({:e}, {:e}))",
                    p[0], p[1], q[0], q[1]
                ),
                Solid::Floor { p, t },
            )
        }
        1 => {
            let r = uniform(rng, 0.1, 2.0);
            let c = [uniform(rng, 0.3, 1.0), -gap - r];
            (
                format!("Circle(centre: ({:e}, {:e}), radius: {r:e})", c[0], c[1]),
                Solid::Drum { c, r },
            )
        }
        _ => {
            // The strip starts inside the ring, above its lower half: the gap at x = 0.5 is
            // large enough for both ends to lie inside too.
            let r = uniform(rng, 1.0, 2.0);
            let g = uniform(rng, 0.15, 0.3);
            let c = [0.5, r - g];
            (
                format!(
                    "Arc(centre: ({:e}, {:e}), radius: {r:e}, from_deg: 180.0, to_deg: 360.0, hollow: true)",
                    c[0], c[1]
                ),
                Solid::Saddle { c, r },
            )
        }
    };
    let drive = if rng.next() > 0.0 {
        format!(
            "loads: [(node: {}, fy: {:e})],",
            n + 1,
            -uniform(rng, 1.0, 40.0)
        )
    } else {
        format!(
            "prescribed: [(node: {}, dof: V, per_step: {:e})],",
            n + 1,
            -uniform(rng, 0.005, 0.05)
        )
    };
    let text = format!(
        r#"(
    name: "campaign",
    formulation: {formulation},
    sections: [(name: "s", E: 2.0e11, A: 2.0e-4, I: 1.6667e-9)],
    bodies: [(name: "strip", section: "s", path: [(0.0, 0.0), (1.0, 0.0)], elements: {n}, first_node: 1)],
    supports: [(node: 1, u: true, v: true, phi: true)],
    {drive}
    obstacles: [(name: "obstacle", shape: {shape}, bodies: ["strip"])],
    control: (steps: 8),
)"#
    );
    (text, solid, n)
}

/// The record's checks (see the file's comment).
fn check(r: &IncrementRecord, solid: &Solid, tol: f64, load: [f64; 2], text: &str) {
    for (k, x) in r.nodes.iter().enumerate() {
        let depth = solid.depth([x[0], x[1]]);
        assert!(
            depth <= tol + 1e-12,
            "node {} inside by {depth:e}\n{text}",
            k + 1
        );
    }
    let mut push = [0.0; 2];
    for c in &r.obstacle_contacts {
        assert!(
            c.force >= 0.0,
            "node {} pulled: {}\n{text}",
            c.node,
            c.force
        );
        assert!(
            c.gap.abs() <= tol,
            "node {} gap {:e}\n{text}",
            c.node,
            c.gap
        );
        push[0] += c.force * c.normal[0];
        push[1] += c.force * c.normal[1];
    }
    let mut held = [0.0; 2];
    for q in &r.reactions {
        match q.dof.as_str() {
            "u" => held[0] += q.value,
            "v" => held[1] += q.value,
            _ => {}
        }
    }
    let slack = 10.0 * r.reference * r.relative_residual.max(1e-8);
    for k in 0..2 {
        let sum = held[k] + push[k] + r.load_factor * load[k];
        assert!(
            sum.abs() <= slack,
            "force balance {k}: {sum:e} (slack {slack:e})\n{text}"
        );
    }
}

#[test]
fn random_obstacle_scenes_keep_every_node_out_and_every_record_in_balance() {
    let mut rng = Rng(0x5eed_0b57_ac1e);
    let (mut finished, mut stopped, mut touched) = (0, 0, 0);
    for _ in 0..40 {
        let (text, solid, _) = scene(&mut rng);
        let parsed = parse(&text, "campaign.ron").expect("a valid scene");
        let load = (parsed.model.loads.first()).map_or([0.0; 2], |l| [l.force[0], l.force[1]]);
        let mut solver = parsed.solver().expect("a stable scene");
        let tol = solver.structure().obstacle_tolerance();
        let mut failed = false;
        let mut all = Vec::new();
        for _ in 0..8 {
            match solver.step(&mut Silent) {
                Ok(records) => {
                    for r in &records {
                        check(r, &solid, tol, load, &text);
                        touched += usize::from(!r.obstacle_contacts.is_empty());
                    }
                    all.extend(records);
                }
                Err(e) => {
                    eprintln!("stopped: {e}");
                    failed = true;
                    break;
                }
            }
        }
        common::assert_audited(&parsed, &all);
        if failed {
            stopped += 1;
        } else {
            finished += 1;
        }
    }
    eprintln!(
        "{finished} runs finished, {stopped} stopped on an error; {touched} records in contact"
    );
    assert!(finished >= 30, "{finished} of 40 finished");
    assert!(touched > 0);
}
