//! The contact campaign: random contact scenes (see `generate.rs`) solved step by step; each
//! run's history goes through JSON and is audited by the oracle (`tsm_contact::audit`), which
//! shares no code with the solver.
//! A run either completes every step or stops with a typed error; the classes are counted.
//! Any panic and any accepted increment out of equilibrium or through a beam fails the test,
//! naming the seed to replay.
//!
//! `cargo test --release --test fuzz_contact` runs 400 scenes; the full campaign is
//! `FUZZ_SCENES=100000 cargo test --release --test fuzz_contact -- --nocapture`
//! (`FUZZ_FIRST_SEED` moves the seeds).

#[path = "../common/mod.rs"]
mod common;
mod generate;

use std::collections::BTreeMap;
use std::panic::{catch_unwind, AssertUnwindSafe};

use tsm_contact::audit::audit_history;
use tsm_contact::history::History;
use tsm_contact::scene::parse;
use tsm_contact::solver::IncrementStatus;

/// How one scene's run ended, and what its accepted increments held.
struct Outcome {
    class: String,
    increments: usize,
    in_contact: usize,
    roundoff: usize,
}

/// Solve the scene of `seed`: its description, its history read back from JSON (none if
/// validation refuses it) and how the run ended.
fn solve(seed: u64) -> Result<(generate::Spec, Option<History>, String), String> {
    let spec = generate::scene(seed);
    let scene = match parse(&spec.text, "generated.ron") {
        Ok(s) => s,
        // A scene that cannot start is refused by validation with a located error: counted by
        // its first words.
        Err(e) => {
            let text = e.to_string();
            let words: Vec<&str> = text.split_whitespace().skip(1).take(4).collect();
            let class = format!("refused ({} ...)", words.join(" "));
            return Ok((spec, None, class));
        }
    };
    let mut history = History::of_model(
        spec.family,
        &scene.model,
        Some(scene.model.formulation),
        Some(scene.params),
    );
    let mut class = "completes every step".to_string();
    let mut solver = scene.solver().map_err(|e| format!("seed {seed}: {e}"))?;
    for _ in 0..scene.steps {
        if let Err(e) = solver.step(&mut history) {
            let debug = format!("{e:?}");
            let name: String = debug.chars().take_while(|c| c.is_alphanumeric()).collect();
            class = format!("stops with {name}");
            if std::env::var("FUZZ_VERBOSE").is_ok() {
                println!("seed {seed} ({}): {e}", spec.family);
            }
            break;
        }
    }
    // The check reads the history as a file holds it.
    let json = serde_json::to_string(&history).expect("a history serialises");
    let read: History = serde_json::from_str(&json).expect("a history reads back");
    Ok((spec, Some(read), class))
}

/// How one scene's run ended: its outcome, or the violation that fails the test.
fn run(seed: u64) -> Result<Outcome, String> {
    let (spec, history, class) = solve(seed)?;
    let class = format!("{}: {class}", spec.family);
    let Some(history) = history else {
        return Ok(Outcome {
            class,
            increments: 0,
            in_contact: 0,
            roundoff: 0,
        });
    };
    let found = audit_history(&history, None).map_err(|e| format!("seed {seed}: {e}"))?;
    if let Some(why) = found.first() {
        return Err(format!("seed {seed} ({}): {why}", spec.family));
    }
    let incs = &history.increments;
    Ok(Outcome {
        class,
        increments: incs.len(),
        in_contact: incs.iter().filter(|r| !r.contacts.is_empty()).count(),
        roundoff: (incs.iter())
            .filter(|r| matches!(r.status, IncrementStatus::RoundOff { .. }))
            .count(),
    })
}

/// Tallies of a campaign: scenes per class, and accepted increments (all, with a contact
/// active, accepted at round-off).
#[derive(Default)]
struct Tally {
    classes: BTreeMap<String, usize>,
    increments: usize,
    in_contact: usize,
    roundoff: usize,
    failures: Vec<String>,
}

/// Run `count` scenes from seed `first` on every core.
fn campaign(first: u64, count: u64) -> Tally {
    let threads = std::thread::available_parallelism().map_or(2, |n| n.get()) as u64;
    let tally = std::sync::Mutex::new(Tally::default());
    std::thread::scope(|s| {
        for t in 0..threads {
            let tally = &tally;
            s.spawn(move || {
                let mut seed = first + t;
                while seed < first + count {
                    let outcome = catch_unwind(AssertUnwindSafe(|| run(seed)))
                        .unwrap_or_else(|_| Err(format!("seed {seed}: panic")));
                    let mut tl = tally.lock().unwrap();
                    match outcome {
                        Ok(o) => {
                            *tl.classes.entry(o.class).or_insert(0) += 1;
                            tl.increments += o.increments;
                            tl.in_contact += o.in_contact;
                            tl.roundoff += o.roundoff;
                        }
                        Err(f) => tl.failures.push(f),
                    }
                    seed += threads;
                }
            });
        }
    });
    tally.into_inner().unwrap()
}

#[test]
fn random_contact_scenes_end_in_equilibrium_or_a_typed_error() {
    let var = |name: &str, default: u64| {
        (std::env::var(name).ok())
            .and_then(|v| v.parse().ok())
            .unwrap_or(default)
    };
    let (count, first) = (var("FUZZ_SCENES", 400), var("FUZZ_FIRST_SEED", 1));
    let t = campaign(first, count);
    println!("{count} scenes from seed {first}:");
    for (c, n) in &t.classes {
        println!("{n:>8}  {c}");
    }
    println!(
        "{} accepted increments checked: {} with a contact active, {} accepted at round-off",
        t.increments, t.in_contact, t.roundoff
    );
    for f in t.failures.iter().take(20) {
        println!("FAIL {f}");
    }
    assert!(
        t.failures.is_empty(),
        "{} of {count} scenes fail: {}",
        t.failures.len(),
        t.failures[0]
    );
    // The campaign exercises contact: most increments have one active.
    assert!(
        4 * t.in_contact > t.increments,
        "too few increments in contact"
    );
}

/// The first generated pin-on-a-beam run with the pin starting clear of the beam and then
/// touching it, and the index of its first increment in contact.
fn pin_run_in_contact() -> (generate::Spec, History, usize) {
    for seed in 1.. {
        let (spec, history, _) = solve(seed).unwrap();
        let clear = spec.gap > 1e-3;
        if let (Some(h), "pin on a beam", true) = (history, spec.family, clear) {
            if let Some(k) = h.increments.iter().position(|r| !r.contacts.is_empty()) {
                return (spec, h, k);
            }
        }
    }
    unreachable!()
}

/// The audit has teeth: a reaction 1% off is out of equilibrium, and a pin moved through the
/// element it touches (its contact dropped) went through that element.
#[test]
fn the_audit_catches_a_wrong_force_and_a_pin_through_a_beam() {
    let (spec, history, k) = pin_run_in_contact();
    let audit = |h: &History| audit_history(h, None).expect("a history with its topology");
    assert!(audit(&history).is_empty(), "{:?}", audit(&history));

    let mut off = history.clone();
    let r = off.increments[k].reactions.iter_mut().last().unwrap();
    r.value *= 1.01;
    let found = audit(&off);
    assert!(
        found.iter().any(
            |f| f.increment == off.increments[k].increment && f.what.contains("out of balance")
        ),
        "a reaction 1% off: {found:?}"
    );

    let mut through = history.clone();
    through.increments.truncate(k + 1);
    let rec = &mut through.increments[k];
    let contact = rec.contacts[0].clone();
    rec.contacts.retain(|c| c.node != contact.node);
    let (_, i, j) = spec.elements[contact.element];
    let at = |id: u32| history.node_ids.iter().position(|&n| n == id).unwrap();
    let (pi, pj, c) = (rec.nodes[at(i)], rec.nodes[at(j)], at(contact.node));
    let (dx, dy) = (pj[0] - pi[0], pj[1] - pi[1]);
    let l = dx.hypot(dy);
    let off = |p: [f64; 2]| ((p[1] - pi[1]) * dx - (p[0] - pi[0]) * dy) / l;
    let came_from = match k {
        0 => spec.coords[&contact.node],
        _ => [
            history.increments[k - 1].nodes[c][0],
            history.increments[k - 1].nodes[c][1],
        ],
    };
    // Moved to half an element length on the other side of the chord than it came from.
    let dist = off([rec.nodes[c][0], rec.nodes[c][1]]);
    let shift = -(dist + 0.5 * l * off(came_from).signum()) / l;
    rec.nodes[c][0] -= shift * dy;
    rec.nodes[c][1] += shift * dx;
    let found = audit(&through);
    assert!(
        found
            .iter()
            .any(|f| f.node == Some(contact.node) && f.what.contains("went through")),
        "a pin through the beam: {found:?}"
    );
}

/// Prints the scene of `FUZZ_SEED`, to replay a failure with `tsm-contact solve`:
/// `FUZZ_SEED=N cargo test --release --test fuzz_contact -- --ignored print_the_scene --nocapture`.
#[test]
#[ignore]
fn print_the_scene() {
    let seed = (std::env::var("FUZZ_SEED").ok())
        .and_then(|v| v.parse().ok())
        .expect("FUZZ_SEED names the scene");
    println!("{}", generate::scene(seed).text);
}
