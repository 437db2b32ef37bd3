//! `whirl frf model.toml --input 10:ux [--output 10:ux,0:uy] [--speed 3000rpm]
//! [--frequencies 0:500Hz:1001] [--force 100]`: frequency response functions.
//!
//! A harmonic force at the input DOF, the rotor spinning at `--speed` (gyroscopic moments at
//! that speed; roller bearings by their linear stiffness, as the other linear analyses).
//! Writes `frf.csv` (per output DOF the receptance, mobility and accelerance as real part,
//! imaginary part, magnitude and phase, and the response amplitude to a force of `--force`
//! newtons), `peaks.csv` (resonance peaks of each receptance with half-power bands; a local
//! maximum within the receptance's round-off is no peak, and the summary lists it) and the
//! plots `receptance`, `mobility` and `accelerance` (magnitude, phase, real and imaginary
//! parts over frequency). Frequencies are added around each peak until its half-power band
//! holds 40 steps, so a lightly damped resonance's height and Q come out of samples
//! (`frf.csv` then holds more rows than `--frequencies` asked for).

use std::fmt::Write;

use whirl::fe::{assemble_banded, Bearings};
use whirl::given::Given;
use whirl::report::Report;
use whirl::response::{dof_spec, frf_refined, DofSpec, FrfReport, FrfRequest, DEFAULT_FRF_FORCE};

use super::{
    default_is, finish, given, hz, lib, load, option_error, report_summary, round_off_note, speed,
    speeds, Common, Outcome, Speeds,
};
use crate::error::Diag;
use crate::output::Output;
use crate::progress::shown;

/// `whirl frf`
#[derive(Debug, clap::Args)]
pub struct Args {
    #[command(flatten)]
    pub common: Common,
    /// Where the force acts: `NODE:DIR` with DIR one of ux, uy, tx, ty (e.g. `10:uy`).
    #[arg(long, value_name = "NODE:DIR", value_parser = dof)]
    pub input: DofSpec,
    /// Where the response is read, comma-separated `NODE:DIR` [default: the input DOF].
    #[arg(long, value_name = "LIST", value_delimiter = ',', value_parser = dof)]
    pub output: Vec<DofSpec>,
    /// Spin speed, e.g. `3000rpm`, `50Hz`; a plain number is rad/s [default: 0, at rest].
    #[arg(long, value_name = "SPEED", value_parser = speed)]
    pub speed: Option<f64>,
    /// Excitation frequencies `start:stop:count`, e.g. `0:500Hz:1001`; plain numbers are
    /// rad/s [default: 1001 from 0 to 1.5 x the sixth undamped natural frequency].
    #[arg(long, value_name = "RANGE", value_parser = speeds)]
    pub frequencies: Option<Speeds>,
    #[arg(long, value_name = "FORCE", value_parser = force,
          help = default_is("Amplitude of the harmonic force, N (`100`, `2kN`), for the response columns.", DEFAULT_FRF_FORCE))]
    pub force: Option<f64>,
}

/// Clap parser of `NODE:DIR`, as the library reads it.
fn dof(text: &str) -> Result<DofSpec, String> {
    dof_spec("", text).map_err(|e| e.message)
}

/// Clap parser of a force: `100`, `2kN`; a plain number is N.
fn force(text: &str) -> Result<f64, String> {
    given(text, Given::force)
}

pub fn run(args: &Args) -> miette::Result<Outcome> {
    let loaded = load(&args.common.model)?;
    let model = &loaded.model;
    let request = FrfRequest {
        input: Some(args.input),
        outputs: args.output.clone(),
        speed: args.speed,
        frequencies: args.frequencies.as_ref().map(|f| f.0.clone()),
        force: args.force,
    };
    let (input, outputs, speed, w, force) = request.resolved(model).map_err(option_error)?;
    if args.frequencies.is_none() {
        super::announce(None, "frequencies", &w);
    }
    if w.is_empty() {
        return Err(Diag::option("--frequencies", "no frequencies to compute").into());
    }
    let system = assemble_banded(model, Bearings::Linearised);
    let result = lib(shown("frf", |p| {
        frf_refined(&system, speed, input, &outputs, &w, p)
    }))?;
    let (f0, f1) = (
        result.frequencies_hz[0],
        result.frequencies_hz[result.frequencies_hz.len() - 1],
    );

    let report = FrfReport { result, force };
    let summary = report_summary("frf", &loaded, &report)?;
    let result = &report.result;

    let mut text = String::new();
    let _ = writeln!(
        text,
        "{}: FRF from {} at spin speed {:.3} Hz ({:.0} rpm), {} frequencies from {:.3} to {:.3} Hz",
        model.name,
        result.input.1,
        hz(speed),
        60.0 * hz(speed),
        w.len(),
        f0,
        f1
    );
    for o in &result.outputs {
        for p in &o.peaks {
            let af = p
                .amplification_factor
                .map_or("-".into(), |a| format!("{a:.1}"));
            let _ = writeln!(
                text,
                "  {}: peak {:.4e} m/N at {:.3} Hz (Q {af}), {:.4e} m under {} N",
                o.name,
                p.amplitude,
                p.speed_hz,
                p.amplitude * force,
                force
            );
        }
    }
    for o in &result.outputs {
        if let Some(note) = round_off_note(&o.maxima_within_round_off_hz) {
            let _ = writeln!(text, "  {}: {note}", o.name);
        }
    }

    let mut out = Output::begin(&args.common.out_dir("frf"))?;
    for table in report.tables() {
        out.table(&table)?;
    }
    out.figures(whirl_figures::frf(model, result), args.common.rpm)?;
    finish(out, summary, text, &args.common)
}
