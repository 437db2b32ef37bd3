//! `whirl ucs model.toml [--stiffness 1e5:1e10:51] [--modes 4] [--at-rest]`: the undamped
//! critical-speed map (API 684).
//!
//! Every bearing (linear and roller) is given the same isotropic stiffness, swept
//! logarithmically, and the lowest critical speeds are found at each (synchronous forward
//! whirl with the gyroscopic moments of the spin; `--at-rest` leaves them out). Writes
//! `ucs.csv` (critical speeds per stiffness), `bearings.csv` (each bearing's own stiffness
//! and the critical speeds where it cuts the curves) and the plot `ucs`.

use std::fmt::Write;

use whirl::modal::{critical_speed_map, UcsRequest, DEFAULT_UCS_MODES};
use whirl::report::Report;

use super::{default_is, finish, lib, load, option_error, report_summary, Common, Outcome};
use crate::output::Output;
use crate::progress::shown;

/// `whirl ucs`
#[derive(Debug, clap::Args)]
pub struct Args {
    #[command(flatten)]
    pub common: Common,
    /// Bearing stiffnesses `start:stop:count` in N/m, spaced logarithmically, e.g.
    /// `1e5:1e10:51` [default: 61 values from 1/100 of the softest bearing's stiffness to
    /// 100 times the stiffest's, widened to whole decades].
    #[arg(long, value_name = "RANGE", value_parser = stiffness_range)]
    pub stiffness: Option<StiffnessRange>,
    #[arg(long, value_name = "N",
          help = default_is("Number of critical speeds (curves), 1 to 200.", DEFAULT_UCS_MODES))]
    pub modes: Option<usize>,
    /// Natural frequencies at rest instead of synchronous critical speeds (no gyroscopic
    /// moments), as some codes draw the map.
    #[arg(long)]
    pub at_rest: bool,
}

/// Stiffnesses in N/m, ascending.
#[derive(Debug, Clone)]
pub struct StiffnessRange(pub Vec<f64>);

/// Clap parser of `start:stop:count` stiffnesses (N/m), as the library reads them.
fn stiffness_range(text: &str) -> Result<StiffnessRange, String> {
    whirl::modal::stiffness_range(text)
        .map(StiffnessRange)
        .map_err(|e| e.message)
}

pub fn run(args: &Args) -> miette::Result<Outcome> {
    let loaded = load(&args.common.model)?;
    let model = &loaded.model;
    let request = UcsRequest {
        stiffness: args.stiffness.as_ref().map(|s| s.0.clone()),
        modes: args.modes,
        at_rest: args.at_rest,
    };
    let (stiffness, modes) = request
        .resolved(model)
        .map_err(|e| option_error(e.into()))?;
    let map = lib(shown("ucs", |p| {
        critical_speed_map(model, &stiffness, modes, !args.at_rest, p)
    }))?;
    let (k0, k1) = (stiffness[0], stiffness[stiffness.len() - 1]);

    let summary = report_summary("ucs", &loaded, &map)?;

    let mut text = String::new();
    let _ = writeln!(
        text,
        "{}: undamped critical-speed map, {} stiffnesses from {:.3e} to {:.3e} N/m, {} modes ({})",
        model.name,
        stiffness.len(),
        k0,
        k1,
        modes,
        if map.synchronous {
            "synchronous forward whirl"
        } else {
            "at rest"
        }
    );
    for b in &map.bearings {
        let speeds: Vec<String> = b
            .critical_speeds_hz
            .iter()
            .map(|c| c.map_or("-".into(), |v| format!("{v:.1}")))
            .collect();
        let _ = writeln!(
            text,
            "  {} ({:.3e} N/m): critical speeds {} Hz",
            b.label,
            b.stiffness,
            speeds.join(", ")
        );
    }

    let mut out = Output::begin(&args.common.out_dir("ucs"))?;
    for table in map.tables() {
        out.table(&table)?;
    }
    out.figures(whirl_figures::ucs(model, &map), args.common.rpm)?;
    finish(out, summary, text, &args.common)
}
