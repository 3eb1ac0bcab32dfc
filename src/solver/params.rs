//! The solver's parameters in one documented struct with defaults.

use serde::{Deserialize, Serialize};

use super::element::contact_element::ContactOptions;

/// How the Newton-Raphson iteration and the increment control behave.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct SolverParams {
    /// Convergence: `|R| <= tolerance * reference`, where R is the unbalanced force over the free
    /// dofs and the reference is `max(|lambda F|, |reactions|, force_floor)` (2-norms).
    pub tolerance: f64,
    /// Smallest reference force, as a multiple of the largest section EA (keeps the test
    /// meaningful when the structure is unloaded, e.g. after every contact released).
    pub force_floor: f64,
    /// Newton iterations allowed per attempt (each active-set pass starts a new count).
    pub max_iterations: usize,
    /// Halvings of the increment allowed before the run stops with an error.
    pub max_cutbacks: usize,
    /// An attempt fails when the relative residual exceeds this (divergence).
    pub divergence: f64,
    /// Largest displacement correction per iteration (m); larger ones are scaled down.
    /// Guards spring-back after a release. `f64::MAX` (the default) disables it.
    pub max_step: f64,
    /// When Newton's updates take the chords' second-order gaps out (`Solver::
    /// take_out_stretch`; one more band solve an iteration). A linear update that turns an
    /// element lengthens its chord by about l dpsi^2 / 2 and turns it by less than meant; on
    /// fine meshes of axially stiff beams in large rotation the spurious forces make Newton
    /// zig-zag and load steps fail. Where every update is corrected, a frictionless contact on
    /// the axis has its contact gap taken out too (`Newton::contact_gap_correction`: a node
    /// sliding along a chord that turns). Default: where needed
    /// (`StretchCorrection::WhereNeeded`).
    pub stretch_correction: StretchCorrection,
    /// Contact state changes allowed within one increment, beyond four per candidate node, before
    /// it is cut back (chattering). Cycling itself is caught earlier: a repeated active set
    /// switches the attempt to one change per pass.
    pub max_active_set_changes: usize,
    /// The contact element's unsymmetric tangent term is used from this iteration on (1 = always).
    pub unsymmetric_from: usize,
    /// Contact fractions are kept within [xi_min, 1 - xi_min] inside the stiffness.
    pub xi_min: f64,
    /// The contact spring in series with an element's contact force, in units of the
    /// element's EI / l^3 (`contact_element::contact_compliance`): it keeps the contact
    /// stiffness finite on and near the element's nodes (3 EI / li^3 for Bernoulli-Euler, G Ae /
    /// li for Timoshenko without it). A node in contact sits inside the shape by Yc l^3 /
    /// (contact_stiffness EI). Infinite: none.
    pub contact_stiffness: f64,
    /// Whether a frictionless contact pushes normal to the beam's surface at the contact point
    /// (the element's end rotations interpolated along it: continuous from one element to the
    /// next) rather than normal to the element's chord, as the paper's element does; see
    /// `element::contact_law`. Parameters read without it (a history that does not name it)
    /// mean the chord's normal.
    #[serde(default)]
    pub surface_normal: bool,
    /// Tolerance for "li/l left (0, 1)" when deciding a transfer, as a fraction of the element.
    pub transfer_tolerance: f64,
    /// A contact within this fraction of an element end that has no neighbouring element (a
    /// free tip) slides off at a converged state: closer than this, K44 ~ G Ae / lj makes the
    /// round-off floor of the residual exceed the tolerance.
    pub free_end_margin: f64,
    /// Also accept a relative residual below `roundoff_factor` times the estimated round-off
    /// floor (eps max|K_ii| max|x| / reference); 0 disables it. Reported per increment.
    pub roundoff_factor: f64,
    /// The largest relative residual an increment may be accepted with at the round-off floor
    /// (where Newton stalls above `tolerance` because the floor itself is above it). Such
    /// increments are marked `IncrementStatus::RoundOff`; a stall above this bound is a
    /// failure (cut back, then `SolveError::RoundOffFloor`). Never below `tolerance`.
    /// Default 1e-5: the floor of a plain 1000-element cantilever (Mattiasson's) is about
    /// 5e-6, and a stiff contact near an element end lifts it to 1e-3 and beyond, which is
    /// refused.
    pub roundoff_bound: f64,
    /// A node found this far through a body (in element lengths) at the end of an increment
    /// makes the increment be cut back instead of activating the contact from so deep.
    pub max_penetration: f64,
    /// The penalty of a node's contact with a rigid obstacle, in units of the largest axial
    /// stiffness EA/l of the model's elements. The augmented Lagrangian closes the gap whatever
    /// the penalty; a stiffer one closes it in fewer updates of the multipliers.
    pub obstacle_penalty: f64,
    /// The largest gap (either way) a node resting on a rigid obstacle is accepted with, as a
    /// fraction of the model's size (`Structure::model_size`): the multipliers are updated
    /// until every gap is within it, and no node may end further inside an obstacle.
    pub obstacle_gap: f64,
    /// The stiffness of the spring that holds a sticking contact node to its point on the beam,
    /// in units of the smallest axial stiffness EA/l of that element and the node's own
    /// elements: while it sticks, the node moves along the beam by its friction force over this
    /// stiffness (`element::friction`).
    pub friction_penalty: f64,
    /// Arc-length control: the length of one increment along the equilibrium path, measured as
    /// the root-mean-square change of the free dofs (m, rad). `None`: load and prescribed displacements advance in equal
    /// steps (Newton with cut-backs). Only for load-driven scenes.
    pub arc_length: Option<f64>,
    /// Contact detection skips (node, body) pairs whose bounding boxes are far apart. Off:
    /// every pair is probed (for checks).
    pub broad_phase: bool,
    /// Where no step of the drive, however short, finds an equilibrium near the last one, the
    /// structure snaps: the drive is held and it moves to the next stable state along a damped
    /// path, its states marked `IncrementStatus::Snapping` (`control/snap.rs`). Off, and in
    /// models where a body may touch itself: the run stops there with the failure.
    pub snap: bool,
}

impl Default for SolverParams {
    fn default() -> Self {
        SolverParams {
            tolerance: 1e-8,
            force_floor: 1e-6,
            max_iterations: 40,
            max_cutbacks: 12,
            divergence: 1e6,
            max_step: f64::MAX,
            stretch_correction: StretchCorrection::WhereNeeded,
            max_active_set_changes: 24,
            unsymmetric_from: 1,
            xi_min: 1e-6,
            contact_stiffness: 1e4,
            surface_normal: true,
            transfer_tolerance: 1e-9,
            free_end_margin: 1e-3,
            roundoff_factor: 0.0,
            roundoff_bound: 1e-5,
            max_penetration: 0.25,
            obstacle_penalty: 1.0,
            obstacle_gap: 1e-9,
            friction_penalty: 10.0,
            arc_length: None,
            broad_phase: true,
            snap: true,
        }
    }
}

/// When Newton's updates are followed by the stretch correction (`Solver::take_out_stretch`).
///
/// Mattiasson's cantilever (k = 10 in 10 steps) on 10^4 elements: 88 increments and 921
/// iterations never, 19 and 184 after the first cut-back, 17 and 155 always. The correction
/// costs one more band solve an iteration (2.3 times the iteration of a long beam) and does not
/// shorten Newton where it has no zig-zag to remove, hence the default: where an update's gaps
/// would load the structure more than the force it removes, or after a cut-back. Under
/// arc-length control (`arc_length`), updates are corrected after a cut-back (or always), not
/// judged.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub enum StretchCorrection {
    /// Plain Newton: the linear update only (`false` in a scene file, the form of scenes
    /// written before the modes).
    #[serde(alias = "false")]
    Never,
    /// Plain Newton until the run's first cut-back, corrected from then on (reported as
    /// `Event::StretchCorrectionOn`). Runs without cut-backs are plain Newton's, bit for bit.
    AfterCutBack,
    /// As `AfterCutBack`, and before the first cut-back, in a model without contact (no
    /// contact entry, no obstacle), each update judged: corrected where its chords' gaps
    /// would load the structure more than the unbalanced force it came to remove (a stiff
    /// chord turned by the update), left plain where the update turns a chord by more than a
    /// radian or was cut to `max_step` (a direction, not a turn meant). With contact, the
    /// linear update is the one the contact stages judge, and a corrected one can carry the
    /// structure onto another path (Example 3.1's last step fails with it; a column in a
    /// channel buckles the other way).
    #[default]
    WhereNeeded,
    /// Every update of every increment (`true` in a scene file).
    #[serde(alias = "true")]
    Always,
}

impl StretchCorrection {
    /// Whether a run's first cut-back turns the correction on for every update from then on
    /// (`AfterCutBack`, `WhereNeeded`).
    pub fn on_after_a_cut_back(self) -> bool {
        matches!(
            self,
            StretchCorrection::AfterCutBack | StretchCorrection::WhereNeeded
        )
    }
}

impl SolverParams {
    /// Contact element options for a given iteration.
    pub fn contact_options(&self, iteration: usize) -> ContactOptions {
        ContactOptions {
            xi_min: self.xi_min,
            unsymmetric: if iteration >= self.unsymmetric_from {
                1.0
            } else {
                0.0
            },
            contact_stiffness: self.contact_stiffness,
            surface_normal: self.surface_normal,
        }
    }
}
