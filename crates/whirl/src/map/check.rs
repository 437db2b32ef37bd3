//! The map checked against cascades: at a few parameter values the default cascade is run
//! and every settled speed is compared with what the map predicts there.
//!
//! - A speed whose NSV reaches the level is *explained* when it lies in an unstable band of
//!   the map, or within the speed tolerance of a resonance line whose response frequency
//!   (or, for a sum or difference, its companion) is the NSV's within the frequency
//!   tolerance.
//! - A speed is *predicted quiet* when it lies in no band and no line lies within the speed
//!   tolerance; the prediction holds when its NSV stays below the level.
//!
//! The speeds where the two disagree are listed with the cascade's own name for the
//! vibration. A common reason is a second motion beside the synchronous orbit: the map
//! follows one orbit, the cascade starts each speed from the static equilibrium and can
//! land on another (`whirl cascade --compare-starts` shows it).

use serde::Serialize;

use super::bands::UnstableBand;
use super::lines::{Excitation, ResonanceLine};
use crate::nsv::{Cascade, SUSTAINED_FRACTION, SUSTAINED_WINDOW};

/// Default NSV level of the check, m: 10 um, the cascade's upper onset level.
pub const DEFAULT_CHECK_LEVEL_M: f64 = 1e-5;

/// Default speed tolerance of a line, Hz of running speed.
pub const DEFAULT_SPEED_TOLERANCE_HZ: f64 = 2.0;

/// A line's response frequency matches an NSV's within this share of it (or 2 Hz, the
/// cascade's resolution, whichever is larger): the natural frequency of the averaged
/// linearisation is the orbit's mean; the vibration rings a few per cent off it.
pub const FREQUENCY_TOLERANCE: f64 = 0.05;

/// Smallest frequency tolerance, Hz.
const MIN_FREQUENCY_TOLERANCE_HZ: f64 = 2.0;

/// How one cascade speed compares with the map.
#[derive(Debug, Clone, Serialize)]
pub struct Disagreement {
    /// Running speed, Hz.
    pub speed_hz: f64,
    /// Its NSV, m (0 without one).
    pub nsv_m: f64,
    /// Its NSV frequency, Hz.
    pub frequency_hz: Option<f64>,
    /// The cascade's name for it.
    pub class: Option<&'static str>,
    /// `unexplained` (NSV at or above the level, no band or matching line) or
    /// `not quiet` (NSV at or above the level where the map predicts none).
    pub kind: &'static str,
}

/// The agreement of one value's map with its cascade.
#[derive(Debug, Clone, Serialize)]
pub struct CascadeCheck {
    /// The value, as given.
    pub value: String,
    /// The NSV level, m.
    pub level_m: f64,
    /// Settled speeds of the cascade that the map's branch covers (the rest are left out:
    /// beyond where the sweep stopped, or across a jump, the map says nothing).
    pub speeds: usize,
    /// Settled speeds the branch does not cover.
    pub not_followed: usize,
    /// Of them with NSV at or above the level, and of those explained by the map.
    pub nsv_speeds: usize,
    /// Explained by a band or a matching line.
    pub explained: usize,
    /// The speeds with NSV at or above the level, Hz.
    pub nsv_speeds_hz: Vec<f64>,
    /// Speeds the map predicts quiet (no band, no line near), and of those below the level.
    pub predicted_quiet: usize,
    /// Predicted quiet and below the level.
    pub quiet_confirmed: usize,
    /// The cascade's sustained onset at the level, Hz.
    pub cascade_sustained_hz: Option<f64>,
    /// The map's first sustained instability: the lowest speed from which the bands cover
    /// the share of the next stretch that a sustained onset needs, Hz.
    pub map_sustained_hz: Option<f64>,
    /// The speeds where the two disagree.
    pub disagreements: Vec<Disagreement>,
}

impl CascadeCheck {
    /// Share of the speeds with NSV that the map explains (1 when there are none).
    pub fn explained_fraction(&self) -> f64 {
        ratio(self.explained, self.nsv_speeds)
    }

    /// Share of the predicted quiet speeds that are quiet (1 when there are none).
    pub fn quiet_fraction(&self) -> f64 {
        ratio(self.quiet_confirmed, self.predicted_quiet)
    }
}

fn ratio(part: usize, whole: usize) -> f64 {
    if whole == 0 {
        1.0
    } else {
        part as f64 / whole as f64
    }
}

/// What the map predicts at one speed.
struct Prediction<'a> {
    bands: &'a [UnstableBand],
    lines: &'a [ResonanceLine],
    speed_tolerance_hz: f64,
}

impl Prediction<'_> {
    fn in_band(&self, speed_hz: f64) -> bool {
        self.bands
            .iter()
            .any(|b| b.span_hz[0] <= speed_hz && speed_hz <= b.span_hz[1])
    }

    fn near(&self, speed_hz: f64) -> impl Iterator<Item = &ResonanceLine> {
        let tolerance = self.speed_tolerance_hz;
        self.lines
            .iter()
            .filter(move |l| (l.speed_hz - speed_hz).abs() <= tolerance)
    }

    /// Whether a line near `speed_hz` responds at `frequency_hz`.
    fn line_explains(&self, speed_hz: f64, frequency_hz: f64) -> bool {
        let tolerance = (FREQUENCY_TOLERANCE * frequency_hz).max(MIN_FREQUENCY_TOLERANCE_HZ);
        self.near(speed_hz).any(|l| {
            responses(l, speed_hz)
                .iter()
                .any(|f| (f - frequency_hz).abs() <= tolerance)
        })
    }
}

/// The frequencies a line's vibration shows at `speed_hz`: its response, and for a sum or
/// a difference the companion.
fn responses(line: &ResonanceLine, speed_hz: f64) -> Vec<f64> {
    match line.excitation {
        Excitation::Sum { order, .. } => {
            vec![line.response_hz, order * speed_hz - line.response_hz]
        }
        Excitation::Difference { .. } => vec![line.response_hz, line.response_hz + speed_hz],
        _ => vec![line.response_hz],
    }
}

/// What the map says of one value: where its branch was followed (Hz, ascending spans),
/// its bands and its lines.
pub struct Predicted<'a> {
    /// The speeds the branch covers ([`super::bands::followed_spans`]).
    pub followed: &'a [[f64; 2]],
    /// The unstable bands.
    pub bands: &'a [UnstableBand],
    /// The resonance lines.
    pub lines: &'a [ResonanceLine],
}

/// Compares `cascade` with what the map predicts for the same value.
pub fn check(
    value: &str,
    cascade: &Cascade,
    map: &Predicted<'_>,
    level_m: f64,
    speed_tolerance_hz: f64,
) -> CascadeCheck {
    let Predicted {
        followed,
        bands,
        lines,
    } = *map;
    let prediction = Prediction {
        bands,
        lines,
        speed_tolerance_hz,
    };
    let mut c = CascadeCheck {
        value: value.to_string(),
        level_m,
        speeds: 0,
        not_followed: 0,
        nsv_speeds: 0,
        explained: 0,
        nsv_speeds_hz: Vec::new(),
        predicted_quiet: 0,
        quiet_confirmed: 0,
        cascade_sustained_hz: cascade
            .nsv_summary(level_m)
            .onsets
            .first()
            .and_then(|o| o.sustained_hz),
        map_sustained_hz: map_sustained(bands, speed_range(cascade)),
        disagreements: Vec::new(),
    };
    for (point, nsv) in cascade.points.iter().zip(&cascade.nsv) {
        if point.diverged.is_some() || !point.settled {
            continue;
        }
        let speed = point.speed_hz;
        if !followed.iter().any(|s| s[0] <= speed && speed <= s[1]) {
            c.not_followed += 1;
            continue;
        }
        c.speeds += 1;
        let nsv_m = nsv.as_ref().map_or(0.0, |n| n.peak.amplitude_m);
        let frequency_hz = nsv.as_ref().map(|n| n.peak.frequency_hz);
        let loud = nsv_m >= level_m;
        let disagree = |kind| Disagreement {
            speed_hz: speed,
            nsv_m,
            frequency_hz,
            class: nsv.as_ref().map(|n| n.class.name()),
            kind,
        };
        if loud {
            c.nsv_speeds += 1;
            c.nsv_speeds_hz.push(speed);
            let explained = prediction.in_band(speed)
                || frequency_hz.is_some_and(|f| prediction.line_explains(speed, f));
            if explained {
                c.explained += 1;
            } else {
                c.disagreements.push(disagree("unexplained"));
            }
        }
        if !prediction.in_band(speed) && prediction.near(speed).next().is_none() {
            c.predicted_quiet += 1;
            if loud {
                c.disagreements.push(disagree("not quiet"));
            } else {
                c.quiet_confirmed += 1;
            }
        }
    }
    c
}

/// The design query's answer tried on the rotor: the default cascade of the largest value
/// the map finds clear, from the map's first speed to the query's.
#[derive(Debug, Clone, Serialize)]
pub struct Confirmation {
    /// The value, as given.
    pub value: String,
    /// The NSV level it must stay below, m.
    pub level_m: f64,
    /// Settled speeds of the cascade.
    pub speeds: usize,
    /// Its largest NSV over them, m (0 without one).
    pub largest_nsv_m: f64,
    /// Where, Hz.
    pub largest_at_hz: Option<f64>,
    /// Whether the NSV stays below the level at every settled speed.
    pub confirmed: bool,
}

/// Whether `cascade` (of the value written `value`) keeps its NSV below `level_m`.
pub fn confirm(value: &str, cascade: &Cascade, level_m: f64) -> Confirmation {
    let settled = cascade
        .points
        .iter()
        .zip(&cascade.nsv)
        .filter(|(p, _)| p.diverged.is_none() && p.settled);
    let (speeds, largest) = settled.fold((0, None::<(f64, f64)>), |(n, best), (p, nsv)| {
        let a = nsv.as_ref().map_or(0.0, |n| n.peak.amplitude_m);
        let best = match best {
            Some((b, _)) if b >= a => best,
            _ => Some((a, p.speed_hz)),
        };
        (n + 1, best)
    });
    let largest_nsv_m = largest.map_or(0.0, |l| l.0);
    Confirmation {
        value: value.to_string(),
        level_m,
        speeds,
        largest_nsv_m,
        largest_at_hz: largest.map(|l| l.1),
        confirmed: speeds > 0 && largest_nsv_m < level_m,
    }
}

/// The lowest band edge from which the bands cover at least [`SUSTAINED_FRACTION`] of the
/// next [`SUSTAINED_WINDOW`] of the cascade's speed range: the map's counterpart of a
/// cascade's sustained onset.
fn map_sustained(bands: &[UnstableBand], [first, last]: [f64; 2]) -> Option<f64> {
    let window = SUSTAINED_WINDOW * (last - first);
    let mut starts: Vec<f64> = bands.iter().map(|b| b.span_hz[0]).collect();
    starts.sort_by(f64::total_cmp);
    starts.into_iter().find(|&start| {
        let end = start + window;
        end <= last && covered(bands, start, end) >= SUSTAINED_FRACTION * window
    })
}

/// The lowest and highest speed of `cascade`, Hz.
fn speed_range(cascade: &Cascade) -> [f64; 2] {
    let speeds = cascade.points.iter().map(|p| p.speed_hz);
    speeds.fold([f64::INFINITY, f64::NEG_INFINITY], |[a, b], s| {
        [a.min(s), b.max(s)]
    })
}

/// The length of [from, to] (Hz) that the union of the bands covers.
fn covered(bands: &[UnstableBand], from: f64, to: f64) -> f64 {
    let mut spans: Vec<[f64; 2]> = bands
        .iter()
        .map(|b| [b.span_hz[0].max(from), b.span_hz[1].min(to)])
        .filter(|s| s[1] > s[0])
        .collect();
    spans.sort_by(|a, b| a[0].total_cmp(&b[0]));
    let (mut total, mut reach) = (0.0, from);
    for [a, b] in spans {
        let a = a.max(reach);
        if b > a {
            total += b - a;
            reach = b;
        }
    }
    total
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::map::Edge;

    fn band(lo: f64, hi: f64) -> UnstableBand {
        UnstableBand {
            opens_hz: lo,
            opens: Edge::BranchStart,
            closes_hz: hi,
            closes: Edge::BranchEnd,
            span_hz: [lo, hi],
            coexisting_stable_hz: Vec::new(),
            growing: Vec::new(),
            largest_growth_per_s: None,
        }
    }

    #[test]
    fn overlapping_bands_count_once() {
        let bands = [band(10.0, 30.0), band(20.0, 40.0), band(50.0, 60.0)];
        assert_eq!(covered(&bands, 0.0, 100.0), 40.0);
        assert_eq!(covered(&bands, 25.0, 55.0), 20.0);
    }

    #[test]
    fn the_sustained_instability_skips_a_narrow_band() {
        // 0-200 Hz: a 10 Hz window, half of it covered. A 2 Hz band at 50 Hz covers a fifth
        // of its window; the band from 120 Hz covers all of its own.
        let bands = [band(50.0, 52.0), band(120.0, 200.0)];
        assert_eq!(map_sustained(&bands, [0.0, 200.0]), Some(120.0));
        // Two bands 4 Hz apart, 3 Hz each: 6 of the 10 Hz from the first one's start.
        let bands = [band(50.0, 53.0), band(57.0, 60.0)];
        assert_eq!(map_sustained(&bands, [0.0, 200.0]), Some(50.0));
        // A band too near the top to fill a window is not sustained.
        assert_eq!(map_sustained(&[band(195.0, 200.0)], [0.0, 200.0]), None);
    }
}
