//! What a simulation reports ([`crate::report`]): the run's settings as resolved, what the
//! settled part of each channel shows, and per roller bearing what the rollers did and
//! whether the spectrum shows the frequencies they excite, N_b w_c and (N_w - 1) w_c
//! (thesis eqs. 4.4-4.5), as `whirl simulate` writes them.
//!
//! The time histories themselves (the record and each bearing's roller forces) are in the
//! [`SimulationResult`]; the tables here are the spectra and their peaks.

use std::f64::consts::PI;
use std::ops::Range;

use serde::Serialize;

use super::{Initial, RunStatus, SimulationOptions, SimulationResult};
use crate::bearing::{
    bearing_life, characteristic_frequencies, contact_frequencies, BearingLife,
    CharacteristicFrequencies, ContactFrequency, ContactLaw, LifeLoads,
};
use crate::error::Result;
use crate::model::{Model, RollerBearing};
use crate::post::{SpectralPeak, Window};
use crate::report::{Report, Table};
use crate::system::SpeedProfile;
use crate::time::{
    peak_near, ContactSummary, RkStats, RollerRecord, SettledChannel, ORDER_TOLERANCE_BINS,
};
use crate::units::rad_s_to_hz as hz;

/// A predicted frequency is matched with the largest spectral peak within this many bins.
/// The flat-top window's main lobe spans +-5 bins, so a component shows as a local maximum
/// within one bin of its frequency; 3 leaves room to see (in `offset_bins`) how far off a
/// peak is without reaching a neighbouring component's lobe.
pub const MATCH_BINS: f64 = 3.0;

/// The contact line spans this many cage revolutions: each roller passes the loaded zone
/// this often.
pub const CONTACT_LINE_CAGE_TURNS: f64 = 3.0;

/// The longest file-name stem of a bearing, in characters: a name of any length must
/// still make a file name within the 255 bytes most file systems allow.
const MAX_SLUG: usize = 64;

/// What the summary says about the numbers.
const NOTES: [&str; 4] = [
    "1X amplitude and phase by order tracking of the settled part; phase as in `whirl unbalance` (x = A cos(Omega t + phase))",
    "spectra: flat-top window, mean removed, zero-to-peak amplitude",
    "divergence_bound (m) applies to the recorded displacements (ux, uy of the recorded nodes, bearing nodes included); any integrated coordinate beyond 1000 times it, rotations and modal coordinates too, also counts as divergence",
    "bearings: contact statistics over the settled part; a roller is in contact when it carries load (for the forcing-function law, when it penetrates); measured peaks are the largest spectral peak of the bearing node's channel within 3 bins of the prediction",
];

/// A simulation with its settled part read.
#[derive(Debug, Clone)]
pub struct SimulationReport {
    /// The run.
    pub result: SimulationResult,
    /// What the settled part of each channel shows.
    pub channels: Vec<SettledChannel>,
    /// What each roller bearing did.
    pub bearings: Vec<BearingReport>,
    /// The contact law used.
    pub contact: ContactLaw,
    /// The speed over time.
    pub speed: SpeedProfile,
    /// Simulated time, s.
    pub duration: f64,
    /// Fixed-interface modes of the reduction, if reduced.
    pub reduction: Option<usize>,
    /// Initial state.
    pub start: Initial,
    /// Divergence bound of the recorded displacements, m.
    pub divergence_bound: f64,
}

/// A predicted contact frequency and the peaks measured near it.
#[derive(Debug, Clone)]
pub struct FrequencyCheck {
    /// What excites it and where it should be.
    pub predicted: ContactFrequency,
    /// Per channel of the bearing's node: the channel and the peak found, if any.
    pub measured: Vec<(String, Option<SpectralPeak>)>,
}

/// What one roller bearing did.
#[derive(Debug, Clone)]
pub struct BearingReport {
    /// Index of its record in [`SimulationResult::rollers`].
    pub roller: usize,
    /// File-name stem, `bearing_a`: the name in lower case with every run of other
    /// characters than letters and digits made one `_`, numbered when two would collide.
    pub stem: String,
    /// Clearance at the final speed, m.
    pub clearance: f64,
    /// Statistics over the settled part.
    pub settled: ContactSummary,
    /// Statistics over the whole run.
    pub whole: ContactSummary,
    /// Cage speed at the final speed, Hz.
    pub cage_hz: f64,
    /// Spectrum bin width, Hz.
    pub resolution_hz: f64,
    /// Contact frequencies and the peaks that show them.
    pub frequencies: Vec<FrequencyCheck>,
    /// The bearing's characteristic frequencies at the final speed, Hz.
    pub characteristic: CharacteristicFrequencies,
    /// Samples of the contact line: the first [`CONTACT_LINE_CAGE_TURNS`] cage revolutions
    /// of the settled part.
    pub line_window: Range<usize>,
    /// Samples of the settled part.
    pub settled_range: Range<usize>,
    /// Fatigue life under the settled part's roller loads (`None` without per-roller
    /// forces or a load rating).
    pub life: Option<BearingLife>,
}

impl RunStatus {
    /// `completed`, `diverged` or `stopped`.
    pub fn name(&self) -> &'static str {
        match self {
            RunStatus::Completed => "completed",
            RunStatus::Diverged { .. } => "diverged",
            RunStatus::Stopped { .. } => "stopped",
        }
    }
}

impl Initial {
    /// The start's name on the command line: `static` or `rest`.
    pub fn name(self) -> &'static str {
        match self {
            Initial::StaticEquilibrium => "static",
            Initial::Rest => "rest",
        }
    }
}

/// `bearing A` -> `bearing_a`, cut to [`MAX_SLUG`] characters.
fn slug(name: &str) -> String {
    let mut s = String::new();
    for c in name.chars().take(MAX_SLUG) {
        if c.is_ascii_alphanumeric() {
            s.push(c.to_ascii_lowercase());
        } else if !s.ends_with('_') {
            s.push('_');
        }
    }
    let s = s.trim_matches('_').to_string();
    if s.is_empty() {
        "bearing".into()
    } else {
        s
    }
}

/// File stems of `names`, numbered (`_2`, `_3`) where two would collide.
fn stems(names: &[&str]) -> Vec<String> {
    let mut out: Vec<String> = Vec::new();
    for name in names {
        let base = slug(name);
        let mut stem = base.clone();
        let mut k = 2;
        while out.contains(&stem) {
            stem = format!("{base}_{k}");
            k += 1;
        }
        out.push(stem);
    }
    out
}

/// `1X`, `2X` at multiples of the running speed, `0.5X`, `1.5X` at half orders (where
/// sub-synchronous whirl sits), otherwise `non-synchronous`.
pub fn order_label(frequency_hz: f64, running_hz: f64, tolerance_hz: f64) -> String {
    if running_hz > 0.0 {
        let halves = (2.0 * frequency_hz / running_hz).round();
        if halves >= 1.0 && (frequency_hz - 0.5 * halves * running_hz).abs() <= tolerance_hz {
            return format!("{}X", 0.5 * halves);
        }
    }
    "non-synchronous".into()
}

impl SimulationReport {
    /// The report of `result`, run on `model` with `options`.
    ///
    /// # Errors
    /// The errors of [`SimulationResult::settled`] (too short a settled part).
    pub fn new(
        model: &Model,
        options: &SimulationOptions,
        result: SimulationResult,
    ) -> Result<SimulationReport> {
        let speed = options.speed;
        let channels = result.settled(&speed)?;
        let final_speed = speed.at(options.duration).0.speed;
        let bearings = bearing_reports(model, &result, &channels, final_speed);
        Ok(SimulationReport {
            result,
            channels,
            bearings,
            contact: options.contact_law(model),
            speed,
            duration: options.duration,
            reduction: options.reduction,
            start: options.initial,
            divergence_bound: options.divergence_bound,
        })
    }

    /// The speed at the end of the run, rad/s.
    pub fn final_speed(&self) -> f64 {
        self.speed.at(self.duration).0.speed
    }

    /// The running speed at the end of the run, Hz.
    pub fn running_hz(&self) -> f64 {
        hz(self.final_speed())
    }

    /// The spectra's bin width, Hz (NaN without channels).
    pub fn resolution_hz(&self) -> f64 {
        self.channels
            .first()
            .map_or(f64::NAN, |r| r.spectrum.resolution_hz)
    }

    /// The record of bearing report `b`.
    pub fn record(&self, b: &BearingReport) -> &RollerRecord {
        &self.result.rollers[b.roller]
    }
}

/// One report per roller bearing recorded; `speed` is the final spin speed, rad/s.
fn bearing_reports(
    model: &Model,
    result: &SimulationResult,
    channels: &[SettledChannel],
    speed: f64,
) -> Vec<BearingReport> {
    let running_hz = hz(speed);
    let names: Vec<&str> = result.rollers.iter().map(|r| r.name.as_str()).collect();
    let start = result.settled_start();
    let end = result.time.len();
    let resolution_hz = channels
        .first()
        .map_or(f64::NAN, |r| r.spectrum.resolution_hz);
    result
        .rollers
        .iter()
        .enumerate()
        .zip(stems(&names))
        .zip(&model.roller_bearings)
        .map(|(((roller, record), stem), bearing)| {
            let frequencies = contact_frequencies(bearing, speed)
                .into_iter()
                .map(|predicted| FrequencyCheck {
                    measured: channels
                        .iter()
                        .filter(|r| r.node == record.node)
                        .map(|r| {
                            let peak = peak_near(
                                &r.spectrum,
                                predicted.frequency_hz,
                                MATCH_BINS,
                                running_hz,
                            );
                            (r.name.clone(), peak)
                        })
                        .collect(),
                    predicted,
                })
                .collect();
            let cage_hz = record.cage_ratio * speed / (2.0 * PI);
            let line_end = if cage_hz > 0.0 {
                let span = CONTACT_LINE_CAGE_TURNS / cage_hz;
                start + result.time[start..].partition_point(|&t| t < result.time[start] + span)
            } else {
                end
            };
            BearingReport {
                roller,
                stem,
                clearance: bearing.clearance.at_speed(speed),
                settled: record.summary(start..end),
                whole: record.summary(0..end),
                cage_hz,
                resolution_hz,
                frequencies,
                characteristic: characteristic_frequencies(bearing, running_hz),
                line_window: start..line_end.min(end),
                settled_range: start..end,
                life: settled_life(bearing, record, start..end, speed),
            }
        })
        .collect()
}

/// The life of `bearing` under the roller loads of `record` over `samples`, at `speed`
/// (rad/s): each sample's radial force is the vector sum of its rollers' loads, which for a
/// ball bearing holds without an axial load (its L10 is left out with one).
fn settled_life(
    bearing: &RollerBearing,
    record: &RollerRecord,
    samples: Range<usize>,
    speed: f64,
) -> Option<BearingLife> {
    let n = record.rollers;
    let mut loads = LifeLoads::default();
    for i in samples {
        let (angles, forces) = (
            &record.angle[i * n..(i + 1) * n],
            &record.force[i * n..(i + 1) * n],
        );
        if forces.iter().any(|f| !f.is_finite()) {
            return None;
        }
        let (fx, fy) = angles
            .iter()
            .zip(forces)
            .fold((0.0, 0.0), |(x, y), (a, f)| {
                (x + f * a.cos(), y + f * a.sin())
            });
        loads.add(bearing, fx.hypot(fy), forces);
    }
    bearing_life(bearing, &loads, speed)
}

/// The key numbers of a [`SimulationReport`].
#[derive(Debug, Clone, Serialize)]
pub struct SimulationSummary {
    /// Integrator.
    pub method: String,
    /// Contact law.
    pub contact: &'static str,
    /// Spin speed (at the start of a ramp), Hz.
    pub speed_hz: f64,
    /// Speed at the end of the ramp, Hz.
    pub ramp_to_hz: Option<f64>,
    /// Speed at the end of the run, Hz.
    pub running_speed_hz: f64,
    /// Simulated time, s.
    pub duration_s: f64,
    /// Settling time, s.
    pub settle_s: f64,
    /// Time step, s.
    pub step_s: f64,
    /// Stable step of the explicit integrator, s.
    pub stable_step_s: f64,
    /// Fixed-interface modes of the reduction, if reduced.
    pub reduction_modes: Option<usize>,
    /// Integrated coordinates.
    pub coordinates: usize,
    /// Initial state (`static` or `rest`).
    pub start: &'static str,
    /// Why the run started from rest instead, if it did.
    pub start_fallback: Option<String>,
    /// Samples recorded.
    pub samples: usize,
    /// Steps per sample.
    pub record_every: usize,
    /// Time between samples, s.
    pub sample_interval_s: f64,
    /// Wall-clock time, s.
    pub wall_time_s: f64,
    /// Runge-Kutta statistics, if that integrator ran.
    pub rk_stats: Option<RkStats>,
    /// How the run ended ([`RunStatus::name`]).
    pub status: &'static str,
    /// Window of the spectra.
    pub spectrum_window: String,
    /// Bin width of the spectra, Hz.
    pub spectrum_resolution_hz: f64,
    /// What the settled part of each channel shows.
    pub channels: Vec<ChannelSummary>,
    /// What the numbers are.
    pub notes: [&'static str; 4],
    /// Divergence bound, m.
    pub divergence_bound: f64,
    /// What each roller bearing did.
    pub bearings: Vec<BearingSummary>,
}

/// One channel's settled part.
#[derive(Debug, Clone, Serialize)]
pub struct ChannelSummary {
    /// Channel, e.g. `n10.ux`.
    pub name: String,
    /// Node.
    pub node: usize,
    /// Mean, m.
    pub mean_m: f64,
    /// 1X amplitude, m.
    pub one_x_amplitude_m: Option<f64>,
    /// 1X phase, degrees.
    pub one_x_phase_deg: Option<f64>,
    /// Peak-to-peak, m.
    pub peak_to_peak_m: f64,
    /// The largest non-synchronous peak.
    pub largest_non_synchronous: Option<PeakSummary>,
    /// The spectral peaks.
    pub peaks: Vec<PeakSummary>,
}

/// One spectral peak.
#[derive(Debug, Clone, Serialize)]
pub struct PeakSummary {
    /// Frequency, Hz.
    pub frequency_hz: f64,
    /// Amplitude, m.
    pub amplitude_m: f64,
    /// Order of the running speed.
    pub order: Option<f64>,
    /// `1X`, `0.5X`, ... or `non-synchronous` ([`order_label`]).
    pub label: String,
}

/// One roller bearing.
#[derive(Debug, Clone, Serialize)]
pub struct BearingSummary {
    /// Name.
    pub name: String,
    /// Node.
    pub node: usize,
    /// File-name stem.
    pub file_stem: String,
    /// Rollers.
    pub rollers: usize,
    /// Clearance at the final speed, m.
    pub clearance_m: f64,
    /// Cage speed, Hz.
    pub cage_speed_hz: f64,
    /// N_b w_c, Hz.
    pub varying_compliance_hz: Option<f64>,
    /// Waviness frequencies, Hz.
    pub waviness_hz: Vec<f64>,
    /// Characteristic frequencies (FTF, BPFO, BPFI, BSF, N_b w_c) at the final speed, Hz.
    pub characteristic_hz: CharacteristicFrequencies,
    /// Bin width, Hz.
    pub spectrum_resolution_hz: f64,
    /// Contact statistics over the settled part.
    pub settled: ContactStatistics,
    /// The same over the whole run.
    pub whole_run: ContactStatistics,
    /// Each predicted frequency and the peaks near it.
    pub frequencies: Vec<FrequencySummary>,
    /// Fatigue life under the settled part's roller loads.
    pub life: Option<BearingLife>,
}

/// Contact statistics.
#[derive(Debug, Clone, Serialize)]
pub struct ContactStatistics {
    /// Samples counted.
    pub samples: usize,
    /// Most rollers in contact at once.
    pub max_in_contact: usize,
    /// Fewest.
    pub min_in_contact: usize,
    /// Mean.
    pub mean_in_contact: f64,
    /// Largest penetration, m.
    pub largest_penetration_m: f64,
    /// Largest roller force, N.
    pub largest_force_n: f64,
}

/// A predicted frequency and the peaks measured near it.
#[derive(Debug, Clone, Serialize)]
pub struct FrequencySummary {
    /// What excites it.
    pub source: String,
    /// Cage orders.
    pub cage_orders: f64,
    /// Predicted frequency, Hz.
    pub predicted_hz: f64,
    /// Per channel of the bearing's node.
    pub measured: Vec<MeasuredPeak>,
}

/// The peak found near a predicted frequency in one channel.
#[derive(Debug, Clone, Serialize)]
pub struct MeasuredPeak {
    /// Channel.
    pub channel: String,
    /// Frequency, Hz.
    pub frequency_hz: Option<f64>,
    /// Amplitude, m.
    pub amplitude_m: Option<f64>,
    /// Distance from the prediction in bins.
    pub offset_bins: Option<f64>,
}

fn statistics(s: &ContactSummary) -> ContactStatistics {
    ContactStatistics {
        samples: s.samples,
        max_in_contact: s.max_in_contact,
        min_in_contact: s.min_in_contact,
        mean_in_contact: s.mean_in_contact,
        largest_penetration_m: s.largest_penetration,
        largest_force_n: s.largest_force,
    }
}

fn peak_summary(p: &SpectralPeak, running_hz: f64, tolerance_hz: f64) -> PeakSummary {
    PeakSummary {
        frequency_hz: p.frequency_hz,
        amplitude_m: p.amplitude,
        order: p.order.is_finite().then_some(p.order),
        label: order_label(p.frequency_hz, running_hz, tolerance_hz),
    }
}

impl SimulationReport {
    fn bearing_summary(&self, b: &BearingReport) -> BearingSummary {
        let record = self.record(b);
        BearingSummary {
            name: record.name.clone(),
            node: record.node,
            file_stem: b.stem.clone(),
            rollers: record.rollers,
            clearance_m: b.clearance,
            cage_speed_hz: b.cage_hz,
            varying_compliance_hz: b.frequencies.first().map(|f| f.predicted.frequency_hz),
            waviness_hz: b
                .frequencies
                .iter()
                .filter(|f| f.predicted.source.contains("waviness"))
                .map(|f| f.predicted.frequency_hz)
                .collect(),
            characteristic_hz: b.characteristic,
            life: b.life.clone(),
            spectrum_resolution_hz: b.resolution_hz,
            settled: statistics(&b.settled),
            whole_run: statistics(&b.whole),
            frequencies: b
                .frequencies
                .iter()
                .map(|f| FrequencySummary {
                    source: f.predicted.source.clone(),
                    cage_orders: f.predicted.cage_orders,
                    predicted_hz: f.predicted.frequency_hz,
                    measured: f
                        .measured
                        .iter()
                        .map(|(channel, peak)| MeasuredPeak {
                            channel: channel.clone(),
                            frequency_hz: peak.map(|p| p.frequency_hz),
                            amplitude_m: peak.map(|p| p.amplitude),
                            offset_bins: peak.map(|p| {
                                (p.frequency_hz - f.predicted.frequency_hz) / b.resolution_hz
                            }),
                        })
                        .collect(),
                })
                .collect(),
        }
    }
}

impl Report for SimulationReport {
    type Summary = SimulationSummary;

    fn summary(&self) -> SimulationSummary {
        let result = &self.result;
        let running_hz = self.running_hz();
        let resolution = self.resolution_hz();
        let tolerance_hz = ORDER_TOLERANCE_BINS * resolution;
        let (speed, ramp_to) = match self.speed {
            SpeedProfile::Constant(w) => (w, None),
            SpeedProfile::Ramp { from, to, .. } => (from, Some(to)),
        };
        SimulationSummary {
            method: result.method.clone(),
            contact: self.contact.name(),
            speed_hz: hz(speed),
            ramp_to_hz: ramp_to.map(hz),
            running_speed_hz: running_hz,
            duration_s: self.duration,
            settle_s: result.settle,
            step_s: result.step,
            stable_step_s: result.stable_step,
            reduction_modes: self.reduction,
            coordinates: result.coordinates,
            start: self.start.name(),
            start_fallback: result.start_fallback.clone(),
            samples: result.time.len(),
            record_every: result.record_every,
            sample_interval_s: result.sample_interval(),
            wall_time_s: result.wall_time_s,
            rk_stats: result.rk_stats,
            status: result.status.name(),
            spectrum_window: Window::FlatTop.to_string(),
            spectrum_resolution_hz: resolution,
            channels: self
                .channels
                .iter()
                .map(|r| ChannelSummary {
                    name: r.name.clone(),
                    node: r.node,
                    mean_m: r.mean,
                    one_x_amplitude_m: r.one_x.map(|c| c.amplitude),
                    one_x_phase_deg: r.one_x.map(|c| c.phase.to_degrees()),
                    peak_to_peak_m: r.peak_to_peak,
                    largest_non_synchronous: r
                        .non_synchronous
                        .map(|p| peak_summary(&p, running_hz, tolerance_hz)),
                    peaks: r
                        .peaks
                        .iter()
                        .map(|p| peak_summary(p, running_hz, tolerance_hz))
                        .collect(),
                })
                .collect(),
            notes: NOTES,
            divergence_bound: self.divergence_bound,
            bearings: self
                .bearings
                .iter()
                .map(|b| self.bearing_summary(b))
                .collect(),
        }
    }

    /// `time_history` (`time_s` and each recorded channel), `spectrum` (the settled part's
    /// amplitude spectrum of each channel), `peaks` (each channel's spectral peaks with their
    /// order and label) and per roller bearing `contacts_<stem>` (at each recorded time the
    /// rollers in contact and each roller's force, missing out of contact, and approach).
    fn tables(&self) -> Vec<Table> {
        let mut history = Table::new("time_history");
        history.numbers("time_s", self.result.time.iter().copied());
        for c in &self.result.channels {
            history.numbers(c.name.clone(), c.values.iter().copied());
        }
        let mut tables = vec![history];
        tables.extend(self.spectrum_tables());
        tables.extend(self.bearings.iter().map(|b| self.contact_table(b)));
        tables
    }
}

impl SimulationReport {
    /// The table `contacts_<stem>` of bearing report `b`.
    fn contact_table(&self, b: &BearingReport) -> Table {
        let r = self.record(b);
        let samples = 0..self.result.time.len();
        let mut t = Table::new(format!("contacts_{}", b.stem));
        t.numbers("time_s", self.result.time.iter().copied())
            .counts("in_contact", samples.clone().map(|i| r.contacts_at(i)));
        for j in 0..r.rollers {
            t.numbers(
                format!("roller_{j}_force_n"),
                samples.clone().map(|i| r.forces_at(i)[j]),
            );
        }
        for j in 0..r.rollers {
            t.numbers(
                format!("roller_{j}_approach_m"),
                samples.clone().map(|i| r.approaches_at(i)[j]),
            );
        }
        t
    }

    /// `spectrum` and `peaks`.
    fn spectrum_tables(&self) -> Vec<Table> {
        let channels = &self.channels;
        let frequencies = channels
            .first()
            .map_or(&[][..], |r| &r.spectrum.frequency_hz);
        let mut spectrum = Table::new("spectrum");
        spectrum.numbers("frequency_hz", frequencies.iter().copied());
        for r in channels {
            spectrum.numbers(
                r.name.clone(),
                (0..frequencies.len()).map(|k| r.spectrum.amplitude[k]),
            );
        }
        let running_hz = self.running_hz();
        let rows: Vec<(&SettledChannel, &SpectralPeak)> = channels
            .iter()
            .flat_map(|r| r.peaks.iter().map(move |p| (r, p)))
            .collect();
        let mut peaks = Table::new("peaks");
        peaks
            .text("channel", rows.iter().map(|(r, _)| r.name.as_str()))
            .numbers("frequency_hz", rows.iter().map(|(_, p)| p.frequency_hz))
            .numbers("amplitude_m", rows.iter().map(|(_, p)| p.amplitude))
            .numbers("order", rows.iter().map(|(_, p)| p.order))
            .text(
                "label",
                rows.iter().map(|(r, p)| {
                    let tolerance_hz = ORDER_TOLERANCE_BINS * r.spectrum.resolution_hz;
                    order_label(p.frequency_hz, running_hz, tolerance_hz)
                }),
            );
        vec![spectrum, peaks]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stems_are_file_safe_and_distinct() {
        assert_eq!(
            stems(&["bearing A", "Bearing-A", "", "x/y"]),
            ["bearing_a", "bearing_a_2", "bearing", "x_y"]
        );
        // A 300-character name: used whole as a file name it failed with "File name too long"
        // after the computation.
        let long = "b".repeat(300);
        assert_eq!(
            stems(&[&long, &long]),
            [long[..64].to_string(), format!("{}_2", &long[..64])]
        );
    }
}
