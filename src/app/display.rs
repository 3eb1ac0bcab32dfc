//! What the user has chosen to see in the results: the force diagram drawn along the beams,
//! the unit rotations are shown in, the node or element picked in the viewport, and the rows
//! and order of the table; and how numbers are written in labels (`num`: three significant
//! digits, plain for everyday magnitudes, scientific like `1.2e-5` for very small or large ones).

/// How angles are shown.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Angles {
    /// Radians.
    #[default]
    Radians,
    /// Degrees.
    Degrees,
}

impl Angles {
    /// `rad` in this unit, with the unit.
    pub fn show(self, rad: f64) -> String {
        match self {
            Angles::Radians => format!("{} rad", num(rad)),
            Angles::Degrees => format!("{} deg", num(rad.to_degrees())),
        }
    }
}

/// A node or an element, by index.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Picked {
    /// A node (index into `Model::nodes`).
    Node(usize),
    /// A beam element (index into `Model::beams`).
    Element(usize),
}

/// Which rows the table shows.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Rows {
    /// One row a node.
    #[default]
    Nodes,
    /// One row an element.
    Elements,
    /// One row an active contact.
    Contacts,
    /// One row a reaction.
    Reactions,
}

/// The table's choices: its rows, the column sorted by and the order.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct TableView {
    /// Whether the window is open.
    pub open: bool,
    /// Which rows.
    pub rows: Rows,
    /// The column sorted by.
    pub column: usize,
    /// Largest first.
    pub descending: bool,
}

/// The dof the load-displacement curve is drawn against: the largest component of the first
/// nodal load, or, with distributed loads only, the translation of the node farthest from the
/// supports along the first distributed load's larger component (a cantilever's tip).
pub(crate) fn loaded_dof(model: &crate::solver::Model) -> Option<(usize, usize)> {
    if let Some(load) = model.loads.first() {
        let o = (0..3)
            .max_by(|&a, &b| load.force[a].abs().total_cmp(&load.force[b].abs()))
            .unwrap_or(1);
        return Some((load.node, o));
    }
    let d = model.distributed.first()?;
    let o = usize::from(d.q[0][1].abs() >= d.q[0][0].abs());
    let held: Vec<usize> = model.supports.iter().map(|s| s.node).collect();
    let far = |n: usize| {
        let p = model.position(n);
        (held.iter())
            .map(|&h| {
                let q = model.position(h);
                (p[0] - q[0]).hypot(p[1] - q[1])
            })
            .fold(f64::INFINITY, f64::min)
    };
    (0..model.nodes.len())
        .max_by(|&a, &b| far(a).total_cmp(&far(b)))
        .map(|n| (n, o))
}

/// Format `v` with three significant digits.
pub fn num(v: f64) -> String {
    let a = v.abs();
    if v == 0.0 || !v.is_finite() {
        return format!("{v}");
    }
    if (1e-3..1e4).contains(&a) {
        let decimals = (2 - a.log10().floor() as i32).max(0) as usize;
        format!("{v:.decimals$}")
    } else {
        format!("{v:.2e}")
    }
}

#[cfg(test)]
mod number_tests {
    #[test]
    fn formats() {
        assert_eq!(super::num(1.734), "1.73");
        assert_eq!(super::num(-0.0123), "-0.0123");
        assert_eq!(super::num(152.4), "152");
        assert_eq!(super::num(2.5e-6), "2.50e-6");
    }
}
