//! Assembly: the unbalanced force (loads minus the internal forces, with its norm, settled block
//! by block as the elements finish with it) and the band tangent summed from beam and contact
//! elements and the follower loads, at one state. The per-element adds are `internal.rs`.

use super::coordinates::between;
use super::dofs::{DofMap, Ordering};
use super::follower::follower_response;
use super::internal::{add_element, add_plain_beam, Internal, Sink};
use super::obstacles::{add_obstacles, ObstacleLink};
use super::packed::PackedBeam;
use crate::solver::element::beam::BeamElement;
use crate::solver::element::contact_element::ContactOptions;
use crate::solver::element::friction::{Grip, Traction};
use crate::solver::element::rim::friction::turns_node;
use crate::solver::element::rim::rim_outcome;
use crate::solver::linear::reduce::sum_squares;
use crate::solver::linear::simd::{dispatch_wide, Avx2};
use crate::solver::linear::BandMatrix;
use crate::solver::model::Model;

/// Element-level results of one assembly, for reports.
#[derive(Clone, Debug, Default)]
pub struct ElementResults {
    /// (N, Mi, Mj) of every beam element.
    pub beam_forces: Vec<[f64; 3]>,
    /// For every contact link, in the order given: (Yc, li/l from the current chord).
    pub contact_forces: Vec<(f64, f64)>,
    /// For every obstacle link, in the order given: the normal force F_N (N).
    pub obstacle_forces: Vec<f64>,
    /// For every obstacle link, in the order given: its friction (`None`: none).
    pub obstacle_friction: Vec<Option<Traction>>,
    /// For every contact link, in the order given: its friction (`None`: frictionless); empty
    /// where the assembly had no grips.
    pub contact_friction: Vec<Option<Traction>>,
}

/// The assembled global quantities at one state.
#[derive(Clone, Debug, Default)]
pub struct Assembled {
    /// The unbalanced force over the free equations (by equation number): the loads given to
    /// the assembly ([`AssemblyContext::loads`]) minus the internal nodal forces sum J S.
    pub unbalanced: Vec<f64>,
    /// The sum of squares of `unbalanced`, accumulated as `sum_squares` accumulates it (bit for
    /// bit), in one pass with the assembly.
    pub unbalanced_norm2: f64,
    /// Each loaded equation of `unbalanced` and its entry before the load was added (in the
    /// order added), so that `reload` can load the same internal forces differently.
    pub unloaded: Vec<(usize, f64)>,
    /// Internal nodal forces sum J S at the dofs that are not free, in the order of
    /// [`DofMap::held`] (where they balance the reactions).
    pub held_internal: Vec<f64>,
    /// Tangent over the free equations (if requested).
    pub tangent: Option<BandMatrix>,
    /// K_fp dp over the free equations for a prescribed increment dp (empty if none was given).
    pub coupling: Vec<f64>,
    /// Element results.
    pub elements: ElementResults,
}

impl Assembled {
    /// Load the same internal forces with `loads` instead (at equations, ascending): the
    /// unbalanced force and its sum of squares become, bit for bit, those an assembly given
    /// `loads` would have. (The next increment's predictor, starting from the converged state
    /// under a new load factor.)
    pub fn reload(&mut self, loads: &[(usize, f64)]) {
        // Undone newest first, so an equation loaded twice gets its first entry back.
        for &(k, v) in self.unloaded.iter().rev() {
            self.unbalanced[k] = v;
        }
        self.unloaded.clear();
        for &(k, f) in loads {
            self.unloaded.push((k, self.unbalanced[k]));
            self.unbalanced[k] += f;
        }
        self.unbalanced_norm2 = sum_squares(&self.unbalanced);
    }
}

/// Everything an assembly needs besides the state.
pub struct AssemblyContext<'a> {
    /// The model.
    pub model: &'a Model,
    /// Its beam elements, ready to evaluate.
    pub elements: &'a [BeamElement],
    /// The same, packed for beams with no contact on them ([`PackedBeam::all`]).
    pub packed: &'a [PackedBeam],
    /// Dof numbering.
    pub dofs: &'a DofMap,
    /// Equation ordering (must match `links`).
    pub ordering: &'a Ordering,
    /// Contact element options.
    pub contact: ContactOptions,
    /// The external forces at their equations (ascending), for the unbalanced force; none
    /// leaves it `-sum J S`.
    pub loads: &'a [(usize, f64)],
    /// The load factors (one per load group) the follower loads are assembled at (`None`:
    /// the model has none, or they are left out).
    pub follower: Option<&'a [f64]>,
    /// The nodes resting on rigid obstacles.
    pub obstacles: &'a [ObstacleLink],
    /// The penalty of the obstacle contacts (N/m).
    pub obstacle_penalty: f64,
    /// The friction of every contact link (`ContactSet::grips`); empty: all frictionless.
    pub grips: &'a [Option<Grip>],
    /// The rounding residues of the displacements (`coordinates.rs`), over all dofs; empty:
    /// none.
    pub residue: &'a [f64],
}

/// Assemble internal forces (and the tangent) at displacements `d`.
/// `dp`, if given, is a prescribed increment (one value per [`Model::prescribed`]) whose K_fp
/// product is returned.
pub fn assemble(
    ctx: &AssemblyContext,
    d: &[f64],
    with_tangent: bool,
    dp: Option<&[f64]>,
) -> Assembled {
    let mut out = Assembled::default();
    assemble_into(ctx, d, with_tangent, dp, &mut out);
    out
}

/// Refill `out` with `len` copies of `v`, keeping its allocation.
fn refill<T: Clone>(out: &mut Vec<T>, len: usize, v: T) {
    out.clear();
    out.resize(len, v);
}

/// `assemble` into the buffers of a previous assembly (Newton iterations reuse them, so a
/// large model allocates nothing per iteration). Every field of `out` is overwritten; the
/// tangent is `None` unless requested.
pub fn assemble_into(
    ctx: &AssemblyContext,
    d: &[f64],
    with_tangent: bool,
    dp: Option<&[f64]>,
    out: &mut Assembled,
) {
    // The AVX2 build where the CPU has it, four plain beams at a time: the same arithmetic,
    // fewer instructions.
    dispatch_wide(
        #[inline(always)]
        |wide| assemble_kernel(ctx, d, with_tangent, dp, out, wide),
    );
}

/// The body of `assemble_into`; `wide` (the proof that the CPU has AVX2) evaluates four plain
/// beams in a row at once.
#[inline(always)]
pub(super) fn assemble_kernel(
    ctx: &AssemblyContext,
    d: &[f64],
    with_tangent: bool,
    dp: Option<&[f64]>,
    out: &mut Assembled,
    wide: Option<Avx2>,
) {
    let model = ctx.model;
    let dofs = ctx.dofs;
    let ord = ctx.ordering;
    let mut internal = Internal::new(
        std::mem::take(&mut out.unbalanced),
        ord.n_eq,
        ctx.loads,
        std::mem::take(&mut out.unloaded),
    );
    refill(&mut out.held_internal, dofs.held.len(), 0.0);
    refill(
        &mut out.coupling,
        if dp.is_some() { ord.n_eq } else { 0 },
        0.0,
    );
    let mut tangent = out.tangent.take();
    if with_tangent {
        // Beam tangents are exactly symmetric (entry by entry); contact elements' are not.
        let t = tangent.get_or_insert_with(|| BandMatrix::zeros(0, 0, 0));
        if ord.links.is_empty() && ctx.follower.is_none() && ctx.obstacles.is_empty() {
            t.reset_symmetric_lazily(ord.n_eq, ord.band);
        } else {
            t.reset(ord.n_eq, ord.band, ord.band);
        }
    } else {
        tangent = None;
    }
    let results = &mut out.elements;
    // Every beam and every contact link writes its entry below: resized, not cleared.
    results.beam_forces.resize(model.beams.len(), [0.0; 3]);
    results.contact_forces.resize(ord.links.len(), (0.0, 0.0));
    results.contact_friction.clear();
    results.contact_friction.resize(ctx.grips.len(), None);
    let mut held = (&dofs.held[..], &mut out.held_internal[..]);
    let coupling = &mut out.coupling;
    if !ctx.obstacles.is_empty() {
        let sink = Sink::of(&mut internal, &mut held, &mut tangent, &mut *coupling);
        let penalty = ctx.obstacle_penalty;
        let forces = (&mut results.obstacle_forces, &mut results.obstacle_friction);
        add_obstacles(
            model,
            dofs,
            ord,
            ctx.obstacles,
            penalty,
            d,
            with_tangent,
            dp,
            forces,
            sink,
        );
    } else {
        results.obstacle_forces.clear();
        results.obstacle_friction.clear();
    }
    let mut gdofs: Vec<usize> = Vec::with_capacity(12);
    let mut k6 = [[0.0; 6]; 6];
    let mut contact_beams = ord.contact_beams.iter().copied().peekable();
    let n_beams = model.beams.len();
    let mut e = 0;
    // A group handed back by the lanes goes one by one up to here.
    #[cfg(target_arch = "x86_64")]
    let mut one_by_one = 0;
    #[cfg(not(target_arch = "x86_64"))]
    let _ = wide;
    while e < n_beams {
        // Four plain beams in a row: evaluated side by side in the lanes of AVX2 vectors
        // where the CPU has them (`wide`), bit for bit as one by one.
        #[cfg(target_arch = "x86_64")]
        let group = match wide {
            Some(cpu)
                if e >= one_by_one
                    && ctx.follower.is_none()
                    && e + 4 <= n_beams
                    && contact_beams.peek().is_none_or(|&c| c >= e + 4) =>
            {
                Some(cpu)
            }
            _ => None,
        };
        #[cfg(target_arch = "x86_64")]
        if let Some(cpu) = group {
            let pb: [&PackedBeam; 4] = std::array::from_fn(|k| &ctx.packed[e + k]);
            let ends = pb.map(|b| b.ends(d, ctx.residue));
            let c = pb.map(|b| &b.constants);
            let lanes = super::super::element::beam_lanes::evaluate4(cpu, c, ends);
            if let Some(g) = lanes {
                for (k, b) in pb.into_iter().enumerate() {
                    let (forces, nodal, t) = g.lane(k, &b.constants);
                    let sink = Sink::of(&mut internal, &mut held, &mut tangent, &mut *coupling);
                    results.beam_forces[e + k] = forces;
                    let t = with_tangent.then_some(t);
                    add_plain_beam(e + k, b, &nodal, t, (ord, dofs, dp), &mut k6, sink);
                }
                e += 4;
                internal.settle(ord.final_before[e] as usize);
                continue;
            }
            one_by_one = e + 4;
        }
        let beam = &model.beams[e];
        // Positions relative to node i's (`coordinates::between`): the element only uses
        // differences, and (X_j - X_i) + ((u_j - u_i) + (r_j - r_i)) rounds to eps |x_j - x_i|
        // where X_j + u_j rounds to eps |X| and u_j to eps |u|. That keeps the residual's
        // round-off floor that of the elements' deformations.
        if contact_beams.next_if_eq(&e).is_none() {
            // A plain beam (both ends carry rotations): its closed-form tangent goes straight
            // into the band. Everything it needs is in its packed record (as `between` would
            // have it: node i at 0, node j at (X_j - X_i) + ((u_j - u_i) + (r_j - r_i))).
            let pb = &ctx.packed[e];
            let (xi, xj, phi) = pb.ends(d, ctx.residue);
            let (r, t) = pb
                .constants
                .evaluate_entries(xi, xj, phi[0], phi[1], with_tangent);
            results.beam_forces[e] = r.forces;
            let sink = Sink::of(&mut internal, &mut held, &mut tangent, &mut *coupling);
            let nodal: [f64; 6] = r.nodal.into();
            add_plain_beam(e, pb, &nodal, t, (ord, dofs, dp), &mut k6, sink);
        } else {
            let on_this = &ord.on_beam[e];
            let at = |n: usize| between(model, &dofs.first, (d, ctx.residue), n, beam.i);
            let ((xi, phi_i), (xj, phi_j)) = (at(beam.i), at(beam.j));
            gdofs.clear();
            gdofs.extend((0..3).map(|o| dofs.dof(beam.i, o)));
            gdofs.extend((0..3).map(|o| dofs.dof(beam.j, o)));
            let xc: Vec<[f64; 2]> = on_this.iter().map(|&k| at(ord.links[k].node).0).collect();
            for &k in on_this {
                let c = ord.links[k].node;
                gdofs.push(dofs.dof(c, 0));
                gdofs.push(dofs.dof(c, 1));
            }
            // Contacts on the axis (every one in most scenes) take the plain element.
            let rims: Vec<f64> = if on_this.iter().all(|&k| ord.links[k].rim == 0.0) {
                Vec::new()
            } else {
                on_this.iter().map(|&k| ord.links[k].rim).collect()
            };
            // No grips (a frictionless model): an empty slice, nothing to gather. A grip off
            // the axis takes its node's rotation, which its rim turns with; where the rim
            // takes the friction's moment, that rotation is a dof of the element, after the
            // contact nodes' (u, v).
            let grips: Vec<Option<Grip>> = if ctx.grips.is_empty() {
                Vec::new()
            } else {
                on_this
                    .iter()
                    .map(|&k| turned_grip(model, dofs, d, ord, k, ctx.grips[k]))
                    .collect()
            };
            for (m, &k) in on_this.iter().enumerate() {
                if !rims.is_empty() && !grips.is_empty() && turns_node(rims[m], &grips[m]) {
                    gdofs.push(dofs.dof(ord.links[k].node, 2));
                }
            }
            let out = rim_outcome(
                &ctx.elements[e],
                (xi, xj),
                [phi_i, phi_j],
                &xc,
                &rims,
                ctx.contact,
                &grips,
                with_tangent,
            );
            if !ctx.grips.is_empty() {
                for (m, &k) in on_this.iter().enumerate() {
                    results.contact_friction[k] = out.friction[m];
                }
            }
            let r = out.response;
            results.beam_forces[e] = [r.forces[0], r.forces[1], r.forces[2]];
            for (m, &k) in on_this.iter().enumerate() {
                results.contact_forces[k] = (r.forces[3 + m], r.xi[m]);
            }
            let k = r
                .tangent
                .as_ref()
                .map(|k| move |a: usize, b: usize| k[(a, b)]);
            let sink = Sink::of(&mut internal, &mut held, &mut tangent, &mut *coupling);
            add_element(&gdofs, r.nodal.as_slice(), k, ord, dofs, dp, sink);
        }
        if let Some(factors) = ctx.follower {
            let on = model.distributed_on(e);
            if on.iter().any(|l| l.follower) {
                let (chord, _) = between(model, &dofs.first, (d, ctx.residue), beam.j, beam.i);
                let (nodal, k) = follower_response(on, chord, factors);
                gdofs.clear();
                gdofs.extend(
                    [beam.i, beam.j]
                        .iter()
                        .flat_map(|&n| (0..2).map(move |o| (n, o)))
                        .map(|(n, o)| dofs.dof(n, o)),
                );
                let k = with_tangent.then_some(move |a: usize, b: usize| k[a][b]);
                let sink = Sink::of(&mut internal, &mut held, &mut tangent, &mut *coupling);
                add_element(&gdofs, &nodal, k, ord, dofs, dp, sink);
            }
        }
        e += 1;
        internal.settle(ord.final_before[e] as usize);
    }
    if let Some(band) = tangent.as_mut() {
        band.finish_assembly();
    }
    out.tangent = tangent;
    (out.unbalanced, out.unbalanced_norm2, out.unloaded) = internal.finish();
}

/// Contact link `k`'s grip `grip` with its node's rotation at displacements `d` where the
/// contact stands off the axis and the node has one (`Grip::turn`).
fn turned_grip(
    model: &Model,
    dofs: &DofMap,
    d: &[f64],
    ord: &Ordering,
    k: usize,
    grip: Option<Grip>,
) -> Option<Grip> {
    let link = &ord.links[k];
    grip.map(|g| Grip {
        turn: (link.rim != 0.0 && model.nodes[link.node].rotation)
            .then(|| d[dofs.dof(link.node, 2)]),
        ..g
    })
}
