//! Going on from a checkpoint: a run restored to an accepted increment solves the increments
//! after it exactly as the unbroken run did (every number of every record equal, bit for bit),
//! on a contact scene with activation, sliding and transfer (Example 3.2), on the same with
//! friction (its stick points restored with the contacts), and on an arc-length run past a
//! limit point (Lee's frame). The reference is the unbroken run itself.

use tsm_contact::scene::builtin::builtin;
use tsm_contact::solver::{IncrementRecord, Silent, Solver};

/// The record with its wall time left out (the one field that is not a result).
fn result(r: &IncrementRecord) -> String {
    let mut r = r.clone();
    r.seconds = 0.0;
    format!("{r:?}")
}

/// Run `steps` steps of built-in scene `name`, keeping a checkpoint of every increment.
fn run(name: &str, steps: usize) -> (Solver, Vec<IncrementRecord>) {
    let mut solver = builtin(name).unwrap().unwrap().solver().unwrap();
    solver.keep_checkpoints(true);
    let mut out = Vec::new();
    for _ in 0..steps {
        out.extend(solver.step(&mut Silent).expect("converges"));
    }
    (solver, out)
}

/// Restore increment `k`'s checkpoint in `solver` and solve up to increment `last` again.
fn again(solver: &mut Solver, k: usize, last: usize) -> Vec<IncrementRecord> {
    let kept = solver.take_checkpoints();
    let at = kept
        .iter()
        .find(|c| c.increment() == k)
        .expect("a checkpoint")
        .clone();
    solver.restore(&at);
    assert_eq!(solver.increment(), k);
    let mut out = Vec::new();
    while solver.increment() < last {
        out.extend(solver.step(&mut Silent).expect("converges"));
    }
    out
}

#[test]
fn example_3_2_goes_on_from_increment_20_exactly_as_before() {
    let (mut solver, first) = run("example_3_2", 40);
    let last = first.last().unwrap().increment;
    let changes: usize = first[20..].iter().map(|r| r.events.len()).sum();
    assert!(changes > 0, "the increments after 20 change the contacts");
    let second = again(&mut solver, 20, last);
    assert_eq!(second.len(), first.len() - 20);
    for (a, b) in first[20..].iter().zip(&second) {
        assert_eq!(result(a), result(b), "increment {}", a.increment);
    }
}

#[test]
fn example_3_2_with_friction_goes_on_from_increment_20_exactly_as_before() {
    let (mut solver, first) = run("example_3_2_friction", 40);
    let last = first.last().unwrap().increment;
    let sticks = |r: &IncrementRecord| r.contacts.iter().filter_map(|c| c.stick).count();
    assert!(
        first[20..].iter().all(|r| sticks(r) > 0),
        "stick points carried on"
    );
    let second = again(&mut solver, 20, last);
    assert_eq!(second.len(), first.len() - 20);
    for (a, b) in first[20..].iter().zip(&second) {
        assert_eq!(result(a), result(b), "increment {}", a.increment);
    }
}

#[test]
fn an_arc_length_run_goes_on_from_a_checkpoint_exactly_as_before() {
    let (mut solver, first) = run("lee_frame", 30);
    let last = first.last().unwrap().increment;
    let second = again(&mut solver, 10, last);
    for (a, b) in first[10..].iter().zip(&second) {
        assert_eq!(result(a), result(b), "increment {}", a.increment);
    }
}
