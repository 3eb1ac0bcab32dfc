//! Tessellation of screen-space polylines into strips of constant on-screen width with mitred
//! joints: as GPU vertices (distance across the strip as a varying, for a soft edge in the
//! fragment shader) or as a feathered `egui::Mesh` (the fallback when wgpu is unavailable).

use bytemuck::{Pod, Zeroable};
use egui::epaint::{Mesh, Vertex, WHITE_UV};
use egui::{Color32, Pos2, Vec2};

/// A strip vertex for `shaders/beams.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct StripVertex {
    /// Position in screen points.
    pub pos: [f32; 2],
    /// sRGB colour (gamma space, not premultiplied), 0..1.
    pub color: [f32; 4],
    /// (signed distance from the centre line, half width), both in physical pixels.
    pub edge: [f32; 2],
}

/// A polyline in screen points with a colour per point.
#[derive(Clone, Debug, Default)]
pub struct Polyline {
    /// Points (screen points).
    pub points: Vec<Pos2>,
    /// Colour at each point.
    pub colors: Vec<Color32>,
}

impl Polyline {
    /// A polyline of one colour.
    pub fn uniform(points: Vec<Pos2>, color: Color32) -> Polyline {
        let colors = vec![color; points.len()];
        Polyline { points, colors }
    }

    /// Drop points closer than a hundredth of a point to their predecessor.
    fn cleaned(&self) -> (Vec<Pos2>, Vec<Color32>) {
        let mut p: Vec<Pos2> = Vec::with_capacity(self.points.len());
        let mut c = Vec::with_capacity(self.points.len());
        for (q, col) in self.points.iter().zip(&self.colors) {
            if !(q.x.is_finite() && q.y.is_finite()) {
                continue;
            }
            if p.last().is_none_or(|l: &Pos2| l.distance(*q) > 0.01) {
                p.push(*q);
                c.push(*col);
            }
        }
        (p, c)
    }
}

/// Unit-normal miter offsets (length >= 1, capped) at every point of a polyline.
fn miters(p: &[Pos2]) -> Vec<Vec2> {
    let n = p.len();
    let normal = |a: Pos2, b: Pos2| {
        let d = (b - a).normalized();
        Vec2::new(-d.y, d.x)
    };
    (0..n)
        .map(|k| {
            let n0 = if k > 0 {
                normal(p[k - 1], p[k])
            } else {
                normal(p[0], p[1])
            };
            let n1 = if k + 1 < n {
                normal(p[k], p[k + 1])
            } else {
                n0
            };
            let m = (n0 + n1).normalized();
            let cos = m.dot(n0).max(0.34);
            if m.x.is_finite() {
                m / cos
            } else {
                n0
            }
        })
        .collect()
}

fn rgba(c: Color32) -> [f32; 4] {
    let [r, g, b, a] = c.to_srgba_unmultiplied();
    [
        r as f32 / 255.0,
        g as f32 / 255.0,
        b as f32 / 255.0,
        a as f32 / 255.0,
    ]
}

/// Append the strip of `line` (half width `half_px` pixels, at `ppp` pixels per point) as a
/// triangle list, widened by one pixel each side for the shader's soft edge.
pub fn push_gpu_strip(line: &Polyline, half_px: f32, ppp: f32, out: &mut Vec<StripVertex>) {
    let (p, c) = line.cleaned();
    if p.len() < 2 {
        return;
    }
    let m = miters(&p);
    let reach = half_px + 1.0;
    let side = |k: usize, s: f32| StripVertex {
        pos: (p[k] + m[k] * (s * reach / ppp)).into(),
        color: rgba(c[k]),
        edge: [s * reach, half_px],
    };
    for k in 0..p.len() - 1 {
        let (l0, r0, l1, r1) = (
            side(k, 1.0),
            side(k, -1.0),
            side(k + 1, 1.0),
            side(k + 1, -1.0),
        );
        out.extend_from_slice(&[l0, r0, l1, r0, r1, l1]);
    }
}

/// Append the strip of `line` to an egui mesh with a one-pixel feathered edge (same look as the
/// GPU path, drawn by egui's own renderer).
pub fn push_mesh_strip(line: &Polyline, half_px: f32, ppp: f32, mesh: &mut Mesh) {
    let (p, c) = line.cleaned();
    if p.len() < 2 {
        return;
    }
    let m = miters(&p);
    let inner = (half_px - 0.5).max(0.25) / ppp;
    let outer = (half_px + 0.5) / ppp;
    let base = mesh.vertices.len() as u32;
    for k in 0..p.len() {
        let solid = c[k];
        let clear = Color32::TRANSPARENT;
        for (off, col) in [
            (outer, clear),
            (inner, solid),
            (-inner, solid),
            (-outer, clear),
        ] {
            mesh.vertices.push(Vertex {
                pos: p[k] + m[k] * off,
                uv: WHITE_UV,
                color: col,
            });
        }
    }
    for k in 0..p.len() as u32 - 1 {
        let a = base + 4 * k;
        let b = a + 4;
        for s in 0..3 {
            mesh.add_triangle(a + s, a + s + 1, b + s);
            mesh.add_triangle(a + s + 1, b + s + 1, b + s);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn strip_has_constant_width_and_soft_edge() {
        let line = Polyline::uniform(
            vec![
                Pos2::new(0.0, 0.0),
                Pos2::new(10.0, 0.0),
                Pos2::new(20.0, 0.0),
            ],
            Color32::RED,
        );
        let mut v = Vec::new();
        push_gpu_strip(&line, 3.0, 2.0, &mut v);
        assert_eq!(v.len(), 12);
        for p in &v {
            // 3 px + 1 px feather at 2 px per point: 2 points from the centre line.
            assert!((p.pos[1].abs() - 2.0).abs() < 1e-6);
            assert_eq!(p.edge[0].abs(), 4.0);
            assert_eq!(p.edge[1], 3.0);
        }
        let mut mesh = Mesh::default();
        push_mesh_strip(&line, 3.0, 2.0, &mut mesh);
        assert_eq!(mesh.vertices.len(), 12);
        assert_eq!(mesh.indices.len(), 2 * 3 * 2 * 3);
    }
}
