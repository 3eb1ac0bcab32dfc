//! The robustness campaign's families (`FAMILIES`, drawn by `mod.rs`): scenes with a plain
//! answer, as scene text on `n` elements per body.

/// A family of scenes with a plain answer.
pub struct Family {
    /// Its name in the report.
    pub name: &'static str,
    /// Its own number of steps.
    pub steps: usize,
    /// The scene on `n` elements per body.
    pub scene: fn(usize) -> String,
    /// Its friction coefficient, where it is the point of the family (else drawn).
    pub mu: Option<f64>,
}

/// The families of the campaign.
pub const FAMILIES: [Family; 7] = [
    Family {
        name: "pin on a mesh node",
        steps: 20,
        scene: pin_on_a_node,
        mu: None,
    },
    Family {
        name: "stacked cantilevers",
        steps: 30,
        scene: stacked_cantilevers,
        mu: None,
    },
    Family {
        name: "bar on a rough beam floor",
        steps: 10,
        scene: bar_on_a_beam_floor,
        mu: Some(0.3),
    },
    Family {
        name: "bar on a rough line",
        steps: 10,
        scene: bar_on_a_line,
        mu: Some(0.3),
    },
    Family {
        name: "a pin pressing two cantilevers",
        steps: 24,
        scene: pin_on_two_cantilevers,
        mu: None,
    },
    Family {
        name: "a pin with a radius",
        steps: 20,
        scene: pin_with_a_radius,
        mu: None,
    },
    Family {
        name: "thick strips",
        steps: 30,
        scene: thick_strips,
        mu: None,
    },
];

/// A steel bar of `n` elements lying on a clamped floor beam (zero gap, declared above it),
/// its left end held along the floor, under its own weight.
pub(crate) fn bar_on_a_beam_floor(n: usize) -> String {
    bar_on(
        n,
        r#"(name: "floor", section: "floor", path: [(0.0, 0.0), (1.2, 0.0)], elements: 12, first_node: 1001),"#,
        r#"(node: 1001, u: true, v: true, phi: true), (node: 1013, u: true, v: true, phi: true),"#,
        r#"contacts: [(node_bodies: ["bar"], bodies: ["floor"], side: Left)],"#,
    )
}

/// The bar of `bar_on_a_beam_floor` on a rigid line instead.
pub(crate) fn bar_on_a_line(n: usize) -> String {
    bar_on(
        n,
        "",
        "",
        r#"obstacles: [(name: "floor", shape: Line(from: (0.0, 0.0), to: (1.2, 0.0)), bodies: ["bar"])],"#,
    )
}

/// The bar with a floor body, its supports, and the contact or obstacle entry.
fn bar_on(n: usize, floor: &str, held: &str, contact: &str) -> String {
    format!(
        r#"(
    name: "bar on a floor", units: N_m, formulation: BernoulliEuler,
    sections: [(name: "bar", E: 2.0e11, A: 1.0e-4, I: 8.3333e-10, density: 7850.0),
               (name: "floor", E: 2.0e11, A: 1.0e-3, I: 8.3333e-8)],
    bodies: [(name: "bar", section: "bar", path: [(0.1, 0.0), (1.1, 0.0)], elements: {n}, first_node: 1),
             {floor}],
    supports: [{held} (node: 1, u: true)],
    {contact}
    control: (steps: 10, gravity: (0.0, -9.81)),
)"#
    )
}

/// A pin pressed onto the midspan node of a pinned-pinned beam of `n` elements (n even), EA =
/// 1e3 EI / L^2.
pub(crate) fn pin_on_a_node(n: usize) -> String {
    format!(
        r#"(
    name: "pin on a mesh node",
    sections: [(name: "s", E: 1.0, A: 1.0e3, I: 1.0, G: 400.0)],
    nodes: [(id: 100000, x: 0.5, y: 0.001, rotation: false)],
    bodies: [(name: "beam", section: "s", path: [(0.0, 0.0), (1.0, 0.0)], elements: {n}, first_node: 1)],
    supports: [(node: 1, u: true, v: true), (node: {last}, u: true, v: true), (node: 100000, u: true)],
    prescribed: [(node: 100000, dof: V, per_step: -0.01)],
    contacts: [(nodes: [100000], bodies: ["beam"])],
    control: (steps: 20),
)"#,
        last = n + 1
    )
}

/// A pin 2 cm above a cantilever of `n` elements (clamped at x = 0) driven 0.48 m down at
/// x = 0.6, pressing it onto a second cantilever of `n` elements 5 cm below, clamped at
/// x = 1.2 and reaching back to x = 0.2: the upper one's tip slides along the lower one, and
/// each beam's nodes may touch the other.
pub(crate) fn pin_on_two_cantilevers(n: usize) -> String {
    format!(
        r#"(
    name: "a pin pressing two cantilevers",
    sections: [(name: "s", E: 1.0, A: 1.0e6, I: 1.0, G: 0.4)],
    nodes: [(id: 100000, x: 0.6, y: 0.02, rotation: false)],
    bodies: [
        (name: "upper", section: "s", path: [(0.0, 0.0), (1.0, 0.0)], elements: {n}, first_node: 1),
        (name: "lower", section: "s", path: [(1.2, -0.05), (0.2, -0.05)], elements: {n}, first_node: 1001),
    ],
    supports: [(node: 1, u: true, v: true, phi: true), (node: 1001, u: true, v: true, phi: true),
               (node: 100000, u: true)],
    prescribed: [(node: 100000, dof: V, per_step: -0.02)],
    contacts: [(nodes: [100000], bodies: ["upper", "lower"]),
               (node_bodies: ["upper"], bodies: ["lower"]),
               (node_bodies: ["lower"], bodies: ["upper"])],
    control: (steps: 24),
)"#
    )
}

/// Two cantilevers of `n` elements, one above the other and overlapping by 0.7 of their
/// length; the upper one's clamp is driven down onto the lower one.
pub(crate) fn stacked_cantilevers(n: usize) -> String {
    format!(
        r#"(
    name: "stacked cantilevers",
    sections: [(name: "s", E: 1.0, A: 1.0e3, I: 1.0, G: 400.0)],
    bodies: [
        (name: "upper", section: "s", path: [(0.0, 0.0), (1.0, 0.0)], elements: {n}, first_node: 1),
        (name: "lower", section: "s", path: [(1.3, -0.05), (0.3, -0.05)], elements: {n}, first_node: {lower}),
    ],
    supports: [(node: 1, u: true, phi: true), (node: {lower}, u: true, v: true, phi: true)],
    prescribed: [(node: 1, dof: V, per_step: -0.01)],
    contacts: [(node_bodies: ["upper"], bodies: ["lower"]), (node_bodies: ["lower"], bodies: ["upper"])],
    control: (steps: 30),
)"#,
        lower = n + 2
    )
}

/// A pin of radius 5 cm whose rim starts 1 mm above a cantilever of `n` elements at x = 0.7,
/// driven 0.4 m down: it touches the beam's parallel curve and slides towards the tip.
pub(crate) fn pin_with_a_radius(n: usize) -> String {
    format!(
        r#"(
    name: "a pin with a radius",
    sections: [(name: "s", E: 1.0, A: 1.0e6, I: 1.0, G: 0.4)],
    nodes: [(id: 100000, x: 0.7, y: 0.051, rotation: false, radius: 0.05)],
    bodies: [(name: "beam", section: "s", path: [(0.0, 0.0), (1.0, 0.0)], elements: {n}, first_node: 1)],
    supports: [(node: 1, u: true, v: true, phi: true), (node: 100000, u: true)],
    prescribed: [(node: 100000, dof: V, per_step: -0.02)],
    contacts: [(nodes: [100000], bodies: ["beam"])],
    control: (steps: 20),
)"#
    )
}

/// Two cantilevers 2 cm thick, the upper (0.6 m) 1 mm clear of the lower (1 m), both of `n`
/// elements: the upper one's tip is driven 0.3 m down, its nodes pressing on the lower one's
/// face.
pub(crate) fn thick_strips(n: usize) -> String {
    format!(
        r#"(
    name: "thick strips",
    sections: [(name: "s", E: 1.0, A: 1.0e6, I: 1.0, G: 0.4, thickness: 0.02)],
    bodies: [
        (name: "lower", section: "s", path: [(0.0, 0.0), (1.0, 0.0)], elements: {n}, first_node: 1),
        (name: "upper", section: "s", path: [(0.0, 0.021), (0.6, 0.021)], elements: {n}, first_node: {upper}),
    ],
    supports: [(node: 1, u: true, v: true, phi: true), (node: {upper}, u: true, v: true, phi: true)],
    prescribed: [(node: {tip}, dof: V, per_step: -0.01)],
    contacts: [(node_bodies: ["upper"], bodies: ["lower"])],
    control: (steps: 30),
)"#,
        upper = n + 2,
        tip = 2 * n + 2
    )
}
