//! `whirl modal model.toml [--speed S] [--modes N]`: undamped modes and damped whirl modes.
//!
//! Writes `undamped_modes.csv` (mode, frequency), `undamped_shapes.csv` (mass-normalised
//! shapes, phi^T M phi = 1, one row per mode and node), `damped_modes.csv` (damped and
//! natural frequency, damping ratio, log decrement, whirl direction at speed S),
//! `damped_shapes.csv` (amplitude and phase of ux, uy and the forward/backward orbit radii
//! per node, largest translation 1), and the plots `mode_shapes` and `damped_orbits`.
//!
//! A speed below 1e-3 rad/s is solved at 1e-3 rad/s ([`whirl::modal::modal_report`]).

use std::fmt::Write;

use whirl::modal::{modal_report, ModalReport, ModalRequest, DEFAULT_MODAL_MODES};
use whirl::model::Model;
use whirl::report::Report;

use super::{
    default_is, finish, hz, lib, load, option_error, report_summary, speed, Common, Outcome,
};
use crate::output::Output;
use crate::progress::shown;

/// `whirl modal`
#[derive(Debug, clap::Args)]
pub struct Args {
    #[command(flatten)]
    pub common: Common,
    /// Spin speed of the damped modes: `3000rpm`, `50Hz`, or a plain number in rad/s
    /// [default: 0, at rest].
    #[arg(long, value_name = "SPEED", value_parser = speed)]
    pub speed: Option<f64>,
    #[arg(long, value_name = "N",
          help = default_is("Number of modes, undamped and damped (1 to 200).", DEFAULT_MODAL_MODES))]
    pub modes: Option<usize>,
}

pub fn run(args: &Args) -> miette::Result<Outcome> {
    let loaded = load(&args.common.model)?;
    let request = ModalRequest {
        speed: args.speed,
        modes: args.modes,
    };
    let (speed, count) = request.resolved().map_err(|e| option_error(e.into()))?;
    let modes = lib(shown("modal", |p| {
        modal_report(&loaded.model, speed, count, p)
    }))?;
    let mut out = Output::begin(&args.common.out_dir("modal"))?;
    for table in modes.tables() {
        out.table(&table)?;
    }
    out.figures(whirl_figures::modal(&loaded.model, &modes), args.common.rpm)?;
    let text = text(&loaded.model, &modes, speed);
    let summary = report_summary("modal", &loaded, &modes)?;
    finish(out, summary, text, &args.common)
}

/// The lines printed without `--json`.
fn text(model: &Model, modes: &ModalReport, speed: f64) -> String {
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
