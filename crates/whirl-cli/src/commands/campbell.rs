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

use serde_json::{json, Value};
use whirl::fe::{assemble, Bearings};
use whirl::modal::{campbell, CampbellOptions};

use super::{
    finish, lib, load, mode_count, speeds, summary_head, whirl_labels, Common, Outcome, Speeds,
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

pub fn run(args: &Args) -> miette::Result<Outcome> {
    let loaded = load(&args.common.model)?;
    let model = &loaded.model;
    let system = assemble(model, Bearings::Linearised);
    let options = CampbellOptions {
        speeds: Speeds::or_default(&args.speeds, model, 0.0, 161),
        modes: args.modes,
        orders: args.orders.clone(),
        basis_size: (!args.full).then(|| CampbellOptions::default_basis(args.modes)),
        max_damping_ratio: 0.9,
    };
    let result = lib(campbell(&system, &options))?;
    let labels = whirl_labels(&result.branches.iter().map(|b| b.whirl).collect::<Vec<_>>());
    let label_of = |branch: usize| {
        result
            .branches
            .iter()
            .position(|b| b.index == branch)
            .map(|i| labels[i].clone())
            .unwrap_or_else(|| format!("branch {branch}"))
    };
    let speeds_hz = &result.speeds_hz;

    let mut s = summary_head("campbell", &loaded);
    s.insert(
        "speed_range_hz".into(),
        json!([speeds_hz.first(), speeds_hz.last()]),
    );
    s.insert("speed_count".into(), speeds_hz.len().into());
    s.insert("orders".into(), json!(result.orders));
    s.insert("basis_size".into(), result.basis_size.into());
    s.insert(
        "branches".into(),
        result
            .branches
            .iter()
            .zip(&labels)
            .map(|(b, l)| {
                json!({
                    "label": l, "whirl": b.whirl.name(),
                    "frequency_at_first_speed_hz": b.frequency_hz.first(),
                    "frequency_at_last_speed_hz": b.frequency_hz.last(),
                    "min_log_decrement": b.log_decrement.iter().copied()
                        .filter(|x| x.is_finite()).fold(f64::INFINITY, f64::min),
                })
            })
            .collect::<Vec<_>>()
            .into(),
    );
    s.insert(
        "critical_speeds".into(),
        result
            .critical_speeds
            .iter()
            .map(|c| {
                json!({
                    "speed_hz": c.speed_hz, "speed_rpm": c.speed_rpm,
                    "frequency_hz": c.frequency_hz, "order": c.order,
                    "branch": label_of(c.branch), "whirl": c.whirl.name(),
                    "damping_ratio": c.damping_ratio,
                })
            })
            .collect::<Vec<_>>()
            .into(),
    );

    let mut text = String::new();
    let _ = writeln!(
        text,
        "{}: {} branches over {} speeds (basis of {} modes)",
        model.name,
        result.branches.len(),
        speeds_hz.len(),
        result.basis_size
    );
    for (b, l) in result.branches.iter().zip(&labels) {
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
            label_of(c.branch),
            order_name(c.order),
            c.damping_ratio
        );
    }

    let mut out = Output::begin(&args.common.out_dir("campbell"))?;
    let mut h = vec!["speed_hz".to_string(), "speed_rpm".to_string()];
    for l in &labels {
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
                label_of(c.branch),
                c.whirl.name().to_string(),
                num(c.damping_ratio),
            ]
        })
        .collect();
    out.csv("critical_speeds.csv", &h, &rows)?;
    out.plot("campbell", |stem| {
        plots::campbell(model, &result, &labels).save(stem)
    })?;
    out.plot("log_decrement", |stem| {
        plots::log_decrement(&result, &labels).save(stem)
    })?;
    finish(out, Value::Object(s), text, &args.common)
}
