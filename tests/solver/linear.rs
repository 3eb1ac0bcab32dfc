//! The banded LU (with row pivoting) against a dense LU, and reverse Cuthill-McKee against the
//! bandwidth a chain must have.

use crate::common;
use common::Rng;
use tsm_contact::solver::linear::{dense_solve, reverse_cuthill_mckee, BandMatrix, NOT_FREE};

#[test]
fn band_lu_agrees_with_dense_lu_even_when_pivoting() {
    let mut rng = Rng(0x9e37_79b9_7f4a_7c15);
    for &(n, kl, ku) in &[
        (1usize, 0usize, 0usize),
        (7, 1, 2),
        (40, 3, 3),
        (200, 5, 2),
        (300, 8, 8),
    ] {
        let mut band = BandMatrix::zeros(n, kl, ku);
        let mut dense = vec![0.0; n * n];
        for i in 0..n {
            for j in i.saturating_sub(kl)..(i + ku + 1).min(n) {
                // Weak diagonal: partial pivoting must swap rows to stay accurate.
                let v = if i == j {
                    1e-3 * rng.next()
                } else {
                    rng.next()
                };
                band.add(i, j, v);
                dense[i * n + j] = v;
            }
        }
        let b: Vec<f64> = (0..n).map(|_| rng.next()).collect();
        solves_like_dense(&mut band, &dense, &b, &format!("n {n} kl {kl} ku {ku}"));
    }
}

#[test]
fn reverse_cuthill_mckee_orders_a_shuffled_chain_to_bandwidth_one() {
    let n = 500;
    // A chain 0-1-2-...-(n-1) under a scrambled labelling.
    let label: Vec<usize> = (0..n).map(|k| (k * 263) % n).collect();
    let mut adj = vec![Vec::new(); n];
    for k in 0..n - 1 {
        adj[label[k]].push(label[k + 1]);
        adj[label[k + 1]].push(label[k]);
    }
    let perm = reverse_cuthill_mckee(&adj);
    let mut pos = vec![0; n];
    for (new, &old) in perm.iter().enumerate() {
        pos[old] = new;
    }
    let band = (0..n)
        .flat_map(|v| adj[v].iter().map(move |&u| (v, u)))
        .map(|(v, u)| pos[v].abs_diff(pos[u]))
        .max()
        .unwrap();
    assert_eq!(band, 1);
    let mut sorted = perm.clone();
    sorted.sort();
    assert_eq!(sorted, (0..n).collect::<Vec<_>>(), "a permutation");
}

/// A symmetric band matrix (n, kl = ku = w) with entries of very different scales, positive
/// definite or (with `shift`) indefinite, as a band and as a dense row-major copy.
fn symmetric_band(rng: &mut Rng, n: usize, w: usize, shift: f64) -> (BandMatrix, Vec<f64>) {
    let mut dense = vec![0.0; n * n];
    // Row scales as far apart as EA/L and EI/L^3 in a frame.
    let scale: Vec<f64> = (0..n).map(|i| [1e6, 1.0, 30.0][i % 3]).collect();
    for i in 0..n {
        for j in i..(i + w + 1).min(n) {
            let v = if i == j {
                w as f64 + 1.0 + rng.next().abs() - shift
            } else {
                rng.next()
            };
            let v = v * (scale[i] * scale[j]).sqrt();
            dense[i * n + j] = v;
            dense[j * n + i] = v;
        }
    }
    let mut band = BandMatrix::symmetric_zeros(n, w);
    for i in 0..n {
        for j in i.saturating_sub(w)..(i + w + 1).min(n) {
            band.add(i, j, dense[i * n + j]);
        }
    }
    (band, dense)
}

#[test]
fn symmetric_band_ldlt_agrees_with_dense_lu_definite_or_not() {
    let mut rng = Rng(0x2545_f491_4f6c_dd1d);
    let mut handed_over_midway = false;
    for &(n, w, shift) in &[
        (3usize, 1usize, 0.0),
        (60, 5, 0.0),
        (300, 5, 0.0),
        (90, 5, 4.0),
        (301, 8, 6.0),
        (90, 5, 6.5),
        // Every unrolled bandwidth of the factorisation and the substitutions.
        (50, 2, 0.0),
        (51, 3, 0.0),
        (70, 4, 3.0),
        (64, 6, 0.0),
        (45, 7, 0.0),
        (20, 12, 0.0),
        (4, 5, 0.0),
    ] {
        let (mut band, dense) = symmetric_band(&mut rng, n, w, shift);
        let b: Vec<f64> = (0..n).map(|_| rng.next()).collect();
        solves_like_dense(&mut band, &dense, &b, &format!("n {n} w {w} shift {shift}"));
        // A positive definite matrix is L D L^T throughout; an indefinite one hands over to
        // the pivoting LU where a diagonal stops dominating.
        let from = band.pivoting_from();
        assert_eq!(
            from.is_none(),
            shift == 0.0,
            "n {n} w {w} shift {shift}: {from:?}"
        );
        handed_over_midway |= from.is_some_and(|j| j > 0);
    }
    assert!(
        handed_over_midway,
        "no case converts a partial L D L^T to LU"
    );
}

#[test]
fn a_reset_band_matrix_is_a_fresh_one() {
    let mut rng = Rng(0x1234_5678_9abc_def1);
    // First a matrix that needs row interchanges (widened storage), then smaller and larger
    // ones in the same storage.
    let mut band = BandMatrix::zeros(50, 3, 3);
    for i in 0..50usize {
        for j in i.saturating_sub(3)..(i + 4).min(50) {
            band.add(i, j, if i == j { 1e-6 } else { rng.next() });
        }
    }
    band.factor(0.0).expect("nonsingular");
    for &(n, w) in &[(20usize, 2usize), (80, 4)] {
        band.reset(n, w, w);
        let mut dense = vec![0.0; n * n];
        for i in 0..n {
            for j in i.saturating_sub(w)..(i + w + 1).min(n) {
                let v = if i == j { 10.0 } else { rng.next() };
                band.add(i, j, v);
                dense[i * n + j] = v;
                assert_eq!(band.get(i, j), v);
            }
        }
        let b: Vec<f64> = (0..n).map(|_| rng.next()).collect();
        let reference = dense_solve(n, &dense, &b).expect("nonsingular");
        band.factor(0.0).expect("nonsingular");
        let mut x = b.clone();
        band.solve(&mut x);
        for (a, r) in x.iter().zip(&reference) {
            assert!((a - r).abs() < 1e-12 * (1.0 + r.abs()), "{a} vs {r}");
        }
    }
}

/// Factor and solve `band` for `b`, and check the solution against the dense solve of the same
/// matrix to 1e-10 of its largest entry; `factor_and_solve` must give the same solution and
/// the same factors bit for bit.
fn solves_like_dense(band: &mut BandMatrix, dense: &[f64], b: &[f64], case: &str) {
    let n = b.len();
    let reference = dense_solve(n, dense, b).expect("nonsingular");
    let mut at_once = band.clone();
    band.factor(0.0).expect("nonsingular");
    let mut x = b.to_vec();
    band.solve(&mut x);
    let mut y = b.to_vec();
    at_once.factor_and_solve(0.0, &mut y).expect("nonsingular");
    let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    assert_eq!(bits(&x), bits(&y), "{case}: factor_and_solve");
    // The factors too: a second right-hand side solves alike with either.
    let (mut x2, mut y2) = (reference.clone(), reference.clone());
    band.solve(&mut x2);
    at_once.solve(&mut y2);
    assert_eq!(bits(&x2), bits(&y2), "{case}: factors of factor_and_solve");
    let scale = reference.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let err = x
        .iter()
        .zip(&reference)
        .fold(0.0f64, |m, (a, r)| m.max((a - r).abs()));
    assert!(err < 1e-10 * scale, "{case}: {err:e} vs {scale:e}");
}

/// A long band is factored from both ends at once (twisted) toward a small middle block. Where
/// a pivot fails the dominance test near either end, or in the middle, both ends stop there and
/// the middle block (then most of the matrix) is factored by the L D L^T that hands over to the
/// pivoting LU. Each case against the dense LU.
#[test]
fn twisted_factorisation_agrees_with_dense_lu_wherever_a_pivot_fails() {
    let mut rng = Rng(0x0dd_b1a5_e5ca_1ab1);
    for &(n, w) in &[(64usize, 5usize), (65, 5), (200, 3), (301, 8), (128, 1)] {
        // None: positive definite throughout. Some(i): diagonal i made tiny and negative, so
        // the pivot there fails the test: near the top, near the bottom, or in the middle.
        // (A large negative diagonal would still dominate: the test is on magnitudes.)
        for bad in [None, Some(3), Some(n - 4), Some(n / 2)] {
            let (mut band, mut dense) = symmetric_band(&mut rng, n, w, 0.0);
            if let Some(i) = bad {
                let v = -1e-9 * dense[i * n + i];
                band.add(i, i, v - dense[i * n + i]);
                dense[i * n + i] = v;
            }
            let b: Vec<f64> = (0..n).map(|_| rng.next()).collect();
            let case = format!("n {n} w {w} bad {bad:?}");
            solves_like_dense(&mut band, &dense, &b, &case);
            let from = band.pivoting_from();
            assert_eq!(from.is_some(), bad.is_some(), "{case}: {from:?}");
        }
    }
}

/// A band reset lazily (each column zeroed when an element first reaches it) over storage full
/// of an old factorisation holds exactly what a band zeroed up front holds, whatever order the
/// elements come in (here every third element first, then the rest backwards).
#[test]
fn a_lazily_reset_band_assembles_like_a_zeroed_one() {
    let mut rng = Rng(0x005e_ed0f_7a1e);
    let n = 90;
    let (mut dirty, _) = symmetric_band(&mut rng, 120, 3, 0.0);
    dirty.factor(0.0).expect("nonsingular");
    dirty.reset_symmetric_lazily(n, 3);
    let mut clean = BandMatrix::symmetric_zeros(n, 3);
    let elements: Vec<([u32; 2], [[f64; 2]; 2])> = (0..n - 1)
        .map(|e| {
            let (a, b) = (rng.next(), rng.next());
            let (i, j) = (e as u32, e as u32 + 1);
            // Some elements numbered out of local order, some with a dof that is not free
            // (each takes the general path of `add_element`, which must zero lazily too).
            let eqs = match e % 5 {
                1 => [j, i],
                3 => [NOT_FREE, j],
                4 => [i, NOT_FREE],
                _ => [i, j],
            };
            (eqs, [[a, b], [b, 2.0 + a]])
        })
        .collect();
    let order: Vec<usize> = (0..n - 1)
        .step_by(3)
        .chain((0..n - 1).rev().filter(|e| e % 3 != 0))
        .collect();
    for &e in &order {
        dirty.add_element(&elements[e].0, &elements[e].1);
    }
    for (eqs, k) in &elements {
        clean.add_element(eqs, k);
    }
    dirty.finish_assembly();
    for i in 0..n {
        for j in i.saturating_sub(3)..=i {
            assert_eq!(dirty.get(i, j), clean.get(i, j), "({i}, {j})");
        }
    }
}

/// The diagonal peak is the largest |value| a diagonal entry took during the assembly: never
/// below the largest final diagonal entry (here elements with negative diagonal entries
/// shrink some diagonal sums), equal to it when every contribution is positive, and reset with
/// the matrix. Every path of `add_element` and `add` is taken.
#[test]
fn the_diagonal_peak_bounds_the_largest_diagonal_entry() {
    let mut rng = Rng(0x0dd_ba11_5eed);
    let n = 40;
    for positive in [true, false] {
        for symmetric in [true, false] {
            let mut band = if symmetric {
                BandMatrix::symmetric_zeros(n, 3)
            } else {
                BandMatrix::zeros(n, 3, 3)
            };
            let mut shrinks = false;
            for e in 0..n - 1 {
                let (i, j) = (e as u32, e as u32 + 1);
                let d = |v: f64| if positive { 1.0 + v.abs() } else { 3.0 * v };
                let (a, b, c) = (d(rng.next()), rng.next(), d(rng.next()));
                shrinks |= a < 0.0 || c < 0.0;
                let eqs = match e % 4 {
                    1 => [j, i],
                    2 => [NOT_FREE, j],
                    _ => [i, j],
                };
                let k = if eqs[0] == j {
                    [[c, b], [b, a]]
                } else {
                    [[a, b], [b, c]]
                };
                band.add_element(&eqs, &k);
            }
            band.add(7, 7, if positive { 0.5 } else { -9.0 });
            band.finish_assembly();
            let (peak, largest) = (band.diagonal_peak(), band.max_diagonal());
            assert!(peak >= largest, "peak {peak} below {largest}");
            if positive {
                assert_eq!(peak, largest);
            } else {
                assert!(shrinks);
            }
            if symmetric {
                band.reset_symmetric_lazily(n, 3);
            } else {
                band.reset(n, 3, 3);
            }
            assert_eq!(band.diagonal_peak(), 0.0);
        }
    }
}

/// A beam's tangent added from its distinct entries (`add_symmetric6`) gives the band, bit for bit,
/// and the diagonal peak that the written-out 6x6 (`add_element`) gives: beams of a chain at
/// random states (their entries from `ForceConstants::evaluate_entries`), numbered along the
/// chain (the direct path) or with a dof not free or out of local order (the general path), in a
/// lazily reset band over an old factorisation and in a zeroed one.
#[test]
fn a_beam_added_from_its_distinct_entries_is_the_written_out_tangent() {
    use tsm_contact::solver::element::beam::BeamElement;
    use tsm_contact::solver::model::Section;
    let mut rng = Rng(0x0b3a_4e17);
    let beams = 30;
    let n = 3 * (beams + 1);
    let (mut dirty, _) = symmetric_band(&mut rng, n + 9, 5, 0.0);
    dirty.factor(0.0).expect("nonsingular");
    dirty.reset_symmetric_lazily(n, 5);
    let mut written = BandMatrix::symmetric_zeros(n, 5);
    let section = Section {
        ea: 1e4,
        ei: 3.0,
        gae: 300.0,
        thickness: 0.0,
    };
    let mut direct = 0;
    for e in 0..beams {
        let xi = [e as f64, 0.1 * rng.next()];
        let xj = [e as f64 + 1.0, 0.2 * rng.next()];
        let el = BeamElement::new([e as f64, 0.0], [e as f64 + 1.0, 0.0], section, 0.01);
        let (_, t) =
            el.constants()
                .evaluate_entries(xi, xj, 0.3 * rng.next(), 0.3 * rng.next(), true);
        let t = t.expect("tangent requested");
        let mut eqs: [u32; 6] = std::array::from_fn(|a| (3 * e + a) as u32);
        match e % 6 {
            1 => eqs[4] = NOT_FREE,
            3 => eqs.swap(0, 1),
            _ => direct += 1,
        }
        dirty.add_symmetric6(&eqs, &t.lower_columns());
        let mut k = [[0.0; 6]; 6];
        t.write(&mut k);
        written.add_element(&eqs, &k);
    }
    assert!(direct > 10);
    dirty.finish_assembly();
    written.finish_assembly();
    for i in 0..n {
        for j in i.saturating_sub(5)..=i {
            assert_eq!(
                dirty.get(i, j).to_bits(),
                written.get(i, j).to_bits(),
                "({i}, {j})"
            );
        }
    }
    assert_eq!(dirty.diagonal_peak(), written.diagonal_peak());
}
