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

use std::fmt::Write;

use whirl::bearing::ContactLaw;
use whirl::given::{Choice, Given};
use whirl::hbm::{
    sweep_with_progress, CageKind, CageModel, HbmRequest, Sweep, SweepOptions, SweepReport,
    SweepSettings, DEFAULT_CAGE_POSITIONS, DEFAULT_CONTACT, DEFAULT_CONTACT_SMOOTHING,
    DEFAULT_HARMONICS, DEFAULT_LOW_SPEED, DEFAULT_STABILITY_MODES, MAX_HARMONICS,
    RESOLUTION_TOLERANCE,
};
use whirl::model::Model;
use whirl::nsv::{DEFAULT_RECORD, DEFAULT_SETTLE};

use super::{
    announce, default_is, finish, given, hz, lib, load, mode_count, option_error, report_summary,
    seconds, speed, speeds, time, Common, Nodes, Outcome, Speeds,
};
use crate::error::Diag;
use crate::output::Output;
use crate::progress::{duration_text, shown};
use whirl::report::Report;

/// The discretisation and bearing model of a harmonic-balance sweep, shared by `whirl hbm`
/// and `whirl map`, each left out at the library's default; [`HbFlags::settings`] hands
/// them to the library.
#[derive(Debug, clap::Args)]
pub struct HbFlags {
    #[arg(long, value_name = "H", value_parser = harmonic_count,
          help = default_is("Harmonics H of the running speed (1 to 50).", DEFAULT_HARMONICS))]
    pub harmonics: Option<usize>,
    #[arg(long, value_enum,
          help = default_is("Contact law of the roller bearings: hertz or forcing (harmonic balance needs a \
                             force law of the displacement).", DEFAULT_CONTACT.choice_name()))]
    pub contact: Option<ContactLaw>,
    #[arg(long, value_enum,
          help = default_is("How the roller passage is made periodic (Hertz only).", CageModel::DEFAULT.kind().choice_name()))]
    pub cage: Option<CageKind>,
    #[arg(long, value_name = "N", value_parser = mode_count,
          help = default_is("Cage positions per roller pitch of the passage average.", DEFAULT_CAGE_POSITIONS))]
    pub cage_positions: Option<usize>,
    #[arg(long, value_name = "LENGTH", value_parser = smoothing_length,
          help = default_is("Approach below which the Hertz law is blended to bounded curvature (harmonic \
                             balance only; docs/theory.md section 7), e.g. `0.01um`; 0 for the exact law.",
                            DEFAULT_CONTACT_SMOOTHING))]
    pub contact_smoothing: Option<f64>,
    /// Time samples per period of the alternating frequency-time transform [default: 32 H,
    /// at least 64].
    #[arg(long, value_name = "N")]
    pub samples: Option<usize>,
    /// Solve on a Craig-Bampton model with N fixed-interface modes, as the time integrators
    /// do (faster; the condensation stays exact) [default: the full model].
    #[arg(long, value_name = "N", value_parser = mode_count)]
    pub reduce: Option<usize>,
    #[arg(long, value_name = "N", value_parser = mode_count,
          help = default_is("Fixed-interface modes of the stability model.", DEFAULT_STABILITY_MODES))]
    pub stability_modes: Option<usize>,
}

impl HbFlags {
    /// The library's request of a run with these flags, every other option left out.
    pub fn request(&self) -> HbmRequest {
        HbmRequest {
            settings: SweepSettings {
                harmonics: self.harmonics,
                samples: self.samples,
                contact: self.contact,
                cage: None,
                contact_smoothing: self.contact_smoothing,
                stability: None,
                stability_modes: self.stability_modes,
                reduction: self.reduce,
            },
            cage: self.cage,
            cage_positions: self.cage_positions,
            ..HbmRequest::default()
        }
    }

    /// The library's settings of a sweep with these flags.
    pub fn settings(&self) -> SweepSettings {
        self.request().sweep_settings()
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
    #[arg(long, value_name = "TIME", value_parser = time,
          help = default_is("Settling time of the comparison runs.", seconds(DEFAULT_SETTLE)))]
    pub settle: Option<f64>,
    #[arg(long, value_name = "TIME", value_parser = time,
          help = default_is("Recorded (analysed) time of the comparison runs.", seconds(DEFAULT_RECORD)))]
    pub record: Option<f64>,
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
    given(text, Given::length_or_zero)
}

/// Harmonic counts of a study.
#[derive(Debug, Clone)]
pub struct HarmonicList(pub Vec<usize>);

/// Clap parser of a harmonic count, 1 to [`MAX_HARMONICS`].
fn harmonic_count(text: &str) -> Result<usize, String> {
    Given::Text(text.into())
        .whole("", 1, MAX_HARMONICS)
        .map_err(|e| e.message)
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
    Given::Text(text.into())
        .wholes("", 1, MAX_HARMONICS)
        .map(HarmonicList)
        .map_err(|e| e.message)
}

/// The library's request from the command line: every option left out stays `None`.
fn request(args: &Args) -> HbmRequest {
    let mut request = HbmRequest {
        speeds: args.speeds.as_ref().map(|s| (s.0[0], s.0[s.0.len() - 1])),
        nodes: (!args.nodes.is_default()).then(|| args.nodes.nodes.clone()),
        compare_time: args.compare_time.clone(),
        settle: args.settle,
        record: args.record,
        harmonics_study: args
            .harmonics_study
            .as_ref()
            .map_or_else(Vec::new, |l| l.0.clone()),
        ..args.hb.request()
    };
    request.settings.stability = args.no_stability.then_some(false);
    request
}

pub fn run(args: &Args) -> miette::Result<Outcome> {
    let loaded = load(&args.common.model)?;
    let model = &loaded.model;
    let request = request(args);
    // Checked, and the default range told, before the first sweep starts.
    let options = request
        .sweep_options(model, request.settings.harmonics())
        .map_err(option_error)?;
    if args.speeds.is_none() {
        announce(None, "speeds", &[options.from, options.to]);
    }
    warn_if_slow(request.most_harmonics(), options.stability);
    let report = lib(request.run(model, &mut |o| sweep_shown(model, o)))?;
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

/// The first and last speed of `--speeds` (rad/s), or the model's default range: a rising
/// range of positive speeds, as harmonic balance needs.
pub fn rising_range(speeds: &Option<Speeds>, model: &Model) -> miette::Result<(f64, f64)> {
    let range = Speeds::or_default(speeds, || model.default_speeds(DEFAULT_LOW_SPEED, 2));
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
