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

use clap::ValueEnum;
use serde_json::{json, Value};
use whirl::bearing::ContactLaw;
use whirl::model::Model;
use whirl::post::{SpectralPeak, Window};
use whirl::system::SpeedProfile;
use whirl::time::{
    simulate, Initial, Method, NewmarkScheme, RkTolerances, RunStatus, SettledChannel,
    SimulationOptions, SimulationResult, ORDER_TOLERANCE_BINS,
};

use super::campbell::order_name;
use super::{
    finish, hz, lib, load, mode_count, node_index, positive_length, report_nodes, speed,
    summary_head, time, Common, Loaded, Outcome,
};
use crate::error::Diag;
use crate::output::{header, num, Output};
use crate::plots;
use crate::progress::progress_line;

/// The time integrator.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum Integrator {
    /// Explicit central difference (thesis eqs. 4.1-4.3); needs a step below 2 / w_max.
    Cd,
    /// Implicit Newmark, average acceleration; any step is stable.
    Newmark,
    /// Adaptive Dormand-Prince 5(4), the accuracy reference; --step is the output interval.
    Rk,
}

/// `whirl simulate`
#[derive(Debug, clap::Args)]
pub struct Args {
    #[command(flatten)]
    pub common: Common,
    /// Spin speed: `50Hz`, `3000rpm`, or a plain number in rad/s.
    #[arg(long, value_name = "SPEED", value_parser = speed, allow_hyphen_values = true)]
    pub speed: f64,
    /// Simulated time: `1s`, `500ms`, or a plain number in s.
    #[arg(long, value_name = "TIME", default_value = "1s", value_parser = time, allow_hyphen_values = true)]
    pub duration: f64,
    /// Time integrator.
    #[arg(long, value_enum, default_value = "cd")]
    pub method: Integrator,
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
    /// Nodes to record, comma-separated [default: every disk and bearing node].
    #[arg(long, value_name = "LIST", value_delimiter = ',', value_parser = node_index)]
    pub nodes: Vec<usize>,
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
    /// Initial state.
    #[arg(long, value_enum, default_value = "static")]
    pub start: Initial,
    /// A recorded displacement (ux or uy of a recorded node, bearing nodes included)
    /// beyond this means the run diverged; any integrated coordinate beyond 1000 times it
    /// (rotations and modal coordinates too) as well.
    #[arg(long, value_name = "LENGTH", default_value = "0.01", value_parser = positive_length)]
    pub divergence_bound: f64,
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
    let nodes = report_nodes(model, &args.nodes)?;
    let (progress, line) = progress_line("simulating".into());
    let mut options = SimulationOptions {
        duration: args.duration,
        step: time_step(args)?,
        method: integrator(args)?,
        contact: args.contact,
        reduction: args.reduce,
        settle: args.settle,
        nodes: Some(nodes),
        initial: args.start,
        divergence_bound: args.divergence_bound,
        record_every: args.record_every,
        progress: Some(progress.clone()),
        ..SimulationOptions::new(SpeedProfile::Constant(args.speed))
    };
    let law = options.contact_law(model);
    let settle = options.settle_time();
    check_settling(args, settle)?;
    options.speed = speed_profile(args, settle)?;
    let speed = options.speed;
    let result = simulate(model, &options);
    line.clear();
    let result = lib(result)?;
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
    let final_speed = speed.at(args.duration).0.speed;
    let running_hz = hz(final_speed);
    let reports = channel_reports(&result, &speed)?;
    let bearings = contacts::bearing_reports(model, &result, &reports, final_speed, running_hz);
    // Every recorded node: those asked for and the bearing nodes a contact law adds.
    let mut recorded: Vec<usize> = result.channels.iter().map(|c| c.node).collect();
    recorded.dedup();

    let mut summary = summary(&loaded, args, law, &result, running_hz, &reports);
    if let Value::Object(map) = &mut summary {
        map.insert("bearings".into(), contacts::summary(&bearings));
    }
    let mut text = text(model, args, &result, running_hz, &reports);
    contacts::text(&mut text, &bearings);
    let mut out = Output::begin(&args.common.out_dir("simulate"))?;
    write_tables(&mut out, &result, &reports, running_hz)?;
    contacts::write(&mut out, &result, &bearings)?;
    out.plot("time_history", |stem| {
        plots::time_history(&result, &recorded).save(stem)
    })?;
    let circles = contacts::clearance_circles(model, final_speed);
    out.plot("orbits", |stem| {
        plots::orbits(&result, &recorded, &circles).save(stem)
    })?;
    let markers = contacts::spectrum_markers(&bearings);
    out.plot("spectrum", |stem| {
        plots::spectrum(&reports, running_hz, &markers).save(stem)
    })?;
    finish(out, summary, text, &args.common)
}

fn integrator(args: &Args) -> miette::Result<Method> {
    match (args.method, args.hht_alpha) {
        (Integrator::Newmark, Some(alpha)) if !(-1.0 / 3.0..=0.0).contains(&alpha) => Err(
            Diag::option("--hht-alpha", format!("{alpha} is outside [-1/3, 0]"))
                .help("e.g. --hht-alpha -0.05; 0 is the average-acceleration rule")
                .into(),
        ),
        (Integrator::Newmark, Some(alpha)) => Ok(Method::Newmark(NewmarkScheme::Hht(alpha))),
        (Integrator::Newmark, None) => Ok(Method::Newmark(NewmarkScheme::AverageAcceleration)),
        (_, Some(_)) => Err(
            Diag::option("--hht-alpha", "applies to --method newmark only")
                .help("add --method newmark, or leave --hht-alpha out")
                .into(),
        ),
        (Integrator::Cd, None) => Ok(Method::CentralDifference),
        (Integrator::Rk, None) => Ok(Method::RungeKutta(RkTolerances::default())),
    }
}

/// The step given (it must be positive), or `None` for the library's default.
fn time_step(args: &Args) -> miette::Result<Option<f64>> {
    match args.step {
        Some(h) if h <= 0.0 => Err(Diag::option("--step", "the time step must be positive").into()),
        given => Ok(given),
    }
}

/// The name a value has on the command line.
fn value_name(value: impl ValueEnum) -> String {
    value
        .to_possible_value()
        .map(|v| v.get_name().to_string())
        .unwrap_or_default()
}

/// The duration must be positive and the settling time (given, or the library's default)
/// must leave a settled part; said here in terms of the flags.
fn check_settling(args: &Args, settle: f64) -> miette::Result<()> {
    if args.duration <= 0.0 {
        return Err(Diag::option("--duration", "the duration must be positive")
            .help("e.g. --duration 1s")
            .into());
    }
    if settle >= args.duration {
        return Err(Diag::option(
            "--settle",
            format!(
                "the settling time {settle} s is not shorter than the duration {} s",
                args.duration
            ),
        )
        .help("the steady-state numbers come from the time after --settle: shorten it or lengthen --duration")
        .into());
    }
    Ok(())
}

/// Constant speed, or a ramp over the settling time to `--ramp-to`.
fn speed_profile(args: &Args, settle: f64) -> miette::Result<SpeedProfile> {
    match args.ramp_to {
        None => Ok(SpeedProfile::Constant(args.speed)),
        Some(_) if settle <= 0.0 => Err(Diag::option(
            "--ramp-to",
            "the speed ramps over the settling time, which is zero",
        )
        .help("give --settle, e.g. --settle 0.5s")
        .into()),
        Some(to) => Ok(SpeedProfile::Ramp {
            from: args.speed,
            to,
            duration: settle,
        }),
    }
}

/// What the settled part of each channel shows; too short a settled part is said in terms
/// of the flags.
fn channel_reports(
    result: &SimulationResult,
    speed: &SpeedProfile,
) -> miette::Result<Vec<SettledChannel>> {
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
    lib(result.settled(speed))
}

/// `1X`, `2X` at multiples of the running speed, `0.5X`, `1.5X` at half orders (where
/// sub-synchronous whirl sits), otherwise `non-synchronous`.
pub fn order_label(frequency_hz: f64, running_hz: f64, tolerance_hz: f64) -> String {
    if running_hz > 0.0 {
        let halves = (2.0 * frequency_hz / running_hz).round();
        if halves >= 1.0 && (frequency_hz - 0.5 * halves * running_hz).abs() <= tolerance_hz {
            return order_name(0.5 * halves);
        }
    }
    "non-synchronous".into()
}

fn peak_json(p: &SpectralPeak, running_hz: f64, tolerance_hz: f64) -> Value {
    json!({
        "frequency_hz": p.frequency_hz, "amplitude_m": p.amplitude,
        "order": p.order.is_finite().then_some(p.order),
        "label": order_label(p.frequency_hz, running_hz, tolerance_hz),
    })
}

fn summary(
    loaded: &Loaded,
    args: &Args,
    law: ContactLaw,
    result: &SimulationResult,
    running_hz: f64,
    reports: &[SettledChannel],
) -> Value {
    let mut s = summary_head("simulate", loaded);
    s.insert("method".into(), result.method.clone().into());
    s.insert("contact".into(), law.name().into());
    s.insert("speed_hz".into(), hz(args.speed).into());
    s.insert("ramp_to_hz".into(), json!(args.ramp_to.map(hz)));
    s.insert("running_speed_hz".into(), running_hz.into());
    s.insert("duration_s".into(), args.duration.into());
    s.insert("settle_s".into(), result.settle.into());
    s.insert("step_s".into(), result.step.into());
    s.insert("stable_step_s".into(), result.stable_step.into());
    s.insert("reduction_modes".into(), json!(args.reduce));
    s.insert("coordinates".into(), result.coordinates.into());
    s.insert("start".into(), value_name(args.start).into());
    s.insert("start_fallback".into(), json!(result.start_fallback));
    s.insert("samples".into(), result.time.len().into());
    s.insert("record_every".into(), result.record_every.into());
    s.insert("sample_interval_s".into(), result.sample_interval().into());
    s.insert("wall_time_s".into(), result.wall_time_s.into());
    s.insert("rk_stats".into(), json!(result.rk_stats));
    // "completed" or "diverged", without the divergence's details (a diverged run stops
    // before anything is written).
    s.insert("status".into(), json!(result.status)["status"].clone());
    let resolution = reports
        .first()
        .map_or(f64::NAN, |r| r.spectrum.resolution_hz);
    s.insert("spectrum_window".into(), Window::FlatTop.to_string().into());
    s.insert("spectrum_resolution_hz".into(), resolution.into());
    let tolerance_hz = ORDER_TOLERANCE_BINS * resolution;
    s.insert(
        "channels".into(),
        reports
            .iter()
            .map(|r| {
                json!({
                    "name": r.name, "node": r.node,
                    "mean_m": r.mean,
                    "one_x_amplitude_m": r.one_x.map(|c| c.amplitude),
                    "one_x_phase_deg": r.one_x.map(|c| c.phase.to_degrees()),
                    "peak_to_peak_m": r.peak_to_peak,
                    "largest_non_synchronous": r.non_synchronous
                        .map(|p| peak_json(&p, running_hz, tolerance_hz)),
                    "peaks": r.peaks.iter()
                        .map(|p| peak_json(p, running_hz, tolerance_hz))
                        .collect::<Vec<_>>(),
                })
            })
            .collect::<Vec<_>>()
            .into(),
    );
    s.insert(
        "notes".into(),
        json!([
            "1X amplitude and phase by order tracking of the settled part; phase as in `whirl unbalance` (x = A cos(Omega t + phase))",
            "spectra: flat-top window, mean removed, zero-to-peak amplitude",
            "divergence_bound (m) applies to the recorded displacements (ux, uy of the recorded nodes, bearing nodes included); any integrated coordinate beyond 1000 times it, rotations and modal coordinates too, also counts as divergence",
            "bearings: contact statistics over the settled part; a roller is in contact when it carries load (for the forcing-function law, when it penetrates); measured peaks are the largest spectral peak of the bearing node's channel within 3 bins of the prediction",
        ]),
    );
    s.insert("divergence_bound".into(), args.divergence_bound.into());
    Value::Object(s)
}

fn text(
    model: &Model,
    args: &Args,
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
        args.duration,
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

fn write_tables(
    out: &mut Output,
    result: &SimulationResult,
    reports: &[SettledChannel],
    running_hz: f64,
) -> miette::Result<()> {
    let mut h = vec!["time_s".to_string()];
    h.extend(result.channels.iter().map(|c| c.name.clone()));
    let rows = result.time.iter().enumerate().map(|(i, t)| {
        std::iter::once(num(*t)).chain(result.channels.iter().map(move |c| num(c.values[i])))
    });
    out.csv("time_history.csv", &h, rows)?;
    let mut columns: Vec<&[f64]> = vec![&result.time];
    columns.extend(result.channels.iter().map(|c| c.values.as_slice()));
    out.npy("time_history.npy", &columns)?;

    let mut h = vec!["frequency_hz".to_string()];
    h.extend(reports.iter().map(|r| r.name.clone()));
    let frequencies = reports
        .first()
        .map_or(&[][..], |r| &r.spectrum.frequency_hz);
    let rows = frequencies.iter().enumerate().map(|(k, f)| {
        std::iter::once(num(*f)).chain(reports.iter().map(move |r| num(r.spectrum.amplitude[k])))
    });
    out.csv("spectrum.csv", &h, rows)?;

    let mut rows = Vec::new();
    for r in reports {
        let tolerance_hz = ORDER_TOLERANCE_BINS * r.spectrum.resolution_hz;
        for p in &r.peaks {
            rows.push(vec![
                r.name.clone(),
                num(p.frequency_hz),
                num(p.amplitude),
                num(p.order),
                order_label(p.frequency_hz, running_hz, tolerance_hz),
            ]);
        }
    }
    let h = header(&["channel", "frequency_hz", "amplitude_m", "order", "label"]);
    out.csv("peaks.csv", &h, &rows)
}
