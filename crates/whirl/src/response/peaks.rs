//! Resonance peaks of a response curve: amplification factor by the half-power method and
//! the API 617 separation margin.
//!
//! Half-power: N1 and N2 are the speeds on either side of the peak speed Nc where the
//! amplitude falls to peak / sqrt(2); AF = Nc / (N2 - N1).
//!
//! API 617 (7th ed., as commonly quoted): no margin is required when AF < 2.5. Otherwise
//! the required separation margin, in percent of the nearest operating speed limit, is
//! 17 (1 - 1 / (AF - 1.5)) for a critical speed below the minimum operating speed and
//! 10 + 17 (1 - 1 / (AF - 1.5)) for one above the maximum continuous speed.
//!
//! The margins separate critical speeds from a machine's continuous running range. A range
//! that starts below [`API617_MIN_SPEED_RATIO`] of its top (from near rest, as a model that
//! only states where it may run often does) holds every critical speed below the top, so
//! every peak would fail: for such a range the margins are reported as not applicable
//! ([`margins_not_applicable`]) rather than assessed.

use serde::Serialize;

/// One peak of a response over speed.
#[derive(Debug, Clone, Serialize)]
pub struct ResponsePeak {
    /// Speed of the peak, Hz.
    pub speed_hz: f64,
    /// Peak amplitude (the curve's unit).
    pub amplitude: f64,
    /// Half-power speeds (N1, N2), Hz, when both lie in the sweep.
    pub half_power_hz: Option<(f64, f64)>,
    /// Amplification factor Nc / (N2 - N1).
    pub amplification_factor: Option<f64>,
    /// Margin API 617 requires, percent.
    pub required_margin_pct: Option<f64>,
    /// Actual margin from the operating range, percent (negative inside the range); `None`
    /// without a range or when margins are not applicable to it.
    pub actual_margin_pct: Option<f64>,
    /// Whether the actual margin meets the requirement (`None` as for the actual margin).
    pub meets_api617: Option<bool>,
}

/// Lowest ratio of the minimum to the maximum operating speed for which API 617 margins are
/// assessed: below it the range is taken for a run-up from near rest, not a running range
/// (continuous ranges of compressors and turbines span well under 10:1).
pub const API617_MIN_SPEED_RATIO: f64 = 0.1;

/// Why API 617 separation margins mean nothing for the operating range `operating_hz`
/// (minimum, maximum, Hz), or `None` when they apply.
pub fn margins_not_applicable(operating_hz: (f64, f64)) -> Option<String> {
    let (lo, hi) = operating_hz;
    (lo < API617_MIN_SPEED_RATIO * hi).then(|| {
        format!(
            "not applicable: the operating range starts at {lo:.2} Hz, below {:.0} % of its top \
             ({hi:.2} Hz), so every critical speed below the top lies inside it; set [operating] \
             min_speed to the lowest continuous running speed to assess separation margins",
            100.0 * API617_MIN_SPEED_RATIO
        )
    })
}

/// Required API 617 separation margin (percent) for an amplification factor, below or above
/// the operating range.
pub fn separation_margin(amplification_factor: f64, above_range: bool) -> f64 {
    if amplification_factor < 2.5 {
        return 0.0;
    }
    let base = 17.0 * (1.0 - 1.0 / (amplification_factor - 1.5));
    if above_range {
        10.0 + base
    } else {
        base
    }
}

/// Speed where `y` crosses `level` between samples `a` and `b` (linear interpolation).
fn crossing(x: &[f64], y: &[f64], a: usize, b: usize, level: f64) -> f64 {
    let t = (level - y[a]) / (y[b] - y[a]);
    x[a] + t * (x[b] - x[a])
}

/// Whether sample `k` (not the first or last) is a local maximum: strictly higher than its
/// left neighbour and not lower than its right one.
pub(crate) fn is_peak(y: &[f64], k: usize) -> bool {
    y[k] > y[k - 1] && y[k] >= y[k + 1]
}

/// How far a local maximum must rise above its surroundings, in units of the round-off
/// estimated at the two samples that define its prominence, to count as a peak. Measured on
/// the reference rotor's unbalance response sampled finely near its first critical speed,
/// where round-off is largest: ripples rose at most 0.18 of that sum at 2,000 elements and
/// 0.92 at 10,000 (the estimate overstates the scatter about fivefold), while the resonance
/// stood 83 times above it at 2,000 elements. Twice the largest ripple keeps every ripple
/// out and, the round-off growing as the cube of the element count, the resonance in up to
/// about 5,000 elements; finer, its top is round-off too.
const ROUND_OFF_MARGIN: f64 = 2.0;

/// The sample the prominence of the local maximum at `k` is measured from: of the lowest
/// samples on either side before one higher than `y[k]` (or the curve's end), the higher.
/// `None` when `k` is an end of the curve.
pub(crate) fn prominence_base(y: &[f64], k: usize) -> Option<usize> {
    let lowest = |side: &mut dyn Iterator<Item = usize>| {
        side.take_while(|&j| y[j] <= y[k])
            .min_by(|&a, &b| y[a].total_cmp(&y[b]))
    };
    let left = lowest(&mut (0..k).rev());
    let right = lowest(&mut (k + 1..y.len()));
    match (left, right) {
        (Some(a), Some(b)) => Some(if y[a] >= y[b] { a } else { b }),
        (one, None) | (None, one) => one,
    }
}

/// Whether the local maximum at `k` stands above the curve's round-off, `round_off(j)` being
/// the size of the error in `y[j]`: its prominence (its height above its
/// [`prominence_base`]) exceeds [`ROUND_OFF_MARGIN`] times the round-off of the two samples
/// that define it. A ripple of round-off on a smooth curve falls back within its own
/// round-off before the curve rises past it; a resonance falls far below its top on both
/// sides.
pub(crate) fn stands_above_round_off(
    y: &[f64],
    k: usize,
    round_off: impl Fn(usize) -> f64,
) -> bool {
    prominence_base(y, k)
        .is_none_or(|base| y[k] - y[base] > ROUND_OFF_MARGIN * (round_off(k) + round_off(base)))
}

/// A curve's local maxima, as sample indices, ascending.
pub(crate) struct Maxima {
    /// Those that stand above the curve's round-off: its peaks.
    pub resolved: Vec<usize>,
    /// Those that do not.
    pub within_round_off: Vec<usize>,
}

/// Each local maximum of `y` with the sample its prominence is measured from.
pub(crate) fn maxima_with_bases(y: &[f64]) -> Vec<(usize, Option<usize>)> {
    (1..y.len().saturating_sub(1))
        .filter(|&k| is_peak(y, k))
        .map(|k| (k, prominence_base(y, k)))
        .collect()
}

/// The samples whose round-off the maxima of every curve (from [`maxima_with_bases`]) need,
/// ascending, each once.
pub(crate) fn samples_to_check(candidates: &[Vec<(usize, Option<usize>)>]) -> Vec<usize> {
    let mut samples: Vec<usize> = candidates
        .iter()
        .flatten()
        .flat_map(|&(k, base)| std::iter::once(k).chain(base))
        .collect();
    samples.sort_unstable();
    samples.dedup();
    samples
}

/// The maxima `candidates` of `y` split by [`stands_above_round_off`].
pub(crate) fn split_maxima(
    y: &[f64],
    candidates: &[(usize, Option<usize>)],
    round_off: impl Fn(usize) -> f64,
) -> Maxima {
    let (resolved, within_round_off) = candidates
        .iter()
        .map(|&(k, _)| k)
        .partition(|&k| stands_above_round_off(y, k, &round_off));
    Maxima {
        resolved,
        within_round_off,
    }
}

/// The nearest samples on either side of the peak at `k` that lie below `level`, if any.
pub(crate) fn samples_below(y: &[f64], k: usize, level: f64) -> (Option<usize>, Option<usize>) {
    let below = (0..k).rev().find(|&j| y[j] < level);
    let above = (k + 1..y.len()).find(|&j| y[j] < level);
    (below, above)
}

/// Local maxima of `y` over `x` (strictly higher than both neighbours), with their
/// half-power bands and margins (only the required margin when there is no operating range,
/// or one for which margins are not applicable), of those that `keep` keeps (for example
/// those that stand above the curve's round-off, [`stands_above_round_off`]).
pub(crate) fn find_peaks(
    x: &[f64],
    y: &[f64],
    operating: Option<(f64, f64)>,
    keep: impl Fn(usize) -> bool,
) -> Vec<ResponsePeak> {
    let operating = operating.filter(|&range| margins_not_applicable(range).is_none());
    let mut peaks = Vec::new();
    for k in 1..y.len().saturating_sub(1) {
        if !(is_peak(y, k) && keep(k)) {
            continue;
        }
        let (xc, yc) = refine_peak(x, y, k);
        let level = yc / std::f64::consts::SQRT_2;
        let (below, above) = samples_below(y, k, level);
        let left = below.map(|j| crossing(x, y, j, j + 1, level));
        let right = above.map(|j| crossing(x, y, j - 1, j, level));
        let band = left.zip(right);
        let af = band.map(|(n1, n2)| xc / (n2 - n1));
        let (required, actual, meets) = match (af, operating) {
            (Some(af), Some((lo, hi))) => {
                let (actual, above) = if xc < lo {
                    (100.0 * (lo - xc) / lo, false)
                } else if xc > hi {
                    (100.0 * (xc - hi) / hi, true)
                } else {
                    (-100.0 * (xc - lo).min(hi - xc) / hi, false)
                };
                let req = separation_margin(af, above);
                (Some(req), Some(actual), Some(af < 2.5 || actual >= req))
            }
            (Some(af), None) => (Some(separation_margin(af, false)), None, None),
            _ => (None, None, None),
        };
        peaks.push(ResponsePeak {
            speed_hz: xc,
            amplitude: yc,
            half_power_hz: band,
            amplification_factor: af,
            required_margin_pct: required,
            actual_margin_pct: actual,
            meets_api617: meets,
        });
    }
    peaks
}

/// Peak location and height from a parabola through the three samples around `k`.
fn refine_peak(x: &[f64], y: &[f64], k: usize) -> (f64, f64) {
    let (x0, x1, x2) = (x[k - 1], x[k], x[k + 1]);
    let (y0, y1, y2) = (y[k - 1], y[k], y[k + 1]);
    let d0 = (y1 - y0) / (x1 - x0);
    let d1 = (y2 - y1) / (x2 - x1);
    let curvature = (d1 - d0) / (x2 - x0);
    if curvature >= 0.0 || !curvature.is_finite() {
        return (x1, y1);
    }
    // Newton form p(x) = y0 + d0 (x - x0) + c (x - x0)(x - x1); vertex where p' = 0.
    let xv = 0.5 * (x0 + x1) - d0 / (2.0 * curvature);
    let yv = y0 + d0 * (xv - x0) + curvature * (xv - x0) * (xv - x1);
    if xv < x0 || xv > x2 {
        (x1, y1)
    } else {
        (xv, yv)
    }
}

// Refinement of a sampled response around its peaks, shared by the unbalance response
// (over speed) and the FRF (over frequency).

/// Steps a peak's half-power band is refined to: the parabola through the top three
/// samples then misses the peak of a resonance by about (1/40)^2 of the band's curvature
/// scale, well under 0.1 %, and the half-power crossings are interpolated over 1/40 of
/// the band.
pub const BAND_SAMPLES: f64 = 40.0;

/// Most refinement passes. Each halves the steps inside the bands, so 16 passes resolve a
/// half-power band 2^16 / [`BAND_SAMPLES`] = 1,638 times narrower than the requested step:
/// with the default 800 speeds up to 900 Hz, a mode at 50 Hz with a damping ratio of 7e-6,
/// below the material damping of a steel shaft (about 1e-4). A narrower band is that of a
/// mode without damping, which no grid resolves; more passes would only add speeds beside
/// its top. Peaks of round-off are not refined at all, so the passes end as soon as the
/// resonances are resolved.
pub(crate) const REFINE_PASSES: usize = 16;

/// Fraction of a peak's height above which its steps are refined: the loop of the polar
/// plot spans most of its sweep there (a single mode's amplitude falls to a quarter at
/// about 2 half-power widths from the peak).
const REFINE_LEVEL: f64 = 0.25;

/// ... and within this many half-power widths of the peak: a single mode's response falls
/// to a quarter about 2 widths away, so a resonance's refinement is not cut by it.
const REFINE_REACH: f64 = 4.0;

/// Midpoints of the steps wider than 1/[`BAND_SAMPLES`] of a peak's half-power band where
/// the curve is above [`REFINE_LEVEL`] of the peak, over the `maxima` of every curve of
/// `curves` sampled at `xs` (those that stand above its round-off), sorted and unique. A band whose edge
/// lies outside the sweep is measured to the sweep's end, so a broad rise is left alone.
pub(crate) fn refinement_points(xs: &[f64], curves: &[Vec<f64>], maxima: &[Maxima]) -> Vec<f64> {
    let mut added = Vec::new();
    for (major, maxima) in curves.iter().zip(maxima) {
        for &k in &maxima.resolved {
            let (low, high) = band(major, k, major[k] / std::f64::consts::SQRT_2);
            let width = xs[high] - xs[low];
            let step = width / BAND_SAMPLES;
            let (low, high) = band(major, k, REFINE_LEVEL * major[k]);
            // A small maximum on a large curve (a bearing node's response riding on the
            // shaft's resonance) stays above a quarter of its height far from it; without
            // this reach its narrow band refined the whole sweep (24,198 speeds for the
            // reference rotor at 40 elements).
            let reach = REFINE_REACH * width;
            added.extend(
                (low..high)
                    .filter(|&j| xs[j + 1] - xs[j] > step)
                    .filter(|&j| xs[j + 1] >= xs[k] - reach && xs[j] <= xs[k] + reach)
                    .map(|j| 0.5 * (xs[j] + xs[j + 1])),
            );
        }
    }
    added.sort_by(f64::total_cmp);
    added.dedup();
    added
}

/// The nearest samples on either side of the peak at `k` below `level` (the ends of the
/// curve when it stays above).
fn band(y: &[f64], k: usize, level: f64) -> (usize, usize) {
    let (below, above) = samples_below(y, k, level);
    (below.unwrap_or(0), above.unwrap_or(y.len() - 1))
}

/// Two ascending lists of points and their samples merged into one ascending list.
pub(crate) fn merge_sorted<T>(
    xs: Vec<f64>,
    samples: Vec<T>,
    added: Vec<f64>,
    added_samples: Vec<T>,
) -> (Vec<f64>, Vec<T>) {
    let mut pairs: Vec<(f64, T)> = xs
        .into_iter()
        .zip(samples)
        .chain(added.into_iter().zip(added_samples))
        .collect();
    pairs.sort_by(|a, b| a.0.total_cmp(&b.0));
    pairs.dedup_by(|a, b| a.0 == b.0);
    pairs.into_iter().unzip()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn half_power_of_a_single_dof_resonance() {
        // |H| = 1 / sqrt((1 - r^2)^2 + (2 zeta r)^2): AF = 1 / (2 zeta) to first order in zeta.
        let zeta = 0.01;
        let x: Vec<f64> = (0..20001).map(|i| 0.5 + i as f64 * 1e-4).collect();
        let y: Vec<f64> = x
            .iter()
            .map(|r| 1.0 / ((1.0 - r * r).powi(2) + (2.0 * zeta * r).powi(2)).sqrt())
            .collect();
        let peaks = find_peaks(&x, &y, Some((2.0, 3.0)), |_| true);
        assert_eq!(peaks.len(), 1);
        let p = &peaks[0];
        // Peak at sqrt(1 - 2 zeta^2), height 1 / (2 zeta sqrt(1 - zeta^2)): parabolic
        // refinement on a 1e-4 grid is good to 1e-6.
        assert!((p.speed_hz - (1.0f64 - 2.0 * zeta * zeta).sqrt()).abs() < 1e-6);
        assert!((p.amplitude * 2.0 * zeta * (1.0 - zeta * zeta).sqrt() - 1.0).abs() < 1e-5);
        // The half-power estimate of 1/(2 zeta) is exact to O(zeta^2): 0.2 % here.
        let af = p.amplification_factor.unwrap();
        assert!((af / 50.0 - 1.0).abs() < 2e-3, "{af}");
        // Below the range: 17 (1 - 1/(AF - 1.5)) = 16.65 %; actual margin is 50 %.
        let req = p.required_margin_pct.unwrap();
        assert!((req - 17.0 * (1.0 - 1.0 / (af - 1.5))).abs() < 1e-12);
        assert_eq!(p.meets_api617, Some(true));
    }

    #[test]
    fn margins_need_a_running_range_not_a_run_up() {
        // The resonance of the test above (r = 1) inside a range from 0.05 (below 10 % of
        // the top, 2) would fail; from 0.5 it still fails, assessed.
        let x: Vec<f64> = (0..2001).map(|i| 0.5 + i as f64 * 1e-3).collect();
        let y: Vec<f64> = x
            .iter()
            .map(|r| 1.0 / ((1.0 - r * r).powi(2) + (0.02 * r).powi(2)).sqrt())
            .collect();
        let run_up = find_peaks(&x, &y, Some((0.05, 2.0)), |_| true);
        assert_eq!(run_up[0].meets_api617, None);
        assert_eq!(run_up[0].actual_margin_pct, None);
        assert!(run_up[0].required_margin_pct.is_some());
        let running = find_peaks(&x, &y, Some((0.5, 2.0)), |_| true);
        assert_eq!(running[0].meets_api617, Some(false));
        // The rule's edge: exactly 10 % of the top is assessed, just below is not.
        assert!(margins_not_applicable((0.2, 2.0)).is_none());
        let why = margins_not_applicable((0.199, 2.0)).unwrap();
        assert!(why.contains("[operating] min_speed"), "{why}");
    }

    #[test]
    fn ripples_within_the_round_off_are_no_peaks() {
        // Two resonances (r = 1 and r = 1.5, the second a shoulder of the first's tail) on a
        // fine grid, with a deterministic ripple of 1e-3 of the curve, up and down at two of
        // every three samples, as round-off makes on a fine mesh: the ripple makes local
        // maxima wherever the curve changes by less per step, and each sample's round-off is
        // said to be 1e-3 of it.
        let x: Vec<f64> = (0..20001).map(|i| 0.5 + i as f64 * 1e-4).collect();
        let resonance = |r: f64, at: f64| 1.0 / ((1.0 - (r / at).powi(2)).powi(2) + 4e-4).sqrt();
        let smooth: Vec<f64> = x
            .iter()
            .map(|&r| resonance(r, 1.0) + 0.5 * resonance(r, 1.5))
            .collect();
        let ripple = [1e-3, -1e-3, 0.0];
        let y: Vec<f64> = smooth
            .iter()
            .enumerate()
            .map(|(i, v)| v * (1.0 + ripple[i % 3]))
            .collect();
        let round_off: Vec<f64> = smooth.iter().map(|v| 1e-3 * v).collect();
        let maxima = (1..y.len() - 1).filter(|&k| is_peak(&y, k)).count();
        assert!(maxima > 1000, "the ripple makes local maxima: {maxima}");
        let peaks = find_peaks(&x, &y, None, |k| {
            stands_above_round_off(&y, k, |j| round_off[j])
        });
        let at: Vec<f64> = peaks.iter().map(|p| p.speed_hz).collect();
        assert_eq!(at.len(), 2, "{at:?}");
        // The peaks of |H| with 1 % damping sit at r = sqrt(1 - 2 zeta^2) of each mode, within
        // the grid's 1e-4 and the other mode's slope.
        assert!(
            (at[0] - 1.0).abs() < 1e-3 && (at[1] - 1.5).abs() < 2e-3,
            "{at:?}"
        );
        // Without the round-off every maximum counts.
        assert_eq!(find_peaks(&x, &y, None, |_| true).len(), maxima);
    }

    #[test]
    fn margins_follow_api617() {
        assert_eq!(separation_margin(2.0, false), 0.0);
        assert!((separation_margin(3.5, false) - 8.5).abs() < 1e-12);
        assert!((separation_margin(3.5, true) - 18.5).abs() < 1e-12);
    }
}
