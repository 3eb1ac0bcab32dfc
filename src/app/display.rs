//! What the user has chosen to see in the results: the force diagram drawn along the beams,
//! the unit rotations are shown in, and the node or element picked in the viewport.

use crate::app::units::num;

/// Which diagram is drawn.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Diagram {
    /// Axial force (tension positive).
    Axial,
    /// Shear force.
    Shear,
    /// Bending moment.
    Moment,
}

impl Diagram {
    /// Every diagram, in the order the picker lists them.
    pub const ALL: [Diagram; 3] = [Diagram::Axial, Diagram::Shear, Diagram::Moment];

    /// Its letter ("N", "V", "M").
    pub fn letter(self) -> &'static str {
        match self {
            Diagram::Axial => "N",
            Diagram::Shear => "V",
            Diagram::Moment => "M",
        }
    }
}

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
