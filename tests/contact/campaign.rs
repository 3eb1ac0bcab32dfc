//! Drives of the robustness campaign (`tsm_contact::reports::robust`) at the places that are
//! hardest for the active set, run whole and audited by the oracle (`tsm_contact::audit`,
//! which shares no code with the solver): every accepted state in equilibrium, on the right
//! side of every beam, within the friction law.

use tsm_contact::audit::audit_history;
use tsm_contact::reports::robust::{cases, history, run, run_keeping, Case, Outcome};
use tsm_contact::solver::IncrementStatus;

/// Panics unless `outcome` accepted at least `least` increments and the oracle found nothing
/// in any of them.
fn audited_at_least(outcome: &Outcome, least: usize) {
    assert!(
        outcome.iterations.len() >= least,
        "{} accepted increments: {:?}",
        outcome.iterations.len(),
        outcome.stop
    );
    assert!(
        outcome.findings.is_empty(),
        "{}",
        outcome.findings.join("\n")
    );
}

/// The drive with seed `drive` of the campaign of `per_scene` drives per scene and seed `seed`.
fn drawn(per_scene: usize, seed: u64, drive: u64) -> Case {
    (cases(per_scene, seed).into_iter())
        .find(|c| c.seed == drive)
        .expect("the campaign draws this drive")
}

/// The campaign's drive with seed `seed` (of 24 per scene, campaign seed 1), run: it completes
/// and the oracle finds nothing in any accepted state.
fn completes_audited(seed: u64) {
    let case = drawn(24, 1, seed);
    let outcome = run(&case);
    assert_eq!(outcome.stop, None, "{case:?} stops");
    assert!(
        outcome.findings.is_empty(),
        "{:?}: {}",
        case.scene,
        outcome.findings.join("\n")
    );
    let done = (case.steps * if case.reverse { 2 } else { 1 }) as f64;
    assert!(
        outcome.iterations.len() as f64 >= done,
        "{} accepted increments for {done} steps",
        outcome.iterations.len()
    );
}

/// Example 3.2 with friction: A's tip comes to rest on B right at B's mesh node 13, so node 13
/// is found at A's tip as A's tip is at node 13. The tip's contact holds the two apart; a
/// contact of node 13 on A within the free-end margin of the tip would slide off it at each
/// pass and be found again.
#[test]
fn a_tip_resting_on_the_mesh_node_of_a_frictional_beam_under_it_completes() {
    completes_audited(0x8ff3_4784_799e_5cbc); // Bernoulli-Euler, mu 0.18, 0.53 of the step
    completes_audited(0xfa8c_fc36_711c_2db8); // Timoshenko, mu 0.16, down and back up
}

/// The campaign's two hard places of a pin pressing one cantilever onto another. With 8 and 8
/// elements and 0.1 m a step, the upper tip races along the lower beam and the pin's force
/// falls: a limit point of the drive, where the tangent tends to singular. Without the snap
/// (`control: (snap: false)`) the drive stops there, and the tangent's least eigenvalue (the
/// drive held) at the last accepted state is below a twentieth of the one after the first
/// step. With 128 and 128 elements and friction (mu 0.2), flat contact node over node, the
/// slips the drive turns back stick (an attempt after a failed one checks its predictor for them), and the
/// drive goes on to a limit point too: the eigenvalue falls below a twentieth as well. With
/// the snap both complete, through states marked snapping, and the oracle finds nothing in any
/// state.
#[test]
fn a_snap_under_the_drive_shows_in_the_tangent_and_both_hard_places_complete_through_a_snap() {
    let stop = |seed: u64| {
        let mut case = drawn(24, 1, seed);
        let text = case.text.take().expect("a family's scene");
        case.text = Some(text.replace("control: (steps: 24)", "control: (steps: 24, snap: false)"));
        let outcome = run(&case);
        assert_eq!(
            outcome.stop.as_ref().map(|s| s.0.as_str()),
            Some("NoConvergence"),
            "{case:?}"
        );
        outcome.stiffness.expect("eigenvalues of a small model")
    };
    let (first, last) = stop(0x08d1_2e02_76c8_4d10);
    assert!(first > 0.0 && last < first / 20.0, "{first} {last}");
    let (first, last) = stop(0x98c4_7599_f066_a9cf);
    assert!(first > 0.0 && last < first / 20.0, "{first} {last}");
    for seed in [0x08d1_2e02_76c8_4d10, 0x98c4_7599_f066_a9cf] {
        let case = drawn(24, 1, seed);
        let outcome = run_keeping(&case, true);
        assert_eq!(outcome.stop, None, "{case:?} stops");
        audited_at_least(&outcome, case.steps);
        assert!(
            (outcome.records.iter()).any(|r| matches!(r.status, IncrementStatus::Snapping { .. })),
            "{seed:#x}: no snap"
        );
    }
}

/// A drive that stops part way through its one step has accepted states of its own, and the
/// oracle reads them; the stop names the element that stops it. `rolled_past_a_turn`
/// (Timoshenko, 16 elements, one step of 46 times the scene's, then back) rolls the beam past
/// three turns on itself, about five elements to a turn, and snaps where no step of the drive
/// finds an equilibrium; every step of the snap bends an element further against its chord
/// than a snap lets one turn (0.5 rad), and the run stops there with the mesh named too coarse.
/// Every accepted state is audited, and the oracle finds nothing in them. The element the
/// error names is, by the end rotations against the chords worked out here from the last
/// accepted state's nodes alone, the most bent one, by the turn the error gives (to its two
/// decimals; the snap's refused step hardly moves), beyond the limit.
#[test]
fn a_snap_whose_every_step_bends_an_element_too_far_stops_naming_the_element() {
    let case = drawn(24, 1, 0x78dd_e6eb_fd29_f055);
    let outcome = run_keeping(&case, true);
    let (kind, text) = outcome.stop.clone().expect("the drive stops");
    assert_eq!(kind, "MeshTooCoarse", "{text}");
    audited_at_least(&outcome, 60);
    let number = |after: &str| -> f64 {
        let rest = &text[text.find(after).expect(after) + after.len()..];
        let word = rest.split_whitespace().next().expect("a number");
        word.parse().expect("a number")
    };
    let (element, turn) = (number("cantilever element "), number(" by "));
    let last = outcome.records.last().expect("accepted states");
    let wrap = |a: f64| {
        (a + std::f64::consts::PI).rem_euclid(std::f64::consts::TAU) - std::f64::consts::PI
    };
    // The cantilever lies along x at rest: node k (from 0) and k + 1 end element k + 1.
    let bends: Vec<f64> = (last.nodes.windows(2))
        .map(|w| {
            let chord = (w[1][1] - w[0][1]).atan2(w[1][0] - w[0][0]);
            wrap(w[0][2] - chord).abs().max(wrap(w[1][2] - chord).abs())
        })
        .collect();
    let most = (0..bends.len())
        .max_by(|&a, &b| bends[a].total_cmp(&bends[b]))
        .unwrap();
    assert_eq!(most + 1, element as usize, "{bends:?}");
    assert!(
        (bends[most] - turn).abs() <= 0.005 && turn > 0.5,
        "{} {turn}",
        bends[most]
    );
}

/// The oracle carries a node's side along a body while the node rests on it: in
/// `rolled_past_a_turn` (Bernoulli-Euler, 16 elements, one step of 39 times the scene's; drive
/// 0xbc09_2f90_cb87_de15 of the campaign of 96 drives per scene, seed 7), node 15 rides on the
/// coil's inner layer from element 2 to element 9, is let go, and lies on the left of the next
/// layer's elements 3 and 4, as it has since it came near them. The oracle reports no crossing
/// of node 15: its side was last measured over element 9, five elements from there.
#[test]
fn the_oracle_carries_a_resting_nodes_side_along_the_body() {
    let case = drawn(96, 7, 0xbc09_2f90_cb87_de15);
    let outcome = run(&case);
    assert!(
        outcome.iterations.len() >= 150,
        "{} accepted increments",
        outcome.iterations.len()
    );
    let node_15 = (outcome.findings.iter()).filter(|f| f.contains("node 15 "));
    assert_eq!(node_15.count(), 0, "{}", outcome.findings.join("\n"));
}

/// A coil holds its own nodes between two of its layers: in the drive above, node 16 lies
/// between the coil's layers at elements 5 and 10, closer to the second, and the first comes
/// down onto it. The node is found through the part it crossed, not only measured against the
/// part it lies closest to, and each part is judged by the node's side of that part. The drive
/// completes, and the oracle finds nothing in any accepted state.
#[test]
fn a_node_between_two_layers_of_a_coil_is_caught_by_either_layer() {
    let case = drawn(96, 7, 0xbc09_2f90_cb87_de15);
    let outcome = run(&case);
    assert_eq!(outcome.stop, None, "{case:?} stops");
    audited_at_least(&outcome, 1);
}

/// A lower node that slides off the upper tip hands the touch to the tip only from the side the
/// tip is on: in a drive of "a pin pressing two cantilevers" (Timoshenko, 64 and 64 elements,
/// friction 0.2, 40 steps of 0.62 times the family's; drive 0xde04_97a6_65c3_ef0a of the
/// campaign of 96 drives per scene, seed 3), the upper tip rests at the very end of a lower
/// element, on its right, when a lower node slides off the tip at an angle. The bodies'
/// directions would put the tip's new contact on the left, and the tip would go through the
/// lower beam. The oracle finds nothing in any accepted state, and the drive accepts at least
/// 70 increments.
#[test]
fn a_tip_handed_a_node_s_touch_keeps_the_side_it_is_on() {
    audited_at_least(&run(&drawn(96, 3, 0xde04_97a6_65c3_ef0a)), 70);
}

/// A pin pressing two cantilevers (Timoshenko, 32 elements each, 19 times the family's step,
/// down and back up): the pin stands at the upper cantilever's tip (li/l = 0.9988) when the
/// structure snaps, and the tip slides out from under it. A contact that slid off an end in
/// the attempt went round that end, so the snap goes on past it instead of finding the pin
/// "through the body before contact was detected" at every step.
#[test]
fn a_pin_whose_contact_slides_off_a_tip_during_a_snap_goes_round_it() {
    completes_audited(0x6a99_b4d8_f77d_d0fd);
}

/// A coil of three zero-thickness layers (`rolled_past_a_turn`, Timoshenko, its own 32
/// elements, one step of 35.9 times the scene's; drive 0x56e2_7ebb_62ed_df56 of the campaign
/// of 96 drives per scene, seed 11): node 6 comes to lie nearest the outer layer while it is
/// still over the middle one, which it was measured against. The part it was measured against
/// is judged too, by the side the node had there, so the node is caught where it would pass
/// 7e-6 m through the middle layer, and caught where it would leave a contact it rested on
/// through that contact's element. The drive completes, and the oracle finds nothing in any
/// accepted state.
#[test]
fn a_node_nearest_another_layer_of_a_coil_is_still_judged_against_the_one_it_lay_over() {
    let case = drawn(96, 11, 0x56e2_7ebb_62ed_df56);
    let outcome = run(&case);
    assert_eq!(outcome.stop, None, "{case:?} stops");
    audited_at_least(&outcome, 200);
}

/// A tip slipping along the coil under it as the end moment rolls the cantilever up
/// (`rolled_past_a_turn`, Timoshenko, 16 elements, mu 0.94, two steps of 7.7 times the
/// scene's, then back; drive 0xe377_9b99_f4a7_c151 of the campaign, seed 1): at the top of the
/// drive the moment unloads. Under the slip mode the tip would slide freely the wrong way,
/// pushed on by its own friction, and no step size converges; after a failed attempt, a slip its
/// predictor turns back sticks and the predictor is solved again. The tip sticks through the
/// first unloading increments, every state audited by the oracle.
#[test]
fn a_slipping_tip_sticks_when_the_drive_turns_back() {
    let case = drawn(24, 1, 0xe377_9b99_f4a7_c151);
    let outcome = run_keeping(&case, true);
    audited_at_least(&outcome, 35);
    let top = (outcome.records.iter())
        .map(|r| r.load_factor)
        .fold(f64::MIN, f64::max);
    let after: Vec<_> = (outcome.records.iter())
        .skip_while(|r| r.load_factor < top)
        .skip(1)
        .take(3)
        .collect();
    assert_eq!(
        after.len(),
        3,
        "three increments after the top of the drive"
    );
    for r in after {
        assert!(r.load_factor < top, "unloading");
        let tip = (r.contacts.iter())
            .find(|c| c.node == 17)
            .expect("the tip rests");
        assert!(
            matches!(tip.friction, tsm_contact::solver::Friction::Sticking),
            "increment {}: the tip {:?}",
            r.increment,
            tip.friction
        );
    }
}

/// A strip lying on a rough table whose weight a drive has almost taken away
/// (`table_lift`, Bernoulli-Euler, mu 0.50, 120 steps of 1.2e-3 times the scene's, then back;
/// drive 0x1715_6092_7c74_6c68 of the campaign, seed 1): the nodes press with 1e-5 N, and
/// the Coulomb limits, 3e-6 N, are below the round-off of a stick spring of full stiffness
/// (friction_penalty EA / l times a few units in the last place of the coordinates). The
/// spring of each contact is no stiffer than its limit resolves, so that stick and slip are
/// decided on the limit, not on round-off: the drive completes, every state audited.
#[test]
fn a_strip_that_barely_presses_on_a_rough_table_sticks_and_slips_on_its_limit() {
    completes_audited(0x1715_6092_7c74_6c68);
}

/// A cantilever rolled 1.19 turns and back (`rolled_past_a_turn`, Bernoulli-Euler, 16
/// elements, frictionless, 11 steps of 1.08 times the scene's; drive 0x1dd1_b5eb_4c3d_61f6 of
/// the campaign of 96 drives per scene, seed 11): past a turn, the tip's turn rests on the
/// first element, and as the coil opens it slides off the clamped end. The touch passes to
/// that end, which rests on the turn from then on, as between two bodies; let go instead, the
/// turn springs back through the elements under it and no step converges. The drive
/// completes, every state audited, with the clamped end (node 1) resting on the turn.
#[test]
fn a_coil_that_opens_off_its_clamped_end_hands_the_touch_to_that_end() {
    let case = drawn(96, 11, 0x1dd1_b5eb_4c3d_61f6);
    let outcome = run_keeping(&case, true);
    assert_eq!(outcome.stop, None, "{case:?} stops");
    audited_at_least(&outcome, 2 * case.steps);
    let rests = (outcome.records.iter()).any(|r| r.contacts.iter().any(|c| c.node == 1));
    assert!(rests, "the clamped end never rests on the turn");
}

/// A pin pressing two cantilevers (Bernoulli-Euler, 128 elements each, one step of 25.5 times
/// the family's; drive 0xb696_2bbf_3ca4_0bcc of the campaign of 96 drives per scene, seed 7):
/// the structure snaps from increment 48 and comes to rest where Newton reaches only the
/// round-off floor, never the tolerance. The snap ends there, at a state whose residual
/// without the viscous force is round-off; stepping on at rest, it would run out of steps. The
/// drive completes, every state audited, a snap ending on a `roundoff` state.
#[test]
fn a_snap_that_comes_to_rest_at_the_round_off_floor_ends_there() {
    let case = drawn(96, 7, 0xb696_2bbf_3ca4_0bcc);
    let outcome = run_keeping(&case, true);
    assert_eq!(outcome.stop, None, "{case:?} stops");
    audited_at_least(&outcome, case.steps);
    let ends_at_floor = outcome.records.windows(2).any(|w| {
        matches!(w[0].status, IncrementStatus::Snapping { .. })
            && matches!(w[1].status, IncrementStatus::RoundOff { .. })
    });
    assert!(ends_at_floor, "no snap ends at the round-off floor");
}

/// Two strips of a thickness stacked (`thick strips`, Timoshenko, 64 elements, two steps of
/// 29.4 times the family's; drive 0x4540_21b5_755d_453c of the campaign of 96 drives per
/// scene, seed 7): a node standing off the lower strip by the thickness is pressed to a point
/// past each of two elements towards the other at a convex mesh node. It rests on the one it
/// overshoots less, every pass the same, and the drive completes, every state audited; hopping
/// between the two at every converged pass, the increment is cut back as chattering.
#[test]
fn a_thick_node_over_a_convex_mesh_node_rests_on_one_element() {
    let case = drawn(96, 7, 0x4540_21b5_755d_453c);
    let outcome = run(&case);
    assert_eq!(outcome.stop, None, "{case:?} stops");
    audited_at_least(&outcome, 2 * case.steps);
}

/// A frictional coil unloading (`rolled_past_a_turn`, Timoshenko, 16 elements, mu 0.94, two
/// steps of 7.7 times the scene's, down and back; drive 0xe377_9b99_f4a7_c151 of the campaign
/// of 24 drives per scene, seed 1): as the end moment falls from 1.52, a turn stuck on the one
/// inside it lets go, and no quasi-static step follows it however short. The coil snaps as any
/// structure does, the load held: each snap's states are marked and out of equilibrium by what
/// they record, and each ends in a state in equilibrium. The drive completes, every state
/// audited, on the right side of its own turns.
#[test]
fn a_frictional_coil_that_lets_go_of_its_own_turn_snaps_through_and_completes() {
    let case = drawn(24, 1, 0xe377_9b99_f4a7_c151);
    let outcome = run_keeping(&case, true);
    assert_eq!(outcome.stop, None, "{case:?} stops");
    audited_at_least(&outcome, 2 * case.steps);
    let records = &outcome.records;
    let snapping = |r: &tsm_contact::solver::IncrementRecord| {
        matches!(r.status, IncrementStatus::Snapping { .. })
    };
    let starts: Vec<usize> = (1..records.len())
        .filter(|&k| snapping(&records[k]) && !snapping(&records[k - 1]))
        .collect();
    assert!(!starts.is_empty(), "the coil never snaps");
    for &first in &starts {
        let end = first + (records[first..].iter().position(|r| !snapping(r))).expect("an end");
        for r in &records[first..=end] {
            assert_eq!(
                r.load_factor, records[first].load_factor,
                "increment {}",
                r.increment
            );
            if let IncrementStatus::Snapping { residual } = r.status {
                assert!(residual > case_tolerance() && residual == r.relative_residual);
            }
        }
        let tolerance = case_tolerance();
        let in_equilibrium = match records[end].status {
            IncrementStatus::Converged => records[end].relative_residual <= tolerance,
            IncrementStatus::RoundOff { ratio } => ratio * tolerance <= 1e-5,
            IncrementStatus::Snapping { .. } => false,
        };
        assert!(
            in_equilibrium,
            "the snap from increment {} ends out of equilibrium: {:?}",
            records[first].increment, records[end].status
        );
    }
}

/// The Newton tolerance of the built-in scenes (`control.tolerance`'s default).
fn case_tolerance() -> f64 {
    tsm_contact::solver::SolverParams::default().tolerance
}

/// Two turns of a coil that lie on each other mesh node on mesh node: in `rolled_past_a_turn`
/// (Bernoulli-Euler, the scene's own mesh, friction 0.96, one step of 36.6 times the scene's,
/// then back; drive 0x9e37_79b7_7f4a_7c14 of the campaign, seed 1), node 30 rests on element
/// 11 within a millionth of its end node 12, and node 12 lies a millionth of element 30's
/// length from node 30, a few 1e-10 m across element 30's chord: the layers kink by a
/// hundredth of a radian there. A contact of node 12 as well pulls, and let go, node 12 is
/// found across again: the two touch vertex on vertex, one contact holds them apart, and the
/// drive completes with every state audited. Such states are found here from the records
/// alone (a contact within 1e-6 of an element's end, that end node in no contact); with that
/// contact taken out of the record, the oracle finds that end node through the layer, in
/// every one of them; so it does with the end node moved 1e-4 element lengths across the
/// other layer, the contact kept.
#[test]
fn two_layers_of_a_coil_that_meet_node_on_node_are_held_apart_by_one_contact() {
    let case = drawn(24, 1, 0x9e37_79b7_7f4a_7c14);
    let outcome = run_keeping(&case, true);
    assert_eq!(outcome.stop, None, "{case:?} stops");
    audited_at_least(&outcome, 2);
    let h = history(&case, &outcome);
    let topology = h.topology.clone().expect("a topology");
    // (record, contact) where the contact's node rests within 1e-6 of an end of its element
    // and that end node is in no contact.
    let mut met = Vec::new();
    for (k, r) in h.increments.iter().enumerate() {
        for (q, c) in r.contacts.iter().enumerate() {
            let e = &topology.elements[c.element];
            let end = match c.xi {
                x if x < 1e-6 => e.i,
                x if x > 1.0 - 1e-6 => e.j,
                _ => continue,
            };
            if r.contacts.iter().all(|o| o.node != end) {
                met.push((k, q, end));
            }
        }
    }
    assert!(met.len() >= 10, "{} states met vertex on vertex", met.len());
    let caught = met.iter().filter(|&&(k, q, end)| {
        let mut planted = h.clone();
        planted.increments.truncate(k + 1);
        planted.increments[k].contacts.remove(q);
        let found = audit_history(&planted, None).expect("audited");
        let at = h.increments[k].increment;
        found
            .iter()
            .any(|f| f.increment == at && f.node == Some(end))
    });
    assert_eq!(caught.count(), met.len());
    // The end node moved 1e-4 element lengths along the normal of the element the contact
    // rests on, the contact kept: one way it is clear, the other it is that far across the
    // other layer, beyond what meeting vertex on vertex allows.
    let slot = |id: u32| h.node_ids.iter().position(|&n| n == id).expect("a node");
    let deeper = met.iter().filter(|&&(k, q, end)| {
        let r = &h.increments[k];
        let e = &topology.elements[r.contacts[q].element];
        let (a, b) = (r.nodes[slot(e.i)], r.nodes[slot(e.j)]);
        let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
        let normal = [-dy * 1e-4, dx * 1e-4];
        [1.0, -1.0].iter().any(|&sign| {
            let mut planted = h.clone();
            planted.increments.truncate(k + 1);
            let node = &mut planted.increments[k].nodes[slot(end)];
            node[0] += sign * normal[0];
            node[1] += sign * normal[1];
            let found = audit_history(&planted, None).expect("audited");
            (found.iter()).any(|f| f.increment == r.increment && f.node == Some(end))
        })
    });
    assert_eq!(deeper.count(), met.len());
}
