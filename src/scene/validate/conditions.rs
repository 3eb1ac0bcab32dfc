//! The boundary conditions and loading of a scene: `supports`, `loads` and `prescribed`
//! displacements, each on a node that has the dof, none both supported and prescribed; the
//! distributed loads come from `distributed.rs`.

use std::collections::HashSet;

use super::errors::{sized, Ctx, SceneError};
use super::geometry::Geometry;
use super::stages::group_index;
use crate::scene::format::SceneFile;
use crate::solver::{DistributedLoad, Dof, Load, Prescribed, Support};

/// Supports, loads and prescribed displacements of a scene.
pub(super) struct Conditions {
    pub(super) supports: Vec<Support>,
    pub(super) loads: Vec<Load>,
    pub(super) prescribed: Vec<Prescribed>,
    pub(super) distributed: Vec<DistributedLoad>,
}

/// The conditions of `sf` on geometry `g`, its loads in the load groups `groups`.
pub(super) fn conditions(
    ctx: &Ctx,
    sf: &SceneFile,
    g: &Geometry,
    groups: &[String],
) -> Result<Conditions, SceneError> {
    let mut supports = Vec::new();
    // (node, dof offset) of every support and prescribed dof, for the checks below in constant
    // time (a scene of many bodies has as many supports).
    let mut held: HashSet<(usize, usize)> = HashSet::new();
    let mut driven: HashSet<(usize, usize)> = HashSet::new();
    for (k, s) in sf.supports.iter().enumerate() {
        let n = g.node_of(ctx, format!("supports[{k}].node"), s.node)?;
        for (on, dof) in [(s.u, Dof::U), (s.v, Dof::V), (s.phi, Dof::Phi)] {
            if on {
                let key = dof.name();
                g.check_dof(
                    ctx,
                    format!("supports[{k}].{key} (node {})", s.node),
                    n,
                    dof,
                )?;
                if held.insert((n, dof.offset())) {
                    supports.push(Support { node: n, dof });
                }
            }
        }
    }
    let mut loads = Vec::new();
    for (k, l) in sf.loads.iter().enumerate() {
        let n = g.node_of(ctx, format!("loads[{k}].node"), l.node)?;
        if l.m != 0.0 {
            g.check_dof(ctx, format!("loads[{k}].m (node {})", l.node), n, Dof::Phi)?;
        }
        for (key, v) in [("fx", l.fx), ("fy", l.fy), ("m", l.m)] {
            if !sized(v) {
                return Err(ctx.err(
                    format!("loads[{k}].{key} (node {})", l.node),
                    Some(format!("node:{}", l.node)),
                    format!("must be finite and below 1e100 in size, got {v:e}"),
                ));
            }
        }
        loads.push(Load {
            node: n,
            force: [l.fx, l.fy, l.m],
            group: group_index(groups, l.group.as_deref()),
        });
    }
    let mut prescribed: Vec<Prescribed> = Vec::new();
    for (k, p) in sf.prescribed.iter().enumerate() {
        let label = format!("(node {} {})", p.node, p.dof.name());
        let field = format!("prescribed[{k}] {label}");
        let n = g.node_of(ctx, format!("prescribed[{k}].node {label}"), p.node)?;
        g.check_dof(ctx, format!("prescribed[{k}].dof {label}"), n, p.dof)?;
        let nd = Some(format!("node:{}", p.node));
        if !sized(p.per_step) {
            return Err(ctx.err(
                format!("prescribed[{k}].per_step {label}"),
                nd,
                format!(
                    "must be finite and below 1e100 in size, got {:e}",
                    p.per_step
                ),
            ));
        }
        if held.contains(&(n, p.dof.offset())) {
            return Err(ctx.err(field, nd, "a dof cannot be both supported and prescribed"));
        }
        if !driven.insert((n, p.dof.offset())) {
            return Err(ctx.err(field, nd, "prescribed twice"));
        }
        prescribed.push(Prescribed {
            node: n,
            dof: p.dof,
            per_step: p.per_step,
        });
    }
    Ok(Conditions {
        supports,
        loads,
        prescribed,
        distributed: super::distributed::distributed(ctx, sf, g, groups)?,
    })
}
