//! `whirl reduce model.toml [--modes 12] [--nodes 5,10]`: how good a Craig-Bampton reduced
//! model is (docs/theory.md section 4, thesis 2.3 and fig. 4.3).
//!
//! The boundary is every DOF of the bearing nodes and of the `--nodes` given; the reduced
//! model keeps those and `--modes` fixed-interface modes. Reported: its natural frequencies
//! (undamped, at rest) against the full model's, for the first `--modes` modes (at least 4),
//! and a study over 1 to max(24, 2 x `--modes`) fixed-interface modes of the frequency
//! errors and of the explicit central difference's stable step, 2 / w_max, which the
//! reduction raises by dropping the highest frequencies.
//!
//! Writes `reduce.csv` (mode, full and reduced frequency, relative error), `study.csv` (one
//! row per mode count: coordinates, stable step, each mode's relative error) and the plots
//! `reduction_error` (modes 1-4, logarithmic) and `stable_step`.

use std::fmt::Write;

use whirl::reduce::DEFAULT_MODES;
use whirl::reduce::{reduction_report, ReductionRow, ReductionStudy};
use whirl::report::Report;

use super::{
    check_nodes, default_is, finish, load, node_index, option_error, report_summary, Common,
    Outcome,
};
use crate::output::Output;
use crate::progress::shown;

/// `whirl reduce`
#[derive(Debug, clap::Args)]
pub struct Args {
    #[command(flatten)]
    pub common: Common,
    #[arg(long, value_name = "N",
          help = default_is("Fixed-interface modes of the reduced model reported (1 to 200).", DEFAULT_MODES))]
    pub modes: Option<usize>,
    /// Nodes added to the boundary besides the bearing nodes, comma-separated.
    #[arg(long, value_name = "LIST", value_delimiter = ',', value_parser = node_index)]
    pub nodes: Vec<usize>,
}

pub fn run(args: &Args) -> miette::Result<Outcome> {
    let loaded = load(&args.common.model)?;
    check_nodes(&loaded.model, "--nodes", &args.nodes)?;
    let report = shown("reduce", |p| {
        reduction_report(&loaded.model, args.modes, &args.nodes, p)
    })
    .map_err(option_error)?;
    let summary = report_summary("reduce", &loaded, &report)?;
    let text = text(&loaded.model.name, &report.study, report.chosen());
    let mut out = Output::begin(&args.common.out_dir("reduce"))?;
    for table in report.tables() {
        out.table(&table)?;
    }
    out.figures(whirl_figures::reduce(&report), args.common.rpm)?;
    finish(out, summary, text, &args.common)
}

fn text(name: &str, study: &ReductionStudy, chosen: &ReductionRow) -> String {
    let mut t = String::new();
    let _ = writeln!(
        t,
        "{name}: Craig-Bampton with {} boundary DOFs and {} fixed-interface modes: \
         {} coordinates instead of {}",
        study.boundary_dofs, chosen.modes, chosen.size, study.full_dofs
    );
    let _ = writeln!(t, "  mode   full [Hz]   reduced [Hz]   relative error");
    for (j, f) in study.full_frequencies_hz.iter().enumerate() {
        let reduced = chosen.frequencies_hz.get(j).copied().unwrap_or(f64::NAN);
        let error = chosen.relative_error.get(j).copied().unwrap_or(f64::NAN);
        let _ = writeln!(t, "  {:4}  {f:10.3}  {reduced:13.3}  {error:15.3e}", j + 1);
    }
    let _ = writeln!(
        t,
        "stable central-difference step: full {:.3e} s, reduced {:.3e} s ({:.1} x)",
        study.full_stable_step,
        chosen.stable_step,
        chosen.stable_step / study.full_stable_step
    );
    t
}
