//! Two cantilevers that meet tip on node: a pin presses one onto the other, the upper tip rests
//! on the lower beam, and nodes of the lower beam rest on the upper tip's element. Every run is
//! audited by the oracle (`tsm_contact::audit`, which shares no code with the solver).

use super::acceptance::{run, two_cantilevers};
use tsm_contact::scene::parse;
use tsm_contact::solver::SolveError;

/// A case of `random_pins_on_two_cantilevers_never_pass_through` kept by itself (Timoshenko,
/// 6 and 33 elements, the pin at x = 0.389 on the upper beam, the lower beam 5 cm under it).
/// The upper tip rests on the lower beam from above, while lower nodes next to it rest on the
/// upper tip's element from beyond the line of that element. When such a node slides off the
/// tip, the bodies' directions would hand the tip a contact on the lower beam from below, the
/// side it never came from; and a lower node let go near the tip as tensile is still beside the
/// tip's element, not round its end. Each node keeps the side it came from: the oracle passes
/// every state (no node through a beam, every contact pressing from its node's side), and the
/// run accepts at least 40 increments before it stops, if it does, with a typed error.
#[test]
fn nodes_meeting_the_upper_tip_keep_the_sides_they_came_from() {
    let text = two_cantilevers("Timoshenko", 6, 33, 0.38910446609121935, 0.0, 0.05);
    let scene = parse(&text, "two").unwrap();
    let (records, err) = run(&scene, 8);
    if let Some(e) = &err {
        assert!(
            !matches!(e, SolveError::Stopped | SolveError::Invalid { .. }),
            "{e}"
        );
    }
    assert!(records.len() >= 40, "{} increments: {err:?}", records.len());
}
