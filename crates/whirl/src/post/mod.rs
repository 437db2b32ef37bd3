//! Post-processing of time histories (docs/theory.md sections 6 and 8; thesis ch. 5).
//!
//! - [`spectrum`]: one-sided amplitude spectrum scaled to physical zero-to-peak
//!   amplitude, `A_k = c_k |X_k| / sum(w)` with `X_k = sum_n w_n x_n e^(-2 pi i k n / N)`,
//!   `c_k = 2` for `0 < k < N/2` and `c_k = 1` at DC and Nyquist; the full (two-sided)
//!   spectrum of `x + i y` that separates forward from backward whirl; a reusable,
//!   allocation-free [`SpectrumPlanner`] for cascades.
//! - [`peaks`]: spectral peaks refined between bins by the window's own main-lobe shape,
//!   their order relative to the running speed, the largest non-synchronous peak (the NSV
//!   amplitude of docs/theory.md section 8) and the amplitude read near a given frequency (1X).
//! - [`tracking`]: the component of a signal at an order of the shaft angle, with its
//!   phase (the settled 1X amplitude and phase of a time history).
//!
//! ```
//! use whirl::post::{amplitude_spectrum, largest_non_synchronous, Window};
//! let fs = 1024.0;
//! let signal: Vec<f64> = (0..1024)
//!     .map(|n| {
//!         let t = n as f64 / fs;
//!         1e-5 * (2.0 * std::f64::consts::PI * 50.0 * t).sin()
//!             + 3e-6 * (2.0 * std::f64::consts::PI * 173.0 * t).sin()
//!     })
//!     .collect();
//! let spectrum = amplitude_spectrum(&signal, fs, Window::Hann).unwrap();
//! let nsv = largest_non_synchronous(&spectrum, 50.0, 2.0, 4).unwrap();
//! assert!((nsv.frequency_hz - 173.0).abs() < 1e-6);
//! assert!((nsv.amplitude - 3e-6).abs() < 1e-15);
//! ```

pub mod peaks;
pub mod spectrum;
pub mod tracking;

pub use peaks::{
    amplitude_at, largest_non_synchronous, largest_non_synchronous_below, spectral_peaks,
    spectral_peaks_above, SpectralPeak,
};
pub use spectrum::{
    amplitude_spectrum, amplitude_spectrum_with, full_spectrum, window_mean, FullSpectrum,
    FullSpectrumPlanner, Spectrum, SpectrumOptions, SpectrumPlanner, Window,
};
pub use tracking::{order_component, OrderComponent};

/// The table `(x, y)`, ascending in x, read at `x` by linear interpolation; `None` outside
/// it.
pub(crate) fn interpolate(points: &[(f64, f64)], x: f64) -> Option<f64> {
    let (first, last) = (points.first()?, points.last()?);
    if x < first.0 || x > last.0 {
        return None;
    }
    let upper = points.partition_point(|p| p.0 < x).min(points.len() - 1);
    let lower = upper.saturating_sub(1);
    let ((x0, y0), (x1, y1)) = (points[lower], points[upper]);
    if x1 == x0 {
        return Some(y1);
    }
    Some(y0 + (y1 - y0) * (x - x0) / (x1 - x0))
}
