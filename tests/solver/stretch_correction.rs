//! The stretch correction of Newton's update (`SolverParams::stretch_correction`, the scene's
//! `control: (stretch_correction: ...)`): it changes how an increment converges, not where.
//! Each figure is checked against the same run without it (plain Newton) and, for the
//! roll-up, against the regular polygon. The default mode corrects, in a model without
//! contact, the updates whose chords' gaps would load the structure more than the force they
//! remove, and switches the correction on for every update at a run's first cut-back; a model
//! with contact is plain Newton's, bit for bit, until then.

use crate::common;

use tsm_contact::scene::{builtin, Scene};
use tsm_contact::solver::{Event, IncrementRecord, Observer, StretchCorrection};

use StretchCorrection::{AfterCutBack, Always, Never, WhereNeeded};

/// Built-in scene `file` on `n` elements, with the correction in `mode`.
fn variant(file: &str, n: usize, mode: StretchCorrection) -> Scene {
    let mut sc = builtin::with_elements(file, n)
        .expect("a one-body built-in scene")
        .expect("valid variant");
    sc.params.stretch_correction = mode;
    sc
}

/// The events of a run, in order.
#[derive(Default)]
struct Events(Vec<Event>);

impl Observer for Events {
    fn event(&mut self, e: &Event) {
        self.0.push(e.clone());
    }
}

fn run_with_events(sc: &Scene) -> (Vec<IncrementRecord>, Vec<Event>) {
    let mut s = sc.solver().expect("stable");
    let mut events = Events::default();
    let recs: Vec<IncrementRecord> = (0..sc.steps)
        .flat_map(|_| s.step(&mut events).expect("converges"))
        .collect();
    common::assert_audited(sc, &recs);
    (recs, events.0)
}

fn run(sc: &Scene) -> Vec<IncrementRecord> {
    run_with_events(sc).0
}

fn iterations(recs: &[IncrementRecord]) -> usize {
    recs.iter().map(|r| r.iterations).sum()
}

/// Where the run's first cut-back is, and the increment it was in.
fn first_cut_back(events: &[Event]) -> (usize, usize) {
    events
        .iter()
        .enumerate()
        .find_map(|(k, e)| match e {
            Event::CutBack { increment, .. } => Some((k, *increment)),
            _ => None,
        })
        .expect("a cut-back")
}

fn switches(events: &[Event]) -> usize {
    let on = |e: &&Event| matches!(e, Event::StretchCorrectionOn { .. });
    events.iter().filter(on).count()
}

/// Mattiasson's cantilever, k = 10 in 10 steps, on 1000 elements, in the three modes. Plain
/// Newton zig-zags and needs 12 increments and 127 iterations (measured); always corrected,
/// 11 and 70 (at most 11 and 100 asserted, and plain Newton at least 1.5 times as many, so
/// that the test fails if the correction stops doing anything). Corrected after a cut-back, it
/// cuts back where plain Newton does (its first attempt diverges), reports the switch right
/// after that cut-back and never again, and then needs 76 iterations (at most 110 asserted). The tip lands on the
/// same place in every mode, to 1e-8 L (measured 1e-16; the increments are accepted at
/// relative residuals up to 5e-6, the round-off floor of 1 mm elements).
#[test]
fn mattiasson_on_1000_elements_converges_in_fewer_iterations() {
    let recs = |mode| run_with_events(&variant("mattiasson.ron", 1000, mode));
    let ((plain, plain_events), (auto, events)) = (recs(Never), recs(AfterCutBack));
    let always = recs(Always).0;
    assert!(
        2 * iterations(&plain) >= 3 * iterations(&always),
        "plain {}, always {}",
        iterations(&plain),
        iterations(&always)
    );
    assert!(
        always.len() <= 11 && iterations(&always) <= 100,
        "always: {} increments, {} iterations",
        always.len(),
        iterations(&always)
    );
    assert_eq!(first_cut_back(&plain_events), first_cut_back(&events));
    let (k, increment) = first_cut_back(&events);
    assert_eq!(events[k + 1], Event::StretchCorrectionOn { increment });
    assert_eq!((switches(&events), switches(&plain_events)), (1, 0));
    assert!(
        iterations(&auto) <= 110,
        "after a cut-back {}",
        iterations(&auto)
    );
    let tip = |r: &[IncrementRecord]| r.last().expect("record").nodes[1000];
    for other in [&always, &auto] {
        let (a, b) = (tip(&plain), tip(other));
        assert!(
            (a[0] - b[0]).abs() < 1e-8 && (a[1] - b[1]).abs() < 1e-8,
            "{a:?} {b:?}"
        );
    }
}

/// The roll-up by 2 pi EI/L on 16 elements in 10 steps: 60 iterations of plain Newton
/// (measured; at least 50 asserted), 20 with the correction on (at most 30), and the
/// same regular polygon either way: the middle node within 1e-12 L of plain Newton's
/// (measured 2e-15).
#[test]
fn roll_up_converges_in_a_third_of_the_iterations() {
    let plain = run(&variant("end_moment.ron", 16, Never));
    let always = run(&variant("end_moment.ron", 16, Always));
    assert!(iterations(&plain) >= 50, "plain {}", iterations(&plain));
    assert!(iterations(&always) <= 30, "always {}", iterations(&always));
    let middle = |r: &[IncrementRecord]| r.last().expect("record").nodes[8];
    let (a, b) = (middle(&plain), middle(&always));
    assert!(
        (a[0] - b[0]).abs() < 1e-12 && (a[1] - b[1]).abs() < 1e-12,
        "{a:?} {b:?}"
    );
}

/// The Bernoulli-Euler pin on 1024 elements with the correction on. Its contact spring keeps
/// the stiffness finite near element ends (without it, 3 EI / li^3 lifts the residual's
/// round-off floor to 1e-3 and beyond), so every increment is accepted within the round-off
/// bound, and the run ends with the pin on the beam, against Reissner's beam (`pin_elastica`,
/// no shear): the contact point to 1e-7 L and the force to 5e-6 of its size.
#[cfg(feature = "reports")]
#[test]
fn bernoulli_euler_pin_on_1024_elements_stays_on_the_beam() {
    use tsm_contact::reports::work_precision::pin_errors;
    use tsm_contact::solver::Formulation;
    let mut sc = variant("pin_on_cantilever.ron", 1024, Always);
    sc.model.formulation = Formulation::BernoulliEuler;
    sc.params.roundoff_factor = 0.0;
    let recs = run(&sc);
    let worst = recs.iter().fold(0.0f64, |w, r| w.max(r.relative_residual));
    assert!(worst <= sc.params.roundoff_bound, "accepted at {worst:e}");
    let [force, arc] = pin_errors(&sc, &recs).expect("the pin ends on the beam");
    eprintln!("Bernoulli-Euler pin, 1024 elements: force {force:e}, arc {arc:e}, worst residual {worst:e}");
    assert!(arc < 1e-7 && force < 5e-6, "arc {arc:e}, force {force:e}");
}

/// Example 3.2 in the default mode (a model with contact): its 49 increments before the first
/// cut-back (in increment 50) are plain Newton's bit for bit (iterations and node positions), the switch
/// is reported there, and from then on each step ends in plain Newton's equilibrium: at the
/// step ends both runs reach (32 of them), every node within 1e-9 m of plain Newton's
/// (measured 3.2e-11 m; increments converge to a relative residual of 1e-8).
#[test]
fn example_3_2_is_plain_newton_until_its_first_cut_back() {
    let sc = builtin::builtin("example_3_2")
        .expect("built-in")
        .expect("valid");
    let mut plain_sc = sc.clone();
    plain_sc.params.stretch_correction = Never;
    assert_eq!(sc.params.stretch_correction, WhereNeeded, "the default");
    let (plain, plain_events) = run_with_events(&plain_sc);
    let (auto, events) = run_with_events(&sc);
    let (k, increment) = first_cut_back(&events);
    assert_eq!(first_cut_back(&plain_events).1, increment);
    assert_eq!(events[k + 1], Event::StretchCorrectionOn { increment });
    assert_eq!(switches(&events), 1);
    let before = increment - 1;
    assert!(before >= 40, "first cut-back in increment {increment}");
    for (a, b) in plain[..before].iter().zip(&auto[..before]) {
        assert_eq!((a.iterations, &a.nodes), (b.iterations, &b.nodes));
    }
    assert_ne!(
        plain.len(),
        auto.len(),
        "the correction changed nothing after the switch"
    );
    // Each step's end (the same prescribed pin position, reached exactly) from the switch on:
    // the same equilibrium either way.
    let mut compared = 0;
    let mut gap = 0.0f64;
    for b in &auto[before..] {
        if let Some(a) = plain[before..]
            .iter()
            .find(|a| a.prescribed == b.prescribed)
        {
            let d = (a.nodes.iter().zip(&b.nodes))
                .map(|(p, q)| (p[0] - q[0]).hypot(p[1] - q[1]))
                .fold(0.0, f64::max);
            gap = gap.max(d);
            compared += 1;
        }
    }
    assert!(compared >= 25, "only {compared} common states");
    assert!(gap < 1e-9, "states {gap:e} m apart");
}

/// A run Newton takes without a cut-back (the roll-up on 16 elements) is plain Newton's bit
/// for bit when corrected after a cut-back: the same iterations, the same node positions, no
/// switch.
#[test]
fn after_a_cut_back_a_run_without_one_is_plain_newton() {
    let (plain, _) = run_with_events(&variant("end_moment.ron", 16, Never));
    let (auto, events) = run_with_events(&variant("end_moment.ron", 16, AfterCutBack));
    assert!(events.is_empty(), "{events:?}");
    assert_eq!(plain.len(), auto.len());
    for (a, b) in plain.iter().zip(&auto) {
        assert_eq!((a.iterations, &a.nodes), (b.iterations, &b.nodes));
    }
}

/// The roll-up by 2 pi EI/L on 64 elements in the default mode, a model without contact: the
/// linear predictor turns the stiff chords (EA L^2 / EI = 1e6) and its gaps would load the
/// beam far beyond the moment's step, so it is corrected, and each increment takes 2
/// iterations, 3 where one more tells the round-off floor (measured: 23 in all; at most 3 each
/// asserted), against plain Newton's 8 or 9 (86 in all; at least 6 each asserted). The same
/// regular polygon either way: every node within 1e-12 L of plain Newton's.
#[test]
fn the_default_corrects_the_roll_up_where_its_updates_turn_stiff_chords() {
    let plain = run(&variant("end_moment.ron", 64, Never));
    let (judged, events) = run_with_events(&variant("end_moment.ron", 64, WhereNeeded));
    assert!(events.is_empty(), "{events:?}");
    assert_eq!(plain.len(), judged.len());
    for (a, b) in plain.iter().zip(&judged) {
        assert!(
            a.iterations >= 6,
            "plain increment {}: {}",
            a.increment,
            a.iterations
        );
        assert!(
            b.iterations <= 3,
            "increment {}: {}",
            b.increment,
            b.iterations
        );
    }
    let (a, b) = (
        plain.last().expect("record"),
        judged.last().expect("record"),
    );
    let gap = (a.nodes.iter().zip(&b.nodes))
        .map(|(p, q)| (p[0] - q[0]).hypot(p[1] - q[1]))
        .fold(0.0, f64::max);
    assert!(gap < 1e-12, "nodes {gap:e} L apart");
}

/// Judged updates are those of prescribed displacements and loads without a step limit: with
/// `max_step` set (the roll-up on 16 elements, a limit it never reaches) or under arc-length
/// control (Lee's frame), the default mode runs as `AfterCutBack`, bit for bit; without either,
/// the roll-up is corrected (fewer iterations than plain Newton's).
#[test]
fn the_default_judges_no_update_under_a_step_limit_or_an_arc_length() {
    let same = |mut a: Scene| {
        a.params.stretch_correction = WhereNeeded;
        let mut b = a.clone();
        b.params.stretch_correction = AfterCutBack;
        let (a, b) = (run(&a), run(&b));
        assert_eq!(a.len(), b.len());
        for (x, y) in a.iter().zip(&b) {
            assert_eq!((x.iterations, &x.nodes), (y.iterations, &y.nodes));
        }
        iterations(&a)
    };
    let mut limited = variant("end_moment.ron", 16, WhereNeeded);
    limited.params.max_step = 1e6;
    let plain = same(limited);
    let judged = iterations(&run(&variant("end_moment.ron", 16, WhereNeeded)));
    assert!(judged < plain, "judged {judged}, plain {plain}");
    same(
        builtin::builtin("lee_frame")
            .expect("built-in")
            .expect("valid"),
    );
}
