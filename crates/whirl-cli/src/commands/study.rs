//! `whirl study study.toml [--out DIR] [--checkpoint DIR] [--restart]`: sensitivity of the
//! non-synchronous vibration to model parameters, each point a cascade (thesis ch. 5,
//! figs. 5.1-5.10, table 5.1). The study file is described in `docs/study-file.md`.
//!
//! Every finished point is saved at once in the checkpoint folder (default `<out>.points`,
//! beside the output folder); running the same study again computes only the points not
//! yet there, and a point interrupted half-way continues from its finished speeds. A
//! checkpoint folder of a different study (the study file or the model changed) is refused.
//!
//! Writes `points.csv` (one row per distinct point: its changes and NSV summary),
//! `sweeps.csv` (one row per sweep and value), `fits.csv` (eq. 5.1 coefficients and R^2),
//! `ranking.csv` (sweeps by their effect on the largest NSV), `ranking_by_parameter.csv`
//! (each parameter by the largest effect among its sweeps), the plots `cascades_<i>` (the
//! cascades of sweep i side by side, one colour scale), `largest_nsv_<i>` (largest NSV
//! versus the parameter, with the fit when asked for, fig. 5.10), and `summary.json`.

use std::fmt::Write;
use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::time::Instant;

use serde_json::Value;
use whirl::report::Report;
use whirl::study::ranking::Effect;
use whirl::study::report::StudyReport;
use whirl::study::results::{analyse, run_points, PointOutcome, PointResult, Source, StudyResults};
use whirl::study::store::Store;
use whirl::study::{point, Point, Study};

use super::{finish_json, lib, Outcome};
use crate::error::{from_whirl, Diag};
use crate::interrupt;
use crate::output::Output;
use crate::progress::{duration_text, progress_line};

/// `whirl study`
#[derive(Debug, clap::Args)]
pub struct Args {
    /// The study file (TOML), e.g. examples/thesis_chapter5_study.toml.
    #[arg(value_name = "STUDY")]
    pub study: PathBuf,
    /// Output folder [default: out/study]. Replaced as a whole when the study finishes.
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
    /// Folder of finished points, kept between runs [default: the output folder's path
    /// with `.points` added].
    #[arg(long, value_name = "DIR")]
    pub checkpoint: Option<PathBuf>,
    /// Discard the points of the checkpoint folder and start again.
    #[arg(long)]
    pub restart: bool,
    /// Print summary.json to stdout instead of the text summary.
    #[arg(long)]
    pub json: bool,
}

impl Args {
    /// The output folder.
    pub fn out_dir(&self) -> PathBuf {
        super::out_or_default(&self.out, "study")
    }
}

/// Runs the study.
pub fn run(args: &Args) -> miette::Result<Outcome> {
    let study = load_study(&args.study)?;
    let out_dir = args.out_dir();
    let checkpoint = args.checkpoint.clone().unwrap_or_else(|| {
        let mut name = out_dir.clone().into_os_string();
        name.push(".points");
        PathBuf::from(name)
    });
    let store = Store::open(&checkpoint, &study.fingerprint, &args.study, args.restart)
        .map_err(|e| from_whirl(e, ""))?;
    let start = Instant::now();
    warn_if_long(&study);
    interrupt::stoppable();
    let results = run_points(
        &study,
        &store,
        |p| compute_point(p, &store),
        |k, p, source, r| tell(k, study.points.len(), p, source, r),
    );
    // A point stopped by Ctrl-C ends the run with its own "interrupted": say instead what
    // was kept and how to go on.
    if interrupt::requested() {
        return Err(Diag::new(format!(
            "the study was stopped; its finished points are kept in `{}`",
            store.dir().display()
        ))
        .help("run the same command again to continue")
        .into());
    }
    let results = lib(results)?;
    check_failures(&study, &results)?;
    let outcome = analyse(&study, &results);
    let report = StudyReport {
        study,
        results,
        outcome,
    };
    let (study, outcome) = (&report.study, &report.outcome);
    let mut out = Output::begin(&out_dir)?;
    for table in report.tables() {
        out.table(&table)?;
    }
    // The study's figures show no speeds on an axis: nothing for --rpm to rewrite.
    out.figures(whirl_figures::study(&report), false)?;
    let summary = summary(args, &report, &store, start)?;
    let text = text(study, outcome, &store);
    finish_json(out, summary, text, args.json)
}

/// A study in which every point failed is a failure (exit status 1, nothing written); some
/// failed points are listed on stderr (and in summary.json).
fn check_failures(study: &Study, results: &[PointOutcome]) -> miette::Result<()> {
    let failed: Vec<(&Point, &String)> = study
        .points
        .iter()
        .zip(results)
        .filter_map(|(p, r)| r.as_ref().err().map(|e| (p, e)))
        .collect();
    let Some((point, first)) = failed.first() else {
        return Ok(());
    };
    if failed.len() == results.len() {
        return Err(Diag::new(format!(
            "every one of the {} points failed; {}: {first}",
            results.len(),
            point.label()
        ))
        .into());
    }
    eprintln!(
        "warning: {} of {} points failed and are left out of fits and ranking: {}",
        failed.len(),
        results.len(),
        failed
            .iter()
            .map(|(p, _)| p.label())
            .collect::<Vec<_>>()
            .join("; ")
    );
    Ok(())
}

/// Reads and validates the study file; errors show the line of the file at fault.
fn load_study(path: &Path) -> miette::Result<Study> {
    let text = whirl::model::read_input(path).map_err(|e| {
        Diag::new(format!(
            "cannot read the study file `{}`: {e}",
            path.display()
        ))
        .help("check the path; examples/thesis_chapter5_study.toml is a complete study")
    })?;
    Study::from_toml_str(&text, path).map_err(|e| {
        // An error of the base model is located in the model file: show that file's line.
        let file = match &e {
            whirl::Error::Input(i) => i.file.clone(),
            _ => None,
        };
        let source = match file {
            Some(f) if f != path => whirl::model::read_input(&f).unwrap_or_default(),
            _ => text.clone(),
        };
        from_whirl(e, &source)
    })
}

/// Warns before starting when the points' time step makes the study hours long, as
/// `whirl cascade --step` does for one cascade (points whose settings are bad are left to
/// fail with their own error).
fn warn_if_long(study: &Study) {
    let seconds: f64 = study
        .points
        .iter()
        .filter_map(|p| point::cascade_options(p).ok())
        .filter_map(|o| super::cascade::least_seconds(&o))
        .map(|(_, seconds)| seconds)
        .sum();
    if seconds > super::cascade::LONG_RUN_S {
        eprintln!(
            "warning: the [cascade] step makes the {} points at least {} of computing on {} \
             cores; leave `step` out for 0.9 times the stable step, or press Ctrl-C to stop \
             (finished points are kept)",
            study.points.len(),
            duration_text(seconds),
            super::cascade::cores()
        );
    }
}

/// One point's cascade, resuming from its own folder of finished speeds.
fn compute_point(p: &Point, store: &Store) -> whirl::Result<PointResult> {
    let partial = p.partial_dir(store.dir());
    // The speeds of the point running (as `whirl cascade` shows them); Ctrl-C stops the
    // point between speeds, its finished speeds kept.
    let (progress, line) = progress_line("cascade".into());
    let result = point::compute(p, Some(&partial), Some(&progress));
    line.clear();
    // The point is saved whole by the caller; its speeds stay until the study ends, for a
    // point that shares its cascade.
    result
}

/// A line on stderr per point, as it becomes available.
fn tell(k: usize, total: usize, p: &Point, source: Source, outcome: &PointOutcome) {
    let what = match (outcome, source) {
        (Ok(r), Source::Computed) if r.resumed_speeds == r.map.speeds_hz.len() => {
            format!(
                "largest NSV {:.3e} m (its cascade shared with another point)",
                r.nsv.largest
            )
        }
        (Ok(r), Source::Computed) => {
            format!(
                "largest NSV {:.3e} m ({:.1} s)",
                r.nsv.largest, r.wall_time_s
            )
        }
        (Ok(r), Source::Resumed) => {
            format!("largest NSV {:.3e} m (from the checkpoint)", r.nsv.largest)
        }
        (Err(e), _) => format!("FAILED, left out: {e}"),
    };
    // On a terminal, clear the progress line this replaces.
    let clear = if std::io::stderr().is_terminal() {
        "\r\x1b[2K"
    } else {
        ""
    };
    eprintln!("{clear}[{}/{total}] {}: {what}", k + 1, p.label());
}

/// summary.json: the run's head (command, study file, checkpoint, wall time) and the
/// study's report.
fn summary(
    args: &Args,
    report: &StudyReport,
    store: &Store,
    start: Instant,
) -> miette::Result<Value> {
    let mut s = match serde_json::to_value(report.summary()) {
        Ok(Value::Object(keys)) => keys,
        _ => return Err(Diag::new("cannot encode the summary").into()),
    };
    for (key, value) in [
        ("command", Value::from("study")),
        ("whirl_version", env!("CARGO_PKG_VERSION").into()),
        ("study_file", args.study.display().to_string().into()),
        ("checkpoint", store.dir().display().to_string().into()),
        ("wall_time_s", start.elapsed().as_secs_f64().into()),
    ] {
        s.insert(key.into(), value);
    }
    Ok(Value::Object(s))
}

fn text(study: &Study, outcome: &StudyResults, store: &Store) -> String {
    let mut t = String::new();
    let _ = writeln!(
        t,
        "{}: {} sweeps, {} distinct points (checkpoint {})",
        study.title,
        study.sweeps.len(),
        study.points.len(),
        store.dir().display()
    );
    for s in &outcome.sweeps {
        let _ = writeln!(t, "{}:", s.name);
        for (j, v) in s.values.iter().enumerate() {
            let onset = s.onset_speed_hz[j].map_or("none".into(), |f| format!("{f:.0} Hz"));
            let _ = match (s.metric_nsv[j], s.largest_nsv[j]) {
                (Some(m), Some(a)) => writeln!(
                    t,
                    "  {v:>12}  {} {m:.3e} m, largest NSV {a:.3e} m, onset {onset}",
                    study.metric.name()
                ),
                _ => writeln!(t, "  {v:>12}  FAILED (see points.csv)"),
            };
        }
        if let Some(e) = &s.fit_error {
            let _ = writeln!(t, "  no fit: {e}");
        }
        if let Some(f) = &s.fit {
            let c: Vec<String> = f.coefficients.iter().map(|c| format!("{c:.4e}")).collect();
            let _ = writeln!(
                t,
                "  fit (highest power first): {}, R^2 = {:.4}",
                c.join(", "),
                f.r_squared
            );
        }
    }
    let _ = writeln!(
        t,
        "effect on the {}, (max - min) / min over each sweep:",
        study.metric.describe()
    );
    for (k, e) in outcome.ranking.iter().enumerate() {
        let _ = writeln!(
            t,
            "  {}. {} ({}): {}",
            k + 1,
            e.sweep,
            e.parameter,
            change(e)
        );
    }
    let _ = writeln!(t, "by parameter (the largest effect among its sweeps):");
    for (k, e) in outcome.ranking_by_parameter.iter().enumerate() {
        let _ = writeln!(
            t,
            "  {}. {}: {} ({})",
            k + 1,
            e.parameter,
            change(e),
            e.sweep
        );
    }
    t
}

/// A relative change for a person.
fn change(e: &Effect) -> String {
    e.relative_change
        .map_or("unbounded (no NSV at some value)".into(), |c| {
            format!("{c:.2}")
        })
}
