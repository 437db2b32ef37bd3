//! `whirl check model.toml`: validate a model and summarise it.
//!
//! Writes `summary.json` (mesh, masses, supports, the first six undamped frequencies),
//! `nodes.csv` (each node's position and what sits there), `frequencies.csv` and the rotor
//! layout plot `rotor.png`/`.svg`.

use std::fmt::Write;

use serde::Serialize;
use whirl::fe::{assemble_banded, Bearings, DOFS_PER_NODE};
use whirl::modal::undamped_modes;
use whirl::model::{Clearance, LinearBearing, Model, RollerBearing};

use super::{finish, hz, lib, load, Common, Head, Loaded, Outcome};
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

fn clearance_at_rest(c: &Clearance) -> f64 {
    c.at_speed(0.0)
}

/// summary.json of `whirl check`: the model as read, with units in the keys.
#[derive(Serialize)]
struct Summary<'a> {
    #[serde(flatten)]
    head: Head,
    nodes: usize,
    dofs: usize,
    elements: usize,
    shaft_sections: usize,
    shaft_length_m: f64,
    shaft_mass_kg: f64,
    disk_mass_kg: f64,
    total_mass_kg: f64,
    gravity_m_per_s2: f64,
    disks: Vec<DiskSummary<'a>>,
    bearings: Vec<BearingSummary<'a>>,
    roller_bearings: Vec<RollerSummary<'a>>,
    unbalances: Vec<UnbalanceSummary>,
    rayleigh_damping: RayleighSummary,
    operating_speed_hz: Option<[f64; 2]>,
    undamped_frequencies_hz: &'a [f64],
}

#[derive(Serialize)]
struct DiskSummary<'a> {
    name: &'a str,
    node: usize,
    z_m: f64,
    mass_kg: f64,
    polar_inertia_kg_m2: f64,
    diametral_inertia_kg_m2: f64,
}

#[derive(Serialize)]
struct BearingSummary<'a> {
    name: &'a str,
    node: usize,
    z_m: f64,
    stiffness_n_per_m: StiffnessSummary,
    damping_n_s_per_m: DampingSummary,
}

#[derive(Serialize)]
struct StiffnessSummary {
    kxx: f64,
    kxy: f64,
    kyx: f64,
    kyy: f64,
}

#[derive(Serialize)]
struct DampingSummary {
    cxx: f64,
    cxy: f64,
    cyx: f64,
    cyy: f64,
}

#[derive(Serialize)]
struct RollerSummary<'a> {
    name: &'a str,
    node: usize,
    z_m: f64,
    rollers: usize,
    pitch_diameter_m: f64,
    roller_diameter_m: f64,
    roller_length_m: f64,
    clearance_at_rest_m: f64,
    contact_stiffness_n_per_m_pow_n: f64,
    contact_exponent: f64,
    contact_damping_n_s_per_m: f64,
    linear_stiffness_n_per_m: f64,
    linear_damping_n_s_per_m: f64,
}

#[derive(Serialize)]
struct UnbalanceSummary {
    node: usize,
    z_m: f64,
    mass_radius_kg_m: f64,
    phase_deg: f64,
}

#[derive(Serialize)]
struct RayleighSummary {
    alpha_per_s: f64,
    beta_s: f64,
}

/// Masses and mesh size.
struct Sizes {
    shaft: f64,
    disks: f64,
    elements: usize,
}

impl Sizes {
    fn of(model: &Model) -> Sizes {
        Sizes {
            shaft: model.shaft_mass(),
            disks: model.disks.iter().map(|d| d.mass).sum(),
            elements: model.sections.iter().map(|s| s.elements).sum(),
        }
    }
}

pub fn run(args: &Args) -> miette::Result<Outcome> {
    let loaded = load(&args.common.model)?;
    let model = &loaded.model;
    let system = assemble_banded(model, Bearings::Linearised);
    let modes = lib(undamped_modes(&system, FREQUENCIES))?;
    let f = &modes.frequencies_hz;
    let sizes = Sizes::of(model);
    let mut out = Output::begin(&args.common.out_dir("check"))?;
    write_tables(&mut out, model, f)?;
    out.plot("rotor", |stem| plots::rotor_layout(model).save(stem))?;
    let text = text(model, &sizes, f);
    finish(out, summary(&loaded, &sizes, f), text, &args.common)
}

fn summary<'a>(loaded: &'a Loaded, sizes: &Sizes, frequencies: &'a [f64]) -> Summary<'a> {
    let model = &loaded.model;
    Summary {
        head: Head::new("check", loaded),
        nodes: model.node_count(),
        dofs: DOFS_PER_NODE * model.node_count(),
        elements: sizes.elements,
        shaft_sections: model.sections.len(),
        shaft_length_m: model.length(),
        shaft_mass_kg: sizes.shaft,
        disk_mass_kg: sizes.disks,
        total_mass_kg: sizes.shaft + sizes.disks,
        gravity_m_per_s2: model.gravity,
        disks: model
            .disks
            .iter()
            .map(|d| DiskSummary {
                name: &d.name,
                node: d.station.node,
                z_m: d.station.z,
                mass_kg: d.mass,
                polar_inertia_kg_m2: d.polar_inertia,
                diametral_inertia_kg_m2: d.diametral_inertia,
            })
            .collect(),
        bearings: model.bearings.iter().map(bearing_summary).collect(),
        roller_bearings: model.roller_bearings.iter().map(roller_summary).collect(),
        unbalances: model
            .unbalances
            .iter()
            .map(|u| UnbalanceSummary {
                node: u.station.node,
                z_m: u.station.z,
                mass_radius_kg_m: u.mass_radius,
                phase_deg: u.phase.to_degrees(),
            })
            .collect(),
        rayleigh_damping: RayleighSummary {
            alpha_per_s: model.damping.alpha,
            beta_s: model.damping.beta,
        },
        operating_speed_hz: model.operating.map(|(a, b)| [hz(a), hz(b)]),
        undamped_frequencies_hz: frequencies,
    }
}

fn bearing_summary(b: &LinearBearing) -> BearingSummary<'_> {
    BearingSummary {
        name: &b.name,
        node: b.station.node,
        z_m: b.station.z,
        stiffness_n_per_m: StiffnessSummary {
            kxx: b.stiffness[0][0],
            kxy: b.stiffness[0][1],
            kyx: b.stiffness[1][0],
            kyy: b.stiffness[1][1],
        },
        damping_n_s_per_m: DampingSummary {
            cxx: b.damping[0][0],
            cxy: b.damping[0][1],
            cyx: b.damping[1][0],
            cyy: b.damping[1][1],
        },
    }
}

fn roller_summary(b: &RollerBearing) -> RollerSummary<'_> {
    RollerSummary {
        name: &b.name,
        node: b.station.node,
        z_m: b.station.z,
        rollers: b.rollers,
        pitch_diameter_m: b.pitch_diameter,
        roller_diameter_m: b.roller_diameter,
        roller_length_m: b.roller_length,
        clearance_at_rest_m: clearance_at_rest(&b.clearance),
        contact_stiffness_n_per_m_pow_n: b.contact_stiffness,
        contact_exponent: b.contact_exponent,
        contact_damping_n_s_per_m: b.contact_damping,
        linear_stiffness_n_per_m: b.linear_stiffness,
        linear_damping_n_s_per_m: b.linear_damping,
    }
}

/// The lines printed without `--json`.
fn text(model: &Model, sizes: &Sizes, frequencies: &[f64]) -> String {
    let mut text = String::new();
    let _ = writeln!(
        text,
        "{}: valid\n  mesh: {} nodes, {} DOFs, {} elements in {} section(s), shaft {:.4} m",
        model.name,
        model.node_count(),
        DOFS_PER_NODE * model.node_count(),
        sizes.elements,
        model.sections.len(),
        model.length()
    );
    let _ = writeln!(
        text,
        "  mass: {:.3} kg (shaft {:.3} kg, disks {:.3} kg)",
        sizes.shaft + sizes.disks,
        sizes.shaft,
        sizes.disks
    );
    let _ = writeln!(
        text,
        "  {} disk(s), {} linear bearing(s), {} roller bearing(s), {} unbalance(s)",
        model.disks.len(),
        model.bearings.len(),
        model.roller_bearings.len(),
        model.unbalances.len()
    );
    let list: Vec<String> = frequencies.iter().map(|x| format!("{x:.2}")).collect();
    let _ = writeln!(text, "  undamped frequencies [Hz]: {}", list.join(", "));
    text
}

/// `nodes.csv` and `frequencies.csv`.
fn write_tables(out: &mut Output, model: &Model, frequencies: &[f64]) -> miette::Result<()> {
    let z = model.node_positions();
    let features = model.node_features();
    let rows: Vec<Vec<String>> = (0..model.node_count())
        .map(|n| vec![n.to_string(), num(z[n]), features[n].clone()])
        .collect();
    out.csv("nodes.csv", &header(&["node", "z_m", "features"]), &rows)?;
    let rows: Vec<Vec<String>> = frequencies
        .iter()
        .enumerate()
        .map(|(i, x)| vec![(i + 1).to_string(), num(*x)])
        .collect();
    out.csv("frequencies.csv", &header(&["mode", "frequency_hz"]), &rows)
}
