//! Scenes: the RON file format (an obstacle's curve in `shape.rs`), validation with located
//! errors, the built-in scenes shipped in `assets/scenes/`, writing a scene back as RON, and a
//! run kept as the scene's load path.

pub mod builtin;
pub mod format;
pub mod kept;
pub mod remesh;
pub mod shape;
pub mod units;
pub mod validate;
pub mod write;

pub use builtin::open;
pub use format::SceneFile;
pub use validate::{from_scene_file, load_file, parse, Scene, SceneError};
