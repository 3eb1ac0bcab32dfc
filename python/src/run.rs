//! `solve`: a scene run in Rust with the GIL released, the history kept in memory. A callback
//! sees every accepted increment (its record as JSON text) and stops the run by returning
//! False; Ctrl-C (a pending signal) stops it at the next Newton iteration and raises
//! `KeyboardInterrupt`, leaving nothing half done.

use pyo3::prelude::*;
use tsm_contact::history::History;
use tsm_contact::solver::report::Flow;
use tsm_contact::solver::{Event, IncrementRecord, IterationRecord, Observer, SolveError};

use crate::history::PyHistory;
use crate::PyScene;

/// Keeps the history and relays increments to Python.
struct Relay {
    history: History,
    callback: Option<Py<PyAny>>,
    /// An exception raised by the callback or a signal (KeyboardInterrupt).
    error: Option<PyErr>,
    /// The callback returned False.
    stopped: bool,
}

impl Relay {
    /// Whether a signal is pending (then the run stops and the exception is kept).
    fn interrupted(&mut self) -> Flow {
        match Python::attach(|py| py.check_signals()) {
            Ok(()) => Flow::Continue,
            Err(e) => {
                self.error = Some(e);
                Flow::Stop
            }
        }
    }
}

impl Observer for Relay {
    fn iteration(&mut self, _r: &IterationRecord) -> Flow {
        self.interrupted()
    }

    fn increment(&mut self, r: &IncrementRecord) -> Flow {
        self.history.increments.push(r.clone());
        let Some(callback) = &self.callback else {
            return self.interrupted();
        };
        let text = match serde_json::to_string(r) {
            Ok(t) => t,
            Err(e) => {
                self.error = Some(pyo3::exceptions::PyValueError::new_err(e.to_string()));
                return Flow::Stop;
            }
        };
        let answer = Python::attach(|py| -> PyResult<bool> {
            py.check_signals()?;
            let out = callback.call1(py, (text,))?;
            let out = out.bind(py);
            Ok(out.is_none() || out.is_truthy()?)
        });
        match answer {
            Ok(true) => Flow::Continue,
            Ok(false) => {
                self.stopped = true;
                Flow::Stop
            }
            Err(e) => {
                self.error = Some(e);
                Flow::Stop
            }
        }
    }

    fn event(&mut self, e: &Event) {
        self.history.events.push(e.clone());
    }
}

/// Run `scene` for `steps` steps (default: the scene's). `on_increment(text)` gets each
/// accepted increment's record as JSON; a falsy answer other than None stops the run. A run
/// that stops on a solver failure or at the callback's word returns its history with `error`
/// set; an exception in the
/// callback or a signal is raised.
#[pyfunction]
#[pyo3(signature = (scene, steps = None, on_increment = None))]
pub fn solve(
    py: Python<'_>,
    scene: &PyScene,
    steps: Option<usize>,
    on_increment: Option<Py<PyAny>>,
) -> PyResult<PyHistory> {
    let sc = &scene.scene;
    let mut solver = sc
        .solver()
        .map_err(|e| crate::SolveError::new_err(format!("{}: {e}", sc.file.name)))?;
    let header = History::of_model(
        &sc.file.name,
        &sc.model,
        Some(sc.model.formulation),
        Some(sc.params),
    );
    let mut relay = Relay {
        history: header,
        callback: on_increment,
        error: None,
        stopped: false,
    };
    let steps = steps.unwrap_or(sc.steps);
    let failure = py.detach(|| {
        for _ in 0..steps {
            match solver.step(&mut relay) {
                Err(SolveError::Stopped) => return None,
                Err(e) => return Some(e.to_string()),
                Ok(_) if relay.error.is_some() || relay.stopped => return None,
                Ok(_) => {}
            }
        }
        None
    });
    if let Some(e) = relay.error.take() {
        return Err(e);
    }
    relay.history.error = failure.or_else(|| {
        relay.stopped.then(|| {
            let last = relay.history.increments.last().map_or(0, |r| r.increment);
            format!("stopped by on_increment after increment {last}")
        })
    });
    Ok(PyHistory {
        history: relay.history,
    })
}
