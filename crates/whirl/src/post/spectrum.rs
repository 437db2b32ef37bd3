//! Amplitude spectra of sampled time histories (docs/theory.md sections 6 and 8).
//!
//! A record `x_n`, `n = 0 .. N-1`, sampled at `fs`, is (optionally) stripped of its mean,
//! multiplied by a window `w_n` and transformed, `X_k = sum_n w_n x_n e^(-2 pi i k n / N)`.
//! The one-sided amplitude spectrum is scaled to physical zero-to-peak amplitude:
//!
//! ```text
//! A_k = c_k |X_k| / sum(w),   c_k = 2 for 0 < k < N/2,   c_k = 1 at DC (and Nyquist, N even)
//! ```
//!
//! which is the usual "divide by the coherent gain `sum(w) / N` and by `N / 2` (or `N`)".
//! A sine `a sin(2 pi f t + phi)` whose frequency is a bin centre, `f = k fs / N`, reads
//! `A_k = a` with every window; a constant `c` reads `A_0 = |c|`. Between bins the reading
//! drops by the window's scalloping loss, [`Window::response`]: up to 36 % for
//! [`Window::Rectangular`], 15 % for [`Window::Hann`], below 0.05 % for [`Window::FlatTop`].
//! [`crate::post::peaks`] undoes that loss for isolated peaks.
//!
//! The full spectrum ([`full_spectrum`]) transforms `z_n = x_n + i y_n` of two orthogonal
//! displacements: an orbit `z = r_f e^(i w t) + r_b e^(-i w t)` reads `r_f` at `+w` (forward
//! whirl, in the direction of `x -> y`) and `r_b` at `-w` (backward whirl), with
//! `A_k = |Z_k| / sum(w)`.
//!
//! Windows are DFT-even ("periodic") cosine sums, `w_n = sum_m a_m cos(2 pi m n / N)`, so
//! a bin-centred sine leaks into no other bin beyond the window's main lobe.
//!
//! For repeated spectra of one record length (a cascade of hundreds of speeds) build a
//! [`SpectrumPlanner`] once: it holds the FFT plan, the window and the work buffers, and
//! its [`SpectrumPlanner::process`] writes into the caller's buffer without allocating.

use std::fmt;
use std::sync::Arc;

use num_complex::Complex;
use realfft::{RealFftPlanner, RealToComplex};
use rustfft::{Fft, FftPlanner};
use serde::{Deserialize, Serialize};

use crate::{Error, Result};

/// The fewest samples a spectrum is taken of.
pub const MIN_SAMPLES: usize = 8;

/// The most samples a spectrum is taken of: half of `time::MAX_RECORDED_VALUES`, so that
/// the longest channel a run can record beside its time can always be transformed, while no
/// length can ask for a plan beyond memory (about 40 bytes a sample: 5 GB at the limit).
pub const MAX_SAMPLES: usize = 1 << 27;

/// Coefficients of HFT90D (G. Heinzel, A. Ruediger, R. Schilling, "Spectrum and spectral
/// density estimation by the Discrete Fourier Transform", 2002, appendix D): -90 dB side
/// lobes, amplitude flat to 0.0039 dB (0.045 %) across a bin, 3.88 bins noise bandwidth.
const HFT90D: [f64; 5] = [1.0, -1.942604, 1.340318, -0.440811, 0.043097];

/// A data window, applied before the FFT.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[cfg_attr(feature = "clap", derive(clap::ValueEnum))]
#[serde(rename_all = "kebab-case")]
pub enum Window {
    /// No window: the sharpest peaks, the most leakage (side lobes fall as 1/f, -13 dB).
    // Cascades are read for peaks between bins, which a rectangular window smears.
    #[cfg_attr(feature = "clap", value(skip))]
    Rectangular,
    /// Hann, `0.5 - 0.5 cos(2 pi n / N)`: main lobe +-2 bins, side lobes -31 dB falling
    /// as 1/f^3. The default for cascades.
    #[default]
    Hann,
    /// Flat top HFT90D: main lobe +-5 bins, -90 dB side lobes, and an amplitude that is
    /// within 0.05 % wherever the frequency falls between bins.
    FlatTop,
}

impl Window {
    /// Cosine-sum coefficients `a_m`: `w_n = sum_m a_m cos(2 pi m n / N)`.
    pub fn coefficients(self) -> &'static [f64] {
        match self {
            Window::Rectangular => &[1.0],
            Window::Hann => &[0.5, -0.5],
            Window::FlatTop => &HFT90D,
        }
    }

    /// The window's `n`-th sample for a record of `len` samples (DFT-even).
    pub fn sample(self, n: usize, len: usize) -> f64 {
        let phase = 2.0 * std::f64::consts::PI * n as f64 / len as f64;
        self.coefficients()
            .iter()
            .enumerate()
            .map(|(m, a)| a * (m as f64 * phase).cos())
            .sum()
    }

    /// All `len` samples of the window.
    pub fn samples(self, len: usize) -> Vec<f64> {
        (0..len).map(|n| self.sample(n, len)).collect()
    }

    /// Normalised magnitude of the window's transform `delta` bins away from a sinusoid
    /// (1 at `delta = 0`): what a bin reads, relative to the true amplitude, when the
    /// sinusoid lies `delta` bins from the bin's centre. Long-record limit,
    /// `|sum_m b_m (-1)^m sinc(delta - m)| / a_0` with `b_0 = a_0`, `b_(+-m) = a_m / 2`;
    /// the relative error against the exact finite-`N` kernel is about
    /// `(pi delta / N)^2 / 6`.
    pub fn response(self, delta: f64) -> f64 {
        let a = self.coefficients();
        let mut sum = a[0] * sinc(delta);
        for (m, am) in a.iter().enumerate().skip(1) {
            let sign = if m % 2 == 0 { 1.0 } else { -1.0 };
            let m = m as f64;
            sum += sign * 0.5 * am * (sinc(delta - m) + sinc(delta + m));
        }
        (sum / a[0]).abs()
    }
}

impl fmt::Display for Window {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Window::Rectangular => "rectangular",
            Window::Hann => "hann",
            Window::FlatTop => "flat-top",
        })
    }
}

/// `sin(pi x) / (pi x)`, 1 at 0.
fn sinc(x: f64) -> f64 {
    if x == 0.0 {
        1.0
    } else {
        let px = std::f64::consts::PI * x;
        px.sin() / px
    }
}

/// The mean of `signal` as the `window` samples weigh it, sum(w x) / sum(w). Removing it
/// leaves nothing at DC, where the plain mean of a record that is not a whole number of
/// periods would leave the difference, which the window's main lobe leaks into the first
/// bins.
pub fn window_mean(signal: &[f64], window: &[f64]) -> f64 {
    let sum: f64 = window.iter().sum();
    signal.iter().zip(window).map(|(v, w)| v * w).sum::<f64>() / sum
}

/// How a spectrum is taken.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
pub struct SpectrumOptions {
    /// The data window.
    pub window: Window,
    /// Subtract the record's mean as the window weighs it ([`window_mean`]) before
    /// windowing. Off by default: the DC bin then reads the mean, and (with Hann) so does
    /// bin 1, through the main lobe; turn it on when a static offset (gravity sag) would
    /// mask low-frequency content.
    pub remove_mean: bool,
}

impl SpectrumOptions {
    /// The given window, mean kept.
    pub fn window(window: Window) -> Self {
        SpectrumOptions {
            window,
            remove_mean: false,
        }
    }
}

/// A one-sided amplitude spectrum, zero-to-peak, in the signal's unit.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Spectrum {
    /// Bin frequencies `k fs / N`, `k = 0 ..= N/2`, Hz.
    pub frequency_hz: Vec<f64>,
    /// Zero-to-peak amplitude of each bin (the signal's unit).
    pub amplitude: Vec<f64>,
    /// Bin spacing `fs / N`, Hz.
    pub resolution_hz: f64,
    /// The window the record was multiplied by.
    pub window: Window,
}

/// A two-sided spectrum of `x + i y`: forward whirl at positive, backward at negative
/// frequencies.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct FullSpectrum {
    /// Bin frequencies from `-(N/2) fs / N` up to `(N - 1 - N/2) fs / N`, ascending, Hz.
    pub frequency_hz: Vec<f64>,
    /// Radius of the circular whirl component at each frequency (the signal's unit).
    pub amplitude: Vec<f64>,
    /// Bin spacing `fs / N`, Hz.
    pub resolution_hz: f64,
    /// The window the record was multiplied by.
    pub window: Window,
}

/// The amplitude spectrum of `signal`, sampled at `sample_rate_hz`, mean kept (the DC bin
/// reads it). See [`amplitude_spectrum_with`] to remove the mean.
///
/// # Errors
/// [`Error::InvalidOption`] for an empty or short (fewer than 8 samples) signal, a sample
/// that is not finite, or a sample rate that is not finite and positive.
pub fn amplitude_spectrum(signal: &[f64], sample_rate_hz: f64, window: Window) -> Result<Spectrum> {
    amplitude_spectrum_with(signal, sample_rate_hz, SpectrumOptions::window(window))
}

/// The amplitude spectrum of `signal` with the given options.
///
/// # Errors
/// As [`amplitude_spectrum`].
pub fn amplitude_spectrum_with(
    signal: &[f64],
    sample_rate_hz: f64,
    options: SpectrumOptions,
) -> Result<Spectrum> {
    check_length("spectrum", signal.len())?;
    SpectrumPlanner::new(signal.len(), sample_rate_hz, options)?.spectrum(signal)
}

/// The full spectrum of the orbit `x + i y` (two displacements at right angles, `y` a
/// quarter turn from `x` in the direction of rotation), mean kept.
///
/// # Errors
/// As [`amplitude_spectrum`], and when `x` and `y` differ in length.
pub fn full_spectrum(
    x: &[f64],
    y: &[f64],
    sample_rate_hz: f64,
    window: Window,
) -> Result<FullSpectrum> {
    check_length("full spectrum", x.len())?;
    FullSpectrumPlanner::new(x.len(), sample_rate_hz, SpectrumOptions::window(window))?
        .spectrum(x, y)
}

/// One-sided amplitude spectra of records of one length, planned once.
///
/// ```
/// use whirl::post::{SpectrumOptions, SpectrumPlanner};
/// let mut planner = SpectrumPlanner::new(1024, 2048.0, SpectrumOptions::default()).unwrap();
/// let mut amplitude = vec![0.0; planner.bins()];
/// for speed in [10.0, 20.0, 30.0] {
///     let record: Vec<f64> = (0..1024)
///         .map(|n| (2.0 * std::f64::consts::PI * speed * n as f64 / 2048.0).sin())
///         .collect();
///     planner.process(&record, &mut amplitude).unwrap(); // allocates nothing
///     let k = (speed / planner.resolution_hz()).round() as usize;
///     assert!((amplitude[k] - 1.0).abs() < 1e-12);
/// }
/// ```
#[derive(Clone)]
pub struct SpectrumPlanner {
    fft: Arc<dyn RealToComplex<f64>>,
    options: SpectrumOptions,
    sample_rate_hz: f64,
    window: Vec<f64>,
    /// `2 / sum(w)`, the scale of the bins between DC and Nyquist.
    scale: f64,
    input: Vec<f64>,
    output: Vec<Complex<f64>>,
    scratch: Vec<Complex<f64>>,
}

impl SpectrumPlanner {
    /// Plans spectra of `len` samples taken at `sample_rate_hz`.
    ///
    /// # Errors
    /// [`Error::InvalidOption`] when `len` is outside [`MIN_SAMPLES`]..=[`MAX_SAMPLES`] or the
    /// sample rate is not finite and positive.
    pub fn new(len: usize, sample_rate_hz: f64, options: SpectrumOptions) -> Result<Self> {
        check_length("spectrum", len)?;
        check_rate("spectrum", sample_rate_hz)?;
        let fft = RealFftPlanner::<f64>::new().plan_fft_forward(len);
        let window = options.window.samples(len);
        let scale = 2.0 / window.iter().sum::<f64>();
        Ok(SpectrumPlanner {
            input: fft.make_input_vec(),
            output: fft.make_output_vec(),
            scratch: fft.make_scratch_vec(),
            fft,
            options,
            sample_rate_hz,
            window,
            scale,
        })
    }

    /// Record length `N`.
    pub fn len(&self) -> usize {
        self.window.len()
    }

    /// Always false: a planner is for at least 8 samples.
    pub fn is_empty(&self) -> bool {
        self.window.is_empty()
    }

    /// Number of one-sided bins, `N/2 + 1`.
    pub fn bins(&self) -> usize {
        self.len() / 2 + 1
    }

    /// Bin spacing `fs / N`, Hz.
    pub fn resolution_hz(&self) -> f64 {
        self.sample_rate_hz / self.len() as f64
    }

    /// The options this planner applies.
    pub fn options(&self) -> SpectrumOptions {
        self.options
    }

    /// Bin frequencies, Hz.
    pub fn frequency_hz(&self) -> Vec<f64> {
        let df = self.resolution_hz();
        (0..self.bins()).map(|k| k as f64 * df).collect()
    }

    /// Writes the amplitude spectrum of `signal` into `amplitude` (length
    /// [`bins`](Self::bins)), allocating nothing.
    ///
    /// # Errors
    /// [`Error::InvalidOption`] when a length is wrong or a sample is not finite.
    pub fn process(&mut self, signal: &[f64], amplitude: &mut [f64]) -> Result<()> {
        const WHAT: &str = "spectrum";
        check_same_length(WHAT, "signal", signal.len(), self.len())?;
        check_same_length(WHAT, "amplitude buffer", amplitude.len(), self.bins())?;
        check_finite(WHAT, "signal", signal)?;
        let mean = if self.options.remove_mean {
            window_mean(signal, &self.window)
        } else {
            0.0
        };
        for ((buffer, x), w) in self.input.iter_mut().zip(signal).zip(&self.window) {
            *buffer = (x - mean) * w;
        }
        self.fft
            .process_with_scratch(&mut self.input, &mut self.output, &mut self.scratch)
            .map_err(|e| Error::Internal(format!("{WHAT}: FFT failed: {e}")))?;
        let len = self.len();
        for (k, (a, x)) in amplitude.iter_mut().zip(&self.output).enumerate() {
            let edge = k == 0 || 2 * k == len;
            // The root of the squared modulus: hypot's care for overflow and underflow costs
            // a few per cent of a cascade, and a displacement's spectrum has neither.
            *a = x.norm_sqr().sqrt() * if edge { 0.5 * self.scale } else { self.scale };
        }
        Ok(())
    }

    /// The amplitude spectrum of `signal` as a new [`Spectrum`].
    ///
    /// # Errors
    /// As [`process`](Self::process).
    pub fn spectrum(&mut self, signal: &[f64]) -> Result<Spectrum> {
        let mut amplitude = vec![0.0; self.bins()];
        self.process(signal, &mut amplitude)?;
        Ok(Spectrum {
            frequency_hz: self.frequency_hz(),
            amplitude,
            resolution_hz: self.resolution_hz(),
            window: self.options.window,
        })
    }
}

/// Full spectra of orbits `x + i y` of one length, planned once.
#[derive(Clone)]
pub struct FullSpectrumPlanner {
    fft: Arc<dyn Fft<f64>>,
    options: SpectrumOptions,
    sample_rate_hz: f64,
    window: Vec<f64>,
    /// `1 / sum(w)`.
    scale: f64,
    buffer: Vec<Complex<f64>>,
    scratch: Vec<Complex<f64>>,
}

impl FullSpectrumPlanner {
    /// Plans full spectra of `len` samples taken at `sample_rate_hz`.
    ///
    /// # Errors
    /// [`Error::InvalidOption`] when `len` is outside [`MIN_SAMPLES`]..=[`MAX_SAMPLES`] or the
    /// sample rate is not finite and positive.
    pub fn new(len: usize, sample_rate_hz: f64, options: SpectrumOptions) -> Result<Self> {
        check_length("full spectrum", len)?;
        check_rate("full spectrum", sample_rate_hz)?;
        let fft = FftPlanner::<f64>::new().plan_fft_forward(len);
        let window = options.window.samples(len);
        let scale = 1.0 / window.iter().sum::<f64>();
        Ok(FullSpectrumPlanner {
            buffer: vec![Complex::new(0.0, 0.0); len],
            scratch: vec![Complex::new(0.0, 0.0); fft.get_inplace_scratch_len()],
            fft,
            options,
            sample_rate_hz,
            window,
            scale,
        })
    }

    /// Record length `N`, which is also the number of bins.
    pub fn len(&self) -> usize {
        self.window.len()
    }

    /// Always false: a planner is for at least 8 samples.
    pub fn is_empty(&self) -> bool {
        self.window.is_empty()
    }

    /// Bin spacing `fs / N`, Hz.
    pub fn resolution_hz(&self) -> f64 {
        self.sample_rate_hz / self.len() as f64
    }

    /// Bin frequencies, ascending from `-(N/2) fs / N`, Hz.
    pub fn frequency_hz(&self) -> Vec<f64> {
        let df = self.resolution_hz();
        let half = (self.len() / 2) as f64;
        (0..self.len()).map(|j| (j as f64 - half) * df).collect()
    }

    /// Writes the full spectrum of `x + i y` into `amplitude` (length `N`, ordered as
    /// [`frequency_hz`](Self::frequency_hz)), allocating nothing.
    ///
    /// # Errors
    /// [`Error::InvalidOption`] when a length is wrong or a sample is not finite.
    pub fn process(&mut self, x: &[f64], y: &[f64], amplitude: &mut [f64]) -> Result<()> {
        const WHAT: &str = "full spectrum";
        let len = self.len();
        check_same_length(WHAT, "x", x.len(), len)?;
        check_same_length(WHAT, "y", y.len(), len)?;
        check_same_length(WHAT, "amplitude buffer", amplitude.len(), len)?;
        check_finite(WHAT, "x", x)?;
        check_finite(WHAT, "y", y)?;
        let (mean_x, mean_y) = if self.options.remove_mean {
            (window_mean(x, &self.window), window_mean(y, &self.window))
        } else {
            (0.0, 0.0)
        };
        for (((z, xn), yn), w) in self.buffer.iter_mut().zip(x).zip(y).zip(&self.window) {
            *z = Complex::new((xn - mean_x) * w, (yn - mean_y) * w);
        }
        self.fft
            .process_with_scratch(&mut self.buffer, &mut self.scratch);
        // fftshift: output j holds the signed bin j - N/2.
        let half = len / 2;
        for (j, a) in amplitude.iter_mut().enumerate() {
            *a = self.buffer[(j + len - half) % len].norm_sqr().sqrt() * self.scale;
        }
        Ok(())
    }

    /// The full spectrum of `x + i y` as a new [`FullSpectrum`].
    ///
    /// # Errors
    /// As [`process`](Self::process).
    pub fn spectrum(&mut self, x: &[f64], y: &[f64]) -> Result<FullSpectrum> {
        let mut amplitude = vec![0.0; self.len()];
        self.process(x, y, &mut amplitude)?;
        Ok(FullSpectrum {
            frequency_hz: self.frequency_hz(),
            amplitude,
            resolution_hz: self.resolution_hz(),
            window: self.options.window,
        })
    }
}

fn check_length(what: &str, len: usize) -> Result<()> {
    if len == 0 {
        Err(Error::InvalidOption(format!("{what}: the signal is empty")))
    } else if len < MIN_SAMPLES {
        Err(Error::InvalidOption(format!(
            "{what}: the signal has {len} samples; at least {MIN_SAMPLES} are needed"
        )))
    } else if len > MAX_SAMPLES {
        Err(Error::InvalidOption(format!(
            "{what}: the signal has {len} samples; at most {MAX_SAMPLES} are taken (record \
             less often or a shorter part)"
        )))
    } else {
        Ok(())
    }
}

fn check_rate(what: &str, sample_rate_hz: f64) -> Result<()> {
    if sample_rate_hz.is_finite() && sample_rate_hz > 0.0 {
        Ok(())
    } else {
        Err(Error::InvalidOption(format!(
            "{what}: the sample rate must be finite and positive, got {sample_rate_hz} Hz"
        )))
    }
}

fn check_same_length(what: &str, name: &str, len: usize, expected: usize) -> Result<()> {
    if len == expected {
        Ok(())
    } else {
        Err(Error::InvalidOption(format!(
            "{what}: the {name} has {len} samples; this planner expects {expected}"
        )))
    }
}

fn check_finite(what: &str, name: &str, signal: &[f64]) -> Result<()> {
    match signal.iter().position(|v| !v.is_finite()) {
        None => Ok(()),
        Some(n) => Err(Error::InvalidOption(format!(
            "{what}: sample {n} of the {name} is {}; every sample must be finite \
             (did the simulation diverge?)",
            signal[n]
        ))),
    }
}

// Cascades are read for peaks between bins, which a rectangular window smears: not offered.
crate::given::choice!(Window { "hann" => Window::Hann, "flat-top" => Window::FlatTop });

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_plan_past_the_sample_limit_is_refused_before_it_is_allocated() {
        // usize::MAX samples could not be allocated at all: refused, not aborted.
        let options = SpectrumOptions {
            window: Window::Hann,
            remove_mean: true,
        };
        for len in [MAX_SAMPLES + 1, usize::MAX] {
            let e = SpectrumPlanner::new(len, 1e5, options)
                .err()
                .map(|e| e.to_string());
            assert!(
                e.is_some_and(|e| e.contains(&format!("at most {MAX_SAMPLES}"))),
                "{len}"
            );
            assert!(
                FullSpectrumPlanner::new(len, 1e5, options).is_err(),
                "{len}"
            );
        }
    }

    /// Slow, obviously correct reference: the DFT sum itself.
    fn naive_amplitude(signal: &[f64], window: Window) -> Vec<f64> {
        let n = signal.len();
        let w = window.samples(n);
        let sum_w: f64 = w.iter().sum();
        (0..=n / 2)
            .map(|k| {
                let x: Complex<f64> = (0..n)
                    .map(|j| {
                        let phase = -2.0 * std::f64::consts::PI * (k * j) as f64 / n as f64;
                        Complex::from_polar(signal[j] * w[j], phase)
                    })
                    .sum();
                let c = if k == 0 || 2 * k == n { 1.0 } else { 2.0 };
                c * x.norm() / sum_w
            })
            .collect()
    }

    #[test]
    fn planner_matches_the_dft_sum() {
        // A fixed pseudo-random record (LCG), odd and even lengths.
        for len in [64usize, 75] {
            let mut state = 12345u64;
            let signal: Vec<f64> = (0..len)
                .map(|_| {
                    state = state.wrapping_mul(6364136223846793005).wrapping_add(1);
                    (state >> 11) as f64 / (1u64 << 53) as f64 - 0.5
                })
                .collect();
            for window in [Window::Rectangular, Window::Hann, Window::FlatTop] {
                let fast = amplitude_spectrum(&signal, 100.0, window).unwrap();
                let slow = naive_amplitude(&signal, window);
                assert_eq!(fast.amplitude.len(), slow.len());
                for (a, b) in fast.amplitude.iter().zip(&slow) {
                    // Both sums carry round-off of order N eps times the largest term.
                    assert!((a - b).abs() < 1e-12, "{window}: {a} vs {b}");
                }
            }
        }
    }

    #[test]
    fn response_is_one_at_the_centre_and_matches_hann_closed_form() {
        for window in [Window::Rectangular, Window::Hann, Window::FlatTop] {
            assert!((window.response(0.0) - 1.0).abs() < 1e-15);
        }
        // Hann: sinc(d) / (1 - d^2), the textbook closed form.
        for d in [0.1, 0.25, 0.5, 0.8, 1.5, 2.5] {
            let closed = sinc(d) / (1.0 - d * d);
            assert!((Window::Hann.response(d) - closed.abs()).abs() < 1e-14);
        }
        // Rectangular: sinc.
        assert!((Window::Rectangular.response(0.5) - 2.0 / std::f64::consts::PI).abs() < 1e-15);
    }

    #[test]
    fn flat_top_is_flat_within_half_a_permille() {
        // Heinzel's table: flatness 0.0039 dB = 0.045 %; sample the response finely.
        let worst = (0..=1000)
            .map(|i| (Window::FlatTop.response(i as f64 * 0.5e-3) - 1.0).abs())
            .fold(0.0, f64::max);
        assert!(worst < 5e-4, "worst {worst}");
    }
}
