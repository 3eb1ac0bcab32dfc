//! Scene validation: parse RON, check every reference and value section by section, and build
//! the solver `Model`. Every error names the file, the line where it could be located, the
//! field and the node, element or body concerned. Never panics on user input.
//! `parse.rs` reads a scene; `geometry.rs` (sections, nodes and bodies),
//! `conditions.rs` (supports, loads, prescribed), `contacts.rs`, `obstacles.rs`, `control.rs` and
//! `stages.rs` (load groups and the load path) check one part each; `errors.rs` locates what is wrong.

mod conditions;
mod contacts;
mod control;
mod distributed;
mod errors;
mod geometry;
mod obstacles;
mod parse;
mod stages;

pub use errors::SceneError;
pub use geometry::MAX_ELEMENTS;
pub use parse::{from_scene_file, load_file, parse, Scene, MAX_SCENE_BYTES};
pub use stages::{group_names, DEFAULT_GROUP, GRAVITY_GROUP};
