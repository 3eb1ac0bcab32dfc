// Fuzz target owning the whole scene-text path: RON parse + validation
// (`tsm_contact::scene::parse`, which already builds a solver once for its mechanism check) and,
// for every scene that validates, constructing the `Solver` again exactly as `cli solve` does
// (`Scene::solver`) without running any increment. Nothing on this path may panic, overflow,
// run out of memory or hang, whatever the input bytes.
#![no_main]

use libfuzzer_sys::fuzz_target;
use tsm_contact::scene;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    let Ok(scene) = scene::parse(text, "<fuzz>") else {
        return;
    };
    // A validated scene must give a solver: `parse` already ran this mechanism check.
    let solver = scene.solver();
    assert!(
        solver.is_ok(),
        "scene validated but Scene::solver failed: {:?}",
        solver.err()
    );
});
