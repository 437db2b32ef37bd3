//! The exponential of a small dense matrix, for the monodromy matrix of harmonic balance's
//! stability: scaling and squaring of Taylor polynomials evaluated with few matrix products
//! (Bader, Blanes & Casas, "Computing the matrix exponential with an optimized Taylor
//! polynomial approximation", Mathematics 7, 2019). Their schemes give the Taylor
//! polynomial T_m of degree m = 1, 2, 4, 8, 12, 18 with 0, 1, 2, 3, 4, 5 products: beyond
//! the powers A^2, A^3 (and A^6 for degree 18) they multiply two linear combinations of the
//! powers, with coefficients that solve the polynomial equations making the product's
//! coefficients those of the series (degree 18 from its terms of degree 9 at most). T_m(A)
//! is exp(A + E) with a backward error E = h(A) = sum_(k > m) c_k A^k, and |E| is at most the
//! unit round-off times |A| when a bound on the size of A's powers is below theta_m (their
//! table for double precision; theta_18 = 1.09), in exact arithmetic.
//!
//! The bound is the 1-norm up to degree 8. From degree 12 on, A^2 and A^3 are formed first,
//! and the bound is the smaller of |A|_1 and alpha = max(|A^2|^(1/2), |A^3|^(1/3)): every
//! power from the second on is a product of squares and cubes, so |A^k|^(1/k) <= alpha
//! (Al-Mohy & Higham, "A new scaling and squaring algorithm for the matrix exponential",
//! SIAM J. Matrix Anal. Appl. 31, 2009, lemma 4.1 and theorem 4.2). Degree 18 also forms
//! A^6, which tightens it further: each k >= 19 is 6 i + r with r in 2..=7 a sum of twos and
//! threes, so |A^k| <= d6^(k - r) a^r <= d6^(k - 7) a^7 with d6 = |A^6|^(1/6) <= a, the
//! smaller of |A|_1 and alpha; the k-th root of that is largest at k = 19, and the bound is
//! beta = d6^(12/19) a^(7/19). The state matrices of a rotor, coupled and damped, are far
//! from normal: their 1-norm overstates the growth of their powers, by 1.5 to 3 on the
//! reference rotor, and beta saves one or two halvings. Above theta_18, A is halved s
//! times until beta / 2^s <= theta_18 (A^2, A^3, A^6 scaled by 4^-s, 8^-s, 64^-s, exactly),
//! and T_18 is squared s times.
//!
//! The Floquet problems' matrices are first-order forms [[0, c I], [B, C]] of a
//! second-order system; [`Exponential::of_state`] forms their A^2 and A^3 by blocks, for a
//! quarter and a half of a product's work.
//!
//! Against the Padé approximants used before (Higham, "The scaling and squaring method for
//! the matrix exponential revisited", SIAM J. Matrix Anal. Appl. 26, 2005, algorithm 2.3):
//! no LU factorisation and no solve with n right-hand sides, which at n = 40-72 took 5-9
//! products' time with faer, for up to two more squarings (theta_13 = 5.37 against 1.09,
//! less what beta saves). The work buffers live in [`Exponential`], so the 160 to 320
//! exponentials of one monodromy matrix allocate nothing.

use faer::linalg::matmul::matmul;
use faer::{Accum, MatMut, MatRef, Par};

use faer::traits::pulp::{Arch, Simd, WithSimd};

/// One exponential as pulp's operation, compiled for the processor's widest vectors.
struct Taylor<'a> {
    work: &'a mut Exponential,
    a: &'a [f64],
    state: Option<f64>,
}

impl WithSimd for Taylor<'_> {
    type Output = Option<()>;

    #[inline(always)]
    fn with_simd<S: Simd>(self, _: S) -> Option<()> {
        self.work.taylor_scaled(self.a, self.state)
    }
}

/// The degrees m of the Taylor polynomials, and theta_m, the largest bound on A's size for
/// which T_m(A) is exp of a matrix within the unit round-off of A in norm (Bader, Blanes &
/// Casas 2019, their table for double precision).
// The digits as published (rounded to the nearest double on reading).
#[allow(clippy::excessive_precision)]
const THETAS: [(usize, f64); 6] = [
    (1, 2.220446049250313e-16),
    (2, 2.580956802971767e-8),
    (4, 3.397168839976962e-4),
    (8, 4.991228871115323e-2),
    (12, 2.996158913811580e-1),
    (18, 1.090863719290036),
];

/// Degree 12 (Bader, Blanes & Casas 2019): with B_i = sum_k c[i][k] A^k over I, A, A^2,
/// A^3, A6 = B_2 + B_3 B_3 and T_12 = B_0 + (B_1 + A6) A6.
// The digits as published (rounded to the nearest double on reading).
#[allow(clippy::excessive_precision)]
const DEGREE_12: [[f64; 4]; 4] = [
    [
        9.0198e-16,
        0.46932117595418237389,
        -0.20099424927047284052,
        -0.04623946134063071740,
    ],
    [
        5.31597895759871264183,
        1.19926790417132231573,
        0.01179296240992997031,
        0.01108844528519167989,
    ],
    [
        0.18188869982170434744,
        0.05502798439925399070,
        0.09351590770535414968,
        0.00610700528898058230,
    ],
    [
        -2.0861320e-13,
        -0.13181061013830184015,
        -0.02027855540589259079,
        -0.00675951846863086359,
    ],
];

/// Degree 18 (Bader, Blanes & Casas 2019): with B_i = sum_k c[i][k] A^k over I, A, A^2,
/// A^3, A^6, A9 = B_0 B_4 + B_3 and T_18 = B_1 + (B_2 + A9) A9.
// The digits as published (rounded to the nearest double on reading).
#[allow(clippy::excessive_precision)]
const DEGREE_18: [[f64; 5]; 5] = [
    [
        0.0,
        -1.00365581030144618291e-1,
        -8.02924648241156932449e-3,
        -8.92138498045729985177e-4,
        0.0,
    ],
    [
        0.0,
        3.97849749499645077844e-1,
        1.36783778460411720168,
        4.98289622525382669416e-1,
        -6.37898194594723280150e-4,
    ],
    [
        -1.09676396052962061844e1,
        1.68015813878906206114,
        5.71779846478865511061e-2,
        -6.98210122488052056106e-3,
        3.34975017086070470649e-5,
    ],
    [
        -9.04316832390810593223e-2,
        -6.76404519071381882256e-2,
        6.75961301770459654925e-2,
        2.95552570429315521194e-2,
        -1.39180257516060693404e-5,
    ],
    [
        0.0,
        0.0,
        -9.23364619367118555360e-2,
        -1.69364939002081722752e-2,
        -1.40086798182036094347e-5,
    ],
];

/// The degree and the halvings s for a matrix of size `size` (see the module's
/// documentation): the lowest degree whose theta_m bounds it, else 18 with the s that brings
/// size / 2^s to theta_18.
fn approximant(size: f64) -> (usize, i32) {
    let (top, theta) = THETAS[THETAS.len() - 1];
    match THETAS.iter().find(|(_, theta)| size <= *theta) {
        Some(&(degree, _)) => (degree, 0),
        None => (top, (size / theta).log2().ceil() as i32),
    }
}

/// The 1-norm (largest column sum) of the column-major matrix with columns of length n, NaN
/// when an entry is. Each column is summed in eight interleaved partial sums, so the sums
/// vectorise (one running sum is a chain of dependent additions: the norms took a fifth of
/// an exponential's time that way).
#[inline(always)]
fn norm_1(a: &[f64], n: usize) -> f64 {
    let mut norm: f64 = 0.0;
    for column in a.chunks_exact(n) {
        let mut lanes = [0.0; 8];
        let chunks = column.chunks_exact(8);
        let mut sum = 0.0;
        for v in chunks.remainder() {
            sum += v.abs();
        }
        for chunk in chunks {
            for (l, v) in lanes.iter_mut().zip(chunk) {
                *l += v.abs();
            }
        }
        for l in lanes {
            sum += l;
        }
        // Not f64::max, which would pass over a NaN (a NaN norm stays).
        if sum > norm || sum.is_nan() {
            norm = sum;
        }
    }
    norm
}

/// Whether every entry is finite, without an early exit so that it vectorises: 0 v is 0
/// for a finite v and NaN for an infinite or NaN one.
#[inline(always)]
fn all_finite(a: &[f64]) -> bool {
    let mut lanes = [0.0; 8];
    let chunks = a.chunks_exact(8);
    let mut tail = 0.0;
    for v in chunks.remainder() {
        tail += 0.0 * v;
    }
    for chunk in chunks {
        for (l, v) in lanes.iter_mut().zip(chunk) {
            *l += 0.0 * v;
        }
    }
    tail == 0.0 && lanes.iter().all(|l| *l == 0.0)
}

/// The exponential of n x n matrices with its work buffers, all column-major n x n: made
/// once per monodromy matrix, reused for every step.
pub(crate) struct Exponential {
    n: usize,
    /// A / 2^s.
    scaled: Vec<f64>,
    /// A^2 and A^3 of the scaled matrix (A^4 for degree 8), then A^6 or A6.
    a2: Vec<f64>,
    a3: Vec<f64>,
    a6: Vec<f64>,
    /// Linear combinations of the powers, the factors of the schemes' products.
    left: Vec<f64>,
    right: Vec<f64>,
    /// A9 of degree 18.
    a9: Vec<f64>,
    /// T_m(A / 2^s), squared s times with `spare`.
    result: Vec<f64>,
    spare: Vec<f64>,
    /// The degree and halvings of the last exponential (what the tests check).
    chosen: (usize, i32),
}

impl Exponential {
    pub(crate) fn new(n: usize) -> Exponential {
        let square = || vec![0.0; n * n];
        Exponential {
            n,
            scaled: square(),
            a2: square(),
            a3: square(),
            a6: square(),
            left: square(),
            right: square(),
            a9: square(),
            result: square(),
            spare: square(),
            chosen: (0, 0),
        }
    }

    /// exp(a) of the column-major n x n matrix `a`, a view into the work buffers valid until
    /// the next call; `None` when `a` is not finite. (The monodromy takes [`Self::of_state`];
    /// this general form is what the tests compare it with.)
    #[cfg(test)]
    pub(crate) fn of(&mut self, a: &[f64]) -> Option<MatRef<'_, f64>> {
        self.run(a, None)
    }

    /// The same for a first-order form of a second-order system, a = [[0, c I], [B, C]] in
    /// blocks of n / 2 (c = `coupling`), whose powers A^2 and A^3 cost a quarter and a half
    /// of a product (the upper rows of A A are c [B C], the lower C [B C] + [0, c B]; and
    /// X A = X_2 [B C] + [0, c X_1] for the column blocks X_1, X_2 of X).
    pub(crate) fn of_state(&mut self, a: &[f64], coupling: f64) -> Option<MatRef<'_, f64>> {
        debug_assert!(self.n.is_multiple_of(2));
        self.run(a, Some(coupling))
    }

    fn run(&mut self, a: &[f64], state: Option<f64>) -> Option<MatRef<'_, f64>> {
        // Through a `WithSimd` whose method is inlined into pulp's dispatch: a closure's body
        // that large was not, and its sums over the powers ran on two-double instructions.
        Arch::new().dispatch(Taylor {
            work: self,
            a,
            state,
        })?;
        Some(MatRef::from_column_major_slice(
            &self.result,
            self.n,
            self.n,
        ))
    }

    /// A^2 and A^3 of the first-order form a = [[0, c I], [B, C]] (see [`Self::of_state`]).
    #[inline(always)]
    fn state_powers(&mut self, a: &[f64], coupling: f64) {
        let (n, half) = (self.n, self.n / 2);
        let lower = MatRef::from_column_major_slice(a, n, n).subrows(half, half);
        // Upper rows c [B C], lower rows C [B C] + [0, c B], column by column.
        for (x, column) in self.a2.chunks_exact_mut(n).zip(a.chunks_exact(n)) {
            for (x, v) in x[..half].iter_mut().zip(&column[half..]) {
                *x = coupling * v;
            }
        }
        matmul(
            MatMut::from_column_major_slice_mut(&mut self.a2, n, n).subrows_mut(half, half),
            Accum::Replace,
            lower.subcols(half, half),
            lower,
            1.0,
            Par::Seq,
        );
        let (_, right) = self.a2.split_at_mut(half * n);
        for (x, column) in right.chunks_exact_mut(n).zip(a.chunks_exact(n)) {
            for (x, v) in x[half..].iter_mut().zip(&column[half..]) {
                *x += coupling * v;
            }
        }
        // A^3 = A^2 A = X_2 [B C] + [0, c X_1] with X = A^2.
        matmul(
            MatMut::from_column_major_slice_mut(&mut self.a3, n, n),
            Accum::Replace,
            MatRef::from_column_major_slice(&self.a2, n, n).subcols(half, half),
            lower,
            1.0,
            Par::Seq,
        );
        let (_, right) = self.a3.split_at_mut(half * n);
        for (x, column) in right.chunks_exact_mut(n).zip(self.a2.chunks_exact(n)) {
            for (x, v) in x.iter_mut().zip(column) {
                *x += coupling * v;
            }
        }
    }

    #[inline(always)]
    fn taylor_scaled(&mut self, a: &[f64], state: Option<f64>) -> Option<()> {
        let n = self.n;
        debug_assert_eq!(a.len(), n * n);
        let norm = norm_1(a, n);
        if !norm.is_finite() {
            return None;
        }
        let low = THETAS[3].1;
        if norm <= low {
            self.scaled.copy_from_slice(a);
            let (degree, _) = approximant(norm);
            self.chosen = (degree, 0);
            self.low_degree(degree);
        } else {
            // A^2 and A^3 (and A^6) of A itself decide the degree and the halvings; scaled
            // by powers of two, they are the powers of the scaled matrix exactly.
            if let Some(coupling) = state {
                self.state_powers(a, coupling);
            } else {
                product(&mut self.a2, a, a, n, Accum::Replace);
                product(&mut self.a3, &self.a2, a, n, Accum::Replace);
            }
            let size = norm.min(f64::max(
                norm_1(&self.a2, n).sqrt(),
                norm_1(&self.a3, n).cbrt(),
            ));
            let (degree, halvings) = if size <= THETAS[4].1 {
                // Degree 12 at least: A^2 and A^3 are paid for.
                (12, 0)
            } else {
                // Degree 18 forms A^6 = (A^3)^2 anyway; with it, beta bounds the powers
                // from 19 on (the module's documentation).
                product(&mut self.a6, &self.a3, &self.a3, n, Accum::Replace);
                let d6 = norm_1(&self.a6, n).powf(1.0 / 6.0);
                approximant(d6.powf(12.0 / 19.0) * size.powf(7.0 / 19.0))
            };
            self.chosen = (degree, halvings);
            let scale = 2f64.powi(-halvings);
            for (s, v) in self.scaled.iter_mut().zip(a) {
                *s = v * scale;
            }
            if halvings > 0 {
                let (scale2, scale3) = (scale * scale, scale * scale * scale);
                for (power, scale) in [(&mut self.a2, scale2), (&mut self.a3, scale3)]
                    .into_iter()
                    .chain((degree == 18).then_some((&mut self.a6, scale3 * scale3)))
                {
                    power.iter_mut().for_each(|v| *v *= scale);
                }
            }
            if degree == 12 {
                self.degree_12();
            } else {
                self.degree_18();
            }
            for _ in 0..halvings {
                product(
                    &mut self.spare,
                    &self.result,
                    &self.result,
                    n,
                    Accum::Replace,
                );
                std::mem::swap(&mut self.spare, &mut self.result);
            }
        }
        all_finite(&self.result).then_some(())
    }

    /// T_1, T_2, T_4 or T_8 of `scaled`, unscaled (sizes up to theta_8).
    #[inline(always)]
    fn low_degree(&mut self, degree: usize) {
        let (n, a) = (self.n, self.scaled.as_slice());
        if degree >= 2 {
            product(&mut self.a2, a, a, n, Accum::Replace);
        }
        let a2 = self.a2.as_slice();
        match degree {
            1 => combine(&mut self.result, n, [(1.0, a)], 1.0),
            2 => combine(&mut self.result, n, [(1.0, a), (0.5, a2)], 1.0),
            4 => {
                // T_4 = I + A + A^2 (I / 2 + A / 6 + A^2 / 24).
                combine(&mut self.left, n, [(1.0 / 6.0, a), (1.0 / 24.0, a2)], 0.5);
                combine(&mut self.result, n, [(1.0, a)], 1.0);
                product(&mut self.result, a2, &self.left, n, Accum::Add);
            }
            _ => {
                // T_8 = I + A + y2 A^2 + (x3 A^2 + A4) (x4 I + x5 A + x6 A^2 + x7 A4) with
                // A4 = A^2 (x1 A + x2 A^2), the coefficients in closed form (Bader,
                // Blanes & Casas 2019).
                let r = 177f64.sqrt();
                let x3 = 2.0 / 3.0;
                let x1 = x3 * (1.0 + r) / 88.0;
                let x2 = x3 * (1.0 + r) / 352.0;
                let x4 = (-271.0 + 29.0 * r) / (315.0 * x3);
                let x5 = (-11.0 + 11.0 * r) / (1260.0 * x3);
                let x6 = (-99.0 + 11.0 * r) / (5040.0 * x3);
                let x7 = (89.0 - r) / (5040.0 * x3 * x3);
                let y2 = (857.0 - 58.0 * r) / 630.0;
                combine(&mut self.left, n, [(x1, a), (x2, a2)], 0.0);
                product(&mut self.a3, a2, &self.left, n, Accum::Replace);
                let a4 = self.a3.as_slice();
                combine(&mut self.left, n, [(x3, a2), (1.0, a4)], 0.0);
                combine(&mut self.right, n, [(x5, a), (x6, a2), (x7, a4)], x4);
                combine(&mut self.result, n, [(1.0, a), (y2, a2)], 1.0);
                product(&mut self.result, &self.left, &self.right, n, Accum::Add);
            }
        }
    }

    /// T_12 of `scaled` from its powers A^2, A^3.
    #[inline(always)]
    fn degree_12(&mut self) {
        let Exponential {
            n,
            scaled,
            a2,
            a3,
            a6,
            left,
            right,
            result,
            ..
        } = self;
        let (n, c) = (*n, &DEGREE_12);
        let terms =
            |i: usize| -> [(f64, &[f64]); 3] { [(c[i][1], scaled), (c[i][2], a2), (c[i][3], a3)] };
        combine(left, n, terms(3), c[3][0]);
        // A6 = B_2 + B_3^2.
        product(a6, left, left, n, Accum::Replace);
        add(a6, n, terms(2), c[2][0]);
        // T_12 = B_0 + (B_1 + A6) A6.
        let [b1, b2, b3] = terms(1);
        combine(right, n, [b1, b2, b3, (1.0, a6)], c[1][0]);
        combine(result, n, terms(0), c[0][0]);
        product(result, right, a6, n, Accum::Add);
    }

    /// T_18 of `scaled` from its powers A^2, A^3, A^6.
    #[inline(always)]
    fn degree_18(&mut self) {
        let Exponential {
            n,
            scaled,
            a2,
            a3,
            a6,
            left,
            right,
            a9,
            result,
            ..
        } = self;
        let (n, c) = (*n, &DEGREE_18);
        let terms = |i: usize| -> [(f64, &[f64]); 4] {
            [
                (c[i][1], scaled),
                (c[i][2], a2),
                (c[i][3], a3),
                (c[i][4], a6),
            ]
        };
        // A9 = B_0 B_4 + B_3.
        combine(left, n, terms(0), c[0][0]);
        combine(right, n, terms(4), c[4][0]);
        product(a9, left, right, n, Accum::Replace);
        add(a9, n, terms(3), c[3][0]);
        // T_18 = B_1 + (B_2 + A9) A9.
        let [b1, b2, b3, b6] = terms(2);
        combine(left, n, [b1, b2, b3, b6, (1.0, a9)], c[2][0]);
        combine(result, n, terms(1), c[1][0]);
        product(result, left, a9, n, Accum::Add);
    }
}

/// out = sum c_k X_k + identity I, elementwise over column-major n x n matrices, in one
/// pass: each element's sum is formed in a register and stored once.
#[inline(always)]
fn combine<const N: usize>(out: &mut [f64], n: usize, terms: [(f64, &[f64]); N], identity: f64) {
    sum_into(out, n, terms, identity, false);
}

/// out += sum c_k X_k + identity I, in one pass like [`combine`].
#[inline(always)]
fn add<const N: usize>(out: &mut [f64], n: usize, terms: [(f64, &[f64]); N], identity: f64) {
    sum_into(out, n, terms, identity, true);
}

#[inline(always)]
fn sum_into<const N: usize>(
    out: &mut [f64],
    n: usize,
    terms: [(f64, &[f64]); N],
    identity: f64,
    keep: bool,
) {
    let len = out.len();
    // Slices of the output's length, so the loop below has no bounds checks.
    let x: [&[f64]; N] = terms.map(|(_, x)| &x[..len]);
    let c: [f64; N] = terms.map(|(c, _)| c);
    for (i, o) in out.iter_mut().enumerate() {
        let mut s = if keep { *o } else { 0.0 };
        for k in 0..N {
            s += c[k] * x[k][i];
        }
        *o = s;
    }
    for i in 0..n {
        out[i * n + i] += identity;
    }
}

/// out = a b (or out + a b) of column-major n x n matrices, by faer's blocked kernels (the
/// state matrices of a Floquet problem are 16 to 80 wide, where they beat a loop of row
/// updates severalfold).
#[inline(always)]
fn product(out: &mut [f64], a: &[f64], b: &[f64], n: usize, accumulate: Accum) {
    matmul(
        MatMut::from_column_major_slice_mut(out, n, n),
        accumulate,
        MatRef::from_column_major_slice(a, n, n),
        MatRef::from_column_major_slice(b, n, n),
        1.0,
        Par::Seq,
    );
}

#[cfg(test)]
mod tests {
    use super::*;

    /// exp(a) of the n x n row-major matrix `a`, row-major, with the degree and halvings
    /// chosen; by the first-order form's products when `coupling` is given.
    fn exponential(a: &[f64], n: usize, coupling: Option<f64>) -> Option<(Vec<f64>, (usize, i32))> {
        exponential_with(&mut Exponential::new(n), a, n, coupling)
    }

    /// The same with the work buffers `work`.
    fn exponential_with(
        work: &mut Exponential,
        a: &[f64],
        n: usize,
        coupling: Option<f64>,
    ) -> Option<(Vec<f64>, (usize, i32))> {
        let column_major: Vec<f64> = (0..n * n).map(|k| a[(k % n) * n + k / n]).collect();
        let e = match coupling {
            Some(c) => work.of_state(&column_major, c)?,
            None => work.of(&column_major)?,
        };
        let e: Vec<f64> = (0..n * n).map(|k| e[(k / n, k % n)]).collect();
        Some((e, work.chosen))
    }

    #[test]
    fn the_degree_is_the_lowest_whose_theta_bounds_the_size() {
        for (size, degree, halvings) in [
            (0.0, 1, 0),
            (2.2e-16, 1, 0),
            (2.3e-16, 2, 0),
            (2.5e-8, 2, 0),
            (2.6e-8, 4, 0),
            (3.3e-4, 4, 0),
            (3.4e-4, 8, 0),
            (0.0499, 8, 0),
            (0.05, 12, 0),
            (0.299, 12, 0),
            (0.3, 18, 0),
            (1.09, 18, 0),
            (1.1, 18, 1),
            (2.18, 18, 1),
            (2.19, 18, 2),
        ] {
            assert_eq!(approximant(size), (degree, halvings), "size {size}");
        }
    }

    /// exp of the damped oscillator's state matrix [[0, 1], [-k, -c]] over t, in closed
    /// form: e^{-c t / 2} (cos(w_d t) I + sin(w_d t) / w_d (A + c / 2 I)), w_d^2 = k - c^2 / 4.
    fn oscillator(k: f64, c: f64, t: f64) -> [f64; 4] {
        let wd = (k - c * c / 4.0).sqrt();
        let (e, cs, sn) = ((-c * t / 2.0).exp(), (wd * t).cos(), (wd * t).sin() / wd);
        [
            e * (cs + sn * c / 2.0),
            e * sn,
            -e * sn * k,
            e * (cs - sn * c / 2.0),
        ]
    }

    #[test]
    fn exponential_of_an_oscillator_matches_the_closed_form_at_every_degree() {
        // On the state (s p, p') with s = sqrt(k) as the Floquet problem scales it, the
        // 1-norm is (s + c) t, and |A^2|^(1/2), |A^3|^(1/3), |A^6|^(1/6) are all about
        // w_d t: from 1.1e-16 (degree 1) through 1.1e-8, 2.2e-4, 0.033 (degrees 2, 4, 8),
        // 0.22 and 0.88 (12 and 18 unscaled) to 4 and 60 rad (2 and 6 halvings) and 1e4 turns
        // of a stiff, lightly damped mode (6e4 rad, 16 halvings). Each both ways: the general
        // products and the first-order form's (coupling s t).
        for (k, c, t, degree, halvings) in [
            (1.0, 0.1, 1e-16, 1, 0),
            (1.0, 0.1, 1e-8, 2, 0),
            (1.0, 0.1, 2e-4, 4, 0),
            (1.0, 0.1, 0.03, 8, 0),
            (1.0, 0.1, 0.2, 12, 0),
            (1.0, 0.1, 0.8, 18, 0),
            (1.0, 0.1, 4.0, 18, 2),
            (4.0, 0.02, 30.0, 18, 6),
            (1e8, 1e-3, 6.0, 18, 16),
        ] {
            let s = f64::sqrt(k);
            let a = [0.0, s * t, -k * t / s, -c * t];
            let e = oscillator(k, c, t);
            let exact = [e[0], s * e[1], e[2] / s, e[3]];
            for coupling in [None, Some(s * t)] {
                let (computed, chosen) = exponential(&a, 2, coupling).unwrap();
                assert_eq!(chosen, (degree, halvings), "k {k}, t {t}");
                // Unscaled, T_m is exp to the unit round-off (its backward error) and its
                // evaluation adds a few roundings of terms no larger than e^|A| (3 at the
                // size 1.09): 1e-14 for entries of about 1. Scaled, the angle w_d t = 6e4 rad
                // itself carries 1e-11 of round-off, which the squarings keep relative to
                // it; 1e-9 bounds both with room.
                let tolerance = if halvings == 0 { 1e-14 } else { 1e-9 };
                for (x, y) in computed.iter().zip(exact) {
                    assert!(
                        (x - y).abs() < tolerance,
                        "k {k}, t {t}, {coupling:?}: {computed:?} vs {exact:?}"
                    );
                }
            }
        }
    }

    #[test]
    fn exponential_of_a_triangular_matrix_is_exact_in_its_known_entries_at_every_degree() {
        // exp [[p, c], [0, q]] = [[e^p, c (e^p - e^q) / (p - q)], [0, e^q]], the divided
        // difference as e^q expm1(p - q) / (p - q) to keep it accurate when p is near q; the
        // sizes select each degree in turn (above theta_8 the powers' norms, a little below
        // the 1-norm max(|p|, |c| + |q|)).
        for (p, q, c, degree, halvings) in [
            (-1e-16, 0.5e-16, 1e-16, 1, 0),
            (-1e-8, 0.5e-8, 1e-8, 2, 0),
            (-2e-4, 1e-4, 1e-4, 4, 0),
            (-0.03, 0.01, 0.02, 8, 0),
            (-0.2, 0.1, 0.1, 12, 0),
            (-0.7, 0.4, 0.5, 18, 0),
            (-3.0, 1.0, 2.0, 18, 2),
            (-20.0, 3.0, 5.0, 18, 5),
        ] {
            let a = [p, c, 0.0, q];
            let (e, chosen) = exponential(&a, 2, None).unwrap();
            assert_eq!(chosen, (degree, halvings), "p {p}, q {q}");
            let divided = f64::exp(q) * f64::exp_m1(p - q) / (p - q);
            let expected = [p.exp(), c * divided, 0.0, q.exp()];
            let largest = expected.iter().fold(0.0, |m: f64, y| m.max(y.abs()));
            // Relative to the largest entry (the exponential is accurate in norm, not
            // entrywise): a few roundings in each of the 5 products and the sums, of terms
            // no larger than e^|A / 2^s| (3 at the size 1.09) against results of about
            // e^-|A / 2^s|, and by 2 at each squaring; the zero entry stays exact (sums
            // and products of upper triangular matrices).
            let tolerance = 32.0 * f64::EPSILON * 2f64.powi(halvings) * largest;
            for (x, y) in e.iter().zip(expected) {
                assert!(
                    (x - y).abs() <= tolerance,
                    "p {p}, q {q}: {e:?} vs {expected:?}"
                );
            }
        }
        // T_1(0) = I + 0, exactly.
        let (identity, chosen) = exponential(&[0.0; 9], 3, None).unwrap();
        assert_eq!(chosen, (1, 0));
        for (k, x) in identity.iter().enumerate() {
            assert_eq!(*x, if k % 4 == 0 { 1.0 } else { 0.0 }, "{identity:?}");
        }
        for bad in [f64::NAN, f64::INFINITY] {
            assert!(exponential(&[bad, 0.0, 0.0, 0.0], 2, None).is_none());
            assert!(exponential(&[0.0, 1.0, bad, 0.0], 2, Some(1.0)).is_none());
        }
    }

    #[test]
    fn the_first_order_form_gives_the_general_exponential() {
        // A 3-coordinate state matrix [[0, c I], [B, C]] (coupled, damped, non-normal) at
        // sizes that take degree 12 and degree 18 with and without halvings: A^2 and A^3
        // formed by blocks hold the same sums as the full products in another order, so
        // the exponentials agree to a few roundings relative to the largest entry (1e-14
        // unscaled, times 2 per squaring).
        let b = [[-4.0, 1.0, 0.3], [0.5, -2.0, 0.7], [0.2, 0.9, -6.0]];
        let d = [[-0.3, 0.1, 0.0], [0.2, -0.1, 0.4], [0.0, 0.3, -0.8]];
        for t in [0.05, 0.2, 1.0, 8.0] {
            let coupling = 2.0 * t;
            let a: Vec<f64> = (0..36)
                .map(|k| {
                    let (i, j) = (k / 6, k % 6);
                    match (i < 3, j < 3) {
                        (true, true) => 0.0,
                        (true, false) => f64::from(u8::from(j - 3 == i)) * coupling,
                        (false, true) => b[i - 3][j] * t / 2.0,
                        (false, false) => d[i - 3][j - 3] * t,
                    }
                })
                .collect();
            let (general, chosen) = exponential(&a, 6, None).unwrap();
            let (blocks, chosen_blocks) = exponential(&a, 6, Some(coupling)).unwrap();
            assert_eq!(chosen, chosen_blocks, "t {t}");
            assert!(chosen.0 >= 12, "t {t}: {chosen:?}");
            let largest = general.iter().fold(0.0, |m: f64, y| m.max(y.abs()));
            let tolerance = 1e-14 * 2f64.powi(chosen.1) * largest;
            for (x, y) in blocks.iter().zip(&general) {
                assert!(
                    (x - y).abs() <= tolerance,
                    "t {t}: {blocks:?} vs {general:?}"
                );
            }
        }
    }

    #[test]
    fn work_buffers_reused_give_the_same_exponential() {
        // One workspace for a sequence of matrices of every degree, a matrix that is not
        // finite among them, must give each the exponential a fresh workspace gives.
        let matrices = [
            [-3.0, 1.0, 2.0, 0.5],
            [f64::NAN, 0.0, 0.0, 0.0],
            [0.001, 0.002, -0.003, 0.004],
            [1e-9, 0.0, 0.0, -1e-9],
            [-20.0, 5.0, 0.0, 3.0],
            [0.03, -0.02, 0.01, 0.04],
            [0.3, -0.2, 0.1, 0.4],
        ];
        let mut work = Exponential::new(2);
        for a in &matrices {
            let reused = exponential_with(&mut work, a, 2, None);
            assert_eq!(reused, exponential(a, 2, None), "{a:?}");
        }
    }
}
