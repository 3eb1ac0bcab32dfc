//! Screenshots: the `view --screenshot` sequence (wait for the scene and the requested steps,
//! let the layout settle, request the frame, save the PNG, close) and the "Save PNG" button.

use std::path::PathBuf;
use std::sync::atomic::AtomicI32;
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use egui::ColorImage;

use super::export::save_png;
use super::state::set_exit;

/// Longest a screenshot run may take before it gives up.
const TIMEOUT: Duration = Duration::from_secs(600);

/// Where a screenshot is in its sequence.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Phase {
    /// Waiting for the worker to load the scene.
    Load,
    /// Waiting for the requested steps (true once the worker reported it started).
    Solving(bool),
    /// Frames left to draw before the shot.
    Settle(u32),
    /// The shot was requested; waiting for the pixels.
    Waiting,
    /// Saved (or failed).
    Done,
}

/// A pending screenshot.
pub struct Shot {
    path: PathBuf,
    exit: Option<Arc<AtomicI32>>,
    close: bool,
    /// Current phase.
    pub phase: Phase,
    slot: Arc<Mutex<Option<Arc<ColorImage>>>>,
    started: Instant,
}

impl Shot {
    /// A screenshot to `path`; `close` ends the app afterwards (the `--screenshot` run).
    pub fn new(path: PathBuf, exit: Option<Arc<AtomicI32>>, close: bool) -> Shot {
        let phase = if close { Phase::Load } else { Phase::Settle(1) };
        Shot {
            path,
            exit,
            close,
            phase,
            slot: Arc::default(),
            started: Instant::now(),
        }
    }

    /// The scene was loaded; `solving` if steps were requested.
    pub fn loaded(&mut self, solving: bool) {
        if self.phase == Phase::Load {
            self.phase = if solving {
                Phase::Solving(false)
            } else {
                Phase::Settle(3)
            };
        }
    }

    /// The worker started solving.
    pub fn started(&mut self) {
        if self.phase == Phase::Solving(false) {
            self.phase = Phase::Solving(true);
        }
    }

    /// The worker went idle; true if that ends the solving phase.
    pub fn idle(&mut self) -> bool {
        if matches!(self.phase, Phase::Solving(true)) {
            self.phase = Phase::Settle(3);
            return true;
        }
        false
    }

    /// Whether the sequence is over.
    pub fn finished(&self) -> bool {
        self.phase == Phase::Done
    }

    /// Advance the sequence by one frame.
    pub fn frame(&mut self, ctx: &egui::Context) {
        if self.close && self.started.elapsed() > TIMEOUT {
            eprintln!("error: screenshot timed out");
            set_exit(&self.exit, 1);
            self.phase = Phase::Done;
            ctx.send_viewport_cmd(egui::ViewportCommand::Close);
            return;
        }
        match self.phase {
            Phase::Settle(0) => {
                let slot = self.slot.clone();
                let c = ctx.clone();
                ctx.request_screenshot(move |img| {
                    *slot.lock().expect("screenshot slot") = Some(img);
                    c.request_repaint();
                });
                self.phase = Phase::Waiting;
            }
            Phase::Settle(n) => self.phase = Phase::Settle(n - 1),
            Phase::Waiting => {
                let img = self.slot.lock().expect("screenshot slot").take();
                if let Some(img) = img {
                    let code = match save_png(&self.path, &img) {
                        Ok(()) => {
                            eprintln!(
                                "saved {} ({}x{})",
                                self.path.display(),
                                img.size[0],
                                img.size[1]
                            );
                            0
                        }
                        Err(e) => {
                            eprintln!("error: cannot write {}: {e}", self.path.display());
                            1
                        }
                    };
                    set_exit(&self.exit, code);
                    self.phase = Phase::Done;
                    if self.close {
                        ctx.send_viewport_cmd(egui::ViewportCommand::Close);
                    }
                    return;
                }
            }
            Phase::Load | Phase::Solving(_) | Phase::Done => {}
        }
        ctx.request_repaint_after(Duration::from_millis(10));
    }
}
