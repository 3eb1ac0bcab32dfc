//! What the pointer is on, and what it carries: the node or element nearest the pointer (within
//! a few points), and its values at the viewed increment in the scene's units, for the hover
//! tooltip and the details panel's "Selected" section.

use egui::Pos2;

use crate::app::display::num;
use crate::app::display::{Angles, Picked};
use crate::figure::{value_at, Diagram};
use crate::scene::units::Units;
use crate::solver::{Dof, IncrementRecord, Model};

/// Points within which the pointer is on a node.
const NODE_REACH: f32 = 8.0;

/// Points within which the pointer is on an element.
const ELEMENT_REACH: f32 = 6.0;

/// The node, else the element, under screen point `at` at record `r` (`s`: world to screen).
pub fn pick(
    model: &Model,
    r: &IncrementRecord,
    at: Pos2,
    s: &dyn Fn([f64; 2]) -> Pos2,
) -> Option<Picked> {
    let screen = |n: usize| s([r.nodes[n][0], r.nodes[n][1]]);
    let node = (0..model.nodes.len())
        .map(|n| (n, screen(n).distance(at)))
        .filter(|&(_, d)| d <= NODE_REACH)
        .min_by(|a, b| a.1.total_cmp(&b.1));
    if let Some((n, _)) = node {
        return Some(Picked::Node(n));
    }
    (model.beams.iter().enumerate())
        .map(|(e, b)| (e, segment_distance(at, screen(b.i), screen(b.j))))
        .filter(|&(_, d)| d <= ELEMENT_REACH)
        .min_by(|a, b| a.1.total_cmp(&b.1))
        .map(|(e, _)| Picked::Element(e))
}

/// Distance from `p` to the segment `a`-`b`.
fn segment_distance(p: Pos2, a: Pos2, b: Pos2) -> f32 {
    let ab = b - a;
    let t = ((p - a).dot(ab) / ab.length_sq().max(1e-12)).clamp(0.0, 1.0);
    p.distance(a + ab * t)
}

/// The lines that describe `picked` at record `r`.
pub fn describe(
    model: &Model,
    r: &IncrementRecord,
    picked: Picked,
    units: Units,
    angles: Angles,
) -> Vec<String> {
    match picked {
        Picked::Node(n) => node_lines(model, r, n, units, angles),
        Picked::Element(e) => element_lines(model, r, e, units),
    }
}

fn node_lines(
    model: &Model,
    r: &IncrementRecord,
    n: usize,
    units: Units,
    angles: Angles,
) -> Vec<String> {
    let node = &model.nodes[n];
    let (len, force) = (units.length(), units.force());
    let p = r.nodes[n];
    let owner = (model.beams.iter())
        .find(|b| b.i == n || b.j == n)
        .map_or(" (a pin)".to_string(), |b| {
            format!(" of {}", model.bodies[b.body].name)
        });
    let mut lines = vec![
        format!("node {}{owner}", node.id),
        format!("x = {} {len}, y = {} {len}", num(p[0]), num(p[1])),
        format!(
            "u = {} {len}, v = {} {len}",
            num(p[0] - node.x),
            num(p[1] - node.y)
        ),
    ];
    if node.rotation {
        lines.push(format!("phi = {}", angles.show(p[2])));
    }
    for x in r.reactions.iter().filter(|x| x.node == node.id) {
        let dof = Dof::ALL.iter().find(|d| d.name() == x.dof).copied();
        let unit = dof.map_or(force.to_string(), |d| units.of_reaction(d));
        lines.push(format!("reaction {} = {} {unit}", x.dof, num(x.value)));
    }
    for load in model.loads.iter().filter(|l| l.node == n) {
        let f = load.force.map(|v| v * r.load_factor);
        lines.push(format!(
            "load fx = {} {force}, fy = {} {force}, m = {} {}",
            num(f[0]),
            num(f[1]),
            num(f[2]),
            units.moment()
        ));
    }
    for c in r.contacts.iter().filter(|c| c.node == node.id) {
        lines.push(format!(
            "contact on {}, li/l = {:.4}, Yc = {} {force}",
            model.element_label(c.element),
            c.xi,
            num(c.force)
        ));
    }
    lines
}

fn element_lines(model: &Model, r: &IncrementRecord, e: usize, units: Units) -> Vec<String> {
    let beam = &model.beams[e];
    let (force, moment) = (units.force(), units.moment());
    let (a, b) = (r.nodes[beam.i], r.nodes[beam.j]);
    let l = (b[0] - a[0]).hypot(b[1] - a[1]);
    let l0 = model.beam_length(e);
    let at = |d: Diagram, x: f64| num(value_at(model, r, d, e, x));
    let (ni, nj) = (model.nodes[beam.i].id, model.nodes[beam.j].id);
    let mut lines = vec![
        format!("{} (nodes {ni}-{nj})", model.element_label(e)),
        format!("N = {} {force}", at(Diagram::Axial, 0.0)),
        format!(
            "V = {} {force} at node {ni}, {} {force} at node {nj}",
            at(Diagram::Shear, 0.0),
            at(Diagram::Shear, 1.0)
        ),
        format!(
            "M = {} {moment} at node {ni}, {} {moment} at node {nj}",
            at(Diagram::Moment, 0.0),
            at(Diagram::Moment, 1.0)
        ),
        format!("stretch (l - l0)/l0 = {}", num((l - l0) / l0)),
    ];
    for c in r.contacts.iter().filter(|c| c.element == e) {
        lines.push(format!(
            "contact of node {}, li/l = {:.4}, Yc = {} {force}",
            c.node,
            c.xi,
            num(c.force)
        ));
    }
    lines
}
