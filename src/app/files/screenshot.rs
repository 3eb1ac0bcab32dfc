//! Screenshots: the `view --screenshot` sequence (wait for the scene and the requested steps,
//! let the layout settle, request the frame, save the PNG and its `.json` sidecar, close) and
//! "Save window image" in the Export menu.

use std::path::PathBuf;
use std::sync::atomic::{AtomicI32, Ordering};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use egui::{ColorImage, Rect};
use serde::Serialize;

use super::export::save_png;
use crate::app::view::View;

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

/// Where the last frame drew the viewport and the convergence plot (points), filled in by
/// `viewport::show` and `plots::show`.
#[derive(Clone, Copy, Debug, Default)]
pub struct Layout {
    /// The viewport's rect.
    pub viewport: Option<Rect>,
    /// The camera it was drawn with.
    pub view: View,
    /// The increment it showed.
    pub increment: usize,
    /// The data area of the convergence plot.
    pub plot: Option<Rect>,
}

/// A rect in image pixels: `min` and `max` corners as `[x, y]`, y down.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct PixelRect {
    /// Top-left corner.
    pub min: [f32; 2],
    /// Bottom-right corner.
    pub max: [f32; 2],
}

impl PixelRect {
    fn new(r: Rect, ppp: f32) -> PixelRect {
        PixelRect {
            min: [r.min.x * ppp, r.min.y * ppp],
            max: [r.max.x * ppp, r.max.y * ppp],
        }
    }
}

/// The `OUT.png.json` sidecar of `view --screenshot OUT.png`: how to find solver coordinates in
/// the image. World point (x, y) in metres is drawn at pixel
/// `(origin_px[0] + scale_px_per_m * x, origin_px[1] - scale_px_per_m * y)`.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct Sidecar {
    /// Image size `[width, height]` (px).
    pub image_size: [usize; 2],
    /// Physical pixels per egui point.
    pub pixels_per_point: f32,
    /// The viewport's rect.
    pub viewport: Option<PixelRect>,
    /// Pixels per metre.
    pub scale_px_per_m: f64,
    /// Pixel position of the world origin.
    pub origin_px: [f64; 2],
    /// The increment shown.
    pub increment: usize,
    /// The data area of the convergence plot.
    pub convergence_plot: Option<PixelRect>,
}

impl Sidecar {
    /// The sidecar of an image of `size` pixels drawn with `layout` at `ppp` pixels per point.
    pub fn new(layout: &Layout, ppp: f32, size: [usize; 2]) -> Sidecar {
        let v = layout.view;
        let c = layout.viewport.map_or(egui::Pos2::ZERO, |r| r.center());
        let ppp64 = f64::from(ppp);
        Sidecar {
            image_size: size,
            pixels_per_point: ppp,
            viewport: layout.viewport.map(|r| PixelRect::new(r, ppp)),
            scale_px_per_m: v.scale * ppp64,
            origin_px: [
                (f64::from(c.x) - v.center[0] * v.scale) * ppp64,
                (f64::from(c.y) + v.center[1] * v.scale) * ppp64,
            ],
            increment: layout.increment,
            convergence_plot: layout.plot.map(|r| PixelRect::new(r, ppp)),
        }
    }
}

/// Write the sidecar of the PNG at `png` to `png` + ".json".
fn save_sidecar(png: &std::path::Path, sidecar: &Sidecar) -> Result<(), String> {
    let mut path = png.as_os_str().to_owned();
    path.push(".json");
    let text = serde_json::to_string_pretty(sidecar).map_err(|e| e.to_string())?;
    crate::history::write_atomic(std::path::Path::new(&path), text.as_bytes())
        .map_err(|e| e.to_string())
}

/// A pending screenshot.
pub struct Shot {
    path: PathBuf,
    exit: Option<Arc<AtomicI32>>,
    close: bool,
    /// Current phase.
    pub phase: Phase,
    slot: Arc<Mutex<Option<Arc<ColorImage>>>>,
    /// Layout and pixels per point of the frame that was captured.
    layout: Option<(Layout, f32)>,
    started: Instant,
    /// Why the run did not do its job (the scene did not load), if it did not: the picture is
    /// still taken, and the run exits with status 1.
    failure: Option<String>,
}

impl Shot {
    /// The run did not do its job: `why` is printed and the exit status is 1, after the
    /// picture (which shows the error) is taken.
    pub fn fail(&mut self, why: &str) {
        self.record_failure(why);
        self.phase = Phase::Settle(3);
    }

    /// Note that the run did not do its job (the solve stopped on an error), and go on.
    pub fn record_failure(&mut self, why: &str) {
        self.failure.get_or_insert_with(|| why.to_string());
    }

    /// A screenshot to `path`; `close` ends the app afterwards (the `--screenshot` run).
    pub fn new(path: PathBuf, exit: Option<Arc<AtomicI32>>, close: bool) -> Shot {
        let phase = if close { Phase::Load } else { Phase::Settle(1) };
        Shot {
            path,
            exit,
            close,
            phase,
            slot: Arc::default(),
            layout: None,
            started: Instant::now(),
            failure: None,
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

    /// Advance the sequence by one frame; `layout` is where this frame drew things.
    pub fn frame(&mut self, ctx: &egui::Context, layout: &Layout) {
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
                self.layout = Some((*layout, ctx.pixels_per_point()));
                self.phase = Phase::Waiting;
            }
            Phase::Settle(n) => self.phase = Phase::Settle(n - 1),
            Phase::Waiting => {
                let img = self.slot.lock().expect("screenshot slot").take();
                if let Some(img) = img {
                    let mut saved = save_png(&self.path, &img);
                    if let (true, Ok(()), Some((layout, ppp))) = (self.close, &saved, &self.layout)
                    {
                        saved = save_sidecar(&self.path, &Sidecar::new(layout, *ppp, img.size));
                    }
                    let code = match saved {
                        Ok(()) => {
                            eprintln!(
                                "saved {} ({}x{})",
                                self.path.display(),
                                img.size[0],
                                img.size[1]
                            );
                            match &self.failure {
                                Some(why) => {
                                    eprintln!("error: {why}");
                                    1
                                }
                                None => 0,
                            }
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

/// Exit code holder for the screenshot run.
pub(crate) fn set_exit(exit: &Option<Arc<AtomicI32>>, code: i32) {
    if let Some(e) = exit {
        e.store(code, Ordering::SeqCst);
    }
}
