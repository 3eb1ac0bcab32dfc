//! Writing a scene file: a `SceneFile` as RON text that `parse` reads back to the same scene
//! (every number written to round-trip exactly).

use super::format::SceneFile;

/// `file` as the RON text of a scene file.
pub fn scene_text(file: &SceneFile) -> Result<String, String> {
    let config = ron::ser::PrettyConfig::new().struct_names(false);
    ron::ser::to_string_pretty(file, config).map_err(|e| e.to_string())
}
