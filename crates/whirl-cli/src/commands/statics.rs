//! `whirl static model.toml [--rollers hertz|linear]`: static response under gravity.
//!
//! Writes `stations.csv` (deflection, slope, bending moment and shear force at both ends of
//! every element, so jumps at disks and bearings show), `reactions.csv` (each bearing's
//! displacement and force on the shaft), `rollers.csv` (each roller's angle, approach and
//! load, for roller bearings with Hertz contacts) and the plots `static_response` and
//! `roller_loads`. The summary gives the largest deflection and where, the reactions and
//! their sum against the rotor's weight. See [`whirl::statics`] for the conventions.

use std::fmt::Write;

use serde_json::{json, Value};
use whirl::statics::{static_response, RollerSupport, StaticResult};

use super::{finish, lib, load, summary_head, Common, Outcome};
use crate::output::{header, num, Output};
use crate::plots;

/// `whirl static`
#[derive(Debug, clap::Args)]
pub struct Args {
    #[command(flatten)]
    pub common: Common,
    /// How roller bearings carry the load [default: hertz].
    #[arg(long, value_enum, default_value = "hertz")]
    pub rollers: RollerSupport,
}

pub fn run(args: &Args) -> miette::Result<Outcome> {
    let loaded = load(&args.common.model)?;
    let model = &loaded.model;
    let result = lib(static_response(model, args.rollers))?;
    let total = result.total_reaction();

    let mut s = summary_head("static", &loaded);
    s.insert("gravity_m_s2".into(), model.gravity.into());
    s.insert("roller_support".into(), json!(result.roller_support));
    s.insert("weight_n".into(), result.weight.into());
    s.insert(
        "max_deflection".into(),
        json!({
            "deflection_m": result.max_deflection.value,
            "node": result.max_deflection.node,
            "z_m": result.max_deflection.z,
        }),
    );
    let (mi, ms) = extreme(&result, |st| st.moment[1].hypot(st.moment[0]));
    s.insert(
        "max_bending_moment".into(),
        json!({ "moment_nm": ms, "node": result.stations[mi].node, "z_m": result.stations[mi].z }),
    );
    let (vi, vs) = extreme(&result, |st| st.shear[1].hypot(st.shear[0]));
    s.insert(
        "max_shear_force".into(),
        json!({ "shear_n": vs, "node": result.stations[vi].node, "z_m": result.stations[vi].z }),
    );
    s.insert(
        "reactions".into(),
        result
            .reactions
            .iter()
            .map(|r| {
                json!({
                    "bearing": r.name, "node": r.node, "z_m": r.z, "kind": r.kind,
                    "displacement_m": r.displacement, "force_n": r.force,
                    "rollers_loaded": r.rollers.iter().filter(|q| q.force > 0.0).count(),
                    "max_roller_load_n": r.rollers.iter().map(|q| q.force).fold(None, |m: Option<f64>, f| Some(m.map_or(f, |m| m.max(f)))),
                })
            })
            .collect::<Vec<_>>()
            .into(),
    );
    s.insert("reaction_sum_n".into(), json!(total));
    s.insert(
        "reaction_sum_over_weight".into(),
        json!(total[1] / result.weight),
    );

    let mut text = String::new();
    let _ = writeln!(
        text,
        "{}: static response under gravity ({} m/s^2), roller bearings {}",
        model.name,
        model.gravity,
        match args.rollers {
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
    }
    let _ = writeln!(
        text,
        "  reactions sum to {:.6} N against a weight of {:.6} N",
        total[1], result.weight
    );

    let mut out = Output::begin(&args.common.out_dir("static"))?;
    write_tables(&mut out, &result)?;
    out.plot("static_response", |stem| {
        plots::static_response(model, &result).save(stem)
    })?;
    if result.reactions.iter().any(|r| !r.rollers.is_empty()) {
        out.plot("roller_loads", |stem| {
            plots::roller_loads(model, &result).save(stem)
        })?;
    }
    finish(out, Value::Object(s), text, &args.common)
}

/// Index and value of the largest `f` over the stations.
fn extreme(result: &StaticResult, f: impl Fn(&whirl::statics::Station) -> f64) -> (usize, f64) {
    result
        .stations
        .iter()
        .map(f)
        .enumerate()
        .fold(
            (0, f64::NEG_INFINITY),
            |a, (i, v)| if v > a.1 { (i, v) } else { a },
        )
}

fn write_tables(out: &mut Output, result: &StaticResult) -> miette::Result<()> {
    let h = header(&[
        "z_m",
        "node",
        "element",
        "ux_m",
        "uy_m",
        "slope_x_rad",
        "slope_y_rad",
        "moment_x_nm",
        "moment_y_nm",
        "shear_x_n",
        "shear_y_n",
    ]);
    let rows: Vec<Vec<String>> = result
        .stations
        .iter()
        .map(|s| {
            vec![
                num(s.z),
                s.node.to_string(),
                s.element.to_string(),
                num(s.deflection[0]),
                num(s.deflection[1]),
                num(s.slope[0]),
                num(s.slope[1]),
                num(s.moment[0]),
                num(s.moment[1]),
                num(s.shear[0]),
                num(s.shear[1]),
            ]
        })
        .collect();
    out.csv("stations.csv", &h, &rows)?;
    let h = header(&[
        "bearing", "node", "z_m", "kind", "ux_m", "uy_m", "fx_n", "fy_n",
    ]);
    let rows: Vec<Vec<String>> = result
        .reactions
        .iter()
        .map(|r| {
            vec![
                r.name.clone(),
                r.node.to_string(),
                num(r.z),
                r.kind.to_string(),
                num(r.displacement[0]),
                num(r.displacement[1]),
                num(r.force[0]),
                num(r.force[1]),
            ]
        })
        .collect();
    out.csv("reactions.csv", &h, &rows)?;
    if result.reactions.iter().any(|r| !r.rollers.is_empty()) {
        let h = header(&["bearing", "roller", "angle_deg", "approach_m", "force_n"]);
        let rows: Vec<Vec<String>> = result
            .reactions
            .iter()
            .flat_map(|r| {
                r.rollers.iter().enumerate().map(move |(j, q)| {
                    vec![
                        r.name.clone(),
                        j.to_string(),
                        num(q.angle_deg),
                        num(q.approach),
                        num(q.force),
                    ]
                })
            })
            .collect();
        out.csv("rollers.csv", &h, &rows)?;
    }
    Ok(())
}
