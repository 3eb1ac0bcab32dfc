//! The reports (feature `reports`, on by default): measurements of the solver that the CLI
//! prints and writes into `docs/`, built on the library's public API only. Each file is one
//! report or the reference it is measured against:
//! `work_precision.rs` (error against time, with `pin_elastica.rs` the contact reference),
//! `stress/` (the stability suite), `scaling.rs` and `contact_scaling.rs` (cost against
//! size, with `plain_chain.rs` the yardstick), `interactive.rs` (slider re-solve times), `robust/` (the robustness campaign, its families' scenes in `families.rs`, the built-in scenes as they ship in `shipped.rs`).

pub mod contact_scaling;
pub mod interactive;
pub mod pin_elastica;
pub mod plain_chain;
pub mod robust;
pub mod scaling;
pub mod stress;
pub mod work_precision;
