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

use serde::Serialize;
use whirl::fe::{assemble_banded, Bearings};
use whirl::modal::{campbell, CampbellOptions, CampbellResult, Whirl};
use whirl::model::Model;

use whirl_plot::SpeedAxis;

use super::{
    finish, lib, load, mode_count, speeds, whirl_labels, Common, Head, Loaded, Outcome, Speeds,
};
use crate::output::{num, Output};
use crate::plots;

/// `whirl campbell`
#[derive(Debug, clap::Args)]
pub struct Args {
    #[command(flatten)]
    pub common: Common,
    /// Spin speeds `start:stop:count`, e.g. `0:800Hz:161` or `0:48000rpm:161`; plain
    /// numbers are rad/s [default: 161 speeds from rest to 1.2 x the model's top
    /// operating speed].
    #[arg(long, value_name = "RANGE", value_parser = speeds)]
    pub speeds: Option<Speeds>,
    /// Number of whirl branches to follow.
    #[arg(long, value_name = "N", default_value = "8", value_parser = mode_count)]
    pub modes: usize,
    /// Excitation orders whose crossings are critical speeds (1 = synchronous).
    #[arg(long, value_name = "LIST", value_delimiter = ',', default_value = "1", value_parser = order)]
    pub orders: Vec<f64>,
    /// Solve the full system at every speed instead of a basis of 2N + 8 undamped modes
    /// (slower; the basis keeps branches within 2e-4 of the full solve).
    #[arg(long)]
    pub full: bool,
}

/// Clap parser of an excitation order: a positive finite number.
fn order(text: &str) -> Result<f64, String> {
    match text.trim().parse::<f64>() {
        Ok(k) if k.is_finite() && k > 0.0 && k <= 100.0 => Ok(k),
        _ => Err(format!(
            "`{text}` is not an order between 0 and 100 (e.g. 1 or 0.5)"
        )),
    }
}

/// "1X", "0.5X".
pub fn order_name(k: f64) -> String {
    format!("{k}X")
}

/// The diagram and its branch labels.
struct Diagram {
    result: CampbellResult,
    /// `1F`, `1B`, ... of the branches.
    labels: Vec<String>,
}

impl Diagram {
    /// The label of branch index `branch`.
    fn label_of(&self, branch: usize) -> String {
        self.result
            .branches
            .iter()
            .position(|b| b.index == branch)
            .map(|i| self.labels[i].clone())
            .unwrap_or_else(|| format!("branch {branch}"))
    }
}

/// summary.json of `whirl campbell`.
#[derive(Serialize)]
struct Summary<'a> {
    #[serde(flatten)]
    head: Head,
    speed_range_hz: [Option<&'a f64>; 2],
    speed_count: usize,
    orders: &'a [f64],
    basis_size: usize,
    branches: Vec<BranchSummary<'a>>,
    critical_speeds: Vec<CriticalSummary>,
}

/// One branch in summary.json.
#[derive(Serialize)]
struct BranchSummary<'a> {
    label: &'a str,
    whirl: Whirl,
    frequency_at_first_speed_hz: Option<&'a f64>,
    frequency_at_last_speed_hz: Option<&'a f64>,
    min_log_decrement: f64,
}

/// One critical speed in summary.json: the library's, with the branch by its label.
#[derive(Serialize)]
struct CriticalSummary {
    speed_hz: f64,
    speed_rpm: f64,
    frequency_hz: f64,
    order: f64,
    branch: String,
    whirl: Whirl,
    damping_ratio: f64,
}

pub fn run(args: &Args) -> miette::Result<Outcome> {
    let loaded = load(&args.common.model)?;
    let diagram = solve(&loaded.model, args)?;
    let mut out = Output::begin(&args.common.out_dir("campbell"))?;
    write_tables(&mut out, &diagram)?;
    write_plots(&mut out, &loaded.model, &diagram, &args.common)?;
    let text = text(&loaded.model, &diagram);
    finish(out, summary(&loaded, &diagram), text, &args.common)
}

/// The Campbell diagram of the linearised model over the speeds asked for.
fn solve(model: &Model, args: &Args) -> miette::Result<Diagram> {
    let system = assemble_banded(model, Bearings::Linearised);
    let options = CampbellOptions {
        speeds: Speeds::or_default(&args.speeds, model, 0.0, 161),
        modes: args.modes,
        orders: args.orders.clone(),
        basis_size: (!args.full).then(|| CampbellOptions::default_basis(args.modes)),
        max_damping_ratio: 0.9,
    };
    let result = lib(campbell(&system, &options))?;
    let labels = whirl_labels(&result.branches.iter().map(|b| b.whirl).collect::<Vec<_>>());
    Ok(Diagram { result, labels })
}

fn summary<'a>(loaded: &Loaded, diagram: &'a Diagram) -> Summary<'a> {
    let result = &diagram.result;
    let speeds_hz = &result.speeds_hz;
    Summary {
        head: Head::new("campbell", loaded),
        speed_range_hz: [speeds_hz.first(), speeds_hz.last()],
        speed_count: speeds_hz.len(),
        orders: &result.orders,
        basis_size: result.basis_size,
        branches: result
            .branches
            .iter()
            .zip(&diagram.labels)
            .map(|(b, label)| BranchSummary {
                label,
                whirl: b.whirl,
                frequency_at_first_speed_hz: b.frequency_hz.first(),
                frequency_at_last_speed_hz: b.frequency_hz.last(),
                min_log_decrement: b
                    .log_decrement
                    .iter()
                    .copied()
                    .filter(|x| x.is_finite())
                    .fold(f64::INFINITY, f64::min),
            })
            .collect(),
        critical_speeds: result
            .critical_speeds
            .iter()
            .map(|c| CriticalSummary {
                speed_hz: c.speed_hz,
                speed_rpm: c.speed_rpm,
                frequency_hz: c.frequency_hz,
                order: c.order,
                branch: diagram.label_of(c.branch),
                whirl: c.whirl,
                damping_ratio: c.damping_ratio,
            })
            .collect(),
    }
}

/// The lines printed without `--json`.
fn text(model: &Model, diagram: &Diagram) -> String {
    let result = &diagram.result;
    let mut text = String::new();
    let _ = writeln!(
        text,
        "{}: {} branches over {} speeds (basis of {} modes)",
        model.name,
        result.branches.len(),
        result.speeds_hz.len(),
        result.basis_size
    );
    for (b, l) in result.branches.iter().zip(&diagram.labels) {
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
            diagram.label_of(c.branch),
            order_name(c.order),
            c.damping_ratio
        );
    }
    text
}

/// `campbell.csv` and `critical_speeds.csv`.
fn write_tables(out: &mut Output, diagram: &Diagram) -> miette::Result<()> {
    let (result, labels) = (&diagram.result, &diagram.labels);
    let speeds_hz = &result.speeds_hz;
    let mut h = vec!["speed_hz".to_string(), "speed_rpm".to_string()];
    for l in labels {
        for q in ["frequency_hz", "damping_ratio", "log_decrement", "whirl"] {
            h.push(format!("{l}_{q}"));
        }
    }
    let rows: Vec<Vec<String>> = speeds_hz
        .iter()
        .enumerate()
        .map(|(i, f)| {
            let mut row = vec![num(*f), num(60.0 * f)];
            for b in &result.branches {
                let found = b.frequency_hz[i].is_finite();
                row.push(num(b.frequency_hz[i]));
                row.push(num(b.damping_ratio[i]));
                row.push(num(b.log_decrement[i]));
                row.push(if found {
                    b.whirl_at[i].name().to_string()
                } else {
                    String::new()
                });
            }
            row
        })
        .collect();
    out.csv("campbell.csv", &h, &rows)?;
    let h: Vec<String> = [
        "speed_hz",
        "speed_rpm",
        "frequency_hz",
        "order",
        "branch",
        "whirl",
        "damping_ratio",
    ]
    .map(String::from)
    .to_vec();
    let rows: Vec<Vec<String>> = result
        .critical_speeds
        .iter()
        .map(|c| {
            vec![
                num(c.speed_hz),
                num(c.speed_rpm),
                num(c.frequency_hz),
                num(c.order),
                diagram.label_of(c.branch),
                c.whirl.name().to_string(),
                num(c.damping_ratio),
            ]
        })
        .collect();
    out.csv("critical_speeds.csv", &h, &rows)
}

fn write_plots(
    out: &mut Output,
    model: &Model,
    diagram: &Diagram,
    common: &Common,
) -> miette::Result<()> {
    let campbell = plots::campbell(model, &diagram.result, &diagram.labels);
    out.plot("campbell", |stem| {
        common.speed_axis(campbell, SpeedAxis::X).save(stem)
    })?;
    let log_decrement = plots::log_decrement(&diagram.result, &diagram.labels);
    out.plot("log_decrement", |stem| {
        common.speed_axis(log_decrement, SpeedAxis::X).save(stem)
    })
}
