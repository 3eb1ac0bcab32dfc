//! Scene files in the app: the list of recent files, a `.ron` file dropped on the window, the
//! scene to open at start-up (the remembered one, or the default with the reason when it
//! cannot be opened), and saving the scene as solved (formulation and stretch correction
//! included) as a RON file.

use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use crate::history::write_atomic;
use crate::scene::Scene;

/// How many recent files the File menu lists.
pub const RECENT: usize = 8;

/// The scene files opened last, newest first.
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
pub struct Recent(Vec<PathBuf>);

impl Recent {
    /// Put `path` first (once), keeping `RECENT` entries.
    pub fn opened(&mut self, path: &Path) {
        let path = std::fs::canonicalize(path).unwrap_or_else(|_| path.to_path_buf());
        self.0.retain(|p| *p != path);
        self.0.insert(0, path);
        self.0.truncate(RECENT);
    }

    /// Forget `path` (it can no longer be opened).
    pub fn forget(&mut self, path: &Path) {
        self.0.retain(|p| p != path);
    }

    /// The files, newest first.
    pub fn files(&self) -> &[PathBuf] {
        &self.0
    }
}

/// Whether `name` names a file rather than a built-in scene.
pub fn is_file(name: &str) -> bool {
    name.ends_with(".ron") || name.contains(std::path::MAIN_SEPARATOR) || name.contains('/')
}

/// The first file dropped on the window this frame if it is a `.ron` file, or the reason it
/// is not taken.
pub fn dropped_scene(ctx: &egui::Context) -> Option<Result<PathBuf, String>> {
    let dropped = ctx.input(|i| i.raw.dropped_files.clone());
    let path = dropped.first()?.path().to_path_buf();
    Some(
        if path
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("ron"))
        {
            Ok(path)
        } else {
            Err(format!(
                "{}: not a scene (a scene is a .ron file)",
                path.display()
            ))
        },
    )
}

/// The scene to open at start-up: the one asked for, else the remembered one if it can still
/// be opened, else `default`. With the default in place of the remembered scene, the reason
/// comes too.
pub fn startup_scene(
    asked: Option<String>,
    remembered: Option<String>,
    default: &str,
) -> (String, Option<String>) {
    if let Some(a) = asked {
        return (a, None);
    }
    match remembered {
        None => (default.to_string(), None),
        Some(r) => match crate::scene::builtin::open(&r) {
            Ok(_) => (r, None),
            Err(e) => (
                default.to_string(),
                Some(format!(
                    "the last scene cannot be opened, so {default} is open instead: {e}"
                )),
            ),
        },
    }
}

/// The scene as solved, as the RON text of a scene file: its file with the formulation and the
/// stretch correction in use.
pub fn scene_text(scene: &Scene) -> Result<String, String> {
    let mut file = scene.file.clone();
    file.formulation = scene.model.formulation;
    file.control.stretch_correction = scene.params.stretch_correction;
    crate::scene::write::scene_text(&file)
}

/// Save the scene as solved to `path` (atomically: a failed write leaves the old file).
pub fn save_scene(path: &Path, scene: &Scene) -> Result<(), String> {
    let text = scene_text(scene)?;
    write_atomic(path, text.as_bytes()).map_err(|e| format!("cannot write {}: {e}", path.display()))
}
