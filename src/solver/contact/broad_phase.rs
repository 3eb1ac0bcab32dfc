//! The contact broad phase: which node-body pairs and which elements are worth a close look.
//! Two levels: a bounding box per body (over the last converged state and the iterate) culls
//! node-body pairs; a uniform grid over element bounding boxes at one state hands a probe the
//! elements near a node, so that a node near a long body does not test every element of it.

use crate::solver::index_map::IndexMap;

use super::set::ContactView;
use crate::solver::assembly::current;

/// Bounding boxes of the bodies over one or more states, grown by `margin` element lengths
/// (the longest element of each body): [x_min, y_min, x_max, y_max].
pub(crate) struct BodyBoxes(Vec<[f64; 4]>);

impl BodyBoxes {
    /// Boxes over every state in `states`.
    pub(crate) fn new(cv: &ContactView<'_>, states: &[&[f64]], margin: f64) -> BodyBoxes {
        let m = &cv.structure.model;
        let pins = cv.structure.max_clearance;
        let boxes = m
            .bodies
            .iter()
            .map(|body| {
                let mut bx = [f64::MAX, f64::MAX, f64::MIN, f64::MIN];
                let mut longest: f64 = 0.0;
                let mut stand_off = pins;
                for &e in &body.elements {
                    longest = longest.max(m.beam_length(e));
                    if cv.structure.stands_off {
                        stand_off = stand_off.max(pins + 0.5 * m.beams[e].section.thickness);
                    }
                    for n in [m.beams[e].i, m.beams[e].j] {
                        for d in states {
                            grow(&mut bx, current(m, &cv.structure.dofs, d, n).0);
                        }
                    }
                }
                // A node that stands off the axis (a pin's radius, the thicknesses) touches
                // from that much further out.
                let g = margin * longest + stand_off;
                [bx[0] - g, bx[1] - g, bx[2] + g, bx[3] + g]
            })
            .collect();
        BodyBoxes(boxes)
    }

    /// Whether node `n`, over every state in `states`, comes within body `b`'s box (always true
    /// with the broad phase switched off).
    pub(crate) fn near(&self, cv: &ContactView<'_>, states: &[&[f64]], n: usize, b: usize) -> bool {
        if !cv.structure.params.broad_phase {
            return true;
        }
        let bx = self.0[b];
        let mut nb = [f64::MAX, f64::MAX, f64::MIN, f64::MIN];
        for d in states {
            grow(
                &mut nb,
                current(&cv.structure.model, &cv.structure.dofs, d, n).0,
            );
        }
        nb[0] <= bx[2] && nb[2] >= bx[0] && nb[1] <= bx[3] && nb[3] >= bx[1]
    }
}

fn grow(bx: &mut [f64; 4], p: [f64; 2]) {
    *bx = [
        bx[0].min(p[0]),
        bx[1].min(p[1]),
        bx[2].max(p[0]),
        bx[3].max(p[1]),
    ];
}

/// A uniform grid over the elements' bounding boxes (chords) at one state. Cells are `reach`
/// wide, `reach` at least `margin` times the longest current chord: every element within
/// `reach` of a point has a cell among the 3 x 3 around the point's cell.
pub(crate) struct ElementGrid {
    /// Cell size, and the distance within which `near` misses no element.
    pub(crate) reach: f64,
    cells: IndexMap<(i64, i64), Vec<usize>>,
}

impl ElementGrid {
    /// The grid over every element at displacements `d`; None with the broad phase off.
    pub(crate) fn new(cv: &ContactView<'_>, d: &[f64], margin: f64) -> Option<ElementGrid> {
        if !cv.structure.params.broad_phase {
            return None;
        }
        let m = &cv.structure.model;
        let ends: Vec<([f64; 2], [f64; 2])> = m
            .beams
            .iter()
            .map(|b| {
                (
                    current(m, &cv.structure.dofs, d, b.i).0,
                    current(m, &cv.structure.dofs, d, b.j).0,
                )
            })
            .collect();
        let longest = ends
            .iter()
            .map(|(a, b)| (b[0] - a[0]).hypot(b[1] - a[1]))
            .fold(0.0, f64::max);
        let reach = margin * longest;
        if !(reach > 0.0 && reach.is_finite()) {
            return None;
        }
        let mut cells: IndexMap<(i64, i64), Vec<usize>> = IndexMap::default();
        for (e, (a, b)) in ends.iter().enumerate() {
            let (x0, x1) = (cell(a[0].min(b[0]), reach), cell(a[0].max(b[0]), reach));
            let (y0, y1) = (cell(a[1].min(b[1]), reach), cell(a[1].max(b[1]), reach));
            for cx in x0..=x1 {
                for cy in y0..=y1 {
                    cells.entry((cx, cy)).or_default().push(e);
                }
            }
        }
        Some(ElementGrid { reach, cells })
    }

    /// Elements whose cells lie within one cell of point `p` (an element spanning two cells
    /// comes twice).
    pub(crate) fn near(&self, p: [f64; 2]) -> impl Iterator<Item = usize> + '_ {
        let (cx, cy) = (cell(p[0], self.reach), cell(p[1], self.reach));
        (-1..=1)
            .flat_map(move |dx| (-1..=1).map(move |dy| (cx + dx, cy + dy)))
            .filter_map(|c| self.cells.get(&c))
            .flatten()
            .copied()
    }
}

fn cell(x: f64, size: f64) -> i64 {
    (x / size).floor() as i64
}
