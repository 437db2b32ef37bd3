//! Peaks of an amplitude spectrum, refined between bins (docs/theory.md section 8: the NSV
//! amplitude).
//!
//! # Method: window-kernel ratio interpolation
//!
//! A sinusoid of amplitude `A` lying `delta` bins (`0 <= delta <= 1`) above bin `k` reads
//! `a_k = A K(delta)` at bin `k` and `a_(k+1) = A K(1 - delta)` at bin `k + 1`, where `K` is
//! the window's normalised main-lobe shape, [`Window::response`]. The ratio of the larger
//! neighbour to the peak bin, `alpha = a_(k+1) / a_k`, fixes `delta` through
//! `K(1 - delta) = alpha K(delta)` (monotone in `delta`, solved by bisection), and then
//! `A = a_k / K(delta)`. For Hann this is the closed form `delta = (2 alpha - 1) / (alpha + 1)`,
//! `A = a_k pi delta (1 - delta^2) / sin(pi delta)` (Grandke 1983); for the rectangular
//! window `delta = alpha / (1 + alpha)`. It is exact for an isolated complex exponential in
//! a long record; what remains is the leakage of other components into the three bins:
//! the sinusoid's own negative-frequency image and its neighbours. Measured on a unit sine
//! swept across one bin 100 bins above DC, N = 4096 (`tests/suite/spectrum.rs`):
//!
//! | window | largest bin, uncorrected | corrected amplitude | frequency |
//! |---|---|---|---|
//! | Hann | 15.1 % low | 1.3e-8 | 7e-8 bins |
//! | flat top (HFT90D) | 0.045 % | 4.5e-9 | 4.5e-7 bins |
//! | rectangular | 36 % low | 4.5e-4 | 1.2e-3 bins |
//!
//! (with the rectangular window the image's 1/f leakage, about 1/(2 pi k) at bin `k`,
//! sets the limit). The log-parabola ("Gaussian") fit it replaces is off by up to 3.8 % in
//! amplitude and 0.016 bins in frequency for Hann.
//!
//! # DC
//!
//! The one-sided spectrum doubles every bin but DC, so a constant `c` reads `c` at bin 0
//! and `2 c K(k)` at bin `k` (with Hann, `c` again at bin 1). Peaks are therefore found on
//! the two-sided shape (bin 0 counted twice against its neighbours): a constant is one
//! peak at 0 Hz of amplitude `c`, not a spurious one at bin 1. The last bin is not
//! interpolated (it has no right neighbour).

use serde::Serialize;

use super::spectrum::{Spectrum, Window};

/// A peak of an amplitude spectrum.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct SpectralPeak {
    /// Frequency, refined between bins, Hz.
    pub frequency_hz: f64,
    /// Zero-to-peak amplitude, corrected for the window's scalloping (the signal's unit).
    pub amplitude: f64,
    /// `frequency_hz / running_speed_hz` (1 for synchronous, 0.5 for half-speed whirl);
    /// NaN when the running speed is not finite and positive.
    pub order: f64,
}

/// Local maxima of `spectrum` with amplitude at least `min_relative` times the largest,
/// refined between bins (see the module doc), largest first, at most `max_peaks` of them.
/// A `min_relative` that is not positive keeps every local maximum.
pub fn spectral_peaks(
    spectrum: &Spectrum,
    running_speed_hz: f64,
    min_relative: f64,
    max_peaks: usize,
) -> Vec<SpectralPeak> {
    let mut peaks = refined_candidates(spectrum, running_speed_hz, min_relative, max_peaks, 0.0);
    // In bin order, then largest first: ties keep the lower frequency first.
    peaks.sort_by_key(|p| p.0);
    let mut peaks: Vec<SpectralPeak> = peaks.into_iter().map(|(_, p)| p).collect();
    peaks.sort_by(|a, b| b.amplitude.total_cmp(&a.amplitude));
    let largest = peaks.first().map_or(0.0, |p| p.amplitude);
    if min_relative > 0.0 {
        let threshold = min_relative * largest;
        peaks.retain(|p| p.amplitude >= threshold);
    }
    peaks.truncate(max_peaks);
    peaks
}

/// The peaks of `spectrum` above `floor` (the signal's unit), refined between bins as in
/// [`spectral_peaks`], largest first: only the local maxima whose raw bin could reach the
/// floor once refined are refined.
pub fn spectral_peaks_above(
    spectrum: &Spectrum,
    running_speed_hz: f64,
    floor: f64,
) -> Vec<SpectralPeak> {
    let mut peaks: Vec<SpectralPeak> =
        refined_candidates(spectrum, running_speed_hz, 0.0, usize::MAX, floor)
            .into_iter()
            .map(|(_, p)| p)
            .filter(|p| p.amplitude > floor)
            .collect();
    peaks.sort_by(|a, b| b.amplitude.total_cmp(&a.amplitude));
    peaks
}

/// The local maxima of `spectrum` that may be among the `max_peaks` largest, at least
/// `min_relative` times the largest and above `floor` once refined, refined, with their
/// bins. Refining raises
/// a bin by at most the window's largest scalloping gain, so the maxima are refined in
/// order of their raw bins until none left could reach what is already kept: the same
/// peaks as refining every maximum (a long record has thousands), for a few refinements.
fn refined_candidates(
    spectrum: &Spectrum,
    running_speed_hz: f64,
    min_relative: f64,
    max_peaks: usize,
    floor: f64,
) -> Vec<(usize, SpectralPeak)> {
    let gain = largest_scalloping_gain(spectrum.window);
    let mut candidates: Vec<usize> = local_maxima(spectrum).collect();
    candidates.sort_by(|&i, &j| {
        let (a, b) = (shape(&spectrum.amplitude, i), shape(&spectrum.amplitude, j));
        b.total_cmp(&a).then(i.cmp(&j))
    });
    let mut kept: Vec<(usize, SpectralPeak)> = Vec::new();
    let mut amplitudes: Vec<f64> = Vec::new();
    let mut largest = 0.0_f64;
    for k in candidates {
        let bound = gain * shape(&spectrum.amplitude, k);
        let relative_cut = min_relative.clamp(0.0, 1.0) * largest;
        let count_cut = if amplitudes.len() >= max_peaks {
            amplitudes[max_peaks.saturating_sub(1)]
        } else {
            0.0
        };
        if bound < floor || (!kept.is_empty() && bound < relative_cut.max(count_cut)) {
            break;
        }
        let p = peak_at(spectrum, k, running_speed_hz);
        largest = largest.max(p.amplitude);
        let at = amplitudes.partition_point(|a| *a >= p.amplitude);
        amplitudes.insert(at, p.amplitude);
        kept.push((k, p));
    }
    kept
}

/// The largest peak that is not within `tolerance_bins` bins of `k * running_speed_hz` for
/// any `k = 0 (DC), 1, ..., max_order`: the non-synchronous vibration amplitude of
/// docs/theory.md section 8. `None` when every local maximum is synchronous. It is the largest
/// non-synchronous local maximum however small, down to round-off; compare it with the 1X
/// ([`amplitude_at`]) to judge whether it matters. A running speed that is not finite and
/// positive excludes only DC.
pub fn largest_non_synchronous(
    spectrum: &Spectrum,
    running_speed_hz: f64,
    tolerance_bins: f64,
    max_order: usize,
) -> Option<SpectralPeak> {
    largest_non_synchronous_where(
        spectrum,
        running_speed_hz,
        tolerance_bins,
        max_order,
        |_| true,
    )
}

/// As [`largest_non_synchronous`], among the peaks at or below `max_frequency_hz` only, with
/// every multiple of the running speed up to there synchronous: the NSV of a cascade that
/// shows (and judges) only that band. Peaks are found on the whole spectrum, so one just
/// inside the band is refined with its neighbour beyond it, and the band's edge is no peak.
pub fn largest_non_synchronous_below(
    spectrum: &Spectrum,
    running_speed_hz: f64,
    tolerance_bins: f64,
    max_frequency_hz: f64,
) -> Option<SpectralPeak> {
    let orders = if running_speed_hz.is_finite() && running_speed_hz > 0.0 {
        // One order beyond the band, so a peak refined just past the edge is still judged.
        (max_frequency_hz / running_speed_hz).ceil().max(0.0) as usize + 1
    } else {
        0
    };
    largest_non_synchronous_where(spectrum, running_speed_hz, tolerance_bins, orders, |p| {
        p.frequency_hz <= max_frequency_hz
    })
}

fn largest_non_synchronous_where(
    spectrum: &Spectrum,
    running_speed_hz: f64,
    tolerance_bins: f64,
    max_order: usize,
    keep: impl Fn(&SpectralPeak) -> bool,
) -> Option<SpectralPeak> {
    let tolerance_hz = tolerance_bins.max(0.0) * spectrum.resolution_hz;
    let speed_ok = running_speed_hz.is_finite() && running_speed_hz > 0.0;
    let synchronous = |f: f64| {
        if speed_ok {
            (0..=max_order).any(|k| (f - k as f64 * running_speed_hz).abs() <= tolerance_hz)
        } else {
            f.abs() <= tolerance_hz
        }
    };
    // Refining raises a local maximum's amplitude by at most the window's largest
    // scalloping within half a bin (its larger neighbour is never above it), so candidates
    // are refined in order of their raw bin and the search stops once no raw bin could
    // beat the best refined one: the result of refining them all, for a few refinements
    // instead of thousands.
    let gain = largest_scalloping_gain(spectrum.window);
    let mut candidates: Vec<usize> = local_maxima(spectrum).collect();
    candidates.sort_by(|&i, &j| {
        let (a, b) = (shape(&spectrum.amplitude, i), shape(&spectrum.amplitude, j));
        b.total_cmp(&a).then(i.cmp(&j))
    });
    let mut best: Option<SpectralPeak> = None;
    for k in candidates {
        let bound = gain * shape(&spectrum.amplitude, k);
        if best.is_some_and(|b| bound < b.amplitude) {
            break;
        }
        let p = peak_at(spectrum, k, running_speed_hz);
        if keep(&p)
            && !synchronous(p.frequency_hz)
            && best.is_none_or(|b| p.amplitude > b.amplitude)
        {
            best = Some(p);
        }
    }
    best
}

/// The largest factor by which refinement raises a local maximum's bin: 1 / K(delta) over
/// delta in [0, 1/2], sampled finely, with a 1 % margin for what falls between samples
/// (an overestimate only refines a few more candidates).
fn largest_scalloping_gain(window: Window) -> f64 {
    let lowest = (0..=64)
        .map(|i| window.response(i as f64 / 128.0))
        .fold(f64::INFINITY, f64::min);
    1.01 / lowest
}

/// The amplitude of the peak nearest `frequency_hz`: the largest bin within one bin of it,
/// refined as in [`spectral_peaks`] (for example the 1X amplitude at the running speed).
/// 0 when `frequency_hz` lies more than one bin outside the spectrum or is not finite.
pub fn amplitude_at(spectrum: &Spectrum, frequency_hz: f64) -> f64 {
    let df = spectrum.resolution_hz;
    let n = spectrum.amplitude.len();
    if n == 0 || !frequency_hz.is_finite() || df.is_nan() || df <= 0.0 {
        return 0.0;
    }
    let position = frequency_hz / df;
    let first = (position - 1.0).ceil().max(0.0);
    let last = (position + 1.0).floor().min((n - 1) as f64);
    if first > last {
        return 0.0;
    }
    let (first, last) = (first as usize, last as usize);
    let shape = |k: usize| shape(&spectrum.amplitude, k);
    let k = (first..=last)
        .max_by(|&i, &j| shape(i).total_cmp(&shape(j)))
        .unwrap_or(first);
    refine(spectrum, k).1
}

/// Bins that are local maxima of the two-sided shape.
fn local_maxima(spectrum: &Spectrum) -> impl Iterator<Item = usize> + '_ {
    let a = &spectrum.amplitude;
    let n = a.len();
    (0..n).filter(move |&k| {
        let here = shape(a, k);
        let right = if k + 1 < n { shape(a, k + 1) } else { 0.0 };
        // Bin 0's left neighbour is its mirror image, bin 1 (= `right`).
        let above_left = k == 0 || here > shape(a, k - 1);
        here > 0.0 && here.is_finite() && above_left && here >= right
    })
}

/// Bin `k` on the scale of a sinusoid's two-sided shape: DC counts twice, since every
/// other bin of the one-sided spectrum was doubled.
fn shape(amplitude: &[f64], k: usize) -> f64 {
    if k == 0 {
        2.0 * amplitude[0]
    } else {
        amplitude[k]
    }
}

fn peak_at(spectrum: &Spectrum, k: usize, running_speed_hz: f64) -> SpectralPeak {
    let (frequency_hz, amplitude) = refine(spectrum, k);
    let order = if running_speed_hz.is_finite() && running_speed_hz > 0.0 {
        frequency_hz / running_speed_hz
    } else {
        f64::NAN
    };
    SpectralPeak {
        frequency_hz,
        amplitude,
        order,
    }
}

/// Frequency (Hz) and amplitude of the sinusoid whose main lobe peaks at bin `k`.
fn refine(spectrum: &Spectrum, k: usize) -> (f64, f64) {
    let a = &spectrum.amplitude;
    let df = spectrum.resolution_hz;
    let bin_hz = k as f64 * df;
    if k == 0 || k + 1 >= a.len() || a[k].is_nan() || a[k] <= 0.0 {
        return (bin_hz, a[k]);
    }
    let (left, right) = (shape(a, k - 1), a[k + 1]);
    let (side, sign) = if right >= left {
        (right, 1.0)
    } else {
        (left, -1.0)
    };
    let delta = offset_from_ratio(spectrum.window, side / a[k]);
    (
        bin_hz + sign * delta * df,
        a[k] / spectrum.window.response(delta),
    )
}

/// Offset `delta` in [0, 1] bins of a sinusoid above the peak bin, from the ratio `alpha`
/// of the larger neighbour to the peak bin: the root of `K(1 - delta) = alpha K(delta)`.
pub(crate) fn offset_from_ratio(window: Window, alpha: f64) -> f64 {
    let k1 = window.response(1.0);
    if alpha.is_nan() || alpha <= k1 {
        return 0.0;
    }
    if alpha * k1 >= 1.0 {
        return 1.0;
    }
    // The closed forms of the module documentation: a cascade refines thousands of peaks,
    // and the bisection's 120 window responses (each a sine) were most of its reading.
    match window {
        Window::Hann => ((2.0 * alpha - 1.0) / (alpha + 1.0)).clamp(0.0, 1.0),
        Window::Rectangular => (alpha / (1.0 + alpha)).clamp(0.0, 1.0),
        Window::FlatTop => offset_by_bisection(window, alpha),
    }
}

/// The root of `K(1 - delta) = alpha K(delta)` in [0, 1] by bisection, for a window
/// without a closed form.
fn offset_by_bisection(window: Window, alpha: f64) -> f64 {
    let (mut low, mut high) = (0.0_f64, 1.0_f64);
    // 60 halvings leave an interval below 1e-18 bins.
    for _ in 0..60 {
        let mid = 0.5 * (low + high);
        if window.response(1.0 - mid) < alpha * window.response(mid) {
            low = mid;
        } else {
            high = mid;
        }
    }
    0.5 * (low + high)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ratio_inversion_matches_closed_forms() {
        for i in 0..=20 {
            let delta = i as f64 / 20.0;
            // Hann: alpha = (1 + delta) / (2 - delta).
            let alpha = (1.0 + delta) / (2.0 - delta);
            // The closed form is the root of the windows' responses: bisection on them
            // finds it to 1e-18 bins; the response's own round-off is ~1e-16.
            assert!((offset_by_bisection(Window::Hann, alpha) - delta).abs() < 1e-12);
            assert!((offset_from_ratio(Window::Hann, alpha) - delta).abs() < 1e-12);
            // Rectangular: alpha = delta / (1 - delta).
            if delta < 1.0 {
                let alpha = delta / (1.0 - delta);
                assert!((offset_by_bisection(Window::Rectangular, alpha) - delta).abs() < 1e-12);
                assert!((offset_from_ratio(Window::Rectangular, alpha) - delta).abs() < 1e-12);
            }
        }
    }

    #[test]
    fn degenerate_spectra_do_not_panic() {
        let empty = Spectrum {
            frequency_hz: vec![],
            amplitude: vec![],
            resolution_hz: 1.0,
            window: Window::Hann,
        };
        assert!(spectral_peaks(&empty, 10.0, 0.1, 5).is_empty());
        assert!(largest_non_synchronous(&empty, 10.0, 2.0, 3).is_none());
        assert_eq!(amplitude_at(&empty, 3.0), 0.0);
        let one = Spectrum {
            frequency_hz: vec![0.0],
            amplitude: vec![1.0],
            resolution_hz: 1.0,
            window: Window::Hann,
        };
        assert_eq!(spectral_peaks(&one, 10.0, 0.1, 5).len(), 1);
        assert_eq!(amplitude_at(&one, 0.2), 1.0);
        assert_eq!(amplitude_at(&one, f64::NAN), 0.0);
    }
}
