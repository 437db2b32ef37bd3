//! `whirl unbalance model.toml --speeds 1:800Hz:800 [--nodes 10,0]`: steady unbalance response.
//!
//! Writes `unbalance.csv` (one row per speed; per node the amplitude (m, zero-to-peak) and
//! phase (degrees) of ux and uy, the orbit's major and minor semi-axes and its whirl),
//! `peaks.csv` (each resonance peak of the major semi-axis with its half-power band,
//! amplification factor and API 617 separation margins) and the plots `bode`, `polar` and
//! `orbit_major`. The default nodes are every disk node and every bearing node.
//! Speeds are added inside each peak's half-power band until it holds 40 steps, so the
//! rows' speeds are uneven near resonances.
//! Margins are assessed only for an operating range that starts at 10 % of its top or
//! above; otherwise `meets_api617` reads "not applicable" and the summary's `api617_status`
//! says why.

use std::fmt::Write;

use serde::Serialize;
use whirl::fe::{assemble, Bearings};
use whirl::response::{unbalance_response_refined, ResponsePeak, UnbalanceResult};

use whirl_plot::SpeedAxis;

use super::{
    finish, lib, load, node_index, report_nodes, speeds, Common, Head, Loaded, Outcome, Speeds,
};
use crate::output::{header, num, opt, Output};
use crate::plots;

/// `whirl unbalance`
#[derive(Debug, clap::Args)]
pub struct Args {
    #[command(flatten)]
    pub common: Common,
    /// Spin speeds `start:stop:count`, e.g. `1:800Hz:800`; plain numbers are rad/s
    /// [default: 800 speeds from 1 Hz to 1.2 x the model's top operating speed].
    #[arg(long, value_name = "RANGE", value_parser = speeds)]
    pub speeds: Option<Speeds>,
    /// Nodes to report, comma-separated [default: every disk and bearing node].
    #[arg(long, value_name = "LIST", value_delimiter = ',', value_parser = node_index)]
    pub nodes: Vec<usize>,
}

/// summary.json of `whirl unbalance`.
#[derive(Serialize)]
struct Summary<'a> {
    #[serde(flatten)]
    head: Head,
    speed_range_hz: [Option<&'a f64>; 2],
    speed_count: usize,
    operating_speed_hz: Option<(f64, f64)>,
    api617_status: String,
    nodes: Vec<NodeSummary<'a>>,
}

/// One reported node in summary.json.
#[derive(Serialize)]
struct NodeSummary<'a> {
    node: usize,
    z_m: f64,
    max_major_semi_axis_m: f64,
    max_major_semi_axis_speed_hz: Option<&'a f64>,
    peaks: Vec<PeakSummary>,
}

/// One resonance peak in summary.json.
#[derive(Serialize)]
struct PeakSummary {
    speed_hz: f64,
    speed_rpm: f64,
    major_semi_axis_m: f64,
    half_power_hz: Option<(f64, f64)>,
    amplification_factor: Option<f64>,
    api617_required_margin_pct: Option<f64>,
    api617_actual_margin_pct: Option<f64>,
    meets_api617: Option<bool>,
}

impl From<&ResponsePeak> for PeakSummary {
    fn from(p: &ResponsePeak) -> Self {
        PeakSummary {
            speed_hz: p.speed_hz,
            speed_rpm: 60.0 * p.speed_hz,
            major_semi_axis_m: p.amplitude,
            half_power_hz: p.half_power_hz,
            amplification_factor: p.amplification_factor,
            api617_required_margin_pct: p.required_margin_pct,
            api617_actual_margin_pct: p.actual_margin_pct,
            meets_api617: p.meets_api617,
        }
    }
}

pub fn run(args: &Args) -> miette::Result<Outcome> {
    let loaded = load(&args.common.model)?;
    let model = &loaded.model;
    let nodes = report_nodes(model, &args.nodes)?;
    let system = assemble(model, Bearings::Linearised);
    let result = lib(unbalance_response_refined(
        model,
        &system,
        &Speeds::or_default(&args.speeds, model, 2.0 * std::f64::consts::PI, 800),
        &nodes,
    ))?;
    let mut out = Output::begin(&args.common.out_dir("unbalance"))?;
    write_tables(&mut out, &result)?;
    let common = &args.common;
    out.plot("bode", |stem| {
        common
            .speed_axis(plots::bode(&result), SpeedAxis::X)
            .save(stem)
    })?;
    out.plot("polar", |stem| plots::polar(&result).save(stem))?;
    out.plot("orbit_major", |stem| {
        common
            .speed_axis(plots::orbit_major(&result), SpeedAxis::X)
            .save(stem)
    })?;
    let text = text(&model.name, &nodes, &result);
    finish(out, summary(&loaded, &result), text, &args.common)
}

fn summary<'a>(loaded: &Loaded, result: &'a UnbalanceResult) -> Summary<'a> {
    let speeds_hz = &result.speeds_hz;
    Summary {
        head: Head::new("unbalance", loaded),
        speed_range_hz: [speeds_hz.first(), speeds_hz.last()],
        speed_count: speeds_hz.len(),
        operating_speed_hz: result.operating_hz,
        api617_status: api617_status(result),
        nodes: result
            .nodes
            .iter()
            .map(|r| {
                let (k, max) = largest(&r.major);
                NodeSummary {
                    node: r.node,
                    z_m: r.z,
                    max_major_semi_axis_m: max,
                    max_major_semi_axis_speed_hz: speeds_hz.get(k),
                    peaks: r.peaks.iter().map(PeakSummary::from).collect(),
                }
            })
            .collect(),
    }
}

/// The index and value of the largest entry (the first of equals; NaN when all are NaN).
fn largest(values: &[f64]) -> (usize, f64) {
    values
        .iter()
        .copied()
        .enumerate()
        .fold((0, f64::NAN), |a, (i, v)| {
            if v > a.1 || a.1.is_nan() {
                (i, v)
            } else {
                a
            }
        })
}

/// The lines printed without `--json`: every peak with its API 617 verdict.
fn text(name: &str, nodes: &[usize], result: &UnbalanceResult) -> String {
    let mut text = String::new();
    let _ = writeln!(
        text,
        "{name}: unbalance response at nodes {nodes:?}, {} speeds",
        result.speeds_hz.len()
    );
    for r in &result.nodes {
        for p in &r.peaks {
            let af = p
                .amplification_factor
                .map_or("-".into(), |a| format!("{a:.1}"));
            let api = match p.meets_api617 {
                Some(true) => "meets API 617",
                Some(false) => "FAILS API 617 margin",
                None if result.api617_note.is_some() => "API 617 margin not applicable",
                None => "",
            };
            let _ = writeln!(
                text,
                "  node {:3}: peak {:.3e} m at {:.2} Hz ({:.0} rpm), AF {af} {api}",
                r.node,
                p.amplitude,
                p.speed_hz,
                60.0 * p.speed_hz
            );
        }
    }
    if let Some(note) = &result.api617_note {
        let _ = writeln!(text, "API 617 separation margins {note}");
    }
    text
}

/// The summary's verdict on the API 617 margins: "assessed" (see each peak's
/// `meets_api617`), the reason they are not applicable, or "no operating range".
fn api617_status(result: &UnbalanceResult) -> String {
    match (&result.api617_note, result.operating_hz) {
        (Some(note), _) => note.clone(),
        (None, Some(_)) => "assessed".to_string(),
        (None, None) => "no operating range: give [operating] min_speed and max_speed to assess separation margins".to_string(),
    }
}

/// `unbalance.csv` and `peaks.csv`.
fn write_tables(out: &mut Output, result: &UnbalanceResult) -> miette::Result<()> {
    let mut h = header(&["speed_hz", "speed_rpm"]);
    for r in &result.nodes {
        for q in [
            "ux_amplitude_m",
            "ux_phase_deg",
            "uy_amplitude_m",
            "uy_phase_deg",
            "major_semi_axis_m",
            "minor_semi_axis_m",
            "whirl",
        ] {
            h.push(format!("n{}_{q}", r.node));
        }
    }
    let rows: Vec<Vec<String>> = result
        .speeds_hz
        .iter()
        .enumerate()
        .map(|(i, f)| {
            let mut row = vec![num(*f), num(60.0 * f)];
            for r in &result.nodes {
                row.extend([
                    num(r.ux_amplitude[i]),
                    num(r.ux_phase_deg[i]),
                    num(r.uy_amplitude[i]),
                    num(r.uy_phase_deg[i]),
                    num(r.major[i]),
                    num(r.minor[i]),
                    r.whirl[i].name().to_string(),
                ]);
            }
            row
        })
        .collect();
    out.csv("unbalance.csv", &h, &rows)?;
    let h = header(&[
        "node",
        "z_m",
        "speed_hz",
        "speed_rpm",
        "major_semi_axis_m",
        "half_power_low_hz",
        "half_power_high_hz",
        "amplification_factor",
        "api617_required_margin_pct",
        "api617_actual_margin_pct",
        "meets_api617",
    ]);
    let mut rows = Vec::new();
    for r in &result.nodes {
        for p in &r.peaks {
            rows.push(vec![
                r.node.to_string(),
                num(r.z),
                num(p.speed_hz),
                num(60.0 * p.speed_hz),
                num(p.amplitude),
                opt(p.half_power_hz.map(|b| b.0)),
                opt(p.half_power_hz.map(|b| b.1)),
                opt(p.amplification_factor),
                opt(p.required_margin_pct),
                opt(p.actual_margin_pct),
                match (p.meets_api617, &result.api617_note) {
                    (Some(m), _) => m.to_string(),
                    (None, Some(_)) => "not applicable".to_string(),
                    (None, None) => String::new(),
                },
            ]);
        }
    }
    out.csv("peaks.csv", &h, &rows)
}
