//! The details panel for the selected increment: the scene's units, the node or element picked
//! in the viewport and the diagram's extreme, "Increment k / n", prescribed values,
//! iterations, "residual 3.2e-11 (converged)" or its acceptance at the round-off floor, the
//! active contacts (li/l, Yc, and their friction force and stick or slip), the events and the
//! reactions.

use egui::RichText;

use super::plots::{ROUNDOFF, SNAPPING};
use crate::app::canvas::diagrams::extreme;
use crate::app::canvas::overlays::{SLIP, STICK};
use crate::app::canvas::query::describe;
use crate::app::display::num;
use crate::app::parts::{Look, Study};
use crate::solver::{Dof, Friction, IncrementStatus};

/// Show the details of the selected increment.
pub fn show(study: &Study, selected: usize, look: &Look, ui: &mut egui::Ui) {
    let Some(l) = &study.loaded else {
        ui.label("no scene loaded");
        return;
    };
    let Some(r) = study.record(selected) else {
        return;
    };
    let model = &l.scene.model;
    let units = l.scene.file.units;
    ui.heading(RichText::new(&l.scene.file.name).strong());
    if !l.scene.file.description.is_empty() {
        ui.label(RichText::new(&l.scene.file.description).small());
    }
    ui.label(RichText::new(format!("units: {}, {}", units.force(), units.length())).small());
    picked(study, selected, look, ui);
    ui.separator();
    ui.label(RichText::new(format!("Increment {} / {}", r.increment, study.last())).strong());
    for ((label, v), p) in (l.prescribed_labels.iter().zip(&r.prescribed)).zip(&model.prescribed) {
        ui.label(format!("{label} = {v:+.5} {}", units.of_dof(p.dof)));
    }
    if let Some(path) = &model.path {
        let stage = match r.stage {
            Some(s) => format!(
                "stage {} of {}: {}",
                s + 1,
                path.stages.len(),
                path.stages.get(s).map_or("", |st| st.name.as_str())
            ),
            None if r.increment == 0 => "before the first stage".into(),
            None => "off the load path (a drag)".into(),
        };
        ui.label(RichText::new(stage).color(super::timeline::STAGE));
    }
    if model.load_groups.len() > 1 {
        for (g, name) in model.load_groups.iter().enumerate() {
            let f = r.load_factors.get(g).copied().unwrap_or(r.load_factor);
            ui.label(format!("load factor of \"{name}\" {f:.4}"));
        }
    } else if l.scene.model.load_per_step != 0.0 || model.path.is_some() && model.has_loads() {
        ui.label(format!("load factor {:.4}", r.load_factor));
    }
    if r.increment > 0 {
        let it8 = r.iterations_8_orders.map_or("-".into(), |v| v.to_string());
        ui.label(format!("iterations {} (8 orders: {it8})", r.iterations));
        match r.status {
            IncrementStatus::Converged => {
                ui.label(format!("residual {:.1e} (converged)", r.relative_residual));
            }
            // Never called converged: the state is as close to equilibrium as round-off allows.
            IncrementStatus::RoundOff { ratio } => {
                let text = format!(
                    "residual {:.1e}: accepted at the round-off floor, {ratio:.0} x the tolerance",
                    r.relative_residual
                );
                ui.label(RichText::new(text).color(ROUNDOFF));
            }
            // A state of a snap: held by the viscous force of its damped path.
            IncrementStatus::Snapping { residual } => {
                let text =
                    format!("residual {residual:.1e}: on the way of a snap, not in equilibrium");
                ui.label(RichText::new(text).color(SNAPPING));
            }
        }
        if r.cutbacks > 0 {
            ui.label(format!("cut-backs {}", r.cutbacks));
        }
        ui.label(format!("time {:.2} ms", r.seconds * 1e3));
    }
    // Node-to-beam contacts where the scene has candidates for them.
    if !model.contacts.is_empty() {
        ui.separator();
        ui.label(RichText::new(format!("Active contacts: {}", r.contacts.len())).strong());
        let frictional = model.contacts.iter().any(|c| c.mu > 0.0);
        egui::Grid::new("contacts")
            .striped(true)
            .num_columns(if frictional { 6 } else { 4 })
            .show(ui, |ui| {
                if !r.contacts.is_empty() {
                    let yc = format!("Yc ({})", units.force());
                    let t = format!("T ({})", units.force());
                    let heads = ["node", "on", "li/l", yc.as_str(), t.as_str(), "grip"];
                    for h in &heads[..if frictional { 6 } else { 4 }] {
                        ui.label(RichText::new(*h).small());
                    }
                    ui.end_row();
                }
                for c in &r.contacts {
                    ui.label(c.node.to_string());
                    ui.label(model.element_label(c.element));
                    ui.label(format!("{:.4}", c.xi));
                    ui.label(num(c.force));
                    if frictional {
                        ui.label(num(c.tangential));
                        ui.label(grip_label(c.friction));
                    }
                    ui.end_row();
                }
            });
    }
    if !r.obstacle_contacts.is_empty() {
        ui.separator();
        let count = r.obstacle_contacts.len();
        ui.label(RichText::new(format!("On obstacles: {count}")).strong());
        let frictional = model.obstacles.iter().any(|o| o.mu > 0.0);
        let columns = if frictional { 6 } else { 4 };
        egui::Grid::new("obstacle contacts")
            .striped(true)
            .num_columns(columns)
            .show(ui, |ui| {
                let force = format!("F ({})", units.force());
                let gap = format!("gap ({})", units.length());
                let t = format!("T ({})", units.force());
                let heads = [
                    "node",
                    "on",
                    force.as_str(),
                    gap.as_str(),
                    t.as_str(),
                    "grip",
                ];
                for h in &heads[..columns] {
                    ui.label(RichText::new(*h).small());
                }
                ui.end_row();
                for c in &r.obstacle_contacts {
                    ui.label(c.node.to_string());
                    ui.label(&c.obstacle);
                    ui.label(num(c.force));
                    ui.label(format!("{:.1e}", c.gap));
                    if frictional {
                        ui.label(num(c.tangential));
                        ui.label(grip_label(c.friction));
                    }
                    ui.end_row();
                }
            });
    }
    let events: Vec<_> = r.events.iter().map(|e| e.describe(model)).collect();
    if !events.is_empty() {
        ui.separator();
        ui.label(RichText::new("Events").strong());
        for e in events {
            ui.label(RichText::new(e).small());
        }
    }
    if !r.reactions.is_empty() {
        ui.separator();
        ui.label(RichText::new("Reactions").strong());
        // Round-off far below every reaction of the run (like 1e-178 N once stress-free) is 0.
        let floor = 1e-12
            * study
                .history
                .iter()
                .flat_map(|r| r.reactions.iter())
                .fold(0.0f64, |a, x| a.max(x.value.abs()));
        egui::Grid::new("reactions")
            .striped(true)
            .num_columns(2)
            .show(ui, |ui| {
                for x in &r.reactions {
                    let dof = Dof::ALL.iter().find(|d| d.name() == x.dof).copied();
                    let unit = dof.map_or(String::new(), |d| units.of_reaction(d));
                    ui.label(format!("node {} {}", x.node, x.dof));
                    let v = if x.value.abs() <= floor { 0.0 } else { x.value };
                    ui.label(format!("{} {unit}", num(v)));
                    ui.end_row();
                }
            });
    }
}

/// The node or element picked in the viewport, and the extreme of the diagram drawn.
fn picked(study: &Study, selected: usize, look: &Look, ui: &mut egui::Ui) {
    let (Some(l), Some(r)) = (&study.loaded, study.record(selected)) else {
        return;
    };
    let (model, units) = (&l.scene.model, l.scene.file.units);
    if let Some(d) = look.diagram {
        if let Some((v, e, x)) = extreme(model, r, d) {
            let unit = match d.letter() {
                "M" => units.moment(),
                _ => units.force().to_string(),
            };
            ui.label(format!(
                "{} extreme {} {unit} on {} at {x:.2} of its length",
                d.letter(),
                num(v),
                model.element_label(e)
            ));
        }
    }
    if let Some(p) = look.pinned {
        ui.separator();
        ui.label(RichText::new("Selected").strong());
        for line in describe(model, r, p, units, look.angles) {
            ui.label(line);
        }
    }
}

/// "sticks" or "slips" in the colour the viewport rings the node with.
fn grip_label(f: Friction) -> RichText {
    match f {
        Friction::Sticking => RichText::new("sticks").color(STICK),
        Friction::Slipping => RichText::new("slips").color(SLIP),
        Friction::Frictionless => RichText::new("none"),
    }
}
