//! `whirl static model.toml [--rollers hertz|linear]`: static response under gravity.
//!
//! Writes `stations.csv` (deflection, slope, bending moment and shear force at both ends of
//! every element, so jumps at disks and bearings show), `reactions.csv` (each bearing's
//! displacement and force on the shaft), `rollers.csv` (each roller's angle, approach and
//! load, for roller bearings with Hertz contacts) and the plots `static_response` and
//! `roller_loads`. The summary gives the largest deflection and where, the reactions and
//! their sum against the rotor's weight. See [`whirl::statics`] for the conventions.

use std::fmt::Write;

use whirl::bearing::RatingSource;
use whirl::given::Choice;
use whirl::report::Report;
use whirl::statics::{static_response, RollerSupport};

use super::{default_is, finish, lib, load, report_summary, Common, Outcome};
use crate::output::Output;

/// `whirl static`
#[derive(Debug, clap::Args)]
pub struct Args {
    #[command(flatten)]
    pub common: Common,
    #[arg(long, value_enum,
          help = default_is("How roller bearings carry the load.", RollerSupport::default().choice_name()))]
    pub rollers: Option<RollerSupport>,
}

pub fn run(args: &Args) -> miette::Result<Outcome> {
    let loaded = load(&args.common.model)?;
    let model = &loaded.model;
    let rollers = args.rollers.unwrap_or_default();
    let result = lib(static_response(model, rollers))?;
    let total = result.total_reaction();
    let (ms, vs) = (result.largest_moment().1, result.largest_shear().1);
    let summary = report_summary("static", &loaded, &result)?;

    let mut text = String::new();
    let _ = writeln!(
        text,
        "{}: static response under gravity ({} m/s^2), roller bearings {}",
        model.name,
        model.gravity,
        match rollers {
            RollerSupport::Hertz => "by Hertz contact",
            RollerSupport::Linear => "by their linear stiffness",
        }
    );
    let _ = writeln!(
        text,
        "  largest deflection {:.4e} m at node {} (z = {:.4} m); largest moment {:.4e} N m, shear {:.4e} N",
        result.max_deflection.value, result.max_deflection.node, result.max_deflection.z, ms, vs
    );
    for r in &result.reactions {
        let _ = writeln!(
            text,
            "  {:<12} node {:3}: force on shaft ({:.4}, {:.4}) N, displacement ({:.3e}, {:.3e}) m",
            r.name, r.node, r.force[0], r.force[1], r.displacement[0], r.displacement[1]
        );
        if let Some(life) = &r.life {
            let l10 = life
                .l10_million_revolutions
                .map_or("none (axial load)".to_string(), |l| format!("{l:.4e}"));
            let _ = writeln!(
                text,
                "  {:<12} life [million rev]: L10 {l10}, reference {:.4e} (C = {:.0} N, {})",
                "",
                life.reference_life_million_revolutions,
                life.dynamic_load_rating_n,
                match life.rating_source {
                    RatingSource::Catalogue => "catalogue",
                    RatingSource::Iso281Formula => "ISO 281 formula",
                }
            );
        }
    }
    let _ = writeln!(
        text,
        "  reactions sum to {:.6} N against a weight of {:.6} N",
        total[1], result.weight
    );

    let mut out = Output::begin(&args.common.out_dir("static"))?;
    for table in result.tables() {
        out.table(&table)?;
    }
    out.figures(whirl_figures::statics(model, &result), args.common.rpm)?;
    finish(out, summary, text, &args.common)
}
