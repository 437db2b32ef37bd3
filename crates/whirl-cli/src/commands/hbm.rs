//! `whirl hbm model.toml [--speeds 1:750Hz] [--harmonics 5] [--nodes 10,0]
//! [--contact hertz|forcing] [--cage passage|frozen] [--compare-time 100Hz,330Hz]
//! [--harmonics-study 1..5]`: the periodic (synchronous) response by harmonic balance,
//! followed over speed by continuation, with Floquet stability and the bifurcations where it
//! changes (thesis 4.3; docs/theory.md section 7).
//!
//! Writes `branch.csv` (one row per continuation point in path order: speed, stability,
//! largest real part of the Floquet exponents, Newton iterations, and per node the
//! amplitude of the constant term and of each harmonic of u_x and u_y), `bifurcations.csv`
//! (kind, speed, frequency of the crossing exponent: the non-synchronous frequency that
//! appears at a Neimark-Sacker point), the plot `harmonics` (amplitude of each harmonic at
//! the first node over speed, stable solid and unstable dashed, bifurcations marked) and
//! `stability` (the largest real part over speed). `--compare-time` solves harmonic balance
//! at exactly each of its speeds (every orbit where the branch crosses it, each marked
//! stable or unstable) and adds `compare_time.csv`
//! and the time-marching amplitudes as markers on `harmonics` (thesis fig. 4.27);
//! `--harmonics-study` adds `harmonics_study.csv` and the plot `harmonics_study`
//! (the first harmonic for each H, thesis fig. 4.28).
//!
//! The roller passage is not periodic in the running speed; summary.json and every plot
//! title say which periodic approximation was used ([`whirl::hbm::CageModel`]).

use std::f64::consts::TAU;
use std::fmt::Write;

use whirl::bearing::ContactLaw;
use whirl::hbm::{
    settled_response, sweep_with_progress, CageKind, CageModel, MarchSettings, SettledResponse,
    Sweep, SweepOptions, SweepReport, SweepSettings, DEFAULT_CAGE_POSITIONS, DEFAULT_HARMONICS,
    DEFAULT_STABILITY_MODES, MAX_HARMONICS, RESOLUTION_TOLERANCE,
};
use whirl::model::Model;

use super::{
    finish, hz, lib, load, mode_count, report_summary, speed, speeds, time, Common, Nodes, Outcome,
    Speeds,
};
use crate::error::Diag;
use crate::output::Output;
use crate::progress::{duration_text, shown};
use whirl::report::Report;

/// The discretisation and bearing model of a harmonic-balance sweep, shared by `whirl hbm`
/// and `whirl map`; [`HbFlags::settings`] hands them to the library.
#[derive(Debug, clap::Args)]
pub struct HbFlags {
    /// Harmonics H of the running speed (1 to 50).
    #[arg(long, value_name = "H", default_value_t = DEFAULT_HARMONICS, value_parser = harmonic_count)]
    pub harmonics: usize,
    /// Contact law of the roller bearings: hertz or forcing (harmonic balance needs a
    /// force law of the displacement).
    #[arg(long, value_enum, default_value = "hertz")]
    pub contact: ContactLaw,
    /// How the roller passage is made periodic (Hertz only).
    #[arg(long, value_enum, default_value = "passage")]
    pub cage: CageKind,
    /// Cage positions per roller pitch of the passage average.
    #[arg(long, value_name = "N", default_value_t = DEFAULT_CAGE_POSITIONS, value_parser = mode_count)]
    pub cage_positions: usize,
    /// Approach below which the Hertz law is blended to bounded curvature (harmonic balance
    /// only; docs/theory.md section 7), e.g. `0.01um`; 0 for the exact law.
    #[arg(long, value_name = "LENGTH", default_value = "0", value_parser = smoothing_length)]
    pub contact_smoothing: f64,
    /// Time samples per period of the alternating frequency-time transform [default: 32 H,
    /// at least 64].
    #[arg(long, value_name = "N")]
    pub samples: Option<usize>,
    /// Solve on a Craig-Bampton model with N fixed-interface modes, as the time integrators
    /// do (faster; the condensation stays exact) [default: the full model].
    #[arg(long, value_name = "N", value_parser = mode_count)]
    pub reduce: Option<usize>,
    /// Fixed-interface modes of the stability model.
    #[arg(long, value_name = "N", default_value_t = DEFAULT_STABILITY_MODES, value_parser = mode_count)]
    pub stability_modes: usize,
}

impl HbFlags {
    /// The library's settings of a sweep with these flags.
    pub fn settings(&self) -> SweepSettings {
        SweepSettings {
            harmonics: Some(self.harmonics),
            samples: self.samples,
            contact: Some(self.contact),
            cage: Some(CageModel::new(self.cage, Some(self.cage_positions))),
            contact_smoothing: Some(self.contact_smoothing),
            stability: None,
            stability_modes: Some(self.stability_modes),
            reduction: self.reduce,
        }
    }
}

/// `whirl hbm`
#[derive(Debug, clap::Args)]
pub struct Args {
    #[command(flatten)]
    pub common: Common,
    /// Speed range `start:stop` (a count, if given, is ignored: continuation chooses its
    /// steps), e.g. `1:750Hz`; plain numbers are rad/s [default: 1 Hz to 1.2 x the model's
    /// top operating speed].
    #[arg(long, value_name = "RANGE", value_parser = speed_span)]
    pub speeds: Option<Speeds>,
    #[command(flatten)]
    pub hb: HbFlags,
    #[command(flatten)]
    pub nodes: Nodes,
    /// Skip the Floquet stability (faster; no bifurcations).
    #[arg(long)]
    pub no_stability: bool,
    /// Speeds at which to run the time integrator and overlay its settled amplitudes,
    /// comma-separated, e.g. `100Hz,330Hz`.
    #[arg(long, value_name = "LIST", value_delimiter = ',', value_parser = speed)]
    pub compare_time: Vec<f64>,
    /// Settling time of the comparison runs.
    #[arg(long, value_name = "TIME", default_value = "0.5s", value_parser = time)]
    pub settle: f64,
    /// Recorded (analysed) time of the comparison runs.
    #[arg(long, value_name = "TIME", default_value = "0.5s", value_parser = time)]
    pub record: f64,
    /// Repeat the sweep for these harmonic counts, e.g. `1..5` or `1,3,5` (thesis fig.
    /// 4.28).
    #[arg(long, value_name = "LIST", value_parser = harmonic_list)]
    pub harmonics_study: Option<HarmonicList>,
}

/// Clap parser of `start:stop` (or `start:stop:count`, the count ignored).
pub fn speed_span(text: &str) -> Result<Speeds, String> {
    if text.split(':').count() == 2 {
        speeds(&format!("{text}:2"))
    } else {
        speeds(text)
    }
}

/// Clap parser of the contact smoothing: a positive length, or 0 for the exact law.
fn smoothing_length(text: &str) -> Result<f64, String> {
    if text.trim().parse::<f64>() == Ok(0.0) {
        return Ok(0.0);
    }
    super::positive_length(text)
}

/// Harmonic counts of a study.
#[derive(Debug, Clone)]
pub struct HarmonicList(pub Vec<usize>);

/// Clap parser of a harmonic count, 1 to [`MAX_HARMONICS`].
fn harmonic_count(text: &str) -> Result<usize, String> {
    match text.trim().parse::<usize>() {
        Ok(h) if (1..=MAX_HARMONICS).contains(&h) => Ok(h),
        _ => Err(format!(
            "`{text}`: a harmonic count is a whole number from 1 to {MAX_HARMONICS} (the \
             stability matrix grows with 2H + 1 and its cost with the cube of that)"
        )),
    }
}

/// Computing time of one branch point of the reference rotor with H = 5 and stability on
/// this project's 2-core test machine (12 points in 0.31 s of CPU, start-up included), s.
const SECONDS_PER_POINT_H5: f64 = 0.025;

/// Estimated time per point above which `hbm` warns before it starts, s.
const SLOW_POINT_S: f64 = 1.0;

/// Estimated computing time of one branch point with `harmonics` harmonics, s: the cost
/// grows about as the cube of 2H + 1 (the dense Newton solves), and halves without the
/// stability.
pub fn point_seconds(harmonics: usize, stability: bool) -> f64 {
    let growth = ((2 * harmonics + 1) as f64 / 11.0).powi(3);
    SECONDS_PER_POINT_H5 * growth * if stability { 1.0 } else { 0.5 }
}

/// Warns before a sweep whose harmonic count makes every point slow.
fn warn_if_slow(harmonics: usize, stability: bool) {
    let per_point = point_seconds(harmonics, stability);
    if per_point > SLOW_POINT_S {
        eprintln!(
            "warning: H = {harmonics} makes each point of the branch about {} of computing, \
             and a branch over a speed range has hundreds of points; fewer harmonics \
             or --no-stability are faster",
            duration_text(per_point)
        );
    }
}

/// Clap parser of `a..b` or `a,b,c` (1 to 50 each).
fn harmonic_list(text: &str) -> Result<HarmonicList, String> {
    let parse = harmonic_count;
    let list = match text.split_once("..") {
        Some((a, b)) => {
            let (a, b) = (parse(a)?, parse(b)?);
            if b < a {
                return Err(format!("`{text}`: the range must not run backwards"));
            }
            (a..=b).collect()
        }
        None => text.split(',').map(parse).collect::<Result<Vec<_>, _>>()?,
    };
    Ok(HarmonicList(list))
}

pub fn run(args: &Args) -> miette::Result<Outcome> {
    let loaded = load(&args.common.model)?;
    let model = &loaded.model;
    let mut nodes = args.nodes.resolve(model)?;
    if args.nodes.is_default() {
        // Disks first: the first node is plotted and compared.
        nodes.sort_by_key(|n| !model.disks.iter().any(|d| d.station.node == *n));
    }
    let options = sweep_options(args, model, args.hb.harmonics)?;
    let most = args
        .harmonics_study
        .iter()
        .flat_map(|l| l.0.iter().copied())
        .fold(args.hb.harmonics, usize::max);
    warn_if_slow(most, options.stability);
    let result = lib(sweep_shown(model, &options))?;
    let comparisons = args
        .compare_time
        .iter()
        .map(|&w| compare_at(model, args, w, nodes[0]))
        .collect::<miette::Result<Vec<_>>>()?;
    let study = match &args.harmonics_study {
        Some(list) => list
            .0
            .iter()
            .map(|&h| {
                let mut o = sweep_options(args, model, h)?;
                o.stability = false;
                Ok((h, lib(sweep_shown(model, &o))?))
            })
            .collect::<miette::Result<Vec<_>>>()?,
        None => Vec::new(),
    };

    let report = SweepReport {
        options,
        sweep: result,
        nodes,
        comparisons,
        study,
    };
    let summary = report_summary("hbm", &loaded, &report)?;
    let text = text_summary(model, &report);
    let tables = report.tables();
    let mut out = Output::begin(&args.common.out_dir("hbm"))?;
    out.table_named(&tables, "branch")?;
    out.table_named(&tables, "bifurcations")?;
    if !report.comparisons.is_empty() {
        out.table_named(&tables, "compare_time")?;
    }
    if !report.study.is_empty() {
        out.table_named(&tables, "harmonics_study")?;
    }
    out.figures(whirl_figures::harmonic_balance(&report), args.common.rpm)?;
    finish(out, summary, text, &args.common)
}

/// The sweep with a progress line: the speed the path has reached.
fn sweep_shown(model: &Model, options: &SweepOptions) -> whirl::Result<Sweep> {
    shown(&format!("hbm (H = {})", options.harmonics), |p| {
        sweep_with_progress(model, options, p)
    })
}

fn sweep_options(args: &Args, model: &Model, harmonics: usize) -> miette::Result<SweepOptions> {
    let (from, to) = rising_range(&args.speeds, model)?;
    let mut settings = args.hb.settings();
    settings.harmonics = Some(harmonics);
    settings.stability = Some(!args.no_stability);
    let mut options = settings.options(from, to);
    options.exact_speeds = args.compare_time.clone();
    Ok(options)
}

/// The first and last speed of `--speeds` (rad/s), or the model's default range: a rising
/// range of positive speeds, as harmonic balance needs.
pub fn rising_range(speeds: &Option<Speeds>, model: &Model) -> miette::Result<(f64, f64)> {
    let range = Speeds::or_default(speeds, model, TAU, 2);
    match (range.first(), range.last()) {
        (Some(&a), Some(&b)) if a > 0.0 && b > a => Ok((a, b)),
        _ => Err(Diag::new(format!(
            "--speeds: harmonic balance needs a rising range of positive speeds, got {:?} Hz",
            range.iter().map(|w| hz(*w)).collect::<Vec<_>>()
        ))
        .help("e.g. --speeds 1:750Hz")
        .into()),
    }
}

/// A time-marching comparison: the settled response at one speed, read against the
/// harmonic-balance solutions at exactly that speed ([`Sweep::at_speeds`]).
type Comparison = SettledResponse;

fn compare_at(model: &Model, args: &Args, w: f64, node: usize) -> miette::Result<Comparison> {
    let settings = MarchSettings {
        settle: args.settle,
        record: args.record,
        contact: args.hb.contact,
        ..MarchSettings::default()
    };
    lib(settled_response(
        model,
        w,
        node,
        args.hb.harmonics,
        &settings,
    ))
}

fn text_summary(model: &Model, report: &SweepReport) -> String {
    let mut text = String::new();
    let result = &report.sweep;
    let branch = &result.branch;
    let _ = writeln!(
        text,
        "{}: harmonic balance, H = {}, {} points in {:.2} s ({}); {}",
        model.name,
        branch.options.harmonics,
        branch.points.len(),
        result.wall_time_s,
        result.bearings,
        branch.end.reason()
    );
    if let Some(low) = result.approached_from {
        let _ = writeln!(
            text,
            "  started on the branch followed up from {:.2} Hz: Newton from the static \
             equilibrium did not converge at {:.2} Hz",
            hz(low),
            hz(report.options.from)
        );
    }
    let (lowest, from) = (branch.speed_span().0, report.options.from);
    if lowest < from {
        let _ = writeln!(
            text,
            "  followed out of the range down to {:.2} Hz: the branch turns back below the first \
             speed, {:.2} Hz (its points there are kept and plotted)",
            hz(lowest),
            hz(from)
        );
    }
    for (a, b) in &branch.jumps {
        let _ = writeln!(
            text,
            "  jumped from {:.2} to {:.2} Hz: the path could not go on there (a stall, a walk back \
             or a corner) and was restarted ahead; not followed between",
            hz(*a),
            hz(*b)
        );
    }
    if !branch.folds_without_crossing.is_empty() {
        let speeds: Vec<String> = branch
            .folds_without_crossing
            .iter()
            .map(|w| format!("{:.2}", hz(*w)))
            .collect();
        let _ = writeln!(
            text,
            "  warning: at {} of {} folds ({} Hz) no Floquet multiplier crosses +1: the \
             stability contradicts the balance there (too few harmonics, or a fold at a \
             contact's edge; docs/theory.md section 7)",
            speeds.len(),
            branch.folds.len(),
            speeds.join(", ")
        );
    }
    if let Some(check) = branch.bifurcations.iter().find_map(|b| b.resolution) {
        let _ = writeln!(
            text,
            "  bifurcations checked at {} samples per period and {} stability modes, {} % of the \
             speed either side: + resolved (the same change), ? not resolved (docs/theory.md \
             section 7)",
            check.samples,
            2 * report.options.stability_modes,
            100.0 * RESOLUTION_TOLERANCE
        );
    }
    for b in &branch.bifurcations {
        let mark = match b.resolution.map(|r| r.resolved) {
            Some(true) => "+ ",
            Some(false) => "? ",
            None => "",
        };
        let _ = writeln!(
            text,
            "  {mark}{} at {:.2} Hz: stability {}, exponent at {:.2} Hz",
            b.kind.name(),
            hz(b.frequency),
            if b.loses_stability {
                "lost"
            } else {
                "regained"
            },
            hz(b.exponent_frequency)
        );
    }
    for c in &report.comparisons {
        let (all, _) = report.solutions_at(c.speed);
        if all.is_empty() {
            let _ = writeln!(
                text,
                "  {:.1} Hz, node {}: the branch has no solution at this speed; time marching 1X uy {:.4e} m",
                hz(c.speed),
                c.node,
                c.uy[0]
            );
        }
        for a in &all {
            let hb = report.hb_1x_uy(a, c);
            let _ = writeln!(
                text,
                "  {:.1} Hz, node {}: 1X uy harmonic balance {:.4e} m ({}, after point {}), time marching {:.4e} m ({:+.2} %)",
                hz(c.speed),
                c.node,
                hb,
                if a.stability.stable { "stable" } else { "unstable" },
                a.after,
                c.uy[0],
                100.0 * (hb - c.uy[0]) / c.uy[0]
            );
            if let Some(note) = whirl::hbm::report::unstable_note(a, c) {
                let _ = writeln!(text, "    {note}");
            }
        }
    }
    text
}
