//! The displacements as Newton carries them: each coordinate `d[g]` with the rounding residue
//! `residue[g]` of the corrections added to it (compensated summation), and the positions the
//! elements take from both.
//!
//! An element's forces come from its nodes' positions relative to each other. Formed from the
//! displacements alone, a relative position carries the round-off of the displacements' size
//! (eps |u|), and a short, stiff element turns that into forces far above its own round-off:
//! a cantilever of 256 elements with EA = 1e6 EI / L^2, bent until its nodes move 0.15 m,
//! has eps |u| EA / l of about 1e-8 N at every node, and the residual's norm over the nodes
//! floors at about 3e-8 of the load, above the default tolerance of 1e-8. The corrections are
//! added to `d` exactly, the part a double cannot hold kept in `residue` (Knuth's two-sum),
//! and renormalised so that `d` stays the double nearest `d + residue`; the elements take
//! their nodes' relative positions from the differences of both,
//! `(X_j - X_i) + ((u_j - u_i) + (r_j - r_i))`, good to eps times the relative position's own
//! size. The floor is then that of the element's deformation itself, and Newton reaches the
//! tolerance instead of stalling at the floor.
//!
//! Histories record `d`: the state to the nearest double of each coordinate.

use crate::solver::model::Model;

/// Add `v` to the coordinate `(d, residue)`: the sum exact, then `d` the double nearest it and
/// `residue` the rest.
#[inline(always)]
pub fn add_carried(d: &mut f64, residue: &mut f64, v: f64) {
    let s = *d + v;
    let back = s - *d;
    let lost = (*d - (s - back)) + (v - back);
    let r = *residue + lost;
    let t = s + r;
    *residue = r - (t - s);
    *d = t;
}

/// The residue of dof `g` (0 where none is carried: `residue` empty).
#[inline(always)]
pub fn residue_at(residue: &[f64], g: usize) -> f64 {
    residue.get(g).copied().unwrap_or(0.0)
}

/// Position of node `n` relative to the current position of node `origin`, and the rotation of
/// `n`: `(X_n - X_origin) + ((u_n - u_origin) + (r_n - r_origin))`, with `first` each node's
/// first global dof (`DofMap::first`) and `residue` the displacements' residues (empty: none).
/// Node `origin` itself is at (0, 0).
#[inline]
pub fn between(
    model: &Model,
    first: &[usize],
    (d, residue): (&[f64], &[f64]),
    n: usize,
    origin: usize,
) -> ([f64; 2], f64) {
    let (f, o) = (first[n], first[origin]);
    let (p, q) = (model.position(n), model.position(origin));
    let phi = if model.nodes[n].rotation {
        d[f + 2]
    } else {
        0.0
    };
    let along = |k: usize| {
        let carried = residue_at(residue, f + k) - residue_at(residue, o + k);
        (p[k] - q[k]) + ((d[f + k] - d[o + k]) + carried)
    };
    ([along(0), along(1)], phi)
}

#[cfg(test)]
mod tests {
    use super::add_carried;

    /// Ten million corrections of 1e-17 to a coordinate of 0.15: a double alone keeps none of
    /// them (each is below half its unit in the last place), the carried coordinate all of
    /// them, to the residue's own round-off; and `d` stays the double nearest the sum.
    #[test]
    fn corrections_below_the_coordinates_resolution_add_up() {
        let (mut plain, mut d, mut r) = (0.15f64, 0.15f64, 0.0f64);
        let n = 10_000_000;
        for _ in 0..n {
            plain += 1e-17;
            add_carried(&mut d, &mut r, 1e-17);
        }
        assert_eq!(plain, 0.15);
        let added = (d - 0.15) + r;
        assert!((added - 1e-10).abs() < 1e-22, "{added:e}");
        assert!(r.abs() <= 0.5 * f64::EPSILON * d, "{r:e}");
    }

    /// A correction that cancels the coordinate leaves the exact difference.
    #[test]
    fn a_cancelling_correction_leaves_the_exact_difference() {
        let (mut d, mut r) = (1.0f64, 0.0f64);
        add_carried(&mut d, &mut r, 1e-20);
        add_carried(&mut d, &mut r, -1.0);
        assert_eq!(d + r, 1e-20);
    }
}
