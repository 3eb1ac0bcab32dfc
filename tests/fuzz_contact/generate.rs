//! Random contact scenes for the campaign: a pin pushed onto a beam, a beam's tip pushed onto
//! another beam, and a pin dragged across two beams (a transfer), with gaps from zero to large,
//! both formulations and random prescribed steps and loads (a third with a distributed load on
//! one beam, fixed or following it). Each scene comes with its own plain description (node
//! positions, bodies, element ends, candidates, loads), which the checker reads instead of the
//! solver's model.

use std::collections::HashMap;
use std::fmt::Write;

use crate::common::Rng;

/// One generated scene: its RON text and what the checker needs to know of it.
pub struct Spec {
    /// Which generator made it.
    pub family: &'static str,
    /// The scene file.
    pub text: String,
    /// Initial position of every node.
    pub coords: HashMap<u32, [f64; 2]>,
    /// Node ids of each body, in order along it; then one group per free pin.
    pub groups: Vec<Vec<u32>>,
    /// Element ends (i, j) in the scene's element order, with the body (group) they belong to.
    pub elements: Vec<(usize, u32, u32)>,
    /// Contact candidates: (node, body) pairs.
    pub candidates: Vec<(u32, usize)>,
    /// Applied loads per unit load factor: node, (fx, fy, m).
    pub loads: Vec<(u32, [f64; 3])>,
    /// Uniform distributed loads per unit load factor: body, (qx, qy) per undeformed length,
    /// or for a follower (along, across) each chord per current length, and whether it
    /// follows.
    pub distributed: Vec<(usize, [f64; 2], bool)>,
    /// The gap between the pushed node and the beam it is pushed onto at the start, over the
    /// scene's length.
    pub gap: f64,
}

/// Uniform in [a, b).
fn uniform(rng: &mut Rng, a: f64, b: f64) -> f64 {
    a + (b - a) * 0.5 * (rng.next() + 1.0)
}

/// An index in 0..n.
fn pick(rng: &mut Rng, n: usize) -> usize {
    ((0.5 * (rng.next() + 1.0) * n as f64) as usize).min(n - 1)
}

/// A gap from zero to large, relative to the length `l`.
fn gap(rng: &mut Rng, l: f64) -> f64 {
    match pick(rng, 5) {
        0 => 0.0,
        1 => 1e-12 * l,
        2 => 1e-6 * l,
        _ => uniform(rng, 1e-3, 0.2) * l,
    }
}

/// Collects the parts of a scene as they are made.
struct Builder {
    spec: Spec,
    bodies: Vec<String>,
    names: Vec<String>,
    pins: Vec<String>,
    supports: Vec<String>,
    prescribed: Vec<String>,
    next_id: u32,
}

impl Builder {
    fn new(family: &'static str) -> Builder {
        Builder {
            spec: Spec {
                family,
                text: String::new(),
                coords: HashMap::new(),
                groups: Vec::new(),
                elements: Vec::new(),
                candidates: Vec::new(),
                loads: Vec::new(),
                distributed: Vec::new(),
                gap: 0.0,
            },
            bodies: Vec::new(),
            names: Vec::new(),
            pins: Vec::new(),
            supports: Vec::new(),
            prescribed: Vec::new(),
            next_id: 1,
        }
    }

    /// A body along the straight segments of `path`, `n` elements each; returns its node ids.
    fn body(&mut self, path: &[[f64; 2]], n: usize) -> Vec<u32> {
        let b = self.spec.groups.len();
        let name = format!("body {}", b + 1);
        let first = self.next_id;
        let mut ids = vec![first];
        self.spec.coords.insert(first, path[0]);
        for w in path.windows(2) {
            for t in 1..=n {
                let s = t as f64 / n as f64;
                let p = [
                    w[0][0] + s * (w[1][0] - w[0][0]),
                    w[0][1] + s * (w[1][1] - w[0][1]),
                ];
                let id = first + ids.len() as u32;
                self.spec.coords.insert(id, p);
                let prev = *ids.last().unwrap();
                self.spec.elements.push((b, prev, id));
                ids.push(id);
            }
        }
        self.next_id = first + ids.len() as u32;
        let pts: Vec<String> = path
            .iter()
            .map(|p| format!("({:e}, {:e})", p[0], p[1]))
            .collect();
        self.bodies.push(format!(
            r#"(name: "{name}", section: "s", path: [{}], elements: {n}, first_node: {first})"#,
            pts.join(", ")
        ));
        self.names.push(name);
        self.spec.groups.push(ids.clone());
        ids
    }

    /// A pin (a node without rotation) at `p`; returns its id. Call after every body.
    fn pin(&mut self, p: [f64; 2]) -> u32 {
        let id = 100_000 + self.pins.len() as u32;
        self.spec.coords.insert(id, p);
        self.pins.push(format!(
            "(id: {id}, x: {:e}, y: {:e}, rotation: false)",
            p[0], p[1]
        ));
        self.spec.groups.push(vec![id]);
        id
    }

    fn support(&mut self, node: u32, dofs: &str) {
        self.supports.push(format!("(node: {node}, {dofs})"));
    }

    fn drive(&mut self, node: u32, dof: &str, per_step: f64) {
        self.prescribed.push(format!(
            "(node: {node}, dof: {dof}, per_step: {per_step:e})"
        ));
    }

    fn load(&mut self, node: u32, f: [f64; 3]) {
        self.spec.loads.push((node, f));
    }

    fn contact(&mut self, node: u32, body: usize) {
        self.spec.candidates.push((node, body));
    }

    /// The scene text, with a random section and formulation.
    fn finish(mut self, rng: &mut Rng, length: f64, steps: usize) -> Spec {
        let e = 1e7 * 10f64.powf(uniform(rng, -2.0, 2.0));
        let h = length * 10f64.powf(uniform(rng, -3.0, -1.3));
        let b = h * uniform(rng, 1.0, 10.0);
        let formulation = if rng.next() < 0.0 {
            "Timoshenko"
        } else {
            "BernoulliEuler"
        };
        // Loads scaled to the section: a tip force of this size bends a beam of the scene's
        // length by about a tenth of it.
        let scale = e * b * h * h * h / 12.0 / (length * length);
        for l in &mut self.spec.loads {
            for v in &mut l.1 {
                *v *= scale;
            }
            l.1[2] *= length;
        }
        let loads: Vec<String> = (self.spec.loads.iter())
            .map(|(n, f)| format!("(node: {n}, fx: {:e}, fy: {:e}, m: {:e})", f[0], f[1], f[2]))
            .collect();
        // A third of the scenes: a uniform distributed load on one beam, fixed or following
        // it, of about the tip load's size in all (drawn last, so the rest of the scene is
        // that of the same seed without it).
        if rng.next() < -1.0 / 3.0 {
            let body = pick(rng, self.names.len());
            let q = scale / length * uniform(rng, 0.2, 2.0);
            let follower = rng.next() < 0.0;
            let angle = uniform(rng, -3.2, 3.2);
            self.spec
                .distributed
                .push((body, [q * angle.cos(), q * angle.sin()], follower));
        }
        let distributed: Vec<String> = (self.spec.distributed.iter())
            .map(|(b, q, f)| {
                format!(
                    r#"(body: "{}", q: ({:e}, {:e}), follower: {f})"#,
                    self.names[*b], q[0], q[1]
                )
            })
            .collect();
        let mut contacts = String::new();
        for (node, body) in &self.spec.candidates {
            let _ = write!(
                contacts,
                r#"(nodes: [{node}], bodies: ["{}"]), "#,
                self.names[*body]
            );
        }
        self.spec.text = format!(
            r#"(
    name: "{}", formulation: {formulation},
    sections: [(name: "s", E: {e:e}, A: {:e}, I: {:e}, G: {:e})],
    nodes: [{}],
    bodies: [{}],
    supports: [{}],
    loads: [{}],
    distributed: [{}],
    prescribed: [{}],
    contacts: [{contacts}],
    control: (steps: {steps}),
)"#,
            self.spec.family,
            b * h,
            b * h * h * h / 12.0,
            e / 2.6,
            self.pins.join(", "),
            self.bodies.join(", "),
            self.supports.join(", "),
            loads.join(", "),
            distributed.join(", "),
            self.prescribed.join(", "),
        );
        self.spec
    }
}

/// A cantilever's path from the origin: one or two straight segments of total length `l`.
fn cantilever_path(rng: &mut Rng, l: f64) -> Vec<[f64; 2]> {
    if rng.next() < 0.0 {
        vec![[0.0, 0.0], [l, 0.0]]
    } else {
        let turn = uniform(rng, -0.6, 0.6);
        let a = uniform(rng, 0.3, 0.7) * l;
        vec![
            [0.0, 0.0],
            [a, 0.0],
            [a + (l - a) * turn.cos(), (l - a) * turn.sin()],
        ]
    }
}

/// A pin beside a cantilever (or a simply supported beam), pushed onto it and along it.
fn pin_on_beam(rng: &mut Rng) -> Spec {
    let mut s = Builder::new("pin on a beam");
    let l = 10f64.powf(uniform(rng, -1.0, 1.0));
    let path = cantilever_path(rng, l);
    let ids = s.body(&path, 2 + pick(rng, 9));
    if rng.next() < 0.5 {
        s.support(ids[0], "u: true, v: true, phi: true");
    } else {
        s.support(ids[0], "u: true, v: true");
        s.support(*ids.last().unwrap(), "v: true");
    }
    // A station on the body, not at its ends, and the side the pin starts on.
    let k = 1 + pick(rng, ids.len() - 2);
    let (p, q) = (s.spec.coords[&ids[k - 1]], s.spec.coords[&ids[k]]);
    let t = uniform(rng, 0.05, 0.95);
    let (dx, dy) = (q[0] - p[0], q[1] - p[1]);
    let len = dx.hypot(dy);
    let n = [-dy / len, dx / len];
    let side = if rng.next() < 0.0 { -1.0 } else { 1.0 };
    let g = gap(rng, l);
    s.spec.gap = g / l;
    let at = [
        p[0] + t * dx + side * g * n[0],
        p[1] + t * dy + side * g * n[1],
    ];
    let pin = s.pin(at);
    s.contact(pin, 0);
    let push = uniform(rng, 0.005, 0.05) * l;
    let slide = uniform(rng, -0.03, 0.03) * l;
    s.drive(pin, "U", -side * push * n[0] + slide * n[1]);
    s.drive(pin, "V", -side * push * n[1] - slide * n[0]);
    if rng.next() < -0.5 {
        s.load(*ids.last().unwrap(), [0.0, 0.1 * rng.next(), 0.0]);
    }
    let steps = 2 + pick(rng, 12);
    s.finish(rng, l, steps)
}

/// Two cantilevers: the tip of the upper one is pushed (by a prescribed displacement or a
/// load) onto the lower one; sometimes the lower tip is a candidate on the upper beam too.
fn beam_on_beam(rng: &mut Rng) -> Spec {
    let mut s = Builder::new("beam on a beam");
    let l = 10f64.powf(uniform(rng, -1.0, 1.0));
    let lower = s.body(&[[0.0, 0.0], [l, 0.0]], 2 + pick(rng, 9));
    let x_tip = uniform(rng, 0.3, 0.95) * l;
    let h = gap(rng, l);
    s.spec.gap = h / l;
    let rise = uniform(rng, 0.0, 0.3) * l;
    let upper_len = uniform(rng, 0.4, 1.0) * l;
    let start = [
        x_tip - (upper_len * upper_len - rise * rise).sqrt(),
        h + rise,
    ];
    let upper = s.body(&[start, [x_tip, h]], 2 + pick(rng, 9));
    s.support(lower[0], "u: true, v: true, phi: true");
    s.support(upper[0], "u: true, v: true, phi: true");
    let tip = *upper.last().unwrap();
    s.contact(tip, 0);
    if rng.next() < 0.0 {
        s.contact(*lower.last().unwrap(), 1);
    }
    if rng.next() < 0.0 {
        s.drive(tip, "V", -uniform(rng, 0.005, 0.04) * l);
    } else {
        s.load(tip, [0.0, -uniform(rng, 0.5, 5.0), 0.0]);
    }
    let steps = 2 + pick(rng, 12);
    s.finish(rng, l, steps)
}

/// Two cantilevers end to end with a gap between their tips, and a pin pressed onto the first
/// and dragged across toward the second: sliding, slide-off and transfer between bodies.
fn pin_across_two_beams(rng: &mut Rng) -> Spec {
    let mut s = Builder::new("pin across two beams");
    let l = 10f64.powf(uniform(rng, -1.0, 1.0));
    let opening = uniform(rng, 0.0, 0.2) * l;
    let a = s.body(&[[0.0, 0.0], [l, 0.0]], 2 + pick(rng, 9));
    let b = s.body(
        &[[2.0 * l + opening, 0.0], [l + opening, 0.0]],
        2 + pick(rng, 9),
    );
    s.support(a[0], "u: true, v: true, phi: true");
    s.support(b[0], "u: true, v: true, phi: true");
    let g = gap(rng, l);
    s.spec.gap = g / l;
    let pin = s.pin([uniform(rng, 0.3, 0.9) * l, g]);
    s.contact(pin, 0);
    s.contact(pin, 1);
    s.drive(pin, "U", uniform(rng, 0.0, 0.1) * l);
    s.drive(pin, "V", -uniform(rng, 0.002, 0.03) * l);
    let steps = 2 + pick(rng, 14);
    s.finish(rng, l, steps)
}

/// The scene of seed `seed`.
pub fn scene(seed: u64) -> Spec {
    let mut rng = Rng(seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1);
    for _ in 0..4 {
        rng.next();
    }
    match pick(&mut rng, 3) {
        0 => pin_on_beam(&mut rng),
        1 => beam_on_beam(&mut rng),
        _ => pin_across_two_beams(&mut rng),
    }
}
