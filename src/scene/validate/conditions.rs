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
                g.check_dof(ctx, format!("supports[{k}].phi (node {})", s.node), n, dof)?;
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
        if ![l.fx, l.fy, l.m].iter().all(|&v| sized(v)) {
            return Err(ctx.err(
                format!("loads[{k}] (node {})", l.node),
                Some(format!("node:{}", l.node)),
                "a load must be finite and below 1e100 in size",
            ));
        }
        loads.push(Load {
            node: n,
            force: [l.fx, l.fy, l.m],
            group: group_index(groups, l.group.as_deref()),
        });
    }
    let mut prescribed: Vec<Prescribed> = Vec::new();
    for (k, p) in sf.prescribed.iter().enumerate() {
        let field = format!("prescribed[{k}] (node {} {})", p.node, p.dof.name());
        let n = g.node_of(ctx, field.clone(), p.node)?;
        g.check_dof(ctx, field.clone(), n, p.dof)?;
        let nd = Some(format!("node:{}", p.node));
        if !sized(p.per_step) {
            return Err(ctx.err(field, nd, "per_step must be finite and below 1e100 in size"));
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
