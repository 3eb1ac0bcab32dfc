//! Command-line interface: `solve` runs a scene headless and prints one line per increment;
//! `view` (feature `gui`) opens the visualiser or renders a screenshot.

use std::path::{Path, PathBuf};
use std::time::Instant;

use clap::{Args, Parser, Subcommand, ValueEnum};

/// `println!` that ends the program quietly when stdout is closed (output piped into `head`)
/// instead of panicking.
macro_rules! out {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        if let Err(e) = writeln!(std::io::stdout(), $($arg)*) {
            if e.kind() == std::io::ErrorKind::BrokenPipe {
                std::process::exit(0);
            }
            panic!("cannot write to stdout: {e}");
        }
    }};
}
use tsm_contact::history::History;
use tsm_contact::scene::{self, Scene, SceneError};
use tsm_contact::solver::report::{ContactChange, Flow};
use tsm_contact::solver::{
    Event, Formulation, IncrementRecord, IncrementStatus, Observer, StretchCorrection,
};

#[derive(Parser)]
#[command(
    name = "tsm-contact",
    version,
    about = "Tangent Stiffness Method for large-displacement contact of plane frames"
)]
struct Cli {
    #[command(subcommand)]
    command: Option<Command>,
}

#[derive(Clone, Copy, ValueEnum)]
enum FormulationArg {
    Timoshenko,
    BernoulliEuler,
}

/// `--stretch-correction`'s values (`StretchCorrection`).
#[derive(Clone, Copy, ValueEnum)]
enum StretchArg {
    Never,
    AfterCutBack,
    Always,
}

/// The `solve` command's arguments.
#[derive(Args)]
struct SolveArgs {
    /// Scene file (RON) or the name of a built-in scene.
    scene: String,
    /// Number of steps (default: the scene's).
    #[arg(long)]
    steps: Option<usize>,
    /// Override the element formulation.
    #[arg(long, value_enum)]
    formulation: Option<FormulationArg>,
    /// Write the full history as JSON.
    #[arg(long)]
    json: Option<PathBuf>,
    /// Print every Newton iteration's residual.
    #[arg(long)]
    verbose: bool,
    /// Use the contact element's unsymmetric tangent term from this iteration of each pass
    /// on (1 = always, the default; 0 = never).
    #[arg(long)]
    unsymmetric_from: Option<usize>,
    /// When Newton's updates take the chords' second-order gaps out (the scene's
    /// `control: (stretch_correction: ...)`, by default after the run's first cut-back): for
    /// fine meshes of axially stiff beams in large rotation. Given without a value: always.
    #[arg(long, num_args = 0..=1, default_missing_value = "always")]
    stretch_correction: Option<StretchArg>,
}

#[derive(Subcommand)]
enum Command {
    /// Solve a scene headless: one line per increment, contact events as they happen.
    Solve(SolveArgs),
    /// List the built-in scenes.
    Scenes,
    /// Work-precision report: error against wall time for reference problems, formulations,
    /// meshes and tolerances; writes work-precision.csv and .svg into --out and prints a table,
    /// then the slider-update timings of the paper scenes (see `interactive`).
    Bench {
        /// Fewer meshes, one tolerance, one repeat.
        #[arg(long)]
        quick: bool,
        /// Output folder.
        #[arg(long, default_value = "docs")]
        out: PathBuf,
    },
    /// Scaling report: one Newton increment of a cantilever of 10 to 10^5 elements (time per
    /// element per iteration, peak memory).
    Scale {
        /// Largest size (default 100000).
        #[arg(long, default_value_t = 100_000)]
        max: usize,
        /// Instead: contact scaling, a bed of 100 to 10^5 elements pressed by a pin in every
        /// span (up to --max), with and without the broad phase.
        #[arg(long)]
        contact: bool,
    },
    /// Stability suite: hard cases for both formulations; prints a Markdown table and writes
    /// stress.md into --out.
    Stress {
        /// Add the long variants (finer load paths, more turns).
        #[arg(long)]
        long: bool,
        /// Output folder.
        #[arg(long, default_value = "docs")]
        out: PathBuf,
    },
    /// Open the visualiser on a scene (default: the built-in default scene).
    #[cfg(feature = "gui")]
    View {
        /// Scene file or built-in name.
        scene: Option<String>,
        /// Solve this many steps before showing (with --screenshot: before the shot).
        #[arg(long)]
        steps: Option<usize>,
        /// Render to this PNG file after the steps and exit.
        #[arg(long)]
        screenshot: Option<PathBuf>,
    },
}

/// Load a scene from a path, or a built-in by name.
pub fn load_scene(name: &str) -> Result<Scene, SceneError> {
    let path = Path::new(name);
    if path.exists() {
        return scene::load_file(path);
    }
    match scene::builtin::builtin(name) {
        Some(r) => r,
        None => Err(SceneError {
            file: name.into(),
            line: None,
            field: "(file)".into(),
            message: "no such file and no built-in scene of that name (try `tsm-contact scenes`)"
                .into(),
        }),
    }
}

pub fn run() -> i32 {
    let cli = Cli::parse();
    match cli.command {
        Some(Command::Solve(args)) => solve(args),
        Some(Command::Bench { quick, out }) => bench(quick, &out),
        Some(Command::Stress { long, out }) => stress(long, &out),
        Some(Command::Scale { max, contact: true }) => {
            let sizes: Vec<usize> = [100, 1_000, 10_000, 100_000]
                .into_iter()
                .filter(|&n| n <= max)
                .collect();
            out!(
                "{}",
                tsm_contact::reports::contact_scaling::table(
                    &tsm_contact::reports::contact_scaling::measure(&sizes, 10_000)
                )
            );
            0
        }
        Some(Command::Scale {
            max,
            contact: false,
        }) => {
            let sizes: Vec<usize> = [10, 100, 1_000, 10_000, 100_000]
                .into_iter()
                .filter(|&n| n <= max)
                .collect();
            out!(
                "{}",
                tsm_contact::reports::scaling::table(&tsm_contact::reports::scaling::measure(
                    &sizes
                ))
            );
            0
        }
        Some(Command::Scenes) => {
            for (f, _) in scene::builtin::BUILTIN {
                out!("{}", f.trim_end_matches(".ron"));
            }
            0
        }
        #[cfg(feature = "gui")]
        Some(Command::View {
            scene,
            steps,
            screenshot,
        }) => tsm_contact::app::run(scene, steps, screenshot),
        None => {
            #[cfg(feature = "gui")]
            {
                tsm_contact::app::run(None, None, None)
            }
            #[cfg(not(feature = "gui"))]
            {
                eprintln!("built without the `gui` feature; use `tsm-contact solve SCENE`");
                2
            }
        }
    }
}

struct Printer {
    history: History,
    verbose: bool,
}

impl Observer for Printer {
    fn iteration(&mut self, r: &tsm_contact::solver::IterationRecord) -> Flow {
        if self.verbose {
            out!(
                "      iter {:>3}  |R| = {:.3e}  |R|/ref = {:.3e}  |du| = {:.3e}  contacts {}",
                r.iteration,
                r.residual,
                r.relative_residual,
                r.step_norm,
                r.active_contacts
            );
        }
        Flow::Continue
    }
    fn increment(&mut self, r: &IncrementRecord) -> Flow {
        let driven = if r.prescribed.is_empty() {
            format!("lambda {:>9.4}", r.load_factor)
        } else {
            r.prescribed
                .iter()
                .map(|v| format!("{v:>+10.5}"))
                .collect::<Vec<_>>()
                .join(" ")
        };
        let it8 = r.iterations_8_orders.map_or("-".into(), |v| v.to_string());
        // A relative residual accepted at the round-off floor (above the tolerance) is marked.
        let mark = match r.status {
            IncrementStatus::Converged => ' ',
            IncrementStatus::RoundOff { .. } => 'r',
        };
        out!(
            "{:>5}  {}  {:>4}  {:>4}  {:>9.2e}{}  {:>3}  {:>3}  {:>8.2}",
            r.increment,
            driven,
            r.iterations,
            it8,
            r.relative_residual,
            mark,
            r.cutbacks,
            r.contacts.len(),
            r.seconds * 1e3
        );
        self.history.increment(r)
    }
    fn event(&mut self, e: &Event) {
        match e {
            Event::CutBack {
                increment,
                reason,
                fraction,
            } => {
                out!("      cut-back in increment {increment}: {reason}; now trying {fraction} of the step")
            }
            Event::StretchCorrectionOn { increment } => {
                out!("      stretch correction on from increment {increment} (the run's first cut-back)")
            }
            Event::Contact(c) => {
                let what = match c.change {
                    ContactChange::Activated => "touches",
                    ContactChange::Transferred => "moves onto",
                    ContactChange::Released => "releases from",
                    ContactChange::SlidOff => "slides off",
                };
                out!(
                    "      event: node {} {} {} element {} (li/l = {:.4}, Yc = {:+.4e}) at iteration {}",
                    c.node, what, c.body, c.element, c.xi, c.force, c.iteration
                );
            }
        }
        self.history.event(e);
    }
}

fn solve(args: SolveArgs) -> i32 {
    let SolveArgs {
        scene: name,
        steps,
        formulation,
        json,
        verbose,
        unsymmetric_from,
        stretch_correction,
    } = args;
    let name = name.as_str();
    let mut scene = match load_scene(name) {
        Ok(s) => s,
        Err(e) => {
            eprintln!("error: {e}");
            return 2;
        }
    };
    if let Some(f) = formulation {
        scene.model.formulation = match f {
            FormulationArg::Timoshenko => Formulation::Timoshenko,
            FormulationArg::BernoulliEuler => Formulation::BernoulliEuler,
        };
    }
    if let Some(k) = unsymmetric_from {
        scene.params.unsymmetric_from = if k == 0 { usize::MAX } else { k };
    }
    if let Some(m) = stretch_correction {
        scene.params.stretch_correction = match m {
            StretchArg::Never => StretchCorrection::Never,
            StretchArg::AfterCutBack => StretchCorrection::AfterCutBack,
            StretchArg::Always => StretchCorrection::Always,
        };
    }
    let steps = steps.unwrap_or(scene.steps);
    let mut solver = match scene.solver() {
        Ok(s) => s,
        Err(e) => {
            eprintln!("error: {e}");
            return 2;
        }
    };
    out!(
        "# {} ({:?}), {} steps, tolerance {:.0e}",
        scene.file.name,
        scene.model.formulation,
        steps,
        scene.params.tolerance
    );
    out!("# incr  prescribed/load  iter  it8  rel.resid   cut  act   ms   (r: accepted at the round-off floor)");
    let mut printer = Printer {
        history: History {
            scene: scene.file.name.clone(),
            formulation: Some(scene.model.formulation),
            params: Some(scene.params),
            node_ids: scene.model.nodes.iter().map(|n| n.id).collect(),
            ..History::default()
        },
        verbose,
    };
    let t0 = Instant::now();
    let mut code = 0;
    for _ in 0..steps {
        if let Err(e) = solver.step(&mut printer) {
            eprintln!("error: {e}");
            printer.history.error = Some(e.to_string());
            code = 1;
            break;
        }
    }
    let total: usize = printer
        .history
        .increments
        .iter()
        .map(|r| r.iterations)
        .sum();
    out!(
        "# {} increments, {} iterations, {:.1} ms",
        printer.history.increments.len(),
        total,
        t0.elapsed().as_secs_f64() * 1e3
    );
    out!(
        "# {}",
        acceptance_summary(&printer.history.increments, code != 0)
    );
    if let Some(path) = json {
        if let Err(e) = printer.history.write_json(&path) {
            eprintln!("error: cannot write {}: {e}", path.display());
            return 2;
        }
    }
    code
}

/// One line on how the increments met the acceptance rule: how many converged to the tolerance,
/// how many were accepted at the round-off floor, the worst relative residual, and whether the
/// run stopped on a failure.
fn acceptance_summary(increments: &[IncrementRecord], failed: bool) -> String {
    let roundoff = (increments.iter())
        .filter(|r| matches!(r.status, IncrementStatus::RoundOff { .. }))
        .count();
    let worst = (increments.iter()).fold(0.0f64, |w, r| w.max(r.relative_residual));
    format!(
        "{} increments converged, {roundoff} accepted at round-off, worst relative residual {worst:.2e}{}",
        increments.len() - roundoff,
        if failed { "; the run stopped on a failure" } else { "" }
    )
}

/// Make the output folder `out` (and its parents) before any measuring, so that a folder that
/// cannot be made fails at once, naming it.
fn output_folder(out: &Path) -> Result<(), i32> {
    std::fs::create_dir_all(out).map_err(|e| {
        eprintln!(
            "error: cannot make the output folder {}: {e}",
            out.display()
        );
        2
    })
}

fn bench(quick: bool, out: &Path) -> i32 {
    use tsm_contact::reports::work_precision as wp;
    if let Err(code) = output_folder(out) {
        return code;
    }
    let (points, failed) = wp::measure(quick);
    let write = |name: &str, text: String| {
        let path = out.join(name);
        tsm_contact::history::write_atomic(&path, text.as_bytes())
            .map_err(|e| format!("{}: {e}", path.display()))
    };
    if let Err(e) = write("work-precision.csv", wp::csv(&points))
        .and_then(|_| write("work-precision.svg", wp::svg(&points)))
    {
        eprintln!("error: cannot write {e}");
        return 2;
    }
    out!("{}", wp::table(&points));
    out!(
        "wrote {0}/work-precision.csv and {0}/work-precision.svg ({1} points)",
        out.display(),
        points.len()
    );
    out!("{}", wp::failures(&failed));
    use tsm_contact::reports::interactive;
    let repeats = if quick { 3 } else { 11 };
    let rows: Vec<_> = interactive::SCENES
        .iter()
        .map(|s| interactive::measure(s, repeats))
        .collect();
    out!("\n{}", interactive::table(&rows));
    0
}

fn stress(long: bool, out: &Path) -> i32 {
    if let Err(code) = output_folder(out) {
        return code;
    }
    let rows = tsm_contact::reports::stress::suite(long);
    let table = tsm_contact::reports::stress::markdown(&rows);
    out!("{table}");
    let page = format!(
        "# Stability suite\n\nGenerated by `tsm-contact stress{}` (release build). One row per case and \
         formulation; see `src/stress.rs` for each case's set-up and `docs/stability.md` for the \
         discussion.\n\n{table}",
        if long { " --long" } else { "" }
    );
    let path = out.join("stress.md");
    if let Err(e) = tsm_contact::history::write_atomic(&path, page.as_bytes()) {
        eprintln!("error: cannot write {}: {e}", path.display());
        return 2;
    }
    out!("wrote {}", path.display());
    0
}
