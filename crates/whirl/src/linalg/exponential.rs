//! The exponential of a small dense matrix, for the monodromy matrix of harmonic balance's
//! stability: scaling and squaring of diagonal Padé approximants with the degree chosen by
//! the norm (Higham, "The scaling and squaring method for the matrix exponential
//! revisited", SIAM J. Matrix Anal. Appl. 26, 2005, algorithm 2.3). The approximant
//! r_m = q_m(A)^-1 p_m(A) of the lowest degree m in 3, 5, 7, 9 whose theta_m bounds |A|_1 is
//! exp(A) to the unit round-off in exact arithmetic; above theta_9, A is halved s times
//! until |A / 2^s|_1 <= theta_13, and r_13 is squared s times. The work buffers live in
//! [`Exponential`], so the 160 to 320 exponentials of one monodromy matrix allocate nothing.

use faer::dyn_stack::{MemBuffer, MemStack, StackReq};
use faer::linalg::lu::partial_pivoting::{factor, solve};
use faer::linalg::matmul::matmul;
use faer::{Accum, MatMut, MatRef, Par};

use super::vectorised;

/// The largest 1-norm for which r_13 matches exp to the unit round-off (Higham 2005,
/// table 2.3).
const THETA_13: f64 = 5.371920351148152;

/// The approximants of degree 3, 5, 7, 9 and 13: theta_m, the largest 1-norm for which r_m
/// matches exp to the unit round-off (Higham 2005, table 2.3), and the coefficients
/// b_0 .. b_m of the numerator p_m(x) = sum b_k x^k; the denominator is q_m(x) = p_m(-x).
const APPROXIMANTS: [(f64, &[f64]); 5] = [
    (1.495585217958292e-2, &[120.0, 60.0, 12.0, 1.0]),
    (
        2.53939833006323e-1,
        &[30240.0, 15120.0, 3360.0, 420.0, 30.0, 1.0],
    ),
    (
        9.504178996162932e-1,
        &[
            17297280.0, 8648640.0, 1995840.0, 277200.0, 25200.0, 1512.0, 56.0, 1.0,
        ],
    ),
    (
        2.097847961257068,
        &[
            17643225600.0,
            8821612800.0,
            2075673600.0,
            302702400.0,
            30270240.0,
            2162160.0,
            110880.0,
            3960.0,
            90.0,
            1.0,
        ],
    ),
    (
        THETA_13,
        &[
            64764752532480000.0,
            32382376266240000.0,
            7771770303897600.0,
            1187353796428800.0,
            129060195264000.0,
            10559470521600.0,
            670442572800.0,
            33522128640.0,
            1323241920.0,
            40840800.0,
            960960.0,
            16380.0,
            182.0,
            1.0,
        ],
    ),
];

/// The Padé coefficients b_0 .. b_m for |A|_1 = `norm`, and the halvings s that bring the
/// norm to theta_13 when it is above theta_9 (Higham 2005, algorithm 2.3).
fn approximant(norm: f64) -> (&'static [f64], i32) {
    let (theta, coefficients) = APPROXIMANTS
        .iter()
        .find(|(theta, _)| norm <= *theta)
        .copied()
        .unwrap_or(APPROXIMANTS[APPROXIMANTS.len() - 1]);
    let halvings = if norm > theta {
        (norm / theta).log2().ceil() as i32
    } else {
        0
    };
    (coefficients, halvings)
}

/// The exponential of n x n matrices with its work buffers, all column-major n x n: made
/// once per monodromy matrix, reused for every step.
pub(crate) struct Exponential {
    n: usize,
    /// A / 2^s.
    scaled: Vec<f64>,
    /// A^2, A^4, A^6, A^8 of the scaled matrix, as many as the degree needs.
    powers: [Vec<f64>; 4],
    /// The inner sums of degree 13's odd and even parts.
    inner: Vec<f64>,
    /// The odd part's sum over even powers, then U = A times it.
    odd: Vec<f64>,
    /// The even part V.
    even: Vec<f64>,
    /// q(A) = V - U, factored in place.
    denominator: Vec<f64>,
    /// p(A) = V + U, solved in place into r(A), and squared s times with `spare`.
    result: Vec<f64>,
    spare: Vec<f64>,
    permutation: Vec<usize>,
    inverse_permutation: Vec<usize>,
    stack: MemBuffer,
}

impl Exponential {
    pub(crate) fn new(n: usize) -> Exponential {
        let square = || vec![0.0; n * n];
        let scratch = StackReq::any_of(&[
            factor::lu_in_place_scratch::<usize, f64>(n, n, Par::Seq, Default::default()),
            solve::solve_in_place_scratch::<usize, f64>(n, n, Par::Seq),
        ]);
        Exponential {
            n,
            scaled: square(),
            powers: [square(), square(), square(), square()],
            inner: square(),
            odd: square(),
            even: square(),
            denominator: square(),
            result: square(),
            spare: square(),
            permutation: vec![0; n],
            inverse_permutation: vec![0; n],
            stack: MemBuffer::new(scratch),
        }
    }

    /// exp(a) of the column-major n x n matrix `a`, a view into the work buffers valid until
    /// the next call; `None` when `a` is not finite (the Padé denominator, regular for every
    /// finite scaled argument, then is not).
    pub(crate) fn of(&mut self, a: &[f64]) -> Option<MatRef<'_, f64>> {
        vectorised(|| self.pade_scaled(a))?;
        Some(MatRef::from_column_major_slice(
            &self.result,
            self.n,
            self.n,
        ))
    }

    #[inline(always)]
    fn pade_scaled(&mut self, a: &[f64]) -> Option<()> {
        let n = self.n;
        debug_assert_eq!(a.len(), n * n);
        // Column sums along contiguous memory: the norm and the scaled copy below vectorise.
        let norm = a
            .chunks_exact(n)
            .map(|column| column.iter().map(|v| v.abs()).sum::<f64>())
            .fold(0.0, f64::max);
        if !norm.is_finite() {
            return None;
        }
        let (b, halvings) = approximant(norm);
        // Exact powers of two, so the scaling itself rounds nothing.
        let scale = 2f64.powi(-halvings);
        for (s, v) in self.scaled.iter_mut().zip(a) {
            *s = v * scale;
        }
        let degree = b.len() - 1;
        // The even powers up to A^(m - 1), A^6 at most for degree 13.
        let powers = (degree / 2).min(3);
        let [a2, a4, a6, a8] = &mut self.powers;
        product(a2, &self.scaled, &self.scaled, n, Accum::Replace);
        if powers >= 2 {
            product(a4, &a2[..], &a2[..], n, Accum::Replace);
        }
        if powers >= 3 {
            product(a6, &a4[..], &a2[..], n, Accum::Replace);
        }
        if degree == 9 {
            product(a8, &a6[..], &a2[..], n, Accum::Replace);
        }
        let (a2, a4, a6, a8) = (a2.as_slice(), a4.as_slice(), a6.as_slice(), a8.as_slice());
        if degree == 13 {
            // U = A (A6 (b13 A6 + b11 A4 + b9 A2) + b7 A6 + b5 A4 + b3 A2 + b1 I) and
            // V = A6 (b12 A6 + b10 A4 + b8 A2) + b6 A6 + b4 A4 + b2 A2 + b0 I.
            // The odd part's sum takes b_(k + 1) where the even part takes b_k.
            for (first, part) in [(1, &mut self.odd), (0, &mut self.even)] {
                let c = |k: usize| b[k + first];
                combine(
                    &mut self.inner,
                    n,
                    &[(c(12), a6), (c(10), a4), (c(8), a2)],
                    0.0,
                );
                combine(part, n, &[(c(6), a6), (c(4), a4), (c(2), a2)], c(0));
                product(part, a6, &self.inner, n, Accum::Add);
            }
        } else {
            // U = A sum b_(2k+1) A^2k and V = sum b_2k A^2k, k = 0 .. (m - 1) / 2.
            let even_powers = [a2, a4, a6, a8];
            let terms = |first: usize| -> [(f64, &[f64]); 4] {
                std::array::from_fn(|k| {
                    let coefficient = b.get(2 * k + 2 + first).copied().unwrap_or(0.0);
                    (coefficient, even_powers[k])
                })
            };
            let used = degree / 2;
            combine(&mut self.odd, n, &terms(1)[..used], b[1]);
            combine(&mut self.even, n, &terms(0)[..used], b[0]);
        }
        product(&mut self.inner, &self.scaled, &self.odd, n, Accum::Replace);
        // p = V + U, q = V - U.
        for ((p, q), (&v, &u)) in self
            .result
            .iter_mut()
            .zip(self.denominator.iter_mut())
            .zip(self.even.iter().zip(&self.inner))
        {
            (*p, *q) = (v + u, v - u);
        }
        // q(A) is well conditioned for |A| <= theta_m (Higham 2005), so partial pivoting
        // suffices; a singular one (a matrix that is not finite) gives a result that is not
        // finite, refused below.
        let stack = MemStack::new(&mut self.stack);
        let mut lu = MatMut::from_column_major_slice_mut(&mut self.denominator, n, n);
        let (_, permutation) = factor::lu_in_place(
            lu.as_mut(),
            &mut self.permutation,
            &mut self.inverse_permutation,
            Par::Seq,
            stack,
            Default::default(),
        );
        let lu = lu.as_ref();
        solve::solve_in_place(
            lu,
            lu,
            permutation,
            MatMut::from_column_major_slice_mut(&mut self.result, n, n),
            Par::Seq,
            stack,
        );
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
        self.result.iter().all(|v| v.is_finite()).then_some(())
    }
}

/// out = sum c_k X_k + identity I, elementwise over column-major n x n matrices.
#[inline(always)]
fn combine(out: &mut [f64], n: usize, terms: &[(f64, &[f64])], identity: f64) {
    // The first term is assigned, not added to a cleared buffer (clearing was 2.6 % of a
    // sweep's samples, in memset).
    let [(c, x), rest @ ..] = terms else {
        out.fill(0.0);
        return;
    };
    for (o, v) in out.iter_mut().zip(*x) {
        *o = c * v;
    }
    for &(c, x) in rest {
        for (o, v) in out.iter_mut().zip(x) {
            *o += c * v;
        }
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

    /// exp(a) of the n x n row-major matrix `a`, row-major.
    fn exponential(a: &[f64], n: usize) -> Option<Vec<f64>> {
        exponential_with(&mut Exponential::new(n), a, n)
    }

    /// The same with the work buffers `work`.
    fn exponential_with(work: &mut Exponential, a: &[f64], n: usize) -> Option<Vec<f64>> {
        let column_major: Vec<f64> = (0..n * n).map(|k| a[(k % n) * n + k / n]).collect();
        let e = work.of(&column_major)?;
        Some((0..n * n).map(|k| e[(k / n, k % n)]).collect())
    }

    /// The degree and halvings chosen for the 1-norm of the row-major 2 x 2 matrix `a`.
    fn chosen(a: &[f64; 4]) -> (usize, i32) {
        let norm = f64::max(a[0].abs() + a[2].abs(), a[1].abs() + a[3].abs());
        let (b, halvings) = approximant(norm);
        (b.len() - 1, halvings)
    }

    #[test]
    fn the_degree_is_the_lowest_whose_theta_bounds_the_norm() {
        for (norm, degree, halvings) in [
            (0.0, 3, 0),
            (0.0149, 3, 0),
            (0.015, 5, 0),
            (0.25, 5, 0),
            (0.26, 7, 0),
            (0.95, 7, 0),
            (0.96, 9, 0),
            (2.09, 9, 0),
            (2.1, 13, 0),
            (5.37, 13, 0),
            (5.38, 13, 1),
            (10.7, 13, 1),
            (10.8, 13, 2),
        ] {
            let (b, s) = approximant(norm);
            assert_eq!((b.len() - 1, s), (degree, halvings), "norm {norm}");
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
        // On the state (s p, p') with s = sqrt(k) as the Floquet problem scales it, the norm
        // is (s + c) t: from 0.011 (degree 3) through 0.22, 0.88, 1.65 (degrees 5, 7, 9) and
        // 4.4 (13 unscaled) to 1e4 turns of a stiff, lightly damped mode (norm 6e4, 14
        // halvings; unscaled, the norm k t = 6e8 took 27 and lost 1e-6 to the non-normal
        // squarings).
        for (k, c, t, degree, halvings) in [
            (1.0, 0.1, 0.01, 3, 0),
            (1.0, 0.1, 0.2, 5, 0),
            (1.0, 0.1, 0.8, 7, 0),
            (1.0, 0.1, 1.5, 9, 0),
            (1.0, 0.1, 4.0, 13, 0),
            (4.0, 0.02, 30.0, 13, 4),
            (1e8, 1e-3, 6.0, 13, 14),
        ] {
            let s = f64::sqrt(k);
            let a = [0.0, s * t, -k * t / s, -c * t];
            assert_eq!(chosen(&a), (degree, halvings), "k {k}, t {t}");
            let e = oscillator(k, c, t);
            let exact = [e[0], s * e[1], e[2] / s, e[3]];
            let computed = exponential(&a, 2).unwrap();
            // Unscaled, r_m is exp to the unit round-off and its evaluation adds a few
            // roundings, magnified by the cancellation between the even and odd parts in p
            // or q (up to about e^(|A| / 2), 9 at the norm 4.4): 1e-14 for entries of about
            // 1. Scaled, the angle w_d t = 6e4 rad itself carries 1e-11 of round-off, which
            // the squarings keep relative to it; 1e-9 bounds both with room.
            let tolerance = if halvings == 0 { 1e-14 } else { 1e-9 };
            for (x, y) in computed.iter().zip(exact) {
                assert!(
                    (x - y).abs() < tolerance,
                    "k {k}, t {t}: {computed:?} vs {exact:?}"
                );
            }
        }
    }

    #[test]
    fn exponential_of_a_triangular_matrix_is_exact_in_its_known_entries_at_every_degree() {
        // exp [[p, c], [0, q]] = [[e^p, c (e^p - e^q) / (p - q)], [0, e^q]], the divided
        // difference as e^q expm1(p - q) / (p - q) to keep it accurate when p is near q; the
        // norm max(|p|, |c| + |q|) selects each degree in turn.
        for (p, q, c, degree, halvings) in [
            (-0.007, 0.004, 0.01, 3, 0),
            (-0.1, 0.05, 0.2, 5, 0),
            (-0.5, 0.3, 0.6, 7, 0),
            (-0.7, 0.4, 1.0, 9, 0),
            (-3.0, 1.0, 2.0, 13, 0),
            (-20.0, 3.0, 5.0, 13, 2),
        ] {
            let a = [p, c, 0.0, q];
            assert_eq!(chosen(&a), (degree, halvings), "p {p}, q {q}");
            let e = exponential(&a, 2).unwrap();
            let divided = f64::exp(q) * f64::exp_m1(p - q) / (p - q);
            let expected = [p.exp(), c * divided, 0.0, q.exp()];
            let largest = expected.iter().fold(0.0, |m: f64, y| m.max(y.abs()));
            // Relative to the largest entry (the exponential is accurate in norm, not
            // entrywise): a few roundings of the evaluation and the solve, magnified by the
            // cancellation between the even and odd parts of p or q (up to e^(|A| / 2^s / 2),
            // 4.5 at the norm 3), and by 2 at each squaring; the zero entry stays exact
            // (products and solves of upper triangular matrices).
            let tolerance = 32.0 * f64::EPSILON * 2f64.powi(halvings) * largest;
            for (x, y) in e.iter().zip(expected) {
                assert!(
                    (x - y).abs() <= tolerance,
                    "p {p}, q {q}: {e:?} vs {expected:?}"
                );
            }
        }
        // q(0)^-1 p(0) = b0 / b0 per diagonal entry: the LU solve multiplies by the pivot's
        // reciprocal, one rounding.
        let identity = exponential(&[0.0; 9], 3).unwrap();
        for (k, x) in identity.iter().enumerate() {
            let expected = if k % 4 == 0 { 1.0 } else { 0.0 };
            assert!((x - expected).abs() <= f64::EPSILON, "{identity:?}");
        }
        assert!(exponential(&[f64::NAN, 0.0, 0.0, 0.0], 2).is_none());
    }

    #[test]
    fn work_buffers_reused_give_the_same_exponential() {
        // One workspace for a sequence of matrices of every degree, a matrix that is not
        // finite among them, must give each the exponential a fresh workspace gives.
        let matrices = [
            [-3.0, 1.0, 2.0, 0.5],
            [f64::NAN, 0.0, 0.0, 0.0],
            [0.001, 0.002, -0.003, 0.004],
            [-20.0, 5.0, 0.0, 3.0],
            [0.3, -0.2, 0.1, 0.4],
        ];
        let mut work = Exponential::new(2);
        for a in &matrices {
            let reused = exponential_with(&mut work, a, 2);
            assert_eq!(reused, exponential(a, 2), "{a:?}");
        }
    }
}
