//! The obstacle contacts a pass predicts for the whole set at once (`ContactSet::
//! predicted_changes`): a beam wrapping a drum, whose wrapped nodes touch with next to no
//! force, and a strip peeling off a table find their contacts in a pass or two, with every
//! state audited by the oracle (`tsm_contact::audit`).

use crate::common;

use tsm_contact::scene::builtin::builtin;
use tsm_contact::solver::{IncrementRecord, Silent};

/// The built-in scene `name` solved in its own steps, audited.
fn solved(name: &str) -> Vec<IncrementRecord> {
    let sc = builtin(name).unwrap().unwrap();
    let mut solver = sc.solver().unwrap();
    let mut out = Vec::new();
    for _ in 0..sc.steps {
        out.extend(solver.step(&mut Silent).expect("converges"));
    }
    common::assert_audited(&sc, &out);
    out
}

/// `cylinder_wrap` (a cantilever of 40 elements pushed onto a drum in 20 steps) takes at most
/// 6 Newton iterations in any increment, and `table_lift` (a strip of 200 elements lifted off
/// a table in 10 steps) at most 8: making and letting go of the contacts pass by pass, the
/// drum's wrapped nodes swing between sets and its increments take up to 30, the table's
/// first up to 40. No increment is cut back, and the wrap keeps its contacts at the end.
#[test]
fn a_drum_and_a_table_find_their_contacts_in_a_pass_or_two() {
    for (name, most) in [("cylinder_wrap", 6), ("table_lift", 8)] {
        let recs = solved(name);
        let its: Vec<usize> = recs.iter().map(|r| r.iterations).collect();
        assert!(its.iter().all(|&n| n <= most), "{name}: {its:?}");
        assert!(recs.iter().all(|r| r.cutbacks == 0), "{name}");
    }
    let last = solved("cylinder_wrap").pop().unwrap();
    assert!(
        last.obstacle_contacts.len() >= 2,
        "{:?}",
        last.obstacle_contacts
    );
}
