//! The state a figure draws when it is asked for a scene and a number of steps: the scene
//! loaded as the app loads it, solved that far.

use crate::scene::Scene;
use crate::solver::{IncrementRecord, Silent, SolveError};
use crate::worker::Loaded;

/// `scene` loaded and solved `steps` steps: the loaded scene and its last state (the undeformed
/// one for no steps).
pub fn solved(scene: Scene, steps: usize) -> Result<(Loaded, IncrementRecord), SolveError> {
    let mut solver = scene.solver()?;
    let loaded = Loaded::new(scene, &solver);
    let mut last = loaded.initial.clone();
    for _ in 0..steps {
        if let Some(r) = solver.step(&mut Silent)?.into_iter().last() {
            last = r;
        }
    }
    Ok((loaded, last))
}
