//! The `contacts` of a scene: candidate nodes (listed, or every node of the named bodies) and
//! the bodies they may touch.

use super::errors::{Ctx, SceneError};
use super::geometry::Geometry;
use crate::scene::format::{SceneFile, SideDef};
use crate::solver::model::SELF_CONTACT_WINDOW;
use crate::solver::{Beam, ContactPair};

/// The contact pairs of `sf` on geometry `g`.
pub(super) fn contacts(
    ctx: &Ctx,
    sf: &SceneFile,
    g: &Geometry,
) -> Result<Vec<ContactPair>, SceneError> {
    let mut contacts = Vec::new();
    for (k, c) in sf.contacts.iter().enumerate() {
        let mut cn = Vec::new();
        for (m, &id) in c.nodes.iter().enumerate() {
            cn.push(g.node_of(ctx, format!("contacts[{k}].nodes[{m}]"), id)?);
        }
        for (m, name) in c.node_bodies.iter().enumerate() {
            let b = g.body_of(ctx, format!("contacts[{k}].node_bodies[{m}]"), name)?;
            for &e in &g.bodies[b].elements {
                let beam: &Beam = &g.beams[e];
                for n in [beam.i, beam.j] {
                    if !cn.contains(&n) {
                        cn.push(n);
                    }
                }
            }
        }
        if !(c.mu.is_finite() && c.mu >= 0.0) {
            return Err(ctx.err(
                format!("contacts[{k}].mu"),
                None,
                format!(
                    "the friction coefficient is {}: it must be a finite number >= 0",
                    c.mu
                ),
            ));
        }
        let mut cb = Vec::new();
        for (m, name) in c.bodies.iter().enumerate() {
            cb.push(g.body_of(ctx, format!("contacts[{k}].bodies[{m}]"), name)?);
        }
        can_act(ctx, k, c.own, (&cn, &cb), g)?;
        // Two candidate nodes at one point would rest on one element at one place: the
        // contact element has no equilibrium for that.
        let mut at: std::collections::HashMap<(u64, u64), usize> = Default::default();
        for &n in &cn {
            let node = &g.nodes[n];
            let key = ((node.x + 0.0).to_bits(), (node.y + 0.0).to_bits());
            if let Some(&other) = at.get(&key) {
                return Err(ctx.err(
                    format!("contacts[{k}].nodes"),
                    Some(format!("id:{}", node.id)),
                    format!(
                        "nodes {} and {} start at the same point ({}, {}): two contact nodes cannot share a point",
                        g.nodes[other].id, node.id, node.x, node.y
                    ),
                ));
            }
            at.insert(key, n);
        }
        contacts.push(ContactPair {
            nodes: cn,
            bodies: cb,
            own: c.own,
            mu: c.mu,
            side: c.side.map(|s| match s {
                SideDef::Left => 1.0,
                SideDef::Right => -1.0,
            }),
        });
    }
    Ok(contacts)
}

/// Contact entry `k` (its candidate nodes `cn` and bodies `cb`, self-contact `own`) must make at
/// least one pair that can touch: a body to touch, a candidate, and a candidate off the body or
/// a body long enough for self-contact beyond a node's own elements and the
/// `SELF_CONTACT_WINDOW` elements on either side of them.
fn can_act(
    ctx: &Ctx,
    k: usize,
    own: bool,
    (cn, cb): (&[usize], &[usize]),
    g: &Geometry,
) -> Result<(), SceneError> {
    let at = format!("contacts[{k}]");
    if cb.is_empty() {
        return Err(ctx.err(
            format!("{at}.bodies"),
            Some("bodies".into()),
            "no body to touch: name at least one",
        ));
    }
    if cn.is_empty() {
        return Err(ctx.err(
            at,
            Some("contacts".into()),
            "no candidate node: list `nodes` or `node_bodies`",
        ));
    }
    let on = |n: usize, b: usize| {
        (g.bodies[b].elements.iter()).any(|&e| g.beams[e].i == n || g.beams[e].j == n)
    };
    let long = |b: usize| g.bodies[b].elements.len() > SELF_CONTACT_WINDOW + 1;
    let pairs = (cn.iter()).any(|&n| cb.iter().any(|&b| !on(n, b) || (own && long(b))));
    if pairs {
        return Ok(());
    }
    let why = if own {
        format!(
            "every candidate lies on the bodies it may touch, and they are too short for \
             self-contact (a node cannot touch its own elements or the {SELF_CONTACT_WINDOW} \
             beyond them on either side)"
        )
    } else {
        "every candidate lies on the bodies it may touch, so no pair can touch: set `own: true` \
         for self-contact"
            .into()
    };
    Err(ctx.err(at, Some("contacts".into()), why))
}
