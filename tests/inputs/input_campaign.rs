//! A seeded campaign of scene inputs, good and bad, over every section of the format: each case
//! changes one entry of a valid scene (one field per line) and carries its expected verdict,
//! accepted, or refused with a message that names the field's path and its line. Bad values
//! are drawn from the classes users make: signs, zeros, overflow (1e300 and products of
//! sizes that overflow), names and nodes that do not exist, wrong types, typos. Accepted
//! scenes build a solver and take a step. No case may panic.

use std::panic::{catch_unwind, AssertUnwindSafe};

use crate::common::Rng;
use tsm_contact::history::History;
use tsm_contact::scene::parse;

/// The valid scene every case starts from: a cantilever pressed by a pin onto a second beam
/// and a floor, with a load, a distributed load, gravity and two stages.
#[rustfmt::skip]
const BASE: &[&str] = &[
    "(",
    "    name: \"campaign\",",
    "    formulation: Timoshenko,",
    "    sections: [",
    "        (name: \"s\", E: 2.0e7, A: 3.0e-4, I: 2.2e-8, G: 7.0e6, density: 1000.0),",
    "    ],",
    "    nodes: [",
    "        (id: 100, x: 0.8, y: 0.002, rotation: false),",
    "    ],",
    "    bodies: [",
    "        (name: \"A\", section: \"s\", path: [(0.0, 0.0), (1.0, 0.0)], elements: 8, first_node: 1),",
    "        (name: \"B\", section: \"s\", path: [(0.5, -0.1), (1.5, -0.1)], elements: 8, first_node: 20),",
    "    ],",
    "    supports: [",
    "        (node: 1, u: true, v: true, phi: true),",
    "        (node: 28, u: true, v: true, phi: true),",
    "        (node: 100, u: true),",
    "    ],",
    "    loads: [",
    "        (node: 5, fx: 0.0, fy: -0.01, m: 0.0, group: \"push\"),",
    "    ],",
    "    prescribed: [",
    "        (node: 100, dof: V, per_step: -0.01),",
    "    ],",
    "    distributed: [",
    "        (body: \"B\", elements: (1, 4), q: (0.0, -0.02)),",
    "    ],",
    "    contacts: [",
    "        (nodes: [100], bodies: [\"A\", \"B\"], mu: 0.1),",
    "        (node_bodies: [\"A\"], bodies: [\"B\"]),",
    "    ],",
    "    obstacles: [",
    "        (name: \"floor\", shape: Line(from: (0.0, -0.3), to: (2.0, -0.3)), bodies: [\"A\", \"B\"], mu: 0.2),",
    "        (name: \"peg\", shape: Circle(centre: (1.3, 0.2), radius: 0.05), bodies: [\"B\"]),",
    "    ],",
    "    control: (",
    "        steps: 10,",
    "        tolerance: 1e-8,",
    "        max_step: 1.0,",
    "        gravity: (0.0, -9.81),",
    "        obstacle_gap: 1e-12,",
    "    ),",
    "    stages: [",
    "        (name: \"press\", steps: 3, prescribed: [(node: 100, dof: V, by: -0.03)]),",
    "        (name: \"push\", steps: 2, loads: [(group: \"push\", to: 1.0)]),",
    "    ],",
    ")",
];

/// The tests' reproducible random sequence, drawn in [0, 1).
struct Draw(Rng);

impl Draw {
    fn next(&mut self) -> f64 {
        0.5 * (self.0.next() + 1.0)
    }

    /// `lo * (hi / lo)^u`: a value spread evenly in magnitude between `lo` and `hi`.
    fn between(&mut self, lo: f64, hi: f64) -> f64 {
        lo * (hi / lo).powf(self.next())
    }
}

/// What a number may be drawn as.
#[derive(Clone, Copy)]
enum Number {
    /// Positive and finite: refused at zero, below it, and at 1e100 or more.
    Positive(f64),
    /// Any sign: refused at a magnitude of 1e100 or more.
    Signed(f64),
    /// Zero or more: refused below zero and at 1e100 or more.
    NonNegative(f64),
}

/// A bad value of `kind` and a good one near `base`.
fn number(d: &mut Draw, kind: Number, good: bool) -> String {
    let huge = |d: &mut Draw| d.between(1e100, 1e300);
    let sign = |d: &mut Draw| if d.next() < 0.5 { -1.0 } else { 1.0 };
    let v = match (kind, good) {
        (Number::Positive(b) | Number::NonNegative(b), true) => b * d.between(0.5, 2.0),
        (Number::Signed(b), true) => b * d.between(0.5, 2.0) * sign(d),
        (Number::Positive(_), false) => match (d.next() * 3.0) as usize {
            0 => 0.0,
            1 => -d.between(1e-6, 1e6),
            _ => huge(d),
        },
        (Number::NonNegative(_), false) => match (d.next() * 2.0) as usize {
            0 => -d.between(1e-6, 1e6),
            _ => huge(d),
        },
        (Number::Signed(_), false) => huge(d) * sign(d),
    };
    format!("{v:e}")
}

/// One family of cases: on the line containing `line`, the text `from` becomes a drawn value
/// (`Drawn`: a number drawn bad or good; `Refused`, `Accepted`: listed texts), which is
/// refused naming `field` at that line (`field@anchor`: at the line holding the anchor, where
/// the cause lies elsewhere; a syntax error names the field's last name), or accepted.
struct Family {
    line: &'static str,
    from: &'static str,
    field: &'static str,
    values: Values,
}

enum Values {
    /// A number `from = <value>`: bad and good ones drawn.
    Drawn(Number),
    /// Replacement texts that are all refused.
    Refused(&'static [&'static str]),
    /// Replacement texts that are all accepted.
    Accepted(&'static [&'static str]),
}

use Number::*;
use Values::*;

#[rustfmt::skip]
const FAMILIES: &[Family] = &[
    // Sections.
    Family { line: "(name: \"s\"", from: "E: 2.0e7", field: "sections[0].E", values: Drawn(Positive(2.0e7)) },
    Family { line: "(name: \"s\"", from: "A: 3.0e-4", field: "sections[0].A", values: Drawn(Positive(3.0e-4)) },
    Family { line: "(name: \"s\"", from: "I: 2.2e-8", field: "sections[0].I", values: Drawn(Positive(2.2e-8)) },
    Family { line: "(name: \"s\"", from: "G: 7.0e6", field: "sections[0].G", values: Drawn(Positive(7.0e6)) },
    Family { line: "(name: \"s\"", from: "density: 1000.0", field: "sections[0].density", values: Drawn(NonNegative(1000.0)) },
    Family { line: "(name: \"s\"", from: "name: \"s\"", field: "bodies[0].section@(name: \"A\"", values: Refused(&["name: \"\"", "name: \"t\""]) },
    Family { line: "(name: \"s\"", from: "name: \"s\"", field: "sections[0].nam", values: Refused(&["nam: \"s\""]) },
    // Nodes.
    Family { line: "(id: 100", from: "x: 0.8", field: "nodes[0].x", values: Drawn(Signed(0.8)) },
    Family { line: "(id: 100", from: "y: 0.002", field: "nodes[0].y", values: Refused(&["y: 1e300", "y: -1e150", "y: \"high\""]) },
    Family { line: "(id: 100", from: "y: 0.002", field: "nodes[0].y", values: Accepted(&["y: 2", "y: 0.01"]) },
    Family { line: "(id: 100", from: "id: 100", field: "nodes[0].id", values: Refused(&["id: -3", "id: 1.5"]) },
    Family { line: "(id: 100", from: "id: 100", field: "bodies[0].first_node@(name: \"A\"", values: Refused(&["id: 5"]) },
    Family { line: "(id: 100", from: "id: 100", field: "bodies[1].first_node@(name: \"B\"", values: Refused(&["id: 20"]) },
    // Bodies.
    Family { line: "(name: \"A\"", from: "elements: 8", field: "bodies[0].elements", values: Refused(&["elements: 0", "elements: -2", "elements: 2.5", "elements: 99999999999999999999"]) },
    Family { line: "(name: \"A\"", from: "elements: 8", field: "bodies[0].elements", values: Accepted(&["elements: 4", "elements: 12", "elements: 16"]) },
    Family { line: "(name: \"A\"", from: "section: \"s\"", field: "bodies[0].section", values: Refused(&["section: \"t\"", "section: \"\"", "section: \"S\""]) },
    Family { line: "(name: \"A\"", from: "path: [(0.0, 0.0), (1.0, 0.0)]", field: "bodies[0].path", values: Refused(&["path: [(0.0, 0.0)]", "path: []", "path: [(0.0, 0.0), (0.0, 0.0)]", "path: [(0.0, 0.0), (1e300, 0.0)]"]) },
    Family { line: "(name: \"A\"", from: "path: [(0.0, 0.0), (1.0, 0.0)]", field: "bodies[0] (body \"A\")", values: Refused(&["path: [(-1e99, 0.0), (1e99, 0.0)]"]) },
    Family { line: "(name: \"A\"", from: "first_node: 1)", field: "bodies[0].first_node", values: Refused(&["first_node: 100)"]) },
    Family { line: "(name: \"A\"", from: "first_node: 1)", field: "bodies[1].first_node@(name: \"B\"", values: Refused(&["first_node: 24)"]) },
    Family { line: "(name: \"A\"", from: "first_node: 1)", field: "bodies[0].first_node", values: Accepted(&["first_node: 0)"]) },
    Family { line: "(name: \"B\"", from: "name: \"B\"", field: "bodies[1].name", values: Refused(&["name: \"A\""]) },
    // Supports.
    Family { line: "(node: 1, u: true", from: "node: 1,", field: "supports[0].node", values: Refused(&["node: 99,", "node: 0,", "node: 5000,"]) },
    Family { line: "(node: 100, u: true)", from: "u: true", field: "supports[2].u", values: Refused(&["u: yes", "u: 1"]) },
    Family { line: "(node: 100, u: true)", from: "u: true", field: "supports[2].w", values: Refused(&["w: true"]) },
    // Loads.
    Family { line: "(node: 5, fx", from: "fy: -0.01", field: "loads[0].fy", values: Drawn(Signed(-0.01)) },
    Family { line: "(node: 5, fx", from: "fx: 0.0", field: "loads[0].fx", values: Refused(&["fx: 1e300", "fx: -2e200", "fx: inf", "fx: NaN"]) },
    Family { line: "(node: 5, fx", from: "m: 0.0", field: "loads[0].m", values: Refused(&["m: 1e120", "m: -1e101"]) },
    Family { line: "(node: 5, fx", from: "node: 5,", field: "loads[0].node", values: Refused(&["node: 77,", "node: 0,"]) },
    // Prescribed.
    Family { line: "(node: 100, dof: V, per_step", from: "per_step: -0.01", field: "prescribed[0].per_step", values: Refused(&["per_step: 1e300", "per_step: -1e300", "per_step: inf"]) },
    Family { line: "(node: 100, dof: V, per_step", from: "node: 100,", field: "prescribed[0].node", values: Refused(&["node: 101,"]) },
    Family { line: "(node: 100, dof: V, per_step", from: "node: 100,", field: "prescribed[0] (node 1 v)", values: Refused(&["node: 1,"]) },
    Family { line: "(node: 100, dof: V, per_step", from: "dof: V", field: "prescribed[0].dof", values: Refused(&["dof: W", "dof: v"]) },
    // Distributed loads.
    Family { line: "(body: \"B\"", from: "q: (0.0, -0.02)", field: "distributed[0].q", values: Refused(&["q: (0.0, -1e300)", "q: (1e200, 0.0)", "q: (0.0, inf)"]) },
    Family { line: "(body: \"B\"", from: "body: \"B\"", field: "distributed[0].body", values: Refused(&["body: \"C\"", "body: \"\""]) },
    Family { line: "(body: \"B\"", from: "elements: (1, 4)", field: "distributed[0].elements", values: Refused(&["elements: (4, 1)", "elements: (0, 4)", "elements: (1, 9)"]) },
    Family { line: "(body: \"B\"", from: "elements: (1, 4)", field: "distributed[0].elements", values: Accepted(&["elements: (1, 8)", "elements: (2, 2)", "elements: (3, 7)"]) },
    // Contacts.
    Family { line: "(nodes: [100]", from: "mu: 0.1", field: "contacts[0].mu", values: Refused(&["mu: -0.1", "mu: 1e300", "mu: inf"]) },
    Family { line: "(nodes: [100]", from: "mu: 0.1", field: "contacts[0].mu", values: Accepted(&["mu: 0.0", "mu: 0.5", "mu: 1.0"]) },
    Family { line: "(nodes: [100]", from: "bodies: [\"A\", \"B\"]", field: "contacts[0].bodies", values: Refused(&["bodies: [\"A\", \"Q\"]", "bodies: []"]) },
    Family { line: "(nodes: [100]", from: "nodes: [100]", field: "contacts[0].nodes", values: Refused(&["nodes: [1234]"]) },
    Family { line: "(node_bodies: [\"A\"]", from: "node_bodies: [\"A\"]", field: "contacts[1].node_bodies", values: Refused(&["node_bodies: [\"Z\"]"]) },
    // Obstacles.
    Family { line: "(name: \"floor\"", from: "mu: 0.2", field: "obstacles[0].mu", values: Refused(&["mu: -1.0", "mu: 1e101"]) },
    Family { line: "(name: \"floor\"", from: "to: (2.0, -0.3)", field: "obstacles[0].shape", values: Refused(&["to: (0.0, -0.3)", "to: (1e300, -0.3)", "to: (1.7e308, -0.3)"]) },
    Family { line: "(name: \"floor\"", from: "bodies: [\"A\", \"B\"]", field: "obstacles[0].bodies", values: Refused(&["bodies: [\"A\", \"X\"]"]) },
    Family { line: "(name: \"peg\"", from: "radius: 0.05", field: "obstacles[1].shape", values: Refused(&["radius: 0.0", "radius: -0.05", "radius: 1e300"]) },
    Family { line: "(name: \"peg\"", from: "radius: 0.05", field: "obstacles[1] (obstacle \"peg\")", values: Refused(&["radius: 0.5"]) },
    Family { line: "(name: \"peg\"", from: "radius: 0.05", field: "obstacles[1].shape", values: Accepted(&["radius: 0.02", "radius: 0.08"]) },
    // Control.
    Family { line: "steps: 10,", from: "steps: 10", field: "control.steps", values: Refused(&["steps: -1", "steps: 1.5"]) },
    Family { line: "steps: 10,", from: "steps: 10", field: "control.steps", values: Accepted(&["steps: 0", "steps: 1000"]) },
    Family { line: "tolerance: 1e-8", from: "tolerance: 1e-8", field: "control.tolerance", values: Refused(&["tolerance: 0.0", "tolerance: -1e-8", "tolerance: 2.0"]) },
    Family { line: "tolerance: 1e-8", from: "tolerance: 1e-8", field: "control.tolerance", values: Accepted(&["tolerance: 1e-6", "tolerance: 1e-10", "tolerance: 1e-20"]) },
    Family { line: "max_step: 1.0", from: "max_step: 1.0", field: "control.max_step", values: Refused(&["max_step: 0.0", "max_step: -1.0", "max_step: 1e300"]) },
    Family { line: "gravity: (0.0, -9.81)", from: "-9.81", field: "control.gravity", values: Refused(&["-1e300", "1e150"]) },
    Family { line: "obstacle_gap: 1e-12", from: "obstacle_gap: 1e-12", field: "control.obstacle_gap", values: Refused(&["obstacle_gap: -1e-12", "obstacle_gap: 1e300"]) },
    // Stages.
    Family { line: "(name: \"press\"", from: "steps: 3", field: "stages[0].steps", values: Refused(&["steps: 0", "steps: -3"]) },
    Family { line: "(name: \"press\"", from: "by: -0.03", field: "stages[0].prescribed[0]", values: Refused(&["by: 1e300", "to: -0.03, by: -0.03"]) },
    Family { line: "(name: \"press\"", from: "node: 100, dof: V, by", field: "stages[0].prescribed[0]", values: Refused(&["node: 5, dof: V, by", "node: 100, dof: U, by"]) },
    Family { line: "(name: \"push\"", from: "group: \"push\"", field: "stages[1].loads[0].group", values: Refused(&["group: \"pull\"", "group: \"\""]) },
    Family { line: "(name: \"push\"", from: "to: 1.0", field: "stages[1].loads[0]", values: Refused(&["to: 1e300", "to: -inf"]) },
];

/// One case: the scene text, the line changed, what was changed, and its expected verdict
/// (`Some(field)`: refused naming that field at that line; `None`: accepted).
struct Case {
    text: String,
    line: usize,
    change: String,
    refused: Option<&'static str>,
}

/// The base scene with `from` on the line containing `anchor` replaced by `to`.
fn changed(anchor: &str, from: &str, to: &str) -> (String, usize) {
    let k = BASE
        .iter()
        .position(|l| l.contains(anchor))
        .unwrap_or_else(|| panic!("no line has {anchor}"));
    assert!(BASE[k].contains(from), "line {} has no {from}", k + 1);
    let lines: Vec<String> = (BASE.iter().enumerate())
        .map(|(j, l)| {
            if j == k {
                l.replacen(from, to, 1)
            } else {
                l.to_string()
            }
        })
        .collect();
    (lines.join("\n"), k + 1)
}

/// At least `count` cases drawn from `seed`: every listed value of every family once, then
/// drawn numbers, bad and good in turn, over the families that draw them.
fn cases(count: usize, seed: u64) -> Vec<Case> {
    let mut d = Draw(Rng(seed | 1));
    let mut out = Vec::new();
    let push = |out: &mut Vec<Case>, f: &Family, to: String, refused: bool| {
        let (text, line) = changed(f.line, f.from, &to);
        out.push(Case {
            text,
            line,
            change: to,
            refused: refused.then_some(f.field),
        });
    };
    for f in FAMILIES {
        match f.values {
            Refused(list) => list
                .iter()
                .for_each(|v| push(&mut out, f, v.to_string(), true)),
            Accepted(list) => list
                .iter()
                .for_each(|v| push(&mut out, f, v.to_string(), false)),
            Drawn(_) => {}
        }
    }
    let drawn: Vec<&Family> = FAMILIES
        .iter()
        .filter(|f| matches!(f.values, Drawn(_)))
        .collect();
    let mut k = 0;
    while out.len() < count {
        let f = drawn[k % drawn.len()];
        let good = (k / drawn.len()) % 3 == 2;
        let Drawn(kind) = f.values else {
            unreachable!()
        };
        let key = f.from.split(':').next().unwrap_or(f.from);
        let value = number(&mut d, kind, good);
        push(&mut out, f, format!("{key}: {value}"), !good);
        k += 1;
    }
    out
}

/// The verdict on one case: `Ok` when it matches its expectation, else what went wrong.
fn judge(case: &Case) -> Result<String, String> {
    let parsed = catch_unwind(AssertUnwindSafe(|| parse(&case.text, "campaign.ron")))
        .map_err(|_| format!("line {}: `{}`: parse panicked", case.line, case.change))?;
    match (parsed, case.refused) {
        (Err(e), Some(expected)) => {
            // `field@anchor`: the cause lies on the line holding the anchor.
            let (field, line) = match expected.split_once('@') {
                Some((field, anchor)) => {
                    let k = BASE
                        .iter()
                        .position(|l| l.contains(anchor))
                        .expect("anchor");
                    (field, k + 1)
                }
                None => (expected, case.line),
            };
            let msg = e.to_string();
            let at = format!("campaign.ron:{line}:");
            // A syntax error names the key it stopped in: the field's last name.
            let leaf = field.rsplit('.').next().unwrap_or(field);
            let leaf = leaf.split('[').next().unwrap_or(leaf);
            let named = if msg.contains("(syntax)") {
                msg.contains(&format!(": {leaf} (syntax):"))
            } else {
                msg.contains(field)
            };
            if msg.contains(&at) && named {
                Ok(msg)
            } else {
                Err(format!(
                    "line {}: `{}`: the message should name {field} at line {line}: {msg}",
                    case.line, case.change
                ))
            }
        }
        (Ok(_), Some(field)) => Err(format!(
            "line {}: `{}`: accepted, should be refused naming {field}",
            case.line, case.change
        )),
        (Err(e), None) => Err(format!(
            "line {}: `{}`: refused, should be accepted: {e}",
            case.line, case.change
        )),
        (Ok(scene), None) => {
            let stepped = catch_unwind(AssertUnwindSafe(|| {
                scene
                    .solver()
                    .map(|mut s| s.step(&mut History::default()).map(|_| ()))
            }));
            match stepped {
                Err(_) => Err(format!(
                    "line {}: `{}`: the step panicked",
                    case.line, case.change
                )),
                Ok(r) => Ok(format!("accepted ({r:?})")),
            }
        }
    }
}

#[test]
fn four_hundred_inputs_get_their_verdicts_naming_field_and_line() {
    let all = cases(400, 0x5eed_cafe);
    assert!(all.len() >= 400);
    let show = std::env::var("TSM_CAMPAIGN_SHOW").is_ok();
    let mut wrong = Vec::new();
    for case in &all {
        match judge(case) {
            Ok(msg) if show => eprintln!("ok   line {} `{}`: {msg}", case.line, case.change),
            Ok(_) => {}
            Err(why) => wrong.push(why),
        }
    }
    let refused = all.iter().filter(|c| c.refused.is_some()).count();
    eprintln!(
        "{} cases: {refused} to refuse, {} to accept",
        all.len(),
        all.len() - refused
    );
    assert!(
        wrong.is_empty(),
        "{} of {} wrong:\n{}",
        wrong.len(),
        all.len(),
        wrong.join("\n")
    );
}
