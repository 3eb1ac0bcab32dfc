//! Scenes: the RON file format, validation with located errors, and the built-in scenes
//! shipped in `assets/scenes/`.

pub mod builtin;
pub mod format;
pub mod remesh;
pub mod units;
pub mod validate;

pub use builtin::open;
pub use format::SceneFile;
pub use validate::{from_scene_file, load_file, parse, Scene, SceneError};
