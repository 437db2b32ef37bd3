//! `whirl cascade model.toml [--speeds 1:750Hz:150] [--settle 0.5s] [--record 0.5s]
//! [--contact hertz|lagrange|forcing|linear] [--reduce 12 | --full-model] [--node N]
//! [--component ux|uy] [--window hann|flat-top] [--max-frequency 3000Hz] [--tolerance 2]
//! [--threshold 1um] [--full] [--restart]`: the cascade (waterfall) diagram of non-synchronous
//! vibration over a speed range (docs/theory.md section 8, thesis ch. 5; see [`whirl::nsv`]).
//!
//! Writes `cascade.csv` (long format: `speed_hz,frequency_hz,amplitude_m`, every bin of
//! the band at every speed), `nsv.csv` (per speed: 1X, the largest non-synchronous peak,
//! its order, class, whirl direction, forward and backward radii, decay over the record),
//! with `--full` also `full_cascade.csv` (signed frequency: forward whirl positive), and
//! the plots `waterfall` (spectra stacked along speed, log amplitude), `cascade_map`
//! (frequency over speed, colour = log amplitude, NSV peaks above the threshold marked),
//! `nsv` (1X and NSV amplitude over speed by class) and with `--full` `full_map` (the maps
//! up to `--map-max-frequency`, default twice the highest speed); 1X, 2X,
//! 0.5X and N_b w_c lines are drawn on the maps and the waterfall. summary.json holds the
//! NSV summary: onset speed above `--threshold`, largest NSV and where, dominant class.
//!
//! # Checkpoint
//!
//! Every finished speed is saved at once in `<out>.partial/<key>/` (beside the output
//! folder; `out/cascade.partial/<key>` by default, the key a hash of the model and the
//! options, so cascades with other options keep their own checkpoints), atomically, so a run that is interrupted (Ctrl-C, a
//! kill, a crash) and started again with the same command computes only the missing
//! speeds and ends with the same bytes as an uninterrupted run. The folder stays after a
//! successful run (running the same command again only redraws); a folder holding another
//! model or other options is refused with what differs, and `--restart` deletes it first.

use std::fmt::Write;
use std::path::{Path, PathBuf};

use whirl::bearing::ContactLaw;
use whirl::given::{Choice, Given};
use whirl::model::Model;
use whirl::nsv::{
    compare_starts, other_start_options, records_span, Cascade, CascadeOptions, CascadeReport,
    CascadeRequest, Component, NsvSummary, PreparedCascade, StartComparison, DEFAULT_COMPONENT,
    DEFAULT_MAX_ADDED, DEFAULT_MAX_RECORDS, DEFAULT_MIN_SPACING_HZ, DEFAULT_RECORD,
    DEFAULT_RELATIVE_ERROR, DEFAULT_SETTLE, DEFAULT_SETTLE_MAX, DEFAULT_SPEED_COUNT, DEFAULT_START,
    DEFAULT_THRESHOLD_M, DEFAULT_TOLERANCE_BINS, DEFAULT_WINDOW, STARTS_DIFFER_SIGMAS,
};
use whirl::post::Window;
use whirl::report::Report;
use whirl::time::Initial;
use whirl::time::DEFAULT_MODES;
use whirl::units::with_uncertainty;

use super::{
    default_is, finish, given, hertz, load, metres, mode_count, node_index, positive_length,
    report_summary, seconds, speeds, time,
};
use super::{Common, Outcome, Speeds};
use crate::error::{from_whirl, Diag};
use crate::interrupt;
use crate::output::Output;
use crate::progress::{duration_text, progress_line};

/// `whirl cascade`: every option left out takes the library's default
/// ([`whirl::nsv::CascadeOptions::new`]), which the help states from the library's constants.
#[derive(Debug, clap::Args)]
pub struct Args {
    #[command(flatten)]
    pub common: Common,
    #[arg(long, value_name = "RANGE", value_parser = speeds,
          help = default_is("Spin speeds `start:stop:count`, e.g. `1:750Hz:150`; plain numbers are rad/s.",
              format_args!("{DEFAULT_SPEED_COUNT} speeds over the model's operating range")))]
    pub speeds: Option<Speeds>,
    #[arg(long, value_name = "TIME", value_parser = time, allow_hyphen_values = true,
          help = default_is("Shortest time simulated and discarded at each speed before the record.", seconds(DEFAULT_SETTLE)))]
    pub settle: Option<f64>,
    #[arg(long, value_name = "TIME", value_parser = time, allow_hyphen_values = true,
          help = default_is("Longest settling time: each speed runs on (checked every half record) until its \
start has died away, at most this long, else it is reported unsettled; give the same as --settle for a \
fixed settling time.", seconds(DEFAULT_SETTLE_MAX)))]
    pub settle_max: Option<f64>,
    /// Compute only the requested speeds: add none where the NSV changes sharply.
    #[arg(long)]
    pub no_refine: bool,
    #[arg(long, value_name = "N", help = default_is("Most speeds the refinement adds.", DEFAULT_MAX_ADDED))]
    pub refine_budget: Option<usize>,
    #[arg(long, value_name = "FREQ", value_parser = frequency, allow_hyphen_values = true,
          help = default_is("Smallest spacing of an added speed from its neighbours: `0.5Hz`, or a plain number \
in rad/s.", hertz(DEFAULT_MIN_SPACING_HZ)))]
    pub refine_spacing: Option<f64>,
    #[arg(long, value_name = "TIME", value_parser = time, allow_hyphen_values = true,
          help = default_is("Time recorded at each speed; its inverse is the bin spacing.", seconds(DEFAULT_RECORD)))]
    pub record: Option<f64>,
    #[arg(long, value_name = "N", help = default_is("Most records averaged at a settled speed (overlapping by \
half): records are added until the NSV's standard error is within --average-tolerance, or within 20 % with \
the NSV clear of every onset level (at least 4); 1 for a single record.", DEFAULT_MAX_RECORDS))]
    pub max_records: Option<usize>,
    #[arg(long, value_name = "FRACTION", allow_hyphen_values = true, help = default_is("Averaging stops once \
the NSV's standard error is within this fraction of it (or 0.05 um).", DEFAULT_RELATIVE_ERROR))]
    pub average_tolerance: Option<f64>,
    #[command(flatten)]
    pub run: RunSettings,
    #[arg(long, value_name = "LENGTH", value_parser = positive_length, allow_hyphen_values = true,
          help = default_is("NSV amplitude (zero-to-peak) from which a speed counts in the summary: onset, \
classes.", metres(DEFAULT_THRESHOLD_M)))]
    pub threshold: Option<f64>,
    /// Top of the frequency axis of the plots `cascade_map` and `full_map` (the CSV files
    /// keep the whole band): `800Hz`, or a plain number in rad/s [default: 2 x the highest
    /// speed, so 1X and 2X and the sub-synchronous whirl below them fill the map].
    #[arg(long, value_name = "FREQ", value_parser = frequency, allow_hyphen_values = true)]
    pub map_max_frequency: Option<f64>,
    /// Also the full spectrum of x + i y (forward whirl at positive, backward at negative
    /// frequency): full_cascade.csv and the plot full_map.
    #[arg(long)]
    pub full: bool,
    /// Delete this cascade's checkpoint folder `<out>.partial/<key>` first and compute
    /// every speed again.
    #[arg(long)]
    pub restart: bool,
    /// Run every speed again from the other start (rest after the static equilibrium, or
    /// the reverse) and mark the speeds where the NSV differs beyond three standard errors:
    /// coexisting motions (starts.csv, the plot `starts`; twice the computing).
    #[arg(long)]
    pub compare_starts: bool,
}

/// How each run of a cascade or a run-up is made and measured: the flags `whirl cascade`
/// and `whirl runup` share, each left out at the library's default.
#[derive(Debug, clap::Args)]
pub struct RunSettings {
    #[arg(long, value_enum, help = default_is("Initial state of every run.", DEFAULT_START.choice_name()))]
    pub start: Option<Initial>,
    /// Contact law of the roller bearings [default: hertz when the model has roller
    /// bearings, linear otherwise].
    #[arg(long, value_name = "LAW", value_enum)]
    pub contact: Option<ContactLaw>,
    #[arg(long, value_name = "N", value_parser = mode_count,
          help = default_is("Craig-Bampton reduction keeping N fixed-interface modes.", DEFAULT_MODES))]
    pub reduce: Option<usize>,
    /// Integrate the full model instead of the reduced one (about ten times slower).
    #[arg(long, conflicts_with = "reduce")]
    pub full_model: bool,
    /// Central-difference time step [default: 0.9 x the stability limit].
    #[arg(long, value_name = "TIME", value_parser = time, allow_hyphen_values = true)]
    pub step: Option<f64>,
    /// The node whose response is analysed [default: the first disk's node].
    #[arg(long, value_name = "N", value_parser = node_index)]
    pub node: Option<usize>,
    #[arg(long, value_enum, help = default_is("Which displacement gives the one-sided spectrum (the full \
spectrum uses both).", DEFAULT_COMPONENT.choice_name()))]
    pub component: Option<Component>,
    #[arg(long, value_enum, help = default_is("Data window of the spectra.", DEFAULT_WINDOW.choice_name()))]
    pub window: Option<Window>,
    /// Top of the frequency band kept and searched: `3000Hz`, or a plain number in rad/s
    /// [default: 2.5 x the top speed or 1.25 x the highest contact frequency there].
    #[arg(long, value_name = "FREQ", value_parser = frequency, allow_hyphen_values = true)]
    pub max_frequency: Option<f64>,
    #[arg(long, value_name = "BINS", value_parser = bins, allow_hyphen_values = true,
          help = default_is("A peak within this many bins of a multiple of the running speed is synchronous.",
                            DEFAULT_TOLERANCE_BINS))]
    pub tolerance: Option<f64>,
}

impl RunSettings {
    /// The library's request with these settings, every other option left out.
    pub fn request(&self) -> CascadeRequest {
        CascadeRequest {
            start: self.start,
            contact: self.contact,
            reduce: if self.full_model {
                Some(None)
            } else {
                self.reduce.map(Some)
            },
            step: self.step,
            node: self.node,
            component: self.component,
            window: self.window,
            max_frequency_hz: self.max_frequency,
            tolerance_bins: self.tolerance,
            ..CascadeRequest::default()
        }
    }
}

/// Clap parser of a frequency: `3000Hz`, `180000rpm`, or a plain number in rad/s (the
/// one rule for plain numbers on the command line); returned in Hz.
pub(super) fn frequency(text: &str) -> Result<f64, String> {
    given(text, Given::frequency_hz)
}

/// Clap parser of a tolerance in bins: a number, 0 or more.
pub(super) fn bins(text: &str) -> Result<f64, String> {
    match text.trim().parse::<f64>() {
        Ok(b) if b.is_finite() && b >= 0.0 => Ok(b),
        _ => Err(format!(
            "`{text}` is not a number of bins (0 or more, e.g. 2)"
        )),
    }
}

pub fn run(args: &Args) -> miette::Result<Outcome> {
    let loaded = load(&args.common.model)?;
    let model = &loaded.model;
    let request = request(args);
    let threshold = request.threshold_m();
    let options = cascade_options(&request, model)?;
    let out_dir = args.common.out_dir("cascade");
    // Built once: the reduction serves the checkpoint's key, the step and every speed.
    let prepared = PreparedCascade::new(model, &options).map_err(|e| library_error(e, &out_dir))?;
    let key = prepared
        .checkpoint_key()
        .map_err(|e| library_error(e, &out_dir))?;
    let checkpoint = checkpoint_dir(&out_dir)?.join(key);
    if args.restart {
        whirl::nsv::checkpoint::restart(&checkpoint).map_err(|e| from_whirl(e, ""))?;
    }
    warn_if_long(&options);
    interrupt::stoppable();
    let (progress, line) = progress_line("cascade".into());
    let result = prepared.run(Some(&checkpoint), Some(&progress));
    line.clear();
    let result = result.map_err(|e| library_error(e, &checkpoint))?;
    warn_of_divergence(&result);
    let nsv = result.nsv_summary(threshold);
    let starts = if args.compare_starts {
        Some(other_start(model, &result, threshold, &out_dir)?)
    } else {
        None
    };

    let mut text = text(model, &result, &nsv, &checkpoint);
    let report = CascadeReport {
        cascade: result,
        threshold_m: threshold,
        starts,
        checkpoint_folder: Some(checkpoint.display().to_string()),
    };
    let summary = report_summary("cascade", &loaded, &report)?;
    let tables = report.tables();
    let result = &report.cascade;
    let mut out = Output::begin(&out_dir)?;
    out.table_named(&tables, "cascade")?;
    if result.options.full {
        out.table_named(&tables, "full_cascade")?;
    }
    out.table_named(&tables, "nsv")?;
    let common = &args.common;
    if let Some(starts) = &report.starts {
        text.push_str(&starts_text(starts));
        out.table_named(&tables, "starts")?;
    }
    let figures = whirl_figures::cascade(&report, args.map_max_frequency);
    out.figures(figures, common.rpm)?;
    finish(out, summary, text, &args.common)
}

/// The cascade again from the other start at the same speeds, with its own checkpoint
/// beside the first run's, compared speed by speed.
fn other_start(
    model: &Model,
    first: &Cascade,
    threshold: f64,
    out_dir: &Path,
) -> miette::Result<StartComparison> {
    let options = other_start_options(first);
    let prepared = PreparedCascade::new(model, &options).map_err(|e| library_error(e, out_dir))?;
    let key = prepared
        .checkpoint_key()
        .map_err(|e| library_error(e, out_dir))?;
    let checkpoint = checkpoint_dir(out_dir)?.join(key);
    eprintln!(
        "comparing starts: every speed again from {}",
        start_name(options.initial)
    );
    let (progress, line) = progress_line("cascade".into());
    let second = prepared.run(Some(&checkpoint), Some(&progress));
    line.clear();
    let second = second.map_err(|e| library_error(e, &checkpoint))?;
    compare_starts(first, second, threshold).map_err(|e| from_whirl(e, ""))
}

fn start_name(start: Initial) -> &'static str {
    match start {
        Initial::StaticEquilibrium => "the static equilibrium",
        Initial::Rest => "rest",
    }
}

fn starts_text(s: &StartComparison) -> String {
    let differing = s.differing_speeds_hz();
    let list: Vec<String> = differing.iter().map(|f| format!("{f:.1}")).collect();
    if differing.is_empty() {
        format!(
            "from {}: the NSV agrees within {STARTS_DIFFER_SIGMAS} standard errors at all {} speeds compared\n",
            start_name(s.other),
            s.compared()
        )
    } else {
        format!(
            "from {}: the NSV differs beyond {STARTS_DIFFER_SIGMAS} standard errors at {} of {} speeds compared (coexisting motions; starts.csv): {} Hz\n",
            start_name(s.other),
            differing.len(),
            s.compared(),
            list.join(", ")
        )
    }
}

/// Computing time of one central-difference step of the reduced reference rotor on Hertz
/// bearings (12 modes: 1 s of rotor time in about 28,000 steps and 36 ms on this project's
/// 2-core test machine), s. Larger models take longer, so estimates from it are lower bounds.
const SECONDS_PER_STEP: f64 = 1.3e-6;

/// An estimated run time above which a cascade warns before it starts, s.
pub const LONG_RUN_S: f64 = 1800.0;

/// The least computing time of a cascade whose time step is given, on this machine's
/// cores, s, with its time steps per speed; `None` when the step is the default (0.9 times
/// the stable step, which the reduced model keeps long).
pub fn least_seconds(options: &CascadeOptions) -> Option<(f64, f64)> {
    let step = options.step?;
    // At least the shortest settling and the fewest records averaged.
    let least_records = records_span(options.averaging.min_records, options.record);
    let steps_per_speed = (options.settle + least_records) / step;
    let seconds = steps_per_speed * options.speeds.len() as f64 * SECONDS_PER_STEP / cores() as f64;
    Some((steps_per_speed, seconds))
}

/// The cores the speeds share.
pub fn cores() -> usize {
    std::thread::available_parallelism().map_or(1, |n| n.get())
}

/// Warns before starting when the time step asked for makes the cascade hours long (a
/// mistyped `--step 1e-8s` would otherwise run for hours in silence).
fn warn_if_long(options: &CascadeOptions) {
    let Some((steps_per_speed, seconds)) = least_seconds(options) else {
        return;
    };
    if seconds > LONG_RUN_S {
        eprintln!(
            "warning: --step {:e} s makes {steps_per_speed:.3e} time steps per speed, {} speeds: \
             at least {} of computing on {} cores; leave --step out for 0.9 times the \
             stable step, or press Ctrl-C to stop (finished speeds are kept)",
            options.step.unwrap_or(0.0),
            options.speeds.len(),
            duration_text(seconds),
            cores()
        );
    }
}

/// Some diverged speeds are listed on stderr (and in summary.json); a cascade in which every
/// speed diverged is the library's error.
fn warn_of_divergence(c: &Cascade) {
    let diverged: Vec<String> = c
        .points
        .iter()
        .filter(|p| p.diverged.is_some())
        .map(|p| format!("{:.1}", p.speed_hz))
        .collect();
    if diverged.is_empty() {
        return;
    }
    eprintln!(
        "warning: the simulation diverged at {} of {} speeds ({} Hz); they have no NSV",
        diverged.len(),
        c.points.len(),
        diverged.join(", ")
    );
}

/// The library's request from the command line: every option left out stays `None`.
fn request(args: &Args) -> CascadeRequest {
    CascadeRequest {
        speeds: args.speeds.as_ref().map(|s| s.0.clone()),
        settle: args.settle,
        settle_max: args.settle_max,
        refine: args.no_refine.then_some(false),
        refine_budget: args.refine_budget,
        refine_spacing_hz: args.refine_spacing,
        record: args.record,
        max_records: args.max_records,
        average_tolerance: args.average_tolerance,
        full: args.full.then_some(true),
        threshold: args.threshold,
        ..args.run.request()
    }
}

/// The library's options from the command line's request.
fn cascade_options(request: &CascadeRequest, model: &Model) -> miette::Result<CascadeOptions> {
    let options = request.options(model).map_err(option_error)?;
    if request.speeds.is_none() {
        super::announce(None, "speeds", &options.speeds);
    }
    Ok(options)
}

/// `<out>.partial`, beside the output folder.
fn checkpoint_dir(out: &Path) -> miette::Result<PathBuf> {
    let name = out.file_name().and_then(|n| n.to_str()).ok_or_else(|| {
        Diag::option(
            "--out",
            format!("`{}` does not name a folder", out.display()),
        )
        .help("give a folder such as `out/cascade`")
    })?;
    Ok(out.with_file_name(format!("{name}.partial")))
}

/// The library's error as the command line knows it: an option by its flag, a checkpoint
/// of another cascade with the way out.
fn library_error(e: whirl::Error, dir: &Path) -> miette::Report {
    if let whirl::Error::Diverged { message, .. } = &e {
        return Diag::new(message.clone())
            .help(
                "check the model (clearance, stiffness, damping) or lower --step; the finished \
                 speeds stay in the checkpoint, --restart discards them",
            )
            .into();
    }
    let whirl::Error::Input(input) = &e else {
        return from_whirl(e, "");
    };
    let field = input.field.as_deref().unwrap_or("");
    if field == "checkpoint" {
        return Diag::new(input.message.clone())
            .help(format!(
                "run again with --restart to delete `{}` and compute every speed anew, or \
                 give another --out",
                dir.display()
            ))
            .into();
    }
    option_error(e)
}

/// The library's error about an option, by the option's flag when it has one.
fn option_error(e: whirl::Error) -> miette::Report {
    flagged_error(e, flag)
}

/// The library's error about an option, by the flag `flag` gives its field when it has one.
pub(super) fn flagged_error(
    e: whirl::Error,
    flag: fn(&str) -> Option<&'static str>,
) -> miette::Report {
    let whirl::Error::Input(input) = &e else {
        return from_whirl(e, "");
    };
    match flag(input.field.as_deref().unwrap_or("")) {
        Some(flag) => {
            let diag = Diag::option(flag, &input.message);
            match &input.help {
                Some(help) => diag.help(help.clone()).into(),
                None => diag.into(),
            }
        }
        None => from_whirl(e, ""),
    }
}

/// The flag of a field of [`CascadeOptions`].
fn flag(field: &str) -> Option<&'static str> {
    Some(match field {
        "speeds" => "--speeds",
        "settle" => "--settle",
        "settle_max" => "--settle-max",
        "refine_spacing" => "--refine-spacing",
        "record" => "--record",
        "max_records" => "--max-records",
        "average_tolerance" => "--average-tolerance",
        "step" => "--step",
        "node" => "--node",
        "max_frequency" => "--max-frequency",
        "tolerance" => "--tolerance",
        _ => return None,
    })
}

/// A length in micrometres with the digits its uncertainty allows.
fn micrometres(value_m: f64, error_m: f64) -> String {
    with_uncertainty(1e6 * value_m, 1e6 * error_m, 3)
}

fn text(model: &Model, c: &Cascade, nsv: &NsvSummary, checkpoint: &Path) -> String {
    let mut t = String::new();
    let (low, high) = c.speed_range_hz();
    let _ = writeln!(
        t,
        "{}: cascade of {} speeds {low:.1}-{high:.1} Hz ({} added by refinement; {} contact, \
         {}), settled {}-{} s + up to {} records of {} s (overlapping by half) averaged each, {:.2} Hz bins up to {:.0} Hz, in {:.1} s \
         ({} speeds from the checkpoint {})",
        model.name,
        c.points.len(),
        nsv.added_speeds,
        c.options.law.name(),
        c.options
            .reduction
            .map_or("full model".to_string(), |m| format!("reduced, {m} modes")),
        c.options.settle,
        c.options.settle_max,
        c.options.averaging.max_records,
        c.options.record,
        c.resolved.resolution_hz,
        c.resolved.max_frequency_hz,
        c.wall_time_s,
        c.resumed,
        checkpoint.display()
    );
    let threshold = format!("{:.2} um", 1e6 * nsv.threshold_m);
    for o in &nsv.onsets {
        let below = o
            .below_hz
            .map_or(String::new(), |b| format!(" (below it {b:.1} Hz)"));
        let sustained = o.sustained_hz.map_or("; never sustained".to_string(), |s| {
            format!("; sustained from {s:.1} Hz")
        });
        let _ = writeln!(
            t,
            "NSV onset (>= {:.2} um): {:.1} Hz{below}{sustained}",
            1e6 * o.level_m,
            o.speed_hz
        );
    }
    if nsv.onset_speed_hz.is_none() {
        let _ = writeln!(t, "no steady NSV reaches {threshold}");
    }
    if let Some(l) = &nsv.largest {
        let around: Vec<String> = l
            .neighbours
            .iter()
            .map(|n| format!("{:.2} um at {:.1} Hz", 1e6 * n.amplitude_m, n.speed_hz))
            .collect();
        let _ = writeln!(
            t,
            "largest NSV: {:.2} +- {:.2} um ({} records) at {:.1} Hz ({:.3}X) when running at \
             {:.1} Hz, {} whirl, {} (neighbours: {})",
            1e6 * l.amplitude_m,
            1e6 * l.standard_error_m,
            l.records,
            l.frequency_hz,
            l.order,
            l.speed_hz,
            l.direction.name(),
            l.class.name(),
            around.join(", ")
        );
    }
    if let Some(st) = &nsv.statistics {
        let _ = writeln!(
            t,
            "NSV over {:.1}-{:.1} Hz: median {} um, 90th percentile {} um, mean {} um (+- from \
             the scatter of four interleaved sub-grids)",
            st.range_hz.0,
            st.range_hz.1,
            micrometres(st.median_m, st.uncertainty.median_m),
            micrometres(st.p90_m, st.uncertainty.p90_m),
            micrometres(st.mean_m, st.uncertainty.mean_m)
        );
    }
    if let Some(d) = nsv.dominant_class {
        let counts: Vec<String> = nsv
            .classes
            .iter()
            .map(|k| format!("{} {}", k.class.name(), k.speeds))
            .collect();
        let _ = writeln!(
            t,
            "dominant class: {} (speeds above the threshold: {})",
            d.name(),
            counts.join(", ")
        );
    }
    if !nsv.unsettled_speeds_hz.is_empty() {
        let list: Vec<String> = nsv
            .unsettled_speeds_hz
            .iter()
            .map(|f| format!("{f:.1}"))
            .collect();
        let _ = writeln!(
            t,
            "unsettled at {} speed(s) (still dying away after {} s; see nsv.csv): {} Hz",
            list.len(),
            c.options.settle_max,
            list.join(", ")
        );
    }
    if !nsv.diverged_speeds_hz.is_empty() {
        let _ = writeln!(
            t,
            "diverged at {} speed(s), from {:.1} Hz: see nsv.csv",
            nsv.diverged_speeds_hz.len(),
            nsv.diverged_speeds_hz[0]
        );
    }
    if let Some(first) = nsv.started_from_rest_hz.first() {
        let _ = writeln!(
            t,
            "started from rest at {} speed(s), from {first:.1} Hz: no static equilibrium was \
             found there (nsv.csv: start_fallback)",
            nsv.started_from_rest_hz.len()
        );
    }
    t
}
