//! The NSV of a whole cascade in a few numbers: where it starts, how large it gets, how
//! large it is over the speed range, and what kind dominates.
//!
//! Only settled speeds count ([`NsvClass::Unsettled`] and diverged speeds are listed
//! apart). The statistics over the speed range weigh each settled speed by the stretch of
//! speed it stands for (half the distance to each neighbour), so they approximate the
//! distribution of the NSV over the range itself: speeds added by the refinement where
//! the NSV changes sharply do not pull them, and a finer grid converges to the same
//! numbers instead of counting a narrow burst more often.

use serde::Serialize;

use super::classify::{Nsv, NsvClass, WhirlDirection};
use super::point::CascadePoint;

/// Default NSV threshold, m: 1 um zero-to-peak at the disk, about a thirtieth of the
/// largest NSV the thesis reports for the reference rotor (3e-5 m at 20 um clearance,
/// fig. 5.5) and 40 times the amplitude of the reference rotor's 4e-5 m unbalance would
/// need to excite at rest; below it a peak is a detail of the spectrum, above it a
/// vibration an engineer would look at.
pub const DEFAULT_THRESHOLD_M: f64 = 1e-6;

/// A speed and the NSV amplitude there.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct SpeedLevel {
    /// Spin speed, Hz.
    pub speed_hz: f64,
    /// NSV amplitude, m (0 where there is no non-synchronous peak).
    pub amplitude_m: f64,
}

/// The largest NSV of a cascade, and how well the speed grid resolves it.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct LargestNsv {
    /// Spin speed, Hz.
    pub speed_hz: f64,
    /// Frequency, Hz.
    pub frequency_hz: f64,
    /// Zero-to-peak amplitude, m.
    pub amplitude_m: f64,
    /// Standard error of the amplitude over the records averaged there, m.
    pub standard_error_m: f64,
    /// Records averaged there.
    pub records: usize,
    /// Frequency over running speed.
    pub order: f64,
    /// Its class.
    pub class: NsvClass,
    /// Its whirl direction.
    pub direction: WhirlDirection,
    /// The nearest settled speeds below and above, with their NSV.
    pub neighbours: Vec<SpeedLevel>,
    /// Distance to the nearer neighbour, Hz: the grid's resolution at the largest NSV.
    pub spacing_hz: Option<f64>,
}

/// The onset of NSV at a level, bracketed by the grid.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Onset {
    /// The level, m.
    pub level_m: f64,
    /// The lowest settled speed whose NSV reaches the level, Hz.
    pub speed_hz: f64,
    /// The settled speed just below it (whose NSV stays under the level), Hz.
    pub below_hz: Option<f64>,
    /// The lowest settled speed from which the NSV stays at or above the level over at
    /// least [`SUSTAINED_FRACTION`] of the next [`SUSTAINED_WINDOW`] of the speed range,
    /// Hz: where the NSV sets in for good, not a narrow resonance below it. `None` when no
    /// stretch holds it.
    pub sustained_hz: Option<f64>,
}

/// Length of the stretch over which a sustained onset must hold, as a share of the
/// cascade's speed range (37 Hz of 1-750 Hz).
pub const SUSTAINED_WINDOW: f64 = 0.05;

/// Share of that stretch (weighed by speed) over which the NSV must reach the level.
pub const SUSTAINED_FRACTION: f64 = 0.5;

/// How large the NSV is over the speed range (settled speeds, each weighed by the stretch
/// of speed it stands for).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct NsvStatistics {
    /// Settled speeds the statistics are taken over.
    pub speeds: usize,
    /// Lowest and highest of them, Hz.
    pub range_hz: (f64, f64),
    /// Median NSV over the range, m.
    pub median_m: f64,
    /// 90th percentile of the NSV over the range, m: exceeded over a tenth of it.
    pub p90_m: f64,
    /// Mean NSV over the range, m.
    pub mean_m: f64,
    /// The NSV integrated over speed (trapezoids), m Hz.
    pub integrated_m_hz: f64,
    /// How far another speed grid (and other records of the same motion) may move the
    /// median, 90th percentile and mean ([`GridSpread`]), m.
    pub uncertainty: GridSpread,
}

/// The uncertainty of statistics taken over a speed grid, from interleaved sub-grids: the
/// speeds dealt in turn into `SUB_GRIDS` sub-grids, each another grid over the same range
/// with its own records, and the statistic taken over each. A sub-grid of a k-th of the
/// speeds scatters about root k times as much as the whole grid does about the statistic
/// over every speed (a sampling error that falls as one over the root of the speeds), so
/// the sub-grids' standard deviation over root k estimates the whole grid's error. NSV that
/// wanders with speed (bursts a few hertz wide, irregular whip) makes this the larger part
/// of a statistic's error: the median of the reference rotor's cascade moved by 12 %
/// between grids of 40 and 110 speeds.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Default)]
pub struct GridSpread {
    /// Of the median, m.
    pub median_m: f64,
    /// Of the 90th percentile, m.
    pub p90_m: f64,
    /// Of the mean, m.
    pub mean_m: f64,
}

/// How many speeds' NSV above the threshold fall in one class, and their largest.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct ClassCount {
    /// The class.
    pub class: NsvClass,
    /// Speeds whose NSV is of this class and at or above the threshold.
    pub speeds: usize,
    /// The largest of them, m.
    pub largest_m: f64,
    /// Their amplitudes summed, m (what "dominant" weighs).
    pub total_m: f64,
}

/// The NSV of a cascade in a few numbers. Unsettled peaks (free vibration still dying away
/// at the longest settling time) are counted in `classes` but never make the onset, the
/// largest, the statistics or the dominant class.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct NsvSummary {
    /// The threshold applied, m.
    pub threshold_m: f64,
    /// The lowest speed whose steady NSV reaches the threshold, Hz.
    pub onset_speed_hz: Option<f64>,
    /// The onset at each level: the threshold, then the refinement's onset levels.
    pub onsets: Vec<Onset>,
    /// The largest steady NSV, wherever it is (threshold or not).
    pub largest: Option<LargestNsv>,
    /// The NSV over the speed range.
    pub statistics: Option<NsvStatistics>,
    /// The class with the largest summed amplitude over the speeds at or above the
    /// threshold.
    pub dominant_class: Option<NsvClass>,
    /// Speeds whose steady NSV reaches the threshold.
    pub speeds_above_threshold: usize,
    /// Per class, the speeds at or above the threshold (classes with none left out).
    pub classes: Vec<ClassCount>,
    /// Speeds added by the refinement of the grid.
    pub added_speeds: usize,
    /// Speeds whose start had not died away at the longest settling time, Hz.
    pub unsettled_speeds_hz: Vec<f64>,
    /// Speeds whose run diverged, Hz.
    pub diverged_speeds_hz: Vec<f64>,
    /// Speeds that started from rest because no static equilibrium was found there, Hz.
    pub started_from_rest_hz: Vec<f64>,
}

/// The NSV level of a point: its steady NSV amplitude (0 without a non-synchronous peak),
/// `None` where it diverged or did not settle.
pub(super) fn level(point: &CascadePoint, nsv: Option<&Nsv>) -> Option<f64> {
    if point.diverged.is_some() || !point.settled {
        return None;
    }
    Some(nsv.map_or(0.0, |n| n.peak.amplitude_m))
}

/// Summarises the classified NSV of `points` (in ascending speed, `nsv` alongside),
/// counting peaks at or above `threshold_m`, with the onsets at `levels_m` too.
pub(super) fn summarise(
    points: &[CascadePoint],
    nsv: &[Option<Nsv>],
    threshold_m: f64,
    levels_m: &[f64],
) -> NsvSummary {
    let settled: Vec<(usize, SpeedLevel)> = points
        .iter()
        .zip(nsv)
        .enumerate()
        .filter_map(|(i, (p, n))| {
            level(p, n.as_ref()).map(|amplitude_m| {
                let speed_hz = p.speed_hz;
                (
                    i,
                    SpeedLevel {
                        speed_hz,
                        amplitude_m,
                    },
                )
            })
        })
        .collect();
    let steady = || nsv.iter().flatten().filter(|n| n.class.is_steady());
    let above = |n: &&Nsv| n.peak.amplitude_m >= threshold_m;
    let mut onsets = Vec::new();
    for level in std::iter::once(threshold_m).chain(levels_m.iter().copied()) {
        if onsets.iter().any(|o: &Onset| o.level_m == level) {
            continue;
        }
        if let Some(onset) = onset_at(&settled, level) {
            onsets.push(onset);
        }
    }
    let largest = largest(points, &settled, nsv);
    let classes: Vec<ClassCount> = NsvClass::ALL
        .iter()
        .map(|&class| {
            let members = || {
                nsv.iter()
                    .flatten()
                    .filter(|n| n.class == class)
                    .filter(above)
            };
            ClassCount {
                class,
                speeds: members().count(),
                largest_m: members().map(|n| n.peak.amplitude_m).fold(0.0, f64::max),
                total_m: members().map(|n| n.peak.amplitude_m).sum(),
            }
        })
        .filter(|c| c.speeds > 0)
        .collect();
    let dominant_class = classes
        .iter()
        .filter(|c| c.class.is_steady())
        .max_by(|a, b| a.total_m.total_cmp(&b.total_m))
        .map(|c| c.class);
    let speeds_where = |keep: &dyn Fn(&CascadePoint) -> bool| {
        points
            .iter()
            .filter(|p| keep(p))
            .map(|p| p.speed_hz)
            .collect()
    };
    NsvSummary {
        threshold_m,
        onset_speed_hz: onsets
            .first()
            .filter(|o| o.level_m == threshold_m)
            .map(|o| o.speed_hz),
        onsets,
        largest,
        statistics: statistics(&settled),
        dominant_class,
        speeds_above_threshold: steady().filter(above).count(),
        classes,
        added_speeds: points.iter().filter(|p| p.added).count(),
        unsettled_speeds_hz: speeds_where(&|p| p.diverged.is_none() && !p.settled),
        diverged_speeds_hz: speeds_where(&|p| p.diverged.is_some()),
        started_from_rest_hz: speeds_where(&|p| p.start_fallback.is_some()),
    }
}

/// The lowest settled speed reaching `level_m`, with the one below it and the sustained
/// onset.
fn onset_at(settled: &[(usize, SpeedLevel)], level_m: f64) -> Option<Onset> {
    let k = settled.iter().position(|(_, s)| s.amplitude_m >= level_m)?;
    Some(Onset {
        level_m,
        speed_hz: settled[k].1.speed_hz,
        below_hz: k.checked_sub(1).map(|j| settled[j].1.speed_hz),
        sustained_hz: sustained_onset(settled, level_m),
    })
}

/// The lowest settled speed at or above `level_m` from which the NSV reaches the level
/// over [`SUSTAINED_FRACTION`] of the next [`SUSTAINED_WINDOW`] of the range. Each gap
/// between neighbouring speeds counts by the trapezoid rule on "reaches the level" (whole
/// when both ends do, half when one does), so the share converges as the grid is refined
/// instead of depending on how many speeds a burst holds.
pub(super) fn sustained_onset(settled: &[(usize, SpeedLevel)], level_m: f64) -> Option<f64> {
    let levels: Vec<&SpeedLevel> = settled.iter().map(|(_, s)| s).collect();
    let (first, last) = (levels.first()?.speed_hz, levels.last()?.speed_hz);
    let window = SUSTAINED_WINDOW * (last - first);
    let reaches = |s: &SpeedLevel| f64::from(u8::from(s.amplitude_m >= level_m));
    for (k, start) in levels.iter().enumerate() {
        if start.amplitude_m < level_m {
            continue;
        }
        let end = start.speed_hz + window;
        if end > last {
            return None;
        }
        let covered: f64 = levels[k..]
            .windows(2)
            .take_while(|pair| pair[0].speed_hz < end)
            .map(|pair| {
                let width = pair[1].speed_hz.min(end) - pair[0].speed_hz;
                0.5 * (reaches(pair[0]) + reaches(pair[1])) * width
            })
            .sum();
        if covered >= SUSTAINED_FRACTION * window {
            return Some(start.speed_hz);
        }
    }
    None
}

/// The largest settled NSV with its neighbours in speed.
fn largest(
    points: &[CascadePoint],
    settled: &[(usize, SpeedLevel)],
    nsv: &[Option<Nsv>],
) -> Option<LargestNsv> {
    let (k, _) = settled
        .iter()
        .enumerate()
        .filter(|(_, (i, _))| nsv[*i].is_some())
        .max_by(|a, b| a.1 .1.amplitude_m.total_cmp(&b.1 .1.amplitude_m))?;
    let (i, here) = settled[k];
    let n = nsv[i].as_ref()?;
    let neighbours: Vec<SpeedLevel> = [k.checked_sub(1), Some(k + 1)]
        .into_iter()
        .flatten()
        .filter_map(|j| settled.get(j).map(|(_, s)| *s))
        .collect();
    let spacing_hz = neighbours
        .iter()
        .map(|s| (s.speed_hz - here.speed_hz).abs())
        .min_by(f64::total_cmp);
    Some(LargestNsv {
        speed_hz: n.speed_hz,
        frequency_hz: n.peak.frequency_hz,
        amplitude_m: n.peak.amplitude_m,
        standard_error_m: n.peak.standard_error_m,
        records: points[i].records,
        order: n.peak.order,
        class: n.class,
        direction: n.direction,
        neighbours,
        spacing_hz,
    })
}

/// Interleaved sub-grids whose statistics give a statistic's uncertainty ([`GridSpread`]):
/// four give three degrees of freedom, where two halves gave one (an estimate that is
/// itself uncertain by a factor of two or more).
pub const SUB_GRIDS: usize = 4;

/// Fewest speeds in a sub-grid for it to stand for the range.
const MIN_SUB_GRID_SPEEDS: usize = 3;

/// Weighted median, 90th percentile, mean and integral of the settled NSV over speed, with
/// their uncertainty over grids.
fn statistics(settled: &[(usize, SpeedLevel)]) -> Option<NsvStatistics> {
    let levels: Vec<SpeedLevel> = settled.iter().map(|(_, s)| *s).collect();
    let mut all = weighted_statistics(&levels)?;
    all.uncertainty = grid_spread(&levels);
    Some(all)
}

/// [`GridSpread`] of `levels` (ascending in speed): zero with fewer than
/// [`MIN_SUB_GRID_SPEEDS`] speeds in a sub-grid, where one says nothing.
fn grid_spread(levels: &[SpeedLevel]) -> GridSpread {
    let k = SUB_GRIDS;
    if levels.len() < k * MIN_SUB_GRID_SPEEDS {
        return GridSpread::default();
    }
    let subs: Vec<NsvStatistics> = (0..k)
        .filter_map(|first| {
            let picked: Vec<SpeedLevel> = levels.iter().skip(first).step_by(k).copied().collect();
            weighted_statistics(&picked)
        })
        .collect();
    let error = |of: fn(&NsvStatistics) -> f64| {
        let values: Vec<f64> = subs.iter().map(of).collect();
        sample_deviation(&values) / (k as f64).sqrt()
    };
    GridSpread {
        median_m: error(|s| s.median_m),
        p90_m: error(|s| s.p90_m),
        mean_m: error(|s| s.mean_m),
    }
}

/// Sample standard deviation (n - 1) of `x`; 0 for fewer than two values.
fn sample_deviation(x: &[f64]) -> f64 {
    if x.len() < 2 {
        return 0.0;
    }
    let n = x.len() as f64;
    let mean = x.iter().sum::<f64>() / n;
    (x.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1.0)).sqrt()
}

/// Weighted median, 90th percentile, mean and integral of `levels` (ascending in speed),
/// without their uncertainty.
fn weighted_statistics(levels: &[SpeedLevel]) -> Option<NsvStatistics> {
    let weights = speed_weights(levels);
    let total: f64 = weights.iter().sum();
    if levels.is_empty() || total.is_nan() || total <= 0.0 {
        return levels.first().map(|s| NsvStatistics {
            speeds: levels.len(),
            range_hz: (s.speed_hz, s.speed_hz),
            median_m: s.amplitude_m,
            p90_m: s.amplitude_m,
            mean_m: s.amplitude_m,
            integrated_m_hz: 0.0,
            uncertainty: GridSpread::default(),
        });
    }
    let integrated_m_hz: f64 = levels
        .iter()
        .zip(&weights)
        .map(|(s, w)| s.amplitude_m * w)
        .sum();
    let mut sorted: Vec<(f64, f64)> = levels
        .iter()
        .zip(&weights)
        .map(|(s, w)| (s.amplitude_m, *w))
        .collect();
    sorted.sort_by(|a, b| a.0.total_cmp(&b.0));
    let quantile = |q: f64| weighted_quantile(&sorted, total, q);
    Some(NsvStatistics {
        speeds: levels.len(),
        range_hz: (levels[0].speed_hz, levels[levels.len() - 1].speed_hz),
        median_m: quantile(0.5),
        p90_m: quantile(0.9),
        mean_m: integrated_m_hz / total,
        integrated_m_hz,
        uncertainty: GridSpread::default(),
    })
}

/// The `q` quantile of values sorted ascending with their weights (summing to `total`),
/// interpolated linearly between the values' midpoints in the weights' cumulative share: a
/// value stands for the middle of its own weight, so the quantile moves smoothly as speeds
/// are added or shifted instead of jumping from one speed's NSV to another's.
fn weighted_quantile(sorted: &[(f64, f64)], total: f64, q: f64) -> f64 {
    let mut below = 0.0;
    let mut previous: Option<(f64, f64)> = None;
    for &(a, w) in sorted {
        let here = (below + 0.5 * w) / total;
        if here >= q {
            return match previous {
                Some((p_share, p_value)) if here > p_share => {
                    p_value + (a - p_value) * (q - p_share) / (here - p_share)
                }
                _ => a,
            };
        }
        previous = Some((here, a));
        below += w;
    }
    sorted.last().map_or(0.0, |s| s.0)
}

/// The stretch of speed each of `levels` (ascending) stands for, Hz: half the distance to
/// each neighbour (the trapezoid rule's weights).
fn speed_weights(levels: &[SpeedLevel]) -> Vec<f64> {
    (0..levels.len())
        .map(|k| {
            let left = k
                .checked_sub(1)
                .map_or(0.0, |j| levels[k].speed_hz - levels[j].speed_hz);
            let right = levels
                .get(k + 1)
                .map_or(0.0, |s| s.speed_hz - levels[k].speed_hz);
            0.5 * (left + right)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn at(speed_hz: f64, amplitude_m: f64) -> SpeedLevel {
        SpeedLevel {
            speed_hz,
            amplitude_m,
        }
    }

    fn indexed(levels: &[SpeedLevel]) -> Vec<(usize, SpeedLevel)> {
        levels.iter().copied().enumerate().collect()
    }

    #[test]
    fn statistics_weigh_speeds_by_their_stretch() {
        // A linear ramp 0..1 over 0..100 Hz: mean 0.5, median 0.5, p90 0.9, integral 50.
        let ramp: Vec<SpeedLevel> = (0..=100).map(|k| at(k as f64, k as f64 / 100.0)).collect();
        let s = statistics(&indexed(&ramp)).unwrap();
        assert!((s.mean_m - 0.5).abs() < 1e-12);
        assert!((s.integrated_m_hz - 50.0).abs() < 1e-9);
        // The step quantile of 101 samples lands within one sample of the exact value.
        assert!((s.median_m - 0.5).abs() <= 0.01 + 1e-12);
        assert!((s.p90_m - 0.9).abs() <= 0.01 + 1e-12);
        // Ten extra speeds crowded into one narrow burst barely move them: a grid that
        // counted speeds instead of speed would put the median in the burst.
        let mut refined = ramp.clone();
        refined.retain(|s| s.speed_hz != 50.0);
        for k in 0..10 {
            refined.push(at(49.5 + 0.1 * k as f64, 10.0));
        }
        refined.sort_by(|a, b| a.speed_hz.total_cmp(&b.speed_hz));
        let r = statistics(&indexed(&refined)).unwrap();
        assert!((r.median_m - s.median_m).abs() <= 0.02);
        assert!((r.p90_m - s.p90_m).abs() <= 0.02);
    }

    #[test]
    fn the_uncertainty_is_the_scatter_of_interleaved_sub_grids() {
        // Sub-grid j (every fourth speed from the j-th) holds only the value j: the four
        // sub-grid means are 0, 1, 2, 3 (sample deviation 1.2910), so the whole grid's
        // mean is uncertain by 1.2910 / 2 = 0.6455 (exact up to the end speeds' half
        // weights, which move each sub-grid mean by nothing here: all its values are equal).
        let levels: Vec<SpeedLevel> = (0..40).map(|k| at(k as f64, (k % 4) as f64)).collect();
        let s = statistics(&indexed(&levels)).unwrap();
        assert!((s.uncertainty.mean_m - 0.645_497).abs() < 1e-6, "{s:?}");
        // A constant NSV is certain whatever the grid.
        let flat: Vec<SpeedLevel> = (0..40).map(|k| at(k as f64, 2.0)).collect();
        let s = statistics(&indexed(&flat)).unwrap();
        assert_eq!(s.uncertainty, GridSpread::default());
    }

    #[test]
    fn the_onset_is_bracketed_by_the_speed_below() {
        let levels = [at(10.0, 0.0), at(20.0, 2e-6), at(30.0, 2e-5)];
        let o = onset_at(&indexed(&levels), 1e-5).unwrap();
        assert_eq!((o.speed_hz, o.below_hz), (30.0, Some(20.0)));
        assert!(onset_at(&indexed(&levels), 1e-4).is_none());
    }

    /// A narrow burst at 12 Hz reaches the level first; the NSV sets in for good from
    /// 300 Hz. On a 1-1000 Hz range the window is 50 Hz: the burst covers 2 Hz of it
    /// (under half), the stretch from 300 Hz all of it. Refining the grid inside the burst
    /// does not move the answer.
    #[test]
    fn the_sustained_onset_skips_a_narrow_burst_whatever_the_grid() {
        let mut levels = vec![at(1.0, 0.0), at(10.0, 0.0), at(12.0, 5e-6), at(14.0, 0.0)];
        levels.extend((0..4).map(|k| at(100.0 + 50.0 * k as f64, 0.0)));
        levels.extend((0..15).map(|k| at(300.0 + 50.0 * k as f64, 3e-6)));
        let onset = onset_at(&indexed(&levels), 1e-6).unwrap();
        assert_eq!(onset.speed_hz, 12.0);
        assert_eq!(onset.sustained_hz, Some(300.0));
        let mut refined = levels.clone();
        // Nine speeds at 11-13 Hz instead of the one at 12 Hz.
        refined.splice(2..3, (0..9).map(|k| at(11.0 + 0.25 * k as f64, 5e-6)));
        assert_eq!(
            onset_at(&indexed(&refined), 1e-6).unwrap().sustained_hz,
            Some(300.0)
        );
    }
}
