//! One module per command; here what they share: the model file argument, `--out` and
//! `--json`, parsers of speeds and lists, names of whirl branches.

pub mod campbell;
pub mod cascade;
pub mod check;
pub mod convergence;
pub mod fit_forcing;
pub mod frf;
pub mod hbm;
pub mod import_ross;
pub mod map;
pub mod modal;
pub mod reduce;
pub mod runup;
pub mod simulate;
pub mod statics;
pub mod stiffness;
pub mod study;
pub mod ucs;
pub mod unbalance;

use std::path::{Path, PathBuf};

use serde::Serialize;
use serde_json::Value;
use whirl::given::Given;
use whirl::model::Model;
use whirl::report::Report;
use whirl::units::{parse_quantity, parse_range, Dimension};

use crate::error::{from_whirl, Diag};
use crate::output::Output;

/// Arguments every command takes.
#[derive(Debug, clap::Args)]
pub struct Common {
    /// The model file (TOML), e.g. examples/reference_rotor.toml.
    #[arg(value_name = "MODEL")]
    pub model: PathBuf,
    /// Output folder [default: out/<command>]. Replaced as a whole when the command
    /// succeeds; left untouched when it fails.
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
    /// Print summary.json to stdout instead of the text summary (the folder is still written).
    #[arg(long)]
    pub json: bool,
    /// Speed axes of the plots, and the speeds their marks name, in rpm instead of Hz (the
    /// tables keep Hz).
    #[arg(long)]
    pub rpm: bool,
}

impl Common {
    /// The output folder of `command`.
    pub fn out_dir(&self, command: &str) -> PathBuf {
        out_or_default(&self.out, command)
    }
}

/// `--nodes`, shared by the commands that report or record chosen nodes (`unbalance`,
/// `hbm`, `simulate`).
#[derive(Debug, clap::Args)]
pub struct Nodes {
    /// Nodes to report, comma-separated, in this order (`hbm` plots and compares the first)
    /// [default: every disk and bearing node].
    #[arg(long, value_name = "LIST", value_delimiter = ',', value_parser = node_index)]
    pub nodes: Vec<usize>,
}

impl Nodes {
    /// The nodes given (checked, repeats removed), or every disk and bearing node
    /// ([`report_nodes`]).
    pub fn resolve(&self, model: &Model) -> miette::Result<Vec<usize>> {
        report_nodes(model, &self.nodes)
    }

    /// Whether none were given.
    pub fn is_default(&self) -> bool {
        self.nodes.is_empty()
    }
}

/// `--out` when given, else `out/<command>`.
pub fn out_or_default(out: &Option<PathBuf>, command: &str) -> PathBuf {
    out.clone()
        .unwrap_or_else(|| Path::new("out").join(command))
}

/// What a command hands back to `main` for printing.
#[derive(Debug)]
pub struct Outcome {
    /// The content of summary.json.
    pub summary: Value,
    /// A few lines for a person.
    pub text: String,
    /// Where the results went.
    pub dir: PathBuf,
    /// How many files were written there.
    pub files: usize,
    /// Print the summary as JSON.
    pub json: bool,
}

/// A model file's text and its validated model.
#[derive(Debug)]
pub struct Loaded {
    /// The file as given on the command line.
    pub path: PathBuf,
    /// The validated model.
    pub model: Model,
}

/// Reads and validates a model file.
pub fn load(path: &Path) -> miette::Result<Loaded> {
    let text = whirl::model::read_input(path).map_err(|e| {
        Diag::new(format!(
            "cannot read the model file `{}`: {e}",
            path.display()
        ))
        .help("check the path; examples/reference_rotor.toml is a complete model to start from")
    })?;
    let model =
        Model::from_toml_str(&text, Some(path.to_path_buf())).map_err(|e| from_whirl(e, &text))?;
    if let Err(whirl::Error::Input(mut e)) = model.check_supports() {
        e.file = Some(path.to_path_buf());
        return Err(Diag::input(&e, &text).into());
    }
    for warning in model.warnings() {
        eprintln!("warning: {}: {warning}", path.display());
    }
    Ok(Loaded {
        path: path.to_path_buf(),
        model,
    })
}

/// A library result as a report (no source text: the error is not in the model file).
pub fn lib<T>(r: whirl::Result<T>) -> miette::Result<T> {
    r.map_err(|e| from_whirl(e, ""))
}

/// The library's error about a setting of a request, named by its flag (the library names
/// the setting as the Python keyword, `cage_steps`; its flag is `--cage-steps`).
pub fn option_error(e: whirl::Error) -> miette::Report {
    match &e {
        whirl::Error::Input(input) if input.file.is_none() && input.field.is_some() => {
            let field = input.field.as_deref().unwrap_or_default();
            let diag = Diag::option(&format!("--{}", field.replace('_', "-")), &input.message);
            match &input.help {
                Some(help) => diag.help(help.clone()).into(),
                None => diag.into(),
            }
        }
        _ => from_whirl(e, ""),
    }
}

/// The line that says which local maxima of a response curve (at `maxima`, Hz) were left
/// out as round-off, if any.
pub fn round_off_note(maxima: &[f64]) -> Option<String> {
    let (first, last) = (maxima.first()?, maxima.last()?);
    Some(format!(
        "{} local maxima between {first:.2} and {last:.2} Hz are within the round-off of \
         the solves and are not reported as peaks (ripples of round-off on a fine mesh; a \
         resonance whose top is among them would be missing: a coarser mesh resolves it)",
        maxima.len()
    ))
}

/// Writes the summary, finishes the folder and builds the outcome.
pub fn finish(
    out: Output,
    summary: impl Serialize,
    text: String,
    common: &Common,
) -> miette::Result<Outcome> {
    finish_json(out, summary, text, common.json)
}

/// [`finish`] for a command without [`Common`]: `json` prints the summary as JSON.
pub fn finish_json(
    out: Output,
    summary: impl Serialize,
    text: String,
    json: bool,
) -> miette::Result<Outcome> {
    let mut summary = serde_json::to_value(summary)
        .map_err(|e| Diag::new(format!("cannot encode the summary: {e}")))?;
    let (dir, files) = out.finish(&mut summary)?;
    Ok(Outcome {
        summary,
        text,
        dir,
        files,
        json,
    })
}

/// The first keys of every summary: which command, which whirl, which model.
#[derive(Debug, Serialize)]
pub struct Head {
    /// The command's name, e.g. `modal`.
    pub command: &'static str,
    /// This build's version.
    pub whirl_version: &'static str,
    /// The model file as given on the command line.
    pub model_file: String,
    /// The model's `name`.
    pub model_name: String,
}

impl Head {
    /// The head of `command`'s summary of `loaded`.
    pub fn new(command: &'static str, loaded: &Loaded) -> Head {
        Head {
            command,
            whirl_version: env!("CARGO_PKG_VERSION"),
            model_file: loaded.path.display().to_string(),
            model_name: loaded.model.name.clone(),
        }
    }
}

/// [`Head`] as the start of a summary built key by key.
pub fn summary_head(command: &'static str, loaded: &Loaded) -> serde_json::Map<String, Value> {
    match serde_json::to_value(Head::new(command, loaded)) {
        Ok(Value::Object(m)) => m,
        _ => serde_json::Map::new(),
    }
}

/// The summary of a library report under the run's [`Head`]: the head's keys, then the
/// report's.
pub fn report_summary<R: Report>(
    command: &'static str,
    loaded: &Loaded,
    report: &R,
) -> miette::Result<Value> {
    let mut s = summary_head(command, loaded);
    match serde_json::to_value(report.summary()) {
        Ok(Value::Object(keys)) => s.extend(keys),
        Ok(other) => {
            return Err(Diag::new(format!("the summary is not a JSON object: {other}")).into())
        }
        Err(e) => return Err(Diag::new(format!("cannot encode the summary: {e}")).into()),
    }
    Ok(Value::Object(s))
}

/// Clap parser of one speed: `3000rpm`, `50Hz`, or a plain number in rad/s (the one rule
/// for plain numbers on the command line, as in the model file: SI). Says on stderr how
/// it was read.
pub fn speed(text: &str) -> Result<f64, String> {
    let w = parse_quantity(text, Dimension::AngularSpeed).map_err(|e| e.to_string())?;
    if w < 0.0 {
        return Err(format!("`{text}`: the speed must not be negative"));
    }
    announce(Some(text), "speed", &[w]);
    Ok(w)
}

/// Tells on stderr how a speed or frequency (range) was resolved, in Hz and rpm, so that a
/// plain number, which is rad/s, never passes unnoticed as something else. `text` is what
/// was given (None for a default, then named `what`).
pub fn announce(text: Option<&str>, what: &str, w: &[f64]) {
    let (Some(&first), Some(&last)) = (w.first(), w.last()) else {
        return;
    };
    let span = |a: f64, b: f64| {
        if a == b {
            format!("{:.4} Hz ({:.1} rpm)", hz(a), 60.0 * hz(a))
        } else {
            format!(
                "{} values from {:.4} to {:.4} Hz ({:.1} to {:.1} rpm)",
                w.len(),
                hz(a),
                hz(b),
                60.0 * hz(a),
                60.0 * hz(b)
            )
        }
    };
    let plain = last != 0.0
        && text.is_some_and(|t| {
            !t.chars()
                .any(|c| c.is_ascii_alphabetic() && c != 'e' && c != 'E')
        });
    match text {
        Some(t) if plain => eprintln!(
            "speed `{t}` has no unit, so it is rad/s: {} (write `Hz` or `rpm` for those units)",
            span(first, last)
        ),
        Some(t) => eprintln!("speed `{t}`: {}", span(first, last)),
        None => eprintln!("{what} (default): {}", span(first, last)),
    }
}

/// Clap parser of a time: `0.5s`, `200ms`, or a plain number in s; not negative (read as
/// the Python package and the study file read it).
pub fn time(text: &str) -> Result<f64, String> {
    given(text, Given::time)
}

/// Clap parser of a positive length: `1 mm`, or a plain number in m.
pub fn positive_length(text: &str) -> Result<f64, String> {
    given(text, Given::length)
}

/// `text` read by the library as `read` reads an option, its error as clap shows it.
pub fn given<T>(
    text: &str,
    read: fn(&Given, &str) -> Result<T, whirl::error::InputError>,
) -> Result<T, String> {
    read(&Given::Text(text.to_string()), "").map_err(|e| format!("`{text}`: {}", e.message))
}

/// Help text ending in the library's default: clap states a default only for an option it
/// fills itself, and these the library fills.
pub fn default_is(text: &str, default: impl std::fmt::Display) -> String {
    format!("{} [default: {default}]", text.trim_end_matches('.'))
}

/// A default time for the help, e.g. `0.5s`.
pub fn seconds(t: f64) -> String {
    format!("{t}s")
}

/// A default frequency for the help, e.g. `0.5Hz`.
pub fn hertz(f: f64) -> String {
    format!("{f}Hz")
}

/// A default length for the help, e.g. `1um`.
pub fn metres(x: f64) -> String {
    format!("{}um", 1e6 * x)
}

/// Clap parser of a node index.
pub fn node_index(text: &str) -> Result<usize, String> {
    text.trim()
        .parse::<usize>()
        .map_err(|_| format!("`{text}` is not a node number (0, 1, 2, ...)"))
}

/// Checks that every node given to `option` is on the shaft.
pub fn check_nodes(model: &Model, option: &str, nodes: &[usize]) -> miette::Result<()> {
    let last = model.node_count() - 1;
    match nodes.iter().find(|&&n| n > last) {
        None => Ok(()),
        Some(bad) => Err(
            Diag::option(option, format!("node {bad} is not on the shaft"))
                .help(format!(
                    "nodes are numbered 0 (z = 0) to {last} (z = {} m)",
                    model.length()
                ))
                .into(),
        ),
    }
}

/// The nodes to report: those given with `--nodes` (checked, repeats removed), or by
/// default every disk node and every bearing node, ascending.
pub fn report_nodes(model: &Model, given: &[usize]) -> miette::Result<Vec<usize>> {
    check_nodes(model, "--nodes", given)?;
    let nodes: Vec<usize> = if given.is_empty() {
        let mut n: Vec<usize> = model.disks.iter().map(|d| d.station.node).collect();
        n.extend(model.bearing_nodes());
        n.sort_unstable();
        n.dedup();
        n
    } else {
        // In the order given (it orders the columns), each node once.
        let mut n: Vec<usize> = Vec::new();
        for &node in given {
            if !n.contains(&node) {
                n.push(node);
            }
        }
        n
    };
    if nodes.is_empty() {
        return Err(Diag::option(
            "--nodes",
            "the model has no disk or bearing to report by default",
        )
        .help("give the nodes to report, e.g. --nodes 0,10")
        .into());
    }
    Ok(nodes)
}

/// Speeds in rad/s from `start:stop:count`.
#[derive(Debug, Clone)]
pub struct Speeds(pub Vec<f64>);

impl Speeds {
    /// The given range, or the library's `default`, announced on stderr (a given range
    /// was, when it was parsed).
    pub fn or_default(given: &Option<Speeds>, default: impl FnOnce() -> Vec<f64>) -> Vec<f64> {
        if let Some(s) = given {
            return s.0.clone();
        }
        let w = default();
        announce(None, "speeds", &w);
        w
    }
}

/// Clap parser of a speed range `start:stop:count` (`0:800Hz:161`); plain numbers are rad/s.
/// Says on stderr how it was read.
pub fn speeds(text: &str) -> Result<Speeds, String> {
    let w = parse_range(text, Dimension::AngularSpeed).map_err(|e| e.to_string())?;
    if w.first().is_some_and(|&w0| w0 < 0.0) {
        return Err(format!("`{text}`: speeds must not be negative"));
    }
    announce(Some(text), "speeds", &w);
    Ok(Speeds(w))
}

/// Clap parser of a count of modes or branches, 1 to 200.
pub fn mode_count(text: &str) -> Result<usize, String> {
    match text.trim().parse::<usize>() {
        Ok(n) if (1..=200).contains(&n) => Ok(n),
        _ => Err(format!("`{text}` is not a whole number from 1 to 200")),
    }
}

/// Speed in Hz from rad/s.
pub fn hz(w: f64) -> f64 {
    whirl::units::rad_s_to_hz(w)
}

#[cfg(test)]
mod tests {
    use clap::ValueEnum;
    use whirl::given::Choice;

    /// clap lists and reads the option enums by its own names; the library reads them for
    /// Python and the study file by [`Choice::NAMES`]: the two must be the same names.
    fn same_names<T: ValueEnum + Choice + std::fmt::Debug>() {
        let clap: Vec<String> = T::value_variants()
            .iter()
            .filter_map(|v| v.to_possible_value())
            .map(|p| p.get_name().to_string())
            .collect();
        let library: Vec<&str> = T::NAMES.iter().map(|(n, _)| *n).collect();
        assert_eq!(clap, library, "{}", std::any::type_name::<T>());
    }

    #[test]
    fn every_option_enum_has_the_same_names_on_the_command_line_and_in_the_library() {
        same_names::<whirl::bearing::ContactLaw>();
        same_names::<whirl::time::Initial>();
        same_names::<whirl::nsv::Component>();
        same_names::<whirl::post::Window>();
        same_names::<whirl::runup::Direction>();
        same_names::<whirl::runup::Steady>();
        same_names::<whirl::hbm::CageKind>();
        same_names::<whirl::statics::RollerSupport>();
        same_names::<whirl::time::Integrator>();
        same_names::<whirl::map::Parallelism>();
    }
}
