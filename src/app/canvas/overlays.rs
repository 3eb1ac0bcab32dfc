//! The viewport's egui overlays (egui's own feathering): clamps, pins and rollers (a pin with a
//! radius with its rim, a solid arc's centre with the rim of its arc), contact nodes with force
//! arrows scaled by Yc (and their friction, coloured by stick or slip), body names, the handle
//! of each prescribed dof, and the nodal and the distributed loads. The legend and the scale
//! bar are `legend.rs`'s.

use egui::{Align2, Color32, FontId, Pos2, Rect, Shape, Stroke, Vec2};

use crate::scene::units::Units;
use crate::solver::{Dof, Friction, IncrementRecord, Model};

use crate::app::display::num;
use crate::app::parts::{Look, Study};
use crate::app::view::handle_world;

/// Lines and text.
pub const INK: Color32 = Color32::from_rgb(40, 44, 52);
pub(crate) const ACTIVE: Color32 = Color32::from_rgb(245, 130, 20);
const HANDLE: Color32 = Color32::from_rgb(20, 150, 90);
/// A frictional contact that sticks.
pub(crate) const STICK: Color32 = Color32::from_rgb(30, 110, 220);
/// A frictional contact that slips.
pub(crate) const SLIP: Color32 = Color32::from_rgb(215, 35, 60);

/// Clamps at nodes with u, v and phi held; small triangles at other supported nodes.
pub(crate) fn supports(
    p: &egui::Painter,
    model: &Model,
    r: &IncrementRecord,
    s: &dyn Fn([f64; 2]) -> Pos2,
) {
    for n in 0..model.nodes.len() {
        let held: Vec<Dof> = model
            .supports
            .iter()
            .filter(|x| x.node == n)
            .map(|x| x.dof)
            .collect();
        // A driven node shows its handle instead.
        if held.is_empty() || model.prescribed.iter().any(|p| p.node == n) {
            continue;
        }
        let at = s([r.nodes[n][0], r.nodes[n][1]]);
        let clamp = held.contains(&Dof::U)
            && held.contains(&Dof::V)
            && (held.contains(&Dof::Phi) || !model.nodes[n].rotation);
        if clamp && model.nodes[n].rotation {
            // Direction into the beam, on screen.
            let into = model
                .beams
                .iter()
                .find_map(|b| {
                    let other = if b.i == n {
                        b.j
                    } else if b.j == n {
                        b.i
                    } else {
                        return None;
                    };
                    // A clamp does not turn: its side follows the undeformed beam.
                    Some((s(model.position(other)) - s(model.position(n))).normalized())
                })
                .unwrap_or(Vec2::X);
            let across = Vec2::new(-into.y, into.x);
            let half = 16.0;
            p.line_segment(
                [at - across * half, at + across * half],
                Stroke::new(3.0, INK),
            );
            for k in 0..6 {
                let o = at + across * (-half + 6.4 * k as f32 + 2.0);
                p.line_segment([o, o - into * 7.0 - across * 6.0], Stroke::new(1.2, INK));
            }
        } else {
            pin_or_roller(p, at, &held);
        }
    }
}

/// A pin (u and v held) as a triangle under the node; a roller (one translation held) as a
/// triangle on two wheels, on the side the held direction pushes from (under the node for v,
/// left of it for u); a held rotation alone as a small square.
fn pin_or_roller(p: &egui::Painter, at: Pos2, held: &[Dof]) {
    let (u, v) = (held.contains(&Dof::U), held.contains(&Dof::V));
    if !u && !v {
        let r = Rect::from_center_size(at, Vec2::splat(9.0));
        p.rect_stroke(r, 0.0, Stroke::new(1.5, INK), egui::StrokeKind::Middle);
        return;
    }
    // Into the support, on screen: down for a v support, left for a u-only one.
    let down = if v {
        Vec2::new(0.0, 1.0)
    } else {
        Vec2::new(-1.0, 0.0)
    };
    let across = Vec2::new(-down.y, down.x);
    let tri = vec![
        at,
        at + down * 12.0 - across * 7.0,
        at + down * 12.0 + across * 7.0,
    ];
    p.add(Shape::convex_polygon(
        tri,
        Color32::from_gray(235),
        Stroke::new(1.2, INK),
    ));
    if u != v {
        for side in [-3.5, 3.5] {
            p.circle_stroke(at + down * 15.5 + across * side, 2.5, Stroke::new(1.2, INK));
        }
    }
}

/// Candidate contact nodes as small dots; active contacts as discs with the force arrow.
pub(crate) fn contacts(
    p: &egui::Painter,
    model: &Model,
    r: &IncrementRecord,
    s: &dyn Fn([f64; 2]) -> Pos2,
) {
    for pair in &model.contacts {
        for &n in &pair.nodes {
            let at = s([r.nodes[n][0], r.nodes[n][1]]);
            if model.nodes[n].rotation {
                p.circle_filled(at, 1.8, INK);
            }
        }
    }
    // Pins (nodes without rotation) drawn as discs, a pin with a radius with its rim.
    for (n, node) in model.nodes.iter().enumerate() {
        if !node.rotation {
            let x = [r.nodes[n][0], r.nodes[n][1]];
            let at = s(x);
            match (node.clearance > 0.0, node.reach) {
                (false, _) => {}
                (true, None) => {
                    let rim = (s([x[0] + node.clearance, x[1]]) - at).length();
                    p.circle_stroke(at, rim, Stroke::new(1.5, INK));
                }
                // A solid arc's centre: its rim only over the arc.
                (true, Some(reach)) => {
                    let span = (reach.to - reach.from).rem_euclid(std::f64::consts::TAU);
                    let rim: Vec<Pos2> = (0..=48)
                        .map(|k| {
                            let a = reach.from + span * k as f64 / 48.0;
                            let r = node.clearance;
                            s([x[0] + r * a.cos(), x[1] + r * a.sin()])
                        })
                        .collect();
                    p.add(Shape::line(rim, Stroke::new(1.5, INK)));
                }
            }
            p.circle(at, 5.5, INK, Stroke::new(1.5, Color32::WHITE));
        }
    }
    let fmax = r
        .contacts
        .iter()
        .fold(1e-30f64, |a, c| a.max(c.force.abs()));
    // Labels are placed largest force first and skipped where they would overlap one already
    // placed (the comb's 50 contacts side by side).
    let mut order: Vec<&crate::solver::report::ContactState> = r.contacts.iter().collect();
    order.sort_by(|a, b| b.force.abs().total_cmp(&a.force.abs()));
    let mut placed: Vec<Rect> = Vec::new();
    for c in order {
        let Some(n) = model.nodes.iter().position(|x| x.id == c.node) else {
            continue;
        };
        let Some(b) = model.beams.get(c.element) else {
            continue;
        };
        let at = s([r.nodes[n][0], r.nodes[n][1]]);
        let (pi, pj) = (
            s([r.nodes[b.i][0], r.nodes[b.i][1]]),
            s([r.nodes[b.j][0], r.nodes[b.j][1]]),
        );
        let chord = (pj - pi).normalized();
        // Force of the node on the beam: along the chord normal turned by the surface's turn
        // (counter-clockwise on the page, clockwise on the screen, whose y points down), of
        // size Yc / cos(turn).
        let (sin, cos) = (c.turn as f32).sin_cos();
        let normal = Vec2::new(
            chord.y * cos - chord.x * sin,
            -chord.y * sin - chord.x * cos,
        );
        let dir = normal * c.force.signum() as f32;
        let size = c.force.abs() / c.turn.cos();
        let len = 14.0 + 36.0 * (size / fmax).min(1.0) as f32;
        let tail = at - dir * (len + 6.0);
        p.arrow(tail, dir * len, Stroke::new(2.5, ACTIVE));
        p.circle(at, 6.0, ACTIVE, Stroke::new(1.5, INK));
        friction_arrow(p, at, chord, (c.tangential, c.friction), fmax);
        let label = format!("{} N", num(size));
        let centre = tail - dir * 4.0;
        let rect = Rect::from_center_size(centre, Vec2::new(6.5 * label.len() as f32, 13.0));
        if placed.iter().any(|q| q.intersects(rect)) {
            continue;
        }
        placed.push(rect);
        p.text(
            centre,
            Align2::CENTER_CENTER,
            label,
            FontId::proportional(11.0),
            INK,
        );
    }
}

/// The friction force `tangential` on a contact node (at `at`) along the screen direction
/// `along`, on the scale of the normal forces (`fmax`), and a ring round the node: blue where
/// it sticks, red where it slips; nothing where it is frictionless.
pub(crate) fn friction_arrow(
    p: &egui::Painter,
    at: Pos2,
    along: Vec2,
    (tangential, friction): (f64, Friction),
    fmax: f64,
) {
    let colour = match friction {
        Friction::Frictionless => return,
        Friction::Sticking => STICK,
        Friction::Slipping => SLIP,
    };
    if tangential != 0.0 {
        let dir = along * tangential.signum() as f32;
        let len = 10.0 + 36.0 * (tangential.abs() / fmax).min(1.0) as f32;
        p.arrow(at - dir * (len + 6.0), dir * len, Stroke::new(2.5, colour));
    }
    p.circle_stroke(at, 8.5, Stroke::new(2.0, colour));
}

/// Body names beside the start of each deformed curve.
pub(crate) fn body_names(
    p: &egui::Painter,
    model: &Model,
    curves: &[crate::figure::geometry::BodyCurve],
    s: &dyn Fn([f64; 2]) -> Pos2,
) {
    let mut placed: Vec<Rect> = Vec::new();
    for c in curves {
        let Some(body) = model.bodies.get(c.body) else {
            continue;
        };
        let k = c.points.len() / 2;
        if c.points.len() >= 3 {
            // Beside the middle of the curve, off its local tangent.
            let (before, mid, after) = (s(c.points[k - 1]), s(c.points[k]), s(c.points[k + 1]));
            let off = (after - before).normalized().rot90() * -1.0;
            // Anchor the text at its side nearest the curve, so long names clear steep curves.
            let side = |v: f32| match v {
                v if v > 0.4 => egui::Align::Min,
                v if v < -0.4 => egui::Align::Max,
                _ => egui::Align::Center,
            };
            // Names that would overlap one already drawn are left out (the comb's 50 teeth).
            let galley = p.layout_no_wrap(
                body.name.clone(),
                FontId::proportional(13.0),
                Color32::from_gray(90),
            );
            let anchor = Align2([side(off.x), side(off.y)]);
            let rect = anchor.anchor_size(mid + off * 10.0, galley.size());
            if placed.iter().any(|q: &Rect| q.intersects(rect)) {
                continue;
            }
            placed.push(rect);
            p.galley(rect.min, galley, Color32::from_gray(90));
        }
    }
}

/// The handle of each prescribed dof (at its target) and the node's path from its start.
pub(crate) fn prescribed(
    p: &egui::Painter,
    study: &Study,
    look: &Look,
    model: &Model,
    r: &IncrementRecord,
    s: &dyn Fn([f64; 2]) -> Pos2,
) {
    for (k, pr) in model.prescribed.iter().enumerate() {
        let n = pr.node;
        let start = s(model.position(n));
        let now = s([r.nodes[n][0], r.nodes[n][1]]);
        p.add(Shape::dashed_line(
            &[start, now],
            Stroke::new(1.0, HANDLE),
            4.0,
            3.0,
        ));
        let Some(t) = study.targets.get(k) else {
            continue;
        };
        let Some(w) = handle_world(model, r, k, *t) else {
            continue;
        };
        let at = s(w);
        let active = look.drag.is_some_and(|d| d.index == k);
        if active {
            p.line_segment([now, at], Stroke::new(1.0, HANDLE));
        }
        p.circle_stroke(
            at,
            10.0,
            Stroke::new(if active { 3.0 } else { 2.0 }, HANDLE),
        );
        let (a, b) = if pr.dof == Dof::U {
            (Vec2::X, Vec2::Y)
        } else {
            (Vec2::Y, Vec2::X)
        };
        for sign in [-1.0f32, 1.0] {
            let tip = at + a * sign * 19.0;
            let base = at + a * sign * 13.0;
            p.add(Shape::convex_polygon(
                vec![tip, base + b * 4.5, base - b * 4.5],
                HANDLE,
                Stroke::NONE,
            ));
        }
        if active || look.hover_handle == Some(k) {
            p.text(
                at + Vec2::new(24.0, 0.0),
                Align2::LEFT_CENTER,
                num(*t),
                FontId::proportional(12.0),
                HANDLE,
            );
        }
    }
}

/// The applied loads at the viewed increment as arrows (forces) and arcs (moments), 40 points
/// for the largest force, with their values.
pub(crate) fn loads(
    p: &egui::Painter,
    model: &Model,
    r: &IncrementRecord,
    units: Units,
    s: &dyn Fn([f64; 2]) -> Pos2,
) {
    let fmax = (model.loads.iter())
        .map(|l| (l.force[0] * r.load_factor).hypot(l.force[1] * r.load_factor))
        .fold(0.0f64, f64::max);
    const LOAD: Color32 = Color32::from_rgb(120, 60, 170);
    for load in &model.loads {
        let at = s([r.nodes[load.node][0], r.nodes[load.node][1]]);
        let f = load.force.map(|v| v * r.load_factor);
        let size = f[0].hypot(f[1]);
        if size > 0.0 && fmax > 0.0 {
            // Screen y points down: the arrow ends at the node, its tail up-force.
            let dir = Vec2::new(f[0] as f32, -f[1] as f32) / size as f32;
            let len = 12.0 + 28.0 * (size / fmax) as f32;
            let tail = at - dir * len;
            p.arrow(tail, dir * (len - 2.0), Stroke::new(2.0, LOAD));
            p.text(
                tail - dir * 4.0,
                Align2::CENTER_CENTER,
                format!("{} {}", num(size), units.force()),
                FontId::proportional(11.0),
                LOAD,
            );
        }
        if f[2] != 0.0 {
            let turn = if f[2] > 0.0 { -1.0f32 } else { 1.0 };
            let pts: Vec<Pos2> = (0..=12)
                .map(|k| {
                    let a = turn * (0.3 + 0.35 * k as f32);
                    at + 14.0 * Vec2::angled(a)
                })
                .collect();
            p.add(Shape::line(pts, Stroke::new(2.0, LOAD)));
            p.text(
                at + Vec2::new(16.0, -16.0),
                Align2::LEFT_BOTTOM,
                format!("{} {}", num(f[2]), units.moment()),
                FontId::proportional(11.0),
                LOAD,
            );
        }
    }
}

/// The distributed loads at the viewed increment: arrows onto the deformed elements (at most
/// about 60 of them, evenly spread), 22 points for the largest load per length, which is
/// labelled with its value.
pub(crate) fn distributed_loads(
    p: &egui::Painter,
    model: &Model,
    r: &IncrementRecord,
    units: Units,
    s: &dyn Fn([f64; 2]) -> Pos2,
) {
    const LOAD: Color32 = Color32::from_rgb(120, 60, 170);
    // The load per length at the middle of the element, in x and y (a follower's turned from
    // its chord frame).
    let at_mid = |d: &crate::solver::DistributedLoad| {
        let q = [(d.q[0][0] + d.q[1][0]) / 2.0, (d.q[0][1] + d.q[1][1]) / 2.0];
        if !d.follower {
            return q;
        }
        let Some((t, n, _)) = crate::figure::geometry::chord_frame(model, r, d.beam) else {
            return q;
        };
        [q[0] * t[0] + q[1] * n[0], q[0] * t[1] + q[1] * n[1]]
    };
    let qmax = (model.distributed.iter())
        .map(|d| {
            let q = at_mid(d);
            (q[0] * r.load_factor).hypot(q[1] * r.load_factor)
        })
        .fold(0.0f64, f64::max);
    if qmax == 0.0 || !qmax.is_finite() {
        return;
    }
    let stride = model.distributed.len().div_ceil(60).max(1);
    let mut labelled = false;
    for d in model.distributed.iter().step_by(stride) {
        let b = &model.beams[d.beam];
        let (a, c) = (r.nodes[b.i], r.nodes[b.j]);
        let at = s([(a[0] + c[0]) / 2.0, (a[1] + c[1]) / 2.0]);
        let q = at_mid(d).map(|v| v * r.load_factor);
        let size = q[0].hypot(q[1]);
        if size == 0.0 {
            continue;
        }
        let dir = Vec2::new(q[0] as f32, -q[1] as f32) / size as f32;
        let len = 6.0 + 16.0 * (size / qmax) as f32;
        let tail = at - dir * len;
        p.arrow(tail, dir * (len - 1.0), Stroke::new(1.2, LOAD));
        if !labelled && size >= qmax * (1.0 - 1e-9) {
            labelled = true;
            p.text(
                tail - dir * 4.0,
                Align2::CENTER_CENTER,
                format!("{} {}/{}", num(size), units.force(), units.length()),
                FontId::proportional(11.0),
                LOAD,
            );
        }
    }
}
