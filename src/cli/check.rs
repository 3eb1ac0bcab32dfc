//! `check`: the independent audit (`tsm_contact::audit`) of a written history: equilibrium from
//! its recorded forces, every support and prescribed dof where it is held, the side of every
//! candidate node, obstacles, the friction law and the statuses. Exit 0 when it finds nothing, 1 naming each increment, node and body found wrong,
//! 2 when the history cannot be read. A thinned history ([`History::every`]) is audited but for
//! pass-through, which it cannot support, and the output says so.

use std::path::Path;

use tsm_contact::audit::audit_history;
use tsm_contact::history::{History, Topology};
use tsm_contact::scene;

/// Audit the history at `path`; `scene_name` supplies the topology a version 1 history lacks
/// (its formulation is the history's).
pub(super) fn check(path: &Path, scene_name: Option<&str>) -> i32 {
    let text = match std::fs::read_to_string(path) {
        Ok(t) => t,
        Err(e) => {
            eprintln!("error: cannot read {}: {e}", path.display());
            return 2;
        }
    };
    let history: History = match serde_json::from_str(&text) {
        Ok(h) => h,
        Err(e) => {
            eprintln!("error: {} is not a history: {e}", path.display());
            return 2;
        }
    };
    let topology = match scene_name.map(scene::builtin::open) {
        None => None,
        Some(Ok(mut s)) => {
            if let Some(f) = history.formulation {
                s.model.formulation = f;
            }
            Some(Topology::of(&s.model))
        }
        Some(Err(e)) => {
            eprintln!("error: {e}");
            return 2;
        }
    };
    let findings = match audit_history(&history, topology.as_ref()) {
        Ok(f) => f,
        Err(why) => {
            eprintln!("error: {}: {why}", path.display());
            return 2;
        }
    };
    for f in &findings {
        out!("{f}");
    }
    if let Some(n) = history.every.filter(|&n| n > 1) {
        out!(
            "{}: keeps every {n}th increment: pass-through is not checked (a node may go through a body and back between the increments kept; solve without --every to check it)",
            path.display()
        );
    }
    out!(
        "{}: {} increment(s) audited, {} finding(s)",
        path.display(),
        history.increments.len(),
        findings.len()
    );
    i32::from(!findings.is_empty())
}
