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

use whirl::fe::{assemble_banded, dof, Bearings, Direction};
use whirl::model::Model;
use whirl::report::Report;
use whirl::response::{default_frequencies, frf_refined, FrfReport};
use whirl::units::{parse_quantity, Dimension};

use super::{
    finish, hz, lib, load, report_summary, round_off_note, speed, speeds, Common, Outcome, Speeds,
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
    #[arg(long, value_name = "NODE:DIR", value_parser = dof_spec)]
    pub input: DofSpec,
    /// Where the response is read, comma-separated `NODE:DIR` [default: the input DOF].
    #[arg(long, value_name = "LIST", value_delimiter = ',', value_parser = dof_spec)]
    pub output: Vec<DofSpec>,
    /// Spin speed, e.g. `3000rpm`, `50Hz`; a plain number is rad/s.
    #[arg(long, value_name = "SPEED", value_parser = speed, default_value = "0")]
    pub speed: f64,
    /// Excitation frequencies `start:stop:count`, e.g. `0:500Hz:1001`; plain numbers are
    /// rad/s [default: 1001 from 0 to 1.5 x the sixth undamped natural frequency].
    #[arg(long, value_name = "RANGE", value_parser = speeds)]
    pub frequencies: Option<Speeds>,
    /// Amplitude of the harmonic force, N (`100`, `2kN`), for the response columns.
    #[arg(long, value_name = "FORCE", value_parser = force, default_value = "1")]
    pub force: f64,
}

/// A DOF as `NODE:DIR`.
#[derive(Debug, Clone, Copy)]
pub struct DofSpec {
    /// Node index.
    pub node: usize,
    /// Direction.
    pub direction: Direction,
}

/// Clap parser of `NODE:DIR`.
fn dof_spec(text: &str) -> Result<DofSpec, String> {
    let (node, dir) = text
        .split_once(':')
        .ok_or_else(|| format!("`{text}`: expected NODE:DIR, e.g. 10:uy"))?;
    let node = node
        .trim()
        .parse::<usize>()
        .map_err(|_| format!("`{text}`: `{node}` is not a node number (0, 1, 2, ...)"))?;
    let direction = Direction::ALL
        .into_iter()
        .find(|d| d.name() == dir.trim())
        .ok_or_else(|| format!("`{text}`: the direction `{dir}` is not one of ux, uy, tx, ty"))?;
    Ok(DofSpec { node, direction })
}

/// Clap parser of a force: `100`, `2kN`; a plain number is N.
fn force(text: &str) -> Result<f64, String> {
    let f = parse_quantity(text, Dimension::Force).map_err(|e| e.to_string())?;
    if f <= 0.0 {
        return Err(format!("`{text}`: the force amplitude must be positive"));
    }
    Ok(f)
}

/// The frequencies asked for, or 1001 from 0 to 1.5 x the sixth undamped natural frequency
/// at rest (three forward-backward pairs of an isotropic rotor).
fn frequencies(args: &Args, model: &Model) -> miette::Result<Vec<f64>> {
    if let Some(f) = &args.frequencies {
        return Ok(f.0.clone());
    }
    let w = lib(default_frequencies(model))?;
    super::announce(None, "frequencies", &w);
    Ok(w)
}

fn global(model: &Model, option: &str, d: DofSpec) -> miette::Result<usize> {
    super::check_nodes(model, option, &[d.node])?;
    Ok(dof(d.node, d.direction))
}

pub fn run(args: &Args) -> miette::Result<Outcome> {
    let loaded = load(&args.common.model)?;
    let model = &loaded.model;
    let input = global(model, "--input", args.input)?;
    let outputs = if args.output.is_empty() {
        vec![input]
    } else {
        args.output
            .iter()
            .map(|&d| global(model, "--output", d))
            .collect::<miette::Result<Vec<_>>>()?
    };
    let w = frequencies(args, model)?;
    if w.is_empty() {
        return Err(Diag::option("--frequencies", "no frequencies to compute").into());
    }
    let system = assemble_banded(model, Bearings::Linearised);
    let result = lib(shown("frf", |p| {
        frf_refined(&system, args.speed, input, &outputs, &w, p)
    }))?;
    let (f0, f1) = (
        result.frequencies_hz[0],
        result.frequencies_hz[result.frequencies_hz.len() - 1],
    );

    let report = FrfReport {
        result,
        force: args.force,
    };
    let summary = report_summary("frf", &loaded, &report)?;
    let result = &report.result;

    let mut text = String::new();
    let _ = writeln!(
        text,
        "{}: FRF from {} at spin speed {:.3} Hz ({:.0} rpm), {} frequencies from {:.3} to {:.3} Hz",
        model.name,
        result.input.1,
        hz(args.speed),
        60.0 * hz(args.speed),
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
                p.amplitude * args.force,
                args.force
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
