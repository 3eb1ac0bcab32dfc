//! Snap-through: a pin driven down onto a cantilever whose tip presses on a second cantilever
//! passes a limit point of its drive (the pin's force falls, and no step however short finds
//! an equilibrium past it). The drive is held and the structure moves along a damped path to
//! the next stable state: the run completes, the states on the way are marked snapping and
//! the rest converged, the oracle audits every state (equilibrium where claimed, a snapping state
//! within the residual it records, and no pass-through) and finds a state that says less, and the strain energy, worked out
//! here from the recorded element forces alone, ends well below where the snap began and
//! never rises above it (the viscous force dissipates, it never feeds). Without
//! the snap the same run stops at the limit point.

use crate::common;

use tsm_contact::history::{History, Topology};
use tsm_contact::scene::{parse, Scene};
use tsm_contact::solver::{Event, IncrementRecord, IncrementStatus, SolveError};

/// The campaign's "a pin pressing two cantilevers" at 32 Bernoulli-Euler elements each, the
/// pin driven 0.019914 m a step for 25 steps.
fn scene() -> Scene {
    let text = r#"(
    name: "a pin pressing two cantilevers",
    formulation: BernoulliEuler,
    sections: [(name: "s", E: 1.0, A: 1.0e6, I: 1.0, G: 0.4)],
    nodes: [(id: 100000, x: 0.6, y: 0.02, rotation: false)],
    bodies: [
        (name: "upper", section: "s", path: [(0.0, 0.0), (1.0, 0.0)], elements: 32, first_node: 1),
        (name: "lower", section: "s", path: [(1.2, -0.05), (0.2, -0.05)], elements: 32, first_node: 1001),
    ],
    supports: [(node: 1, u: true, v: true, phi: true), (node: 1001, u: true, v: true, phi: true),
               (node: 100000, u: true)],
    prescribed: [(node: 100000, dof: V, per_step: -0.019914)],
    contacts: [(nodes: [100000], bodies: ["upper", "lower"]),
               (node_bodies: ["upper"], bodies: ["lower"]),
               (node_bodies: ["lower"], bodies: ["upper"])],
    control: (steps: 25),
)"#;
    parse(text, "snap.ron").expect("a valid scene")
}

/// The run of `scene` with the snap on or off: its history (states and events), and the error
/// it stopped with, if it did.
fn run(scene: &Scene, snap: bool) -> (History, Option<SolveError>) {
    let mut scene = scene.clone();
    scene.params.snap = snap;
    let mut solver = scene.solver().expect("a solver");
    let mut history = History::default();
    for _ in 0..scene.steps {
        if let Err(e) = solver.step(&mut history) {
            return (history, Some(e));
        }
    }
    (history, None)
}

/// The strain energy of state `r` (J): axial, bending and shear, from each element's recorded
/// chord forces (N, Mi, Mj) over its length at rest, the bending moment linear along it from
/// -Mi to Mj.
fn strain_energy(topology: &Topology, r: &IncrementRecord) -> f64 {
    let at = |id: u32| {
        let n = topology.nodes.iter().find(|n| n.id == id).expect("a node");
        [n.x, n.y]
    };
    (topology.elements.iter().zip(&r.element_forces))
        .map(|(e, f)| {
            let (a, b) = (at(e.i), at(e.j));
            let l = (b[0] - a[0]).hypot(b[1] - a[1]);
            let [n, mi, mj] = *f;
            let shear = (mi + mj) / l;
            n * n * l / (2.0 * e.ea)
                + l / (6.0 * e.ei) * (mi * mi - mi * mj + mj * mj)
                + shear * shear * l / (2.0 * e.gae)
        })
        .sum()
}

fn snapping(r: &IncrementRecord) -> bool {
    matches!(r.status, IncrementStatus::Snapping { .. })
}

#[test]
fn a_pin_pressing_two_cantilevers_snaps_past_its_limit_point_to_a_state_of_less_energy() {
    let scene = scene();
    let (history, error) = run(&scene, true);
    assert!(error.is_none(), "the run completes: {error:?}");
    let records = &history.increments;
    common::assert_audited(&scene, records);

    // One snap: converged states, the snapping ones, converged states again.
    let first = records.iter().position(snapping).expect("a snap");
    let after = first
        + records[first..]
            .iter()
            .position(|r| !snapping(r))
            .expect("an end");
    assert!(records[after..].iter().all(|r| !snapping(r)), "one snap");
    assert!(after - first >= 10, "the snap goes in many short steps");
    let snaps: Vec<&Event> = (history.events.iter())
        .filter(|e| matches!(e, Event::Snaps { .. }))
        .collect();
    assert_eq!(snaps.len(), 1, "one snap is reported");
    assert_eq!(snaps[0].increment(), records[first].increment);
    for r in &records[first..after] {
        let IncrementStatus::Snapping { residual } = r.status else {
            unreachable!()
        };
        assert!(
            residual > scene.params.tolerance && residual == r.relative_residual,
            "increment {}: a snapping state is out of equilibrium by what it records",
            r.increment
        );
    }

    // The drive is held through the snap (the pin's last short step at its start aside).
    let held = records[first].prescribed[0];
    for r in &records[first..=after] {
        assert_eq!(r.prescribed[0], held, "increment {}", r.increment);
    }
    let before = &records[first - 1];
    assert!((held - before.prescribed[0]).abs() < 1e-4);

    // The energy falls by a good part of itself, and never rises above where the snap began.
    // (The energy from the recorded end forces takes each element's moment as linear: an
    // element that carries a contact inside it has a kink there, of energy of the order of
    // P^2 l^3 / EI, 1e-4 of the whole here, so that sum may creep up by that while the
    // structure creeps past the limit point.)
    let topology = Topology::of(&scene.model);
    let energy: Vec<f64> = (records[first - 1..=after].iter())
        .map(|r| strain_energy(&topology, r))
        .collect();
    for (k, e) in energy.iter().enumerate() {
        assert!(
            *e <= energy[0] * (1.0 + 1e-3),
            "increment {}: the energy rises from {} to {e}",
            records[first - 1 + k].increment,
            energy[0]
        );
    }
    let (start, end) = (energy[0], energy[energy.len() - 1]);
    println!(
        "snap: increments {} to {} ({} states), strain energy {start:.4} J to {end:.4} J",
        records[first].increment,
        records[after].increment,
        after - first,
    );
    assert!(
        end < 0.8 * start,
        "the snap releases energy: {start} J to {end} J"
    );
    // The pin's force fell towards the limit point: past its peak before the snap.
    let pin = |r: &IncrementRecord| {
        (r.reactions.iter())
            .find(|x| x.node == 100000 && x.dof == "v")
            .map_or(0.0, |x| x.value.abs())
    };
    let peak = records[..first].iter().map(pin).fold(0.0, f64::max);
    assert!(pin(before) < 0.95 * peak, "the force falls before the snap");

    // The oracle holds a snapping state to the residual it records: called converged, or
    // snapping by less than it is out of balance, it is found out.
    for status in [
        IncrementStatus::Converged,
        IncrementStatus::Snapping { residual: 1e-9 },
    ] {
        let mut told = records.clone();
        told[first + 3].status = status;
        told[first + 3].relative_residual = 1e-9;
        assert!(
            !common::findings(&scene, &told).is_empty(),
            "a snapping state told {status:?} goes unnoticed"
        );
    }

    // Without the snap the run stops at the limit point, with nothing marked snapping.
    let (plain, error) = run(&scene, false);
    assert!(
        matches!(error, Some(SolveError::NoConvergence { increment, .. }) if increment == records[first].increment),
        "without the snap: {error:?}"
    );
    assert!(plain.increments.iter().all(|r| !snapping(r)));
    assert_eq!(plain.increments.len(), first);
}
