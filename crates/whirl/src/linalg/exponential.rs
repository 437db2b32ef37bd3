//! The exponential of a small dense matrix, for the monodromy matrix of harmonic balance's
//! stability: scaling and squaring of the degree-13 Padé approximant (Higham, "The scaling
//! and squaring method for the matrix exponential revisited", SIAM J. Matrix Anal. Appl. 26,
//! 2005, with the degree fixed at 13). A is halved s times until |A / 2^s|_1 <= theta_13,
//! where the approximant r_13 = q(A)^-1 p(A) equals exp to double precision, and the result
//! is squared s times.

use faer::linalg::matmul::matmul;
use faer::linalg::solvers::Solve;
use faer::{Accum, Mat, MatMut, MatRef, Par};

use super::vectorised;

/// The largest 1-norm for which r_13 matches exp to the unit round-off (Higham 2005,
/// table 2.3).
const THETA_13: f64 = 5.371920351148152;

/// Coefficients b_0 .. b_13 of the degree-13 Padé numerator p(x) = sum b_k x^k; the
/// denominator is p(-x).
const PADE_13: [f64; 14] = [
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
];

/// exp(a) of the n x n row-major matrix `a`; `None` when `a` is not finite (the Padé
/// denominator, regular for every finite scaled argument, then is not).
pub(crate) fn exponential(a: &[f64], n: usize) -> Option<Vec<f64>> {
    vectorised(|| pade_scaled(a, n))
}

#[inline(always)]
fn pade_scaled(a: &[f64], n: usize) -> Option<Vec<f64>> {
    let norm = (0..n)
        .map(|j| (0..n).map(|i| a[i * n + j].abs()).sum::<f64>())
        .fold(0.0, f64::max);
    if !norm.is_finite() {
        return None;
    }
    // s halvings bring the norm to theta_13 or below; exact powers of two, so the scaling
    // itself rounds nothing.
    let halvings = if norm > THETA_13 {
        (norm / THETA_13).log2().ceil() as i32
    } else {
        0
    };
    let scale = 2f64.powi(-halvings);
    let a: Vec<f64> = a.iter().map(|v| v * scale).collect();
    let b = &PADE_13;
    let a2 = product(&a, &a, n);
    let a4 = product(&a2, &a2, n);
    let a6 = product(&a4, &a2, n);
    let identity = |k: usize| if k.is_multiple_of(n + 1) { 1.0 } else { 0.0 };
    // Odd part U = A (A6 (b13 A6 + b11 A4 + b9 A2) + b7 A6 + b5 A4 + b3 A2 + b1 I) and even
    // part V = A6 (b12 A6 + b10 A4 + b8 A2) + b6 A6 + b4 A4 + b2 A2 + b0 I: p = V + U,
    // q = V - U.
    let combine =
        |c: [f64; 4], k: usize| c[0] * a6[k] + c[1] * a4[k] + c[2] * a2[k] + c[3] * identity(k);
    let inner_odd: Vec<f64> = (0..n * n)
        .map(|k| combine([b[13], b[11], b[9], 0.0], k))
        .collect();
    let inner_even: Vec<f64> = (0..n * n)
        .map(|k| combine([b[12], b[10], b[8], 0.0], k))
        .collect();
    let mut odd = product(&a6, &inner_odd, n);
    let mut even = product(&a6, &inner_even, n);
    for k in 0..n * n {
        odd[k] += combine([b[7], b[5], b[3], b[1]], k);
        even[k] += combine([b[6], b[4], b[2], b[0]], k);
    }
    let odd = product(&a, &odd, n);
    // q(A) = V - U is well conditioned for |A| <= theta_13 (Higham 2005), so partial
    // pivoting suffices; a singular one (a matrix that is not finite) gives a result that is
    // not finite, refused below.
    let denominator = Mat::from_fn(n, n, |i, j| even[i * n + j] - odd[i * n + j]).partial_piv_lu();
    let mut numerator = Mat::from_fn(n, n, |i, j| even[i * n + j] + odd[i * n + j]);
    denominator.solve_in_place(numerator.as_mut());
    let mut result: Vec<f64> = (0..n * n).map(|k| numerator[(k / n, k % n)]).collect();
    for _ in 0..halvings {
        result = product(&result, &result, n);
    }
    result.iter().all(|v| v.is_finite()).then_some(result)
}

/// a b of two n x n row-major matrices, by faer's blocked kernels (the state matrices of a
/// Floquet problem are 16 to 80 wide, where they beat a loop of row updates severalfold).
pub(crate) fn product(a: &[f64], b: &[f64], n: usize) -> Vec<f64> {
    let mut out = vec![0.0; n * n];
    matmul(
        MatMut::from_row_major_slice_mut(&mut out, n, n),
        Accum::Replace,
        MatRef::from_row_major_slice(a, n, n),
        MatRef::from_row_major_slice(b, n, n),
        1.0,
        Par::Seq,
    );
    out
}

#[cfg(test)]
mod tests {
    use super::*;

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
    fn exponential_of_an_oscillator_matches_the_closed_form_small_and_stiff() {
        // From a quarter turn (no scaling) to 1e4 turns of a stiff, lightly damped mode, on
        // the state (s p, p') with s = sqrt(k) as the Floquet problem scales it: its norm
        // 6e4 takes 14 halvings (unscaled, the norm k t = 6e8 took 27 and lost 1e-6 to
        // the non-normal squarings).
        for (k, c, t) in [(1.0, 0.1, 1.5), (4.0, 0.02, 30.0), (1e8, 1e-3, 6.0)] {
            let s = f64::sqrt(k);
            let a = [0.0, s * t, -k * t / s, -c * t];
            let e = oscillator(k, c, t);
            let exact = [e[0], s * e[1], e[2] / s, e[3]];
            let computed = exponential(&a, 2).unwrap();
            for (x, y) in computed.iter().zip(exact) {
                // The angle w_d t = 6e4 rad itself carries 1e-11 of round-off, which the
                // squarings keep relative to it; 1e-9 bounds both with room.
                assert!(
                    (x - y).abs() < 1e-9,
                    "k {k}, t {t}: {computed:?} vs {exact:?}"
                );
            }
        }
    }

    #[test]
    fn exponential_of_a_triangular_matrix_is_exact_in_its_known_entries() {
        // exp [[a, 1], [0, b]] = [[e^a, (e^a - e^b) / (a - b)], [0, e^b]], and the identity
        // for the zero matrix.
        let (p, q) = (-0.7, 0.4);
        let e = exponential(&[p, 1.0, 0.0, q], 2).unwrap();
        let expected = [p.exp(), (p.exp() - q.exp()) / (p - q), 0.0, q.exp()];
        for (x, y) in e.iter().zip(expected) {
            assert!((x - y).abs() < 1e-15, "{e:?} vs {expected:?}");
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
}
