//! The uniform grid that hands the crossing check the elements near a node's path over one
//! increment, so that the check stays linear in the candidate pairs.

use super::chord::Chord;
use crate::solver::index_map::IndexMap;

/// A uniform grid over the boxes the chords sweep over an increment (grown by the longer of the
/// element's two chords), so that a node's path meets only the elements near it: the check
/// stays linear in the candidate pairs. Cells are twice the mean chord; an element whose box
/// covers more than `MAX_CELLS` cells is kept in a list every query sees.
#[derive(Debug)]
pub(super) struct SweptGrid {
    cell: f64,
    map: IndexMap<(i64, i64), Vec<usize>>,
    big: Vec<usize>,
    boxes: Vec<[f64; 4]>,
    /// The union of the boxes of each body's elements (empty where a body has none).
    bodies: Vec<[f64; 4]>,
}

/// Cells one element's box may cover before it goes into the list every query sees.
const MAX_CELLS: i64 = 64;

impl SweptGrid {
    /// The grid over `chords` (None: not a candidate body's element); `body_of` gives each
    /// element's body, of `n_bodies`; only the elements of bodies for which `long` holds go
    /// into the cells (every body gets its box).
    pub(super) fn new(
        chords: &[Option<(Chord, Chord)>],
        body_of: impl Fn(usize) -> usize,
        long: impl Fn(usize) -> bool,
        n_bodies: usize,
    ) -> SweptGrid {
        let mut boxes = vec![[f64::NAN; 4]; chords.len()];
        let (mut total, mut count) = (0.0, 0usize);
        for (e, c) in chords.iter().enumerate() {
            let Some((c0, c1)) = c else { continue };
            let g = c0.l.max(c1.l);
            let xs = [c0.p[0], c0.p[0] + c0.u[0], c1.p[0], c1.p[0] + c1.u[0]];
            let ys = [c0.p[1], c0.p[1] + c0.u[1], c1.p[1], c1.p[1] + c1.u[1]];
            let (x0, x1) = xs
                .iter()
                .fold((f64::MAX, f64::MIN), |(a, b), &x| (a.min(x), b.max(x)));
            let (y0, y1) = ys
                .iter()
                .fold((f64::MAX, f64::MIN), |(a, b), &y| (a.min(y), b.max(y)));
            boxes[e] = [x0 - g, y0 - g, x1 + g, y1 + g];
            total += g;
            count += 1;
        }
        let cell = if count > 0 && total > 0.0 {
            2.0 * total / count as f64
        } else {
            1.0
        };
        let mut bodies = vec![[f64::MAX, f64::MAX, f64::MIN, f64::MIN]; n_bodies];
        for (e, bx) in boxes.iter().enumerate() {
            if !bx[0].is_nan() {
                let u = &mut bodies[body_of(e)];
                *u = [
                    u[0].min(bx[0]),
                    u[1].min(bx[1]),
                    u[2].max(bx[2]),
                    u[3].max(bx[3]),
                ];
            }
        }
        let mut grid = SweptGrid {
            cell,
            map: IndexMap::default(),
            big: Vec::new(),
            boxes,
            bodies,
        };
        for e in 0..chords.len() {
            let bx = grid.boxes[e];
            if bx[0].is_nan() || !long(body_of(e)) {
                continue;
            }
            match grid.cells(bx) {
                Some((i0, j0, i1, j1)) => {
                    for i in i0..=i1 {
                        for j in j0..=j1 {
                            grid.map.entry((i, j)).or_default().push(e);
                        }
                    }
                }
                None => grid.big.push(e),
            }
        }
        grid
    }

    /// The cell range of a box, None if it covers too many cells (or is not finite).
    fn cells(&self, bx: [f64; 4]) -> Option<(i64, i64, i64, i64)> {
        let f = |v: f64| (v / self.cell).floor();
        let (i0, j0, i1, j1) = (f(bx[0]), f(bx[1]), f(bx[2]), f(bx[3]));
        let span = (i1 - i0 + 1.0) * (j1 - j0 + 1.0);
        (span.is_finite() && span <= MAX_CELLS as f64)
            .then_some((i0 as i64, j0 as i64, i1 as i64, j1 as i64))
    }

    /// Whether the box [lo, hi] meets element `e`'s box.
    pub(super) fn meets_element(&self, e: usize, lo: [f64; 2], hi: [f64; 2]) -> bool {
        let b = self.boxes[e];
        b[0] <= hi[0] && b[2] >= lo[0] && b[1] <= hi[1] && b[3] >= lo[1]
    }

    /// Whether the box [lo, hi] meets the box of body `b`'s elements.
    pub(super) fn meets_body(&self, b: usize, lo: [f64; 2], hi: [f64; 2]) -> bool {
        let u = self.bodies[b];
        u[0] <= hi[0] && u[2] >= lo[0] && u[1] <= hi[1] && u[3] >= lo[1]
    }

    /// The elements whose boxes meet the box [lo, hi], ascending.
    pub(super) fn query(&self, lo: [f64; 2], hi: [f64; 2]) -> Vec<usize> {
        let meets = |e: &usize| {
            let b = self.boxes[*e];
            b[0] <= hi[0] && b[2] >= lo[0] && b[1] <= hi[1] && b[3] >= lo[1]
        };
        let mut out: Vec<usize> = self.big.iter().copied().filter(meets).collect();
        match self.cells([lo[0], lo[1], hi[0], hi[1]]) {
            Some((i0, j0, i1, j1)) => {
                for i in i0..=i1 {
                    for j in j0..=j1 {
                        if let Some(v) = self.map.get(&(i, j)) {
                            out.extend(v.iter().copied().filter(meets));
                        }
                    }
                }
            }
            // A path longer than the grid's reach: every element is looked at.
            None => out.extend(
                (0..self.boxes.len())
                    .filter(|e| !self.boxes[*e][0].is_nan())
                    .filter(meets),
            ),
        }
        out.sort_unstable();
        out.dedup();
        out
    }
}
