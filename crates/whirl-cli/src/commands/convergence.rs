//! `whirl convergence model.toml [--counts 2,4,...,40] [--modes N]`: mesh convergence.
//!
//! Each count is the total number of beam elements, shared among the shaft sections in
//! proportion to their lengths. A mesh on which a disk or bearing would fall between nodes
//! is skipped and listed in the summary. Writes `convergence.csv` (per element count, each
//! mode's frequency and its relative change from the previous mesh) and the plots
//! `convergence` (frequency versus elements, one panel per mode) and `convergence_change`.
//! A coarse mesh has fewer modes than `--modes` asks for: its missing modes are empty
//! cells (null in the summary), listed in the summary's `meshes_with_fewer_modes` and
//! announced on stderr.

use std::fmt::Write;

use whirl::modal::{
    check_element_count, convergence, default_element_counts, DEFAULT_CONVERGENCE_MODES,
};
use whirl::report::Report;

use super::{default_is, finish, load, option_error, report_summary, Common, Outcome};
use crate::output::Output;
use crate::progress::shown;

/// `whirl convergence`
#[derive(Debug, clap::Args)]
pub struct Args {
    #[command(flatten)]
    pub common: Common,
    #[arg(long, value_name = "LIST", value_delimiter = ',', value_parser = element_count,
          help = default_is("Total element counts, comma-separated.", counts_text(&default_element_counts())))]
    pub counts: Vec<usize>,
    #[arg(long, value_name = "N",
          help = default_is("Number of modes to follow (1 to 200).", DEFAULT_CONVERGENCE_MODES))]
    pub modes: Option<usize>,
}

/// Element counts as the help shows them: the first three and the last of a long list.
fn counts_text(counts: &[usize]) -> String {
    match counts {
        [a, b, c, _, .., last] => format!("{a},{b},{c},...,{last}"),
        _ => counts
            .iter()
            .map(ToString::to_string)
            .collect::<Vec<_>>()
            .join(","),
    }
}

/// Clap parser of an element count: a whole number, in the range the library takes
/// ([`check_element_count`], which gives the reason for it).
fn element_count(text: &str) -> Result<usize, String> {
    let count = text
        .trim()
        .parse::<usize>()
        .map_err(|_| format!("`{text}` is not a whole number of elements"))?;
    check_element_count(count).map_err(|e| match e {
        whirl::Error::Input(input) => input.message,
        other => other.to_string(),
    })?;
    Ok(count)
}

pub fn run(args: &Args) -> miette::Result<Outcome> {
    let loaded = load(&args.common.model)?;
    let model = &loaded.model;
    let result = shown("convergence", |p| {
        convergence(model, &args.counts, args.modes, p)
    })
    .map_err(option_error)?;

    let short = result.meshes_with_fewer_modes();
    if !short.is_empty() {
        eprintln!("note: {}", fewer_modes_note(&short, result.modes_requested));
    }
    let summary = report_summary("convergence", &loaded, &result)?;

    let mut text = String::new();
    let _ = writeln!(
        text,
        "{}: frequencies [Hz] versus element count",
        model.name
    );
    for (n, f) in result.element_counts.iter().zip(&result.frequencies_hz) {
        let list: Vec<String> = f
            .iter()
            .map(|x| {
                if x.is_finite() {
                    format!("{x:10.3}")
                } else {
                    format!("{:>10}", "-")
                }
            })
            .collect();
        let _ = writeln!(text, "  {n:5} {}", list.join(" "));
    }
    if !short.is_empty() {
        let _ = writeln!(text, "{}", fewer_modes_note(&short, result.modes_requested));
    }
    if !result.skipped.is_empty() {
        let _ = writeln!(
            text,
            "skipped (a feature would not sit on a node): {:?}",
            result.skipped
        );
    }

    let mut out = Output::begin(&args.common.out_dir("convergence"))?;
    for table in result.tables() {
        out.table(&table)?;
    }
    out.figures(whirl_figures::convergence(&result), args.common.rpm)?;
    finish(out, summary, text, &args.common)
}

/// What the user is told about meshes that cannot give every mode asked for.
fn fewer_modes_note(short: &[(usize, usize)], requested: usize) -> String {
    let list: Vec<String> = short
        .iter()
        .map(|(n, m)| format!("{n} elements: {m}"))
        .collect();
    format!(
        "{} of the meshes have fewer than the {requested} modes asked for ({}); \
         their missing modes are left empty (- here, empty cells in convergence.csv, null in summary.json)",
        short.len(),
        list.join(", ")
    )
}
