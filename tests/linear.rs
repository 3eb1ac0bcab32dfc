//! The banded LU (with row pivoting) against a dense LU, and reverse Cuthill-McKee against the
//! bandwidth a chain must have.

mod common;
use common::Rng;
use tsm_contact::solver::linear::{dense_solve, reverse_cuthill_mckee, BandMatrix};

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
        let reference = dense_solve(n, &dense, &b).expect("nonsingular");
        band.factor(0.0).expect("nonsingular");
        let mut x = b.clone();
        band.solve(&mut x);
        let scale = reference.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        let err = x
            .iter()
            .zip(&reference)
            .fold(0.0f64, |m, (a, r)| m.max((a - r).abs()));
        assert!(
            err < 1e-10 * scale,
            "n {n} kl {kl} ku {ku}: {err:e} vs {scale:e}"
        );
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
