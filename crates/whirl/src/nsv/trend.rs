//! How an NSV line moves with the running speed, and which lines stand beside it: the
//! evidence [`super::classify`] names a mechanism by (docs/theory.md section 8).
//!
//! # The slope
//!
//! A line's frequency against the running speed tells the mechanisms apart: a whip or whirl
//! locked at a natural frequency stays put (`df/dOmega ~ 0`, drifting only as the contact
//! stiffness changes with speed), a subharmonic `Omega/n` moves at `1/n`, a
//! varying-compliance tone `m N_b w_c +- n Omega` at its own order `f/Omega`, and a
//! combination resonance `f = k Omega - f_j` at about `k` (less where the partner mode is
//! pulled along). At each settled neighbour within [`window_hz`] of the speed, but not
//! nearer than the tolerance (two bins: closer speeds move a line by less than the
//! frequency is known to), the line is found again: the largest non-synchronous spectral
//! line within `tol + reach |dOmega|` of the frequency, where `reach` covers every slope
//! named here. The slope is the median over those neighbours of `df / dOmega`, so a
//! neighbour where the line has gone (the search then finds another line) does not pull
//! it, and it depends neither on the order of the points nor on how finely the grid is
//! refined: the window is in hertz of speed, not a count of neighbours.
//!
//! # Companions
//!
//! A combination resonance `f + f_j = k Omega` (sum type) shows its partner at
//! `k Omega - f` in the same spectrum; a difference type `f_j - f = k Omega` shows it at
//! `k Omega + f`. A companion is a spectral line within the tolerance of one of these, clear
//! of the noise floor ([`COMPANION_FLOOR`] times the spectrum's median) and at least
//! [`COMPANION_FRACTION`] of the NSV. A locked whip has companions too (the nonlinear
//! contacts mix it with the unbalance response into `Omega -+ f`), so a companion confirms
//! a combination but never makes one: the slope does.

use crate::post::{spectral_peaks_above, SpectralPeak, Spectrum, Window};

use super::point::CascadePoint;

/// Least half-width of the speed window a slope is measured over, Hz: two steps of the
/// default 150-speed grid over 1-750 Hz plus a margin, and narrow enough to stay inside the
/// 16 Hz of speed over which the reference rotor's 20 um combination resonance lives.
pub const WINDOW_MIN_HZ: f64 = 12.0;

/// The window is at least this many tolerances wide (a coarse record's wide bins need
/// more speed for a line to move by a measurable amount).
const WINDOW_TOLERANCES: f64 = 3.0;

/// Steepest slope a line is followed with (combination resonances up to `k = 2`, with a
/// margin for the pull of the partner mode).
const REACH_SLOPE: f64 = 2.5;

/// A line followed at its own order (a super-synchronous varying-compliance tone moves at
/// `f/Omega`, up to about 11 for `3 N_b w_c`) is searched this much beyond that slope.
const REACH_ORDER_MARGIN: f64 = 1.25;

/// A spectral line stands this many times above the spectrum's median (its noise floor):
/// on the reference rotor the companions of the NSV stand 10-200 times above it.
pub const COMPANION_FLOOR: f64 = 10.0;

/// A companion is at least this fraction of the NSV: on the reference rotor they are
/// 0.4-15 % of it (0.8 % at the 20 um maximum), so this keeps them all and drops the
/// intermodulation debris of a large NSV further down.
pub const COMPANION_FRACTION: f64 = 1e-3;

/// Multiples `k` of the running speed tried for companions `k Omega -+ f`.
pub const COMPANION_ORDERS: usize = 2;

/// How the cascade's spectra are read: bin spacing and window, and the tolerance.
#[derive(Debug, Clone, Copy)]
pub struct Reading {
    /// Bin spacing, Hz.
    pub resolution_hz: f64,
    /// The window of the spectra.
    pub window: Window,
    /// The cascade's tolerance, Hz (`tolerance_bins` times the bin spacing).
    pub tolerance_hz: f64,
}

/// Half-width of the speed window a slope is measured over, Hz.
pub fn window_hz(tolerance_hz: f64) -> f64 {
    WINDOW_MIN_HZ.max(WINDOW_TOLERANCES * tolerance_hz)
}

/// The non-synchronous spectral lines of one point, refined between bins, and its floor.
#[derive(Debug, Clone, Default)]
pub(super) struct Lines {
    /// Lines clear of the floor, at least the tolerance from every multiple of the speed.
    lines: Vec<SpectralPeak>,
}

impl Lines {
    /// The lines of `point`'s one-sided spectrum (none where it kept no spectrum).
    pub(super) fn of(point: &CascadePoint, r: &Reading) -> Lines {
        if point.amplitude.len() < 3 {
            return Lines::default();
        }
        let floor = median(&point.amplitude) * COMPANION_FLOOR;
        let spectrum = Spectrum {
            frequency_hz: (0..point.amplitude.len())
                .map(|k| k as f64 * r.resolution_hz)
                .collect(),
            amplitude: point.amplitude.clone(),
            resolution_hz: r.resolution_hz,
            window: r.window,
        };
        let speed = point.speed_hz;
        let synchronous = |f: f64| {
            let k = (f / speed).round();
            (f - k * speed).abs() <= r.tolerance_hz
        };
        let lines = spectral_peaks_above(&spectrum, speed, floor)
            .into_iter()
            .filter(|p| !synchronous(p.frequency_hz))
            .collect();
        Lines { lines }
    }

    /// The largest line within `half_width_hz` of `frequency_hz`.
    fn largest_near(&self, frequency_hz: f64, half_width_hz: f64) -> Option<&SpectralPeak> {
        self.lines
            .iter()
            .filter(|p| (p.frequency_hz - frequency_hz).abs() <= half_width_hz)
            .max_by(|a, b| a.amplitude.total_cmp(&b.amplitude))
    }
}

/// The median of `x`, the mean of the middle two for an even count (0 for none).
fn median(x: &[f64]) -> f64 {
    let mut sorted: Vec<f64> = x.iter().copied().filter(|v| v.is_finite()).collect();
    sorted.sort_by(f64::total_cmp);
    match sorted.len() {
        0 => 0.0,
        n if n % 2 == 1 => sorted[n / 2],
        n => 0.5 * (sorted[n / 2 - 1] + sorted[n / 2]),
    }
}

/// How a point's NSV line moves with speed around it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Trend {
    /// Median `df/dOmega` over the neighbours where the line was found, Hz per Hz.
    pub slope: f64,
    /// Neighbours it was measured over.
    pub neighbours: usize,
    /// Lowest and highest of those neighbours' speeds, with the point's own, Hz.
    pub span_hz: (f64, f64),
}

/// The trend of the NSV of point `i` (see the module documentation); `None` when no
/// settled neighbour in the window shows the line.
pub(super) fn trend(
    points: &[CascadePoint],
    lines: &[Lines],
    i: usize,
    r: &Reading,
) -> Option<Trend> {
    let p = &points[i];
    let peak = p.peak?;
    let f = peak.frequency_hz;
    let window = window_hz(r.tolerance_hz);
    let reach = REACH_SLOPE.max(REACH_ORDER_MARGIN * peak.order.abs());
    let mut slopes = Vec::new();
    let mut span = (p.speed_hz, p.speed_hz);
    for (q, q_lines) in points.iter().zip(lines) {
        let d_speed = q.speed_hz - p.speed_hz;
        let far_enough = d_speed.abs() >= r.tolerance_hz && d_speed.abs() <= window;
        if !far_enough || !q.settled || q.diverged.is_some() {
            continue;
        }
        let Some(line) = q_lines.largest_near(f, r.tolerance_hz + reach * d_speed.abs()) else {
            continue;
        };
        slopes.push((line.frequency_hz - f) / d_speed);
        span = (span.0.min(q.speed_hz), span.1.max(q.speed_hz));
    }
    if slopes.is_empty() {
        return None;
    }
    Some(Trend {
        slope: median(&slopes),
        neighbours: slopes.len(),
        span_hz: span,
    })
}

/// A line beside the NSV at `k Omega - f` (sum type) or `k Omega + f` (difference type).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Companion {
    /// Its frequency, Hz.
    pub frequency_hz: f64,
    /// Its amplitude over the NSV's.
    pub relative: f64,
    /// The multiple `k` of the running speed.
    pub order: usize,
    /// Whether it is the sum type's partner `k Omega - f` (else `k Omega + f`).
    pub sum: bool,
}

/// The largest companion of point `p`'s NSV in its own spectrum; `None` when none stands
/// clear (see the module documentation).
pub(super) fn companion(p: &CascadePoint, lines: &Lines, r: &Reading) -> Option<Companion> {
    let peak = p.peak?;
    let (f, speed) = (peak.frequency_hz, p.speed_hz);
    let mut best: Option<Companion> = None;
    for k in 1..=COMPANION_ORDERS {
        let k_speed = k as f64 * speed;
        for (sum, target) in [(true, k_speed - f), (false, k_speed + f)] {
            // At Omega/2k the sum type's partner is the line itself.
            if target <= 0.0 || (target - f).abs() <= r.tolerance_hz {
                continue;
            }
            let Some(line) = lines.largest_near(target, r.tolerance_hz) else {
                continue;
            };
            let relative = line.amplitude / peak.amplitude_m;
            if relative >= COMPANION_FRACTION && best.is_none_or(|b| relative > b.relative) {
                best = Some(Companion {
                    frequency_hz: line.frequency_hz,
                    relative,
                    order: k,
                    sum,
                });
            }
        }
    }
    best
}
