//! Where the speed grid of a cascade is refined: the midpoints of the stretches between
//! neighbouring speeds across which the answer could change.
//!
//! After each round of speeds, the stretches between neighbours (ascending speed, settled
//! points only) are ranked, most important first:
//!
//! 1. both sides of the largest NSV, then of every other local maximum reaching half of it
//!    (a narrow lock-in burst that a coarse grid only grazes is found by bisecting towards
//!    its top);
//! 2. below the onset at each level of [`Refinement::onset_levels_m`] (the stretch from the
//!    last speed under the level to the first above), and within one sustained-onset window
//!    ([`SUSTAINED_WINDOW`] of the range) either side of each level's sustained onset, every
//!    stretch wider than a quarter of that window (the share of the window the NSV covers
//!    is only measured as finely as the grid resolves it);
//! 3. sharp changes between neighbours where either reaches the smallest onset level and
//!    a tenth of the largest NSV: the NSV changes by more than [`SHARP_RATIO`] times, or
//!    its class changes, or its frequency jumps by more than the lock tolerance; larger NSV
//!    first. Only once nothing of ranks 1 and 2 is left, so the bisection towards the
//!    largest NSV and the onsets is never starved by changes that do not move them.
//!
//! Before the first round, the speeds where an excitation meets a natural frequency of the
//! rotor on linearised bearings are added ([`resonance_speeds`]): a varying-compliance or
//! waviness frequency (and its multiples) or half the running speed crossing a Campbell
//! branch. Such a resonance is a fraction of a hertz wide in speed (the half-power width
//! 2 zeta f_n divided by the excitation's order): a grid finds it only by chance, and then
//! its onset or its size depends on the grid.
//!
//! A stretch is halved only while its halves stay at least `min_spacing_hz` wide, and the
//! rounds stop when nothing is left to halve or `max_added` speeds have been added.

use super::classify::{lock_tolerance, NamedFrequency, Nsv};
use super::options::Refinement;
use super::point::CascadePoint;
use super::summary::{level, sustained_onset, SpeedLevel, SUSTAINED_WINDOW};

/// Neighbours whose NSV differ by more than this factor are a sharp change.
pub const SHARP_RATIO: f64 = 2.0;

/// Local maxima reaching this fraction of the largest NSV are bisected towards like it.
const PEAK_FRACTION: f64 = 0.5;

/// Sharp changes are refined where either side reaches this fraction of the largest NSV
/// (below it they move neither the largest, nor the onsets, nor the upper statistics).
const SHARP_FRACTION: f64 = 0.1;

/// Multiples of a contact frequency whose crossings with natural frequencies are added.
const RESONANCE_MULTIPLES: usize = 3;

/// A stretch between two neighbouring settled points (indices into the points, ascending
/// speed) and how urgently it is halved: lower rank first, then larger NSV.
#[derive(Debug, Clone, Copy)]
struct Stretch {
    low: usize,
    high: usize,
    rank: u8,
    level: f64,
}

/// The speeds (rad/s) to add next: midpoints of the most important stretches, at most
/// `room` of them. `points` are in ascending speed with `nsv` alongside; `tolerance_hz`
/// is the cascade's synchronous tolerance.
pub(super) fn next_speeds(
    points: &[CascadePoint],
    nsv: &[Option<Nsv>],
    refine: &Refinement,
    tolerance_hz: f64,
    room: usize,
) -> Vec<f64> {
    let settled: Vec<(usize, f64)> = points
        .iter()
        .zip(nsv)
        .enumerate()
        .filter_map(|(i, (p, n))| level(p, n.as_ref()).map(|l| (i, l)))
        .collect();
    let mut stretches: Vec<Stretch> = Vec::new();
    let wide = |low: usize, high: usize| {
        points[high].speed_hz - points[low].speed_hz >= 2.0 * refine.min_spacing_hz
    };
    let add = |stretches: &mut Vec<Stretch>, k: Option<usize>, rank: u8| {
        let Some(k) = k.filter(|k| k + 1 < settled.len()) else {
            return;
        };
        let (low, high) = (settled[k].0, settled[k + 1].0);
        if wide(low, high) && !stretches.iter().any(|s| s.low == low) {
            let level = settled[k].1.max(settled[k + 1].1);
            stretches.push(Stretch {
                low,
                high,
                rank,
                level,
            });
        }
    };
    for k in peaks(&settled) {
        add(&mut stretches, k.checked_sub(1), 0);
        add(&mut stretches, Some(k), 0);
    }
    for &level in &refine.onset_levels_m {
        if let Some(k) = settled.iter().position(|&(_, l)| l >= level) {
            add(&mut stretches, k.checked_sub(1), 1);
        }
        for k in around_sustained_onset(points, &settled, level) {
            add(&mut stretches, Some(k), 1);
        }
    }
    if stretches.is_empty() {
        let top = settled.iter().map(|s| s.1).fold(0.0, f64::max);
        let floor = refine
            .onset_levels_m
            .iter()
            .copied()
            .fold(f64::INFINITY, f64::min)
            .max(SHARP_FRACTION * top);
        for k in 0..settled.len().saturating_sub(1) {
            let ((i, a), (j, b)) = (settled[k], settled[k + 1]);
            if a.max(b) >= floor && sharp(&nsv[i], a, &nsv[j], b, tolerance_hz) {
                add(&mut stretches, Some(k), 2);
            }
        }
    }
    stretches.sort_by(|x, y| x.rank.cmp(&y.rank).then(y.level.total_cmp(&x.level)));
    stretches
        .iter()
        .take(room)
        .map(|s| 0.5 * (points[s.low].speed + points[s.high].speed))
        .collect()
}

/// Positions (in `settled`) of the stretches within one sustained-onset window either side
/// of the sustained onset at `level` that are wider than a quarter of the window.
fn around_sustained_onset(
    points: &[CascadePoint],
    settled: &[(usize, f64)],
    level: f64,
) -> Vec<usize> {
    let levels: Vec<(usize, SpeedLevel)> = settled
        .iter()
        .map(|&(i, amplitude_m)| {
            let speed_hz = points[i].speed_hz;
            (
                i,
                SpeedLevel {
                    speed_hz,
                    amplitude_m,
                },
            )
        })
        .collect();
    let (Some(first), Some(last)) = (levels.first(), levels.last()) else {
        return Vec::new();
    };
    let window = SUSTAINED_WINDOW * (last.1.speed_hz - first.1.speed_hz);
    let Some(onset) = sustained_onset(&levels, level) else {
        return Vec::new();
    };
    (0..levels.len().saturating_sub(1))
        .filter(|&k| {
            let (low, high) = (levels[k].1.speed_hz, levels[k + 1].1.speed_hz);
            high > onset - window && low < onset + window && high - low > 0.25 * window
        })
        .collect()
}

/// Positions (in `settled`) of the largest level and of the other local maxima reaching
/// [`PEAK_FRACTION`] of it, largest first.
fn peaks(settled: &[(usize, f64)]) -> Vec<usize> {
    let top = settled.iter().map(|s| s.1).fold(0.0, f64::max);
    if top <= 0.0 {
        return Vec::new();
    }
    let at = |k: Option<usize>| k.and_then(|k| settled.get(k)).map_or(0.0, |s| s.1);
    let mut found: Vec<usize> = (0..settled.len())
        .filter(|&k| {
            let here = settled[k].1;
            here >= PEAK_FRACTION * top && here >= at(k.checked_sub(1)) && here >= at(Some(k + 1))
        })
        .collect();
    found.sort_by(|&a, &b| settled[b].1.total_cmp(&settled[a].1));
    found
}

/// Whether two neighbours' NSV differ sharply: in size, class or frequency.
fn sharp(a: &Option<Nsv>, level_a: f64, b: &Option<Nsv>, level_b: f64, tolerance_hz: f64) -> bool {
    let (low, high) = (level_a.min(level_b), level_a.max(level_b));
    if high > SHARP_RATIO * low {
        return true;
    }
    match (a, b) {
        (Some(a), Some(b)) => {
            let tolerance =
                lock_tolerance(a.peak.frequency_hz.max(b.peak.frequency_hz), tolerance_hz);
            a.class.differs_from(b.class)
                || (a.peak.frequency_hz - b.peak.frequency_hz).abs() > tolerance
        }
        _ => false,
    }
}

/// The speeds (rad/s) between neighbouring `speeds` (ascending, rad/s) where a contact
/// frequency, one of its first multiples or half the running speed crosses a natural
/// frequency, by linear interpolation between the neighbours; `contact[i]` and
/// `natural[i]` are the frequencies at `speeds[i]` (the same names at every speed). None
/// closer than `min_spacing_hz` to a speed of the grid or to another.
pub(super) fn resonance_speeds(
    speeds: &[f64],
    contact: &[Vec<NamedFrequency>],
    natural: &[Vec<NamedFrequency>],
    min_spacing_hz: f64,
) -> Vec<f64> {
    let hz = crate::units::rad_s_to_hz;
    let mut found: Vec<f64> = Vec::new();
    for k in 0..speeds.len().saturating_sub(1) {
        let (a, b) = (speeds[k], speeds[k + 1]);
        let excitations = |i: usize| -> Vec<f64> {
            let mut e: Vec<f64> = contact[i]
                .iter()
                .flat_map(|c| (1..=RESONANCE_MULTIPLES).map(move |m| m as f64 * c.frequency_hz))
                .collect();
            e.push(0.5 * hz(speeds[i]));
            e
        };
        let (ea, eb) = (excitations(k), excitations(k + 1));
        for (na, nb) in natural[k].iter().zip(&natural[k + 1]) {
            if na.name != nb.name {
                continue;
            }
            for (xa, xb) in ea.iter().zip(&eb) {
                let (ga, gb) = (xa - na.frequency_hz, xb - nb.frequency_hz);
                if ga * gb < 0.0 {
                    found.push(a + (b - a) * ga / (ga - gb));
                }
            }
        }
    }
    found.sort_by(f64::total_cmp);
    let mut kept: Vec<f64> = Vec::new();
    for w in found {
        let clear = |other: f64| (hz(w) - hz(other)).abs() >= min_spacing_hz;
        if speeds.iter().all(|&s| clear(s)) && kept.iter().all(|&s| clear(s)) {
            kept.push(w);
        }
    }
    kept
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::nsv::classify::{NsvClass, WhirlDirection};
    use crate::nsv::point::NsvPeak;

    /// A settled point at `speed_hz` whose NSV is `amplitude_m` at 45 Hz.
    fn point(speed_hz: f64, amplitude_m: f64) -> (CascadePoint, Option<Nsv>) {
        let peak = NsvPeak {
            frequency_hz: 45.0,
            amplitude_m,
            order: 45.0 / speed_hz,
            forward_m: amplitude_m,
            backward_m: 0.0,
            decay_ratio: 1.0,
            settling_ratio: Some(1.0),
            standard_error_m: 0.0,
            variation: 0.0,
        };
        let p = CascadePoint::settled_at(speed_hz, 1e-4, Some(peak));
        let n = Nsv {
            speed_hz,
            peak,
            class: NsvClass::Whip(WhirlDirection::Forward),
            explanation: String::new(),
            direction: WhirlDirection::Forward,
            slope: None,
        };
        (p, Some(n))
    }

    /// A narrow burst: 150 um at 594 Hz falling to 30 um 5 Hz away, on a 2 um floor.
    fn burst(speed_hz: f64) -> f64 {
        2e-6 + 1.5e-4 * (-((speed_hz - 594.0) / 3.0).powi(2)).exp()
    }

    #[test]
    fn rounds_of_bisection_find_a_narrow_burst_from_a_coarse_grid() {
        let refine = Refinement::default();
        let mut speeds: Vec<f64> = (0..30).map(|k| 1.0 + 749.0 * k as f64 / 29.0).collect();
        for _ in 0..40 {
            let (points, nsv): (Vec<_>, Vec<_>) =
                speeds.iter().map(|&f| point(f, burst(f))).unzip();
            let room = refine.max_added.saturating_sub(speeds.len() - 30);
            let next = next_speeds(&points, &nsv, &refine, 4.0, room);
            if next.is_empty() {
                break;
            }
            speeds.extend(next.iter().map(|w| w / std::f64::consts::TAU));
            speeds.sort_by(f64::total_cmp);
        }
        let best = speeds
            .iter()
            .copied()
            .max_by(|a, b| burst(*a).total_cmp(&burst(*b)))
            .unwrap();
        // Bisection stops at twice the smallest spacing (0.5 Hz): the top is found within
        // a hertz, and its amplitude within 2 %: exp(-(1/3)^2) = 0.89 at worst, 0.97 at
        // 0.5 Hz.
        assert!((best - 594.0).abs() < 1.0, "{best}");
        assert!(burst(best) > 0.97 * burst(594.0));
        assert!(speeds.len() - 30 <= refine.max_added);
    }

    /// A step: no NSV below 300 Hz, 3 um from 300 Hz on, sampled every 100 Hz over
    /// 0-1000 Hz (a sustained-onset window of 50 Hz). The stretches within 50 Hz of the
    /// sustained onset are wider than a quarter window, so they are halved; the plateau
    /// beyond is not.
    #[test]
    fn stretches_around_the_sustained_onset_are_halved() {
        let refine = Refinement {
            onset_levels_m: vec![1e-6],
            ..Refinement::default()
        };
        // Rising slowly above the step, so the only local maximum (bisected towards by the
        // first rule) is the last speed.
        let step = |f: f64| if f >= 300.0 { 3e-6 + 1e-9 * f } else { 0.0 };
        let (points, nsv): (Vec<_>, Vec<_>) = (0..=10)
            .map(|k| 100.0 * k as f64)
            .map(|f| point(f.max(1.0), step(f)))
            .unzip();
        let next: Vec<f64> = next_speeds(&points, &nsv, &refine, 4.0, 100)
            .iter()
            .map(|w| w / std::f64::consts::TAU)
            .collect();
        // 250 Hz: below the onset (200-300) and beside it; 350 Hz: after it (300-400).
        assert!(next.iter().any(|f| (f - 250.0).abs() < 1e-9), "{next:?}");
        assert!(next.iter().any(|f| (f - 350.0).abs() < 1e-9), "{next:?}");
        // Nothing else but beside the largest NSV (900-1000 Hz).
        assert!(
            next.iter()
                .all(|f| (200.0..=400.0).contains(f) || *f > 900.0),
            "{next:?}"
        );
    }

    #[test]
    fn resonances_are_found_where_an_excitation_crosses_a_natural_frequency() {
        // 8 rollers at cage ratio 0.456: N_b w_c = 3.65 f; a 50 Hz mode is met at 13.7 Hz.
        let speeds: Vec<f64> = [1.0, 26.8, 52.6]
            .iter()
            .map(|f| f * std::f64::consts::TAU)
            .collect();
        let named = |name: &str, f: f64| NamedFrequency {
            name: name.into(),
            frequency_hz: f,
        };
        let contact: Vec<Vec<NamedFrequency>> = speeds
            .iter()
            .map(|w| vec![named("N_b w_c", 3.648 * w / std::f64::consts::TAU)])
            .collect();
        let natural: Vec<Vec<NamedFrequency>> = speeds
            .iter()
            .map(|_| vec![named("mode 1 forward", 50.0)])
            .collect();
        let found = resonance_speeds(&speeds, &contact, &natural, 0.5);
        let hz: Vec<f64> = found.iter().map(|w| w / std::f64::consts::TAU).collect();
        // m = 1 at 50 / 3.648 = 13.71 Hz, m = 2 at 6.85 Hz, m = 3 at 4.57 Hz, and 0.5X
        // at 100 Hz lies beyond the grid.
        assert_eq!(hz.len(), 3, "{hz:?}");
        assert!((hz[2] - 50.0 / 3.648).abs() < 1e-9);
    }
}
