//! `whirl runup model.toml [--speeds 1:750Hz] [--rate 20Hz/s] [--direction up|down|both]
//! [--hold 1s] [--window-length TIME] [--overlap 0.75] [--steady none|cascade|starts]
//! [--steady-speeds 60] [--hysteresis-ratio 2] [--threshold 1um] [--smoothing 10Hz]
//! [--steady-smoothing 2Hz]` and the
//! cascade's run settings (`--contact`, `--reduce`/`--full-model`, `--step`, `--start`,
//! `--node`, `--component`, `--window`, `--max-frequency`, `--tolerance`): run-up and
//! coast-down through a speed range at a constant acceleration (see [`whirl::runup`]).
//!
//! Writes `runup.csv` (per window of each sweep: time, speed, 1X, NSV, its frequency and
//! order), `runup_spectra.csv` (long format: every bin of at most 200 windows a sweep),
//! with the steady cascade `steady.csv` (per speed: 1X, NSV, and from the other start),
//! with both directions `hysteresis.csv` and `bands.csv`; the plots `runup_map` (each sweep's time-frequency
//! cascade beside the steady cascade) and `runup_nsv` (1X and NSV over speed, both
//! directions and steady, hysteresis bands and coexisting steady motions marked).
//! Every option left out takes the library's default ([`whirl::runup::RunupOptions::new`]),
//! which the help states from the library's constants.

use std::fmt::Write;

use whirl::given::Choice;
use whirl::nsv::DEFAULT_THRESHOLD_M;
use whirl::report::Report;
use whirl::runup::{
    runup, Direction, Quantity, Runup, RunupReport, RunupRequest, Steady, DEFAULT_DIRECTION,
    DEFAULT_HOLD, DEFAULT_HYSTERESIS_RATIO, DEFAULT_OVERLAP, DEFAULT_RATE_HZ_PER_S,
    DEFAULT_SMOOTHING_HZ, DEFAULT_STEADY, DEFAULT_STEADY_SMOOTHING_HZ, DEFAULT_STEADY_SPEEDS,
};
use whirl::units::{parse_angular_acceleration, parse_speed_range};

use super::cascade::{flagged_error, frequency, RunSettings};
use super::{
    default_is, finish, hertz, load, metres, positive_length, report_summary, seconds, time,
};
use super::{Common, Outcome};
use crate::interrupt;
use crate::output::Output;
use crate::progress::progress_line;

/// `whirl runup`
#[derive(Debug, clap::Args)]
pub struct Args {
    #[command(flatten)]
    pub common: Common,
    /// Speed range `low:high`, e.g. `1:750Hz`; plain numbers are rad/s [default: the model's
    /// operating range].
    #[arg(long, value_name = "RANGE", value_parser = speed_range)]
    pub speeds: Option<(f64, f64)>,
    #[arg(long, value_name = "RATE", value_parser = rate, allow_hyphen_values = true,
          help = default_is("Acceleration of the spin: `20Hz/s`, `1200rpm/s`, or a plain number in rad/s^2",
                            format!("{DEFAULT_RATE_HZ_PER_S}Hz/s")))]
    pub rate: Option<f64>,
    #[arg(long, value_enum, help = default_is("Run-up (low to high), coast-down (high to low), or both",
                                              DEFAULT_DIRECTION.choice_name()))]
    pub direction: Option<Direction>,
    #[arg(long, value_name = "TIME", value_parser = time, allow_hyphen_values = true,
          help = default_is("Time at the starting speed before the ramp", seconds(DEFAULT_HOLD)))]
    pub hold: Option<f64>,
    /// Length of one short-time window [default: 1 / sqrt(rate in Hz/s)].
    #[arg(long, value_name = "TIME", value_parser = time, allow_hyphen_values = true)]
    pub window_length: Option<f64>,
    #[arg(long, value_name = "FRACTION", allow_hyphen_values = true,
          help = default_is("Overlap of consecutive windows, a fraction in [0, 1)", DEFAULT_OVERLAP))]
    pub overlap: Option<f64>,
    #[arg(long, value_enum, help = default_is("The steady cascade compared with: none, the cascade, or the \
cascade from both starts (marks coexisting motions; twice the cost)", DEFAULT_STEADY.choice_name()))]
    pub steady: Option<Steady>,
    #[arg(long, value_name = "N",
          help = default_is("Speeds of the steady cascade over the range", DEFAULT_STEADY_SPEEDS))]
    pub steady_speeds: Option<usize>,
    #[arg(long, value_name = "RATIO", allow_hyphen_values = true, help = default_is("Run-up and coast-down \
differ where the larger amplitude exceeds the smaller by this ratio", DEFAULT_HYSTERESIS_RATIO))]
    pub hysteresis_ratio: Option<f64>,
    #[arg(long, value_name = "LENGTH", value_parser = positive_length, allow_hyphen_values = true,
          help = default_is("... and reaches this amplitude (zero-to-peak)", metres(DEFAULT_THRESHOLD_M)))]
    pub threshold: Option<f64>,
    #[arg(long, value_name = "FREQ", value_parser = frequency, allow_hyphen_values = true,
          help = default_is("Span of speed each direction is smoothed over before they are compared: `10Hz`, \
or a plain number in rad/s", hertz(DEFAULT_SMOOTHING_HZ)))]
    pub smoothing: Option<f64>,
    #[arg(long, value_name = "FREQ", value_parser = frequency, allow_hyphen_values = true,
          help = default_is("Span of speed each sweep's NSV is smoothed over before it is compared with the \
steady cascade", hertz(DEFAULT_STEADY_SMOOTHING_HZ)))]
    pub steady_smoothing: Option<f64>,
    #[command(flatten)]
    pub run: RunSettings,
    /// Top of the maps' frequency axis (the CSV files keep the whole band) [default: 2 x
    /// the highest speed].
    #[arg(long, value_name = "FREQ", value_parser = frequency, allow_hyphen_values = true)]
    pub map_max_frequency: Option<f64>,
}

/// Clap parser of a speed range `low:high` (`1:750Hz`); returned in rad/s.
fn speed_range(text: &str) -> Result<(f64, f64), String> {
    parse_speed_range(text).map_err(|e| e.to_string())
}

/// Clap parser of an angular acceleration (`20Hz/s`); returned in rad/s^2. Its sign is
/// checked by the library.
fn rate(text: &str) -> Result<f64, String> {
    parse_angular_acceleration(text).map_err(|e| e.to_string())
}

/// The flag of a field of the run-up's options.
fn flag(field: &str) -> Option<&'static str> {
    Some(match field {
        "speeds" => "--speeds",
        "rate" => "--rate",
        "hold" => "--hold",
        "window" => "--window-length",
        "overlap" => "--overlap",
        "steady_speeds" => "--steady-speeds",
        "hysteresis_ratio" => "--hysteresis-ratio",
        "threshold" => "--threshold",
        "smoothing" => "--smoothing",
        "steady_smoothing" => "--steady-smoothing",
        "step" => "--step",
        "node" => "--node",
        "max_frequency" => "--max-frequency",
        "tolerance" => "--tolerance",
        _ => return None,
    })
}

/// The library's request from the command line: every option left out stays `None`.
fn request(args: &Args) -> RunupRequest {
    RunupRequest {
        speeds: args.speeds,
        rate: args.rate,
        direction: args.direction,
        hold: args.hold,
        window_length: args.window_length,
        overlap: args.overlap,
        steady: args.steady,
        steady_speeds: args.steady_speeds,
        hysteresis_ratio: args.hysteresis_ratio,
        threshold_m: args.threshold,
        smoothing_hz: args.smoothing,
        steady_smoothing_hz: args.steady_smoothing,
        cascade: args.run.request(),
    }
}

pub fn run(args: &Args) -> miette::Result<Outcome> {
    let loaded = load(&args.common.model)?;
    let model = &loaded.model;
    let options = request(args)
        .options(model)
        .map_err(|e| flagged_error(e, flag))?;
    let out_dir = args.common.out_dir("runup");
    interrupt::stoppable();
    let (progress, line) = progress_line("steady cascade".into());
    let result = runup(model, &options, Some(&progress));
    line.clear();
    let result = result.map_err(|e| flagged_error(e, flag))?;
    let text = text(&result);
    let report = RunupReport { runup: result };
    let summary = report_summary("runup", &loaded, &report)?;
    let tables = report.tables();
    let mut out = Output::begin(&out_dir)?;
    for t in &tables {
        out.table(t)?;
    }
    let common = &args.common;
    let figures = whirl_figures::runup(&report, args.map_max_frequency);
    out.figures(figures, common.rpm)?;
    finish(out, summary, text, common)
}

fn text(r: &Runup) -> String {
    let mut t = String::new();
    let o = &r.options;
    let _ = writeln!(
        t,
        "run-up {:.1}-{:.1} Hz at {:.3} Hz/s ({:.1} s a sweep after {} s at the start), {:.3} s \
         windows ({:.2} Hz bins) overlapping by {}, in {:.1} s",
        o.low / std::f64::consts::TAU,
        o.high / std::f64::consts::TAU,
        o.rate_hz_per_s(),
        o.ramp_s(),
        o.hold,
        r.resolved.window_s,
        r.resolved.resolution_hz,
        o.overlap,
        r.wall_time_s
    );
    for s in &r.sweeps {
        let one_x = s
            .windows
            .iter()
            .max_by(|a, b| a.one_x_m.total_cmp(&b.one_x_m));
        let nsv = s
            .windows
            .iter()
            .max_by(|a, b| a.nsv_m().total_cmp(&b.nsv_m()));
        if let (Some(a), Some(b)) = (one_x, nsv) {
            let _ = writeln!(
                t,
                "{}: largest 1X {:.2} um at {:.1} Hz, largest NSV {:.2} um at {:.1} Hz ({} windows, \
                 march {:.1} s){}",
                s.sweep.name(),
                1e6 * a.one_x_m,
                a.speed_hz,
                1e6 * b.nsv_m(),
                b.speed_hz,
                s.windows.len(),
                s.wall_s,
                s.diverged
                    .as_ref()
                    .map_or(String::new(), |m| format!("; diverged: {m}"))
            );
        }
    }
    for d in r.against_steady() {
        let _ = writeln!(
            t,
            "{} against steady ({} steady speeds): RMS difference 1X {:.3} um (steady RMS {:.3}), \
             NSV {:.3} um (steady RMS {:.3})",
            d.sweep.name(),
            d.speeds,
            1e6 * d.one_x_rms_m,
            1e6 * d.one_x_steady_rms_m,
            1e6 * d.nsv_rms_m,
            1e6 * d.nsv_steady_rms_m
        );
    }
    if let Some(h) = r.hysteresis() {
        if h.bands.is_empty() {
            let _ = writeln!(
                t,
                "hysteresis: none beyond a ratio of {} (at {:.2} um or more) at {} speeds",
                o.hysteresis_ratio,
                1e6 * o.threshold_m,
                h.points.len()
            );
        }
        for b in &h.bands {
            let _ = writeln!(
                t,
                "hysteresis of the {}: {:.1}-{:.1} Hz, largest at {:.1} Hz: up {:.2} um, down \
                 {:.2} um",
                match b.quantity {
                    Quantity::OneX => "1X",
                    Quantity::Nsv => "NSV",
                },
                b.low_hz,
                b.high_hz,
                b.peak_speed_hz,
                1e6 * b.up_m,
                1e6 * b.down_m
            );
        }
        for f in &h.flagged {
            let _ = writeln!(
                t,
                "steady two motions at {:.1} Hz (NSV {:.2} / {:.2} um): sweeps {} / {} um{}",
                f.speed_hz,
                1e6 * f.steady_first_m,
                1e6 * f.steady_other_m,
                f.nsv_up_m.map_or("-".into(), |v| format!("{:.2}", 1e6 * v)),
                f.nsv_down_m
                    .map_or("-".into(), |v| format!("{:.2}", 1e6 * v)),
                if f.in_nsv_band {
                    ", in a hysteresis band"
                } else {
                    ""
                }
            );
        }
    }
    t
}
