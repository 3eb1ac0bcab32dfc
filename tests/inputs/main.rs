//! Inputs and outputs: scene validation and its seeded campaigns, history files, the command line, the docs and the architecture.
//! One test binary; each module is one subject (`cargo test --release --test inputs -- MODULE::`).

#[path = "../common/mod.rs"]
mod common;

mod architecture;
mod cli;
mod docs;
mod files;
mod fuzz_scenes;
mod input_campaign;
mod scene;
mod scene_sizes;
