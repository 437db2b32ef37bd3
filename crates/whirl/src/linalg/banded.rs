//! LU factorisation with partial pivoting of a band matrix, for the condensation's D_bb.
//!
//! A finite-element rotor couples only neighbouring nodes, so its matrices are banded; the
//! dynamic stiffness of one harmonic with the cos and sin copies of each coordinate
//! interleaved keeps a band twice as wide. Factorising it costs O(n k^2) instead of the
//! O(n^3) of a dense factorisation, which makes the condensation's cost grow only linearly
//! with the model size.
//!
//! The algorithm is the one of LAPACK's dgbtrf/dgbtrs (Golub & Van Loan, "Matrix
//! Computations", 4th ed., section 4.3.5): row interchanges widen the upper band from k_u
//! to k_l + k_u, and each step's interchange is applied to the right-hand side just before
//! that step's elimination.

/// A band matrix factorised in place.
pub(crate) struct BandedLu {
    n: usize,
    lower: usize,
    /// Upper bandwidth after fill-in, k_l + k_u.
    upper: usize,
    /// Row i holds columns i - lower ..= i + upper at offsets 0 ..= lower + upper.
    rows: Vec<f64>,
    pivots: Vec<usize>,
    /// The last column of row i of U that can be nonzero (at most i + upper).
    extents: Vec<usize>,
}

impl BandedLu {
    /// Factorises the n x n matrix `entry(i, j)` with `lower` sub- and `upper`
    /// super-diagonals (entries outside the band are taken as zero). `None` when a pivot
    /// is zero or not finite: the matrix is singular.
    pub(crate) fn new(
        n: usize,
        lower: usize,
        upper: usize,
        entry: impl Fn(usize, usize) -> f64,
    ) -> Option<BandedLu> {
        let upper_fill = lower + upper;
        let width = lower + upper_fill + 1;
        let mut lu = BandedLu {
            n,
            lower,
            upper: upper_fill,
            rows: vec![0.0; n * width],
            pivots: vec![0; n],
            extents: vec![0; n],
        };
        for (i, row) in lu.rows.chunks_exact_mut(width).enumerate() {
            let first = i.saturating_sub(lower);
            let last = (i + upper).min(n.saturating_sub(1));
            for (j, slot) in (first..=last).zip(&mut row[first + lower - i..]) {
                *slot = entry(i, j);
            }
        }
        // The rightmost column that row interchanges have filled so far (LAPACK's `ju`):
        // the rows still to be eliminated are zero to its right, so the interchanges and
        // the updates stop there. Skipping those zeros changes no bit of the result.
        let mut filled = 0;
        for k in 0..n {
            let last_row = (k + lower).min(n - 1);
            let pivot = (k..=last_row)
                .max_by(|&a, &b| lu.get(a, k).abs().total_cmp(&lu.get(b, k).abs()))
                .unwrap_or(k);
            let value = lu.get(pivot, k);
            if value == 0.0 || !value.is_finite() {
                return None;
            }
            lu.pivots[k] = pivot;
            filled = filled.max((pivot + upper).min(n - 1));
            let last_col = filled;
            lu.extents[k] = last_col;
            if pivot != k {
                let (above, below) = lu.rows.split_at_mut(pivot * width);
                let row_k = &mut above[k * width + lower..k * width + lower + last_col - k + 1];
                let from = k + lower - pivot;
                row_k.swap_with_slice(&mut below[from..from + last_col - k + 1]);
            }
            for i in k + 1..=last_row {
                let at = i * width + k + lower - i;
                let l = lu.rows[at] / value;
                lu.rows[at] = l;
                if l != 0.0 {
                    // Columns k + 1 ..= last_col of rows k and i are contiguous in storage.
                    let from_k = k * width + lower + 1;
                    let (pivot_row, below) = lu.rows.split_at_mut(i * width);
                    let u = &pivot_row[from_k..from_k + last_col - k];
                    let row = &mut below[at - i * width + 1..at - i * width + 1 + last_col - k];
                    for (a, b) in row.iter_mut().zip(u) {
                        *a -= l * b;
                    }
                }
            }
        }
        Some(lu)
    }

    fn index(&self, i: usize, j: usize) -> usize {
        i * (self.lower + self.upper + 1) + (j + self.lower - i)
    }

    fn get(&self, i: usize, j: usize) -> f64 {
        self.rows[self.index(i, j)]
    }

    /// Solves A x = b in place for one right-hand side: [`Self::solve_rows`] with k = 1,
    /// with the back substitution as dot products over the contiguous rows of U.
    pub(crate) fn solve(&self, b: &mut [f64]) {
        let (n, lower) = (self.n, self.lower);
        let width = lower + self.upper + 1;
        for s in 0..n {
            b.swap(s, self.pivots[s]);
            let pivot = b[s];
            if pivot != 0.0 {
                for i in s + 1..=(s + lower).min(n - 1) {
                    b[i] -= self.rows[i * width + s + lower - i] * pivot;
                }
            }
        }
        for i in (0..n).rev() {
            let last = self.extents[i];
            let row = &self.rows[i * width + lower..i * width + lower + last - i + 1];
            let above: f64 = row[1..]
                .iter()
                .zip(&b[i + 1..=last])
                .map(|(u, x)| u * x)
                .sum();
            b[i] = (b[i] - above) / row[0];
        }
    }

    /// Solves A X = B in place for `k` right-hand sides stored row by row (row i of B at
    /// `i * k .. (i + 1) * k`), so every elimination step updates contiguous rows.
    pub(crate) fn solve_rows(&self, b: &mut [f64], k: usize) {
        let (n, lower) = (self.n, self.lower);
        let width = lower + self.upper + 1;
        for s in 0..n {
            let p = self.pivots[s];
            if p != s {
                let (head, tail) = b.split_at_mut(p * k);
                head[s * k..(s + 1) * k].swap_with_slice(&mut tail[..k]);
            }
            let (head, tail) = b.split_at_mut((s + 1) * k);
            let pivot_row = &head[s * k..];
            for (i, row) in (s + 1..=(s + lower).min(n - 1)).zip(tail.chunks_exact_mut(k)) {
                let l = self.rows[i * width + s + lower - i];
                if l != 0.0 {
                    for (r, q) in row.iter_mut().zip(pivot_row) {
                        *r -= l * q;
                    }
                }
            }
        }
        for i in (0..n).rev() {
            let last = self.extents[i];
            // Row i of U from its diagonal on.
            let u = &self.rows[i * width + lower..i * width + lower + last - i + 1];
            let (head, tail) = b.split_at_mut((i + 1) * k);
            let row = &mut head[i * k..];
            for (&u, solved) in u[1..].iter().zip(tail.chunks_exact(k)) {
                if u != 0.0 {
                    for (r, q) in row.iter_mut().zip(solved) {
                        *r -= u * q;
                    }
                }
            }
            let d = u[0];
            row.iter_mut().for_each(|r| *r /= d);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use faer::Mat;

    #[test]
    fn solves_like_a_dense_factorisation_even_when_pivoting_is_needed() {
        // An indefinite band matrix with a zero diagonal entry: elimination without row
        // interchanges would divide by zero at the first step.
        let (n, kl, ku) = (30, 3, 2);
        let entry = |i: usize, j: usize| {
            let outside = j + kl < i || i + ku < j;
            if outside || (i == j && i.is_multiple_of(7)) {
                0.0
            } else {
                ((i * 13 + j * 7) % 11) as f64 - 5.0 + if i == j { 0.5 } else { 0.0 }
            }
        };
        let lu = BandedLu::new(n, kl, ku, entry).unwrap();
        // Two right-hand sides, row by row.
        let k = 2;
        let b: Vec<f64> = (0..n * k).map(|i| (i as f64).sin()).collect();
        let mut x = b.clone();
        lu.solve_rows(&mut x, k);
        // The single right-hand side solve gives the first column alike.
        let mut first: Vec<f64> = (0..n).map(|i| b[i * k]).collect();
        lu.solve(&mut first);
        for i in 0..n {
            assert!((first[i] - x[i * k]).abs() < 1e-13 * (1.0 + x[i * k].abs()));
        }
        let a = Mat::from_fn(n, n, entry);
        let mut dense = Mat::from_fn(n, k, |i, j| b[i * k + j]);
        faer::linalg::solvers::Solve::solve_in_place(&a.partial_piv_lu(), dense.as_mut());
        for i in 0..n {
            for j in 0..k {
                // Both are backward stable on a matrix of condition ~1e2.
                let (ours, theirs) = (x[i * k + j], dense[(i, j)]);
                assert!(
                    (ours - theirs).abs() < 1e-11,
                    "{i}, {j}: {ours} vs {theirs}"
                );
            }
        }
    }

    #[test]
    fn a_singular_matrix_is_refused() {
        // Two equal rows.
        let entry = |i: usize, j: usize| {
            if i < 2 {
                1.0 + j as f64
            } else {
                (i == j) as u8 as f64
            }
        };
        assert!(BandedLu::new(3, 2, 2, entry).is_none());
    }
}
