//! The friction law at an accepted state, checked from the forces and stick points alone:
//! no contact carries a friction force beyond mu times its pressure, and a contact whose stick
//! point moved during the increment (it slipped) carries exactly mu times its pressure,
//! against the slip.

use crate::solver::element::friction::STICK_ROUNDOFF_ULPS;
use crate::solver::model::Model;

/// How far the friction force may lie from the Coulomb limit, relative to it: far above the
/// round-off of a converged state, far below any error a user would see.
pub const FRICTION_LAW_TOLERANCE: f64 = 1e-6;

/// One frictional contact as the check reads it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FrictionRecord {
    /// Node index.
    pub node: usize,
    /// Body index, or obstacle index where `obstacle`.
    pub body: usize,
    /// Whether the node rests on a rigid obstacle rather than a body.
    pub obstacle: bool,
    /// Friction coefficient.
    pub mu: f64,
    /// Normal pressure N (N, compressive positive).
    pub pressure: f64,
    /// The friction force on the node along the body's (or the obstacle's) direction of its
    /// stick points (N).
    pub tangential: f64,
    /// The stick point at the start of the increment (length along the body, m); `None` for
    /// a contact that began during it.
    pub stick_before: Option<f64>,
    /// The stick point at the end of the increment.
    pub stick_after: f64,
    /// The length after which the stick points repeat (the circumference of a circle or of an
    /// arc's circle, its places taken modulo it: `Shape::period`), 0 where they do not: its
    /// round-off is theirs too.
    pub period: f64,
    /// The size of what else a stick point is worked from (m; a rim's roll), 0 where none:
    /// its round-off is the stick point's too.
    pub scale: f64,
}

/// A contact that breaks the friction law.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FrictionViolation {
    /// Node index.
    pub node: usize,
    /// Body index, or obstacle index where `obstacle`.
    pub body: usize,
    /// Whether the node rests on a rigid obstacle.
    pub obstacle: bool,
    /// |T| / (mu N).
    pub ratio: f64,
    /// How far its stick point moved in the increment (m).
    pub slipped: f64,
}

impl FrictionViolation {
    /// What the node rests on, for messages: the body's name, or "obstacle NAME".
    pub fn surface(&self, model: &Model) -> String {
        if self.obstacle {
            format!("obstacle {}", model.obstacles[self.body].name)
        } else {
            model.bodies[self.body].name.clone()
        }
    }
}

/// The first contact of `records` that breaks the friction law, if any.
pub fn friction_law(records: &[FrictionRecord]) -> Option<FrictionViolation> {
    records.iter().find_map(|r| {
        let limit = r.mu * r.pressure.max(0.0);
        let t = r.tangential.abs();
        let before = r.stick_before.unwrap_or(r.stick_after);
        let slipped = r.stick_after - before;
        let over = t > limit * (1.0 + FRICTION_LAW_TOLERANCE);
        // A stick point is a place along a body: a move within a few units in the last place
        // of it (or of the period it is taken modulo) is the round-off of recomputing it, not
        // a slip with a direction.
        let size = (before.abs().max(r.stick_after.abs()))
            .max(r.period)
            .max(r.scale);
        let roundoff = STICK_ROUNDOFF_ULPS * f64::EPSILON * size;
        let moved = slipped.abs() > roundoff;
        let short = moved && t < limit * (1.0 - FRICTION_LAW_TOLERANCE);
        let along = moved && r.tangential * slipped > 0.0;
        (over || short || along).then_some(FrictionViolation {
            node: r.node,
            body: r.body,
            obstacle: r.obstacle,
            ratio: if limit > 0.0 {
                t / limit
            } else {
                f64::INFINITY
            },
            slipped,
        })
    })
}
