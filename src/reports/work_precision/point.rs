//! One point of the work-precision report: a problem solved on one mesh, formulation and
//! tolerance, with its error and time.

use crate::solver::Formulation;

/// One measured point.
#[derive(Clone, Debug, PartialEq)]
pub struct Point {
    /// Problem name.
    pub problem: String,
    /// Element formulation.
    pub formulation: Formulation,
    /// Elements in the mesh.
    pub elements: usize,
    /// Newton tolerance (relative residual).
    pub tolerance: f64,
    /// Converged increments.
    pub increments: usize,
    /// Newton iterations in all.
    pub iterations: usize,
    /// Error against the reference (problem-specific, dimensionless).
    pub error: f64,
    /// Median wall time of one whole run (s).
    pub seconds: f64,
}
