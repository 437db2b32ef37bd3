//! Dense vector and matrix kernels of the Newton solvers (harmonic balance, its
//! continuation, the static equilibrium, the least-squares fits): plain in-order sums, so
//! their results do not depend on where they are called from.

use faer::Mat;

use super::dot_in_order;

/// Euclidean norm |v|.
pub(crate) fn norm(v: &[f64]) -> f64 {
    dot_in_order(v, v).sqrt()
}

/// a - b.
pub(crate) fn difference(a: &[f64], b: &[f64]) -> Vec<f64> {
    a.iter().zip(b).map(|(x, y)| x - y).collect()
}

/// out = A x.
pub(crate) fn multiply(a: &Mat<f64>, x: &[f64], out: &mut [f64]) {
    for (i, o) in out.iter_mut().enumerate() {
        *o = (0..x.len()).map(|j| a[(i, j)] * x[j]).sum();
    }
}

/// out += alpha A x.
pub(crate) fn add_product(a: &Mat<f64>, alpha: f64, x: &[f64], out: &mut [f64]) {
    if alpha == 0.0 {
        return;
    }
    for (i, o) in out.iter_mut().enumerate() {
        *o += alpha * (0..x.len()).map(|j| a[(i, j)] * x[j]).sum::<f64>();
    }
}

/// Solves A y = b by LU with partial pivoting; `None` when the solution is not finite.
pub(crate) fn solve_dense(a: &Mat<f64>, b: &[f64]) -> Option<Vec<f64>> {
    let mut y = Mat::<f64>::from_fn(b.len(), 1, |i, _| b[i]);
    faer::linalg::solvers::Solve::solve_in_place(&a.partial_piv_lu(), y.as_mut());
    let y: Vec<f64> = (0..b.len()).map(|i| y[(i, 0)]).collect();
    y.iter().all(|v| v.is_finite()).then_some(y)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn products_and_solve_agree_with_a_worked_example() {
        // A = [[2, 1], [1, 3]], x = (1, -1): A x = (1, -2); A^-1 (1, -2) = x again.
        let a = Mat::from_fn(2, 2, |i, j| [[2.0, 1.0], [1.0, 3.0]][i][j]);
        let mut out = [0.0; 2];
        multiply(&a, &[1.0, -1.0], &mut out);
        assert_eq!(out, [1.0, -2.0]);
        add_product(&a, 0.5, &[1.0, -1.0], &mut out);
        assert_eq!(out, [1.5, -3.0]);
        let y = solve_dense(&a, &[1.0, -2.0]).unwrap();
        // Two eliminations of small integers: a few roundings at most.
        assert!((y[0] - 1.0).abs() < 1e-15 && (y[1] + 1.0).abs() < 1e-15);
        assert_eq!(norm(&difference(&[4.0, 1.0], &[1.0, 5.0])), 5.0);
        let singular = Mat::from_fn(2, 2, |_, _| 1.0);
        assert!(solve_dense(&singular, &[1.0, 2.0]).is_none());
    }
}
