//! `whirl import-ross rotor.toml [--out DIR]`: a rotor saved by ROSS (`Rotor.save`, the
//! Python rotordynamics library) as a whirl model file (see [`whirl::model::ross`]).
//!
//! Writes `model.toml` (the whirl model, ready for every other command), `frequencies.csv`
//! (the first undamped natural frequencies of the translated model, to compare with ROSS's)
//! and summary.json (the notes on what the translation dropped or changed). What whirl
//! cannot represent is refused, naming the ROSS element.

use std::fmt::Write;
use std::path::PathBuf;

use serde::Serialize;
use whirl::modal::trusted_modes;
use whirl::model::ross::from_ross_toml;
use whirl::model::Model;

use super::{finish_json, lib, Outcome};
use crate::error::{from_whirl, Diag};
use crate::output::{header, num, Output};

/// Undamped frequencies reported for comparison with ROSS.
const MODES: usize = 8;

/// `whirl import-ross`
#[derive(Debug, clap::Args)]
pub struct Args {
    /// A rotor file written by ROSS's `Rotor.save`.
    #[arg(value_name = "ROSS_FILE")]
    pub file: PathBuf,
    /// Output folder [default: out/import-ross].
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
    /// Print summary.json to stdout instead of the text summary (the folder is still written).
    #[arg(long)]
    pub json: bool,
}

impl Args {
    /// The output folder.
    pub fn out_dir(&self) -> PathBuf {
        super::out_or_default(&self.out, "import-ross")
    }
}

#[derive(Debug, Serialize)]
struct Summary {
    command: &'static str,
    whirl_version: &'static str,
    ross_file: String,
    model_name: String,
    nodes: usize,
    disks: usize,
    bearings: usize,
    frequencies_hz: Vec<f64>,
    notes: Vec<String>,
}

pub fn run(args: &Args) -> miette::Result<Outcome> {
    let text = whirl::model::read_input(&args.file).map_err(|e| {
        Diag::new(format!("cannot read `{}`: {e}", args.file.display()))
            .help("give a file written by ROSS's Rotor.save")
    })?;
    let name = args
        .file
        .file_stem()
        .and_then(|s| s.to_str())
        .unwrap_or("rotor");
    let import = from_ross_toml(&text, name).map_err(|e| from_whirl(e, ""))?;
    let model =
        Model::from_toml_str(&import.toml, None).map_err(|e| from_whirl(e, &import.toml))?;
    let frequencies = lib(trusted_modes(&model, MODES))?.frequencies_hz;
    let summary = Summary {
        command: "import-ross",
        whirl_version: env!("CARGO_PKG_VERSION"),
        ross_file: args.file.display().to_string(),
        model_name: model.name.clone(),
        nodes: model.node_count(),
        disks: model.disks.len(),
        bearings: model.bearings.len(),
        frequencies_hz: frequencies.clone(),
        notes: import.notes.clone(),
    };
    let mut out = Output::begin(&args.out_dir())?;
    out.text("model.toml", &import.toml)?;
    let rows = frequencies
        .iter()
        .enumerate()
        .map(|(i, f)| [(i + 1).to_string(), num(*f)]);
    out.csv("frequencies.csv", &header(&["mode", "frequency_hz"]), rows)?;
    let text = text_summary(&summary);
    finish_json(out, summary, text, args.json)
}

fn text_summary(s: &Summary) -> String {
    let mut t = format!(
        "{}: {} nodes, {} disks, {} bearings, translated from ROSS into model.toml\n",
        s.ross_file, s.nodes, s.disks, s.bearings
    );
    let list: Vec<String> = s.frequencies_hz.iter().map(|f| format!("{f:.4}")).collect();
    let _ = writeln!(t, "undamped natural frequencies: {} Hz", list.join(", "));
    for note in &s.notes {
        let _ = writeln!(t, "note: {note}");
    }
    t
}
