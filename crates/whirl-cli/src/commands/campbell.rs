//! `whirl campbell model.toml --speeds 0:800Hz:161 [--modes 8] [--orders 1,2,0.5] [--full]`
//!
//! Writes `campbell.csv` (one row per speed; per branch its damped frequency, damping
//! ratio, log decrement and whirl direction), `critical_speeds.csv` (crossings of the
//! branches with the excitation orders) and the plots `campbell` (branches, forward solid
//! and backward dashed, order lines, critical speeds) and `log_decrement`.
//!
//! Branches are named by whirl direction and rank at the highest speed: `1F` is the lowest
//! forward branch, `1B` the lowest backward one.

use std::fmt::Write;

use whirl::fe::{assemble_banded, Bearings};
use whirl::modal::{
    campbell, CampbellRequest, CampbellResult, DEFAULT_BRANCHES, DEFAULT_CAMPBELL_SPEEDS,
    DEFAULT_ORDER,
};
use whirl::model::Model;
use whirl::report::Report;

use super::{
    announce, default_is, finish, lib, load, option_error, report_summary, speeds, Common, Outcome,
    Speeds,
};
use crate::output::Output;
use crate::progress::shown;

/// `whirl campbell`
#[derive(Debug, clap::Args)]
pub struct Args {
    #[command(flatten)]
    pub common: Common,
    #[arg(long, value_name = "RANGE", value_parser = speeds,
          help = default_is("Spin speeds `start:stop:count`, e.g. `0:800Hz:161` or `0:48000rpm:161`; plain numbers are rad/s.",
              format_args!("{DEFAULT_CAMPBELL_SPEEDS} speeds from rest to 1.2 x the model's top operating speed")))]
    pub speeds: Option<Speeds>,
    #[arg(long, value_name = "N",
          help = default_is("Number of whirl branches to follow (1 to 200).", DEFAULT_BRANCHES))]
    pub modes: Option<usize>,
    #[arg(long, value_name = "LIST", value_delimiter = ',', allow_hyphen_values = true,
          help = default_is("Excitation orders whose crossings are critical speeds (1 = synchronous), \
                             each above 0 and at most 100.", DEFAULT_ORDER))]
    pub orders: Option<Vec<f64>>,
    /// Solve the full system at every speed instead of a basis of 2N + 8 undamped modes
    /// (slower; the basis keeps branches within 2e-4 of the full solve).
    #[arg(long)]
    pub full: bool,
}

pub fn run(args: &Args) -> miette::Result<Outcome> {
    let loaded = load(&args.common.model)?;
    let diagram = solve(&loaded.model, args)?;
    let mut out = Output::begin(&args.common.out_dir("campbell"))?;
    for table in diagram.tables() {
        out.table(&table)?;
    }
    out.figures(
        whirl_figures::campbell(&loaded.model, &diagram),
        args.common.rpm,
    )?;
    let text = text(&loaded.model, &diagram);
    let summary = report_summary("campbell", &loaded, &diagram)?;
    finish(out, summary, text, &args.common)
}

/// The Campbell diagram of the linearised model over the speeds asked for.
fn solve(model: &Model, args: &Args) -> miette::Result<CampbellResult> {
    let request = CampbellRequest {
        speeds: args.speeds.as_ref().map(|s| s.0.clone()),
        modes: args.modes,
        orders: args.orders.clone(),
        full: args.full,
    };
    let options = request.options(model).map_err(|e| option_error(e.into()))?;
    if args.speeds.is_none() {
        announce(None, "speeds", &options.speeds);
    }
    let system = assemble_banded(model, Bearings::Linearised);
    lib(shown("campbell", |p| campbell(&system, &options, p)))
}

/// The lines printed without `--json`.
fn text(model: &Model, result: &CampbellResult) -> String {
    let mut text = String::new();
    let _ = writeln!(
        text,
        "{}: {} branches over {} speeds (basis of {} modes)",
        model.name,
        result.branches.len(),
        result.speeds_hz.len(),
        result.basis_size
    );
    for (b, l) in result.branches.iter().zip(result.labels()) {
        let first = b.frequency_hz.first().copied().unwrap_or(f64::NAN);
        let last = b.frequency_hz.last().copied().unwrap_or(f64::NAN);
        let _ = writeln!(
            text,
            "  {l:>3}  {first:9.2} Hz -> {last:9.2} Hz  {}",
            b.whirl.name()
        );
    }
    let _ = writeln!(text, "critical speeds:");
    for c in &result.critical_speeds {
        let _ = writeln!(
            text,
            "  {:9.2} Hz ({:7.0} rpm)  {} x {}  zeta {:.4}",
            c.speed_hz,
            c.speed_rpm,
            result.label_of(c.branch),
            whirl_figures::order_name(c.order),
            c.damping_ratio
        );
    }
    text
}
