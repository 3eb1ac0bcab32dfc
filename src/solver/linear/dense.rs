//! A dense LU solve, for cross-checks and tiny systems.

/// Dense LU solve (partial pivoting) of a row-major n x n system; `None` if singular.
pub fn dense_solve(n: usize, a: &[f64], b: &[f64]) -> Option<Vec<f64>> {
    let m = nalgebra::DMatrix::from_row_slice(n, n, a);
    let rhs = nalgebra::DVector::from_column_slice(b);
    m.lu().solve(&rhs).map(|x| x.iter().copied().collect())
}
