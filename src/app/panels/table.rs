//! The table window: the nodes, elements, contacts or reactions of the viewed increment, one
//! row each, in the scene's units, sorted by any column (a click on its header; again to turn
//! the order). Only the rows in view are laid out, so a large model scrolls freely.

use egui::RichText;

use crate::app::display::num;
use crate::app::display::{Rows, TableView};
use crate::app::parts::{Look, Study};
use crate::figure::{value_at, Diagram};
use crate::solver::{IncrementRecord, Model};

/// A row: its cells as text, and the numbers it sorts by (NaN for a text column).
struct Row {
    cells: Vec<String>,
    keys: Vec<f64>,
}

/// The headers and rows of `rows` at record `r`.
fn table(
    model: &Model,
    r: &IncrementRecord,
    rows: Rows,
    units: crate::scene::units::Units,
) -> (Vec<String>, Vec<Row>) {
    let (len, force, moment) = (units.length(), units.force(), units.moment());
    let row = |cells: Vec<String>, keys: Vec<f64>| Row { cells, keys };
    match rows {
        Rows::Nodes => (
            vec![
                "node".into(),
                format!("x ({len})"),
                format!("y ({len})"),
                format!("u ({len})"),
                format!("v ({len})"),
                "phi (rad)".into(),
            ],
            (model.nodes.iter().zip(&r.nodes))
                .map(|(n, p)| {
                    let k = [n.id as f64, p[0], p[1], p[0] - n.x, p[1] - n.y, p[2]];
                    let mut c = vec![n.id.to_string()];
                    c.extend(k[1..].iter().map(|v| num(*v)));
                    row(c, k.to_vec())
                })
                .collect(),
        ),
        Rows::Elements => (
            vec![
                "element".into(),
                format!("N ({force})"),
                format!("V ({force})"),
                format!("M at i ({moment})"),
                format!("M at j ({moment})"),
                "stretch".into(),
            ],
            (0..model.beams.len())
                .map(|e| {
                    let b = &model.beams[e];
                    let (a, c) = (r.nodes[b.i], r.nodes[b.j]);
                    let l = (c[0] - a[0]).hypot(c[1] - a[1]);
                    let k = [
                        e as f64,
                        value_at(model, r, Diagram::Axial, e, 0.0),
                        value_at(model, r, Diagram::Shear, e, 0.0),
                        value_at(model, r, Diagram::Moment, e, 0.0),
                        value_at(model, r, Diagram::Moment, e, 1.0),
                        l / model.beam_length(e) - 1.0,
                    ];
                    let mut cells = vec![model.element_label(e)];
                    cells.extend(k[1..].iter().map(|v| num(*v)));
                    row(cells, k.to_vec())
                })
                .collect(),
        ),
        Rows::Contacts => (
            vec![
                "node".into(),
                "on".into(),
                "li/l".into(),
                format!("Yc ({force})"),
            ],
            (r.contacts.iter())
                .map(|c| {
                    let cells = vec![
                        c.node.to_string(),
                        model.element_label(c.element),
                        format!("{:.4}", c.xi),
                        num(c.force),
                    ];
                    row(cells, vec![c.node as f64, c.element as f64, c.xi, c.force])
                })
                .collect(),
        ),
        Rows::Reactions => (
            vec!["node".into(), "dof".into(), "reaction".into()],
            (r.reactions.iter())
                .map(|x| {
                    let unit = if x.dof == "phi" {
                        moment.clone()
                    } else {
                        force.to_string()
                    };
                    let cells = vec![
                        x.node.to_string(),
                        x.dof.clone(),
                        format!("{} {unit}", num(x.value)),
                    ];
                    row(cells, vec![x.node as f64, f64::NAN, x.value])
                })
                .collect(),
        ),
    }
}

/// Show the table window while it is open.
pub fn window(study: &Study, selected: usize, look: &mut Look, ctx: &egui::Context) {
    let mut view = look.table;
    if !view.open {
        return;
    }
    let (Some(l), Some(r)) = (&study.loaded, study.record(selected)) else {
        return;
    };
    let (model, units) = (&l.scene.model, l.scene.file.units);
    let title = format!("Table: increment {}", r.increment);
    let mut open = true;
    egui::Window::new("Table")
        .title_bar(true)
        .open(&mut open)
        .default_size([560.0, 360.0])
        .min_height(320.0)
        .show(ctx, |ui| {
            ui.label(RichText::new(title).strong());
            ui.horizontal(|ui| {
                for (rows, name) in [
                    (Rows::Nodes, "Nodes"),
                    (Rows::Elements, "Elements"),
                    (Rows::Contacts, "Contacts"),
                    (Rows::Reactions, "Reactions"),
                ] {
                    if ui.selectable_label(view.rows == rows, name).clicked() && view.rows != rows {
                        view = TableView {
                            rows,
                            column: 0,
                            descending: false,
                            ..view
                        };
                    }
                }
            });
            let (headers, mut rows) = table(model, r, view.rows, units);
            let c = view.column.min(headers.len() - 1);
            rows.sort_by(|a, b| {
                let o = a.keys[c].abs().total_cmp(&b.keys[c].abs());
                if view.descending {
                    o.reverse()
                } else {
                    o
                }
            });
            let columns = headers.len();
            egui::Grid::new("table headers")
                .num_columns(columns)
                .min_col_width(80.0)
                .show(ui, |ui| {
                    for (k, h) in headers.iter().enumerate() {
                        let mark = match (k == c, view.descending) {
                            (true, true) => " v",
                            (true, false) => " ^",
                            _ => "",
                        };
                        if ui
                            .button(format!("{h}{mark}"))
                            .on_hover_text("sort by the size of this column")
                            .clicked()
                        {
                            view.descending = if k == c { !view.descending } else { true };
                            view.column = k;
                        }
                    }
                });
            let height = ui.text_style_height(&egui::TextStyle::Body) + 4.0;
            egui::ScrollArea::vertical()
                .auto_shrink([false, false])
                .show_rows(ui, height, rows.len(), |ui, range| {
                    egui::Grid::new("table rows")
                        .num_columns(columns)
                        .min_col_width(80.0)
                        .striped(true)
                        .show(ui, |ui| {
                            for row in &rows[range] {
                                for cell in &row.cells {
                                    ui.label(cell);
                                }
                                ui.end_row();
                            }
                        });
                });
        });
    view.open = open;
    look.table = view;
}
