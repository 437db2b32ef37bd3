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

use serde_json::{json, Value};
use whirl::fe::{assemble, dof_name, Bearings};
use whirl::reduce::{boundary_dofs, reduction_study, ReductionRow, ReductionStudy};
use whirl::time::DEFAULT_MODES;

use super::{
    check_nodes, finish, lib, load, mode_count, node_index, summary_head, Common, Outcome,
};
use crate::error::Diag;
use crate::output::{header, num, opt, Output};
use crate::plots;

/// The study runs to at least this many fixed-interface modes.
const STUDY_MODES: usize = 24;

/// At least this many frequencies are compared (the error plot shows modes 1-4).
const MIN_COMPARED: usize = 4;

/// `whirl reduce`
#[derive(Debug, clap::Args)]
pub struct Args {
    #[command(flatten)]
    pub common: Common,
    /// Fixed-interface modes of the reduced model reported.
    #[arg(long, value_name = "N", default_value_t = DEFAULT_MODES, value_parser = mode_count)]
    pub modes: usize,
    /// Nodes added to the boundary besides the bearing nodes, comma-separated.
    #[arg(long, value_name = "LIST", value_delimiter = ',', value_parser = node_index)]
    pub nodes: Vec<usize>,
}

pub fn run(args: &Args) -> miette::Result<Outcome> {
    let loaded = load(&args.common.model)?;
    let model = &loaded.model;
    check_nodes(model, "--nodes", &args.nodes)?;
    let system = assemble(model, Bearings::Linearised);
    let boundary = boundary_dofs(model, &args.nodes);
    let internal = system.dofs() - boundary.len();
    if internal == 0 {
        return Err(Diag::option(
            "--nodes",
            "every DOF is on the boundary: nothing is left to reduce",
        )
        .help("mark fewer nodes as boundary")
        .into());
    }
    // A reduced model cannot keep more modes than it has internal DOFs.
    let modes = args.modes.min(internal);
    let counts: Vec<usize> = (1..=STUDY_MODES.max(2 * modes).min(internal)).collect();
    let compared = modes.max(MIN_COMPARED).min(system.dofs());
    let study = lib(reduction_study(&system, &boundary, &counts, compared))?;
    let chosen = study
        .rows
        .iter()
        .find(|r| r.modes == modes)
        .ok_or_else(|| Diag::new(format!("the study has no row with {modes} modes")))?;
    let names: Vec<String> = boundary.iter().map(|&d| dof_name(d)).collect();

    let summary = summary(&loaded, &study, chosen, &names);
    let text = text(&loaded.model.name, &study, chosen);
    let mut out = Output::begin(&args.common.out_dir("reduce"))?;
    let rows: Vec<Vec<String>> = study
        .full_frequencies_hz
        .iter()
        .enumerate()
        .map(|(j, f)| {
            vec![
                (j + 1).to_string(),
                num(*f),
                opt(chosen.frequencies_hz.get(j).copied()),
                opt(chosen.relative_error.get(j).copied()),
            ]
        })
        .collect();
    let h = header(&[
        "mode",
        "full_frequency_hz",
        "reduced_frequency_hz",
        "relative_error",
    ]);
    out.csv("reduce.csv", &h, &rows)?;
    let mut h = header(&["fixed_interface_modes", "coordinates", "stable_step_s"]);
    h.extend((1..=compared).map(|j| format!("mode{j}_relative_error")));
    let rows: Vec<Vec<String>> = study
        .rows
        .iter()
        .map(|r| {
            let mut row = vec![r.modes.to_string(), r.size.to_string(), num(r.stable_step)];
            row.extend((0..compared).map(|j| opt(r.relative_error.get(j).copied())));
            row
        })
        .collect();
    out.csv("study.csv", &h, &rows)?;
    out.plot("reduction_error", |stem| {
        plots::reduction_error(&study).save(stem)
    })?;
    out.plot("stable_step", |stem| plots::stable_steps(&study).save(stem))?;
    finish(out, summary, text, &args.common)
}

fn summary(
    loaded: &super::Loaded,
    study: &ReductionStudy,
    chosen: &ReductionRow,
    boundary_names: &[String],
) -> Value {
    let mut s = summary_head("reduce", loaded);
    s.insert("full_dofs".into(), study.full_dofs.into());
    s.insert("boundary_dofs".into(), json!(boundary_names));
    s.insert("fixed_interface_modes".into(), chosen.modes.into());
    s.insert("reduced_coordinates".into(), chosen.size.into());
    s.insert(
        "full_frequencies_hz".into(),
        json!(study.full_frequencies_hz),
    );
    s.insert(
        "reduced_frequencies_hz".into(),
        json!(chosen.frequencies_hz),
    );
    s.insert("relative_errors".into(), json!(chosen.relative_error));
    s.insert(
        "max_relative_error".into(),
        json!(chosen
            .relative_error
            .iter()
            .map(|e| e.abs())
            .fold(0.0, f64::max)),
    );
    s.insert("full_stable_step_s".into(), study.full_stable_step.into());
    s.insert("reduced_stable_step_s".into(), chosen.stable_step.into());
    s.insert(
        "study".into(),
        study
            .rows
            .iter()
            .map(|r| {
                json!({
                    "fixed_interface_modes": r.modes, "coordinates": r.size,
                    "stable_step_s": r.stable_step, "relative_errors": r.relative_error,
                })
            })
            .collect::<Vec<_>>()
            .into(),
    );
    s.insert(
        "notes".into(),
        json!([
            "undamped natural frequencies at rest, linearised bearings",
            "stable step of the explicit central difference, 2 / w_max, without contact stiffness",
        ]),
    );
    Value::Object(s)
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
