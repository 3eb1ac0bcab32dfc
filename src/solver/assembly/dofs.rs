//! The dof map (which global dofs are free, supported or prescribed), node positions from the
//! displacements, and the equation ordering: reverse Cuthill-McKee over the current element
//! graph, contact links included, with each beam's equations.

use super::coordinates::add_carried;
use crate::solver::linear::simd::dispatch;
use crate::solver::linear::{consecutive_first, reverse_cuthill_mckee, NOT_FREE};
use crate::solver::model::Model;

/// What a global dof is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DofKind {
    /// Solved for.
    Free,
    /// Held at zero.
    Supported,
    /// Driven; index into [`Model::prescribed`].
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
        // A node that moves with a pilot is held as the pilot is (`Node::moves_with`).
        for (n, node) in model.nodes.iter().enumerate() {
            if let Some(p) = node.moves_with {
                for o in 0..2 {
                    kind[first[n] + o] = kind[first[p] + o];
                }
            }
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
    /// The node's side of the beam times its contact distance (`Model::contact_distance`):
    /// where it stands off the beam's axis (0: on it).
    pub rim: f64,
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
    /// dofs), each sum carried with its residue (`coordinates::add_carried`): in one run over
    /// slices where the dofs are in a row (`dofs_in_a_row`), the same arithmetic either way.
    pub fn add_scaled(&self, (d, residue): (&mut [f64], &mut [f64]), scale: f64, x: &[f64]) {
        dispatch(
            #[inline(always)]
            || self.add_scaled_here((d, residue), scale, x),
        );
    }

    /// `add_scaled` in the build it is dispatched to.
    #[inline(always)]
    fn add_scaled_here(&self, (d, residue): (&mut [f64], &mut [f64]), scale: f64, x: &[f64]) {
        match self.dofs_in_a_row {
            Some(g) => {
                let n = x.len();
                let (d, r) = (&mut d[g..g + n], &mut residue[g..g + n]);
                for ((v, r), x) in d.iter_mut().zip(r.iter_mut()).zip(x) {
                    add_carried(v, r, scale * x);
                }
            }
            None => {
                for (&g, x) in self.dof_of.iter().zip(x) {
                    let g = g as usize;
                    add_carried(&mut d[g], &mut residue[g], scale * x);
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
