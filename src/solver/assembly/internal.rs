//! The internal forces over the free equations while an assembly adds to them (`Internal`), and
//! the adds of one element's forces, tangent and K_fp dp coupling.

use super::dofs::{DofKind, DofMap, Ordering};
use super::packed::PackedBeam;
use crate::solver::element::beam::TangentEntries;
use crate::solver::linear::{zero_ahead, BandMatrix, NOT_FREE};

/// The fewest equations [`Internal::settle`] takes at a time: enough to pay for the call, few
/// enough (1 KiB) to be in L1 still.
const SETTLE_BATCH: usize = 128;

/// The internal forces over the free equations while an assembly adds to them, turned into
/// the unbalanced force (negated, loaded and summed) block by block as the assembly finishes
/// with them. They are zeroed a block at a time as the elements reach them (in one pass with
/// the assembly, while in cache, as the band is: [`BandMatrix::reset_symmetric_lazily`]), not
/// in a pass of their own; and settled (`settle`) while still in cache, not in a pass of
/// their own either.
pub(super) struct Internal<'a> {
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
    /// The loaded equations and their entries before the load ([`Assembled::unloaded`]).
    unloaded: Vec<(usize, f64)>,
    /// The sum of squares of the settled entries in four partial sums, entry k in `acc[k % 4]`
    /// (as `sum_squares` has them).
    acc: [f64; 4],
}

impl<'a> Internal<'a> {
    /// `n` forces over the storage of the last assembly's (`v`, and `unloaded`), none yet
    /// valid, to be loaded with `loads`.
    pub(super) fn new(
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
    pub(super) fn zero_to(&mut self, end: usize) {
        zero_ahead(&mut self.v, &mut self.zeroed, end);
    }

    /// Add `f` to the force of equation `q`.
    #[inline(always)]
    pub(super) fn add(&mut self, q: usize, f: f64) {
        debug_assert!(
            q >= self.settled,
            "equation {q} added to after it was settled"
        );
        self.zero_to(q + 1);
        self.v[q] += f;
    }

    /// The forces of the six equations from `first` on, ready to add to.
    #[inline(always)]
    pub(super) fn run6(&mut self, first: usize) -> &mut [f64; 6] {
        debug_assert!(
            first >= self.settled,
            "equation {first} added to after it was settled"
        );
        self.zero_to(first + 6);
        (&mut self.v[first..first + 6]).try_into().unwrap()
    }

    /// No element adds to the equations before `end` any more ([`Ordering::final_before`]):
    /// settle their whole blocks of four, in batches of at least `SETTLE_BATCH` equations.
    #[inline(always)]
    pub(super) fn settle(&mut self, end: usize) {
        if end >= self.settled + SETTLE_BATCH {
            self.settle_blocks(end & !3);
        }
    }

    /// Settle the entries from `settled` to `end` (a multiple of 4): negate each block of
    /// four, add its loads, and add the squares to the partial sums (entry k into `acc[k % 4]`,
    /// as `sum_squares` sums).
    #[inline(always)]
    pub(super) fn settle_blocks(&mut self, end: usize) {
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
    pub(super) fn finish(mut self) -> (Vec<f64>, f64, Vec<(usize, f64)>) {
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
/// consecutive equations where its dofs have them ([`Ordering::beam_first`]), dof by dof
/// otherwise; with its K_fp dp where a prescribed increment `dp` is given (`k6` the scratch for
/// its whole tangent).
#[inline(always)]
pub(super) fn add_plain_beam(
    e: usize,
    pb: &PackedBeam,
    nodal: &[f64; 6],
    t: Option<TangentEntries>,
    (ord, dofs, dp): (&Ordering, &DofMap, Option<&[f64]>),
    k6: &mut [[f64; 6]; 6],
    Sink {
        internal,
        held,
        tangent,
        coupling,
    }: Sink,
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
            band.add_symmetric6_consecutive(first as usize, &t.lower_columns());
        } else {
            band.add_symmetric6(&ord.beam_eqs[e], &t.lower_columns());
        }
        if let Some(dp) = dp {
            t.write(k6);
            let eqs: [Option<usize>; 6] = std::array::from_fn(|a| ord.equation(g[a]));
            add_coupling(&g, &eqs, |a, b| k6[a][b], dofs, dp, coupling);
        }
    }
}

/// The held dofs ([`DofMap::held`]) and the internal forces at them.
pub(super) type Held<'a> = (&'a [usize], &'a mut [f64]);

/// Add nodal force `f` at global dof `g`, whose equation is `q` (`NOT_FREE` if it has none):
/// to the free equations' internal forces, or to those at the held dofs.
#[inline(always)]
pub(super) fn add_nodal_force(
    q: u32,
    g: usize,
    f: f64,
    internal: &mut Internal<'_>,
    (dofs, forces): Held,
) {
    if q != NOT_FREE {
        internal.add(q as usize, f);
    } else {
        let k = dofs
            .binary_search(&g)
            .expect("a dof with no equation is held");
        forces[k] += f;
    }
}

/// Where element contributions go.
pub(super) struct Sink<'a, 'b> {
    /// Internal forces at the free equations.
    pub(super) internal: &'a mut Internal<'b>,
    /// The held dofs and the internal forces at them.
    pub(super) held: Held<'a>,
    /// The band tangent, where one is assembled.
    pub(super) tangent: Option<&'a mut BandMatrix>,
    /// K_fp dp, by equation.
    pub(super) coupling: &'a mut Vec<f64>,
}

impl<'a, 'b> Sink<'a, 'b> {
    /// The sink over the assembly's outputs, borrowed for one element.
    #[inline(always)]
    pub(super) fn of(
        internal: &'a mut Internal<'b>,
        held: &'a mut Held<'_>,
        tangent: &'a mut Option<BandMatrix>,
        coupling: &'a mut Vec<f64>,
    ) -> Sink<'a, 'b> {
        Sink {
            internal,
            held: (held.0, &mut *held.1),
            tangent: tangent.as_mut(),
            coupling,
        }
    }
}

/// Add one element's nodal forces and (if given) its tangent over the global dofs `gdofs`.
pub(super) fn add_element(
    gdofs: &[usize],
    nodal: &[f64],
    k: Option<impl Fn(usize, usize) -> f64>,
    ord: &Ordering,
    dofs: &DofMap,
    dp: Option<&[f64]>,
    Sink {
        internal,
        held,
        tangent: band,
        coupling,
    }: Sink,
) {
    for (a, &g) in gdofs.iter().enumerate() {
        add_nodal_force(ord.eq[g], g, nodal[a], internal, (held.0, &mut *held.1));
    }
    if let Some(k) = k {
        add_matrix(gdofs, k, ord, band, dofs, dp, coupling);
    }
}

pub(super) fn add_matrix(
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
/// prescribed increments `dp` (one per [`Model::prescribed`], found through `DofKind`).
pub(super) fn add_coupling(
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
