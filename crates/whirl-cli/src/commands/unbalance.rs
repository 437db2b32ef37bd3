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

use whirl::fe::{assemble_banded, Bearings};
use whirl::report::Report;
use whirl::response::{
    default_unbalance_speeds, unbalance_response_refined, UnbalanceResult,
    DEFAULT_UNBALANCE_FROM_HZ, DEFAULT_UNBALANCE_SPEEDS,
};

use super::{
    default_is, finish, lib, load, report_summary, round_off_note, speeds, Common, Nodes, Outcome,
    Speeds,
};
use crate::output::Output;
use crate::progress::shown;

/// `whirl unbalance`
#[derive(Debug, clap::Args)]
pub struct Args {
    #[command(flatten)]
    pub common: Common,
    #[arg(long, value_name = "RANGE", value_parser = speeds,
          help = default_is("Spin speeds `start:stop:count`, e.g. `1:800Hz:800`; plain numbers are rad/s.",
              format_args!("{DEFAULT_UNBALANCE_SPEEDS} speeds from {DEFAULT_UNBALANCE_FROM_HZ} Hz to 1.2 x the model's top operating speed")))]
    pub speeds: Option<Speeds>,
    #[command(flatten)]
    pub nodes: Nodes,
}

pub fn run(args: &Args) -> miette::Result<Outcome> {
    let loaded = load(&args.common.model)?;
    let model = &loaded.model;
    let nodes = args.nodes.resolve(model)?;
    let system = assemble_banded(model, Bearings::Linearised);
    let speeds = Speeds::or_default(&args.speeds, || default_unbalance_speeds(model));
    let result = lib(shown("unbalance", |p| {
        unbalance_response_refined(model, &system, &speeds, &nodes, p)
    }))?;
    let mut out = Output::begin(&args.common.out_dir("unbalance"))?;
    for table in result.tables() {
        out.table(&table)?;
    }
    out.figures(whirl_figures::unbalance(&result), args.common.rpm)?;
    let text = text(&model.name, &nodes, &result);
    let summary = report_summary("unbalance", &loaded, &result)?;
    finish(out, summary, text, &args.common)
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
    for r in &result.nodes {
        if let Some(note) = round_off_note(&r.maxima_within_round_off_hz) {
            let _ = writeln!(text, "  node {:3}: {note}", r.node);
        }
    }
    if let Some(note) = &result.api617_note {
        let _ = writeln!(text, "API 617 separation margins {note}");
    }
    text
}
