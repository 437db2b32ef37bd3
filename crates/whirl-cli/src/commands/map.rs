//! `whirl map model.toml [--parameter PATH] --values LIST --speeds RANGE [hbm options]
//! [--clear-below SPEED]`: the NSV map. One harmonic-balance sweep with Floquet stability
//! per value of a model parameter (default `roller_bearing[*].clearance`), and per value
//! the speed bands where the synchronous orbit is unstable, each named by the bifurcation
//! that opens it (docs/theory.md section 7).
//!
//! Writes `bands.csv` (one row per unstable band: value, opening and closing speed and
//! bifurcation, the emerging frequency, the share of the band where a stable orbit
//! coexists), `values.csv` (per value the first loss of stability and the sweep's cost) and
//! the plot `map` (speed on x, the parameter on y, the unstable bands coloured by what
//! opens them). `--clear-below` asks which values keep the orbit stable below a speed.

use std::fmt::Write;

use whirl::map::check::DEFAULT_CHECK_LEVEL_M;
use whirl::map::{growing_text, map_with, MapReport, MapRequest, Parallelism};
use whirl::report::Report;

use super::cascade::{cores, LONG_RUN_S};
use super::hbm::{point_seconds, rising_range, speed_span, HbFlags};
use super::{
    default_is, finish, lib, load, metres, option_error, positive_length, report_summary, speed,
    Common, Outcome, Speeds,
};
use crate::output::Output;
use crate::progress::{duration_text, shown};

/// `whirl map`
#[derive(Debug, clap::Args)]
pub struct Args {
    #[command(flatten)]
    pub common: Common,
    /// The parameter, as a study file addresses it, e.g. `roller_bearing[0].rollers`
    /// [default: roller_bearing[*].clearance].
    #[arg(long, value_name = "PATH")]
    pub parameter: Option<String>,
    /// The values, comma-separated, each as the model file writes it, e.g.
    /// `10um,20um,60um` or `12,16,20`.
    #[arg(long, value_name = "LIST", value_delimiter = ',', required = true)]
    pub values: Vec<String>,
    /// Speed range `start:stop` of every sweep, e.g. `1:750Hz`; plain numbers are rad/s
    /// [default: 1 Hz to 1.2 x the model's top operating speed].
    #[arg(long, value_name = "RANGE", value_parser = speed_span)]
    pub speeds: Option<Speeds>,
    #[command(flatten)]
    pub hb: HbFlags,
    /// Report which values keep the synchronous orbit free of unstable bands below this
    /// speed, e.g. `600Hz`.
    #[arg(long, value_name = "SPEED", value_parser = speed)]
    pub clear_below: Option<f64>,
    /// Run the default cascade at these values (comma-separated, among `--values`) and
    /// report how well the map explains it: the share of speeds with NSV at the level that
    /// lie in a band or on a matching resonance line, the share of predicted quiet speeds
    /// that are quiet, and the speeds where they disagree.
    #[arg(long, value_name = "LIST", value_delimiter = ',')]
    pub check: Vec<String>,
    #[arg(long, value_name = "LENGTH", value_parser = positive_length,
          help = default_is("NSV level of `--check` and `--confirm`, e.g. `10um`.", metres(DEFAULT_CHECK_LEVEL_M)))]
    pub check_level: Option<f64>,
    /// Run the default cascade of the largest value `--clear-below` finds clear, up to that
    /// speed, and report whether its NSV stays below the check level.
    #[arg(long, requires = "clear_below")]
    pub confirm: bool,
    /// How the sweeps share the threads (the answer is the same either way) [default:
    /// values].
    #[arg(long, value_enum)]
    pub spread: Option<Parallelism>,
}

pub fn run(args: &Args) -> miette::Result<Outcome> {
    let loaded = load(&args.common.model)?;
    let (from, to) = rising_range(&args.speeds, &loaded.model)?;
    let model_text = whirl::model::read_input(&loaded.path).map_err(|e| {
        crate::error::Diag::new(format!("cannot read `{}`: {e}", loaded.path.display()))
    })?;
    let request = MapRequest {
        model_text,
        model_file: Some(loaded.path.clone()),
        parameter: args.parameter.clone(),
        values: args.values.clone(),
        from,
        to,
        settings: args.hb.settings(),
        clear_below: args.clear_below,
        check: args.check.clone(),
        check_level_m: args.check_level,
        confirm: args.confirm,
    };
    let spread = args.spread.unwrap_or_default();
    // Check the request before the progress line starts.
    request.values().map_err(option_error)?;
    warn_if_long(&request);
    let report = shown("map", |p| map_with(&request, spread, p));
    let report = lib(report)?;
    let summary = report_summary("map", &loaded, &report)?;
    let text = text_summary(&report);
    let tables = report.tables();
    let mut out = Output::begin(&args.common.out_dir("map"))?;
    out.table_named(&tables, "bands")?;
    out.table_named(&tables, "lines")?;
    out.table_named(&tables, "values")?;
    if !report.checks.is_empty() {
        out.table_named(&tables, "checks")?;
    }
    out.figures(whirl_figures::map(&report), args.common.rpm)?;
    finish(out, summary, text, &args.common)
}

/// Fewest points of a sweep of the reference rotor over its range (10 um, 1-750 Hz: 420;
/// the larger clearances' folded branches take up to 1,707).
const LEAST_POINTS: f64 = 400.0;

/// Warns before a map whose sweeps alone are estimated to take more than half an hour of
/// computing on this machine's cores (many values, many harmonics).
fn warn_if_long(request: &MapRequest) {
    let options = request.sweep_options();
    let per_sweep = LEAST_POINTS * point_seconds(options.harmonics, true);
    let seconds = request.values.len() as f64 * per_sweep / cores() as f64;
    if seconds > LONG_RUN_S {
        eprintln!(
            "warning: {} values at H = {} make {} sweeps of at least {} each: at least {} on {} \
             cores; fewer values or harmonics are faster, or press Ctrl-C to stop",
            request.values.len(),
            options.harmonics,
            request.values.len(),
            duration_text(per_sweep),
            duration_text(seconds),
            cores()
        );
    }
}

/// Stretches of what grows inside a band that the text shows.
const GROWING_SHOWN: usize = 3;

/// A line per value (first loss, bands) and the design query's answer.
fn text_summary(report: &MapReport) -> String {
    let mut text = String::new();
    let s = report.summary();
    let _ = writeln!(
        text,
        "map of `{}` over {:.1}-{:.1} Hz, H = {}: {} values in {:.1} s ({} CPU, {} threads, \
         sweeps spread {})",
        s.parameter,
        s.speed_range_hz[0],
        s.speed_range_hz[1],
        s.harmonics,
        s.values.len(),
        s.wall_s,
        s.cpu_s.map_or("unknown".into(), |c| format!("{c:.1} s")),
        s.threads,
        match s.parallelism {
            Parallelism::Values => "one per thread",
            Parallelism::WithinSweeps => "each over every thread",
        }
    );
    for v in &s.values {
        let first = match (v.first_stability_loss_hz, v.first_loss_kind) {
            (Some(f), Some(k)) => format!("first loss {f:.2} Hz ({k})"),
            _ if v.failed => format!("failed: {}", v.end),
            _ => "stable throughout".into(),
        };
        let _ = writeln!(
            text,
            "  {}: {first}; {} resonance lines ({} on a stable orbit)",
            v.value, v.lines, v.lines_on_stable_orbit
        );
        for b in &v.bands {
            let emerging = b
                .emerging_hz
                .filter(|_| b.opens == "Neimark-Sacker" || b.opens == "period doubling")
                .map_or(String::new(), |f| format!(", {f:.1} Hz emerges"));
            let coexists = if b.coexisting_stable_hz.is_empty() {
                String::new()
            } else {
                "; a stable orbit coexists over part of it".into()
            };
            let growth = b
                .largest_growth_per_s
                .map_or(String::new(), |g| format!(", growth up to {g:.3}/s"));
            let _ = writeln!(
                text,
                "    unstable {:.2}-{:.2} Hz{growth}: opens by {}{emerging}, closes by {}{coexists}",
                b.span_hz[0], b.span_hz[1], b.opens, b.closes
            );
            // A band that wanders through a resonance changes its leading multiplier many
            // times: the first few here, all of them in bands.csv.
            if b.growing.len() > 1 {
                let shown = &b.growing[..b.growing.len().min(GROWING_SHOWN)];
                let more = match b.growing.len() - shown.len() {
                    0 => String::new(),
                    n => format!("; {n} more in bands.csv"),
                };
                let _ = writeln!(text, "      growing: {}{more}", growing_text(shown));
            }
        }
    }
    for c in &s.checks {
        let onset = |f: Option<f64>| f.map_or("none".into(), |f| format!("{f:.1} Hz"));
        let _ = writeln!(
            text,
            "  against the cascade at {}: {} of {} speeds with NSV >= {:.1} um explained ({:.0} %), \
             {} of {} predicted quiet speeds quiet ({:.0} %); sustained onset {} (cascade) / {} (map){}",
            c.check.value,
            c.check.explained,
            c.check.nsv_speeds,
            c.check.level_m * 1e6,
            100.0 * c.explained_fraction,
            c.check.quiet_confirmed,
            c.check.predicted_quiet,
            100.0 * c.quiet_fraction,
            onset(c.check.cascade_sustained_hz),
            onset(c.check.map_sustained_hz),
            match c.check.not_followed {
                0 => String::new(),
                n => format!("; {n} speeds where the branch was not followed left out"),
            },
        );
    }
    if let Some(q) = &s.clear_below {
        let _ = writeln!(
            text,
            "  no unstable band below {:.1} Hz: {} (largest {}, smallest {}){}",
            q.speed_hz,
            if q.clear.is_empty() {
                "no value".into()
            } else {
                q.clear.join(", ")
            },
            q.largest_clear.as_deref().unwrap_or("none"),
            q.smallest_clear.as_deref().unwrap_or("none"),
            if q.undecided.is_empty() {
                String::new()
            } else {
                format!("; undecided: {}", q.undecided.join(", "))
            }
        );
    }
    if let Some(c) = &s.confirmation {
        let _ = writeln!(
            text,
            "  tried by the cascade of {} up to that speed: NSV below {:.1} um {} (largest {:.2} um{}, {} speeds)",
            c.value,
            c.level_m * 1e6,
            if c.confirmed { "throughout" } else { "not everywhere" },
            c.largest_nsv_m * 1e6,
            c.largest_at_hz.map_or(String::new(), |f| format!(" at {f:.1} Hz")),
            c.speeds,
        );
    }
    text
}
