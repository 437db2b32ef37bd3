//! The small linear-algebra kernels of the solvers, in one place: dense and banded
//! products and factorisations that vectorise and allocate nothing inside the time-step
//! loop ([`Dense`], [`Columns`], [`Band`], [`BandLu`], [`Factors`]), the pivoting band LU of
//! harmonic balance's condensation ([`banded::BandedLu`]), the exponential of a small
//! matrix for its stability ([`Exponential`]), the sine and cosine of a turning angle
//! ([`Turning`]), and the one cost model that
//! chooses between dense and banded steps ([`Layout`]), and the plain dense kernels of the
//! Newton solvers (`norm`, `multiply`, `solve_dense`, ...).

pub(crate) mod banded;
mod dense;
mod exponential;
mod turning;

pub(crate) use dense::{add_product, difference, multiply, norm, solve_dense};
pub(crate) use exponential::Exponential;
pub(crate) use turning::{rotate, Turning};

use faer::traits::pulp::Arch;
use faer::Mat;

/// How a solver's step stores its matrices: dense, or banded with these lower and upper
/// bandwidths (of M, K, C and G together).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Layout {
    Dense,
    /// Lower and upper bandwidths of M, K, C and G together.
    Banded(usize, usize),
}

impl Layout {
    /// The cheaper layout for `matrices` (all n x n) in a step that makes `products` band
    /// products and one banded solve per row, against `dense_per_row` multiplications per
    /// row of its dense form. A band row costs (l + u + 1) multiplications per product and
    /// l + u in the solve. On the reference rotor's full model (n = 84, l = u = 7) the
    /// central difference's banded step took 0.8 of the dense one's time for a quarter of
    /// the multiplications: a band multiplication costs about three dense ones (short
    /// rows, and triangular solves where each row waits for the one before), hence the
    /// factor 3.
    pub(crate) fn choose(
        matrices: [&Mat<f64>; 4],
        products: usize,
        dense_per_row: usize,
    ) -> Layout {
        let (lower, upper) = matrices
            .into_iter()
            .map(bandwidths)
            .fold((0, 0), |(l, u), (lm, um)| (l.max(lm), u.max(um)));
        let banded = products * (lower + upper + 1) + (lower + upper);
        if 3 * banded < dense_per_row {
            Layout::Banded(lower, upper)
        } else {
            Layout::Dense
        }
    }

    /// The bandwidths when banded.
    pub(crate) fn band(self) -> Option<(usize, usize)> {
        match self {
            Layout::Banded(l, u) => Some((l, u)),
            Layout::Dense => None,
        }
    }

    /// The bandwidths its matrices are stored with (a dense matrix is a full band).
    pub(crate) fn widths(self, n: usize) -> (usize, usize) {
        self.band()
            .unwrap_or((n.saturating_sub(1), n.saturating_sub(1)))
    }
}

/// a . b summed in order: the plain sum, for the static solver whose results are kept
/// bit for bit as they were computed before [`dot`] existed (eight partial sums round
/// differently).
pub(crate) fn dot_in_order(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// A dense row-major matrix for the small products of the time-step loop, where a plain
/// loop over contiguous rows vectorises and has no call overhead.
#[derive(Debug, Clone)]
pub(crate) struct Dense {
    pub cols: usize,
    pub data: Vec<f64>,
}

impl Dense {
    pub fn from_mat(m: &Mat<f64>) -> Dense {
        let (rows, cols) = (m.nrows(), m.ncols());
        let mut data = Vec::with_capacity(rows * cols);
        for i in 0..rows {
            for j in 0..cols {
                data.push(m[(i, j)]);
            }
        }
        Dense { cols, data }
    }

    /// out += self * x.
    #[inline]
    pub fn mul_add(&self, x: &[f64], out: &mut [f64]) {
        for (row, o) in self.data.chunks_exact(self.cols).zip(out.iter_mut()) {
            *o += row.iter().zip(x).map(|(a, b)| a * b).sum::<f64>();
        }
    }
}

// Kernels of the central difference's step: products and solves that vectorise and whose
// results do not depend on the vector width. Each output element is computed in an order
// fixed by the source (the compiler may not reassociate floating-point sums), and vector
// lanes only hold different elements or different fixed partial sums. They allocate nothing.

/// Runs `f` compiled for the widest vector instructions the processor has (AVX2 and FMA on
/// most x86-64, chosen at run time; the default build targets baseline x86-64, two doubles
/// per instruction). The kernels below are `inline(always)` so that they are compiled
/// inside it. Rust never fuses a multiply and an add unasked, so results are the same on
/// every processor.
#[inline(always)]
pub(crate) fn vectorised<R>(f: impl FnOnce() -> R) -> R {
    Arch::new().dispatch(f)
}

/// a . b with eight partial sums, so the loop vectorises and pipelines: a single running sum
/// is a chain of dependent additions. Rows shorter than eight are summed in order.
#[inline(always)]
pub(crate) fn dot(a: &[f64], b: &[f64]) -> f64 {
    debug_assert_eq!(a.len(), b.len());
    let (a8, b8) = (a.chunks_exact(8), b.chunks_exact(8));
    let tail: f64 = a8
        .remainder()
        .iter()
        .zip(b8.remainder())
        .map(|(x, y)| x * y)
        .sum();
    let mut acc = [0.0; 8];
    for (x, y) in a8.zip(b8) {
        for k in 0..8 {
            acc[k] += x[k] * y[k];
        }
    }
    let pairs = [
        acc[0] + acc[4],
        acc[1] + acc[5],
        acc[2] + acc[6],
        acc[3] + acc[7],
    ];
    ((pairs[0] + pairs[2]) + (pairs[1] + pairs[3])) + tail
}

/// Solves the k x k row-major system in place by Gaussian elimination with partial
/// pivoting; b becomes the solution. A singular system leaves non-finite values, for the caller to
/// report.
pub(crate) fn solve_small(a: &mut [f64], b: &mut [f64]) {
    let k = b.len();
    for col in 0..k {
        let pivot = (col..k)
            .max_by(|&r, &s| a[r * k + col].abs().total_cmp(&a[s * k + col].abs()))
            .unwrap_or(col);
        if pivot != col {
            for j in 0..k {
                a.swap(col * k + j, pivot * k + j);
            }
            b.swap(col, pivot);
        }
        for r in col + 1..k {
            let m = a[r * k + col] / a[col * k + col];
            for j in col..k {
                a[r * k + j] -= m * a[col * k + j];
            }
            b[r] -= m * b[col];
        }
    }
    for col in (0..k).rev() {
        let s: f64 = (col + 1..k).map(|j| a[col * k + j] * b[j]).sum();
        b[col] = (b[col] - s) / a[col * k + col];
    }
}

/// y += alpha x.
#[inline(always)]
pub(crate) fn axpy(alpha: f64, x: &[f64], y: &mut [f64]) {
    debug_assert_eq!(x.len(), y.len());
    for (yi, xi) in y.iter_mut().zip(x) {
        *yi += alpha * xi;
    }
}

/// A dense matrix stored by columns. Its product is a sum of scaled columns, four at a time,
/// so the loop runs along contiguous columns, vectorises across rows and needs no
/// horizontal sums (which a row-by-row dot product of short rows spends much of its time
/// on).
#[derive(Debug, Clone)]
pub(crate) struct Columns {
    rows: usize,
    data: Vec<f64>,
}

impl Columns {
    pub fn from_fn(rows: usize, cols: usize, f: impl Fn(usize, usize) -> f64) -> Columns {
        let data = (0..cols)
            .flat_map(|j| (0..rows).map(move |i| (i, j)))
            .map(|(i, j)| f(i, j))
            .collect();
        Columns { rows, data }
    }

    /// Column j.
    #[inline(always)]
    pub fn column(&self, j: usize) -> &[f64] {
        &self.data[j * self.rows..(j + 1) * self.rows]
    }

    /// out += self * x.
    #[inline(always)]
    pub fn mul_add(&self, x: &[f64], out: &mut [f64]) {
        let n = self.rows;
        let out = &mut out[..n];
        let blocks = self.data.chunks_exact(4 * n);
        let rest = blocks.remainder();
        let x4 = x.chunks_exact(4);
        let x_rest = x4.remainder();
        for (block, xs) in blocks.zip(x4) {
            let (c0, block) = block.split_at(n);
            let (c1, block) = block.split_at(n);
            let (c2, c3) = block.split_at(n);
            for i in 0..n {
                out[i] += (xs[0] * c0[i] + xs[1] * c1[i]) + (xs[2] * c2[i] + xs[3] * c3[i]);
            }
        }
        for (column, &xj) in rest.chunks_exact(n).zip(x_rest) {
            axpy(xj, column, out);
        }
    }
}

/// The lower and upper bandwidths of a square matrix: the largest i - j and j - i of its
/// nonzero entries.
pub(crate) fn bandwidths(m: &Mat<f64>) -> (usize, usize) {
    let n = m.nrows();
    let (mut lower, mut upper) = (0, 0);
    for j in 0..n {
        for i in 0..n {
            if m[(i, j)] != 0.0 {
                lower = lower.max(i.saturating_sub(j));
                upper = upper.max(j.saturating_sub(i));
            }
        }
    }
    (lower, upper)
}

/// A square band matrix with `lower` sub- and `upper` super-diagonals, stored by diagonals:
/// the product adds one diagonal at a time along contiguous memory, which vectorises,
/// where rows of a band are too short to.
#[derive(Debug, Clone)]
pub(crate) struct Band {
    n: usize,
    lower: usize,
    upper: usize,
    /// Diagonal k (offset d = k - lower) holds a[i, i + d] at k * n + i; zero where i + d
    /// falls outside the matrix.
    diagonals: Vec<f64>,
}

impl Band {
    /// The band of `f(i, j)`; entries outside it are taken as zero.
    pub fn from_fn(
        n: usize,
        (lower, upper): (usize, usize),
        f: impl Fn(usize, usize) -> f64,
    ) -> Band {
        let mut diagonals = vec![0.0; n * (lower + upper + 1)];
        for k in 0..=lower + upper {
            for i in Band::rows(n, lower, k) {
                diagonals[k * n + i] = f(i, i + k - lower);
            }
        }
        Band {
            n,
            lower,
            upper,
            diagonals,
        }
    }

    /// The rows where diagonal k lies inside an n by n matrix (none if it lies outside).
    #[inline(always)]
    fn rows(n: usize, lower: usize, k: usize) -> std::ops::Range<usize> {
        let start = lower.saturating_sub(k);
        let end = n.saturating_sub(k.saturating_sub(lower));
        if start < end {
            start..end
        } else {
            0..0
        }
    }

    /// out += self * x.
    #[inline(always)]
    pub fn mul_add(&self, x: &[f64], out: &mut [f64]) {
        let n = self.n;
        for k in 0..=self.lower + self.upper {
            let rows = Band::rows(n, self.lower, k);
            if rows.is_empty() {
                continue;
            }
            let columns = rows.start + k - self.lower..rows.end + k - self.lower;
            let diagonal = &self.diagonals[k * n..(k + 1) * n][rows.clone()];
            for ((o, a), xj) in out[rows].iter_mut().zip(diagonal).zip(&x[columns]) {
                *o += a * xj;
            }
        }
    }

    /// Entry (i, j), zero outside the band.
    pub fn get(&self, i: usize, j: usize) -> f64 {
        if j + self.lower < i || i + self.upper < j {
            0.0
        } else {
            self.diagonals[(j + self.lower - i) * self.n + i]
        }
    }

    /// Adds `value` to entry (i, j), which must lie inside the band.
    pub fn add(&mut self, i: usize, j: usize, value: f64) {
        debug_assert!(
            j + self.lower >= i && i + self.upper >= j,
            "({i}, {j}) outside the band"
        );
        self.diagonals[(j + self.lower - i) * self.n + i] += value;
    }

    /// The number of rows (and columns).
    pub fn size(&self) -> usize {
        self.n
    }

    /// The lower and upper bandwidths.
    pub fn widths(&self) -> (usize, usize) {
        (self.lower, self.upper)
    }

    /// The same band with every entry mapped by `f(i, j, value)`.
    pub fn map(&self, f: impl Fn(usize, usize, f64) -> f64) -> Band {
        Band::from_fn(self.n, self.widths(), |i, j| f(i, j, self.get(i, j)))
    }

    /// B X for a dense X, column by column.
    pub fn times(&self, x: &Mat<f64>) -> Mat<f64> {
        let mut out = Mat::<f64>::zeros(x.nrows(), x.ncols());
        for j in 0..x.ncols() {
            self.mul_add(x.col_as_slice(j), out.col_as_slice_mut(j));
        }
        out
    }

    /// X^T B X for a dense X (n x p): the band projected on X's columns.
    pub fn project(&self, x: &Mat<f64>) -> Mat<f64> {
        x.transpose() * self.times(x)
    }

    /// The dense matrix, zero outside the band.
    pub fn to_dense(&self) -> Mat<f64> {
        Mat::from_fn(self.n, self.n, |i, j| self.get(i, j))
    }

    /// The band of a dense matrix, as wide as its nonzero entries reach.
    pub fn of_dense(m: &Mat<f64>) -> Band {
        Band::from_fn(m.nrows(), bandwidths(m), |i, j| m[(i, j)])
    }
}

/// LU factors of a band matrix without row swaps, so that L and U keep the band and both
/// triangular solves run row by row. Without swaps the factorisation is reliable when the
/// matrix's symmetric part is positive definite and its skew part is small against it
/// (Golub & Van Loan, Matrix Computations, "unsymmetric positive definite systems"); the
/// caller checks that, see [`BandLu::pivots_positive`].
#[derive(Debug, Clone)]
pub(crate) struct BandLu {
    lower: usize,
    upper: usize,
    /// Row i of L left of the diagonal, L[i, i - lower..i], at i * lower (zero before
    /// column 0).
    l: Vec<f64>,
    /// Row i of U right of the diagonal, divided by the diagonal: U[i, i + 1..=i + upper] /
    /// U[i, i] at i * upper (zero past the last column).
    u: Vec<f64>,
    /// 1 / U[i, i].
    inverse_diagonal: Vec<f64>,
}

impl BandLu {
    /// Factorises `a`; `None` when a pivot is zero or not finite.
    pub fn new(a: &Band) -> Option<BandLu> {
        let (n, kl, ku) = (a.n, a.lower, a.upper);
        let mut l = vec![0.0; n * kl];
        let mut u = vec![0.0; n * ku];
        let mut inverse_diagonal = vec![0.0; n];
        // Row i of the work band covers columns i - kl..=i + ku; eliminated entries hold L.
        let width = kl + ku + 1;
        let at = |i: usize, j: usize| i * width + j + kl - i;
        let mut w = vec![0.0; n * width];
        for i in 0..n {
            for j in i.saturating_sub(kl)..(i + ku + 1).min(n) {
                w[at(i, j)] = a.get(i, j);
            }
        }
        for k in 0..n {
            let pivot = w[at(k, k)];
            if !(pivot.is_finite() && pivot != 0.0) {
                return None;
            }
            let below = k + 1..(k + kl + 1).min(n);
            let right = k + 1..(k + ku + 1).min(n);
            for i in below {
                let m = w[at(i, k)] / pivot;
                w[at(i, k)] = m;
                for j in right.clone() {
                    w[at(i, j)] -= m * w[at(k, j)];
                }
            }
            inverse_diagonal[k] = 1.0 / pivot;
            for j in right {
                u[k * ku + j - k - 1] = w[at(k, j)] / pivot;
            }
            for j in k.saturating_sub(kl)..k {
                l[k * kl + j + kl - k] = w[at(k, j)];
            }
        }
        Some(BandLu {
            lower: kl,
            upper: ku,
            l,
            u,
            inverse_diagonal,
        })
    }

    /// True when every pivot is positive: for a symmetric matrix, exactly when it is
    /// positive definite (its leading minors, the products of the pivots, are positive).
    pub fn pivots_positive(&self) -> bool {
        self.inverse_diagonal.iter().all(|&d| d > 0.0)
    }

    /// Zeros needed before and after the right-hand side by [`BandLu::solve_padded`].
    pub fn padding(&self) -> (usize, usize) {
        (self.lower, self.upper)
    }

    /// Solves A x = b in place, b in `padded` after [`BandLu::padding`]'s zeros before it
    /// and followed by its zeros after (which stay zero): padding makes every row of L and U
    /// the same length, so the loops clip nothing. Each row's sum leaves the entry just
    /// solved for last, so the rest of the row is summed while that entry is still being
    /// computed: the chain from one row to the next is one multiplication and one
    /// subtraction.
    #[inline(always)]
    pub fn solve_padded(&self, padded: &mut [f64]) {
        let n = self.inverse_diagonal.len();
        let (kl, ku) = (self.lower, self.upper);
        assert_eq!(padded.len(), kl + n + ku);
        if let Some(last) = kl.checked_sub(1) {
            // Row i of L covers padded[i..i + kl]; b_i is at padded[kl + i].
            for (i, row) in self.l.chunks_exact(kl).enumerate() {
                let s = dot(&row[..last], &padded[i..i + last]);
                padded[kl + i] = (padded[kl + i] - s) - row[last] * padded[kl + i - 1];
            }
        }
        for i in (0..n).rev() {
            let at = kl + i;
            let scaled = padded[at] * self.inverse_diagonal[i];
            padded[at] = match self.u[i * ku..(i + 1) * ku].split_first() {
                Some((near, far)) => {
                    let s = dot(far, &padded[at + 2..at + 1 + ku]);
                    (scaled - s) - near * padded[at + 1]
                }
                None => scaled,
            };
        }
    }
}

/// A square matrix factorised for repeated solves: a band LU without row swaps when a band
/// is given and that is safe, else the dense inverse from a pivoting LU, or, for a band
/// too large to hold dense ([`Factors::of_band`]), the band LU with row swaps.
pub(crate) enum Factors {
    Banded {
        lu: BandLu,
        /// The right-hand side with the zeros around it that the solve needs.
        padded: Vec<f64>,
    },
    Inverse(Columns),
    Pivoted(banded::BandedLu),
}

impl Factors {
    /// Banded with bandwidths `band` when given and the matrix's symmetric part is positive
    /// definite, which makes the factorisation without row swaps safe (see [`BandLu`]);
    /// otherwise the dense inverse. `None` when the matrix is singular.
    pub fn new(band: Option<(usize, usize)>, a: &Mat<f64>) -> Option<Factors> {
        if let Some(lu) = band.and_then(|widths| banded_lu(a, widths)) {
            let (before, after) = lu.padding();
            let padded = vec![0.0; before + a.nrows() + after];
            return Some(Factors::Banded { lu, padded });
        }
        let n = a.nrows();
        let mut inverse = Mat::<f64>::identity(n, n);
        faer::linalg::solvers::Solve::solve_in_place(&a.partial_piv_lu(), inverse.as_mut());
        if inverse.col_iter().any(|c| c.iter().any(|v| !v.is_finite())) {
            return None;
        }
        Some(Factors::Inverse(Columns::from_fn(n, n, |i, j| {
            inverse[(i, j)]
        })))
    }

    /// The band `a` factorised without ever holding it dense: without row swaps when that is
    /// safe (as [`Factors::new`]), else with them (a band LU's memory and cost stay linear
    /// in the size, where the dense inverse's grow as its square and cube). `None` when `a`
    /// is singular.
    pub fn of_band(a: &Band) -> Option<Factors> {
        if let Some(lu) = banded_lu_of(a) {
            let (before, after) = lu.padding();
            let padded = vec![0.0; before + a.size() + after];
            return Some(Factors::Banded { lu, padded });
        }
        let (lower, upper) = a.widths();
        banded::BandedLu::new(a.size(), lower, upper, |i, j| a.get(i, j)).map(Factors::Pivoted)
    }

    /// out = A^-1 rhs.
    #[inline(always)]
    pub fn solve(&mut self, rhs: &[f64], out: &mut [f64]) {
        match self {
            Factors::Banded { lu, padded } => {
                let start = lu.padding().0;
                padded[start..start + rhs.len()].copy_from_slice(rhs);
                lu.solve_padded(padded);
                out.copy_from_slice(&padded[start..start + rhs.len()]);
            }
            Factors::Inverse(inverse) => {
                out.iter_mut().for_each(|x| *x = 0.0);
                inverse.mul_add(rhs, out);
            }
            Factors::Pivoted(lu) => {
                out.copy_from_slice(rhs);
                lu.solve(out);
            }
        }
    }
}

/// The band LU of `a` when its symmetric part has positive pivots, else `None`.
fn banded_lu(a: &Mat<f64>, widths: (usize, usize)) -> Option<BandLu> {
    banded_lu_of(&Band::from_fn(a.nrows(), widths, |i, j| a[(i, j)]))
}

/// [`banded_lu`] of a band.
fn banded_lu_of(a: &Band) -> Option<BandLu> {
    let (lower, upper) = a.widths();
    let w = lower.max(upper);
    let symmetric = Band::from_fn(a.size(), (w, w), |i, j| 0.5 * (a.get(i, j) + a.get(j, i)));
    if !BandLu::new(&symmetric)?.pivots_positive() {
        return None;
    }
    BandLu::new(a)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A reproducible, unstructured value for entry (i, j).
    fn entry(i: usize, j: usize) -> f64 {
        ((i * 31 + j * 17) as f64 * 0.618).sin()
    }

    /// A band matrix (lower 3, upper 2) whose symmetric part is positive definite, as dense.
    fn banded(n: usize) -> Mat<f64> {
        Mat::from_fn(n, n, |i, j| {
            if i == j {
                10.0 + entry(i, i).abs()
            } else if j + 3 >= i && j <= i + 2 {
                entry(i, j)
            } else {
                0.0
            }
        })
    }

    fn dense_product(a: &Mat<f64>, x: &[f64]) -> Vec<f64> {
        (0..a.nrows())
            .map(|i| (0..a.ncols()).map(|j| a[(i, j)] * x[j]).sum())
            .collect()
    }

    fn close(a: &[f64], b: &[f64]) -> f64 {
        let scale = b.iter().fold(0.0f64, |s, x| s.max(x.abs()));
        a.iter()
            .zip(b)
            .fold(0.0f64, |s, (x, y)| s.max((x - y).abs()))
            / scale
    }

    #[test]
    fn band_product_and_lu_match_dense_algebra() {
        for n in [1, 2, 5, 40] {
            let a = banded(n);
            let band = Band::from_fn(n, (3, 2), |i, j| a[(i, j)]);
            let x: Vec<f64> = (0..n).map(|i| entry(i, 7)).collect();
            let mut product = vec![0.0; n];
            band.mul_add(&x, &mut product);
            // The same sums in another order: a few roundings of O(10) terms.
            assert!(close(&product, &dense_product(&a, &x)) < 1e-14);

            let lu = BandLu::new(&band).expect("diagonally dominant");
            let (before, after) = lu.padding();
            let mut padded = vec![0.0; before + n + after];
            padded[before..before + n].copy_from_slice(&product);
            lu.solve_padded(&mut padded);
            let solved = &padded[before..before + n];
            // The matrix is well conditioned (diagonally dominant), so x comes back to a
            // few units of round-off.
            assert!(close(solved, &x) < 1e-13, "n = {n}");
        }
    }

    #[test]
    fn pivots_tell_positive_definite_from_indefinite() {
        let mut a = banded(6);
        let symmetric =
            |a: &Mat<f64>| Band::from_fn(6, (3, 3), |i, j| 0.5 * (a[(i, j)] + a[(j, i)]));
        assert!(BandLu::new(&symmetric(&a)).unwrap().pivots_positive());
        a[(4, 4)] = -a[(4, 4)];
        assert!(!BandLu::new(&symmetric(&a)).unwrap().pivots_positive());
    }

    #[test]
    fn a_band_factorised_as_a_band_solves_whether_or_not_it_is_definite() {
        // Definite: the LU without row swaps; a pivot made negative: the one with them
        // (where `Factors::new` would hold the dense inverse).
        let n = 40;
        let mut a = banded(n);
        for definite in [true, false] {
            if !definite {
                a[(17, 17)] = -a[(17, 17)];
            }
            let band = Band::from_fn(n, (3, 2), |i, j| a[(i, j)]);
            let mut factors = Factors::of_band(&band).expect("not singular");
            assert_eq!(matches!(factors, Factors::Banded { .. }), definite);
            let x: Vec<f64> = (0..n).map(|i| entry(i, 5)).collect();
            let b = dense_product(&a, &x);
            let mut solved = vec![0.0; n];
            factors.solve(&b, &mut solved);
            // Well conditioned (diagonally dominant either way): a few units of round-off.
            assert!(close(&solved, &x) < 1e-13, "definite: {definite}");
        }
    }

    #[test]
    fn column_product_matches_dense_algebra_on_every_instruction_set() {
        for (rows, cols) in [(1, 1), (3, 7), (20, 40), (21, 42)] {
            let a = Mat::from_fn(rows, cols, entry);
            let columns = Columns::from_fn(rows, cols, |i, j| a[(i, j)]);
            let x: Vec<f64> = (0..cols).map(|j| entry(j, 3)).collect();
            let (mut plain, mut wide) = (vec![0.5; rows], vec![0.5; rows]);
            columns.mul_add(&x, &mut plain);
            vectorised(|| columns.mul_add(&x, &mut wide));
            // Lanes hold different rows, never parts of one sum: bit for bit the same.
            assert_eq!(plain, wide);
            let expected: Vec<f64> = dense_product(&a, &x).iter().map(|v| v + 0.5).collect();
            assert!(close(&plain, &expected) < 1e-14);
        }
    }
}
