//! The `contacts` of a scene: candidate nodes (listed, or every node of the named bodies) and
//! the bodies they may touch.

use super::errors::{sized, Ctx, SceneError};
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
            let n = g.node_of(ctx, format!("contacts[{k}].nodes[{m}]"), id);
            cn.push(n.map_err(|e| ctx.in_entry(e, ("contacts", k)))?);
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
        if !(sized(c.mu) && c.mu >= 0.0) {
            return Err(ctx.err_entry(
                format!("contacts[{k}].mu"),
                ("contacts", k),
                format!(
                    "the friction coefficient is {:e}: it must be finite, >= 0 and below 1e100",
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
        if let Some((e, f)) = crossing_chords(g, (&cn, &cb), c.own) {
            let name = |e: usize| {
                let b = &g.bodies[g.beams[e].body];
                let place = b.elements.iter().position(|&x| x == e).map_or(0, |p| p + 1);
                format!("element {place} of body {}", b.name)
            };
            return Err(ctx.err(
                format!("contacts[{k}]"),
                Some("contacts".into()),
                format!(
                    "{} and {} cross where the scene starts: bodies that may touch start apart \
                     (or touching), never through each other",
                    name(e),
                    name(f)
                ),
            ));
        }
        stand_off(ctx, k, c.own, (&cn, &cb), g)?;
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

/// Two element chords at rest that cross between their ends, one of a body the candidates `cn`
/// lie on and one of a body in `cb` they may touch (of one body only with `own`, and then not
/// neighbours): such bodies start through each other. Elements are binned in a grid of cells
/// an element long, so that only nearby pairs are tested.
fn crossing_chords(
    g: &Geometry,
    (cn, cb): (&[usize], &[usize]),
    own: bool,
) -> Option<(usize, usize)> {
    let candidate: std::collections::HashSet<usize> = cn.iter().copied().collect();
    let touching: Vec<usize> = (0..g.bodies.len())
        .filter(|&b| {
            (g.bodies[b].elements.iter())
                .any(|&e| candidate.contains(&g.beams[e].i) || candidate.contains(&g.beams[e].j))
        })
        .collect();
    let pairs: Vec<(usize, usize)> = (touching.iter())
        .flat_map(|&a| cb.iter().map(move |&b| (a, b)))
        .filter(|&(a, b)| a != b || own)
        .collect();
    if pairs.is_empty() {
        return None;
    }
    let at = |n: usize| [g.nodes[n].x, g.nodes[n].y];
    let involved: Vec<usize> = {
        let mut v: Vec<usize> = pairs.iter().flat_map(|&(a, b)| [a, b]).collect();
        v.sort_unstable();
        v.dedup();
        v
    };
    let elements: Vec<usize> = (involved.iter())
        .flat_map(|&b| g.bodies[b].elements.iter().copied())
        .collect();
    let cell = (elements.iter())
        .map(|&e| {
            let (p, q) = (at(g.beams[e].i), at(g.beams[e].j));
            (q[0] - p[0]).hypot(q[1] - p[1])
        })
        .fold(0.0f64, f64::max);
    if !(cell > 0.0 && cell.is_finite()) {
        return None;
    }
    let mut grid: std::collections::HashMap<(i64, i64), Vec<usize>> = Default::default();
    for &e in &elements {
        let (p, q) = (at(g.beams[e].i), at(g.beams[e].j));
        let c = |v: f64| (v / cell).floor() as i64;
        for x in c(p[0].min(q[0]))..=c(p[0].max(q[0])) {
            for y in c(p[1].min(q[1]))..=c(p[1].max(q[1])) {
                grid.entry((x, y)).or_default().push(e);
            }
        }
    }
    let wanted = |e: usize, f: usize| {
        let (a, b) = (g.beams[e].body, g.beams[f].body);
        pairs.contains(&(a, b)) || pairs.contains(&(b, a))
    };
    let shares = |e: usize, f: usize| {
        let (x, y) = (&g.beams[e], &g.beams[f]);
        x.i == y.i || x.i == y.j || x.j == y.i || x.j == y.j
    };
    for list in grid.values() {
        for (k, &e) in list.iter().enumerate() {
            for &f in &list[k + 1..] {
                if e != f && !shares(e, f) && wanted(e, f) {
                    let (p, q) = (at(g.beams[e].i), at(g.beams[e].j));
                    let (r, s) = (at(g.beams[f].i), at(g.beams[f].j));
                    if segments_cross(p, q, r, s) {
                        return Some((e.min(f), e.max(f)));
                    }
                }
            }
        }
    }
    None
}

/// Whether segments pq and rs cross at a point inside both (touching at an end, or lying along
/// each other, is not crossing).
fn segments_cross(p: [f64; 2], q: [f64; 2], r: [f64; 2], s: [f64; 2]) -> bool {
    let orient = |a: [f64; 2], b: [f64; 2], c: [f64; 2]| {
        let v = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
        let scale = (b[0] - a[0]).hypot(b[1] - a[1]) * (c[0] - a[0]).hypot(c[1] - a[1]);
        if v.abs() <= 1e-12 * scale {
            0.0
        } else {
            v.signum()
        }
    };
    let (o1, o2) = (orient(p, q, r), orient(p, q, s));
    let (o3, o4) = (orient(r, s, p), orient(r, s, q));
    o1 * o2 < 0.0 && o3 * o4 < 0.0
}

/// Contact entry `k`'s candidates that stand off the axes (a node's radius, the thickness of
/// its own elements or of the bodies `cb`: the solver's contact distance) must start clear of
/// the bodies by that distance.
fn stand_off(
    ctx: &Ctx,
    k: usize,
    own: bool,
    (cn, cb): (&[usize], &[usize]),
    g: &Geometry,
) -> Result<(), SceneError> {
    let thick =
        |b: usize| (g.bodies[b].elements.iter()).any(|&e| g.beams[e].section.thickness > 0.0);
    if cn.iter().all(|&n| g.nodes[n].clearance == 0.0) && !cb.iter().any(|&b| thick(b)) {
        return Ok(());
    }
    let at = |n: usize| [g.nodes[n].x, g.nodes[n].y];
    for &n in cn {
        for &b in cb {
            let els = &g.bodies[b].elements;
            // A node's own elements and the window beyond them, by place along the body.
            let places: Vec<usize> = (0..els.len())
                .filter(|&p| g.beams[els[p]].i == n || g.beams[els[p]].j == n)
                .collect();
            let window = places.first().zip(places.last()).map(|(&lo, &hi)| {
                (
                    lo.saturating_sub(SELF_CONTACT_WINDOW),
                    hi + SELF_CONTACT_WINDOW,
                )
            });
            if window.is_some() && !own {
                continue;
            }
            for (place, &e) in els.iter().enumerate() {
                if window.is_some_and(|(lo, hi)| (lo..=hi).contains(&place)) {
                    continue;
                }
                let r = g.nodes[n].clearance + 0.5 * g.beams[e].section.thickness;
                if r == 0.0 {
                    continue;
                }
                let node = &g.nodes[n];
                let dist = segment_distance(at(n), at(g.beams[e].i), at(g.beams[e].j));
                if dist < r * (1.0 - 1e-9) {
                    return Err(ctx.err(
                        format!("contacts[{k}]"),
                        Some(format!("id:{}", node.id)),
                        format!(
                            "node {} starts {dist:e} m from the axis of element {} of body {}, \
                             within its contact distance {r:e} m (its radius and the half \
                             thicknesses): it must start clear of the body by that distance",
                            node.id,
                            place + 1,
                            g.bodies[b].name
                        ),
                    ));
                }
            }
        }
    }
    Ok(())
}

/// The distance of point `p` from the segment from `a` to `b`.
fn segment_distance(p: [f64; 2], a: [f64; 2], b: [f64; 2]) -> f64 {
    let (u, v) = ([b[0] - a[0], b[1] - a[1]], [p[0] - a[0], p[1] - a[1]]);
    let t = ((u[0] * v[0] + u[1] * v[1]) / (u[0] * u[0] + u[1] * u[1])).clamp(0.0, 1.0);
    (v[0] - t * u[0]).hypot(v[1] - t * u[1])
}
