//! The `tsm-contact` binary: the GUI by default, `solve` for headless runs.

mod cli;

/// mimalloc (the default `mimalloc` feature): the contact element's small per-call matrices
/// made glibc's malloc and free a fifth of Example 3.2's instructions.
#[cfg(feature = "mimalloc")]
#[global_allocator]
static ALLOCATOR: mimalloc::MiMalloc = mimalloc::MiMalloc;

fn main() {
    std::process::exit(cli::run());
}
