//! Command-line interface, one file per subcommand: `solve` runs a scene headless
//! (`solve.rs`); `bench`, `stress` and `scale` measure the solver (`reports.rs`); `scenes`
//! lists the built-in scenes; `check` audits a written history (`check.rs`); `view` (feature `gui`) opens the visualiser or renders a
//! screenshot; `figure` (feature `figures`) draws a state as a PNG or SVG without a window
//! (`figure.rs`). `args.rs` is the command line as clap parses it.

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

mod args;
mod check;
#[cfg(feature = "figures")]
mod figure;
#[cfg(feature = "reports")]
mod reports;
mod signals;
mod solve;

use clap::Parser;

use args::{Cli, Command};

/// Parse the command line and run it; returns the process exit code.
pub fn run() -> i32 {
    let cli = Cli::parse();
    match cli.command {
        Some(Command::Solve(args)) => solve::solve(args),
        #[cfg(feature = "reports")]
        Some(Command::Bench { quick, out }) => reports::bench(quick, &out),
        #[cfg(feature = "reports")]
        Some(Command::Stress { long, out }) => reports::stress(long, &out),
        #[cfg(feature = "reports")]
        Some(Command::Robust {
            per_scene,
            seed,
            drive,
            json,
            out,
        }) => match drive {
            Some(drive) => reports::robust_drive(per_scene, seed, drive, json.as_deref()),
            None => reports::robust(per_scene, seed, &out),
        },
        #[cfg(feature = "reports")]
        Some(Command::Scale { max, contact }) => reports::scale(max, contact),
        Some(Command::Check { history, scene }) => check::check(&history, scene.as_deref()),
        Some(Command::Scenes) => {
            for (f, _) in tsm_contact::scene::builtin::BUILTIN {
                out!("{}", f.trim_end_matches(".ron"));
            }
            0
        }
        #[cfg(feature = "gui")]
        Some(Command::View {
            scene,
            steps,
            screenshot,
            diagram,
        }) => {
            let diagram = diagram.map(args::DiagramArg::diagram);
            tsm_contact::app::run(tsm_contact::app::Startup {
                scene,
                steps,
                screenshot,
                diagram,
                ..Default::default()
            })
        }
        #[cfg(feature = "figures")]
        Some(Command::Figure {
            scene,
            steps,
            diagram,
            out,
            size,
        }) => figure::run(&scene, steps, diagram, &out, &size),
        None => {
            #[cfg(feature = "gui")]
            {
                tsm_contact::app::run(tsm_contact::app::Startup::default())
            }
            #[cfg(not(feature = "gui"))]
            {
                eprintln!("built without the `gui` feature; use `tsm-contact solve SCENE`");
                2
            }
        }
    }
}
