//! The central viewport: pan (drag on empty space), zoom at the cursor (scroll), fit
//! (double-click, the "Fit" button or F), dragging the handle of a prescribed dof, the values of
//! what the pointer is on (hover) and its selection (click), and the beams
//! (deformed strips coloured by bending moment over the grey undeformed shape, see
//! `beams_gpu`, over the faces of bodies with a thickness) under the overlays of `overlays`.

use std::sync::Arc;

use egui::{Align2, Color32, FontId, Pos2, Rect, Sense, Stroke, Vec2};

use crate::solver::Dof;

use super::beams_gpu::{self, Built, Strip};
use super::diagrams::{self, moment_color};
use super::legend;
use super::overlays::{self, INK};
use super::query::{describe, pick};
use super::strips::Polyline;
use crate::app::files::screenshot::Layout;
use crate::app::parts::{Action, Look, Notices, Study};
use crate::app::view::{bounds, handle_world, Drag};
use crate::figure::geometry::{
    deformed_bodies, faces, half_thickness, max_moment, obstacle_outlines, undeformed_bodies,
    BodyCurve,
};
use crate::figure::Diagram;

const GHOST: Color32 = Color32::from_rgb(175, 178, 186);
/// A body's faces where it has a thickness: the band and its edges.
const FACE: Color32 = Color32::from_rgba_premultiplied(40, 48, 64, 72);
const FACE_EDGE: Color32 = Color32::from_rgb(120, 124, 134);
/// The outline of a rigid obstacle (as the figure draws it, `figure::Kind::Obstacle`).
const OBSTACLE: Color32 = Color32::from_rgb(90, 90, 96);

/// What the cached curves were built for: the scene load, and the increment (its number and
/// wall time, which tell records apart).
type CurveKey = (u64, usize, u64);

/// What the cached strips were built for: the curves, the view (centre, scale), the viewport
/// and pixels per point, and the renderer.
type ScreenKey = (CurveKey, [u64; 2], u64, [u32; 5], bool);

/// Show the viewport.
#[allow(clippy::too_many_arguments)]
pub fn show(
    study: &Study,
    selected: usize,
    look: &mut Look,
    layout: &mut Layout,
    notices: &Notices,
    actions: &mut Vec<Action>,
    ui: &mut egui::Ui,
    gpu: Option<&egui_wgpu::RenderState>,
) {
    let rect = ui.available_rect_before_wrap();
    let bg = ui.allocate_rect(rect, Sense::click_and_drag());
    let painter = ui.painter_at(rect);
    painter.rect_filled(rect, 0.0, Color32::from_rgb(251, 251, 253));
    if study.loaded.is_none() {
        let msg = (notices.error.as_ref()).map_or_else(|| "loading...".into(), |e| e.to_string());
        painter.text(
            rect.center(),
            Align2::CENTER_CENTER,
            msg,
            FontId::proportional(16.0),
            INK,
        );
        return;
    }
    handles(study, selected, look, actions, ui, rect);
    navigate(look, ui, &bg, rect, layout.viewport);
    if look.fit_pending {
        fit(study, look, rect);
        look.fit_pending = false;
    }
    layout.viewport = Some(rect);
    layout.view = look.camera;
    layout.increment = study.record(selected).map_or(0, |r| r.increment);
    let (Some(l), Some(r)) = (study.loaded.as_ref(), study.record(selected)) else {
        return;
    };
    let model = &l.scene.model;
    let view = look.camera;
    let to_screen = |p: [f64; 2]| view.to_screen(rect, p);
    let ppp = ui.ctx().pixels_per_point();

    // Beams: ghost first, then the deformed strips. The curves of the viewed increment are
    // built once and kept while it stays in view.
    let key = (study.generation, r.increment, r.seconds.to_bits());
    let id = ui.scope_id().with("deformed curves");
    let cached: Option<(CurveKey, Arc<Vec<BodyCurve>>)> = ui.data(|d| d.get_temp(id));
    let curves = match cached {
        Some((k, c)) if k == key => c,
        _ => {
            let c = Arc::new(deformed_bodies(model, &l.elements, r));
            ui.data_mut(|d| d.insert_temp(id, (key, Arc::clone(&c))));
            c
        }
    };
    let mmax = max_moment(&curves);
    // The strips on screen, built once for this increment, view and window.
    let f = |v: f32| v.to_bits();
    let screen_key = (
        key,
        view.center.map(f64::to_bits),
        view.scale.to_bits(),
        [
            f(rect.min.x),
            f(rect.min.y),
            f(rect.max.x),
            f(rect.max.y),
            f(ppp),
        ],
        gpu.is_some(),
    );
    let id = ui.scope_id().with("beam strips");
    let cached: Option<(ScreenKey, Built)> = ui.data(|d| d.get_temp(id));
    let built = match cached {
        Some((k, b)) if k == screen_key => b,
        _ => {
            let mut strips: Vec<Strip> = undeformed_bodies(model)
                .into_iter()
                .map(|line| Strip {
                    line: Polyline::uniform(line.into_iter().map(to_screen).collect(), GHOST),
                    half_px: 0.9 * ppp,
                })
                .collect();
            for c in curves.iter() {
                let line = Polyline {
                    points: c.points.iter().map(|p| to_screen(*p)).collect(),
                    colors: c.moments.iter().map(|m| moment_color(*m, mmax)).collect(),
                };
                strips.push(Strip {
                    line,
                    half_px: 3.0 * ppp,
                });
            }
            let b = beams_gpu::build(&strips, ppp, gpu.is_some());
            ui.data_mut(|d| d.insert_temp(id, (screen_key, b.clone())));
            b
        }
    };
    for outline in obstacle_outlines(model, r) {
        let points: Vec<Pos2> = outline.into_iter().map(to_screen).collect();
        painter.add(egui::Shape::line(points, Stroke::new(3.0, OBSTACLE)));
    }
    // Only a scene with a section of some thickness has faces: the frame loop looks at its few
    // sections, not at every element.
    let thick = (l.scene.file.sections.iter()).any(|s| s.thickness.is_some_and(|t| t > 0.0));
    if thick {
        paint_faces(&painter, model, &curves, &to_screen);
    }
    beams_gpu::paint(&painter, rect, &built, gpu);
    obstacle_contacts(&painter, model, r, &to_screen);

    overlays::supports(&painter, model, r, &to_screen);
    overlays::contacts(&painter, model, r, &to_screen);
    overlays::body_names(&painter, model, &curves, &to_screen);
    overlays::prescribed(&painter, study, look, model, r, &to_screen);
    let units = l.scene.file.units;
    if let Some(d) = look.diagram {
        let unit = match d {
            Diagram::Moment => units.moment(),
            _ => units.force().to_string(),
        };
        diagrams::paint(&painter, model, r, d, &unit, &to_screen);
    }
    overlays::loads(&painter, model, r, units, &to_screen);
    overlays::distributed_loads(&painter, model, r, units, &to_screen);
    legend::legend(&painter, rect, mmax, units);
    legend::scale_bar(&painter, rect, view.scale, units);
    // What the pointer is on: its values on hover, pinned in the details panel on a click.
    let at = bg.hover_pos();
    let hovered = at.and_then(|at| pick(model, r, at, &to_screen));
    if let (Some(h), Some(at)) = (hovered, at) {
        // Shown at once (not after a tooltip's delay), beside the pointer.
        let lines = describe(model, r, h, units, look.angles);
        egui::Area::new(ui.scope_id().with("query"))
            .order(egui::Order::Tooltip)
            .fixed_pos(at + Vec2::new(14.0, 14.0))
            .interactable(false)
            .show(ui.ctx(), |ui| {
                egui::Frame::popup(ui.style()).show(ui, |ui| {
                    for line in lines {
                        ui.label(line);
                    }
                });
            });
    }
    let clicked = bg.clicked().then_some(hovered);
    let text = format!(
        "increment {}{}",
        r.increment,
        if study.busy { "  (solving...)" } else { "" }
    );
    painter.text(
        rect.right_top() + Vec2::new(-10.0, 10.0),
        Align2::RIGHT_TOP,
        text,
        FontId::proportional(14.0),
        INK,
    );
    if let Some(p) = clicked {
        look.pinned = p;
    }
}

/// Interact with the prescribed-dof handles: dragging one sets its target.
fn handles(
    study: &Study,
    selected: usize,
    look: &mut Look,
    actions: &mut Vec<Action>,
    ui: &mut egui::Ui,
    rect: Rect,
) {
    let (Some(l), Some(r)) = (study.loaded.as_ref(), study.record(selected)) else {
        return;
    };
    let model = &l.scene.model;
    // (index, dof, current target, screen position) of every draggable handle.
    let spots: Vec<(usize, Dof, f64, Pos2)> = (0..model.prescribed.len())
        .filter_map(|k| {
            let t = study.targets.get(k).copied()?;
            let w = handle_world(model, r, k, t)?;
            Some((
                k,
                model.prescribed[k].dof,
                t,
                look.camera.to_screen(rect, w),
            ))
        })
        .collect();
    let mut send = None;
    look.hover_handle = None;
    for (k, dof, t, pos) in spots {
        let id = ui.scope_id().with(("handle", k));
        let resp = ui.interact(
            Rect::from_center_size(pos, Vec2::splat(24.0)),
            id,
            Sense::drag(),
        );
        let resp = resp
            .on_hover_cursor(match dof {
                Dof::U => egui::CursorIcon::ResizeHorizontal,
                _ => egui::CursorIcon::ResizeVertical,
            })
            .on_hover_text("drag to set the target of this prescribed dof");
        if resp.hovered() {
            look.hover_handle = Some(k);
        }
        if resp.drag_started() {
            look.drag = Some(Drag {
                index: k,
                start: t,
                moved: Vec2::ZERO,
            });
        }
        if resp.dragged() {
            if let Some(d) = &mut look.drag {
                d.moved += resp.drag_delta();
                let along = if dof == Dof::U { d.moved.x } else { -d.moved.y };
                let value = d.start + f64::from(along) / look.camera.scale;
                if (value - t).abs() > 1e-12 {
                    send = Some((d.index, value));
                }
            }
        }
        if resp.drag_stopped() {
            look.drag = None;
            // The worker may have reached the last target while the handle was held (its
            // `Idle` then left `targeting` on): follow the converged states again.
            if !study.busy && send.is_none() {
                actions.push(Action::FollowRun);
            }
        }
    }
    if let Some((index, value)) = send {
        actions.push(Action::Drive { index, value });
    }
}

/// Pan by dragging empty space, zoom at the cursor by scrolling, fit on double-click, on F and
/// when the viewport changes size.
fn navigate(look: &mut Look, ui: &egui::Ui, bg: &egui::Response, rect: Rect, before: Option<Rect>) {
    if bg.dragged() && look.drag.is_none() {
        look.camera.pan(bg.drag_delta());
    }
    let fit_key =
        ui.input(|i| i.key_pressed(egui::Key::F)) && !ui.ctx().egui_wants_keyboard_input();
    // A resized viewport (window or panels) is fitted again.
    let resized = before.is_some_and(|r| r.size() != rect.size());
    if bg.double_clicked() || fit_key || resized {
        look.fit_pending = true;
    }
    if let Some(at) = bg.hover_pos() {
        let (scroll, zoom) = ui.input(|i| (i.smooth_scroll_delta.y, i.zoom_delta()));
        let factor = f64::from(zoom) * (f64::from(scroll) * 0.002).exp();
        if (factor - 1.0).abs() > 1e-6 {
            look.camera.zoom_at(rect, at, factor);
        }
    }
}

/// Height kept clear of the beams at the top of the viewport for the legend (points).
const LEGEND_ROOM: f32 = 70.0;

/// Fit the undeformed shape and every converged state into the viewport below the legend.
fn fit(study: &Study, look: &mut Look, rect: Rect) {
    let b = bounds(study.history.iter().flat_map(|r| r.nodes.iter()));
    let room = if rect.height() > 3.0 * LEGEND_ROOM {
        LEGEND_ROOM
    } else {
        0.0
    };
    let below = Rect::from_min_max(rect.min + Vec2::new(0.0, room), rect.max);
    look.camera.fit(below, b);
    // `fit` centred the bounds in `below`; the view is anchored at the centre of `rect`.
    look.camera.center[1] += f64::from(room / 2.0) / look.camera.scale;
}

/// The nodes resting on obstacles: a disc at the node and an arrow of the obstacle's push
/// along its normal, 14 to 50 points long by the force (the largest the longest), and the
/// friction force along the obstacle where it has friction.
fn obstacle_contacts(
    p: &egui::Painter,
    model: &crate::solver::Model,
    r: &crate::solver::IncrementRecord,
    s: &dyn Fn([f64; 2]) -> Pos2,
) {
    let fmax = (r.obstacle_contacts.iter()).fold(1e-30f64, |a, c| a.max(c.force.abs()));
    for c in &r.obstacle_contacts {
        let Some(n) = model.nodes.iter().position(|x| x.id == c.node) else {
            continue;
        };
        let at = s([r.nodes[n][0], r.nodes[n][1]]);
        // The push on the node, along the normal (screen y points down).
        let dir = Vec2::new(c.normal[0] as f32, -c.normal[1] as f32);
        let len = 14.0 + 36.0 * (c.force.abs() / fmax) as f32;
        p.arrow(
            at - dir * (len + 6.0),
            dir * len,
            Stroke::new(2.5, overlays::ACTIVE),
        );
        p.circle(at, 5.0, overlays::ACTIVE, Stroke::new(1.5, INK));
        // The tangent (normal_y, -normal_x) on the screen.
        let along = Vec2::new(c.normal[1] as f32, c.normal[0] as f32);
        overlays::friction_arrow(p, at, along, (c.tangential, c.friction), fmax);
    }
}

/// The faces of every body with a thickness: a band of its thickness about its deformed curve,
/// under the moment strip along its axis.
fn paint_faces(
    painter: &egui::Painter,
    model: &crate::solver::Model,
    curves: &[BodyCurve],
    to_screen: &impl Fn([f64; 2]) -> Pos2,
) {
    for c in curves {
        let sides = faces(&c.points, half_thickness(model, c.body));
        if sides.is_empty() {
            continue;
        }
        let mut mesh = egui::Mesh::default();
        for (k, [left, right]) in sides.iter().enumerate() {
            mesh.colored_vertex(to_screen(*left), FACE);
            mesh.colored_vertex(to_screen(*right), FACE);
            if k > 0 {
                let v = 2 * k as u32;
                mesh.add_triangle(v - 2, v - 1, v);
                mesh.add_triangle(v - 1, v + 1, v);
            }
        }
        painter.add(mesh);
        for side in 0..2 {
            let edge: Vec<Pos2> = sides.iter().map(|f| to_screen(f[side])).collect();
            painter.add(egui::Shape::line(edge, Stroke::new(1.0, FACE_EDGE)));
        }
    }
}
