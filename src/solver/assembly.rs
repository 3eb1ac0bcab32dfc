//! Assembly: the dof map (which global dofs are free, supported or prescribed), the equation
//! ordering (reverse Cuthill-McKee over the current element graph, contacts included), and the
//! unbalanced force (loads minus the internal forces, with its norm, settled block by block as
//! the elements finish with it) and band tangent summed from beam and contact elements.

use super::beam::{BeamElement, ForceConstants, TangentEntries};
use super::contact_element::{contact_response, ContactOptions};
use super::linear::{consecutive_first, reverse_cuthill_mckee, zero_ahead, BandMatrix, NOT_FREE};
use super::model::Model;
use super::reduce::sum_squares;
use super::simd::dispatch_wide;

/// What a global dof is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DofKind {
    /// Solved for.
    Free,
    /// Held at zero.
    Supported,
    /// Driven; index into `Model::prescribed`.
    Prescribed(usize),
}

/// Global dof numbering: node n owns dofs `first[n] .. first[n] + model.node_dofs(n)`.
#[derive(Clone, Debug)]
pub struct DofMap {
    /// First global dof of each node.
    pub first: Vec<usize>,
    /// Kind of each global dof.
    pub kind: Vec<DofKind>,
    /// The global dofs that are not free (supported or prescribed), ascending: where the
    /// reactions act.
    pub held: Vec<usize>,
}

impl DofMap {
    /// Number the dofs of `model`.
    pub fn new(model: &Model) -> DofMap {
        let mut first = Vec::with_capacity(model.nodes.len());
        let mut total = 0;
        for n in 0..model.nodes.len() {
            first.push(total);
            total += model.node_dofs(n);
        }
        let mut kind = vec![DofKind::Free; total];
        for s in &model.supports {
            kind[first[s.node] + s.dof.offset()] = DofKind::Supported;
        }
        for (p, pr) in model.prescribed.iter().enumerate() {
            kind[first[pr.node] + pr.dof.offset()] = DofKind::Prescribed(p);
        }
        let held = (0..total).filter(|&g| kind[g] != DofKind::Free).collect();
        DofMap { first, kind, held }
    }

    /// Total number of dofs.
    pub fn len(&self) -> usize {
        self.kind.len()
    }

    /// True if the model has no dofs.
    pub fn is_empty(&self) -> bool {
        self.kind.is_empty()
    }

    /// The global dof index of (node, offset).
    pub fn dof(&self, node: usize, offset: usize) -> usize {
        self.first[node] + offset
    }

    /// (node, offset) of a global dof.
    pub fn owner(&self, dof: usize) -> (usize, usize) {
        let n = self.first.partition_point(|&f| f <= dof) - 1;
        (n, dof - self.first[n])
    }
}

/// A contact node resting on a beam element (what the assembly needs of a contact).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContactLink {
    /// Index of the contact node.
    pub node: usize,
    /// Index of the beam element it touches.
    pub beam: usize,
}

/// Equation numbers of the free dofs for one element topology, and the band widths.
#[derive(Clone, Debug)]
pub struct Ordering {
    /// Equation of each global dof (`NOT_FREE` if not free): 4 bytes a dof, so that the loops
    /// over every dof of a large model stream as little memory as they can.
    pub eq: Vec<u32>,
    /// Number of equations.
    pub n_eq: usize,
    /// The global dof of every equation (the inverse of `eq`).
    pub dof_of: Vec<u32>,
    /// `Some(g)` where equation e is dof g + e for every e (a chain numbered along itself,
    /// supports only at its start): `add_scaled` then works on one run of each vector.
    pub dofs_in_a_row: Option<usize>,
    /// Half-bandwidth.
    pub band: usize,
    /// The contact topology this ordering was built for.
    pub links: Vec<ContactLink>,
    /// For every beam, the indices into `links` of the contacts resting on it.
    pub on_beam: Vec<Vec<usize>>,
    /// The beams with a contact resting on them, ascending (the assembly walks the others
    /// without reading `on_beam`).
    pub contact_beams: Vec<usize>,
    /// For every beam, the equations of its six dofs (u, v, phi at i, then at j; `NOT_FREE`
    /// where the dof is not free).
    pub beam_eqs: Vec<[u32; 6]>,
    /// For every beam, its first equation where its six dofs are free and numbered
    /// consecutively in local order (`consecutive_first`), else `NOT_FREE`: all the assembly
    /// reads of a beam's equations in the usual case.
    pub beam_first: Vec<u32>,
    /// For every beam e, and one past the last: no beam from e on (contact nodes included)
    /// reaches an equation below `final_before[e]` (the smallest equation they reach; `n_eq`
    /// past the last). The assembly settles the unbalanced force below it (`Internal::settle`)
    /// as soon as beam e - 1 is in.
    pub final_before: Vec<u32>,
}

impl Ordering {
    /// Order the free dofs of `model` for the element graph with the given contacts.
    pub fn new(model: &Model, dofs: &DofMap, links: &[ContactLink]) -> Ordering {
        let nn = model.nodes.len();
        let mut adj = vec![Vec::new(); nn];
        let mut connect = |a: usize, b: usize| {
            if a != b {
                adj[a].push(b);
                adj[b].push(a);
            }
        };
        for b in &model.beams {
            connect(b.i, b.j);
        }
        for l in links {
            let b = &model.beams[l.beam];
            connect(b.i, l.node);
            connect(b.j, l.node);
        }
        let perm = reverse_cuthill_mckee(&adj);
        let mut eq = vec![NOT_FREE; dofs.len()];
        let mut n_eq = 0;
        for &n in &perm {
            for o in 0..model.node_dofs(n) {
                let d = dofs.dof(n, o);
                if dofs.kind[d] == DofKind::Free {
                    assert!(n_eq < NOT_FREE, "more equations than u32 numbers");
                    eq[d] = n_eq;
                    n_eq += 1;
                }
            }
        }
        let n_eq = n_eq as usize;
        let mut dof_of = vec![0; n_eq];
        for (g, &e) in eq.iter().enumerate() {
            if e != NOT_FREE {
                dof_of[e as usize] = u32::try_from(g).expect("dofs fit in u32");
            }
        }
        let dofs_in_a_row = dof_of
            .first()
            .map(|&g| g as usize)
            .filter(|&g| (dof_of.iter().enumerate()).all(|(e, &d)| d as usize == g + e));
        let mut on_beam = vec![Vec::new(); model.beams.len()];
        for (k, l) in links.iter().enumerate() {
            on_beam[l.beam].push(k);
        }
        let beam_eqs: Vec<[u32; 6]> = model
            .beams
            .iter()
            .map(|b| std::array::from_fn(|a| eq[dofs.dof([b.i, b.j][a / 3], a % 3)]))
            .collect();
        let beam_first = (beam_eqs.iter())
            .map(|eqs| consecutive_first(eqs).map_or(NOT_FREE, |f| f as u32))
            .collect();
        let contact_beams = (0..model.beams.len())
            .filter(|&e| !on_beam[e].is_empty())
            .collect();
        let mut ord = Ordering {
            eq,
            n_eq,
            dof_of,
            dofs_in_a_row,
            band: 0,
            links: links.to_vec(),
            on_beam,
            contact_beams,
            beam_eqs,
            beam_first,
            final_before: vec![n_eq as u32; model.beams.len() + 1],
        };
        let mut band = 0;
        for (e, b) in model.beams.iter().enumerate() {
            let mut nodes = vec![b.i, b.j];
            nodes.extend(ord.on_beam[e].iter().map(|&k| links[k].node));
            let eqs: Vec<usize> = nodes
                .iter()
                .flat_map(|&n| (0..model.node_dofs(n)).map(move |o| (n, o)))
                .filter_map(|(n, o)| ord.equation(dofs.dof(n, o)))
                .collect();
            if let (Some(lo), Some(hi)) = (eqs.iter().min(), eqs.iter().max()) {
                band = band.max(hi - lo);
                ord.final_before[e] = *lo as u32;
            }
        }
        for e in (0..model.beams.len()).rev() {
            ord.final_before[e] = ord.final_before[e].min(ord.final_before[e + 1]);
        }
        ord.band = band;
        ord
    }

    /// `d[dof_of[e]] += scale x[e]` for every equation e (x over the equations, d over the
    /// dofs): in one run over slices where the dofs are in a row (`dofs_in_a_row`), the same
    /// arithmetic either way.
    pub fn add_scaled(&self, d: &mut [f64], scale: f64, x: &[f64]) {
        match self.dofs_in_a_row {
            Some(g) => {
                for (v, x) in d[g..g + x.len()].iter_mut().zip(x) {
                    *v += scale * x;
                }
            }
            None => {
                for (&g, x) in self.dof_of.iter().zip(x) {
                    d[g as usize] += scale * x;
                }
            }
        }
    }

    /// The equation of global dof `g`, if it is free.
    #[inline]
    pub fn equation(&self, g: usize) -> Option<usize> {
        let e = self.eq[g];
        (e != NOT_FREE).then_some(e as usize)
    }

    /// (global dof, equation) of every free dof, in global dof order.
    #[inline]
    pub fn free_dofs(&self) -> impl Iterator<Item = (usize, usize)> + '_ {
        self.eq
            .iter()
            .enumerate()
            .filter(|(_, &e)| e != NOT_FREE)
            .map(|(g, &e)| (g, e as usize))
    }
}

/// Element-level results of one assembly, for reports.
#[derive(Clone, Debug, Default)]
pub struct ElementResults {
    /// (N, Mi, Mj) of every beam element.
    pub beam_forces: Vec<[f64; 3]>,
    /// For every contact link, in the order given: (Yc, li/l from the current chord).
    pub contact_forces: Vec<(f64, f64)>,
}

/// The assembled global quantities at one state.
#[derive(Clone, Debug, Default)]
pub struct Assembled {
    /// The unbalanced force over the free equations (by equation number): the loads given to
    /// the assembly (`AssemblyContext::loads`) minus the internal nodal forces sum J S.
    pub unbalanced: Vec<f64>,
    /// The sum of squares of `unbalanced`, accumulated as `sum_squares` accumulates it (bit for
    /// bit), in one pass with the assembly.
    pub unbalanced_norm2: f64,
    /// Each loaded equation of `unbalanced` and its entry before the load was added (in the
    /// order added), so that `reload` can load the same internal forces differently.
    pub unloaded: Vec<(usize, f64)>,
    /// Internal nodal forces sum J S at the dofs that are not free, in the order of
    /// `DofMap::held` (where they balance the reactions).
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

/// What the assembly reads of a beam with no contact on it, packed into one cache line: the
/// first global dofs of its end nodes (u, v, phi each), the initial position of its end j
/// relative to its end i, and its force constants.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PackedBeam {
    /// First global dof of node i, then of node j.
    pub first: [u32; 2],
    /// X_j - X_i (initial).
    pub span: [f64; 2],
    /// The element force equation's constants.
    pub constants: ForceConstants,
}

impl PackedBeam {
    /// The packed beams of `model` (whose elements are `elements`, numbered by `dofs`).
    pub fn all(model: &Model, dofs: &DofMap, elements: &[BeamElement]) -> Vec<PackedBeam> {
        let first = |n: usize| u32::try_from(dofs.first[n]).expect("dofs fit in u32");
        model
            .beams
            .iter()
            .zip(elements)
            .map(|(b, el)| {
                let (p, q) = (model.position(b.i), model.position(b.j));
                PackedBeam {
                    first: [first(b.i), first(b.j)],
                    span: [q[0] - p[0], q[1] - p[1]],
                    constants: el.constants(),
                }
            })
            .collect()
    }

    /// The beam's ends at displacements `d`, as `relative` has them: end i at 0 + u_i, end j
    /// at (X_j - X_i) + u_j, and the end rotations (i, j).
    #[inline(always)]
    pub fn ends(&self, d: &[f64]) -> ([f64; 2], [f64; 2], [f64; 2]) {
        let u = |end: usize| {
            let f = self.first[end] as usize;
            &d[f..f + 3]
        };
        let (ui, uj) = (u(0), u(1));
        (
            [0.0 + ui[0], 0.0 + ui[1]],
            [self.span[0] + uj[0], self.span[1] + uj[1]],
            [ui[2], uj[2]],
        )
    }
}

/// Everything an assembly needs besides the state.
pub struct AssemblyContext<'a> {
    /// The model.
    pub model: &'a Model,
    /// Its beam elements, ready to evaluate.
    pub elements: &'a [BeamElement],
    /// The same, packed for beams with no contact on them (`PackedBeam::all`).
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
}

/// Current position of node `n` and its rotation (0 for 2-dof nodes).
#[inline]
pub fn current(model: &Model, dofs: &DofMap, d: &[f64], n: usize) -> ([f64; 2], f64) {
    let f = dofs.first[n];
    let p = model.position(n);
    let phi = if model.nodes[n].rotation {
        d[f + 2]
    } else {
        0.0
    };
    ([p[0] + d[f], p[1] + d[f + 1]], phi)
}

/// Position of node `n` relative to the initial position of node `origin`, and its rotation:
/// `(X_n - X_origin) + u_n`.
#[inline]
pub fn relative(
    model: &Model,
    dofs: &DofMap,
    d: &[f64],
    n: usize,
    origin: usize,
) -> ([f64; 2], f64) {
    let f = dofs.first[n];
    let (p, o) = (model.position(n), model.position(origin));
    let phi = if model.nodes[n].rotation {
        d[f + 2]
    } else {
        0.0
    };
    ([(p[0] - o[0]) + d[f], (p[1] - o[1]) + d[f + 1]], phi)
}

/// Assemble internal forces (and the tangent) at displacements `d`.
/// `dp`, if given, is a prescribed increment (one value per `Model::prescribed`) whose K_fp
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

/// The body of `assemble_into`; `wide` (only where the CPU has AVX2) evaluates four plain
/// beams in a row at once.
#[inline(always)]
fn assemble_kernel(
    ctx: &AssemblyContext,
    d: &[f64],
    with_tangent: bool,
    dp: Option<&[f64]>,
    out: &mut Assembled,
    wide: bool,
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
        if ord.links.is_empty() {
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
    let held = (&dofs.held[..], &mut out.held_internal[..]);
    let coupling = &mut out.coupling;
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
        if wide
            && e >= one_by_one
            && e + 4 <= n_beams
            && contact_beams.peek().is_none_or(|&c| c >= e + 4)
        {
            let pb: [&PackedBeam; 4] = std::array::from_fn(|k| &ctx.packed[e + k]);
            let ends = pb.map(|b| b.ends(d));
            let c = pb.map(|b| &b.constants);
            // SAFETY: `wide` only where the CPU has AVX2 (see `assemble_into`).
            let lanes = unsafe { super::beam_lanes::evaluate4(c, ends) };
            if let Some(g) = lanes {
                for (k, b) in pb.into_iter().enumerate() {
                    let (forces, nodal, t) = g.lane(k, &b.constants);
                    let sink = (
                        &mut internal,
                        (held.0, &mut *held.1),
                        tangent.as_mut(),
                        &mut *coupling,
                    );
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
        // Positions relative to node i's initial position: the element only uses differences,
        // and (X_j - X_i) + (u_j - u_i) rounds to eps |u| where X_j + u_j rounds to eps |X|.
        // That keeps the round-off floor of the residual low for lightly loaded states.
        if contact_beams.next_if_eq(&e).is_none() {
            // A plain beam (both ends carry rotations): its closed-form tangent goes straight
            // into the band. Everything it needs is in its packed record (as `relative` would
            // have it: node i at 0 + u_i, node j at (X_j - X_i) + u_j).
            let pb = &ctx.packed[e];
            let (xi, xj, phi) = pb.ends(d);
            let (r, t) = pb
                .constants
                .evaluate_entries(xi, xj, phi[0], phi[1], with_tangent);
            results.beam_forces[e] = r.forces;
            let sink = (
                &mut internal,
                (held.0, &mut *held.1),
                tangent.as_mut(),
                &mut *coupling,
            );
            let nodal: [f64; 6] = r.nodal.into();
            add_plain_beam(e, pb, &nodal, t, (ord, dofs, dp), &mut k6, sink);
        } else {
            let on_this = &ord.on_beam[e];
            let (xi, phi_i) = relative(model, dofs, d, beam.i, beam.i);
            let (xj, phi_j) = relative(model, dofs, d, beam.j, beam.i);
            gdofs.clear();
            gdofs.extend((0..3).map(|o| dofs.dof(beam.i, o)));
            gdofs.extend((0..3).map(|o| dofs.dof(beam.j, o)));
            let xc: Vec<[f64; 2]> = on_this
                .iter()
                .map(|&k| relative(model, dofs, d, ord.links[k].node, beam.i).0)
                .collect();
            for &k in on_this {
                let c = ord.links[k].node;
                gdofs.push(dofs.dof(c, 0));
                gdofs.push(dofs.dof(c, 1));
            }
            let r = contact_response(
                &ctx.elements[e],
                xi,
                xj,
                [phi_i, phi_j],
                &xc,
                ctx.contact,
                with_tangent,
            );
            results.beam_forces[e] = [r.forces[0], r.forces[1], r.forces[2]];
            for (m, &k) in on_this.iter().enumerate() {
                results.contact_forces[k] = (r.forces[3 + m], r.xi[m]);
            }
            let k = r
                .tangent
                .as_ref()
                .map(|k| move |a: usize, b: usize| k[(a, b)]);
            let sink = (
                &mut internal,
                (held.0, &mut *held.1),
                tangent.as_mut(),
                &mut *coupling,
            );
            add_element(&gdofs, r.nodal.as_slice(), k, ord, dofs, dp, sink);
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

/// The fewest equations `Internal::settle` takes at a time: enough to pay for the call, few
/// enough (1 KiB) to be in L1 still.
const SETTLE_BATCH: usize = 128;

/// The internal forces over the free equations while an assembly adds to them, turned into
/// the unbalanced force (negated, loaded and summed) block by block as the assembly finishes
/// with them. They are zeroed a block at a time as the elements reach them (in one pass with
/// the assembly, while in cache, as the band is: `BandMatrix::reset_symmetric_lazily`), not
/// in a pass of their own; and settled (`settle`) while still in cache, not in a pass of
/// their own either.
struct Internal<'a> {
    /// The forces (stale from the last assembly beyond `zeroed`; the unbalanced force before
    /// `settled`).
    v: Vec<f64>,
    /// Entries before this are valid.
    zeroed: usize,
    /// Entries before this (a multiple of 4 until `finish`) are final: negated, loaded and
    /// summed into `acc`.
    settled: usize,
    /// The loads not yet added (at equations, ascending).
    loads: &'a [(usize, f64)],
    /// The loaded equations and their entries before the load (`Assembled::unloaded`).
    unloaded: Vec<(usize, f64)>,
    /// The sum of squares of the settled entries in four partial sums, entry k in `acc[k % 4]`
    /// (as `sum_squares` has them).
    acc: [f64; 4],
}

impl<'a> Internal<'a> {
    /// `n` forces over the storage of the last assembly's (`v`, and `unloaded`), none yet
    /// valid, to be loaded with `loads`.
    fn new(
        mut v: Vec<f64>,
        n: usize,
        loads: &'a [(usize, f64)],
        mut unloaded: Vec<(usize, f64)>,
    ) -> Internal<'a> {
        v.truncate(n);
        v.resize(n, 0.0);
        unloaded.clear();
        Internal {
            v,
            zeroed: 0,
            settled: 0,
            loads,
            unloaded,
            acc: [0.0; 4],
        }
    }

    /// Make the entries before `end` valid (`zero_ahead`).
    #[inline(always)]
    fn zero_to(&mut self, end: usize) {
        zero_ahead(&mut self.v, &mut self.zeroed, end);
    }

    /// Add `f` to the force of equation `q`.
    #[inline(always)]
    fn add(&mut self, q: usize, f: f64) {
        debug_assert!(
            q >= self.settled,
            "equation {q} added to after it was settled"
        );
        self.zero_to(q + 1);
        self.v[q] += f;
    }

    /// The forces of the six equations from `first` on, ready to add to.
    #[inline(always)]
    fn run6(&mut self, first: usize) -> &mut [f64; 6] {
        debug_assert!(
            first >= self.settled,
            "equation {first} added to after it was settled"
        );
        self.zero_to(first + 6);
        (&mut self.v[first..first + 6]).try_into().unwrap()
    }

    /// No element adds to the equations before `end` any more (`Ordering::final_before`):
    /// settle their whole blocks of four, in batches of at least `SETTLE_BATCH` equations.
    #[inline(always)]
    fn settle(&mut self, end: usize) {
        if end >= self.settled + SETTLE_BATCH {
            self.settle_blocks(end & !3);
        }
    }

    /// Settle the entries from `settled` to `end` (a multiple of 4): negate each block of
    /// four, add its loads, and add the squares to the partial sums (entry k into `acc[k % 4]`,
    /// as `sum_squares` sums).
    #[inline(always)]
    fn settle_blocks(&mut self, end: usize) {
        self.zero_to(end);
        let start = self.settled;
        let mut acc = self.acc;
        let blocks = self.v[start..end].chunks_exact_mut(4);
        if self.loads.first().is_none_or(|&(k, _)| k >= end) {
            // No load among them (the usual case).
            for o in blocks {
                for (a, x) in acc.iter_mut().zip(o) {
                    *x = -*x;
                    *a += *x * *x;
                }
            }
        } else {
            for (b, o) in blocks.enumerate() {
                let base = start + 4 * b;
                for x in o.iter_mut() {
                    *x = -*x;
                }
                while let Some((&(k, f), rest)) = self.loads.split_first() {
                    if k >= base + 4 {
                        break;
                    }
                    self.unloaded.push((k, o[k - base]));
                    o[k - base] += f;
                    self.loads = rest;
                }
                for (a, x) in acc.iter_mut().zip(o.iter()) {
                    *a += x * x;
                }
            }
        }
        self.acc = acc;
        self.settled = end;
    }

    /// The unbalanced force, its sum of squares and the loaded equations' entries before
    /// their loads: the rest settled (those no element reached zeroed).
    fn finish(mut self) -> (Vec<f64>, f64, Vec<(usize, f64)>) {
        let n = self.v.len();
        self.zero_to(n);
        self.settle_blocks(n & !3);
        let whole = self.settled;
        for x in &mut self.v[whole..] {
            *x = -*x;
        }
        for &(k, f) in self.loads {
            self.unloaded.push((k, self.v[k]));
            self.v[k] += f;
        }
        let acc = self.acc;
        let norm2 = self.v[whole..]
            .iter()
            .fold((acc[0] + acc[1]) + (acc[2] + acc[3]), |s, x| s + x * x);
        (self.v, norm2, self.unloaded)
    }
}

/// Add a plain beam's nodal forces and (if given) its tangent entries: straight into six
/// consecutive equations where its dofs have them (`Ordering::beam_first`), dof by dof
/// otherwise; with its K_fp dp where a prescribed increment `dp` is given (`k6` the scratch for
/// its whole tangent).
#[inline(always)]
fn add_plain_beam(
    e: usize,
    pb: &PackedBeam,
    nodal: &[f64; 6],
    t: Option<TangentEntries>,
    (ord, dofs, dp): (&Ordering, &DofMap, Option<&[f64]>),
    k6: &mut [[f64; 6]; 6],
    (internal, held, tangent, coupling): Sink,
) {
    let (fi, fj) = (pb.first[0] as usize, pb.first[1] as usize);
    let g: [usize; 6] = std::array::from_fn(|a| [fi, fj][a / 3] + a % 3);
    let first = ord.beam_first[e];
    if first != NOT_FREE {
        // Six free equations in a row (a chain numbered along itself).
        let first = first as usize;
        for (v, f) in internal.run6(first).iter_mut().zip(nodal) {
            *v += f;
        }
    } else {
        let eqs = &ord.beam_eqs[e];
        for ((&q, &g), &f) in eqs.iter().zip(&g).zip(nodal) {
            add_nodal_force(q, g, f, internal, (held.0, &mut *held.1));
        }
    }
    if let (Some(band), Some(t)) = (tangent, t) {
        if first != NOT_FREE {
            band.add_beam_consecutive(first as usize, &t);
        } else {
            band.add_beam(&ord.beam_eqs[e], &t);
        }
        if let Some(dp) = dp {
            t.write(k6);
            let eqs: [Option<usize>; 6] = std::array::from_fn(|a| ord.equation(g[a]));
            add_coupling(&g, &eqs, |a, b| k6[a][b], dofs, dp, coupling);
        }
    }
}

/// The held dofs (`DofMap::held`) and the internal forces at them.
type Held<'a> = (&'a [usize], &'a mut [f64]);

/// Add nodal force `f` at global dof `g`, whose equation is `q` (`NOT_FREE` if it has none):
/// to the free equations' internal forces, or to those at the held dofs.
#[inline(always)]
fn add_nodal_force(q: u32, g: usize, f: f64, internal: &mut Internal<'_>, (dofs, forces): Held) {
    if q != NOT_FREE {
        internal.add(q as usize, f);
    } else {
        let k = dofs
            .binary_search(&g)
            .expect("a dof with no equation is held");
        forces[k] += f;
    }
}

/// Where element contributions go: internal forces (free equations, then held dofs), the band
/// tangent, K_fp dp.
type Sink<'a, 'b> = (
    &'a mut Internal<'b>,
    Held<'a>,
    Option<&'a mut BandMatrix>,
    &'a mut Vec<f64>,
);

/// Add one element's nodal forces and (if given) its tangent over the global dofs `gdofs`.
fn add_element(
    gdofs: &[usize],
    nodal: &[f64],
    k: Option<impl Fn(usize, usize) -> f64>,
    ord: &Ordering,
    dofs: &DofMap,
    dp: Option<&[f64]>,
    (internal, held, band, coupling): Sink,
) {
    for (a, &g) in gdofs.iter().enumerate() {
        add_nodal_force(ord.eq[g], g, nodal[a], internal, (held.0, &mut *held.1));
    }
    if let Some(k) = k {
        add_matrix(gdofs, k, ord, band, dofs, dp, coupling);
    }
}

fn add_matrix(
    gdofs: &[usize],
    k: impl Fn(usize, usize) -> f64,
    ord: &Ordering,
    band: Option<&mut BandMatrix>,
    dofs: &DofMap,
    dp: Option<&[f64]>,
    coupling: &mut [f64],
) {
    let Some(band) = band else { return };
    let eqs: Vec<Option<usize>> = gdofs.iter().map(|&g| ord.equation(g)).collect();
    for (a, &ea) in eqs.iter().enumerate() {
        let Some(ea) = ea else { continue };
        for (b, &eb) in eqs.iter().enumerate() {
            if let Some(eb) = eb {
                band.add(ea, eb, k(a, b));
            }
        }
    }
    if let Some(dp) = dp {
        add_coupling(gdofs, &eqs, k, dofs, dp, coupling);
    }
}

/// Add an element's `K_fp dp` over the global dofs `gdofs` (with equations `eqs`), for the
/// prescribed increments `dp` (one per `Model::prescribed`, found through `DofKind`).
fn add_coupling(
    gdofs: &[usize],
    eqs: &[Option<usize>],
    k: impl Fn(usize, usize) -> f64,
    dofs: &DofMap,
    dp: &[f64],
    coupling: &mut [f64],
) {
    for (a, &ea) in eqs.iter().enumerate() {
        let Some(ea) = ea else { continue };
        for (b, &gb) in gdofs.iter().enumerate() {
            // A prescribed dof has no equation.
            let DofKind::Prescribed(p) = dofs.kind[gb] else {
                continue;
            };
            if dp[p] != 0.0 {
                coupling[ea] += k(a, b) * dp[p];
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::solver::Solver;

    /// `add_scaled` adds what the equation-by-equation loop over `dof_of` adds, bit for bit,
    /// both where the dofs are in a row (the Mattiasson cantilever: clamped at its first node)
    /// and where they are not (Example 3.2: bodies, supports at both ends, contacts).
    #[test]
    fn a_scaled_correction_lands_on_the_dofs_of_its_equations() {
        for (scene, steps, in_a_row) in [("mattiasson", 0, true), ("example_3_2", 30, false)] {
            let s = crate::test_support::solver_after(scene, steps);
            let ord = s.ordering_for(&s.contacts);
            assert_eq!(ord.dofs_in_a_row.is_some(), in_a_row, "{scene}");
            let x: Vec<f64> = (0..ord.n_eq).map(|e| 0.37 * e as f64 - 1.1).collect();
            let d0: Vec<f64> = (0..s.dofs.len()).map(|g| (g as f64).sin()).collect();
            let mut expected = d0.clone();
            for (e, &g) in ord.dof_of.iter().enumerate() {
                expected[g as usize] += 0.7 * x[e];
            }
            let mut d = d0;
            ord.add_scaled(&mut d, 0.7, &x);
            let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
            assert_eq!(bits(&d), bits(&expected), "{scene}");
        }
    }

    /// An assembly into the buffers of an earlier one (stale internal forces and band, zeroed
    /// as the elements reach them) gives what an assembly into fresh buffers gives, bit for
    /// bit: over the buffers of another state of the same model (a long beam of 1000 elements,
    /// several blocks of lazy zeroing; Example 3.2 with contacts, its equations reached out of
    /// order) and over those of a larger model.
    #[test]
    fn an_assembly_over_old_buffers_is_a_fresh_one() {
        let long = crate::scaling::long_beam(1000).solver().expect("stable");
        let mut larger = Assembled::default();
        let ord = long.ordering_for(&long.contacts);
        let bent: Vec<f64> = (0..long.d.len()).map(|g| 1e-3 * (g as f64).sin()).collect();
        assemble_into(&long.context(&ord), &bent, true, None, &mut larger);
        let contact = crate::test_support::solver_after("example_3_2", 30);
        for (s, reuse_larger) in [(&long, false), (&contact, false), (&contact, true)] {
            let ord = s.ordering_for(&s.contacts);
            let ctx = s.context(&ord);
            let mut out = if reuse_larger {
                larger.clone()
            } else {
                let other: Vec<f64> = s.d.iter().map(|v| 1.5 * v + 1e-4).collect();
                assemble(&ctx, &other, true, None)
            };
            // A deformed state (the long beam has not been stepped).
            let now: Vec<f64> = (s.d.iter().enumerate())
                .map(|(g, v)| v + 1e-4 * (0.3 * g as f64).cos())
                .collect();
            assemble_into(&ctx, &now, true, None, &mut out);
            let fresh = assemble(&ctx, &now, true, None);
            let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
            let case = format!(
                "{} equations, over a larger model's: {reuse_larger}",
                ord.n_eq
            );
            assert_eq!(bits(&out.unbalanced), bits(&fresh.unbalanced), "{case}");
            assert_eq!(
                bits(&out.held_internal),
                bits(&fresh.held_internal),
                "{case}"
            );
            assert!(fresh.unbalanced.iter().any(|f| *f != 0.0), "{case}: loaded");
            let (ko, kf) = (
                out.tangent.expect("tangent"),
                fresh.tangent.expect("tangent"),
            );
            for i in 0..ord.n_eq {
                for j in i.saturating_sub(ord.band)..(i + ord.band + 1).min(ord.n_eq) {
                    assert_eq!(ko.get(i, j).to_bits(), kf.get(i, j).to_bits(), "{case}");
                }
            }
        }
    }

    /// The unbalanced force settled block by block during the assembly is, bit for bit, what
    /// separate passes over the internal forces give (negate them, add the loads, then
    /// `sum_squares`, as Newton did before): on a chain of 1000 elements (equations in a row,
    /// settled as the elements go) and on Example 3.2 with contacts (equations reached out of
    /// order, most settled at the end), with the scene's own loads (none for Example 3.2) and with loads at the first
    /// equation, on both sides of a block boundary, in the middle and in the last,
    /// incomplete block. `reload` then gives what an assembly with the other loads gives.
    #[test]
    fn the_unbalanced_force_settled_during_assembly_is_the_separate_pass() {
        let long = crate::scaling::long_beam(1002).solver().expect("stable");
        let contact = crate::test_support::solver_after("example_3_2", 30);
        for s in [&long, &contact] {
            let ord = s.ordering_for(&s.contacts);
            let n = ord.n_eq;
            assert!(
                n % 4 != 0,
                "{n} equations: the last block must be incomplete"
            );
            let now: Vec<f64> = (s.d.iter().enumerate())
                .map(|(g, v)| v + 1e-4 * (0.3 * g as f64).cos())
                .collect();
            let bare = assemble(&s.context(&ord), &now, true, None);
            let internal: Vec<f64> = bare.unbalanced.iter().map(|u| -u).collect();
            assert_eq!(
                bare.unbalanced_norm2.to_bits(),
                sum_squares(&bare.unbalanced).to_bits()
            );
            let scene = Solver::loads_at_equations(&s.external_force(1.0), &ord);
            let mut spread: Vec<(usize, f64)> = [0, 3, 4, n / 2, n - 2, n - 1]
                .iter()
                .map(|&k| (k, 0.25 + k as f64))
                .collect();
            spread.dedup_by_key(|l| l.0);
            let mut last: Option<Assembled> = None;
            // The long beam is loaded; Example 3.2 is driven by a prescribed displacement.
            assert_eq!(scene.is_empty(), s.model.beams.len() != 1002);
            for loads in [&scene, &spread] {
                let ctx = AssemblyContext {
                    loads,
                    ..s.context(&ord)
                };
                let asm = assemble(&ctx, &now, true, None);
                let mut expected: Vec<f64> = internal.iter().map(|i| -i).collect();
                for &(k, f) in loads.iter() {
                    expected[k] += f;
                }
                let norm2 = sum_squares(&expected);
                let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
                assert_eq!(bits(&asm.unbalanced), bits(&expected), "{n} equations");
                assert_eq!(asm.unbalanced_norm2.to_bits(), norm2.to_bits());
                if let Some(mut other) = last.take() {
                    other.reload(loads);
                    assert_eq!(bits(&other.unbalanced), bits(&expected), "reloaded");
                    assert_eq!(other.unbalanced_norm2.to_bits(), norm2.to_bits());
                }
                last = Some(asm);
            }
        }
    }

    /// `Ordering::final_before` is the smallest equation any beam from e on reaches, its
    /// contact nodes included (found here by looking at every later beam): on a chain and on
    /// Example 3.2 with contacts.
    #[test]
    fn no_beam_reaches_below_its_final_equation() {
        for (scene, steps) in [("mattiasson", 0), ("example_3_2", 30)] {
            let s = crate::test_support::solver_after(scene, steps);
            let ord = s.ordering_for(&s.contacts);
            assert!(!ord.links.is_empty() || scene == "mattiasson");
            let reach = |e: usize| -> Vec<u32> {
                let b = &s.model.beams[e];
                let mut nodes = vec![b.i, b.j];
                nodes.extend(ord.on_beam[e].iter().map(|&k| ord.links[k].node));
                (nodes.iter())
                    .flat_map(|&n| (0..s.model.node_dofs(n)).map(move |o| (n, o)))
                    .map(|(n, o)| ord.eq[s.dofs.dof(n, o)])
                    .filter(|&q| q != NOT_FREE)
                    .collect()
            };
            let nb = s.model.beams.len();
            assert_eq!(ord.final_before.len(), nb + 1);
            assert_eq!(ord.final_before[nb] as usize, ord.n_eq);
            for e in 0..nb {
                let lowest = (e..nb).flat_map(reach).min().unwrap_or(ord.n_eq as u32);
                assert_eq!(ord.final_before[e], lowest, "{scene}: beam {e}");
            }
        }
    }

    /// The AVX2 build of the assembly (four plain beams at a time) gives the baseline build's
    /// internal forces, reactions, tangent and K_fp dp bit for bit (the element arithmetic is
    /// the same, only its instructions differ): at a deformed state of the Mattiasson
    /// cantilever (a chain, every group of four plain) and of Example 3.2 with contacts on
    /// (plain beams between contact beams) under a prescribed increment. Skipped (with a note)
    /// without AVX2.
    #[test]
    fn avx2_build_assembles_bit_for_bit_like_the_baseline() {
        #[cfg(target_arch = "x86_64")]
        {
            if !crate::test_support::has_avx2() {
                return;
            }
            for (scene, steps, turned) in [
                ("mattiasson", 4, false),
                ("mattiasson", 4, true),
                ("example_3_2", 30, false),
            ] {
                let mut s = crate::test_support::solver_after(scene, steps);
                if turned {
                    // Nodes 8 to 11 turned a whole turn more: their elements' chord rotations
                    // are unwrapped by the scalar path (the lanes hand their groups back).
                    for n in 8..12 {
                        s.d[s.dofs.first[n] + 2] += std::f64::consts::TAU;
                    }
                    let ends: [_; 4] = std::array::from_fn(|k| s.packed[8 + k].ends(&s.d));
                    let c = std::array::from_fn(|k| &s.packed[8 + k].constants);
                    // SAFETY: the CPU has AVX2 (checked above).
                    let lanes = unsafe { crate::solver::beam_lanes::evaluate4(c, ends) };
                    assert!(lanes.is_none(), "handed back");
                }
                let ord = s.ordering_for(&s.contacts);
                let ctx = s.context(&ord);
                let dp: Vec<f64> = (0..s.model.prescribed.len())
                    .map(|p| 1e-3 * (p + 1) as f64)
                    .collect();
                let dp = (!dp.is_empty()).then_some(dp.as_slice());
                let (mut base, mut wide) = (Assembled::default(), Assembled::default());
                assemble_kernel(&ctx, &s.d, true, dp, &mut base, false);
                // SAFETY: the CPU has AVX2 (checked above).
                unsafe {
                    crate::solver::simd::with_avx2(
                        #[inline(always)]
                        || assemble_kernel(&ctx, &s.d, true, dp, &mut wide, true),
                    )
                };
                let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
                assert_eq!(bits(&base.unbalanced), bits(&wide.unbalanced), "{scene}");
                assert_eq!(bits(&base.held_internal), bits(&wide.held_internal));
                assert_eq!(bits(&base.coupling), bits(&wide.coupling), "{scene}");
                let forces = |a: &Assembled| bits(a.elements.beam_forces.concat().as_slice());
                assert_eq!(forces(&base), forces(&wide), "{scene}");
                let all = base.unbalanced.iter().chain(&base.held_internal);
                let biggest = all.fold(0.0f64, |m, f| m.max(f.abs()));
                assert!(biggest > 1e-6, "{scene}: a loaded state ({biggest})");
                if scene == "example_3_2" {
                    assert!(!ord.contact_beams.is_empty(), "contacts on");
                    assert!(base.coupling.iter().any(|&f| f != 0.0), "K_fp dp");
                }
                let (kb, kw) = (
                    base.tangent.expect("tangent"),
                    wide.tangent.expect("tangent"),
                );
                for i in 0..ord.n_eq {
                    for j in i.saturating_sub(ord.band)..(i + ord.band + 1).min(ord.n_eq) {
                        let (a, b) = (kb.get(i, j), kw.get(i, j));
                        assert_eq!(a.to_bits(), b.to_bits(), "{scene} ({i}, {j})");
                    }
                }
            }
        }
    }
}
