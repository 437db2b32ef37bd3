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
//! Every option left out takes the library's default ([`whirl::runup::RunupOptions::new`]).

use std::fmt::Write;

use whirl::bearing::ContactLaw;
use whirl::nsv::{CascadeRequest, Component};
use whirl::post::Window;
use whirl::report::Report;
use whirl::runup::{runup, Direction, Quantity, Runup, RunupReport, RunupRequest, Steady};
use whirl::time::Initial;
use whirl::units::{parse_angular_acceleration, parse_speed_range};

use super::cascade::{bins, flagged_error, frequency};
use super::{finish, load, mode_count, node_index, positive_length, report_summary, time};
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
    /// Acceleration of the spin: `20Hz/s`, `1200rpm/s`, or a plain number in rad/s^2
    /// [default: 20Hz/s].
    #[arg(long, value_name = "RATE", value_parser = rate, allow_hyphen_values = true)]
    pub rate: Option<f64>,
    /// Run-up (low to high), coast-down (high to low), or both [default: both].
    #[arg(long, value_enum)]
    pub direction: Option<Direction>,
    /// Time at the starting speed before the ramp [default: 1s].
    #[arg(long, value_name = "TIME", value_parser = time, allow_hyphen_values = true)]
    pub hold: Option<f64>,
    /// Length of one short-time window [default: 1 / sqrt(rate in Hz/s)].
    #[arg(long, value_name = "TIME", value_parser = time, allow_hyphen_values = true)]
    pub window_length: Option<f64>,
    /// Overlap of consecutive windows, a fraction in [0, 1) [default: 0.75].
    #[arg(long, value_name = "FRACTION", allow_hyphen_values = true)]
    pub overlap: Option<f64>,
    /// The steady cascade compared with: none, the cascade, or the cascade from both starts
    /// (marks coexisting motions; twice the cost) [default: starts].
    #[arg(long, value_enum)]
    pub steady: Option<Steady>,
    /// Speeds of the steady cascade over the range [default: 60].
    #[arg(long, value_name = "N")]
    pub steady_speeds: Option<usize>,
    /// Run-up and coast-down differ where the larger amplitude exceeds the smaller by this
    /// ratio [default: 2].
    #[arg(long, value_name = "RATIO", allow_hyphen_values = true)]
    pub hysteresis_ratio: Option<f64>,
    /// ... and reaches this amplitude (zero-to-peak) [default: 1um].
    #[arg(long, value_name = "LENGTH", value_parser = positive_length, allow_hyphen_values = true)]
    pub threshold: Option<f64>,
    /// Span of speed each direction is smoothed over before they are compared: `10Hz`, or a
    /// plain number in rad/s [default: 10Hz].
    #[arg(long, value_name = "FREQ", value_parser = frequency, allow_hyphen_values = true)]
    pub smoothing: Option<f64>,
    /// Span of speed each sweep's NSV is smoothed over before it is compared with the
    /// steady cascade [default: 2Hz].
    #[arg(long, value_name = "FREQ", value_parser = frequency, allow_hyphen_values = true)]
    pub steady_smoothing: Option<f64>,
    /// Initial state of the sweeps and the steady cascade [default: static].
    #[arg(long, value_enum)]
    pub start: Option<Initial>,
    /// Contact law of the roller bearings [default: hertz when the model has roller
    /// bearings, linear otherwise].
    #[arg(long, value_name = "LAW", value_enum)]
    pub contact: Option<ContactLaw>,
    /// Craig-Bampton reduction keeping N fixed-interface modes [default: 12].
    #[arg(long, value_name = "N", value_parser = mode_count)]
    pub reduce: Option<usize>,
    /// Integrate the full model instead of the reduced one.
    #[arg(long, conflicts_with = "reduce")]
    pub full_model: bool,
    /// Central-difference time step [default: 0.9 x the stability limit].
    #[arg(long, value_name = "TIME", value_parser = time, allow_hyphen_values = true)]
    pub step: Option<f64>,
    /// The node whose response is analysed [default: the first disk's node].
    #[arg(long, value_name = "N", value_parser = node_index)]
    pub node: Option<usize>,
    /// Which displacement is analysed [default: uy].
    #[arg(long, value_enum)]
    pub component: Option<Component>,
    /// Data window of the spectra [default: hann].
    #[arg(long, value_enum)]
    pub window: Option<Window>,
    /// Top of the frequency band searched: `3000Hz`, or a plain number in rad/s [default:
    /// the steady cascade's].
    #[arg(long, value_name = "FREQ", value_parser = frequency, allow_hyphen_values = true)]
    pub max_frequency: Option<f64>,
    /// A peak within this many bins of a multiple of the running speed is synchronous
    /// [default: 2].
    #[arg(long, value_name = "BINS", value_parser = bins, allow_hyphen_values = true)]
    pub tolerance: Option<f64>,
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
        cascade: CascadeRequest {
            start: args.start,
            contact: args.contact,
            reduce: if args.full_model {
                Some(None)
            } else {
                args.reduce.map(Some)
            },
            step: args.step,
            node: args.node,
            component: args.component,
            window: args.window,
            max_frequency_hz: args.max_frequency,
            tolerance_bins: args.tolerance,
            ..CascadeRequest::default()
        },
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
