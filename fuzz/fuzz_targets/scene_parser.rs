// Fuzz target owning the whole scene-text path: RON parse + validation
// (`tsm_contact::scene::parse`, which already builds a solver once for its mechanism check) and,
// for every scene that validates, constructing the `Solver` again exactly as `cli solve` does
// (`Scene::solver`) without running any increment. Nothing on this path may panic, overflow,
// run out of memory or hang, whatever the input bytes.
// Set SCENE_FUZZ_VERBOSE=1 when replaying an input to print what the parser made of it.
#![no_main]

use std::sync::OnceLock;

use libfuzzer_sys::fuzz_target;
use tsm_contact::scene;

fn verbose() -> bool {
    static V: OnceLock<bool> = OnceLock::new();
    *V.get_or_init(|| std::env::var_os("SCENE_FUZZ_VERBOSE").is_some())
}

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    let scene = match scene::parse(text, "<fuzz>") {
        Ok(s) => s,
        Err(e) => {
            if verbose() {
                eprintln!("scene rejected: {e}");
            }
            return;
        }
    };
    if verbose() {
        eprintln!(
            "scene validated: {} nodes, {} beams",
            scene.model.nodes.len(),
            scene.model.beams.len()
        );
    }
    // A validated scene must give a solver: `parse` already ran this mechanism check.
    let solver = scene.solver();
    assert!(
        solver.is_ok(),
        "scene validated but Scene::solver failed: {:?}",
        solver.err()
    );
});
