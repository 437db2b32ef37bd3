//! `whirl simulate model.toml --speed 50Hz [--duration 1s] [--method cd|newmark|rk]
//! [--hht-alpha A] [--step S] [--reduce N] [--settle T] [--nodes 10,0] [--contact hertz|lagrange|forcing|linear]
//! [--record-every N] [--ramp-to SPEED] [--start static|rest] [--divergence-bound X]`: time
//! response (docs/theory.md section 6).
//!
//! Writes `time_history.csv` and `time_history.npy` (column `time_s`, then one column per
//! channel `n10.ux`, `n10.uy`, ... in m; the .npy is a 2-D float64 array, rows = samples),
//! `spectrum.csv` (flat-top amplitude spectrum of each channel's settled part, mean removed,
//! m zero-to-peak: the flat top reads a peak's amplitude within 0.05 % wherever it falls
//! between bins), `peaks.csv` (the largest spectral peaks with their order of the running
//! speed: `1X`, `0.5X`, or `non-synchronous`) and the plots `time_history`, `orbits` (a
//! roller bearing's node with its clearance circle) and `spectrum` (1X and its multiples,
//! and each roller bearing's varying-compliance and waviness frequencies, marked).
//!
//! With a contact law (Hertz, the default when the model has roller bearings) every roller
//! bearing's node is recorded, and per bearing `contacts_<bearing>.csv` (each roller's force
//! and approach over time), the plots `contact_line_<bearing>` (which rollers touch when,
//! thesis fig. 4.7) and `contact_zone_<bearing>` (roller force versus roller angle, fig.
//! 4.9), and in summary.json the rollers in contact, the largest penetration and force, and
//! the predicted contact frequencies with the spectral peak measured nearest each; see
//! [`contacts`].
//!
//! Every `--record-every`-th step is recorded [default: as many steps as fit in
//! [`whirl::time::DEFAULT_SAMPLE_INTERVAL`]]: the full model's stable step is a few
//! microseconds, and recording each would write hundreds of MB for a second of motion.
//!
//! The settled 1X amplitude and phase come from order tracking of the settled part
//! ([`whirl::post::order_component`]), in the phase convention of `whirl unbalance`, so the
//! two compare directly. With `--ramp-to` the speed rises linearly from `--speed` over the
//! settling time and then holds: the settled part runs at the final speed.
//!
//! The central difference runs at 0.9 times its stability limit unless `--step` is given; a
//! given step above the limit is refused with the limit in the message. A run that
//! diverges writes nothing and says when and why.

mod contacts;

use std::fmt::Write;

use whirl::bearing::ContactLaw;
use whirl::given::Choice;
use whirl::model::Model;
use whirl::report::Report;
use whirl::time::{
    simulate, Initial, Integrator, RunStatus, SettledChannel, SimulationReport, SimulationRequest,
    SimulationResult, DEFAULT_DIVERGENCE_BOUND, DEFAULT_DURATION, DEFAULT_INITIAL,
};

use super::{
    default_is, finish, lib, load, mode_count, option_error, positive_length, report_summary,
    seconds, speed, time, Common, Nodes, Outcome,
};
use crate::error::Diag;
use crate::output::Output;
use crate::progress::progress_line;

/// `whirl simulate`
#[derive(Debug, clap::Args)]
pub struct Args {
    #[command(flatten)]
    pub common: Common,
    /// Spin speed: `50Hz`, `3000rpm`, or a plain number in rad/s.
    #[arg(long, value_name = "SPEED", value_parser = speed, allow_hyphen_values = true)]
    pub speed: f64,
    #[arg(long, value_name = "TIME", value_parser = time, allow_hyphen_values = true,
          help = default_is("Simulated time: `1s`, `500ms`, or a plain number in s", seconds(DEFAULT_DURATION)))]
    pub duration: Option<f64>,
    #[arg(long, value_enum, help = default_is("Time integrator", Integrator::default().choice_name()))]
    pub method: Option<Integrator>,
    /// HHT-alpha of --method newmark, in [-1/3, 0]: below 0 damps the highest
    /// frequencies (Hilber-Hughes-Taylor) [default: 0, the average-acceleration rule].
    #[arg(long, value_name = "ALPHA", allow_hyphen_values = true)]
    pub hht_alpha: Option<f64>,
    /// Time step (output interval for rk) [default: 0.9 x the stability limit for cd,
    /// 1e-5 s otherwise].
    #[arg(long, value_name = "TIME", value_parser = time, allow_hyphen_values = true)]
    pub step: Option<f64>,
    /// Craig-Bampton reduction keeping N fixed-interface modes (bearing nodes are the
    /// boundary) [default: the full model].
    #[arg(long, value_name = "N", value_parser = mode_count)]
    pub reduce: Option<usize>,
    /// Time discarded before the steady-state numbers [default: half the duration].
    #[arg(long, value_name = "TIME", value_parser = time, allow_hyphen_values = true)]
    pub settle: Option<f64>,
    #[command(flatten)]
    pub nodes: Nodes,
    /// Contact law of the roller bearings [default: hertz when the model has roller
    /// bearings, linear otherwise].
    #[arg(long, value_name = "LAW", value_enum)]
    pub contact: Option<ContactLaw>,
    /// Record every N-th step [default: as many steps as fit in 1e-5 s, at least 1].
    #[arg(long, value_name = "N", value_parser = record_every)]
    pub record_every: Option<usize>,
    /// Raise the speed linearly from --speed to this over the settling time, then hold it.
    #[arg(long, value_name = "SPEED", value_parser = speed, allow_hyphen_values = true)]
    pub ramp_to: Option<f64>,
    #[arg(long, value_enum, help = default_is("Initial state", DEFAULT_INITIAL.choice_name()))]
    pub start: Option<Initial>,
    #[arg(long, value_name = "LENGTH", value_parser = positive_length, help = default_is(
        "A recorded displacement (ux or uy of a recorded node, bearing nodes included) beyond this \
means the run diverged; any integrated coordinate beyond 1000 times it (rotations and modal \
coordinates too) as well", DEFAULT_DIVERGENCE_BOUND))]
    pub divergence_bound: Option<f64>,
}

/// Clap parser of `--record-every`: a whole number of steps, at least 1.
fn record_every(text: &str) -> Result<usize, String> {
    match text.trim().parse::<usize>() {
        Ok(n) if n >= 1 => Ok(n),
        _ => Err(format!(
            "`{text}` is not a number of steps: give a whole number, 1 or more"
        )),
    }
}

pub fn run(args: &Args) -> miette::Result<Outcome> {
    let loaded = load(&args.common.model)?;
    let model = &loaded.model;
    let nodes = args.nodes.resolve(model)?;
    let (progress, line) = progress_line("simulating".into());
    let mut options = request(args, nodes).options().map_err(option_error)?;
    options.progress = Some(progress);
    let result = simulate(model, &options);
    line.clear();
    let result = result.map_err(option_error)?;
    // A run stopped by its progress (not asked for here: Ctrl-C quits `simulate` at once)
    // is reported as the library says it.
    let result = match &result.status {
        RunStatus::Diverged { message, .. } => {
            return Err(Diag::new(message.clone())
                .help("nothing was written")
                .into())
        }
        RunStatus::Stopped { .. } => lib(result.completed())?,
        RunStatus::Completed => result,
    };
    check_settled_part(&result)?;
    let report = lib(SimulationReport::new(model, &options, result))?;
    let running_hz = report.running_hz();
    let result = &report.result;

    let summary = report_summary("simulate", &loaded, &report)?;
    let mut text = text(
        model,
        args,
        options.duration,
        result,
        running_hz,
        &report.channels,
    );
    contacts::text(&mut text, &report);
    let mut out = Output::begin(&args.common.out_dir("simulate"))?;
    for table in report.tables() {
        out.table(&table)?;
    }
    write_time_history_npy(&mut out, result)?;
    out.figures(whirl_figures::simulate(model, &report), args.common.rpm)?;
    finish(out, summary, text, &args.common)
}

/// The run as the flags ask for it.
fn request(args: &Args, nodes: Vec<usize>) -> SimulationRequest {
    SimulationRequest {
        speed: args.speed,
        ramp_to: args.ramp_to,
        duration: args.duration,
        method: args.method.unwrap_or_default(),
        hht_alpha: args.hht_alpha,
        step: args.step,
        reduce: args.reduce,
        settle: args.settle,
        nodes: Some(nodes),
        contact: args.contact,
        record_every: args.record_every,
        start: args.start,
        divergence_bound: args.divergence_bound,
    }
}

/// Too short a settled part for a spectrum, said in terms of the flags.
fn check_settled_part(result: &SimulationResult) -> miette::Result<()> {
    let settled = result.time.len() - result.settled_start();
    if settled < whirl::post::spectrum::MIN_SAMPLES {
        return Err(Diag::option(
            "--settle",
            format!(
                "the settled part holds {settled} samples; a spectrum needs at least {}",
                whirl::post::spectrum::MIN_SAMPLES
            ),
        )
        .help("shorten --settle, lengthen --duration, or use a smaller --step")
        .into());
    }
    Ok(())
}

fn text(
    model: &Model,
    args: &Args,
    duration: f64,
    result: &SimulationResult,
    running_hz: f64,
    reports: &[SettledChannel],
) -> String {
    let mut t = String::new();
    let _ = writeln!(
        t,
        "{}: {} at {running_hz:.2} Hz for {} s, step {:.3e} s (stable limit {:.3e} s), \
         {} coordinates{}, {} samples in {:.2} s",
        model.name,
        result.method,
        duration,
        result.step,
        result.stable_step,
        result.coordinates,
        args.reduce
            .map_or(String::new(), |n| format!(" (reduced, {n} modes)")),
        result.time.len(),
        result.wall_time_s
    );
    if let Some(why) = &result.start_fallback {
        let _ = writeln!(t, "note: {why}");
    }
    let _ = writeln!(t, "settled part (from {} s):", result.settle);
    for r in reports {
        let one_x = r.one_x.map_or("-".into(), |c| {
            format!("{:.4e} m at {:7.2} deg", c.amplitude, c.phase.to_degrees())
        });
        let nsv = r.non_synchronous.map_or("none".into(), |p| {
            format!("{:.3e} m at {:.2} Hz", p.amplitude, p.frequency_hz)
        });
        let _ = writeln!(
            t,
            "  {:>7}: 1X {one_x}, peak-to-peak {:.4e} m, largest non-synchronous {nsv}",
            r.name, r.peak_to_peak
        );
    }
    t
}

/// `time_history.npy` (its .csv is a table of the report).
fn write_time_history_npy(out: &mut Output, result: &SimulationResult) -> miette::Result<()> {
    let mut columns: Vec<&[f64]> = vec![&result.time];
    columns.extend(result.channels.iter().map(|c| c.values.as_slice()));
    out.npy("time_history.npy", &columns)
}
