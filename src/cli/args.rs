//! The command line as clap parses it: the subcommands and their arguments.

use std::path::PathBuf;

use clap::{Args, Parser, Subcommand, ValueEnum};

/// The command line.
#[derive(Parser)]
#[command(
    name = "tsm-contact",
    version,
    about = "Tangent Stiffness Method for large-displacement contact of plane frames"
)]
pub(super) struct Cli {
    #[command(subcommand)]
    pub(super) command: Option<Command>,
}

/// `--formulation`'s values.
#[derive(Clone, Copy, ValueEnum)]
pub(super) enum FormulationArg {
    Timoshenko,
    BernoulliEuler,
}

/// `--stretch-correction`'s values (`StretchCorrection`).
#[derive(Clone, Copy, ValueEnum)]
pub(super) enum StretchArg {
    Never,
    WhereNeeded,
    AfterCutBack,
    Always,
}

/// The `solve` command's arguments.
#[derive(Args)]
pub(super) struct SolveArgs {
    /// Scene file (RON) or the name of a built-in scene.
    pub(super) scene: String,
    /// Number of steps (default: the scene's).
    #[arg(long)]
    pub(super) steps: Option<usize>,
    /// Override the element formulation.
    #[arg(long, value_enum)]
    pub(super) formulation: Option<FormulationArg>,
    /// Write the full history as JSON.
    #[arg(long)]
    pub(super) json: Option<PathBuf>,
    /// Print every Newton iteration's residual.
    #[arg(long)]
    pub(super) verbose: bool,
    /// Use the contact element's unsymmetric tangent term from this iteration of each pass
    /// on (1 = always, the default; 0 = never).
    #[arg(long)]
    pub(super) unsymmetric_from: Option<usize>,
    /// When Newton's updates take the chords' second-order gaps out (the scene's
    /// `control: (stretch_correction: ...)`, by default where needed): for fine meshes of
    /// axially stiff beams in large rotation. Given without a value: always.
    #[arg(long, num_args = 0..=1, default_missing_value = "always")]
    pub(super) stretch_correction: Option<StretchArg>,
    /// The most bytes the history (`--json`) may take; a run that would write more stops at
    /// that increment with an error (default 1 GiB).
    #[arg(long, default_value_t = tsm_contact::history::DEFAULT_MAX_OUTPUT)]
    pub(super) max_output: u64,
    /// Keep every N-th accepted increment in the history (`--json`), and the last: a thinned
    /// history says so, and `check` does not judge pass-through on it (a node may go through
    /// a body and back between the increments kept).
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..))]
    pub(super) every: Option<u32>,
}

/// The subcommands.
#[derive(Subcommand)]
pub(super) enum Command {
    /// Solve a scene headless: one line per increment, contact events as they happen.
    #[command(
        after_help = "Example: tsm-contact solve example_3_2 --steps 12 --json history.json"
    )]
    Solve(SolveArgs),
    /// Audit a history independently of the solver: equilibrium from the recorded forces, every
    /// support and prescribed dof where it is held, the side of every candidate node (through
    /// contact and release), obstacles, the friction law and the statuses. Exit 1 naming each increment, node and body found wrong. A thinned
    /// history (`solve --every N`) gets every check but pass-through, and says so.
    #[command(after_help = "Example: tsm-contact check history.json")]
    Check {
        /// The history (JSON, as `solve --json` writes it).
        history: std::path::PathBuf,
        /// The scene the history was solved on: the topology of a history that carries none.
        #[arg(long)]
        scene: Option<String>,
    },
    /// List the built-in scenes.
    #[command(after_help = "Example: tsm-contact scenes")]
    Scenes,
    /// Work-precision report: error against wall time for reference problems, formulations,
    /// meshes and tolerances; writes work-precision.csv and .svg into --out and prints a table,
    /// then the slider-update timings of the paper scenes (see `interactive`).
    #[cfg(feature = "reports")]
    #[command(after_help = "Example: tsm-contact bench --quick --out /tmp/report")]
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
    #[cfg(feature = "reports")]
    #[command(after_help = "Example: tsm-contact scale --max 10000")]
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
    #[cfg(feature = "reports")]
    #[command(after_help = "Example: tsm-contact stress --out /tmp/report")]
    Stress {
        /// Add the long variants (finer load paths, more turns).
        #[arg(long)]
        long: bool,
        /// Output folder.
        #[arg(long, default_value = "docs")]
        out: PathBuf,
    },
    /// Robustness campaign: seeded random drives of every built-in scene (meshes, formulations,
    /// steps from 3e-4 to 50 times the scene's, down and back up, friction); counts how they
    /// end and the Newton iterations of every increment (failed attempts included), audits
    /// every accepted state; then the built-in scenes as they ship and the validation
    /// problems, each through its own steps; prints a Markdown report and writes robustness.md
    /// into --out.
    #[cfg(feature = "reports")]
    #[command(after_help = "Example: tsm-contact robust --per-scene 4 --out /tmp/report")]
    Robust {
        /// Drives per built-in scene.
        #[arg(long, default_value_t = 24)]
        per_scene: usize,
        /// The campaign's seed (2k and 2k + 1 draw the same drives: each drive's draw starts odd).
        #[arg(long, default_value_t = 1)]
        seed: u64,
        /// Run only the drive with this seed (as the report prints it, 0x...) and print how it
        /// ends, writing no report.
        #[arg(long, value_parser = parse_drive)]
        drive: Option<u64>,
        /// With --drive: write the drive's history (every accepted state) as JSON, for `check`
        /// and the app.
        #[arg(long, requires = "drive")]
        json: Option<PathBuf>,
        /// Output folder.
        #[arg(long, default_value = "docs")]
        out: PathBuf,
    },
    /// Open the visualiser on a scene (default: the built-in default scene).
    #[cfg(feature = "gui")]
    #[command(
        after_help = "Example: tsm-contact view example_3_2 --steps 56 --screenshot shot.png"
    )]
    View {
        /// Scene file or built-in name.
        scene: Option<String>,
        /// Solve this many steps before showing (with --screenshot: before the shot).
        #[arg(long)]
        steps: Option<usize>,
        /// Render to this PNG file after the steps and exit.
        #[arg(long)]
        screenshot: Option<PathBuf>,
        /// Draw this force diagram along the beams: n (axial), v (shear) or m (moment).
        #[arg(long, value_enum)]
        diagram: Option<DiagramArg>,
    },
    /// Draw a scene's state after some steps as a figure for papers, without a window: the
    /// undeformed shape, the deformed beams, a force diagram, pins and contact nodes; a PNG of
    /// the chosen size or an SVG, by the extension of --out.
    #[cfg(feature = "figures")]
    #[command(
        after_help = "Example: tsm-contact figure example_3_2 --steps 40 --diagram m --out fig.png --size 1200x700"
    )]
    Figure {
        /// Scene file or built-in name.
        scene: String,
        /// Solve this many steps first (default: the scene's).
        #[arg(long)]
        steps: Option<usize>,
        /// Draw this force diagram along the beams: n (axial), v (shear) or m (moment).
        #[arg(long, value_enum)]
        diagram: Option<DiagramArg>,
        /// The file to write: .png or .svg.
        #[arg(long)]
        out: PathBuf,
        /// Width x height of a PNG in pixels (an SVG is 1200 wide, as tall as it needs).
        #[arg(long, default_value = "1600x1000")]
        size: String,
    },
}

/// A force diagram drawn along the beams: axial force N, shear V or bending moment M.
#[cfg(feature = "figures")]
#[derive(Clone, Copy, Debug, clap::ValueEnum)]
pub enum DiagramArg {
    N,
    V,
    M,
}

#[cfg(feature = "figures")]
impl DiagramArg {
    /// The diagram it names.
    pub fn diagram(self) -> tsm_contact::figure::Diagram {
        use tsm_contact::figure::Diagram;
        match self {
            DiagramArg::N => Diagram::Axial,
            DiagramArg::V => Diagram::Shear,
            DiagramArg::M => Diagram::Moment,
        }
    }
}

/// A drive's seed as the robustness report prints it: hexadecimal with `0x`, or decimal.
#[cfg(feature = "reports")]
fn parse_drive(text: &str) -> Result<u64, String> {
    let parsed = match text.strip_prefix("0x") {
        Some(hex) => u64::from_str_radix(hex, 16),
        None => text.parse(),
    };
    parsed.map_err(|e| format!("{text:?} is not a drive's seed (0x... or decimal): {e}"))
}
