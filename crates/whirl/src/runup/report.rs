//! What a run-up reports ([`crate::report`]): its settings as resolved, each sweep and its
//! difference from the steady cascade in a few numbers, the hysteresis bands, and the
//! tables `whirl runup` writes.

use serde::Serialize;

use super::{
    Band, FlaggedSpeed, Runup, RunupResolved, SteadyDifference, Sweep, SweepResult, SweepWindow,
};
use crate::nsv::{Component, NsvSummary};
use crate::report::{Report, Table};
use crate::time::Initial;
use crate::units::rad_s_to_hz;

/// A run-up as reported.
#[derive(Debug, Clone)]
pub struct RunupReport {
    /// The run-up.
    pub runup: Runup,
}

/// What the summary says about its numbers.
const NOTES: [&str; 6] = [
    "amplitudes are zero-to-peak, m, of the analysed component with the window-weighted mean removed, read off each short-time spectrum exactly as the steady cascade reads a record (whirl::nsv::measure)",
    "each window's running speed is the speed at its middle; by default the window is 1 / sqrt(rate in Hz/s) long, so the speed moves by one bin within it",
    "against_steady: at the steady cascade's speeds within the sweep, the RMS of the sweep's 1X (its NSV power-averaged over steady_smoothing_hz) minus the steady cascade's, the sweep read between its windows linearly; and the RMS of the steady values for scale",
    "hysteresis: run-up and coast-down (their NSV power-averaged over smoothing_hz of speed) compared at the run-up's window speeds; they differ where the larger exceeds hysteresis_ratio times the smaller and reaches threshold_m; neighbouring differing speeds form a band",
    "flagged: the steady cascade's speeds whose two starts (static equilibrium and rest) settle on NSV differing beyond 3 standard errors (coexisting motions), with the sweeps' NSV there",
    "a run-up's transient differs from the steady states near resonances (the peak is delayed and lowered by the acceleration) and wherever the steady state is not unique",
];

/// One sweep in a few numbers.
#[derive(Debug, Clone, Serialize)]
pub struct SweepSummary {
    /// Its direction.
    pub sweep: Sweep,
    /// Windows read.
    pub windows: usize,
    /// Largest 1X, m, and the speed where, Hz.
    pub largest_one_x_m: f64,
    /// Speed of the largest 1X, Hz.
    pub largest_one_x_speed_hz: f64,
    /// Largest NSV, m.
    pub largest_nsv_m: f64,
    /// Speed of the largest NSV, Hz.
    pub largest_nsv_speed_hz: f64,
    /// Its frequency, Hz.
    pub largest_nsv_frequency_hz: f64,
    /// Wall-clock time of the march, s.
    pub wall_s: f64,
    /// Why the march stopped early, if it did.
    pub diverged: Option<String>,
    /// Why it started from rest, if it did.
    pub start_fallback: Option<String>,
}

/// The steady cascade's speeds and summary.
#[derive(Debug, Clone, Serialize)]
pub struct SteadySummary {
    /// Speeds computed (requested and added).
    pub speeds: usize,
    /// Its NSV summary at the run-up's threshold.
    pub nsv: NsvSummary,
    /// Speeds where its two starts differ (coexisting motions), Hz; `None` when it ran
    /// from one start.
    pub coexisting_hz: Option<Vec<f64>>,
}

/// The hysteresis in a few numbers.
#[derive(Debug, Clone, Serialize)]
pub struct HysteresisSummary {
    /// Speeds compared.
    pub speeds_compared: usize,
    /// Bands where the directions differ.
    pub bands: Vec<Band>,
    /// The steady cascade's speeds with coexisting motions, with the sweeps there.
    pub flagged: Vec<FlaggedSpeed>,
}

/// The key numbers of a [`RunupReport`].
#[derive(Debug, Clone, Serialize)]
pub struct RunupSummary {
    /// Lowest and highest speed of the sweep, Hz.
    pub speed_range_hz: (f64, f64),
    /// Acceleration, Hz/s.
    pub rate_hz_per_s: f64,
    /// Time of one sweep's ramp, s.
    pub ramp_s: f64,
    /// Time at the starting speed before the ramp, s.
    pub hold_s: f64,
    /// Start of the sweeps and the steady cascade.
    pub start: Initial,
    /// Contact law.
    pub contact: &'static str,
    /// Fixed-interface modes of the reduction, if reduced.
    pub reduction_modes: Option<usize>,
    /// Node analysed.
    pub node: usize,
    /// Component analysed.
    pub component: Component,
    /// Sampling and windows.
    pub resolved: RunupResolved,
    /// Overlap of consecutive windows.
    pub overlap: f64,
    /// Bins within which a peak counts as synchronous.
    pub tolerance_bins: f64,
    /// Ratio beyond which the directions differ.
    pub hysteresis_ratio: f64,
    /// Amplitude from which a difference counts, m.
    pub threshold_m: f64,
    /// Smoothing span of the hysteresis, Hz.
    pub smoothing_hz: f64,
    /// Smoothing span of the steady comparison, Hz.
    pub steady_smoothing_hz: f64,
    /// Each sweep.
    pub sweeps: Vec<SweepSummary>,
    /// The steady cascade, if computed.
    pub steady: Option<SteadySummary>,
    /// Each sweep against the steady cascade.
    pub against_steady: Vec<SteadyDifference>,
    /// Run-up against coast-down, when both were computed.
    pub hysteresis: Option<HysteresisSummary>,
    /// Wall-clock time, s.
    pub wall_time_s: f64,
    /// What the numbers mean.
    pub notes: Vec<&'static str>,
}

/// The window with the largest `value`.
fn largest(windows: &[SweepWindow], value: impl Fn(&SweepWindow) -> f64) -> Option<&SweepWindow> {
    windows.iter().max_by(|a, b| value(a).total_cmp(&value(b)))
}

fn sweep_summary(s: &SweepResult) -> SweepSummary {
    let one_x = largest(&s.windows, |w| w.one_x_m);
    let nsv = largest(&s.windows, SweepWindow::nsv_m);
    SweepSummary {
        sweep: s.sweep,
        windows: s.windows.len(),
        largest_one_x_m: one_x.map_or(0.0, |w| w.one_x_m),
        largest_one_x_speed_hz: one_x.map_or(f64::NAN, |w| w.speed_hz),
        largest_nsv_m: nsv.map_or(0.0, SweepWindow::nsv_m),
        largest_nsv_speed_hz: nsv.map_or(f64::NAN, |w| w.speed_hz),
        largest_nsv_frequency_hz: nsv.and_then(|w| w.nsv).map_or(f64::NAN, |n| n.frequency_hz),
        wall_s: s.wall_s,
        diverged: s.diverged.clone(),
        start_fallback: s.start_fallback.clone(),
    }
}

impl Report for RunupReport {
    type Summary = RunupSummary;

    fn summary(&self) -> RunupSummary {
        let r = &self.runup;
        let o = &r.options;
        let steady = r.steady.as_ref().map(|c| SteadySummary {
            speeds: c.points.len(),
            nsv: c.nsv_summary(o.threshold_m),
            coexisting_hz: r.starts.as_ref().map(|s| s.differing_speeds_hz()),
        });
        let hysteresis = r.hysteresis().map(|h| HysteresisSummary {
            speeds_compared: h.points.len(),
            bands: h.bands,
            flagged: h.flagged,
        });
        RunupSummary {
            speed_range_hz: (rad_s_to_hz(o.low), rad_s_to_hz(o.high)),
            rate_hz_per_s: o.rate_hz_per_s(),
            ramp_s: o.ramp_s(),
            hold_s: o.hold,
            start: o.cascade.initial,
            contact: o.cascade.law.name(),
            reduction_modes: o.cascade.reduction,
            node: o.cascade.node,
            component: o.cascade.component,
            resolved: r.resolved,
            overlap: o.overlap,
            tolerance_bins: o.cascade.tolerance_bins,
            hysteresis_ratio: o.hysteresis_ratio,
            threshold_m: o.threshold_m,
            smoothing_hz: o.smoothing_hz,
            steady_smoothing_hz: o.steady_smoothing_hz,
            sweeps: r.sweeps.iter().map(sweep_summary).collect(),
            steady,
            against_steady: r.against_steady(),
            hysteresis,
            wall_time_s: r.wall_time_s,
            notes: NOTES.to_vec(),
        }
    }

    /// `runup` (one row per window of each sweep), `runup_spectra` (long format: every bin
    /// of every window whose spectrum is kept), with a steady cascade `steady` (one row per speed), with both
    /// directions `hysteresis` (the smoothed curves compared) and `bands`.
    fn tables(&self) -> Vec<Table> {
        let r = &self.runup;
        let rows = || {
            r.sweeps
                .iter()
                .flat_map(|s| s.windows.iter().map(move |w| (s.sweep, w)))
        };
        let mut windows = Table::new("runup");
        windows
            .text("sweep", rows().map(|(s, _)| s.name()))
            .numbers("time_s", rows().map(|(_, w)| w.time_s))
            .numbers("speed_hz", rows().map(|(_, w)| w.speed_hz))
            .numbers("one_x_m", rows().map(|(_, w)| w.one_x_m))
            .numbers("nsv_m", rows().map(|(_, w)| w.nsv_m()))
            .optional(
                "nsv_frequency_hz",
                rows().map(|(_, w)| w.nsv.map(|n| n.frequency_hz)),
            )
            .optional("nsv_order", rows().map(|(_, w)| w.nsv.map(|n| n.order)));
        let bins = || {
            rows().flat_map(|(s, w)| {
                w.amplitude
                    .iter()
                    .zip(&r.frequency_hz)
                    .map(move |(a, f)| (s, w, *f, *a))
            })
        };
        let mut spectra = Table::new("runup_spectra");
        spectra
            .text("sweep", bins().map(|b| b.0.name()))
            .numbers("speed_hz", bins().map(|b| b.1.speed_hz))
            .numbers("frequency_hz", bins().map(|b| b.2))
            .numbers("amplitude_m", bins().map(|b| b.3));
        let mut tables = vec![windows, spectra];
        if let Some(c) = &r.steady {
            let mut steady = Table::new("steady");
            let other = |i: usize| r.starts.as_ref().map(|s| s.pairs[i]);
            steady
                .numbers("speed_hz", c.points.iter().map(|p| p.speed_hz))
                .numbers("one_x_m", c.points.iter().map(|p| p.one_x_m))
                .numbers(
                    "nsv_m",
                    c.points
                        .iter()
                        .map(|p| p.peak.map_or(0.0, |n| n.amplitude_m)),
                )
                .bits("settled", c.points.iter().map(|p| p.settled))
                .optional(
                    "other_start_nsv_m",
                    (0..c.points.len()).map(|i| other(i).map(|p| p.other_m)),
                )
                .flags(
                    "starts_differ",
                    (0..c.points.len()).map(|i| other(i).map(|p| p.differs)),
                );
            tables.push(steady);
        }
        if let Some(h) = r.hysteresis() {
            let p = &h.points;
            let mut t = Table::new("hysteresis");
            t.numbers("speed_hz", p.iter().map(|q| q.speed_hz))
                .numbers("one_x_up_m", p.iter().map(|q| q.one_x_up_m))
                .numbers("one_x_down_m", p.iter().map(|q| q.one_x_down_m))
                .numbers("nsv_up_m", p.iter().map(|q| q.nsv_up_m))
                .numbers("nsv_down_m", p.iter().map(|q| q.nsv_down_m))
                .bits("one_x_differs", p.iter().map(|q| q.one_x_differs))
                .bits("nsv_differs", p.iter().map(|q| q.nsv_differs));
            tables.push(t);
            let b = &h.bands;
            let mut t = Table::new("bands");
            t.text("quantity", b.iter().map(|x| x.quantity.name()))
                .numbers("low_hz", b.iter().map(|x| x.low_hz))
                .numbers("high_hz", b.iter().map(|x| x.high_hz))
                .numbers("peak_speed_hz", b.iter().map(|x| x.peak_speed_hz))
                .numbers("up_m", b.iter().map(|x| x.up_m))
                .numbers("down_m", b.iter().map(|x| x.down_m))
                .numbers("ratio", b.iter().map(Band::ratio));
            tables.push(t);
        }
        tables
    }
}
