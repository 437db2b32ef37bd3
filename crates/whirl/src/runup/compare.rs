//! A sweep against the steady cascade, and run-up against coast-down.

use serde::Serialize;

use super::{RunupOptions, Sweep, SweepResult, SweepWindow};
use crate::nsv::{Cascade, StartComparison};
use crate::post::interpolate;

/// Which amplitude.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub enum Quantity {
    /// The synchronous response.
    #[serde(rename = "1X")]
    OneX,
    /// The largest non-synchronous peak.
    #[serde(rename = "NSV")]
    Nsv,
}

impl Quantity {
    /// `1X` or `NSV`.
    pub fn name(self) -> &'static str {
        match self {
            Quantity::OneX => "1X",
            Quantity::Nsv => "NSV",
        }
    }

    fn of(self, w: &SweepWindow) -> f64 {
        match self {
            Quantity::OneX => w.one_x_m,
            Quantity::Nsv => w.nsv_m(),
        }
    }
}

/// One sweep against the steady cascade, at the cascade's speeds within the sweep. The
/// sweep is read at each steady speed (its windows lie far closer together than the steady
/// speeds, so interpolating it there is accurate where interpolating the steady cascade
/// between its speeds would cut off every resonance peak): its 1X as it is, its NSV
/// power-averaged over the smoothing span first, as the steady cascade averages records
/// (one short window's NSV of an irregular whip is one draw).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct SteadyDifference {
    /// The sweep.
    pub sweep: Sweep,
    /// Steady speeds compared.
    pub speeds: usize,
    /// RMS over those speeds of the sweep's 1X minus the steady 1X, m.
    pub one_x_rms_m: f64,
    /// RMS of the steady 1X over the same speeds, m (the scale of the difference).
    pub one_x_steady_rms_m: f64,
    /// RMS of the sweep's NSV minus the steady NSV (0 where there is no peak), m.
    pub nsv_rms_m: f64,
    /// RMS of the steady NSV over the same speeds, m.
    pub nsv_steady_rms_m: f64,
}

/// The steady cascade's (speed Hz, 1X m, NSV m) at its speeds that did not diverge,
/// ascending.
fn steady_curve(c: &Cascade) -> Vec<(f64, f64, f64)> {
    let mut curve: Vec<(f64, f64, f64)> = c
        .points
        .iter()
        .filter(|p| p.diverged.is_none())
        .map(|p| {
            let nsv = p.peak.map_or(0.0, |n| n.amplitude_m);
            (p.speed_hz, p.one_x_m, nsv)
        })
        .collect();
    curve.sort_by(|a, b| a.0.total_cmp(&b.0));
    curve
}

fn rms(values: &[f64]) -> f64 {
    if values.is_empty() {
        return 0.0;
    }
    (values.iter().map(|v| v * v).sum::<f64>() / values.len() as f64).sqrt()
}

/// `sweep` against `steady`, its NSV smoothed over `smoothing_hz`; `None` when no steady
/// speed lies within the sweep.
pub(super) fn against_steady(
    sweep: &SweepResult,
    steady: &Cascade,
    smoothing_hz: f64,
) -> Option<SteadyDifference> {
    let one_x = smoothed(sweep, Quantity::OneX, 0.0);
    let nsv = smoothed(sweep, Quantity::Nsv, smoothing_hz);
    let mut d1 = Vec::new();
    let mut s1 = Vec::new();
    let mut dn = Vec::new();
    let mut sn = Vec::new();
    for (speed_hz, steady_1x, steady_nsv) in steady_curve(steady) {
        let (Some(a), Some(b)) = (interpolate(&one_x, speed_hz), interpolate(&nsv, speed_hz))
        else {
            continue;
        };
        d1.push(a - steady_1x);
        s1.push(steady_1x);
        dn.push(b - steady_nsv);
        sn.push(steady_nsv);
    }
    (!d1.is_empty()).then(|| SteadyDifference {
        sweep: sweep.sweep,
        speeds: d1.len(),
        one_x_rms_m: rms(&d1),
        one_x_steady_rms_m: rms(&s1),
        nsv_rms_m: rms(&dn),
        nsv_steady_rms_m: rms(&sn),
    })
}

/// Run-up and coast-down at one of the run-up's speeds, the NSV of each power-averaged over
/// the smoothing span.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct HysteresisPoint {
    /// Speed, Hz.
    pub speed_hz: f64,
    /// Run-up 1X, m.
    pub one_x_up_m: f64,
    /// Coast-down 1X at the same speed, m.
    pub one_x_down_m: f64,
    /// Run-up NSV, m.
    pub nsv_up_m: f64,
    /// Coast-down NSV, m.
    pub nsv_down_m: f64,
    /// The 1X differs beyond the tolerance.
    pub one_x_differs: bool,
    /// The NSV differs beyond the tolerance.
    pub nsv_differs: bool,
}

/// A band of neighbouring speeds where run-up and coast-down differ.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Band {
    /// 1X or NSV.
    pub quantity: Quantity,
    /// Lowest and highest speed of the band, Hz.
    pub low_hz: f64,
    /// Highest speed, Hz.
    pub high_hz: f64,
    /// Speed of the largest ratio in the band, Hz.
    pub peak_speed_hz: f64,
    /// Run-up amplitude there, m.
    pub up_m: f64,
    /// Coast-down amplitude there, m.
    pub down_m: f64,
}

impl Band {
    /// Larger over smaller amplitude at the band's peak.
    pub fn ratio(&self) -> f64 {
        self.up_m.max(self.down_m) / self.up_m.min(self.down_m).max(f64::MIN_POSITIVE)
    }
}

/// A speed where the steady cascade found two motions (its two starts differ), with the
/// sweeps there.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct FlaggedSpeed {
    /// Speed, Hz.
    pub speed_hz: f64,
    /// Steady NSV from the first and the other start, m.
    pub steady_first_m: f64,
    /// From the other start, m.
    pub steady_other_m: f64,
    /// Run-up and coast-down NSV there (smoothed), m; `None` outside the sweeps.
    pub nsv_up_m: Option<f64>,
    /// Coast-down NSV, m.
    pub nsv_down_m: Option<f64>,
    /// Within half the smoothing span of an NSV band.
    pub in_nsv_band: bool,
}

/// Run-up against coast-down.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Hysteresis {
    /// At each run-up window's speed within the coast-down's range, ascending.
    pub points: Vec<HysteresisPoint>,
    /// Bands where they differ, 1X then NSV, each ascending.
    pub bands: Vec<Band>,
    /// The steady cascade's speeds with coexisting motions (empty unless it ran from both
    /// starts).
    pub flagged: Vec<FlaggedSpeed>,
}

/// `(speed, amplitude)` of a sweep's windows, ascending, each the power average over the
/// windows within half `span_hz` of it.
fn smoothed(sweep: &SweepResult, quantity: Quantity, span_hz: f64) -> Vec<(f64, f64)> {
    let mut raw: Vec<(f64, f64)> = sweep
        .windows
        .iter()
        .map(|w| (w.speed_hz, quantity.of(w)))
        .collect();
    raw.sort_by(|a, b| a.0.total_cmp(&b.0));
    let half = 0.5 * span_hz;
    raw.iter()
        .map(|&(s, _)| {
            let from = raw.partition_point(|p| p.0 < s - half);
            let to = raw.partition_point(|p| p.0 <= s + half);
            let power: f64 = raw[from..to].iter().map(|p| p.1 * p.1).sum();
            (s, (power / (to - from).max(1) as f64).sqrt())
        })
        .collect()
}

/// Whether `a` and `b` differ: the larger above `ratio` times the smaller and at least
/// `threshold`.
fn differ(a: f64, b: f64, ratio: f64, threshold: f64) -> bool {
    let (large, small) = (a.max(b), a.min(b));
    large >= threshold && large > ratio * small
}

pub(super) fn hysteresis(
    up: &SweepResult,
    down: &SweepResult,
    o: &RunupOptions,
    starts: Option<&StartComparison>,
) -> Hysteresis {
    // The 1X is deterministic and narrow near a critical speed: compared as it is.
    let span = o.smoothing_hz;
    let up_1x = smoothed(up, Quantity::OneX, 0.0);
    let up_nsv = smoothed(up, Quantity::Nsv, span);
    let down_1x = smoothed(down, Quantity::OneX, 0.0);
    let down_nsv = smoothed(down, Quantity::Nsv, span);
    let points: Vec<HysteresisPoint> = up_1x
        .iter()
        .zip(&up_nsv)
        .filter_map(|(&(s, a1), &(_, an))| {
            let b1 = interpolate(&down_1x, s)?;
            let bn = interpolate(&down_nsv, s)?;
            Some(HysteresisPoint {
                speed_hz: s,
                one_x_up_m: a1,
                one_x_down_m: b1,
                nsv_up_m: an,
                nsv_down_m: bn,
                one_x_differs: differ(a1, b1, o.hysteresis_ratio, o.threshold_m),
                nsv_differs: differ(an, bn, o.hysteresis_ratio, o.threshold_m),
            })
        })
        .collect();
    let mut bands = bands_of(&points, Quantity::OneX);
    bands.extend(bands_of(&points, Quantity::Nsv));
    let flagged = starts.map_or_else(Vec::new, |s| {
        s.pairs
            .iter()
            .filter(|p| p.differs)
            .map(|p| FlaggedSpeed {
                speed_hz: p.speed_hz,
                steady_first_m: p.first_m,
                steady_other_m: p.other_m,
                nsv_up_m: interpolate(&up_nsv, p.speed_hz),
                nsv_down_m: interpolate(&down_nsv, p.speed_hz),
                in_nsv_band: bands.iter().any(|b| {
                    b.quantity == Quantity::Nsv
                        && p.speed_hz >= b.low_hz - 0.5 * span
                        && p.speed_hz <= b.high_hz + 0.5 * span
                }),
            })
            .collect()
    });
    Hysteresis {
        points,
        bands,
        flagged,
    }
}

/// Runs of neighbouring differing points of `quantity`, each with its largest ratio.
fn bands_of(points: &[HysteresisPoint], quantity: Quantity) -> Vec<Band> {
    let read = |p: &HysteresisPoint| match quantity {
        Quantity::OneX => (p.one_x_differs, p.one_x_up_m, p.one_x_down_m),
        Quantity::Nsv => (p.nsv_differs, p.nsv_up_m, p.nsv_down_m),
    };
    let mut bands: Vec<Band> = Vec::new();
    let mut open = false;
    for p in points {
        let (differs, up_m, down_m) = read(p);
        if !differs {
            open = false;
            continue;
        }
        let here = Band {
            quantity,
            low_hz: p.speed_hz,
            high_hz: p.speed_hz,
            peak_speed_hz: p.speed_hz,
            up_m,
            down_m,
        };
        match bands.last_mut() {
            Some(band) if open => {
                band.high_hz = p.speed_hz;
                if here.ratio() > band.ratio() {
                    band.peak_speed_hz = p.speed_hz;
                    band.up_m = up_m;
                    band.down_m = down_m;
                }
            }
            _ => bands.push(here),
        }
        open = true;
    }
    bands
}

#[cfg(test)]
mod tests {
    use super::*;

    fn window(speed_hz: f64, one_x_m: f64) -> SweepWindow {
        SweepWindow {
            time_s: 0.0,
            speed_hz,
            one_x_m,
            nsv: None,
            amplitude: Vec::new(),
        }
    }

    fn sweep(sweep: Sweep, points: &[(f64, f64)]) -> SweepResult {
        SweepResult {
            sweep,
            windows: points.iter().map(|&(s, a)| window(s, a)).collect(),
            diverged: None,
            start_fallback: None,
            wall_s: 0.0,
        }
    }

    #[test]
    fn interpolation_is_linear_and_refuses_outside() {
        let p = [(1.0, 10.0), (3.0, 30.0)];
        assert_eq!(interpolate(&p, 2.0), Some(20.0));
        assert_eq!(interpolate(&p, 1.0), Some(10.0));
        assert_eq!(interpolate(&p, 0.5), None);
        assert_eq!(interpolate(&p, 3.5), None);
    }

    #[test]
    fn a_band_is_a_run_of_speeds_where_the_directions_differ_beyond_the_ratio() {
        // Up: 1 um everywhere but 4 um from 30 to 50 Hz; down: 1 um everywhere (given in
        // falling speed, as a coast-down is). Ratio 2, threshold 1 um, no smoothing.
        let speeds: Vec<f64> = (0..10).map(|k| 10.0 * k as f64).collect();
        let up: Vec<(f64, f64)> = speeds
            .iter()
            .map(|&s| {
                (
                    s,
                    if (30.0..=50.0).contains(&s) {
                        4e-6
                    } else {
                        1e-6
                    },
                )
            })
            .collect();
        let down: Vec<(f64, f64)> = speeds.iter().rev().map(|&s| (s, 1e-6)).collect();
        let model =
            crate::model::Model::from_toml_str(crate::examples::REFERENCE_ROTOR, None).unwrap();
        let mut o = RunupOptions::new(&model, 1.0, 600.0, 100.0);
        o.smoothing_hz = 0.0;
        let h = hysteresis(&sweep(Sweep::Up, &up), &sweep(Sweep::Down, &down), &o, None);
        assert_eq!(h.points.len(), 10);
        let one_x: Vec<&Band> = h
            .bands
            .iter()
            .filter(|b| b.quantity == Quantity::OneX)
            .collect();
        assert_eq!(one_x.len(), 1);
        assert_eq!((one_x[0].low_hz, one_x[0].high_hz), (30.0, 50.0));
        assert!((one_x[0].ratio() - 4.0).abs() < 1e-12);
        // The same curves below the threshold are no hysteresis.
        o.threshold_m = 1e-5;
        let h = hysteresis(&sweep(Sweep::Up, &up), &sweep(Sweep::Down, &down), &o, None);
        assert!(h.bands.is_empty());
    }
}
