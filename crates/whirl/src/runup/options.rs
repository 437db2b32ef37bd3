//! What a run-up computes: the sweep, its short-time spectra, the steady cascade it is
//! compared with, and the tolerance of the hysteresis between its directions.

use serde::Serialize;

use crate::error::{Error, InputError, Result};
use crate::model::Model;
use crate::nsv::{even_speeds, CascadeOptions, DEFAULT_THRESHOLD_M};
use crate::post::spectrum::MIN_SAMPLES;
use crate::units::rad_s_to_hz;

/// Default time at the starting speed before the ramp, s: the start (the static
/// equilibrium, or rest) rings down first. The reference rotor's first mode (2 % damping,
/// 50 Hz) loses a factor of 500 per second.
pub const DEFAULT_HOLD: f64 = 1.0;

/// Default overlap of consecutive short-time windows: 3/4, so that the speeds read are a
/// quarter of a window apart (a Hann window's samples near its ends weigh little, and half
/// an overlap would leave the speed between two readings hardly seen).
pub const DEFAULT_OVERLAP: f64 = 0.75;

/// Default number of speeds of the steady cascade the run-up is compared with, spread
/// evenly over the sweep (the cascade's refinement adds speeds where the NSV changes
/// sharply).
pub const DEFAULT_STEADY_SPEEDS: usize = 60;

/// Default ratio beyond which run-up and coast-down differ: the larger amplitude more than
/// twice the smaller (6 dB), well outside the record-to-record scatter of an irregular
/// whip (+-35 % in one record) and the speed-resolution blur of a short window.
pub const DEFAULT_HYSTERESIS_RATIO: f64 = 2.0;

/// Default span of speed over which each sweep's NSV is power-averaged before run-up and
/// coast-down are compared, Hz: an irregular whip scatters by a factor of two and more from
/// one short window to the next (on the reference rotor at 5 Hz/s, 2 Hz of smoothing left
/// 40 "bands" of such scatter between 100 and 340 Hz), and a hysteresis worth the name
/// spans more than a few hertz.
pub const DEFAULT_SMOOTHING_HZ: f64 = 10.0;

/// Default span of speed over which each sweep's NSV is power-averaged before it is
/// compared with the steady cascade, Hz: narrower than [`DEFAULT_SMOOTHING_HZ`], as the
/// steady NSV has resonances only a few hertz wide (on the reference rotor 150 um at
/// 594 Hz, 48 um at 598 Hz) that a wider span flattens: against the reference rotor's
/// steady cascade the NSV's RMS difference at 2 Hz/s was 5.3 um with 2 Hz, 9.9 um with
/// 10 Hz.
pub const DEFAULT_STEADY_SMOOTHING_HZ: f64 = 2.0;

/// Default sweeps: run-up and coast-down, so that the hysteresis between them is read.
pub const DEFAULT_DIRECTION: Direction = Direction::Both;

/// Default steady cascade compared with: from both starts, marking coexisting motions.
pub const DEFAULT_STEADY: Steady = Steady::Starts;

/// Which way the speed is swept.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[cfg_attr(feature = "clap", derive(clap::ValueEnum))]
#[serde(rename_all = "lowercase")]
pub enum Direction {
    /// From the low speed to the high one (run-up).
    Up,
    /// From the high speed to the low one (coast-down).
    Down,
    /// Both, as two runs: the hysteresis between them is reported.
    Both,
}

impl Direction {
    /// The sweeps it asks for, run-up first.
    pub fn sweeps(self) -> Vec<Sweep> {
        match self {
            Direction::Up => vec![Sweep::Up],
            Direction::Down => vec![Sweep::Down],
            Direction::Both => vec![Sweep::Up, Sweep::Down],
        }
    }
}

/// One sweep's direction.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Sweep {
    /// Run-up.
    Up,
    /// Coast-down.
    Down,
}

impl Sweep {
    /// `up` or `down`.
    pub fn name(self) -> &'static str {
        match self {
            Sweep::Up => "up",
            Sweep::Down => "down",
        }
    }
}

/// Which steady cascade the run-up is compared with.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[cfg_attr(feature = "clap", derive(clap::ValueEnum))]
#[serde(rename_all = "kebab-case")]
pub enum Steady {
    /// None: the run-up alone.
    None,
    /// The cascade at the steady speeds.
    Cascade,
    /// The cascade, and again from the other start, so that the speeds with coexisting
    /// motions ([`crate::nsv::compare_starts`]) are marked: twice the cascade's cost.
    Starts,
}

/// What a run-up computes. Build with [`RunupOptions::new`] and change fields.
#[derive(Debug, Clone, Serialize)]
pub struct RunupOptions {
    /// Lowest speed of the sweep, rad/s (0 or more).
    pub low: f64,
    /// Highest speed, rad/s (above `low`).
    pub high: f64,
    /// Angular acceleration of the spin, rad/s^2 (positive; a coast-down decelerates by it).
    pub rate: f64,
    /// Run-up, coast-down, or both.
    pub direction: Direction,
    /// Time at the starting speed before the ramp, s.
    pub hold: f64,
    /// Length of one short-time window, s; `None` for the default, 1 / sqrt(rate in Hz/s):
    /// the speed then moves by one bin (1 / window) within a window, so each order's line
    /// is blurred by one bin and the 1X read at the window's middle speed loses about 1 %.
    pub window: Option<f64>,
    /// Overlap of consecutive windows, a fraction in [0, 1).
    pub overlap: f64,
    /// The steady cascade compared with.
    pub steady: Steady,
    /// Settings shared with the steady cascade: its speeds (the steady grid), and the run
    /// settings and measurement of both: contact law, reduction, step, start, node,
    /// component, data window, band and synchronous tolerance.
    pub cascade: CascadeOptions,
    /// Amplitudes of the two directions differ when the larger exceeds the smaller by this
    /// ratio (more than 1) ...
    pub hysteresis_ratio: f64,
    /// ... and reaches this amplitude, m (zero-to-peak).
    pub threshold_m: f64,
    /// Span of speed each sweep's NSV is power-averaged over before run-up and coast-down
    /// are compared, Hz (0 for none).
    pub smoothing_hz: f64,
    /// Span of speed each sweep's NSV is power-averaged over before it is compared with the
    /// steady cascade, Hz (0 for none).
    pub steady_smoothing_hz: f64,
}

impl RunupOptions {
    /// The defaults for a sweep of `model` between `low` and `high` (rad/s) at `rate`
    /// (rad/s^2): both directions, [`DEFAULT_HOLD`] at the start, the default window
    /// and overlap, compared with the steady cascade from both starts at
    /// [`DEFAULT_STEADY_SPEEDS`] speeds (the cascade's defaults otherwise, see
    /// [`CascadeOptions::new`]), hysteresis beyond [`DEFAULT_HYSTERESIS_RATIO`] and
    /// [`DEFAULT_THRESHOLD_M`] after [`DEFAULT_SMOOTHING_HZ`] of smoothing, against the
    /// steady cascade after [`DEFAULT_STEADY_SMOOTHING_HZ`].
    pub fn new(model: &Model, low: f64, high: f64, rate: f64) -> Self {
        let speeds = steady_speeds(low, high, DEFAULT_STEADY_SPEEDS);
        RunupOptions {
            low,
            high,
            rate,
            direction: DEFAULT_DIRECTION,
            hold: DEFAULT_HOLD,
            window: None,
            overlap: DEFAULT_OVERLAP,
            steady: DEFAULT_STEADY,
            cascade: CascadeOptions::new(model, speeds),
            hysteresis_ratio: DEFAULT_HYSTERESIS_RATIO,
            threshold_m: DEFAULT_THRESHOLD_M,
            smoothing_hz: DEFAULT_SMOOTHING_HZ,
            steady_smoothing_hz: DEFAULT_STEADY_SMOOTHING_HZ,
        }
    }

    /// Rate in Hz/s.
    pub fn rate_hz_per_s(&self) -> f64 {
        rad_s_to_hz(self.rate)
    }

    /// The window's length, s: [`RunupOptions::window`] or its default.
    pub fn window_s(&self) -> f64 {
        self.window
            .unwrap_or_else(|| 1.0 / self.rate_hz_per_s().sqrt())
    }

    /// Time of one sweep's ramp, s.
    pub fn ramp_s(&self) -> f64 {
        (self.high - self.low) / self.rate
    }
}

/// `count` speeds of the steady cascade evenly spread over `low..=high` (rad/s), none at
/// rest: a cascade needs a running speed at each point, so a sweep from rest starts its
/// steady grid one step above it.
pub fn steady_speeds(low: f64, high: f64, count: usize) -> Vec<f64> {
    if low > 0.0 {
        return even_speeds(low, high, count);
    }
    let step = high / count.max(1) as f64;
    even_speeds(step, high, count)
}

/// An option error naming the field.
fn bad(field: &str, message: String, help: &str) -> Error {
    InputError::field(field, message).help(help).into()
}

/// Checks the options of the sweep itself (the steady cascade's are checked by the
/// cascade).
///
/// # Errors
/// [`Error::Input`] naming the field: `speeds` for a range that is empty, reversed,
/// negative or not finite; `rate` for an acceleration that is not positive and finite;
/// `hold`, `window`, `overlap`, `hysteresis_ratio`, `threshold`, `smoothing`,
/// `steady_smoothing` for values
/// outside their ranges; `window` also for a window of fewer samples than a spectrum
/// needs or longer than the sweep.
pub(super) fn check(o: &RunupOptions) -> Result<()> {
    let finite = |x: f64| x.is_finite();
    if !(finite(o.low) && finite(o.high) && o.low >= 0.0) {
        return Err(bad(
            "speeds",
            format!(
                "the sweep's speeds must be finite and not negative, got {} to {} rad/s",
                o.low, o.high
            ),
            "give a range such as 1:750Hz",
        ));
    }
    if o.high <= o.low {
        return Err(bad(
            "speeds",
            format!(
                "the sweep from {:.3} Hz to {:.3} Hz is empty: the high speed must be above \
                 the low one",
                rad_s_to_hz(o.low),
                rad_s_to_hz(o.high)
            ),
            "give the range low:high, e.g. 1:750Hz (the direction says which way it is swept)",
        ));
    }
    if !(finite(o.rate) && o.rate > 0.0) {
        return Err(bad(
            "rate",
            format!(
                "the acceleration must be positive, got {:.4} Hz/s",
                o.rate_hz_per_s()
            ),
            "give it as e.g. 20Hz/s; a coast-down decelerates by the same rate",
        ));
    }
    if !(finite(o.hold) && o.hold >= 0.0) {
        return Err(bad(
            "hold",
            format!("the hold must be 0 s or more, got {} s", o.hold),
            "e.g. 1s",
        ));
    }
    let window = o.window_s();
    if !(finite(window) && window > 0.0) {
        return Err(bad(
            "window",
            format!("the window must be positive, got {window} s"),
            "leave it out for 1 / sqrt(rate in Hz/s)",
        ));
    }
    if window > o.ramp_s() {
        return Err(bad(
            "window",
            format!(
                "the window of {window:.3} s is longer than the sweep's {:.3} s",
                o.ramp_s()
            ),
            "sweep a wider range, more slowly, or give a shorter window",
        ));
    }
    if !(o.overlap >= 0.0 && o.overlap < 1.0) {
        return Err(bad(
            "overlap",
            format!("the overlap must be in [0, 1), got {}", o.overlap),
            "e.g. 0.75",
        ));
    }
    if !(finite(o.hysteresis_ratio) && o.hysteresis_ratio > 1.0) {
        return Err(bad(
            "hysteresis_ratio",
            format!(
                "the hysteresis ratio must be above 1, got {}",
                o.hysteresis_ratio
            ),
            "e.g. 2 (6 dB)",
        ));
    }
    if !(finite(o.threshold_m) && o.threshold_m > 0.0) {
        return Err(bad(
            "threshold",
            format!("the threshold must be positive, got {} m", o.threshold_m),
            "e.g. 1um",
        ));
    }
    for (field, span) in [
        ("smoothing", o.smoothing_hz),
        ("steady_smoothing", o.steady_smoothing_hz),
    ] {
        if !(finite(span) && span >= 0.0) {
            return Err(bad(
                field,
                format!("the smoothing must be 0 Hz or more, got {span} Hz"),
                "e.g. 10Hz, or 0Hz for none",
            ));
        }
    }
    Ok(())
}

/// The window's samples at `sample_interval` (s), checked.
///
/// # Errors
/// [`Error::Input`] naming `window` when it holds fewer than [`MIN_SAMPLES`].
pub(super) fn window_samples(o: &RunupOptions, sample_interval: f64) -> Result<usize> {
    let samples = (o.window_s() / sample_interval).round() as usize;
    if samples < MIN_SAMPLES {
        return Err(bad(
            "window",
            format!(
                "a window of {:.3e} s holds {samples} samples at {sample_interval:.3e} s each, \
                 fewer than the {MIN_SAMPLES} a spectrum takes",
                o.window_s()
            ),
            "give a longer window, or a lower rate",
        ));
    }
    Ok(samples)
}

crate::given::choice!(Direction { "up" => Direction::Up, "down" => Direction::Down, "both" => Direction::Both });
crate::given::choice!(Steady { "none" => Steady::None, "cascade" => Steady::Cascade, "starts" => Steady::Starts });
