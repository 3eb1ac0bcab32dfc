//! The plots under the timeline: convergence (log10 of the relative residual against the
//! cumulative iteration number, streaming live, with the tolerance line and markers at cut-backs
//! and contact events; all increments or the selected one) and the reaction against the
//! displacement of the driven dof (load factor against displacement under load control).

use egui::Color32;
use egui_plot::{GridInput, GridMark, HLine, HoverPosition, Line, MarkerShape, Plot, Points};

use crate::app::display::Picked;
use crate::app::files::screenshot::Layout;
use crate::app::parts::{Look, Study};
use crate::solver::{Dof, Event, IncrementRecord, IncrementStatus, IterationRecord};

const RESIDUAL: Color32 = Color32::from_rgb(40, 90, 170);
const SELECTED: Color32 = Color32::from_rgb(230, 120, 0);
const CUT: Color32 = Color32::from_rgb(200, 30, 30);
const CONTACT: Color32 = Color32::from_rgb(20, 150, 70);
/// Increments accepted at the round-off floor, above the tolerance (also on the timeline).
pub(crate) const ROUNDOFF: Color32 = Color32::from_rgb(200, 120, 0);
/// States on the way of a snap, not in equilibrium (on the timeline and in the details).
pub(crate) const SNAPPING: Color32 = Color32::from_rgb(150, 60, 190);

/// Show both plots side by side.
pub fn show(
    study: &Study,
    selected: usize,
    look: &mut Look,
    layout: &mut Layout,
    ui: &mut egui::Ui,
) {
    ui.columns(2, |cols| {
        convergence(study, selected, look, layout, &mut cols[0]);
        if let Some(dof) = reaction(study, selected, look, &mut cols[1]) {
            look.plot_dof = dof;
        }
    });
}

/// Floor of the plotted residual (an exactly zero residual is drawn here).
const FLOOR: f64 = 1e-18;

fn lg(v: f64) -> f64 {
    v.max(FLOOR).log10()
}

/// Decade grid marks (integers of log10).
pub(crate) fn decades(input: GridInput) -> Vec<GridMark> {
    let (lo, hi) = input.bounds;
    // Powers of two keep 1e-8 (the usual tolerance) on a labelled line.
    let raw = (hi - lo) / 8.0;
    let step = [1.0, 2.0, 4.0, 8.0, 16.0, 32.0, 64.0]
        .into_iter()
        .find(|s| *s >= raw)
        .unwrap_or(128.0);
    // The first mark at or above the range's foot: one below it would be labelled outside
    // the frame.
    let mut v = (lo / step).ceil() * step;
    let mut out = Vec::new();
    while v <= hi && out.len() < 200 {
        out.push(GridMark {
            value: v,
            step_size: step,
        });
        v += step;
    }
    out
}

/// "1e-8" for an integer log10 value.
fn power_label(mark: GridMark, _range: &std::ops::RangeInclusive<f64>) -> String {
    if (mark.value - mark.value.round()).abs() < 1e-9 {
        format!("1e{}", mark.value.round() as i64)
    } else {
        String::new()
    }
}

/// Points of the residual history, markers and the selected increment's span.
struct Series {
    all: Vec<[f64; 2]>,
    selected: Vec<[f64; 2]>,
    cuts: Vec<[f64; 2]>,
    contacts: Vec<[f64; 2]>,
    /// The last residual of each increment accepted at the round-off floor.
    roundoff: Vec<[f64; 2]>,
}

/// Most points a plotted line gets (long runs are reduced to keep frames fast).
const MAX_POINTS: usize = 4000;

/// Reduce a long series to the lowest and highest point of each of `max / 2` buckets, in x
/// order, so the sawtooth's envelope survives.
fn envelope(points: Vec<[f64; 2]>, max: usize) -> Vec<[f64; 2]> {
    if points.len() <= max {
        return points;
    }
    let bucket = points.len().div_ceil(max / 2);
    let mut out = Vec::with_capacity(max + 2);
    for chunk in points.chunks(bucket) {
        let lo = chunk.iter().min_by(|a, b| a[1].total_cmp(&b[1])).copied();
        let hi = chunk.iter().max_by(|a, b| a[1].total_cmp(&b[1])).copied();
        if let (Some(lo), Some(hi)) = (lo, hi) {
            if lo[0] <= hi[0] {
                out.extend([lo, hi]);
            } else {
                out.extend([hi, lo]);
            }
        }
    }
    out
}

/// Keep every n-th point so that at most about `max` remain (the last one always).
fn thin(points: Vec<[f64; 2]>, max: usize) -> Vec<[f64; 2]> {
    if points.len() <= max {
        return points;
    }
    let step = points.len().div_ceil(max);
    let last = *points.last().expect("non-empty");
    let mut out: Vec<[f64; 2]> = points.into_iter().step_by(step).collect();
    if out.last() != Some(&last) {
        out.push(last);
    }
    out
}

fn series(history: &[IncrementRecord], live: &[IterationRecord], selected: usize) -> Series {
    let mut s = Series {
        all: Vec::new(),
        selected: Vec::new(),
        cuts: Vec::new(),
        contacts: Vec::new(),
        roundoff: Vec::new(),
    };
    let mut x = 0.0;
    for (k, r) in history.iter().enumerate().skip(1) {
        let start = x;
        for it in &r.residuals {
            x += 1.0;
            if it.relative_residual > 0.0 {
                s.all.push([x, lg(it.relative_residual)]);
                if k == selected {
                    s.selected.push([x, lg(it.relative_residual)]);
                }
            }
        }
        let y_at = |i: usize| {
            let v = r
                .residuals
                .get(i.saturating_sub(1))
                .map_or(0.0, |it| it.relative_residual);
            if v > 0.0 {
                lg(v)
            } else {
                0.0
            }
        };
        if r.cutbacks > 0 {
            s.cuts.push([start + 1.0, y_at(1)]);
        }
        if matches!(r.status, IncrementStatus::RoundOff { .. }) {
            s.roundoff.push([x, lg(r.relative_residual)]);
        }
        for e in &r.events {
            let iteration = match e {
                Event::Contact(c) => c.iteration,
                Event::Obstacle(o) => o.iteration,
                _ => continue,
            };
            let i = iteration.max(1);
            s.contacts.push([start + i as f64, y_at(i)]);
        }
    }
    for it in live {
        x += 1.0;
        if it.relative_residual > 0.0 {
            s.all.push([x, lg(it.relative_residual)]);
        }
    }
    s.all = envelope(s.all, MAX_POINTS);
    s.cuts = thin(s.cuts, MAX_POINTS / 4);
    s.contacts = thin(s.contacts, MAX_POINTS / 4);
    s.roundoff = thin(s.roundoff, MAX_POINTS / 4);
    s
}

/// Marker of a key entry.
#[derive(Clone, Copy)]
enum Mark {
    Line,
    Dashed,
    Diamond,
    Down,
}

/// A coloured key entry: a drawn marker and a label, one widget (a wrapping row moves it to the
/// next line whole).
fn key(ui: &mut egui::Ui, color: Color32, mark: Mark, text: &str) {
    let galley = egui::WidgetText::from(egui::RichText::new(text).small()).into_galley(
        ui,
        Some(egui::TextWrapMode::Extend),
        f32::INFINITY,
        egui::TextStyle::Small,
    );
    let gap = ui.spacing().item_spacing.x;
    let size = egui::vec2(16.0 + gap + galley.size().x, galley.size().y.max(10.0));
    let (whole, response) = ui.allocate_exact_size(size, egui::Sense::hover());
    response.widget_info(|| egui::WidgetInfo::labeled(egui::Role::Label, true, text));
    let rect = egui::Rect::from_center_size(
        egui::pos2(whole.left() + 8.0, whole.center().y),
        egui::vec2(16.0, 10.0),
    );
    let p = ui.painter();
    let c = rect.center();
    let stroke = egui::Stroke::new(2.0, color);
    match mark {
        Mark::Line => {
            p.line_segment([rect.left_center(), rect.right_center()], stroke);
        }
        Mark::Dashed => {
            p.add(egui::Shape::dashed_line(
                &[rect.left_center(), rect.right_center()],
                stroke,
                4.0,
                2.0,
            ));
        }
        Mark::Diamond => {
            let pts = vec![
                c + egui::vec2(0.0, -5.0),
                c + egui::vec2(5.0, 0.0),
                c + egui::vec2(0.0, 5.0),
                c + egui::vec2(-5.0, 0.0),
            ];
            p.add(egui::Shape::convex_polygon(pts, color, egui::Stroke::NONE));
        }
        Mark::Down => {
            let pts = vec![
                c + egui::vec2(-5.0, -4.0),
                c + egui::vec2(5.0, -4.0),
                c + egui::vec2(0.0, 5.0),
            ];
            p.add(egui::Shape::convex_polygon(pts, color, egui::Stroke::NONE));
        }
    }
    let text_at = egui::pos2(rect.right() + gap, whole.center().y - galley.size().y / 2.0);
    p.galley(text_at, galley, ui.visuals().text_color());
}

fn convergence(
    study: &Study,
    selected: usize,
    look: &mut Look,
    layout: &mut Layout,
    ui: &mut egui::Ui,
) {
    // Wrapped: in a narrow window the keys go onto a second row rather than past the column
    // (where they ran under the reaction plot's title, and the plot grew as wide as the row).
    ui.horizontal_wrapped(|ui| {
        ui.label("Convergence:");
        ui.selectable_value(&mut look.plot_all, true, "all increments");
        ui.selectable_value(&mut look.plot_all, false, "selected increment");
        ui.separator();
        key(ui, RESIDUAL, Mark::Line, "residual");
        if look.plot_all {
            key(ui, SELECTED, Mark::Line, "selected");
            key(ui, CONTACT, Mark::Diamond, "contact event");
            key(ui, CUT, Mark::Down, "cut-back");
        }
        key(ui, CUT, Mark::Dashed, "tolerance");
    });
    let tol = study
        .loaded
        .as_ref()
        .map_or(1e-8, |l| l.scene.params.tolerance);
    let s = if look.plot_all {
        series(&study.history, &study.live, selected)
    } else {
        let r = study.record(selected).filter(|r| r.increment > 0);
        let pts: Vec<[f64; 2]> = r
            .map(|r| {
                r.residuals
                    .iter()
                    .enumerate()
                    .filter(|(_, it)| it.relative_residual > 0.0)
                    .map(|(i, it)| [(i + 1) as f64, lg(it.relative_residual)])
                    .collect()
            })
            .unwrap_or_default();
        let roundoff = (study.record(selected))
            .filter(|r| matches!(r.status, IncrementStatus::RoundOff { .. }))
            .map(|r| vec![[r.residuals.len() as f64, lg(r.relative_residual)]])
            .unwrap_or_default();
        Series {
            all: pts,
            selected: Vec::new(),
            cuts: Vec::new(),
            contacts: Vec::new(),
            roundoff,
        }
    };
    let x_label = if look.plot_all {
        "cumulative iteration"
    } else {
        "iteration"
    };
    let shown = Plot::new("convergence")
        .x_axis_label(x_label)
        .y_axis_label("relative residual")
        .y_grid_spacer(decades)
        .y_axis_formatter(power_label)
        .include_y(lg(tol) - 2.0)
        .include_y(0.0)
        .include_x(0.0)
        .label_formatter(|h| {
            let (HoverPosition::NearDataPoint { position: p, .. }
            | HoverPosition::Elsewhere { position: p }) = h;
            Some(format!("iteration {:.0}\n{:.2e}", p.x, 10f64.powf(p.y)))
        })
        .allow_scroll(false)
        .show(ui, move |p| {
            scroll_zoom(p);
            p.hline(
                HLine::new(format!("tolerance {tol:.0e}"), lg(tol))
                    .color(CUT)
                    .style(egui_plot::LineStyle::dashed_loose()),
            );
            p.line(
                Line::new("relative residual", s.all)
                    .color(RESIDUAL)
                    .width(1.5),
            );
            if !s.selected.is_empty() {
                p.line(
                    Line::new("selected increment", s.selected)
                        .color(SELECTED)
                        .width(2.5),
                );
            }
            if !s.cuts.is_empty() {
                p.points(
                    Points::new("cut-back", s.cuts)
                        .shape(MarkerShape::Down)
                        .color(CUT)
                        .radius(5.0)
                        .filled(true),
                );
            }
            if !s.contacts.is_empty() {
                p.points(
                    Points::new("contact event", s.contacts)
                        .shape(MarkerShape::Diamond)
                        .color(CONTACT)
                        .radius(4.0),
                );
            }
            if !s.roundoff.is_empty() {
                p.points(
                    Points::new("accepted at round-off", s.roundoff)
                        .shape(MarkerShape::Square)
                        .color(ROUNDOFF)
                        .radius(5.0)
                        .filled(true),
                );
            }
        });
    layout.plot = Some(*shown.transform.frame());
}

/// The response plot; returns the dof of the selected node the user picked for its x axis.
fn reaction(study: &Study, selected: usize, look: &Look, ui: &mut egui::Ui) -> Option<Dof> {
    let mut plot_dof = None;
    let Some(l) = &study.loaded else {
        return None;
    };
    let model = &l.scene.model;
    let units = l.scene.file.units;
    let (title, x_label, y_label, pts): (&str, String, String, Vec<[f64; 2]>) =
        if let Some(p) = model.prescribed.first() {
            let (dof, ids) = (p.dof.name(), model.moving_with(p.node));
            let pts = (study.history.iter())
                .map(|r| [r.prescribed[0], r.held_force(&ids, dof)])
                .collect();
            (
                "Reaction against displacement of the driven dof:",
                format!(
                    "{} (prescribed, {})",
                    l.prescribed_labels[0],
                    units.of_dof(p.dof)
                ),
                format!("reaction ({})", units.of_reaction(p.dof)),
                pts,
            )
        } else if let Some((n, o)) = crate::app::display::loaded_dof(model) {
            let x0 = [model.nodes[n].x, model.nodes[n].y, 0.0][o];
            let pts = study
                .history
                .iter()
                .map(|r| [r.nodes[n][o] - x0, r.load_factor])
                .collect();
            let unit = units.of_dof(Dof::ALL[o]);
            // Along a load path the first load group's factor, named.
            let factor = match model.load_groups.first() {
                Some(g) if model.load_groups.len() > 1 => format!("load factor of \"{g}\""),
                _ => "load factor".into(),
            };
            (
                "Load factor against displacement of the loaded dof:",
                format!("{} ({unit})", model.dof_label(n, o)),
                factor,
                pts,
            )
        } else {
            return None;
        };
    let (title, x_label, pts) = match look.pinned {
        // A node picked in the view: the same response against its own displacement.
        Some(Picked::Node(n)) => {
            let o = if model.nodes[n].rotation {
                look.plot_dof.offset()
            } else {
                look.plot_dof.offset().min(1)
            };
            let x0 = [model.nodes[n].x, model.nodes[n].y, 0.0][o];
            let xs = study.history.iter().map(|r| r.nodes[n][o] - x0);
            let pts: Vec<[f64; 2]> = xs.zip(&pts).map(|(x, p)| [x, p[1]]).collect();
            let label = model.dof_label(n, o);
            let what = if model.prescribed.is_empty() {
                "Load factor"
            } else {
                "Reaction"
            };
            let title = format!("{what} against {label}, the node selected in the view:");
            let x_label = format!("{label} ({})", units.of_dof(Dof::ALL[o]));
            (title, x_label, pts)
        }
        _ => (title.to_string(), x_label, pts),
    };
    ui.horizontal(|ui| {
        ui.label(title);
        if let Some(Picked::Node(n)) = look.pinned {
            let dofs = model.node_dofs(n);
            for dof in Dof::ALL.into_iter().take(dofs) {
                if ui
                    .selectable_label(look.plot_dof == dof, dof.name())
                    .clicked()
                {
                    plot_dof = Some(dof);
                }
            }
        }
    });
    let sel = pts.get(selected).copied();
    // A snap is the jump between its ends: the states of its damped path are not in equilibrium.
    let held = (pts.into_iter().zip(study.history.iter()))
        .filter_map(|(p, r)| (!matches!(r.status, IncrementStatus::Snapping { .. })).then_some(p));
    let pts = thin(held.collect(), MAX_POINTS);
    Plot::new("reaction")
        .x_axis_label(x_label)
        .y_axis_label(y_label)
        .allow_scroll(false)
        .show(ui, move |p| {
            scroll_zoom(p);
            p.line(
                Line::new("equilibrium path", pts)
                    .color(RESIDUAL)
                    .width(1.5),
            );
            if let Some(s) = sel {
                p.points(
                    Points::new("selected", vec![s])
                        .color(SELECTED)
                        .radius(5.0)
                        .filled(true),
                );
            }
        });
    plot_dof
}

/// The scroll wheel over a plot zooms it about the pointer (drag pans, double-click resets).
fn scroll_zoom(p: &mut egui_plot::PlotUi<'_>) {
    if !p.response().hovered() {
        return;
    }
    let scroll = p.ctx().input(|i| i.smooth_scroll_delta.y);
    if scroll != 0.0 {
        let factor = (scroll * 0.002).exp();
        p.zoom_bounds_around_hovered(egui::Vec2::splat(factor));
    }
}
