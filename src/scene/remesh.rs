//! Re-meshing a scene on its parsed form (`SceneFile`): a one-body scene divided into `n`
//! elements per path segment instead of its own K, with every reference to a node of the body
//! (supports, loads, prescribed displacements, contact nodes) moved to the node at the same
//! place along the new mesh.

use super::format::SceneFile;

/// `sf` with its one body divided into `n` elements per path segment. `None` where the scene
/// has more than one body, an explicit node among the body's node ids (old or new), or names a
/// node of the body that has no node at the same place in the new mesh (the place must be a
/// whole number of new elements along its segment).
pub fn remesh(sf: &SceneFile, n: usize) -> Option<SceneFile> {
    let [body] = sf.bodies.as_slice() else {
        return None;
    };
    if n == 0 || body.elements == 0 {
        return None;
    }
    let own = body.elements;
    let first = body.first_node;
    let segments = body.path.len().saturating_sub(1);
    let last = first as usize + own * segments;
    // Explicit nodes keep their ids: none may lie among the body's, old or new.
    let reach = last.max(first as usize + n * segments);
    if (sf.nodes.iter()).any(|node| (first as usize..=reach).contains(&(node.id as usize))) {
        return None;
    }
    // The id in the new mesh of node `id` of the old one (other ids stay).
    let moved = |id: u32| -> Option<u32> {
        let k = (id as usize).checked_sub(first as usize)?;
        if id as usize > last {
            return Some(id);
        }
        let (segment, along) = (k / own, k % own);
        if !(along * n).is_multiple_of(own) {
            return None;
        }
        u32::try_from(first as usize + segment * n + along * n / own).ok()
    };
    let map = |id: u32| -> Option<u32> {
        if id < first {
            Some(id)
        } else {
            moved(id)
        }
    };
    let mut out = sf.clone();
    out.bodies[0].elements = n;
    for s in &mut out.supports {
        s.node = map(s.node)?;
    }
    for l in &mut out.loads {
        l.node = map(l.node)?;
    }
    for p in &mut out.prescribed {
        p.node = map(p.node)?;
    }
    for c in &mut out.contacts {
        for id in &mut c.nodes {
            *id = map(*id)?;
        }
    }
    Some(out)
}
