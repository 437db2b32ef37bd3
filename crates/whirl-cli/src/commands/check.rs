//! `whirl check model.toml`: validate a model and summarise it.
//!
//! Writes `summary.json` (mesh, masses, supports, the first six undamped frequencies),
//! `nodes.csv` (each node's position and what sits there), `frequencies.csv` and the rotor
//! layout plot `rotor.png`/`.svg`; with a speed-dependent clearance also `clearance.csv` and
//! its plot over speed (thesis fig. 3.3).

use std::fmt::Write;

use whirl::modal::{check_model, ModelCheck};
use whirl::report::Report;

use super::{finish, lib, load, report_summary, Common, Outcome};
use crate::output::Output;

/// `whirl check`
#[derive(Debug, clap::Args)]
pub struct Args {
    #[command(flatten)]
    pub common: Common,
}

pub fn run(args: &Args) -> miette::Result<Outcome> {
    let loaded = load(&args.common.model)?;
    let model = &loaded.model;
    let check = lib(check_model(model))?;
    let mut out = Output::begin(&args.common.out_dir("check"))?;
    for table in check.tables() {
        out.table(&table)?;
    }
    out.figures(whirl_figures::check(&check), args.common.rpm)?;
    let text = text(&check);
    let summary = report_summary("check", &loaded, &check)?;
    finish(out, summary, text, &args.common)
}

/// The lines printed without `--json`.
fn text(check: &ModelCheck) -> String {
    let (model, frequencies) = (&check.model, &check.frequencies_hz);
    let (shaft, disks) = (model.shaft_mass(), check.disk_mass());
    let mut text = String::new();
    let _ = writeln!(
        text,
        "{}: valid\n  mesh: {} nodes, {} DOFs, {} elements in {} section(s), shaft {:.4} m",
        model.name,
        model.node_count(),
        model.dof_count(),
        check.elements(),
        model.sections.len(),
        model.length()
    );
    let _ = writeln!(
        text,
        "  mass: {:.3} kg (shaft {:.3} kg, disks {:.3} kg)",
        shaft + disks,
        shaft,
        disks
    );
    let _ = writeln!(
        text,
        "  {} disk(s), {} linear bearing(s), {} roller bearing(s), {} ball bearing(s), {} unbalance(s)",
        model.disks.len(),
        model.bearings.len(),
        model.roller_bearings.iter().filter(|b| !b.is_ball()).count(),
        model.roller_bearings.iter().filter(|b| b.is_ball()).count(),
        model.unbalances.len()
    );
    if !model.housings.is_empty() {
        let dampers = model
            .housings
            .iter()
            .filter(|h| h.squeeze_film.is_some())
            .count();
        let _ = writeln!(
            text,
            "  {} housing(s) ({} with a squeeze-film damper)",
            model.housings.len(),
            dampers
        );
    }
    let list: Vec<String> = frequencies.iter().map(|x| format!("{x:.2}")).collect();
    let _ = writeln!(text, "  undamped frequencies [Hz]: {}", list.join(", "));
    text
}
