//! What a cascade computes, and the derived numbers every speed shares (time step,
//! sampling, frequency band).

use serde::Serialize;

use crate::bearing::{contact_frequencies, ContactLaw};
use crate::error::{Error, InputError, Result};
use crate::model::Model;
use crate::post::spectrum::MIN_SAMPLES;
use crate::post::Window;
use crate::system::{Linear, SpeedProfile};
use crate::time::{
    Initial, Method, SimulationOptions, DEFAULT_DIVERGENCE_BOUND, DEFAULT_MODES, MAX_STEPS,
};
use crate::units::rad_s_to_hz;

/// Speeds of a cascade given none: this many over the model's operating range
/// ([`default_speeds`]).
pub const DEFAULT_SPEED_COUNT: usize = 150;

/// Default shortest settling time, s: the first record is taken after it.
pub const DEFAULT_SETTLE: f64 = 0.5;

/// Default time recorded at each speed, s: 2 Hz bins.
pub const DEFAULT_RECORD: f64 = 0.5;

/// Default initial state of every run: the static equilibrium under gravity, where the
/// rotor runs in service.
pub const DEFAULT_START: Initial = Initial::StaticEquilibrium;

/// Default displacement of the one-sided spectrum: the vertical, as the thesis' cascades
/// (figs. 5.x) show the disk's response.
pub const DEFAULT_COMPONENT: Component = Component::Uy;

/// Default data window of the spectra.
pub const DEFAULT_WINDOW: Window = Window::Hann;

/// Default longest settling time, s: a speed whose start has not died away by then is
/// reported unsettled. The reference rotor's first mode (2 % damping, 50 Hz) loses a factor
/// of 500 per second, so free vibration of tens of micrometres is gone well within it.
pub const DEFAULT_SETTLE_MAX: f64 = 4.0;

/// Default fewest records averaged at a settled speed: four half-second records
/// overlapping by half (1.25 s) nearly halve the scatter of one.
pub const DEFAULT_MIN_RECORDS: usize = 4;

/// Default most records averaged at a settled speed (8.25 s of steady motion with 0.5 s
/// records overlapping by half).
pub const DEFAULT_MAX_RECORDS: usize = 32;

/// Default tolerance of the averaged NSV: a standard error within 5 % of its amplitude ...
pub const DEFAULT_RELATIVE_ERROR: f64 = 0.05;

/// ... or within this, m: NSV of a few tenths of a micrometre need not be known better.
pub const DEFAULT_ABSOLUTE_ERROR_M: f64 = 5e-8;

/// ... or within this fraction once the NSV is clear of every onset level: an irregular
/// whip (records scattering by 35-50 %) gets there in about seven records, where 5 % would
/// take over a hundred; the median, mean and 90th percentile over a range of speeds average
/// such scatter down.
pub const DEFAULT_DECIDED_ERROR: f64 = 0.2;

/// Default largest number of speeds the refinement adds.
pub const DEFAULT_MAX_ADDED: usize = 60;

/// Default smallest spacing the refinement makes between two speeds, Hz.
pub const DEFAULT_MIN_SPACING_HZ: f64 = 0.5;

/// Default NSV levels whose onset the refinement brackets, m: 1 um (the summary's default
/// threshold) and 10 um.
pub const DEFAULT_ONSET_LEVELS_M: [f64; 2] = [1e-6, 1e-5];

/// Default tolerance of "at a multiple of the running speed", in bins: the Hann window's
/// main lobe is +-2 bins, so a synchronous peak refined between bins lies well inside.
pub const DEFAULT_TOLERANCE_BINS: f64 = 2.0;

/// The default band reaches this many times the top running speed (2X and a margin) ...
const BAND_ORDERS: f64 = 2.5;
/// ... or this far above the highest varying-compliance or waviness frequency at the top
/// speed, whichever is higher.
const BAND_MARGIN: f64 = 1.25;

/// Which displacement of the response node the one-sided spectrum is taken of.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[cfg_attr(feature = "clap", derive(clap::ValueEnum))]
#[serde(rename_all = "lowercase")]
pub enum Component {
    /// Horizontal, u_x.
    Ux,
    /// Vertical, u_y.
    Uy,
}

/// How the speed grid is refined after the requested speeds (see the module
/// documentation of [`crate::nsv`]).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Refinement {
    /// Whether speeds are added at all.
    pub enabled: bool,
    /// At most this many speeds are added.
    pub max_added: usize,
    /// No speed is added closer than this to another, Hz.
    pub min_spacing_hz: f64,
    /// NSV levels (m, zero-to-peak) whose onset (the lowest speed reaching them) is
    /// bracketed down to the smallest spacing; the smallest is also the level below which
    /// sharp changes between neighbours are not refined.
    pub onset_levels_m: Vec<f64>,
}

impl Default for Refinement {
    fn default() -> Self {
        Refinement {
            enabled: true,
            max_added: DEFAULT_MAX_ADDED,
            min_spacing_hz: DEFAULT_MIN_SPACING_HZ,
            onset_levels_m: DEFAULT_ONSET_LEVELS_M.to_vec(),
        }
    }
}

/// How many records of a settled speed are averaged (see the module documentation of
/// [`crate::nsv`]).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Averaging {
    /// At least this many records (1 or more).
    pub min_records: usize,
    /// At most this many records (at least `min_records`; 1 for a single record).
    pub max_records: usize,
    /// Averaging stops once the NSV's standard error is within this fraction of it ...
    pub relative_error: f64,
    /// ... or within this, m ...
    pub absolute_error_m: f64,
    /// ... or within this fraction with the NSV clear of every onset level of the
    /// refinement (see [`crate::nsv`]'s averaging rule).
    pub decided_error: f64,
}

impl Averaging {
    /// Time spanned by the most records, s, for records `record` seconds long.
    pub fn recorded_time(&self, record: f64) -> f64 {
        records_span(self.max_records, record)
    }
}

/// Time spanned by `count` records `record` seconds long overlapping by half, s.
pub fn records_span(count: usize, record: f64) -> f64 {
    0.5 * (count as f64 + 1.0) * record
}

impl Default for Averaging {
    fn default() -> Self {
        Averaging {
            min_records: DEFAULT_MIN_RECORDS,
            max_records: DEFAULT_MAX_RECORDS,
            relative_error: DEFAULT_RELATIVE_ERROR,
            absolute_error_m: DEFAULT_ABSOLUTE_ERROR_M,
            decided_error: DEFAULT_DECIDED_ERROR,
        }
    }
}

/// What a cascade computes. Build with [`CascadeOptions::new`] and change fields.
#[derive(Debug, Clone, Serialize)]
pub struct CascadeOptions {
    /// Requested spin speeds, rad/s, each positive (the results hold them and the added
    /// speeds in ascending order).
    pub speeds: Vec<f64>,
    /// Shortest time simulated and discarded before the record at each speed, s.
    pub settle: f64,
    /// Longest settling time, s: the run at a speed goes on (checked every half record)
    /// until its start has died away or this is reached. Equal to `settle` for a fixed
    /// settling time.
    pub settle_max: f64,
    /// Where each run starts: the static equilibrium under gravity, or rest.
    pub initial: Initial,
    /// Speeds added where the NSV changes sharply.
    pub refine: Refinement,
    /// Time of one record, whose spectrum is taken, s. The bin spacing is its inverse.
    pub record: f64,
    /// How many records of a settled speed are averaged.
    pub averaging: Averaging,
    /// Contact law of the roller bearings.
    pub law: ContactLaw,
    /// Craig-Bampton reduction with this many fixed-interface modes; `None` for the full
    /// model.
    pub reduction: Option<usize>,
    /// Central-difference time step, s; `None` for [`crate::time::STABLE_FRACTION`] of the
    /// stability limit.
    pub step: Option<f64>,
    /// The node whose response is analysed.
    pub node: usize,
    /// Which of its displacements gives the one-sided spectrum (the full spectrum uses both).
    pub component: Component,
    /// Data window of the spectra.
    pub window: Window,
    /// Top of the frequency band kept and searched, Hz; `None` for the default (the higher of
    /// 2.5 times the top speed and 1.25 times the highest contact frequency there).
    pub max_frequency_hz: Option<f64>,
    /// A peak within this many bins of a multiple of the running speed is synchronous; the
    /// same tolerance names 0.5X and contact combinations.
    pub tolerance_bins: f64,
    /// Keep the full (two-sided) spectrum of `x + i y` of every speed, not only its reading
    /// at the NSV peak.
    pub full: bool,
    /// A recorded displacement beyond this (m) means the run at that speed diverged.
    pub divergence_bound: f64,
}

/// The speeds of a cascade given none, rad/s: [`DEFAULT_SPEED_COUNT`] evenly spaced from the
/// low to the high bound of the model's `[operating]` range, both included. A range that
/// starts at rest starts at high / [`DEFAULT_SPEED_COUNT`] instead: a cascade needs a
/// running speed at each point. The command line, the study and the Python package all
/// take their default from here.
///
/// # Errors
/// [`Error::Input`] naming `speeds` when the model states no operating range.
pub fn default_speeds(model: &Model) -> Result<Vec<f64>> {
    let Some((low, high)) = model.operating else {
        return Err(bad(
            "speeds",
            "the model states no operating speed range".into(),
            "give the speeds (e.g. 1:750Hz:150), or add [operating] to the model",
        ));
    };
    let n = DEFAULT_SPEED_COUNT;
    let low = if low > 0.0 { low } else { high / n as f64 };
    Ok(even_speeds(low, high, n))
}

/// `n` (at least 2) speeds evenly spaced from `low` to `high`, both included.
pub fn even_speeds(low: f64, high: f64, n: usize) -> Vec<f64> {
    let step = (high - low) / (n.max(2) - 1) as f64;
    (0..n.max(2)).map(|i| low + step * i as f64).collect()
}

impl CascadeOptions {
    /// The defaults for `model` at `speeds` (rad/s): settling from 0.5 s until the start
    /// has died away (at most 4 s) from the static equilibrium, 0.5 s recorded (2 Hz
    /// bins), the grid refined ([`Refinement::default`]), the model's default contact law (Hertz with roller bearings), the
    /// reduced model ([`DEFAULT_MODES`]), the first disk's node (else the middle node), its
    /// vertical displacement, Hann window, the default band, 2 bins tolerance.
    pub fn new(model: &Model, speeds: Vec<f64>) -> Self {
        let node = model
            .disks
            .first()
            .map_or(model.node_count() / 2, |d| d.station.node);
        CascadeOptions {
            speeds,
            settle: DEFAULT_SETTLE,
            settle_max: DEFAULT_SETTLE_MAX.max(DEFAULT_SETTLE),
            initial: DEFAULT_START,
            refine: Refinement::default(),
            record: DEFAULT_RECORD,
            averaging: Averaging::default(),
            law: ContactLaw::default_for(model),
            reduction: Some(DEFAULT_MODES),
            step: None,
            node,
            component: DEFAULT_COMPONENT,
            window: DEFAULT_WINDOW,
            max_frequency_hz: None,
            tolerance_bins: DEFAULT_TOLERANCE_BINS,
            full: false,
            divergence_bound: DEFAULT_DIVERGENCE_BOUND,
        }
    }

    /// The settings of every run of the cascade, at rest: each point sets its speed, its
    /// duration and the resolved step and sampling. Channels only, no roller records: one
    /// response per speed is all a point reads.
    pub(crate) fn run_settings(&self) -> SimulationOptions {
        SimulationOptions {
            step: self.step,
            method: Method::CentralDifference,
            contact: Some(self.law),
            reduction: self.reduction,
            settle: Some(self.settle),
            nodes: Some(vec![self.node]),
            initial: self.initial,
            divergence_bound: self.divergence_bound,
            record_rollers: false,
            ..SimulationOptions::new(SpeedProfile::Constant(0.0))
        }
    }
}

/// Numbers derived once from the options and shared by every speed.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Resolved {
    /// Time step, s.
    pub step: f64,
    /// Steps per recorded sample.
    pub record_every: usize,
    /// Samples in the record whose spectrum is taken.
    pub samples: usize,
    /// Sample rate of the record, Hz.
    pub sample_rate_hz: f64,
    /// Bin spacing, Hz.
    pub resolution_hz: f64,
    /// Top of the band, Hz.
    pub max_frequency_hz: f64,
    /// One-sided bins kept: 0 up to `bins - 1`.
    pub bins: usize,
}

/// The most samples in a cascade's record: each thread holds two spectrum plans of the
/// record's length, with their windows and buffers (about 60 bytes a sample), so 2^22
/// samples are a quarter of a GB a thread, and 42 s recorded at the default 100 kHz already
/// resolves 0.024 Hz, finer than any NSV question needs.
pub const MAX_RECORD_SAMPLES: usize = 1 << 22;

/// An option error naming the field.
fn bad(field: &str, message: String, help: &str) -> Error {
    InputError::field(field, message).help(help).into()
}

/// Works out step, sampling and band of options already checked ([`check`]), the
/// stability limit from the model's `linear` system made for them.
pub(super) fn resolve(model: &Model, o: &CascadeOptions, linear: &Linear) -> Result<Resolved> {
    // Recorded at the simulation's default interval (100 kHz), far above every frequency of
    // the band and the bearing nodes' contact resonances, so nothing aliases into the band.
    let run = o.run_settings();
    let step = run.time_step_on(model, linear)?;
    let record_every = run.record_interval(step);
    let step = match o.step {
        Some(_) => step,
        None => fft_friendly_step(step, record_every, o.record),
    };
    let interval = step * record_every as f64;
    let samples = (o.record / interval + 1e-9).floor() as usize;
    if !(MIN_SAMPLES..=MAX_RECORD_SAMPLES).contains(&samples) {
        let fix = if samples < MIN_SAMPLES {
            "longer"
        } else {
            "shorter"
        };
        return Err(bad(
            "record",
            format!(
                "{} s recorded at {interval:.3e} s per sample gives {samples} samples; a \
                 spectrum takes from {MIN_SAMPLES} to {MAX_RECORD_SAMPLES}",
                o.record
            ),
            &format!("record {fix} (0.5 s gives 2 Hz bins)"),
        ));
    }
    check_longest_run(o, step)?;
    let sample_rate_hz = 1.0 / interval;
    let resolution_hz = sample_rate_hz / samples as f64;
    let nyquist = 0.5 * sample_rate_hz;
    let max_frequency_hz = o
        .max_frequency_hz
        .unwrap_or_else(|| default_band(model, &o.speeds))
        .min(nyquist);
    let bins = ((max_frequency_hz / resolution_hz).floor() as usize + 1).min(samples / 2 + 1);
    Ok(Resolved {
        step,
        record_every,
        samples,
        sample_rate_hz,
        resolution_hz,
        max_frequency_hz,
        bins,
    })
}

/// The default `step`, shortened by less than a record's worth of samples so that `record`
/// seconds sampled every `record_every` steps hold a number of samples with no prime factor
/// above 5. The FFT of such a length runs a mixed-radix plan; 0.5 s at the reference
/// rotor's step was 15,413 samples, a prime, whose FFT ran Bluestein's algorithm at several
/// times the cost. A shorter step stays within the stability limit.
fn fft_friendly_step(step: f64, record_every: usize, record: f64) -> f64 {
    let interval = step * record_every as f64;
    let samples = (record / interval + 1e-9).floor() as usize;
    if !(MIN_SAMPLES..=MAX_RECORD_SAMPLES).contains(&samples) {
        // Refused by the caller with the record's own message (and the search for a smooth
        // length would be long where those numbers are sparse).
        return step;
    }
    let smooth = next_five_smooth(samples);
    // The samples are taken at `k / smooth` of the record, which the floor above must find
    // again: a hair under the exact interval.
    record / smooth as f64 / record_every as f64 * (1.0 - 1e-12)
}

/// The least number at or above `n` (at least 1) with no prime factor above 5.
pub(crate) fn next_five_smooth(n: usize) -> usize {
    let is_smooth = |mut m: usize| {
        for p in [2, 3, 5] {
            while m.is_multiple_of(p) {
                m /= p;
            }
        }
        m == 1
    };
    (n.max(1)..).find(|&m| is_smooth(m)).unwrap_or(n)
}

/// Refused before any speed starts: every speed's run would be refused anyway. The field
/// blamed is the step when one was given, else the longer of the settling and the records.
fn check_longest_run(o: &CascadeOptions, step: f64) -> Result<()> {
    let records = o.averaging.recorded_time(o.record);
    let longest = o.settle_max.max(o.settle) + records;
    if longest / step <= MAX_STEPS {
        return Ok(());
    }
    let (field, help) = match o.step {
        Some(_) => ("step", "leave it out for 0.9 times the stability limit"),
        None if records > o.settle_max.max(o.settle) => {
            ("record", "record shorter, or average fewer records")
        }
        None => ("settle_max", "settle for less time"),
    };
    Err(bad(
        field,
        format!(
            "{step:.3e} s steps make {:.3e} time steps in a speed's longest run (settling up to {} s \
             and up to {} records of {} s overlapping by half): at most {MAX_STEPS:.0e}",
            longest / step,
            o.settle_max,
            o.averaging.max_records,
            o.record
        ),
        help,
    ))
}

/// The default band's top: 2.5X of the top speed, or 1.25 times the highest contact
/// frequency there, whichever is higher, Hz.
fn default_band(model: &Model, speeds: &[f64]) -> f64 {
    let top = speeds.iter().copied().fold(0.0, f64::max);
    let contact = model
        .roller_bearings
        .iter()
        .flat_map(|b| contact_frequencies(b, top))
        .map(|c| c.frequency_hz)
        .fold(0.0, f64::max);
    (BAND_ORDERS * rad_s_to_hz(top)).max(BAND_MARGIN * contact)
}

/// Refuses a model without roller bearings: its response is linear, every frequency in it
/// is the running speed's or a decaying transient's, so a cascade could only report
/// round-off as NSV ("largest NSV 0.00 um ... backward-whip").
fn nonlinear(model: &Model) -> Result<()> {
    if !model.roller_bearings.is_empty() || model.has_squeeze_films() {
        return Ok(());
    }
    Err(Error::Unsupported(
        "the model has no roller bearing, so it is linear: it has no non-synchronous \
         vibration to find (a cascade would report round-off); use `unbalance` for its \
         response over speed, or add a [[roller_bearing]] with its clearance"
            .into(),
    ))
}

/// Checks the options against the model, before anything is built for them.
pub(super) fn check(model: &Model, o: &CascadeOptions) -> Result<()> {
    nonlinear(model)?;
    check_settings(model, o)
}

/// [`check`] without refusing a linear model: the run settings of a transient (a run-up),
/// whose 1X is worth reading on any model.
pub(super) fn check_settings(model: &Model, o: &CascadeOptions) -> Result<()> {
    if o.speeds.is_empty() {
        return Err(bad(
            "speeds",
            "a cascade needs at least one speed".into(),
            "give a range such as 1:750Hz:150",
        ));
    }
    if let Some(w) = o.speeds.iter().find(|w| !(w.is_finite() && **w > 0.0)) {
        return Err(bad(
            "speeds",
            format!("every speed must be positive, got {w} rad/s"),
            "start the range above zero, e.g. 1:750Hz:150 (at rest there is no running \
             speed to call a vibration synchronous to)",
        ));
    }
    let positive = |x: f64| x.is_finite() && x > 0.0;
    if !(o.settle.is_finite() && o.settle >= 0.0) {
        return Err(bad(
            "settle",
            format!("the settling time must be 0 s or more, got {} s", o.settle),
            "e.g. 0.5 s",
        ));
    }
    if !(o.settle_max.is_finite() && o.settle_max >= o.settle) {
        return Err(bad(
            "settle_max",
            format!(
                "the longest settling time must be at least the shortest ({} s), got {} s",
                o.settle, o.settle_max
            ),
            "e.g. 4 s, or equal to the settling time for a fixed settling time",
        ));
    }
    if !positive(o.refine.min_spacing_hz) {
        return Err(bad(
            "refine_spacing",
            format!(
                "the smallest spacing of added speeds must be positive, got {} Hz",
                o.refine.min_spacing_hz
            ),
            "e.g. 0.5 Hz",
        ));
    }
    if let Some(level) = o.refine.onset_levels_m.iter().find(|l| !positive(**l)) {
        return Err(bad(
            "refine_levels",
            format!("every onset level must be positive, got {level} m"),
            "e.g. 1 um and 10 um",
        ));
    }
    let a = &o.averaging;
    if a.min_records == 0 || a.max_records < a.min_records {
        return Err(bad(
            "max_records",
            format!(
                "between 1 and the most records averaged, at least 1 and at most the most: \
                 got at least {} and at most {}",
                a.min_records, a.max_records
            ),
            "e.g. 4 and 32 records, or 1 and 1 for a single record",
        ));
    }
    let at_least_zero = |x: f64| x.is_finite() && x >= 0.0;
    if !(at_least_zero(a.relative_error)
        && at_least_zero(a.absolute_error_m)
        && at_least_zero(a.decided_error))
    {
        return Err(bad(
            "average_tolerance",
            format!(
                "the averaging tolerances must be 0 or more, got {}, {} m and {} once decided",
                a.relative_error, a.absolute_error_m, a.decided_error
            ),
            "e.g. 0.05 (5 %) and 5e-8 m",
        ));
    }
    if !positive(o.record) {
        return Err(bad(
            "record",
            format!("the recorded time must be positive, got {} s", o.record),
            "e.g. 0.5 s (2 Hz bins)",
        ));
    }
    if let Some(h) = o.step.filter(|h| !positive(*h)) {
        return Err(bad(
            "step",
            format!("the time step must be positive, got {h} s"),
            "leave it out for 0.9 times the stability limit",
        ));
    }
    if o.node >= model.node_count() {
        return Err(bad(
            "node",
            format!("node {} is not on the shaft", o.node),
            &format!("nodes are numbered 0 to {}", model.node_count() - 1),
        ));
    }
    if let Some(f) = o.max_frequency_hz.filter(|f| !positive(*f)) {
        return Err(bad(
            "max_frequency",
            format!("the top of the band must be positive, got {f} Hz"),
            "e.g. 3 kHz, or leave it out for the default",
        ));
    }
    if !(o.tolerance_bins.is_finite() && o.tolerance_bins >= 0.0) {
        return Err(bad(
            "tolerance",
            format!(
                "the tolerance must be 0 bins or more, got {}",
                o.tolerance_bins
            ),
            "e.g. 2 bins",
        ));
    }
    if !positive(o.divergence_bound) {
        return Err(bad(
            "divergence_bound",
            format!("must be positive, got {} m", o.divergence_bound),
            "e.g. 0.01 m",
        ));
    }
    Ok(())
}

crate::given::choice!(Component { "ux" => Component::Ux, "uy" => Component::Uy });

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_next_five_smooth_number_has_no_larger_prime_factor() {
        assert_eq!(
            next_five_smooth(15_413),
            15_552,
            "2^6 3^5 follows the prime 15,413"
        );
        assert_eq!(next_five_smooth(15_552), 15_552);
        assert_eq!(next_five_smooth(7), 8);
        assert_eq!(next_five_smooth(0), 1);
    }

    #[test]
    fn the_default_step_is_shortened_to_a_smooth_record_within_a_record_of_samples() {
        // The reference rotor's reduced step: 0.5 s held 15,413 samples.
        let step = 0.5 / 15_413.5;
        let shorter = fft_friendly_step(step, 1, 0.5);
        assert!(shorter < step && shorter > step * (1.0 - 1.0 / 15_413.0 * 200.0));
        let samples = (0.5 / shorter + 1e-9).floor() as usize;
        assert_eq!(samples, 15_552);
        // A record the cascade refuses keeps its step: it is refused with its own message.
        assert_eq!(fft_friendly_step(step, 1, 1e9), step);
    }
}
