//! The work-precision report: for reference problems with known answers, each element
//! formulation, mesh and Newton tolerance, the error against the reference and the wall time
//! (median of repeats). Written as CSV, an SVG log-log plot (error against time) and a
//! Markdown table by `tsm-contact bench`.

use std::fmt::Write as _;
use std::time::Instant;

use crate::reports::pin_elastica::{rim_on_cantilever, Stiffness};
use crate::scene::builtin::with_elements;
use crate::scene::Scene;
use crate::solver::{Formulation, IncrementRecord, Silent};

mod plot;
mod point;
pub use plot::svg;
pub use point::Point;

/// Mattiasson (1981) tip displacements (k, u/L, w/L) for k = 1, 5, 10.
pub const MATTIASSON: [(f64, f64, f64); 3] = [
    (1.0, 0.056433236, 0.301720774),
    (5.0, 0.387628361, 0.713791524),
    (10.0, 0.554995598, 0.810609025),
];

/// The report's name of the end-moment problem.
const END_MOMENT: &str = "End moment 2 pi";

/// The report's name of the contact problem.
const PIN_CONTACT: &str = "Pin contact";

/// The report's name of Mattiasson's problem at load k.
fn mattiasson_name(k: f64) -> String {
    format!("Mattiasson k={k}")
}

/// The one-body built-in scene `file` on `n` elements of formulation `formulation` at
/// tolerance `tol`, with the load factor `load` reached over its steps where given: a reference
/// problem as the report solves it, under the solver's own acceptance rules.
fn cantilever(
    file: &str,
    n: usize,
    formulation: Formulation,
    tol: f64,
    load: Option<f64>,
) -> Scene {
    let mut sc = with_elements(file, n)
        .expect("a one-body built-in scene")
        .expect("valid variant");
    sc.model.formulation = formulation;
    sc.params.tolerance = tol;
    if let Some(k) = load {
        sc.model.load_per_step = k / sc.steps as f64;
    }
    sc
}

fn run(sc: &Scene) -> Option<Vec<IncrementRecord>> {
    let mut solver = sc.solver().ok()?;
    let mut out = Vec::new();
    for _ in 0..sc.steps {
        out.extend(solver.step(&mut Silent).ok()?);
    }
    Some(out)
}

/// Time `f` `repeats` times; return the median (s) and the last result.
fn timed<T>(repeats: usize, mut f: impl FnMut() -> T) -> (f64, T) {
    timed_on(repeats, || (), |()| f())
}

/// Time `run` `repeats` times, each on a fresh value from `setup` (not timed); return the median
/// (s) and the last result.
pub(crate) fn timed_on<S, T>(
    repeats: usize,
    mut setup: impl FnMut() -> S,
    mut run: impl FnMut(S) -> T,
) -> (f64, T) {
    let mut times = Vec::with_capacity(repeats);
    let mut last = None;
    for _ in 0..repeats.max(1) {
        let input = setup();
        let t = Instant::now();
        last = Some(run(input));
        times.push(t.elapsed().as_secs_f64());
    }
    times.sort_by(f64::total_cmp);
    (times[times.len() / 2], last.expect("ran once"))
}

/// Mattiasson cantilever at load k: error max(|u/L - ref|, |w/L - ref|) at the tip.
pub fn mattiasson(
    k_index: usize,
    n: usize,
    f: Formulation,
    tol: f64,
    repeats: usize,
) -> Option<Point> {
    let (k, u_ref, w_ref) = MATTIASSON[k_index];
    let sc = mattiasson_scene(k_index, n, f, tol);
    let (seconds, recs) = timed(repeats, || run(&sc));
    let recs = recs?;
    let tip = recs.last()?.nodes[n];
    let error = ((1.0 - tip[0]) - u_ref).abs().max((-tip[1] - w_ref).abs());
    Some(point(mattiasson_name(k), f, n, tol, &recs, error, seconds))
}

/// Mattiasson's cantilever at load `MATTIASSON[k_index]` on `n` elements of formulation `f`,
/// at tolerance `tol`.
fn mattiasson_scene(k_index: usize, n: usize, f: Formulation, tol: f64) -> Scene {
    cantilever("mattiasson.ron", n, f, tol, Some(MATTIASSON[k_index].0))
}

/// The contact problem's scene on `n` elements of formulation `f`, at tolerance `tol`.
fn pin_contact_scene(n: usize, f: Formulation, tol: f64) -> Scene {
    cantilever("pin_on_cantilever.ron", n, f, tol, None)
}

/// The reference problems on `n` elements of formulation `f` at tolerance `tol`, by name, as
/// this report solves them (Mattiasson's three loads, the end moment, the pin contact).
pub fn problems(n: usize, f: Formulation, tol: f64) -> Vec<(String, Scene)> {
    let mut out: Vec<_> = (0..MATTIASSON.len())
        .map(|k| {
            (
                mattiasson_name(MATTIASSON[k].0),
                mattiasson_scene(k, n, f, tol),
            )
        })
        .collect();
    out.push((
        END_MOMENT.into(),
        cantilever("end_moment.ron", n, f, tol, None),
    ));
    out.push((PIN_CONTACT.into(), pin_contact_scene(n, f, tol)));
    out
}

/// End moment 2 pi EI/L, the whole roll-up: the beam closes into a circle of radius L / 2 pi
/// through the clamp, and its middle (node n/2, n even) lies at (0, L / pi). The tip closes
/// onto the clamp on every mesh (the elements' chords make a regular polygon), so the error is
/// the middle's distance from its place, over L.
pub fn end_moment(n: usize, f: Formulation, tol: f64, repeats: usize) -> Option<Point> {
    let sc = cantilever("end_moment.ron", n, f, tol, None);
    let (seconds, recs) = timed(repeats, || run(&sc));
    let recs = recs?;
    let middle = recs.last()?.nodes[n / 2];
    let error = middle[0].hypot(middle[1] - 1.0 / std::f64::consts::PI);
    Some(point(END_MOMENT.into(), f, n, tol, &recs, error, seconds))
}

/// The contact problem: a frictionless pin driven down onto a cantilever
/// (`pin_on_cantilever.ron`), against Reissner's beam solved by shooting (`pin_elastica`; with
/// the section's shear for Timoshenko, without for Bernoulli-Euler; the pin's normal in the shear
/// kink under it chosen as the contact element chooses it). Error: the larger of the
/// pin force's error over its size and the contact point's error along the beam over L, at
/// the last increment.
pub fn pin_contact(n: usize, f: Formulation, tol: f64, repeats: usize) -> Option<Point> {
    pin_contact_errors(n, f, tol, repeats).map(|(p, _)| p)
}

/// `pin_contact`, with its two errors apart: (force error over the force's size, contact
/// point error over L).
pub fn pin_contact_errors(
    n: usize,
    f: Formulation,
    tol: f64,
    repeats: usize,
) -> Option<(Point, [f64; 2])> {
    let sc = pin_contact_scene(n, f, tol);
    let (seconds, recs) = timed(repeats, || run(&sc));
    let recs = recs?;
    let [force_error, arc_error] = pin_errors(&sc, &recs)?;
    let p = point(
        PIN_CONTACT.into(),
        f,
        n,
        tol,
        &recs,
        force_error.max(arc_error),
        seconds,
    );
    Some((p, [force_error, arc_error]))
}

/// The errors of a run `recs` of a pin-on-cantilever scene `sc` (one prescribed pin, one
/// straight cantilever numbered from its clamp, any mesh and formulation) at its last
/// increment, against Reissner's beam: (pin force error over the force's size, contact point
/// error over L). `None` if the pin is not on the beam at the end.
pub fn pin_errors(sc: &Scene, recs: &[IncrementRecord]) -> Option<[f64; 2]> {
    let pin = sc.model.prescribed.first()?;
    let start = sc.model.position(pin.node);
    let at = [start[0], start[1] + pin.per_step * sc.steps as f64];
    let beam = sc.model.beams.first()?.section;
    let length: f64 = (sc.model.beams.iter())
        .map(|b| {
            let (p, q) = (sc.model.position(b.i), sc.model.position(b.j));
            (q[0] - p[0]).hypot(q[1] - p[1])
        })
        .sum();
    let timoshenko = sc.model.formulation == Formulation::Timoshenko;
    let gae = if timoshenko { beam.gae } else { f64::INFINITY };
    let stiffness = Stiffness {
        ea: beam.ea,
        ei: beam.ei,
        gae,
    };
    let last = recs.last()?;
    let contact = last.contacts.first()?;
    // The shear kink under the pin (`pin_elastica`'s module comment): the force is normal to
    // the section (`surface_normal`), or to the chord, which weights the two sides by li / l.
    let share = contact.xi * f64::from(u8::from(!sc.params.surface_normal));
    let radius = sc.model.contact_distance(pin.node, 0);
    let reference = rim_on_cantilever((at, radius), length, stiffness, share)?;
    let user = sc.model.nodes[pin.node].id;
    let reaction = |dof: &str| {
        (last.reactions.iter())
            .find(|r| r.node == user && r.dof == dof)
            .map(|r| r.value)
    };
    let force = [reaction("u")?, reaction("v")?];
    let arc = (contact.element as f64 + contact.xi) * length / sc.model.beams.len() as f64;
    let size = reference.force[0].hypot(reference.force[1]);
    let force_error = (force[0] - reference.force[0]).hypot(force[1] - reference.force[1]) / size;
    let arc_error = (arc - reference.arc).abs() / length;
    Some([force_error, arc_error])
}

fn point(
    problem: String,
    f: Formulation,
    n: usize,
    tol: f64,
    recs: &[IncrementRecord],
    error: f64,
    seconds: f64,
) -> Point {
    Point {
        problem,
        formulation: f,
        elements: n,
        tolerance: tol,
        increments: recs.len(),
        iterations: recs.iter().map(|r| r.iterations).sum(),
        error,
        seconds,
    }
}

/// A run of the report that did not converge (no point for it).
#[derive(Clone, Debug, PartialEq)]
pub struct Failed {
    /// Problem name.
    pub problem: String,
    /// Element formulation.
    pub formulation: Formulation,
    /// Elements in the mesh.
    pub elements: usize,
    /// Newton tolerance (relative residual).
    pub tolerance: f64,
}

/// Every point of the report, and the runs that did not converge. `quick` uses fewer meshes
/// and repeats.
pub fn measure(quick: bool) -> (Vec<Point>, Vec<Failed>) {
    let meshes: &[usize] = if quick {
        &[4, 8, 16, 32]
    } else {
        &[4, 8, 16, 32, 64, 128, 256, 512, 1024]
    };
    let tols: &[f64] = if quick { &[1e-8] } else { &[1e-6, 1e-8, 1e-10] };
    let repeats = if quick { 1 } else { 5 };
    let (mut out, mut failed) = (Vec::new(), Vec::new());
    for f in [Formulation::BernoulliEuler, Formulation::Timoshenko] {
        for &tol in tols {
            for &n in meshes {
                let mut take = |problem: String, p: Option<Point>| match p {
                    Some(p) => out.push(p),
                    None => failed.push(Failed {
                        problem,
                        formulation: f,
                        elements: n,
                        tolerance: tol,
                    }),
                };
                for (k, &(load, _, _)) in MATTIASSON.iter().enumerate() {
                    take(mattiasson_name(load), mattiasson(k, n, f, tol, repeats));
                }
                take(END_MOMENT.into(), end_moment(n, f, tol, repeats));
                take(PIN_CONTACT.into(), pin_contact(n, f, tol, repeats));
            }
        }
    }
    (out, failed)
}

/// The runs that did not converge, a line each (empty if none).
pub fn failures(failed: &[Failed]) -> String {
    let mut s = String::new();
    for r in failed {
        let _ = writeln!(
            s,
            "did not converge: {}, {:?}, {} elements, tolerance {:e}",
            r.problem, r.formulation, r.elements, r.tolerance
        );
    }
    s
}

/// CSV text of the points.
pub fn csv(points: &[Point]) -> String {
    let mut s = String::from(
        "problem,formulation,elements,tolerance,increments,iterations,error,seconds\n",
    );
    for p in points {
        let _ = writeln!(
            s,
            "{},{:?},{},{:e},{},{},{:e},{:e}",
            p.problem,
            p.formulation,
            p.elements,
            p.tolerance,
            p.increments,
            p.iterations,
            p.error,
            p.seconds
        );
    }
    s
}

/// Markdown table: error and time per mesh at tolerance 1e-8.
pub fn table(points: &[Point]) -> String {
    let mut s = String::from("| problem | formulation | elements | iterations | error | time (ms) |\n|---|---|---|---|---|---|\n");
    for p in points.iter().filter(|p| p.tolerance == 1e-8) {
        let _ = writeln!(
            s,
            "| {} | {:?} | {} | {} | {:.2e} | {:.3} |",
            p.problem,
            p.formulation,
            p.elements,
            p.iterations,
            p.error,
            p.seconds * 1e3
        );
    }
    s
}
