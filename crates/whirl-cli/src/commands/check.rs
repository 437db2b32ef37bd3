//! `whirl check model.toml`: validate a model and summarise it.
//!
//! Writes `summary.json` (mesh, masses, supports, the first six undamped frequencies),
//! `nodes.csv` (each node's position and what sits there), `frequencies.csv` and the rotor
//! layout plot `rotor.png`/`.svg`.

use std::fmt::Write;

use serde_json::{json, Value};
use whirl::fe::{assemble, Bearings, DOFS_PER_NODE};
use whirl::modal::undamped_modes;
use whirl::model::{Clearance, Model};

use super::{finish, hz, lib, load, summary_head, Common, Outcome};
use crate::output::{header, num, Output};
use crate::plots;

/// Undamped frequencies listed by `check`.
const FREQUENCIES: usize = 6;

/// `whirl check`
#[derive(Debug, clap::Args)]
pub struct Args {
    #[command(flatten)]
    pub common: Common,
}

/// Total mass of the shaft sections, kg.
pub fn shaft_mass(model: &Model) -> f64 {
    model
        .sections
        .iter()
        .map(|s| s.material.density * s.area() * s.length)
        .sum()
}

/// What sits at each node, e.g. `disk; bearing A`.
pub fn node_features(model: &Model) -> Vec<String> {
    let mut f = vec![Vec::<String>::new(); model.node_count()];
    for d in &model.disks {
        f[d.station.node].push(d.name.clone());
    }
    for b in &model.bearings {
        f[b.station.node].push(b.name.clone());
    }
    for b in &model.roller_bearings {
        f[b.station.node].push(b.name.clone());
    }
    for (i, u) in model.unbalances.iter().enumerate() {
        f[u.station.node].push(format!("unbalance {i}"));
    }
    f.into_iter().map(|v| v.join("; ")).collect()
}

fn clearance_at_rest(c: &Clearance) -> f64 {
    c.at_speed(0.0)
}

pub fn run(args: &Args) -> miette::Result<Outcome> {
    let loaded = load(&args.common.model)?;
    let model = &loaded.model;
    let system = assemble(model, Bearings::Linearised);
    let modes = lib(undamped_modes(&system, FREQUENCIES))?;
    let f = &modes.frequencies_hz;

    let shaft = shaft_mass(model);
    let disks: f64 = model.disks.iter().map(|d| d.mass).sum();
    let elements: usize = model.sections.iter().map(|s| s.elements).sum();
    let z = model.node_positions();

    let mut s = summary_head("check", &loaded);
    s.insert("nodes".into(), model.node_count().into());
    s.insert("dofs".into(), (DOFS_PER_NODE * model.node_count()).into());
    s.insert("elements".into(), elements.into());
    s.insert("shaft_sections".into(), model.sections.len().into());
    s.insert("shaft_length_m".into(), model.length().into());
    s.insert("shaft_mass_kg".into(), shaft.into());
    s.insert("disk_mass_kg".into(), disks.into());
    s.insert("total_mass_kg".into(), (shaft + disks).into());
    s.insert("gravity_m_per_s2".into(), model.gravity.into());
    s.insert(
        "disks".into(),
        model
            .disks
            .iter()
            .map(|d| {
                json!({
                    "name": d.name, "node": d.station.node, "z_m": d.station.z,
                    "mass_kg": d.mass, "polar_inertia_kg_m2": d.polar_inertia,
                    "diametral_inertia_kg_m2": d.diametral_inertia,
                })
            })
            .collect::<Vec<_>>()
            .into(),
    );
    s.insert(
        "bearings".into(),
        model
            .bearings
            .iter()
            .map(|b| {
                json!({
                    "name": b.name, "node": b.station.node, "z_m": b.station.z,
                    "stiffness_n_per_m": {"kxx": b.stiffness[0][0], "kxy": b.stiffness[0][1],
                                          "kyx": b.stiffness[1][0], "kyy": b.stiffness[1][1]},
                    "damping_n_s_per_m": {"cxx": b.damping[0][0], "cxy": b.damping[0][1],
                                          "cyx": b.damping[1][0], "cyy": b.damping[1][1]},
                })
            })
            .collect::<Vec<_>>()
            .into(),
    );
    s.insert(
        "roller_bearings".into(),
        model
            .roller_bearings
            .iter()
            .map(|b| {
                json!({
                    "name": b.name, "node": b.station.node, "z_m": b.station.z,
                    "rollers": b.rollers, "pitch_diameter_m": b.pitch_diameter,
                    "roller_diameter_m": b.roller_diameter, "roller_length_m": b.roller_length,
                    "clearance_at_rest_m": clearance_at_rest(&b.clearance),
                    "contact_stiffness_n_per_m_pow_n": b.contact_stiffness,
                    "contact_exponent": b.contact_exponent,
                    "contact_damping_n_s_per_m": b.contact_damping,
                    "linear_stiffness_n_per_m": b.linear_stiffness,
                    "linear_damping_n_s_per_m": b.linear_damping,
                })
            })
            .collect::<Vec<_>>()
            .into(),
    );
    s.insert(
        "unbalances".into(),
        model
            .unbalances
            .iter()
            .map(|u| {
                json!({"node": u.station.node, "z_m": u.station.z,
                       "mass_radius_kg_m": u.mass_radius, "phase_deg": u.phase.to_degrees()})
            })
            .collect::<Vec<_>>()
            .into(),
    );
    s.insert(
        "rayleigh_damping".into(),
        json!({"alpha_per_s": model.damping.alpha, "beta_s": model.damping.beta}),
    );
    s.insert(
        "operating_speed_hz".into(),
        model
            .operating
            .map(|(a, b)| json!([hz(a), hz(b)]))
            .unwrap_or(Value::Null),
    );
    s.insert("undamped_frequencies_hz".into(), json!(f));

    let mut text = String::new();
    let _ = writeln!(
        text,
        "{}: valid\n  mesh: {} nodes, {} DOFs, {} elements in {} section(s), shaft {:.4} m",
        model.name,
        model.node_count(),
        DOFS_PER_NODE * model.node_count(),
        elements,
        model.sections.len(),
        model.length()
    );
    let _ = writeln!(
        text,
        "  mass: {:.3} kg (shaft {:.3} kg, disks {:.3} kg)",
        shaft + disks,
        shaft,
        disks
    );
    let _ = writeln!(
        text,
        "  {} disk(s), {} linear bearing(s), {} roller bearing(s), {} unbalance(s)",
        model.disks.len(),
        model.bearings.len(),
        model.roller_bearings.len(),
        model.unbalances.len()
    );
    let list: Vec<String> = f.iter().map(|x| format!("{x:.2}")).collect();
    let _ = writeln!(text, "  undamped frequencies [Hz]: {}", list.join(", "));

    let mut out = Output::begin(&args.common.out_dir("check"))?;
    let features = node_features(model);
    let rows: Vec<Vec<String>> = (0..model.node_count())
        .map(|n| vec![n.to_string(), num(z[n]), features[n].clone()])
        .collect();
    out.csv("nodes.csv", &header(&["node", "z_m", "features"]), &rows)?;
    let rows: Vec<Vec<String>> = f
        .iter()
        .enumerate()
        .map(|(i, x)| vec![(i + 1).to_string(), num(*x)])
        .collect();
    out.csv("frequencies.csv", &header(&["mode", "frequency_hz"]), &rows)?;
    out.plot("rotor", |stem| plots::rotor_layout(model).save(stem))?;
    finish(out, Value::Object(s), text, &args.common)
}
