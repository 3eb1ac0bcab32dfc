//! The converged state of a run: displacements (with their rounding residues), prescribed
//! values, load factors, contact set, increment count, steps along the load path, and what the
//! increment control remembers between increments (the arc length and its direction, whether
//! the run has cut back).

use super::contact::ContactSet;

/// Where the arc-length control stands between increments.
#[derive(Clone, Debug, Default)]
pub struct ArcState {
    /// Arc length of the next increment (shrinks on failure, regrows to the nominal length).
    pub ds: Option<f64>,
    /// The last converged increment of the displacements (all dofs), for the sign of the next
    /// predictor (the path keeps its direction through limit points).
    pub last: Option<Vec<f64>>,
}

/// The last converged state.
#[derive(Clone, Debug, Default)]
pub struct State {
    /// Displacements over all dofs: the nearest doubles to the state's coordinates.
    pub d: Vec<f64>,
    /// What the coordinates hold beyond `d`, over the same dofs: the rounding residues of the
    /// corrections that reached them (`assembly::add_carried`).
    pub residue: Vec<f64>,
    /// Values of the prescribed displacements, one per `Model::prescribed`.
    pub prescribed: Vec<f64>,
    /// Load factors, one per load group (`Model::group_count`).
    pub load_factors: Vec<f64>,
    /// Steps of the model's load path completed (`Model::path`).
    pub path_step: usize,
    /// The active contacts and remembered sides.
    pub contacts: ContactSet,
    /// Number of converged increments.
    pub increment: usize,
    /// Arc-length control memory.
    pub arc: ArcState,
    /// Whether the run has cut an increment back (`StretchCorrection::AfterCutBack`,
    /// `WhereNeeded`).
    pub cut_back: bool,
}
