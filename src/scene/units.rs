//! The unit system a scene is written in: the solver works in whatever consistent units the
//! scene uses, and every number shown or written is labelled with the scene's units.

use serde::{Deserialize, Serialize};

/// The largest size a number of a scene may have, in any units: beyond it, the products the
/// solver forms of them (stiffness times displacement, load times steps) would leave double
/// precision.
pub(crate) const MAGNITUDE: f64 = 1e100;

/// Whether `v` is finite and below `MAGNITUDE` in size.
pub(crate) fn sized(v: f64) -> bool {
    v.is_finite() && v.abs() < MAGNITUDE
}

/// A consistent set of force and length units.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub enum Units {
    /// Newtons and metres (the default).
    #[default]
    #[serde(rename = "N_m")]
    NM,
    /// Kilonewtons and metres.
    #[serde(rename = "kN_m")]
    KnM,
    /// Newtons and millimetres.
    #[serde(rename = "N_mm")]
    NMm,
    /// Kilonewtons and centimetres.
    #[serde(rename = "kN_cm")]
    KnCm,
    /// Pounds-force and inches.
    #[serde(rename = "lb_in")]
    LbIn,
    /// Kips and inches.
    #[serde(rename = "kip_in")]
    KipIn,
}

impl Units {
    /// Every unit system, in the order a picker lists them.
    pub const ALL: [Units; 6] = [
        Units::NM,
        Units::KnM,
        Units::NMm,
        Units::KnCm,
        Units::LbIn,
        Units::KipIn,
    ];

    /// The force unit ("N").
    pub fn force(self) -> &'static str {
        match self {
            Units::NM | Units::NMm => "N",
            Units::KnM | Units::KnCm => "kN",
            Units::LbIn => "lb",
            Units::KipIn => "kip",
        }
    }

    /// The length unit ("m").
    pub fn length(self) -> &'static str {
        match self {
            Units::NM | Units::KnM => "m",
            Units::NMm => "mm",
            Units::KnCm => "cm",
            Units::LbIn | Units::KipIn => "in",
        }
    }

    /// The moment unit ("N m").
    pub fn moment(self) -> String {
        format!("{} {}", self.force(), self.length())
    }

    /// The name a scene file uses (`kN_m`).
    pub fn name(self) -> &'static str {
        match self {
            Units::NM => "N_m",
            Units::KnM => "kN_m",
            Units::NMm => "N_mm",
            Units::KnCm => "kN_cm",
            Units::LbIn => "lb_in",
            Units::KipIn => "kip_in",
        }
    }

    /// The unit of a dof: a length for u and v, radians for a rotation.
    pub fn of_dof(self, dof: crate::solver::Dof) -> &'static str {
        match dof {
            crate::solver::Dof::Phi => "rad",
            _ => self.length(),
        }
    }

    /// The unit of the reaction at a dof: a force for u and v, a moment for a rotation.
    pub fn of_reaction(self, dof: crate::solver::Dof) -> String {
        match dof {
            crate::solver::Dof::Phi => self.moment(),
            _ => self.force().to_string(),
        }
    }
}
