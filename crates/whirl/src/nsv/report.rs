//! What a cascade reports ([`crate::report`]): its settings as resolved, the NSV in a few
//! numbers, and the spectra and per-speed NSV tables, as `whirl cascade` writes them.

use serde::Serialize;

use super::{Cascade, NsvPeak, NsvSummary, StartComparison, STARTS_DIFFER_SIGMAS};
use crate::bearing::BearingOrders;
use crate::report::{Report, Table};

/// A cascade read at an NSV threshold, and the comparison with the other start if one was
/// run.
#[derive(Debug, Clone)]
pub struct CascadeReport {
    /// The cascade.
    pub cascade: Cascade,
    /// NSV amplitude that counts, m (zero-to-peak).
    pub threshold_m: f64,
    /// The same speeds from the other start, compared.
    pub starts: Option<StartComparison>,
    /// The checkpoint folder the run kept, if any.
    pub checkpoint_folder: Option<String>,
}

/// What the summary says about the cascade's numbers.
const NOTES: [&str; 9] = [
    "amplitudes are zero-to-peak, m, of the analysed component with the window-weighted mean removed; peaks refined between bins",
    "nsv: the largest spectral peak in the band not within tolerance_bins of a multiple of the running speed; classes and their rules: whirl::nsv::classify",
    "each speed settles until its largest non-synchronous peak stops dying away (or is negligible), from settle_s up to settle_max_s; an unsettled speed (still dying away at settle_max_s) has no NSV class and never makes the onset, the largest, the statistics or the dominant class",
    "each settled speed power-averages the spectra of records overlapping by half until the NSV's standard error (inflated by the records' correlation) is within averaging.relative_error of it (or averaging.absolute_error_m), or within averaging.decided_error with the NSV at least 2 standard errors from every onset level, from min_records to max_records records; nsv.csv gives records, nsv_standard_error_m and nsv_variation (record-to-record scatter: near 0 for a steady vibration)",
    "started_from_rest_hz: speeds where no static equilibrium was found, so the run started from rest (nsv.csv: start_fallback)",
    "speeds are refined where the NSV changes sharply, around the largest NSV and below each onset level (nsv.csv: added = 1); largest.neighbours and largest.spacing_hz say how finely the largest NSV is resolved",
    "statistics: each settled speed weighed by the stretch of speed it stands for, so they do not depend on how many speeds a region holds; their uncertainty is the records' scatter and the speed grid's, not a choice between coexisting steady motions: where two coexist the start picks one, and running every speed again from the other start (compare starts) marks such speeds",
    "onsets[].sustained_hz: the lowest speed from which the NSV reaches the level over at least half of the next 5 % of the speed range (a narrow resonance below it does not count)",
    "direction: forward when the full spectrum of x + i y is larger at +f than at -f",
];

/// The key numbers of a [`CascadeReport`].
#[derive(Debug, Clone, Serialize)]
pub struct CascadeSummary {
    /// Speeds computed (requested and added).
    pub speeds: usize,
    /// Lowest and highest speed, Hz.
    pub speed_range_hz: (f64, f64),
    /// Contact law.
    pub contact: &'static str,
    /// Fixed-interface modes of the reduction, if reduced.
    pub reduction_modes: Option<usize>,
    /// Node analysed.
    pub node: usize,
    /// Component analysed.
    pub component: super::Component,
    /// Shortest settling time, s.
    pub settle_s: f64,
    /// Longest settling time, s.
    pub settle_max_s: f64,
    /// Start of each speed.
    pub start: crate::time::Initial,
    /// Speed refinement.
    pub refinement: super::Refinement,
    /// Length of one record, s.
    pub record_s: f64,
    /// Record averaging.
    pub averaging: super::Averaging,
    /// Time step, s.
    pub step_s: f64,
    /// Sample interval, s.
    pub sample_interval_s: f64,
    /// Samples per record.
    pub samples_per_record: usize,
    /// Spectral window.
    pub window: String,
    /// Bin spacing, Hz.
    pub resolution_hz: f64,
    /// Top of the band, Hz.
    pub max_frequency_hz: f64,
    /// Bins within which a peak counts as synchronous.
    pub tolerance_bins: f64,
    /// Whether the full spectrum was computed.
    pub full_spectrum: bool,
    /// The NSV in a few numbers.
    pub nsv: NsvSummary,
    /// Each roller bearing's characteristic frequencies (FTF, BPFO, BPFI, BSF, N_b w_c) as
    /// orders of the spin speed.
    pub bearing_orders: Vec<BearingOrders>,
    /// Speeds loaded from the checkpoint.
    pub resumed_speeds: usize,
    /// Wall-clock time, s.
    pub wall_time_s: f64,
    /// The checkpoint folder.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub checkpoint_folder: Option<String>,
    /// What the numbers are.
    pub notes: [&'static str; 9],
    /// The comparison with the other start.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub starts: Option<StartsSummary>,
}

/// The comparison with the other start.
#[derive(Debug, Clone, Serialize)]
pub struct StartsSummary {
    /// The other start.
    pub other_start: crate::time::Initial,
    /// Speeds compared.
    pub compared_speeds: usize,
    /// Speeds where the two differ, Hz.
    pub differing_speeds_hz: Vec<f64>,
    /// Standard errors of the difference beyond which they differ.
    pub sigmas: f64,
    /// The NSV of the other start.
    pub other_start_nsv: NsvSummary,
    /// What differing means.
    pub note: &'static str,
}

impl Cascade {
    /// Lowest and highest speed, Hz.
    pub fn speed_range_hz(&self) -> (f64, f64) {
        let s = self.speeds_hz();
        let low = s.iter().copied().fold(f64::INFINITY, f64::min);
        let high = s.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        (low, high)
    }
}

impl Report for CascadeReport {
    type Summary = CascadeSummary;

    fn summary(&self) -> CascadeSummary {
        let c = &self.cascade;
        let (o, r) = (&c.options, &c.resolved);
        CascadeSummary {
            speeds: c.points.len(),
            speed_range_hz: c.speed_range_hz(),
            contact: o.law.name(),
            reduction_modes: o.reduction,
            node: o.node,
            component: o.component,
            settle_s: o.settle,
            settle_max_s: o.settle_max,
            start: o.initial,
            refinement: o.refine.clone(),
            record_s: o.record,
            averaging: o.averaging,
            step_s: r.step,
            sample_interval_s: 1.0 / r.sample_rate_hz,
            samples_per_record: r.samples,
            window: o.window.to_string(),
            resolution_hz: r.resolution_hz,
            max_frequency_hz: r.max_frequency_hz,
            tolerance_bins: o.tolerance_bins,
            full_spectrum: o.full,
            nsv: c.nsv_summary(self.threshold_m),
            bearing_orders: c.bearing_orders.clone(),
            resumed_speeds: c.resumed,
            wall_time_s: c.wall_time_s,
            checkpoint_folder: self.checkpoint_folder.clone(),
            notes: NOTES,
            starts: self.starts.as_ref().map(|s| StartsSummary {
                other_start: s.other,
                compared_speeds: s.compared(),
                differing_speeds_hz: s.differing_speeds_hz(),
                sigmas: STARTS_DIFFER_SIGMAS,
                other_start_nsv: s.cascade.nsv_summary(self.threshold_m),
                note: "differing: the NSV amplitudes from the two starts differ by more than \
                       `sigmas` standard errors of their difference and the larger reaches the \
                       threshold: most likely two coexisting steady motions (starts.csv)",
            }),
        }
    }

    /// `cascade` (amplitude per speed and frequency), `full_cascade` (the same of the full
    /// spectrum, when computed), `nsv` (the NSV at each speed) and `starts` (the comparison
    /// with the other start, when run).
    fn tables(&self) -> Vec<Table> {
        let c = &self.cascade;
        let mut tables = vec![spectra("cascade", c, &c.frequency_hz, |p| &p.amplitude)];
        if c.options.full {
            tables.push(spectra("full_cascade", c, &c.full_frequency_hz, |p| {
                &p.full_amplitude
            }));
        }
        tables.push(nsv_table(c));
        if let Some(s) = &self.starts {
            let p = &s.pairs;
            let mut t = Table::new("starts");
            t.numbers("speed_hz", p.iter().map(|p| p.speed_hz))
                .numbers("nsv_m", p.iter().map(|p| p.first_m))
                .numbers("nsv_standard_error_m", p.iter().map(|p| p.first_error_m))
                .numbers("other_start_nsv_m", p.iter().map(|p| p.other_m))
                .numbers(
                    "other_start_standard_error_m",
                    p.iter().map(|p| p.other_error_m),
                )
                .bits("comparable", p.iter().map(|p| p.comparable))
                .bits("differs", p.iter().map(|p| p.differs));
            tables.push(t);
        }
        tables
    }
}

/// One row per speed and bin of the spectra `amplitude` picks.
fn spectra(
    name: &str,
    c: &Cascade,
    frequencies: &[f64],
    amplitude: fn(&super::CascadePoint) -> &Vec<f64>,
) -> Table {
    let cells: Vec<(&super::CascadePoint, usize)> = c
        .points
        .iter()
        .flat_map(|p| (0..amplitude(p).len().min(frequencies.len())).map(move |k| (p, k)))
        .collect();
    let mut t = Table::new(name);
    t.numbers("speed_hz", cells.iter().map(|(p, _)| p.speed_hz))
        .numbers("frequency_hz", cells.iter().map(|&(_, k)| frequencies[k]))
        .numbers("amplitude_m", cells.iter().map(|&(p, k)| amplitude(p)[k]))
        .bits("added", cells.iter().map(|(p, _)| p.added));
    t
}

/// The NSV at each speed.
fn nsv_table(c: &Cascade) -> Table {
    let (p, n) = (&c.points, &c.nsv);
    let peak = |f: fn(&NsvPeak) -> f64| {
        n.iter()
            .map(move |n| n.as_ref().map_or(f64::NAN, |n| f(&n.peak)))
    };
    let text =
        |f: fn(&super::Nsv) -> String| n.iter().map(move |n| n.as_ref().map_or(String::new(), f));
    let mut t = Table::new("nsv");
    t.numbers("speed_hz", p.iter().map(|p| p.speed_hz))
        .bits("added", p.iter().map(|p| p.added))
        .bits("settled", p.iter().map(|p| p.settled))
        .numbers("settle_s", p.iter().map(|p| p.settle_s))
        .counts("records", p.iter().map(|p| p.records))
        .numbers("one_x_m", p.iter().map(|p| p.one_x_m))
        .numbers("nsv_frequency_hz", peak(|p| p.frequency_hz))
        .numbers("nsv_amplitude_m", peak(|p| p.amplitude_m))
        .numbers("nsv_order", peak(|p| p.order))
        .text("class", text(|n| n.class.name().into()))
        .text("direction", text(|n| n.direction.name().into()))
        .numbers(
            "slope",
            n.iter()
                .map(|n| n.as_ref().and_then(|n| n.slope).unwrap_or(f64::NAN)),
        )
        .numbers("forward_m", peak(|p| p.forward_m))
        .numbers("backward_m", peak(|p| p.backward_m))
        .numbers("decay_ratio", peak(|p| p.decay_ratio))
        .numbers(
            "settling_ratio",
            peak(|p| p.settling_ratio.unwrap_or(f64::NAN)),
        )
        .numbers("nsv_standard_error_m", peak(|p| p.standard_error_m))
        .numbers("nsv_variation", peak(|p| p.variation))
        .text("explanation", text(|n| n.explanation.clone()))
        .text(
            "diverged",
            p.iter().map(|p| p.diverged.clone().unwrap_or_default()),
        )
        .text(
            "start_fallback",
            p.iter()
                .map(|p| p.start_fallback.clone().unwrap_or_default()),
        );
    t
}
