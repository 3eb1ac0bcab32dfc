//! The Python module `tsm_contact._native`: scenes (`Scene`), runs (`solve`, in `run.rs`),
//! histories with their arrays (`History`, in `history.rs`), the independent audit (`check`) and
//! the figure (`figure`, in `figure.rs`), all on the one Rust library. `tsm_contact/__init__.py`
//! wraps them for Python users (numpy arrays, pickling, callbacks).

mod figure;
mod history;
mod run;

use std::path::PathBuf;

use pyo3::create_exception;
use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use tsm_contact::scene::{self, Scene, SceneFile};

create_exception!(
    _native,
    SceneError,
    PyValueError,
    "A scene that cannot be read: `file`, `line` (or None), `field` and `message` say where and why."
);
create_exception!(
    _native,
    SolveError,
    PyRuntimeError,
    "A solver that cannot start on a scene (a mechanism, a node starting inside a body)."
);

/// `e` as a Python `SceneError` carrying its file, line, field and message.
fn scene_error(py: Python<'_>, e: scene::SceneError) -> PyErr {
    let err = SceneError::new_err(e.to_string());
    let value = err.value(py);
    let _ = value.setattr("file", &e.file);
    let _ = value.setattr("line", e.line);
    let _ = value.setattr("field", &e.field);
    let _ = value.setattr("message", &e.message);
    err
}

/// A validated scene: the model, the solver parameters and the number of steps.
#[pyclass(module = "tsm_contact._native", name = "Scene", frozen)]
pub struct PyScene {
    pub(crate) scene: Scene,
}

#[pymethods]
impl PyScene {
    /// Read and validate the RON scene file at `path`.
    #[staticmethod]
    fn from_file(py: Python<'_>, path: PathBuf) -> PyResult<PyScene> {
        scene::load_file(&path)
            .map(|scene| PyScene { scene })
            .map_err(|e| scene_error(py, e))
    }

    /// Validate the RON scene `text`; errors name `origin` as the file.
    #[staticmethod]
    #[pyo3(signature = (text, origin = "<text>"))]
    fn from_text(py: Python<'_>, text: &str, origin: &str) -> PyResult<PyScene> {
        scene::parse(text, origin)
            .map(|scene| PyScene { scene })
            .map_err(|e| scene_error(py, e))
    }

    /// Validate a scene given as JSON text of the scene file's fields (what `from_dict` sends).
    #[staticmethod]
    #[pyo3(signature = (text, origin = "<dict>"))]
    fn from_json(py: Python<'_>, text: &str, origin: &str) -> PyResult<PyScene> {
        let mut de = serde_json::Deserializer::from_str(text);
        let file: SceneFile = serde_path_to_error::deserialize(&mut de).map_err(|e| {
            let path = e.path().to_string();
            let field = if path.is_empty() || path == "." {
                "(structure)".to_string()
            } else {
                path
            };
            scene_error(
                py,
                scene::SceneError {
                    file: origin.into(),
                    line: None,
                    field,
                    // Where in the JSON text is no help to a dict's author: the path is.
                    message: (e.into_inner().to_string().split(" at line ").next())
                        .unwrap_or_default()
                        .to_string(),
                },
            )
        })?;
        scene::from_scene_file(file, origin)
            .map(|scene| PyScene { scene })
            .map_err(|e| scene_error(py, e))
    }

    /// A built-in scene by name (`tsm-contact scenes` lists them).
    #[staticmethod]
    fn builtin(py: Python<'_>, name: &str) -> PyResult<PyScene> {
        match scene::builtin::builtin(name) {
            Some(r) => r
                .map(|scene| PyScene { scene })
                .map_err(|e| scene_error(py, e)),
            None => Err(PyValueError::new_err(format!(
                "no built-in scene named {name:?}; the built-in scenes: {}",
                builtin_names().join(", ")
            ))),
        }
    }

    /// The scene as RON text that `from_text` reads back to the same scene.
    fn to_ron(&self) -> PyResult<String> {
        scene::write::scene_text(&self.scene.file).map_err(PyValueError::new_err)
    }

    /// The scene file's fields as JSON text (what `to_dict` reads; `from_json` takes it back).
    fn to_json(&self) -> PyResult<String> {
        serde_json::to_string(&self.scene.file).map_err(|e| PyValueError::new_err(e.to_string()))
    }

    /// The scene's name.
    #[getter]
    fn name(&self) -> String {
        self.scene.file.name.clone()
    }

    /// The steps a run makes by default.
    #[getter]
    fn steps(&self) -> usize {
        self.scene.steps
    }

    /// The node ids, in the order of the history's node arrays.
    #[getter]
    fn node_ids(&self) -> Vec<u32> {
        self.scene.model.nodes.iter().map(|n| n.id).collect()
    }

    /// The element formulation: "Timoshenko" or "BernoulliEuler".
    #[getter]
    fn formulation(&self) -> String {
        format!("{:?}", self.scene.model.formulation)
    }
}

/// The names of the built-in scenes.
#[pyfunction]
fn builtin_names() -> Vec<&'static str> {
    (scene::builtin::BUILTIN.iter())
        .map(|(name, _)| name.trim_end_matches(".ron"))
        .collect()
}

/// The module.
#[pymodule]
fn _native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add("SceneError", py.get_type::<SceneError>())?;
    m.add("SolveError", py.get_type::<SolveError>())?;
    m.add_class::<PyScene>()?;
    m.add_class::<history::PyHistory>()?;
    m.add_function(wrap_pyfunction!(builtin_names, m)?)?;
    m.add_function(wrap_pyfunction!(run::solve, m)?)?;
    m.add_function(wrap_pyfunction!(history::check, m)?)?;
    m.add_function(wrap_pyfunction!(figure::figure, m)?)?;
    Ok(())
}
