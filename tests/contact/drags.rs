//! Drags as the app makes them: the worker marched to targets that jump by uneven amounts
//! (frames of a drag handle), down past the scene's own path and back up past the start. Every
//! record the worker sends is audited by the oracle (`tsm_contact::audit`), which shares no
//! code with the solver: no node goes through a body, every state is in equilibrium.

use crate::common;

use std::time::{Duration, Instant};

use tsm_contact::scene::builtin::builtin;
use tsm_contact::solver::{IncrementRecord, Silent};
use tsm_contact::worker::{Command, Message, Worker};

/// The frames of a drag, in scene steps: down to `depth` steps in uneven jumps of 0.1 to 1.9
/// steps (a hand on the mouse, frame by frame), then back up to `back` steps (negative: past
/// the start). `seed` picks the jumps.
fn frames(seed: u64, depth: f64, back: f64) -> Vec<f64> {
    let mut x: u64 = 0x9e37_79b9_7f4a_7c15 ^ seed.wrapping_mul(0x2545_f491_4f6c_dd1d);
    let mut jump = move || {
        x ^= x << 13;
        x ^= x >> 7;
        x ^= x << 17;
        0.1 + 1.8 * ((x >> 11) as f64 / (1u64 << 53) as f64)
    };
    let mut out = Vec::new();
    let mut s = 0.0;
    while s < depth {
        s = (s + jump()).min(depth);
        out.push(s);
    }
    while s > back {
        s = (s - jump()).max(back);
        out.push(s);
    }
    out
}

/// Drag built-in scene `name`'s prescribed dofs together through `frames` (in scene steps)
/// with the worker, one frame at a time; audit everything it accepted. Returns the records
/// and the errors.
fn drag(name: &str, frames: &[f64]) -> (Vec<IncrementRecord>, Vec<String>) {
    let (scene, w) = loaded(name);
    let (mut records, mut errors) = (Vec::new(), Vec::new());
    for &f in frames {
        for (index, p) in scene.model.prescribed.iter().enumerate() {
            w.send(Command::SetTarget {
                index,
                value: f * p.per_step,
            });
        }
        let (r, e) = common::until_idle(&w, Duration::from_secs(120));
        records.extend(r);
        errors.extend(e);
    }
    common::assert_audited(&scene, &records);
    (records, errors)
}

/// A worker with built-in scene `name` loaded, and the scene.
fn loaded(name: &str) -> (tsm_contact::scene::Scene, Worker) {
    let scene = builtin(name).unwrap().unwrap();
    let w = Worker::spawn(None);
    w.send(Command::LoadScene(Box::new(scene.clone())));
    let t0 = Instant::now();
    let mut loaded = false;
    while t0.elapsed() < Duration::from_secs(60) {
        match w.recv_timeout(Duration::from_millis(50)) {
            Some(Message::Loaded(_)) => loaded = true,
            Some(Message::Error(e)) => panic!("{name}: {e}"),
            Some(Message::Idle) if loaded => break,
            _ => {}
        }
    }
    assert!(loaded, "{name} did not load");
    (scene, w)
}

/// `drag` with the frames of eight seeds; returns every record, and the errors of the drags
/// that stopped (a drag that stops goes on from the last accepted state at the next frame).
fn drag_seeds(name: &str, depth: f64, back: f64) -> (Vec<IncrementRecord>, Vec<String>) {
    let (mut records, mut errors) = (Vec::new(), Vec::new());
    for seed in 0..8 {
        let (r, e) = drag(name, &frames(seed, depth, back));
        records.extend(r);
        errors.extend(e.into_iter().map(|e| format!("seed {seed}: {e}")));
    }
    eprintln!(
        "{name}: {} records, {} stops: {errors:?}",
        records.len(),
        errors.len()
    );
    (records, errors)
}

/// At most `most` of the drags stopped, each where Newton found no equilibrium after every
/// cut-back (a contact point crossing a mesh node where the chords meet in a valley seen from
/// the node, `docs/limits.md`), never on a crossing; a stopped drag goes on from its last
/// accepted state at the next frame.
fn few_stops(errors: &[String], most: usize) {
    assert!(errors.len() <= most, "{} stops: {errors:?}", errors.len());
    assert!(
        errors.iter().all(|e| e.contains("no convergence")),
        "{errors:?}"
    );
}

/// Example 3.2 dragged down to 0.33 m and back up past the start: the pin stays on A's upper
/// side until it leaves round A's free end, and nothing is found.
#[test]
fn example_3_2_dragged_down_and_back_up() {
    let (records, errors) = drag_seeds("example_3_2", 33.0, -3.0);
    few_stops(&errors, 2);
    // Until 0.5 m down the pin rests on A or is clear above it: it is never on B or C while A
    // is straight above it.
    let pin_on_a_or_above = records.iter().all(|r| {
        r.contacts
            .iter()
            .filter(|c| c.node == 34)
            .all(|c| c.body == "A")
    });
    assert!(pin_on_a_or_above, "the pin rested on B or C within 0.33 m");
}

/// Example 3.2 dragged all the way down (past B and C) and back up past the start.
#[test]
fn example_3_2_dragged_to_the_end_and_back() {
    let (_, errors) = drag_seeds("example_3_2", 80.0, -3.0);
    few_stops(&errors, 2);
}

/// Example 3.2 with friction, dragged down and back up.
#[test]
fn example_3_2_friction_dragged_down_and_back_up() {
    let (_, errors) = drag_seeds("example_3_2_friction", 40.0, -3.0);
    few_stops(&errors, 2);
}

/// Example 3.1 dragged down and back up.
#[test]
fn example_3_1_dragged_down_and_back_up() {
    let (_, errors) = drag_seeds("example_3_1", 18.0, -2.0);
    few_stops(&errors, 0);
}

/// The roller dragged along the strip and back.
#[test]
fn roller_dragged_along_and_back() {
    let (_, errors) = drag_seeds("roller", 48.0, 0.0);
    few_stops(&errors, 0);
}

/// A drag kept as the scene's path: Example 3.2 run 10 scene steps, then dragged in uneven
/// frames down to 0.5 m and back up past the start, as the app does. The run becomes the
/// scene's stages (`kept_path`), is written as RON and read back; solved headless to the end of
/// its path, that scene lands on every state of the drag, bit for bit, increment by increment
/// (its cut-backs included), and the kept stage lists one value per step of the drag.
#[test]
fn a_drag_kept_as_a_path_replays_to_the_same_states() {
    use tsm_contact::scene::kept::{kept_path, KEPT_STAGE};
    use tsm_contact::scene::{parse, write::scene_text};
    let (scene, w) = loaded("example_3_2");
    w.send(Command::RunSteps(10));
    let (mut records, errors) = common::until_idle(&w, Duration::from_secs(60));
    let per_step = scene.model.prescribed[0].per_step;
    for f in frames(7, 50.0, -3.0) {
        w.send(Command::SetTarget {
            index: 0,
            value: f * per_step,
        });
        let (r, e) = common::until_idle(&w, Duration::from_secs(120));
        records.extend(r);
        assert!(e.is_empty() && errors.is_empty(), "{e:?} {errors:?}");
    }
    let kept = kept_path(&scene.file, &scene.model, &records).unwrap();
    assert_eq!(kept.stages.len(), 1);
    assert_eq!(kept.stages[0].name.as_deref(), Some(KEPT_STAGE));
    let text = scene_text(&kept).unwrap();
    let again = parse(&text, "kept.ron").unwrap();
    let steps = records.iter().filter(|r| !r.partial).count();
    assert_eq!(again.steps, steps);
    let mut solver = again.solver().unwrap();
    let mut replay = Vec::new();
    for _ in 0..again.steps {
        replay.extend(solver.step(&mut Silent).unwrap());
    }
    assert_eq!(replay.len(), records.len(), "the same increments");
    for (a, b) in records.iter().zip(&replay) {
        assert_eq!(a.prescribed, b.prescribed, "increment {}", a.increment);
        assert_eq!(a.nodes, b.nodes, "increment {}", a.increment);
        assert_eq!(a.reactions, b.reactions, "increment {}", a.increment);
    }
    common::assert_audited(&again, &replay);
    eprintln!(
        "kept drive: {steps} steps, {} increments replayed bit for bit",
        replay.len()
    );
}
