//! `whirl fit-forcing model.toml --speeds 100Hz:500Hz:5 [--bearing 0] [--duration 0.3s]
//! [--settle 0.2s] [--reduce 12]`: the forcing function of a roller bearing (thesis eq.
//! 3.12) fitted to its Hertz response.
//!
//! At each speed the rotor runs on its Hertz bearings; the chosen bearing's deflection and
//! cage-averaged elastic contact force are sampled from the settled part, and
//! F = (a0 + a1 W) (u_r - gamma)^(b0 + b1 W) is fitted to all samples in log-log (see
//! [`whirl::time::forcing_fit`]). Writes `fit.csv` (every sample: speed, deflection,
//! force, fitted force), `forcing_function.toml` (the `forcing_function = { ... }` line to
//! paste into the bearing's `[[roller_bearing]]` block) and the plot `force_deflection`
//! (force over deflection beyond the clearance, log-log, samples and fit per speed).
//! summary.json holds the coefficients with their units and the fit quality per speed.

use std::fmt::Write;
use std::path::{Path, PathBuf};

use whirl::model::Model;
use whirl::report::Report;
use whirl::time::{
    fit_forcing, FitForcingRequest, ForcingFit, ForcingFitReport, DEFAULT_FIT_DURATION,
    DEFAULT_FIT_SETTLE, DEFAULT_MODES,
};

use crate::progress::shown;
use whirl_plot::PlotError;

use super::{
    default_is, finish, hz, lib, load, option_error, report_summary, seconds, speeds, time, Common,
    Outcome, Speeds,
};
use crate::error::Diag;
use crate::output::Output;

/// `whirl fit-forcing`
#[derive(Debug, clap::Args)]
pub struct Args {
    #[command(flatten)]
    pub common: Common,
    /// Spin speeds to fit at, `start:stop:count`, e.g. `100Hz:500Hz:5`; plain numbers are
    /// rad/s. The law is meant for speeds inside this range.
    #[arg(long, value_name = "RANGE", value_parser = speeds)]
    pub speeds: Speeds,
    /// The roller bearing to fit, numbered from 0 in file order [default: 0, the first].
    #[arg(long, value_name = "INDEX")]
    pub bearing: Option<usize>,
    #[arg(long, value_name = "TIME", value_parser = time,
          help = default_is("Simulated time per speed: `0.3s`, `300ms`, or a plain number in s.", seconds(DEFAULT_FIT_DURATION)))]
    pub duration: Option<f64>,
    #[arg(long, value_name = "TIME", value_parser = time,
          help = default_is("Time discarded before sampling.", seconds(DEFAULT_FIT_SETTLE)))]
    pub settle: Option<f64>,
    #[arg(long, value_name = "N",
          help = default_is("Craig-Bampton reduction keeping N fixed-interface modes (bearing nodes are the boundary).", DEFAULT_MODES))]
    pub reduce: Option<usize>,
}

pub fn run(args: &Args) -> miette::Result<Outcome> {
    let loaded = load(&args.common.model)?;
    let model = &loaded.model;
    let request = FitForcingRequest {
        speeds: Some(args.speeds.0.clone()),
        bearing: args.bearing,
        duration: args.duration,
        settle: args.settle,
        reduce: args.reduce,
    };
    let (speeds, bearing, options) = request.resolved().map_err(|e| option_error(e.into()))?;
    check_bearing(model, bearing)?;
    let fit = lib(shown("fit-forcing", |p| {
        fit_forcing(model, bearing, &speeds, &options, p)
    }))?;
    let report = ForcingFitReport::new(model, bearing, fit);
    let summary = report_summary("fit-forcing", &loaded, &report)?;
    let text = summary_text(model, &report.fit, report.warning.as_deref());
    let mut out = Output::begin(&args.common.out_dir("fit-forcing"))?;
    for table in report.tables() {
        out.table(&table)?;
    }
    let block = toml_block(&report.fit, &args.speeds.0);
    out.plot("forcing_function", |stem| write_text(stem, "toml", &block))?;
    out.figures(whirl_figures::fit_forcing(&report), args.common.rpm)?;
    finish(out, summary, text, &args.common)
}

fn check_bearing(model: &Model, index: usize) -> miette::Result<()> {
    let count = model.roller_bearings.len();
    if index < count {
        return Ok(());
    }
    let help = match count {
        0 => "the model has no [[roller_bearing]]; forcing functions replace roller bearings"
            .to_string(),
        n => format!("roller bearings are numbered 0 to {} in file order", n - 1),
    };
    Err(
        Diag::option("--bearing", format!("there is no roller bearing {index}"))
            .help(help)
            .into(),
    )
}

fn summary_text(model: &Model, fit: &ForcingFit, warning: Option<&str>) -> String {
    let mut text = String::new();
    let law = &fit.law;
    let _ = writeln!(
        text,
        "{}: forcing function of {} from {} samples at {} speeds",
        model.name,
        fit.bearing,
        fit.points.len(),
        fit.speeds.len()
    );
    let _ = writeln!(
        text,
        "  F = ({:.6e} {:+.6e} W) (u_r - gamma)^({:.6} {:+.6e} W)   [N, m, W in rad/s]",
        law.a0, law.a1, law.b0, law.b1
    );
    let _ = writeln!(
        text,
        "  R^2 {:.5}, rms relative force error {:.2} %",
        fit.r_squared,
        100.0 * fit.rms_relative_error
    );
    for s in &fit.speeds {
        let _ = writeln!(
            text,
            "  {:8.2} Hz: {:5} samples ({} out of contact), R^2 {:.4}, rms error {:.2} %",
            hz(s.speed),
            s.points,
            s.excluded,
            s.r_squared,
            100.0 * s.rms_relative_error
        );
    }
    if let Some(why) = warning {
        let _ = writeln!(text, "  warning: {why}");
    }
    text
}

/// The text of forcing_function.toml: comments saying where the law comes from, then the
/// line to paste. `{:?}` prints each f64 in full precision and always as a TOML float.
fn toml_block(fit: &ForcingFit, speeds: &[f64]) -> String {
    let (lo, hi) = speeds
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), &w| {
            (l.min(w), h.max(w))
        });
    let law = &fit.law;
    format!(
        "# Forcing function of {} (thesis eq. 3.12), fitted by `whirl fit-forcing` at \
         {:.2} to {:.2} Hz\n# (R^2 {:.5}). F [N] = (a0 + a1 W) (u_r - gamma)^(b0 + b1 W), u_r \
         in m, W in rad/s.\n# Paste into the bearing's [[roller_bearing]] block.\n\
         forcing_function = {{ a0 = {:?}, a1 = {:?}, b0 = {:?}, b1 = {:?} }}\n",
        fit.bearing,
        hz(lo),
        hz(hi),
        fit.r_squared,
        law.a0,
        law.a1,
        law.b0,
        law.b1
    )
}

/// Writes `text` to `stem.extension`. Goes through [`Output::plot`], which registers
/// whatever files its closure writes in the output folder.
fn write_text(stem: &Path, extension: &str, text: &str) -> Result<Vec<PathBuf>, PlotError> {
    let path = stem.with_extension(extension);
    std::fs::write(&path, text).map_err(|source| PlotError::Io {
        path: path.clone(),
        source,
    })?;
    Ok(vec![path])
}
