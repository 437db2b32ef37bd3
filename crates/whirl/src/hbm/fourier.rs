//! The truncated Fourier basis (thesis eq. 4.13) and the alternating frequency-time (AFT)
//! transforms between Fourier coefficients and time samples (thesis eqs. 4.21-4.22).
//!
//! A coordinate over one period, in phase theta = w t, is
//!
//! ```text
//! q(theta) = a_0 + sum_{r=1..H} a_r cos(r theta) + b_r sin(r theta)
//! ```
//!
//! stored in 2H + 1 "slots": slot 0 is a_0, slot 2r - 1 is a_r and slot 2r is b_r. Samples
//! are taken at theta_j = 2 pi j / N. With the DFT X_m = sum_j x_j e^{-i m theta_j} the
//! coefficients are a_0 = X_0 / N, a_r = 2 Re X_r / N, b_r = -2 Im X_r / N.
//!
//! The Jacobian of the sampled force's coefficients with respect to the coordinate's
//! coefficients is the Galerkin matrix (P_row / N) sum_j J(theta_j) B_row(theta_j)
//! B_col(theta_j) of the sampled tangent J, with B the basis functions and P = 1 for the
//! constant and 2 otherwise. Products of two basis functions are sums of harmonics r + s and
//! r - s, so the matrix comes from the DFT of J alone (taken at indices modulo N): it is the
//! exact derivative of the sampled residual, aliasing included, at the cost of one FFT.

use std::sync::Arc;

use num_complex::Complex;
use realfft::{ComplexToReal, RealFftPlanner, RealToComplex};

use crate::error::{InputError, Result};

/// Slot of the cosine coefficient of harmonic r >= 1.
pub(crate) fn cos_slot(r: usize) -> usize {
    2 * r - 1
}

/// Slot of the sine coefficient of harmonic r >= 1.
pub(crate) fn sin_slot(r: usize) -> usize {
    2 * r
}

/// Harmonic of a slot and whether it holds a sine coefficient.
pub(crate) fn slot_basis(slot: usize) -> (usize, bool) {
    (slot.div_ceil(2), slot > 0 && slot.is_multiple_of(2))
}

/// The smallest power of two N that keeps harmonics 0..=H free of aliasing when the force is
/// a polynomial of degree `degree` in the coordinates: its highest harmonic, degree * H,
/// folds onto N - degree * H, which must lie above H, so N >= (degree + 1) H + 1. A power
/// of two keeps the FFT at its fastest.
pub fn aliasing_free_samples(harmonics: usize, degree: usize) -> usize {
    ((degree.max(1) + 1) * harmonics + 1).next_power_of_two()
}

/// The most harmonics H: Newton's dense Jacobian has (2H + 1) times the bearing
/// coordinates as its side and its solves cost the cube of that, about 800 times H = 5's
/// at 50 (the thesis used up to 5).
pub const MAX_HARMONICS: usize = 50;

/// The most time samples per period N: 40 times the default (32 H) at [`MAX_HARMONICS`];
/// every Newton step transforms each of them, and the default already resolves the contacts.
pub const MAX_SAMPLES: usize = 65_536;

/// Checks H harmonics on N samples per period before anything is planned or allocated for
/// them: H from 1 to [`MAX_HARMONICS`], N above 2H (harmonic H below the Nyquist frequency)
/// and at most [`MAX_SAMPLES`].
///
/// # Errors
/// [`crate::Error::Input`] naming `harmonics` or `samples` otherwise.
pub fn check_counts(harmonics: usize, samples: usize) -> Result<()> {
    let default = "leave it out for the default (32 H, at least 64)";
    if !(1..=MAX_HARMONICS).contains(&harmonics) {
        return Err(InputError::field(
            "harmonics",
            format!(
                "{harmonics}: harmonic balance takes from 1 to {MAX_HARMONICS} harmonics (the \
                 stability matrix grows with 2H + 1 and its cost with the cube of that)"
            ),
        )
        .help("e.g. 5")
        .into());
    }
    if samples <= 2 * harmonics {
        return Err(InputError::field(
            "samples",
            format!(
                "harmonic balance with {harmonics} harmonics needs more than 2 H = {} time \
                 samples per period, got {samples}",
                2 * harmonics
            ),
        )
        .help(default)
        .into());
    }
    if samples > MAX_SAMPLES {
        return Err(InputError::field(
            "samples",
            format!(
                "{samples} time samples per period: at most {MAX_SAMPLES} (every Newton step \
                 transforms each of them; the default 32 H already resolves the contacts)"
            ),
        )
        .help(default)
        .into());
    }
    Ok(())
}

/// Real FFTs planned once for one number of harmonics and samples, with their buffers, so an
/// AFT evaluation allocates nothing.
pub(crate) struct Aft {
    harmonics: usize,
    samples: usize,
    forward: Arc<dyn RealToComplex<f64>>,
    inverse: Arc<dyn ComplexToReal<f64>>,
    time: Vec<f64>,
    spectrum: Vec<Complex<f64>>,
    scratch: Vec<Complex<f64>>,
}

impl Aft {
    /// Plans transforms for H harmonics on N samples; N must exceed 2H so that harmonic H
    /// lies below the Nyquist frequency.
    ///
    /// # Errors
    /// Those of [`check_counts`].
    pub fn new(harmonics: usize, samples: usize) -> Result<Aft> {
        check_counts(harmonics, samples)?;
        let mut planner = RealFftPlanner::<f64>::new();
        let forward = planner.plan_fft_forward(samples);
        let inverse = planner.plan_fft_inverse(samples);
        let scratch_len = forward.get_scratch_len().max(inverse.get_scratch_len());
        Ok(Aft {
            harmonics,
            samples,
            time: forward.make_input_vec(),
            spectrum: forward.make_output_vec(),
            scratch: vec![Complex::default(); scratch_len],
            forward,
            inverse,
        })
    }

    /// Number of time samples per period.
    pub fn samples(&self) -> usize {
        self.samples
    }

    /// Samples over one period of the series whose slot s holds `coefficient(s)`.
    pub fn synthesise(&mut self, coefficient: impl Fn(usize) -> f64, out: &mut [f64]) {
        // The unnormalised inverse DFT of X_0 = a_0, X_r = (a_r - i b_r) / 2 is the series.
        self.spectrum.fill(Complex::default());
        self.spectrum[0] = Complex::new(coefficient(0), 0.0);
        for r in 1..=self.harmonics {
            self.spectrum[r] =
                Complex::new(coefficient(cos_slot(r)), -coefficient(sin_slot(r))) * 0.5;
        }
        self.inverse
            .process_with_scratch(&mut self.spectrum, out, &mut self.scratch)
            .expect("buffer sizes fixed at planning and a real-valued DC and Nyquist bin");
    }

    /// The 2H + 1 Fourier coefficients of one period of samples.
    pub fn analyse(&mut self, samples: &[f64], out: &mut [f64]) {
        self.transform(samples);
        let n = self.samples as f64;
        out[0] = self.spectrum[0].re / n;
        for r in 1..=self.harmonics {
            out[cos_slot(r)] = 2.0 * self.spectrum[r].re / n;
            out[sin_slot(r)] = -2.0 * self.spectrum[r].im / n;
        }
    }

    /// The Galerkin matrix of the sampled tangent `samples`, row-major over slots:
    /// entry (row, col) = (P_row / N) sum_j J_j B_row(theta_j) B_col(theta_j).
    pub fn galerkin(&mut self, samples: &[f64], out: &mut [f64]) {
        self.transform(samples);
        let slots = 2 * self.harmonics + 1;
        let n = self.samples as f64;
        for row in 0..slots {
            let (r, row_sin) = slot_basis(row);
            let weight = if row == 0 { 1.0 } else { 2.0 } / n;
            for col in 0..slots {
                let (s, col_sin) = slot_basis(col);
                let (r, s) = (r as i64, s as i64);
                let (diff, sum) = (self.dft(r - s), self.dft(r + s));
                let value = match (row_sin, col_sin) {
                    (false, false) => 0.5 * (diff.re + sum.re),
                    // cos(r) sin(s) = [sin((s + r)) + sin((s - r))] / 2, and
                    // sum_j J_j sin(m theta_j) = -Im X_m; X_{-m} = conj(X_m).
                    (false, true) => -0.5 * (sum.im - diff.im),
                    (true, false) => -0.5 * (sum.im + diff.im),
                    (true, true) => 0.5 * (diff.re - sum.re),
                };
                out[row * slots + col] = weight * value;
            }
        }
    }

    /// Forward DFT of `samples` into `self.spectrum` (bins 0..=N/2).
    fn transform(&mut self, samples: &[f64]) {
        self.time.copy_from_slice(samples);
        self.forward
            .process_with_scratch(&mut self.time, &mut self.spectrum, &mut self.scratch)
            .expect("buffer sizes fixed at planning");
    }

    /// DFT bin m of the last transform, for any integer m: bins repeat with period N and
    /// those above N/2 are conjugates of bins below, as the samples are real.
    fn dft(&self, m: i64) -> Complex<f64> {
        let n = self.samples as i64;
        let m = m.rem_euclid(n) as usize;
        if m <= self.samples / 2 {
            self.spectrum[m]
        } else {
            self.spectrum[self.samples - m].conj()
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counts_past_their_limits_are_refused_before_a_plan_is_made() {
        // usize::MAX samples could not be planned at all: refused, not aborted.
        for (h, n, field) in [
            (5, MAX_SAMPLES + 1, "`samples`"),
            (5, usize::MAX, "`samples`"),
            (5, 10, "`samples`"),
            (0, 64, "`harmonics`"),
            (MAX_HARMONICS + 1, MAX_SAMPLES, "`harmonics`"),
        ] {
            let e = Aft::new(h, n).err().map(|e| e.to_string());
            assert!(
                e.as_deref().is_some_and(|e| e.contains(field)),
                "{h} {n}: {e:?}"
            );
        }
        assert!(Aft::new(MAX_HARMONICS, MAX_SAMPLES).is_ok());
    }
    use std::f64::consts::PI;

    /// Basis function of a slot at phase theta.
    fn basis(slot: usize, theta: f64) -> f64 {
        match slot_basis(slot) {
            (0, _) => 1.0,
            (r, false) => (r as f64 * theta).cos(),
            (r, true) => (r as f64 * theta).sin(),
        }
    }

    #[test]
    fn synthesis_and_analysis_invert_each_other() {
        let (h, n) = (4, 16);
        let mut aft = Aft::new(h, n).unwrap();
        let coefficients: Vec<f64> = (0..2 * h + 1).map(|s| (s as f64 * 0.7).sin()).collect();
        let mut samples = vec![0.0; n];
        aft.synthesise(|s| coefficients[s], &mut samples);
        for (j, x) in samples.iter().enumerate() {
            let theta = 2.0 * PI * j as f64 / n as f64;
            let direct: f64 = (0..2 * h + 1)
                .map(|s| coefficients[s] * basis(s, theta))
                .sum();
            // A sum of nine O(1) terms: round-off.
            assert!((x - direct).abs() < 1e-14);
        }
        let mut back = vec![0.0; 2 * h + 1];
        aft.analyse(&samples, &mut back);
        for (a, b) in back.iter().zip(&coefficients) {
            assert!((a - b).abs() < 1e-14);
        }
    }

    #[test]
    fn galerkin_matrix_matches_the_direct_sum_with_aliasing() {
        // N = 12 < 4H + 1: products of harmonics alias, and the DFT route must still agree.
        let (h, n) = (4, 12);
        let slots = 2 * h + 1;
        let mut aft = Aft::new(h, n).unwrap();
        let tangent: Vec<f64> = (0..n).map(|j| (j as f64 * 1.3).cos() + 0.2).collect();
        let mut matrix = vec![0.0; slots * slots];
        aft.galerkin(&tangent, &mut matrix);
        for row in 0..slots {
            for col in 0..slots {
                let weight = if row == 0 { 1.0 } else { 2.0 } / n as f64;
                let direct: f64 = (0..n)
                    .map(|j| {
                        let theta = 2.0 * PI * j as f64 / n as f64;
                        tangent[j] * basis(row, theta) * basis(col, theta)
                    })
                    .sum::<f64>()
                    * weight;
                // Twelve O(1) terms summed two ways.
                assert!(
                    (matrix[row * slots + col] - direct).abs() < 1e-13,
                    "({row}, {col})"
                );
            }
        }
    }

    #[test]
    fn aliasing_rule_keeps_cubic_harmonics_off_the_retained_ones() {
        for h in 1..10 {
            let n = aliasing_free_samples(h, 3);
            assert!(n.is_power_of_two() && n > 4 * h && n - 3 * h > h);
        }
    }
}
