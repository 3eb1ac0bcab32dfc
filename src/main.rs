//! The `tsm-contact` binary: the GUI by default, `solve` for headless runs.

mod cli;

fn main() {
    std::process::exit(cli::run());
}
