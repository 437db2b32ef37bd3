//! Spectra, peaks and the NSV amplitude (docs/theory.md sections 6 and 8) on signals whose answer
//! is known in closed form.

use std::f64::consts::PI;

use whirl::post::{
    amplitude_at, amplitude_spectrum, amplitude_spectrum_with, full_spectrum,
    largest_non_synchronous, spectral_peaks, spectral_peaks_above, FullSpectrumPlanner,
    SpectrumOptions, SpectrumPlanner, Window,
};
use whirl::Error;

const WINDOWS: [Window; 3] = [Window::Rectangular, Window::Hann, Window::FlatTop];

/// `sum_i a_i sin(2 pi f_i t + phi_i)` sampled at `fs`.
fn sines(len: usize, fs: f64, components: &[(f64, f64, f64)]) -> Vec<f64> {
    (0..len)
        .map(|n| {
            let t = n as f64 / fs;
            components
                .iter()
                .map(|&(f, a, phi)| a * (2.0 * PI * f * t + phi).sin())
                .sum()
        })
        .collect()
}

#[test]
fn a_bin_centred_sine_reads_its_amplitude() {
    // N = 1000 at 1000 Hz: 1 Hz bins, 123 Hz is bin 123.
    let (len, fs) = (1000, 1000.0);
    for amplitude in [1.0, 2.5e-5] {
        let signal = sines(len, fs, &[(123.0, amplitude, 0.7)]);
        for window in WINDOWS {
            let spectrum = amplitude_spectrum(&signal, fs, window).unwrap();
            assert_eq!(spectrum.amplitude.len(), len / 2 + 1);
            assert_eq!(spectrum.resolution_hz, 1.0);
            assert_eq!(spectrum.window, window);
            let read = spectrum.amplitude[123];
            // Exact in exact arithmetic; the FFT's round-off is ~N eps relative.
            assert!(
                (read - amplitude).abs() < 1e-12 * amplitude,
                "{window}: read {read}, expected {amplitude}"
            );
            // Everything outside the main lobe (5 bins at most) is round-off.
            let leak = spectrum
                .amplitude
                .iter()
                .enumerate()
                .filter(|(k, _)| k.abs_diff(123) > 5)
                .map(|(_, a)| *a)
                .fold(0.0, f64::max);
            assert!(leak < 1e-13 * amplitude, "{window}: leakage {leak}");
        }
    }
}

#[test]
fn odd_lengths_and_the_nyquist_bin_are_scaled() {
    // Odd N: no Nyquist bin, every bin but DC doubled. 99 samples at 99 Hz, 10 Hz is bin 10.
    let signal = sines(99, 99.0, &[(10.0, 0.5, 0.0)]);
    let spectrum = amplitude_spectrum(&signal, 99.0, Window::Hann).unwrap();
    assert_eq!(spectrum.amplitude.len(), 50);
    assert!((spectrum.amplitude[10] - 0.5).abs() < 1e-14);
    // Even N: a cosine at Nyquist, (-1)^n, reads its amplitude in the last bin (rectangular;
    // round-off only).
    let nyquist: Vec<f64> = (0..64)
        .map(|n| if n % 2 == 0 { 0.3 } else { -0.3 })
        .collect();
    let spectrum = amplitude_spectrum(&nyquist, 64.0, Window::Rectangular).unwrap();
    assert!((spectrum.amplitude[32] - 0.3).abs() < 1e-14);
    assert_eq!(spectrum.frequency_hz[32], 32.0);
}

/// Worst relative amplitude error and worst frequency error (bins) over sines swept
/// across one bin, 100 bins above DC, N = 4096: (raw largest bin, interpolated peak).
fn sweep_between_bins(window: Window) -> (f64, f64, f64) {
    let (len, fs) = (4096, 4096.0);
    let (mut raw, mut refined, mut frequency) = (0.0_f64, 0.0_f64, 0.0_f64);
    for i in 0..=40 {
        let f = 100.0 + i as f64 / 40.0;
        let signal = sines(len, fs, &[(f, 1.0, 0.3 + i as f64)]);
        let spectrum = amplitude_spectrum(&signal, fs, window).unwrap();
        let largest = spectrum.amplitude.iter().cloned().fold(0.0, f64::max);
        raw = raw.max((largest - 1.0).abs());
        let peak = spectral_peaks(&spectrum, 50.0, 0.5, 1)[0];
        refined = refined.max((peak.amplitude - 1.0).abs());
        frequency = frequency.max((peak.frequency_hz - f).abs() / spectrum.resolution_hz);
    }
    (raw, refined, frequency)
}

#[test]
fn flat_top_reads_an_off_bin_sine_within_a_permille() {
    let (raw, refined, frequency) = sweep_between_bins(Window::FlatTop);
    eprintln!("flat top: raw {raw:.2e}, refined {refined:.2e}, frequency {frequency:.2e} bins");
    // HFT90D is flat to 0.045 % (Heinzel et al. 2002); the check asks for 0.1 %.
    assert!(raw < 1e-3, "raw {raw}");
    // Corrected by its own kernel (measured 4.5e-9): bounded by the long-record kernel's
    // error, (pi 5 / N)^2 / 6 = 1e-7 at the edge of its +-5-bin main lobe.
    assert!(refined < 1e-6, "refined {refined}");
    // Its neighbours' ratio varies least across a bin, so its frequency is the least
    // sharp of the three (measured 4.5e-7 bins).
    assert!(frequency < 1e-5, "frequency {frequency}");
}

#[test]
fn hann_with_interpolation_reads_an_off_bin_sine() {
    let (raw, refined, frequency) = sweep_between_bins(Window::Hann);
    eprintln!("hann: raw {raw:.2e}, refined {refined:.2e}, frequency {frequency:.2e} bins");
    // Without correction Hann loses up to 15 % (K(0.5) = 8 / (3 pi) = 0.849).
    assert!(raw > 0.14 && raw < 0.16, "raw {raw}");
    // The kernel ratio is exact for one complex exponential; the image at -100 bins leaks
    // about 1 / (pi 200^3) = 4e-8 and the long-record kernel errs (pi / N)^2 / 6 = 1e-7;
    // measured 1.3e-8 and 7e-8 bins.
    assert!(refined < 1e-7, "refined {refined}");
    assert!(frequency < 1e-6, "frequency {frequency}");
}

#[test]
fn rectangular_interpolation_is_limited_by_the_image_leakage() {
    let (raw, refined, frequency) = sweep_between_bins(Window::Rectangular);
    eprintln!("rectangular: raw {raw:.2e}, refined {refined:.2e}, frequency {frequency:.2e}");
    // Scalloping up to 1 - 2 / pi = 36 %.
    assert!(raw > 0.35 && raw < 0.37, "raw {raw}");
    // The image at -100 bins leaks ~1 / (2 pi 100) = 1.6e-3 into the peak's bins
    // (measured 4.5e-4 in amplitude, 1.2e-3 bins in frequency).
    assert!(refined < 5e-3, "refined {refined}");
    assert!(frequency < 5e-3, "frequency {frequency}");
}

#[test]
fn two_sines_are_found_with_their_orders() {
    // 1000 Hz, N = 2048: 0.488 Hz bins; 50 Hz at bin 102.4 and 173 Hz at 354.3, both off-bin.
    let (len, fs) = (2048, 1000.0);
    let signal = sines(len, fs, &[(50.0, 1e-5, 0.2), (173.0, 3e-6, 1.1)]);
    let spectrum = amplitude_spectrum(&signal, fs, Window::Hann).unwrap();
    let peaks = spectral_peaks(&spectrum, 50.0, 0.01, 10);
    assert_eq!(peaks.len(), 2, "{peaks:?}");
    // Each reads the other's Hann leakage (~1 / (pi 250^3) = 2e-8 of 1e-5, 7e-8 relative
    // at 173 Hz) and its own image: measured 1.5e-8 relative and 4e-8 Hz, so 1e-6 and
    // 1e-5 Hz (2e-5 bins) leave room without hiding a wrong method.
    assert!((peaks[0].frequency_hz - 50.0).abs() < 1e-5);
    assert!((peaks[0].amplitude - 1e-5).abs() < 1e-5 * 1e-6);
    assert!((peaks[0].order - 1.0).abs() < 1e-6);
    assert!((peaks[1].frequency_hz - 173.0).abs() < 1e-5);
    assert!((peaks[1].amplitude - 3e-6).abs() < 3e-6 * 1e-6);
    assert!((peaks[1].order - 3.46).abs() < 1e-6);
    // max_peaks and min_relative cut the list.
    assert_eq!(spectral_peaks(&spectrum, 50.0, 0.01, 1).len(), 1);
    assert_eq!(spectral_peaks(&spectrum, 50.0, 0.5, 10).len(), 1);
    // amplitude_at reads the 1X from a speed that is not a bin centre.
    assert!((amplitude_at(&spectrum, 50.0) - 1e-5).abs() < 1e-5 * 1e-6);
    assert!((amplitude_at(&spectrum, 173.3) - 3e-6).abs() < 3e-6 * 1e-6);
    // Far from any peak it reads the leakage floor.
    assert!(amplitude_at(&spectrum, 300.0) < 1e-12);
    assert_eq!(amplitude_at(&spectrum, 2000.0), 0.0);
    // Above a floor: the same refined peaks as refining every maximum and keeping those
    // above it (the leakage's maxima, down to round-off, stay below 1e-9).
    let every = spectral_peaks(&spectrum, 50.0, 0.0, usize::MAX);
    for floor in [1e-9, 5e-6, 2e-5] {
        let kept: Vec<_> = every
            .iter()
            .filter(|p| p.amplitude > floor)
            .copied()
            .collect();
        assert_eq!(
            spectral_peaks_above(&spectrum, 50.0, floor),
            kept,
            "{floor}"
        );
    }
    assert_eq!(spectral_peaks_above(&spectrum, 50.0, 1e-9).len(), 2);
}

#[test]
fn the_largest_non_synchronous_peak_ignores_dc_1x_and_2x() {
    let (len, fs) = (2048, 1000.0);
    // Offset, 1X, 2X larger than the 173 Hz whirl, which is what NSV must find.
    let mut signal = sines(
        len,
        fs,
        &[(50.0, 1e-5, 0.2), (100.0, 5e-6, 0.4), (173.0, 3e-6, 1.1)],
    );
    for x in &mut signal {
        *x += 2e-5;
    }
    let spectrum = amplitude_spectrum(&signal, fs, Window::Hann).unwrap();
    let all = spectral_peaks(&spectrum, 50.0, 0.01, 10);
    assert_eq!(all.len(), 4, "{all:?}");
    assert_eq!(all[0].frequency_hz, 0.0);
    let nsv = largest_non_synchronous(&spectrum, 50.0, 2.0, 4).unwrap();
    // As in the two-sine test, plus the offset's and 2X's leakage (below 1e-7 relative).
    assert!((nsv.frequency_hz - 173.0).abs() < 1e-5, "{nsv:?}");
    assert!((nsv.amplitude - 3e-6).abs() < 3e-6 * 1e-6);
    // With only 1X excluded, 2X is the largest "non-synchronous" peak.
    let only_1x = largest_non_synchronous(&spectrum, 50.0, 2.0, 1).unwrap();
    assert!((only_1x.frequency_hz - 100.0).abs() < 1e-3);
    // With 173 Hz taken as the running speed's 1X, 50 Hz becomes the largest.
    let other = largest_non_synchronous(&spectrum, 173.0, 2.0, 1).unwrap();
    assert!((other.frequency_hz - 50.0).abs() < 1e-3);
    // A purely synchronous record: whatever is found is round-off, far below 1X.
    let synchronous = sines(len, fs, &[(50.0, 1e-5, 0.2), (100.0, 5e-6, 0.4)]);
    let spectrum = amplitude_spectrum(&synchronous, fs, Window::Hann).unwrap();
    if let Some(p) = largest_non_synchronous(&spectrum, 50.0, 2.0, 4) {
        assert!(p.amplitude < 1e-5 * 1e-6, "{p:?}");
    }
}

#[test]
fn dc_is_its_own_bin_and_its_own_peak() {
    // 0.3 + 0.1 sin at bin 40.
    let (len, fs) = (512, 512.0);
    let signal: Vec<f64> = sines(len, fs, &[(40.0, 0.1, 0.5)])
        .into_iter()
        .map(|x| x + 0.3)
        .collect();
    for window in WINDOWS {
        let spectrum = amplitude_spectrum(&signal, fs, window).unwrap();
        // The sine's main lobe ends 5 bins from 40; DC reads the mean to round-off.
        assert!((spectrum.amplitude[0] - 0.3).abs() < 1e-12, "{window}");
        assert!((spectrum.amplitude[40] - 0.1).abs() < 1e-12, "{window}");
        // One peak at DC, one at 40 Hz: the DC's main lobe (with Hann bin 1 also reads
        // 0.3; with the flat top bin 1 reads 1.94 x 0.3) is not a peak of its own.
        let peaks = spectral_peaks(&spectrum, 10.0, 1e-6, 10);
        assert_eq!(peaks.len(), 2, "{window}: {peaks:?}");
        assert_eq!(peaks[0].frequency_hz, 0.0);
        assert!((peaks[0].amplitude - 0.3).abs() < 1e-12);
        assert!((peaks[1].frequency_hz - 40.0).abs() < 1e-9);
        assert!((amplitude_at(&spectrum, 0.0) - 0.3).abs() < 1e-12);

        let options = SpectrumOptions {
            window,
            remove_mean: true,
        };
        let centred = amplitude_spectrum_with(&signal, fs, options).unwrap();
        // The sine is whole periods, so the record's mean is exactly the offset.
        assert!(centred.amplitude[0] < 1e-12, "{window}");
        assert!(centred.amplitude[1..10].iter().all(|a| *a < 1e-12));
        assert!((centred.amplitude[40] - 0.1).abs() < 1e-12);
    }
}

#[test]
fn full_spectrum_separates_forward_and_backward_whirl() {
    // 960 Hz, N = 1024: 0.9375 Hz bins, 30 Hz is bin 32.
    let (len, fs) = (1024, 960.0);
    let t = |n: usize| n as f64 / fs;
    let w = 2.0 * PI * 30.0;
    let x: Vec<f64> = (0..len).map(|n| (w * t(n)).cos()).collect();
    let y_forward: Vec<f64> = (0..len).map(|n| (w * t(n)).sin()).collect();
    let y_backward: Vec<f64> = y_forward.iter().map(|v| -v).collect();
    for window in WINDOWS {
        for (y, sign) in [(&y_forward, 1.0), (&y_backward, -1.0)] {
            let full = full_spectrum(&x, y, fs, window).unwrap();
            assert_eq!(full.amplitude.len(), len);
            assert_eq!(full.frequency_hz[0], -480.0);
            assert_eq!(full.frequency_hz[len - 1], 479.0625);
            let (j, peak) = full
                .amplitude
                .iter()
                .enumerate()
                .fold((0, 0.0), |b, (j, a)| if *a > b.1 { (j, *a) } else { b });
            assert_eq!(full.frequency_hz[j], sign * 30.0, "{window}");
            // A bin-centred circle: radius 1 to FFT round-off.
            assert!((peak - 1.0).abs() < 1e-12, "{window}: {peak}");
            // Its mirror reads nothing but round-off.
            let mirror = full
                .frequency_hz
                .iter()
                .position(|f| *f == -sign * 30.0)
                .unwrap();
            assert!(full.amplitude[mirror] < 1e-12);
        }
    }
    // An ellipse x = a cos, y = b sin is a forward circle (a + b) / 2 plus a backward one
    // (a - b) / 2.
    let (a, b) = (3e-5, 1e-5);
    let xs: Vec<f64> = x.iter().map(|v| a * v).collect();
    let ys: Vec<f64> = y_forward.iter().map(|v| b * v).collect();
    let mut planner = FullSpectrumPlanner::new(len, fs, SpectrumOptions::default()).unwrap();
    let full = planner.spectrum(&xs, &ys).unwrap();
    let at = |f: f64| full.amplitude[full.frequency_hz.iter().position(|g| *g == f).unwrap()];
    assert!((at(30.0) - 2e-5).abs() < 1e-12 * a);
    assert!((at(-30.0) - 1e-5).abs() < 1e-12 * a);
}

#[test]
fn the_planner_reuses_its_plan_and_matches_the_one_shot_spectrum() {
    let (len, fs) = (600, 300.0);
    let mut planner = SpectrumPlanner::new(len, fs, SpectrumOptions::default()).unwrap();
    assert_eq!(planner.len(), len);
    assert_eq!(planner.bins(), 301);
    assert_eq!(planner.resolution_hz(), 0.5);
    let mut amplitude = vec![0.0; planner.bins()];
    for f in [12.25, 40.0, 77.7] {
        let signal = sines(len, fs, &[(f, 2.0, 0.1)]);
        planner.process(&signal, &mut amplitude).unwrap();
        let once = amplitude_spectrum(&signal, fs, Window::Hann).unwrap();
        // Same plan, same arithmetic: identical bits.
        assert_eq!(amplitude, once.amplitude);
    }
    // Wrong lengths are errors, not panics.
    assert!(planner.process(&[0.0; 599], &mut amplitude).is_err());
    assert!(planner.process(&[0.0; 600], &mut [0.0; 300]).is_err());
}

fn message(result: Result<impl std::fmt::Debug, Error>) -> String {
    match result {
        Err(Error::InvalidOption(message)) => message,
        other => panic!("expected a numerical error, got {other:?}"),
    }
}

#[test]
fn bad_inputs_are_errors_with_clear_messages() {
    let good = vec![0.0; 16];
    assert!(message(amplitude_spectrum(&[], 100.0, Window::Hann)).contains("empty"));
    assert!(message(amplitude_spectrum(&[1.0; 7], 100.0, Window::Hann)).contains("at least 8"));
    for rate in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        assert!(message(amplitude_spectrum(&good, rate, Window::Hann)).contains("sample rate"));
        assert!(message(full_spectrum(&good, &good, rate, Window::Hann)).contains("sample rate"));
    }
    for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
        let mut signal = good.clone();
        signal[5] = bad;
        let text = message(amplitude_spectrum(&signal, 100.0, Window::Hann));
        assert!(
            text.contains("sample 5") && text.contains("finite"),
            "{text}"
        );
        let text = message(full_spectrum(&good, &signal, 100.0, Window::Hann));
        assert!(text.contains("sample 5 of the y"), "{text}");
    }
    assert!(message(full_spectrum(&good, &good[..10], 100.0, Window::Hann)).contains("y"));
    assert!(message(full_spectrum(&[], &[], 100.0, Window::Hann)).contains("empty"));
    assert!(SpectrumPlanner::new(3, 100.0, SpectrumOptions::default()).is_err());
    assert!(FullSpectrumPlanner::new(16, 0.0, SpectrumOptions::default()).is_err());
}
