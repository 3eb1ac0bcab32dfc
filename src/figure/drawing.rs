//! The viewed state as a figure for papers, independent of the window: the rigid obstacles, the
//! undeformed shape as a grey ghost, each body's deformed curve (the curve the viewport draws), the force
//! diagram if one is chosen, pins as open circles and contact nodes as red dots, all in world
//! coordinates. `svg.rs` writes it as SVG; `raster.rs` draws it as a PNG of any size.

use super::geometry::{
    chord_frame, deformed_bodies, faces, half_thickness, moment_at, obstacle_outlines,
    transverse_load, undeformed_bodies,
};
use crate::solver::{IncrementRecord, Model};
use crate::worker::Loaded;

/// Which diagram is drawn.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Diagram {
    /// Axial force (tension positive).
    Axial,
    /// Shear force.
    Shear,
    /// Bending moment.
    Moment,
}

impl Diagram {
    /// Every diagram, in the order the picker lists them.
    pub const ALL: [Diagram; 3] = [Diagram::Axial, Diagram::Shear, Diagram::Moment];

    /// Its letter ("N", "V", "M").
    pub fn letter(self) -> &'static str {
        match self {
            Diagram::Axial => "N",
            Diagram::Shear => "V",
            Diagram::Moment => "M",
        }
    }
}

/// Samples per element of a diagram.
const DIAGRAM_SAMPLES: usize = 8;

/// The share of the figure's larger side the largest diagram value spans.
const DIAGRAM_REACH: f64 = 0.06;

/// What a line of the figure is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    /// The undeformed shape.
    Ghost,
    /// A body's deformed curve.
    Body,
    /// A force diagram's outline.
    Diagram,
    /// A rigid obstacle's outline.
    Obstacle,
    /// A face of a body with a thickness, half of it from the axis.
    Face,
}

impl Kind {
    /// Colour (RGB) and width (px at 1200 px across).
    pub fn style(self) -> ([u8; 3], f64) {
        match self {
            Kind::Ghost => ([175, 178, 186], 1.5),
            Kind::Body => ([0, 0, 0], 2.0),
            Kind::Diagram => ([40, 90, 200], 1.2),
            Kind::Obstacle => ([90, 90, 96], 3.0),
            Kind::Face => ([120, 124, 134], 1.0),
        }
    }
}

/// A polyline of the figure.
#[derive(Clone, Debug)]
pub struct Line {
    /// What it is.
    pub kind: Kind,
    /// Its name (a body's name for a body's curve).
    pub name: String,
    /// Points in world coordinates.
    pub points: Vec<[f64; 2]>,
}

/// A node marked in the figure.
#[derive(Clone, Debug)]
pub struct Dot {
    /// The node's id.
    pub node: u32,
    /// Where (world coordinates).
    pub at: [f64; 2],
    /// In contact (red, filled) or a pin (white, open).
    pub contact: bool,
}

/// The figure of one increment.
#[derive(Clone, Debug, Default)]
pub struct Figure {
    /// The lines: obstacles, ghost, bodies, then diagrams.
    pub lines: Vec<Line>,
    /// The marked nodes.
    pub dots: Vec<Dot>,
}

/// Maps world coordinates into an image of `width` x `height` pixels, y down, the figure
/// centred and fitted with a margin of 5% of its larger side.
#[derive(Clone, Copy, Debug)]
pub struct Frame {
    /// Pixels per world unit.
    pub scale: f64,
    /// World point at the image centre.
    pub center: [f64; 2],
    /// Image size (px).
    pub size: [f64; 2],
}

impl Frame {
    /// The pixel position of world point `p`.
    pub fn px(&self, p: [f64; 2]) -> [f64; 2] {
        [
            self.size[0] / 2.0 + (p[0] - self.center[0]) * self.scale,
            self.size[1] / 2.0 - (p[1] - self.center[1]) * self.scale,
        ]
    }
}

impl Figure {
    /// World bounds `[xmin, ymin, xmax, ymax]` of everything drawn.
    pub fn bounds(&self) -> [f64; 4] {
        let mut b = [f64::MAX, f64::MAX, f64::MIN, f64::MIN];
        let points = self.lines.iter().flat_map(|l| l.points.iter());
        for p in points.chain(self.dots.iter().map(|d| &d.at)) {
            b = [
                b[0].min(p[0]),
                b[1].min(p[1]),
                b[2].max(p[0]),
                b[3].max(p[1]),
            ];
        }
        b
    }

    /// The frame that fits the figure into `width` x `height` pixels (`height` 0: as tall as
    /// the figure needs at that width).
    pub fn frame(&self, width: f64, height: f64) -> Frame {
        let b = self.bounds();
        let span = (b[2] - b[0]).max(b[3] - b[1]).max(1e-300);
        let margin = 0.05 * span;
        let (w, h) = (b[2] - b[0] + 2.0 * margin, b[3] - b[1] + 2.0 * margin);
        let scale = if height > 0.0 {
            (width / w).min(height / h)
        } else {
            width / w
        };
        let height = if height > 0.0 { height } else { h * scale };
        Frame {
            scale,
            center: [(b[0] + b[2]) / 2.0, (b[1] + b[3]) / 2.0],
            size: [width, height],
        }
    }
}

/// The figure of record `r` of a loaded scene, with `diagram` drawn if given.
pub fn figure(loaded: &Loaded, r: &IncrementRecord, diagram: Option<Diagram>) -> Figure {
    let model = &loaded.scene.model;
    let mut f = Figure::default();
    for points in obstacle_outlines(model, r) {
        f.lines.push(Line {
            kind: Kind::Obstacle,
            name: String::new(),
            points,
        });
    }
    for points in undeformed_bodies(model) {
        f.lines.push(Line {
            kind: Kind::Ghost,
            name: String::new(),
            points,
        });
    }
    for c in deformed_bodies(model, &loaded.elements, r) {
        let sides = faces(&c.points, half_thickness(model, c.body));
        for side in 0..2 {
            if !sides.is_empty() {
                f.lines.push(Line {
                    kind: Kind::Face,
                    name: String::new(),
                    points: sides.iter().map(|s| s[side]).collect(),
                });
            }
        }
        f.lines.push(Line {
            kind: Kind::Body,
            name: model.bodies[c.body].name.clone(),
            points: c.points,
        });
    }
    for (n, node) in model.nodes.iter().enumerate().filter(|(_, n)| !n.rotation) {
        f.dots.push(Dot {
            node: node.id,
            at: [r.nodes[n][0], r.nodes[n][1]],
            contact: false,
        });
    }
    let touching =
        (r.contacts.iter().map(|c| c.node)).chain(r.obstacle_contacts.iter().map(|c| c.node));
    for id in touching {
        if let Some(n) = model.nodes.iter().position(|x| x.id == id) {
            f.dots.push(Dot {
                node: id,
                at: [r.nodes[n][0], r.nodes[n][1]],
                contact: true,
            });
        }
    }
    if let Some(d) = diagram {
        let b = f.bounds();
        let reach = DIAGRAM_REACH * (b[2] - b[0]).max(b[3] - b[1]);
        f.lines.extend(diagram_lines(model, r, d, reach));
    }
    f
}

/// The outline of `diagram` along every element's chord, off it by the value scaled so that
/// the largest spans `reach` (positive to the chord's left).
fn diagram_lines(model: &Model, r: &IncrementRecord, d: Diagram, reach: f64) -> Vec<Line> {
    let values: Vec<Vec<f64>> = (0..model.beams.len())
        .map(|e| {
            (0..=DIAGRAM_SAMPLES)
                .map(|k| value_at(model, r, d, e, k as f64 / DIAGRAM_SAMPLES as f64))
                .collect()
        })
        .collect();
    let largest = values.iter().flatten().fold(0.0f64, |m, v| m.max(v.abs()));
    if largest == 0.0 || !largest.is_finite() {
        return Vec::new();
    }
    let s = reach / largest;
    let mut out = Vec::new();
    for (e, beam) in model.beams.iter().enumerate() {
        let (a, b) = (r.nodes[beam.i], r.nodes[beam.j]);
        let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
        let Some((_, n, _)) = chord_frame(model, r, e) else {
            continue;
        };
        let mut points = vec![[a[0], a[1]]];
        for (k, v) in values[e].iter().enumerate() {
            let x = k as f64 / DIAGRAM_SAMPLES as f64;
            let p = [a[0] + x * dx, a[1] + x * dy];
            points.push([p[0] + s * v * n[0], p[1] + s * v * n[1]]);
        }
        points.push([b[0], b[1]]);
        out.push(Line {
            kind: Kind::Diagram,
            name: format!("{} {}", d.letter(), model.element_label(e)),
            points,
        });
    }
    out
}

/// The value of `diagram` at fraction `x` along element `e`.
pub fn value_at(model: &Model, r: &IncrementRecord, diagram: Diagram, e: usize, x: f64) -> f64 {
    let f = r.element_forces.get(e).copied().unwrap_or([0.0; 3]);
    match diagram {
        Diagram::Axial => f[0],
        Diagram::Moment => moment_at(model, r, e, x),
        Diagram::Shear => {
            // dM/ds of `moment_at`: the end moments' share, and each contact force's jump.
            let l = model.beam_length(e);
            let mut v = -(f[1] + f[2]) / l;
            for c in r.contacts.iter().filter(|c| c.element == e) {
                let a = c.xi.clamp(0.0, 1.0);
                v += c.force * if x < a { 1.0 - a } else { -a };
            }
            if let Some([pi, pj]) = transverse_load(model, r, e) {
                v += l * ((2.0 * pi + pj) / 6.0 - pi * x - (pj - pi) * x * x / 2.0);
            }
            v
        }
    }
}
