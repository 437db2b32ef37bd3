//! `whirl modal model.toml [--speed S] [--modes N]`: undamped modes and damped whirl modes.
//!
//! Writes `undamped_modes.csv` (mode, frequency), `undamped_shapes.csv` (mass-normalised
//! shapes, phi^T M phi = 1, one row per mode and node), `damped_modes.csv` (damped and
//! natural frequency, damping ratio, log decrement, whirl direction at speed S),
//! `damped_shapes.csv` (amplitude and phase of ux, uy and the forward/backward orbit radii
//! per node, largest translation 1), and the plots `mode_shapes` and `damped_orbits`.
//!
//! At zero speed an isotropic rotor's forward and backward modes coincide and their shapes
//! are any mix of the two; as in the Campbell diagram, a speed below 1e-3 rad/s is solved
//! at 1e-3 rad/s, where they separate (frequency change below 1e-8 relative).

use std::fmt::Write;

use serde::Serialize;
use whirl::fe::{assemble_banded, dof, Bearings, Direction};
use whirl::modal::{undamped_modes, ComplexMode, ModalBasis, UndampedModes, Whirl};
use whirl::model::Model;

use super::{
    finish, hz, lib, load, mode_count, speed, whirl_labels, Common, Head, Loaded, Outcome,
};
use crate::output::{header, num, Output};
use crate::plots;

/// Roots more damped than this are left out (overdamped or spurious, docs/theory.md section 3).
const MAX_DAMPING_RATIO: f64 = 0.9;

/// Smallest speed solved, rad/s (see the module doc).
const SPEED_FLOOR: f64 = 1e-3;

/// `whirl modal`
#[derive(Debug, clap::Args)]
pub struct Args {
    #[command(flatten)]
    pub common: Common,
    /// Spin speed of the damped modes: `3000rpm`, `50Hz`, or a plain number in rad/s.
    #[arg(long, value_name = "SPEED", default_value = "0", value_parser = speed)]
    pub speed: f64,
    /// Number of modes (undamped and damped).
    #[arg(long, value_name = "N", default_value = "6", value_parser = mode_count)]
    pub modes: usize,
}

/// The modes `whirl modal` reports.
struct Modes {
    undamped: UndampedModes,
    damped: Vec<ComplexMode>,
    /// `1F`, `1B`, ... of the damped modes.
    labels: Vec<String>,
}

/// summary.json of `whirl modal`.
#[derive(Serialize)]
struct Summary<'a> {
    #[serde(flatten)]
    head: Head,
    speed_hz: f64,
    speed_rpm: f64,
    undamped_frequencies_hz: &'a [f64],
    damped_modes: Vec<DampedSummary<'a>>,
    notes: [&'static str; 3],
}

/// One damped mode in summary.json.
#[derive(Serialize)]
struct DampedSummary<'a> {
    label: &'a str,
    damped_frequency_hz: f64,
    natural_frequency_hz: f64,
    damping_ratio: f64,
    log_decrement: f64,
    whirl: Whirl,
}

pub fn run(args: &Args) -> miette::Result<Outcome> {
    let loaded = load(&args.common.model)?;
    let modes = solve(&loaded.model, args)?;
    let mut out = Output::begin(&args.common.out_dir("modal"))?;
    write_tables(&mut out, &loaded.model, &modes)?;
    write_plots(&mut out, &loaded.model, &modes, args.speed)?;
    let text = text(&loaded.model, &modes, args.speed);
    finish(
        out,
        summary(&loaded, &modes, args.speed),
        text,
        &args.common,
    )
}

/// The undamped modes and the damped modes at the speed (see the module doc).
fn solve(model: &Model, args: &Args) -> miette::Result<Modes> {
    let system = assemble_banded(model, Bearings::Linearised);
    let undamped = lib(undamped_modes(&system, args.modes))?;
    let basis = lib(ModalBasis::for_modes(&system, args.modes))?;
    let damped = lib(basis.modes_at(args.speed.max(SPEED_FLOOR), MAX_DAMPING_RATIO, args.modes))?;
    let labels = whirl_labels(&damped.iter().map(|m| m.whirl).collect::<Vec<_>>());
    Ok(Modes {
        undamped,
        damped,
        labels,
    })
}

fn summary<'a>(loaded: &Loaded, modes: &'a Modes, speed: f64) -> Summary<'a> {
    Summary {
        head: Head::new("modal", loaded),
        speed_hz: hz(speed),
        speed_rpm: 60.0 * hz(speed),
        undamped_frequencies_hz: &modes.undamped.frequencies_hz,
        damped_modes: modes
            .damped
            .iter()
            .zip(&modes.labels)
            .map(|(m, label)| DampedSummary {
                label,
                damped_frequency_hz: m.damped_frequency_hz,
                natural_frequency_hz: m.natural_frequency_hz,
                damping_ratio: m.damping_ratio,
                log_decrement: m.log_decrement,
                whirl: m.whirl,
            })
            .collect(),
        notes: [
            "undamped shapes are mass-normalised (phi^T M phi = 1)",
            "damped shapes are scaled so that the largest translation is 1",
            "roots with damping ratio above 0.9 are left out",
        ],
    }
}

/// The lines printed without `--json`.
fn text(model: &Model, modes: &Modes, speed: f64) -> String {
    let mut text = String::new();
    let list: Vec<String> = modes
        .undamped
        .frequencies_hz
        .iter()
        .map(|x| format!("{x:.2}"))
        .collect();
    let _ = writeln!(
        text,
        "{}: undamped frequencies [Hz]: {}",
        model.name,
        list.join(", ")
    );
    let _ = writeln!(
        text,
        "damped modes at {:.2} Hz ({:.0} rpm):",
        hz(speed),
        60.0 * hz(speed)
    );
    for (m, l) in modes.damped.iter().zip(&modes.labels) {
        let _ = writeln!(
            text,
            "  {l:>3}  {:9.3} Hz  zeta {:.4}  log dec {:.4}  {}",
            m.damped_frequency_hz,
            m.damping_ratio,
            m.log_decrement,
            m.whirl.name()
        );
    }
    text
}

/// The four tables of the module doc.
fn write_tables(out: &mut Output, model: &Model, modes: &Modes) -> miette::Result<()> {
    let z = model.node_positions();
    write_undamped(out, &z, &modes.undamped)?;
    write_damped(out, &z, &modes.damped, &modes.labels)
}

/// `undamped_modes.csv` and `undamped_shapes.csv`.
fn write_undamped(out: &mut Output, z: &[f64], undamped: &UndampedModes) -> miette::Result<()> {
    let f = &undamped.frequencies_hz;
    let rows: Vec<Vec<String>> = f
        .iter()
        .enumerate()
        .map(|(i, x)| vec![(i + 1).to_string(), num(*x)])
        .collect();
    out.csv(
        "undamped_modes.csv",
        &header(&["mode", "frequency_hz"]),
        &rows,
    )?;
    let mut rows = Vec::new();
    for (j, fj) in f.iter().enumerate() {
        for (n, zn) in z.iter().enumerate() {
            let mut row = vec![(j + 1).to_string(), num(*fj), n.to_string(), num(*zn)];
            row.extend(
                Direction::ALL
                    .iter()
                    .map(|&d| num(undamped.shapes[(dof(n, d), j)])),
            );
            rows.push(row);
        }
    }
    let h = header(&[
        "mode",
        "frequency_hz",
        "node",
        "z_m",
        "ux",
        "uy",
        "tx",
        "ty",
    ]);
    out.csv("undamped_shapes.csv", &h, &rows)
}

/// `damped_modes.csv` and `damped_shapes.csv`.
fn write_damped(
    out: &mut Output,
    z: &[f64],
    damped: &[ComplexMode],
    labels: &[String],
) -> miette::Result<()> {
    let rows: Vec<Vec<String>> = damped
        .iter()
        .zip(labels)
        .enumerate()
        .map(|(i, (m, l))| {
            vec![
                (i + 1).to_string(),
                l.clone(),
                num(m.damped_frequency_hz),
                num(m.natural_frequency_hz),
                num(m.damping_ratio),
                num(m.log_decrement),
                m.whirl.name().to_string(),
                num(m.eigenvalue.0),
                num(m.eigenvalue.1),
            ]
        })
        .collect();
    let h = header(&[
        "mode",
        "label",
        "damped_frequency_hz",
        "natural_frequency_hz",
        "damping_ratio",
        "log_decrement",
        "whirl",
        "eigenvalue_real_per_s",
        "eigenvalue_imag_rad_per_s",
    ]);
    out.csv("damped_modes.csv", &h, &rows)?;
    let mut rows = Vec::new();
    for (i, (m, l)) in damped.iter().zip(labels).enumerate() {
        for (n, zn) in z.iter().enumerate() {
            let (a, b) = (
                m.shape[dof(n, Direction::Ux)],
                m.shape[dof(n, Direction::Uy)],
            );
            let (rf, rb) = m.orbit_radii(n);
            rows.push(vec![
                (i + 1).to_string(),
                l.clone(),
                n.to_string(),
                num(*zn),
                num(a.norm()),
                num(a.arg().to_degrees()),
                num(b.norm()),
                num(b.arg().to_degrees()),
                num(rf),
                num(rb),
            ]);
        }
    }
    let h = header(&[
        "mode",
        "label",
        "node",
        "z_m",
        "ux_amplitude",
        "ux_phase_deg",
        "uy_amplitude",
        "uy_phase_deg",
        "forward_radius",
        "backward_radius",
    ]);
    out.csv("damped_shapes.csv", &h, &rows)
}

fn write_plots(out: &mut Output, model: &Model, modes: &Modes, speed: f64) -> miette::Result<()> {
    out.plot("mode_shapes", |stem| {
        plots::mode_shapes(model, &modes.undamped).save(stem)
    })?;
    out.plot("damped_orbits", |stem| {
        plots::damped_orbits(model, &modes.damped, &modes.labels, hz(speed)).save(stem)
    })
}
