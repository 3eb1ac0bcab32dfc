//! The viewport's 2-D camera: world metres to screen points and back, pan, zoom about a point
//! and fit-to-bounds. Persisted between runs of the app.

use egui::{Pos2, Rect, Vec2};
use serde::{Deserialize, Serialize};

use crate::solver::{Dof, IncrementRecord, Model};

/// World-to-screen mapping: `center` (m) sits at the middle of the viewport, `scale` points per
/// metre, y up.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct View {
    /// World point at the centre of the viewport (m).
    pub center: [f64; 2],
    /// Screen points per metre.
    pub scale: f64,
}

impl Default for View {
    fn default() -> Self {
        View {
            center: [0.5, -0.2],
            scale: 500.0,
        }
    }
}

impl View {
    /// Screen position of a world point in viewport `rect`.
    pub fn to_screen(&self, rect: Rect, p: [f64; 2]) -> Pos2 {
        let c = rect.center();
        Pos2::new(
            c.x + ((p[0] - self.center[0]) * self.scale) as f32,
            c.y - ((p[1] - self.center[1]) * self.scale) as f32,
        )
    }

    /// World point under a screen position in viewport `rect`.
    pub fn to_world(&self, rect: Rect, s: Pos2) -> [f64; 2] {
        let c = rect.center();
        [
            self.center[0] + f64::from(s.x - c.x) / self.scale,
            self.center[1] - f64::from(s.y - c.y) / self.scale,
        ]
    }

    /// Move the view with the pointer by a screen drag `delta`.
    pub fn pan(&mut self, delta: Vec2) {
        self.center[0] -= f64::from(delta.x) / self.scale;
        self.center[1] += f64::from(delta.y) / self.scale;
    }

    /// Zoom by `factor`, keeping the world point under `anchor` fixed.
    pub fn zoom_at(&mut self, rect: Rect, anchor: Pos2, factor: f64) {
        let before = self.to_world(rect, anchor);
        self.scale = (self.scale * factor).clamp(1e-3, 1e9);
        let after = self.to_world(rect, anchor);
        self.center[0] += before[0] - after[0];
        self.center[1] += before[1] - after[1];
    }

    /// Fit world bounds `[xmin, ymin, xmax, ymax]` into `rect` with a margin.
    pub fn fit(&mut self, rect: Rect, b: [f64; 4]) {
        if !b.iter().all(|v| v.is_finite()) || rect.width() < 1.0 || rect.height() < 1.0 {
            return;
        }
        let w = (b[2] - b[0]).max(1e-9);
        let h = (b[3] - b[1]).max(1e-9);
        let sx = f64::from(rect.width()) * 0.86 / w;
        let sy = f64::from(rect.height()) * 0.80 / h;
        self.scale = sx.min(sy);
        self.center = [(b[0] + b[2]) / 2.0, (b[1] + b[3]) / 2.0];
    }
}

/// Bounds `[xmin, ymin, xmax, ymax]` of a set of points (NaN-free; infinite if empty).
pub fn bounds<'a>(points: impl IntoIterator<Item = &'a [f64; 3]>) -> [f64; 4] {
    let mut b = [
        f64::INFINITY,
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::NEG_INFINITY,
    ];
    for p in points {
        b[0] = b[0].min(p[0]);
        b[1] = b[1].min(p[1]);
        b[2] = b[2].max(p[0]);
        b[3] = b[3].max(p[1]);
    }
    b
}

/// A drag of a prescribed-dof handle in progress.
#[derive(Clone, Copy, Debug)]
pub struct Drag {
    /// Which prescribed dof.
    pub index: usize,
    /// The dof's target when the drag started.
    pub start: f64,
    /// Pointer motion so far (screen points).
    pub moved: egui::Vec2,
}

/// World position of the handle of prescribed dof `k` (initial position plus the target).
pub(crate) fn handle_world(
    model: &Model,
    r: &IncrementRecord,
    k: usize,
    target: f64,
) -> Option<[f64; 2]> {
    let p = model.prescribed.get(k)?;
    let n = p.node;
    let cur = [r.nodes[n][0], r.nodes[n][1]];
    match p.dof {
        Dof::U => Some([model.nodes[n].x + target, cur[1]]),
        Dof::V => Some([cur[0], model.nodes[n].y + target]),
        Dof::Phi => None,
    }
}
