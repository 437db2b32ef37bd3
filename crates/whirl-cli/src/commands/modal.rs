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

use serde_json::{json, Value};
use whirl::fe::{assemble, dof, Bearings, Direction};
use whirl::modal::{undamped_modes, ModalBasis};

use super::{
    finish, hz, lib, load, mode_count, speed, summary_head, whirl_labels, Common, Outcome,
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

pub fn run(args: &Args) -> miette::Result<Outcome> {
    let loaded = load(&args.common.model)?;
    let model = &loaded.model;
    let system = assemble(model, Bearings::Linearised);
    let undamped = lib(undamped_modes(&system, args.modes))?;
    let basis = lib(ModalBasis::full(&system))?;
    let mut damped = lib(basis.modes_at(args.speed.max(SPEED_FLOOR), MAX_DAMPING_RATIO))?;
    damped.truncate(args.modes);
    let labels = whirl_labels(&damped.iter().map(|m| m.whirl).collect::<Vec<_>>());
    let z = model.node_positions();

    let mut s = summary_head("modal", &loaded);
    s.insert("speed_hz".into(), hz(args.speed).into());
    s.insert("speed_rpm".into(), (60.0 * hz(args.speed)).into());
    s.insert(
        "undamped_frequencies_hz".into(),
        json!(undamped.frequencies_hz),
    );
    s.insert(
        "damped_modes".into(),
        damped
            .iter()
            .zip(&labels)
            .map(|(m, l)| {
                json!({
                    "label": l, "damped_frequency_hz": m.damped_frequency_hz,
                    "natural_frequency_hz": m.natural_frequency_hz,
                    "damping_ratio": m.damping_ratio, "log_decrement": m.log_decrement,
                    "whirl": m.whirl.name(),
                })
            })
            .collect::<Vec<_>>()
            .into(),
    );
    s.insert(
        "notes".into(),
        json!([
            "undamped shapes are mass-normalised (phi^T M phi = 1)",
            "damped shapes are scaled so that the largest translation is 1",
            "roots with damping ratio above 0.9 are left out",
        ]),
    );

    let mut text = String::new();
    let list: Vec<String> = undamped
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
        hz(args.speed),
        60.0 * hz(args.speed)
    );
    for (m, l) in damped.iter().zip(&labels) {
        let _ = writeln!(
            text,
            "  {l:>3}  {:9.3} Hz  zeta {:.4}  log dec {:.4}  {}",
            m.damped_frequency_hz,
            m.damping_ratio,
            m.log_decrement,
            m.whirl.name()
        );
    }

    let mut out = Output::begin(&args.common.out_dir("modal"))?;
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
    out.csv("undamped_shapes.csv", &h, &rows)?;

    let rows: Vec<Vec<String>> = damped
        .iter()
        .zip(&labels)
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
    for (i, (m, l)) in damped.iter().zip(&labels).enumerate() {
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
    out.csv("damped_shapes.csv", &h, &rows)?;

    out.plot("mode_shapes", |stem| {
        plots::mode_shapes(model, &undamped).save(stem)
    })?;
    out.plot("damped_orbits", |stem| {
        plots::damped_orbits(model, &damped, &labels, hz(args.speed)).save(stem)
    })?;
    finish(out, Value::Object(s), text, &args.common)
}
