//! `whirl stiffness model.toml [--bearing 0] [--clearances 10um:120um:12] [--load 60N]
//! [--load-angle -90] [--cage-angle -90] [--cage-steps 32] [--surface-clearances 20um,60um]
//! [--grid 41]`: equivalent stiffness of a roller bearing versus clearance and its
//! force-deflection surfaces (thesis section 3.4, figs. 3.8-3.10).
//!
//! Three stiffnesses per clearance, all the 2x2 tangent -dF/du of the Hertz contacts without
//! damping (see `whirl::bearing::stiffness`):
//!
//! - `frozen`: at the static equilibrium under the load, the cage held with roller 0 on the
//!   load line (at the bottom under gravity) unless `--cage-angle` says otherwise;
//! - `averaged`: the equilibrium solved again at `--cage-steps` cage positions across one
//!   roller pitch and the tangents averaged, with their smallest and largest values;
//! - `fixed`: at one journal displacement for every clearance, the frozen equilibrium of the
//!   largest clearance, where that bearing carries the load: smaller clearances are pressed
//!   harder at the same position (eq. 3.25 read as a function of displacement).
//!
//! The load defaults to the bearing's share of the rotor weight: its reaction in a linear
//! static solve with gravity, roller bearings replaced by their `linear_stiffness`.
//!
//! Writes `stiffness.csv` (one row per clearance), `passage.csv` (one row per clearance and
//! cage position), `surfaces_<clearance>.csv` (F_x, F_y, F_r on a `--grid` x `--grid` grid
//! of displacements spanning twice the largest surface clearance each way), the plots
//! `stiffness_vs_clearance` and `surface_<clearance>_{fx,fy,fr}`, and `summary.json`.

use std::fmt::Write;

use whirl::bearing::stiffness::{
    clearance_label, force_surface, gravity_load, stiffness_versus_clearance, ForceSurface,
    FrozenBearing, StiffnessOptions, StiffnessReport, StiffnessStudy,
};
use whirl::model::{Model, RollerBearing};
use whirl::report::{index_list, Report};
use whirl::units::{parse_quantity, parse_range, Dimension};

use super::{finish, lib, load, report_summary, Common, Outcome};
use crate::error::Diag;
use crate::output::Output;
use crate::plots_stiffness;

/// `whirl stiffness`
#[derive(Debug, clap::Args)]
pub struct Args {
    #[command(flatten)]
    pub common: Common,
    /// Which roller bearing, by its order in the model file (0 = the first).
    #[arg(long, value_name = "INDEX", default_value = "0")]
    pub bearing: usize,
    /// Clearances `start:stop:count`, e.g. `10um:120um:12`; plain numbers are m.
    #[arg(long, value_name = "RANGE", default_value = "10um:120um:12", value_parser = clearance_range)]
    pub clearances: Clearances,
    /// Load the rotor puts on the bearing, e.g. `60N` or `2kN` [default: the bearing's share
    /// of the rotor weight, from a linear static solve with gravity].
    #[arg(long, value_name = "FORCE", value_parser = force)]
    pub load: Option<f64>,
    /// Direction of `--load`, degrees from +x towards +y (-90 = down, along gravity).
    #[arg(long, value_name = "DEG", default_value = "-90", requires = "load", value_parser = degrees, allow_hyphen_values = true)]
    pub load_angle: f64,
    /// Angle of roller 0 for the frozen cage, degrees from +x towards +y [default: on the
    /// load line].
    #[arg(long, value_name = "DEG", value_parser = degrees, allow_hyphen_values = true)]
    pub cage_angle: Option<f64>,
    /// Cage positions across one roller passage for the averaged stiffness.
    #[arg(long, value_name = "N", default_value = "32", value_parser = cage_steps)]
    pub cage_steps: usize,
    /// Clearances of the force-deflection surfaces, comma-separated.
    #[arg(long, value_name = "LIST", value_delimiter = ',', default_value = "20um,60um", value_parser = clearance)]
    pub surface_clearances: Vec<f64>,
    /// Points per side of the surfaces' displacement grid.
    #[arg(long, value_name = "N", default_value = "41", value_parser = grid_points)]
    pub grid: usize,
}

/// Clearances in m from `start:stop:count`.
#[derive(Debug, Clone)]
pub struct Clearances(pub Vec<f64>);

/// Clap parser of a clearance range; no clearance may be negative.
fn clearance_range(text: &str) -> Result<Clearances, String> {
    let c = parse_range(text, Dimension::Length).map_err(|e| e.to_string())?;
    if c.first().is_some_and(|&c0| c0 < 0.0) {
        return Err(format!("`{text}`: a clearance must not be negative"));
    }
    if c.len() > 1000 {
        return Err(format!("`{text}`: at most 1000 clearances"));
    }
    Ok(Clearances(c))
}

/// Clap parser of one clearance: a non-negative length.
fn clearance(text: &str) -> Result<f64, String> {
    let c = parse_quantity(text, Dimension::Length).map_err(|e| e.to_string())?;
    if c < 0.0 {
        return Err(format!("`{text}`: a clearance must not be negative"));
    }
    Ok(c)
}

/// Clap parser of a load: a positive force.
fn force(text: &str) -> Result<f64, String> {
    let f = parse_quantity(text, Dimension::Force).map_err(|e| e.to_string())?;
    if f <= 0.0 {
        return Err(format!("`{text}`: the load must be positive"));
    }
    Ok(f)
}

/// Clap parser of an angle in degrees.
fn degrees(text: &str) -> Result<f64, String> {
    match text.trim().parse::<f64>() {
        Ok(a) if a.is_finite() => Ok(a),
        _ => Err(format!("`{text}` is not an angle in degrees (e.g. -90)")),
    }
}

/// Clap parser of the cage positions per passage, 1 to 1000.
fn cage_steps(text: &str) -> Result<usize, String> {
    match text.trim().parse::<usize>() {
        Ok(n) if (1..=1000).contains(&n) => Ok(n),
        _ => Err(format!("`{text}` is not a whole number from 1 to 1000")),
    }
}

/// Clap parser of the surface grid size, 2 to 401 points per side.
fn grid_points(text: &str) -> Result<usize, String> {
    match text.trim().parse::<usize>() {
        Ok(n) if (2..=401).contains(&n) => Ok(n),
        _ => Err(format!("`{text}` is not a whole number from 2 to 401")),
    }
}

/// The roller bearing `index` of the model, or an error that lists what there is.
fn pick_bearing(model: &Model, index: usize) -> miette::Result<&RollerBearing> {
    if model.roller_bearings.is_empty() {
        return Err(Diag::new(
            "the model has no [[roller_bearing]]: the stiffness command needs one",
        )
        .help("add a [[roller_bearing]] table (see docs/model-file.md)")
        .into());
    }
    model.roller_bearings.get(index).ok_or_else(|| {
        let list: Vec<String> = model
            .roller_bearings
            .iter()
            .enumerate()
            .map(|(i, b)| format!("{i} = {}", b.name))
            .collect();
        Diag::option(
            "--bearing",
            format!(
                "the model has {} roller bearing(s) ({}); there is no bearing {index}",
                model.roller_bearings.len(),
                list.join(", ")
            ),
        )
        .into()
    })
}

/// The largest roller approach, as a fraction of the roller diameter, a load may cause:
/// Hertz contact theory holds for approaches of micrometres; a tenth of the roller would
/// crush it (steel yields long before).
const MAX_APPROACH_OVER_ROLLER: f64 = 0.1;

/// Refuses a load that would press the rollers further into the rings than contact theory
/// (or the steel) allows. Carried by N rollers of stiffness k and exponent n, a load F needs
/// the most loaded roller's approach delta to satisfy F <= N k delta^n, so
/// delta >= (F / (N k))^(1/n) whatever the clearance: a lower bound that the check uses.
fn check_load_within_contact(bearing: &RollerBearing, load: [f64; 2]) -> miette::Result<()> {
    let force = load[0].hypot(load[1]);
    let per_roller = force / (bearing.rollers as f64 * bearing.contact_stiffness);
    let approach = per_roller.powf(1.0 / bearing.contact_exponent);
    let limit = MAX_APPROACH_OVER_ROLLER * bearing.roller_diameter;
    if approach > limit {
        return Err(Diag::option(
            "--load",
            format!(
                "under {force:.4e} N the most loaded roller of `{}` would be pressed at least \
                 {approach:.4e} m into its rings, more than a tenth of its diameter ({:.4e} m): \
                 far beyond where Hertz contact, or the steel, holds",
                bearing.name, bearing.roller_diameter
            ),
        )
        .help("give a load the bearing can carry, e.g. --load 1kN")
        .into());
    }
    Ok(())
}

/// The load vector and where it came from.
fn bearing_load(args: &Args, model: &Model) -> miette::Result<([f64; 2], &'static str)> {
    if let Some(magnitude) = args.load {
        let a = args.load_angle.to_radians();
        return Ok(([magnitude * a.cos(), magnitude * a.sin()], "--load"));
    }
    let w = lib(gravity_load(model, args.bearing))?;
    if w[0].hypot(w[1]) > 0.0 {
        Ok((
            w,
            "share of the rotor weight: the bearing's reaction in a linear static solve \
             with gravity, roller bearings at their linear_stiffness",
        ))
    } else {
        Err(
            Diag::new("the bearing carries no weight: the model has no gravity")
                .help("give the load, e.g. --load 100N")
                .into(),
        )
    }
}

fn text(bearing: &RollerBearing, study: &StiffnessStudy, load_source: &str) -> String {
    let mut t = String::new();
    let um = |x: f64| x * 1e6;
    let w = study.load;
    let _ = writeln!(
        t,
        "{} (node {}): load ({:.2}, {:.2}) N [{}], roller 0 at {:.1} deg",
        bearing.name,
        bearing.station.node,
        w[0],
        w[1],
        if load_source == "--load" {
            "--load"
        } else {
            "share of the weight"
        },
        study.cage_angle.to_degrees()
    );
    let _ = writeln!(
        t,
        "stiffness in MN/m; fixed displacement ({:.3}, {:.3}) um",
        um(study.fixed_displacement[0]),
        um(study.fixed_displacement[1])
    );
    let _ = writeln!(
        t,
        "  clearance |  frozen: uy [um] rollers   kxx      kyy |  averaged:   kxx      kyy  \
         most rollers |  fixed:   kxx      kyy"
    );
    let mn = |x: f64| x * 1e-6;
    for c in &study.clearances {
        let f = &c.frozen.tangent;
        let _ = writeln!(
            t,
            "  {:>9} | {:14.3} {:>7} {:8.2} {:8.2} | {:14.2} {:8.2} {:5} | {:12.2} {:8.2}",
            clearance_label(c.clearance),
            um(f.displacement[1]),
            index_list(f.rollers.iter().map(|r| r.index)),
            mn(f.stiffness.kxx),
            mn(f.stiffness.kyy),
            mn(c.averaged.mean.kxx),
            mn(c.averaged.mean.kyy),
            c.averaged.most_rollers,
            mn(c.fixed.stiffness.kxx),
            mn(c.fixed.stiffness.kyy),
        );
    }
    let determinate = study.determinate_clearances();
    if !determinate.is_empty() {
        let _ = writeln!(
            t,
            "at {} of {} clearances no more than two rollers carry the load at any cage \
             position: there the frozen and averaged stiffness do not depend on the clearance",
            determinate.len(),
            study.clearances.len()
        );
    }
    t
}

/// Half-width of the surfaces' grid, m: twice the largest surface clearance, so that the
/// force-free disk fills the middle half; with only zero clearances, ten Hertz deflections
/// under the load.
fn surface_extent(bearing: &RollerBearing, clearances: &[f64], load: f64) -> miette::Result<f64> {
    let largest = clearances.iter().copied().fold(0.0, f64::max);
    if largest > 0.0 {
        return Ok(2.0 * largest);
    }
    Ok(10.0 * lib(FrozenBearing::new(bearing, 0.0, 0.0))?.hertz_deflection(load))
}

/// The surfaces at each distinct clearance of `--surface-clearances`.
fn surfaces(
    args: &Args,
    bearing: &RollerBearing,
    study: &StiffnessStudy,
) -> miette::Result<Vec<ForceSurface>> {
    let load = study.load[0].hypot(study.load[1]);
    let extent = surface_extent(bearing, &args.surface_clearances, load)?;
    let n = args.grid;
    let axis: Vec<f64> = (0..n)
        .map(|i| -extent + 2.0 * extent * i as f64 / (n - 1) as f64)
        .collect();
    let mut labels = Vec::new();
    let mut out = Vec::new();
    for &c in &args.surface_clearances {
        // Two clearances with one label would write one file twice.
        let label = clearance_label(c);
        if !labels.contains(&label) {
            labels.push(label);
            out.push(lib(force_surface(
                bearing,
                c,
                study.cage_angle,
                &axis,
                &axis,
            ))?);
        }
    }
    Ok(out)
}

pub fn run(args: &Args) -> miette::Result<Outcome> {
    let loaded = load(&args.common.model)?;
    let model = &loaded.model;
    let bearing = pick_bearing(model, args.bearing)?;
    let (load_vector, load_source) = bearing_load(args, model)?;
    check_load_within_contact(bearing, load_vector)?;
    let study = lib(stiffness_versus_clearance(
        bearing,
        &StiffnessOptions {
            clearances: args.clearances.0.clone(),
            load: load_vector,
            cage_angle: args.cage_angle.map(f64::to_radians),
            cage_steps: args.cage_steps,
            fixed_displacement: None,
        },
    ))?;
    let surfaces = surfaces(args, bearing, &study)?;

    let report = StiffnessReport {
        bearing: bearing.clone(),
        study,
        load_source: load_source.into(),
        surfaces,
    };
    let tables = report.tables();
    let mut out = Output::begin(&args.common.out_dir("stiffness"))?;
    out.table_named(&tables, "stiffness")?;
    out.table_named(&tables, "passage")?;
    let study = &report.study;
    out.plot("stiffness_vs_clearance", |stem| {
        plots_stiffness::stiffness_vs_clearance(study).save(stem)
    })?;
    for surface in &report.surfaces {
        let label = clearance_label(surface.clearance);
        out.table_named(&tables, &format!("surfaces_{label}"))?;
        for component in plots_stiffness::Component::ALL {
            out.plot(&format!("surface_{label}_{}", component.name()), |stem| {
                plots_stiffness::force_surface(surface, component).save(stem)
            })?;
        }
    }
    let summary = report_summary("stiffness", &loaded, &report)?;
    let text = text(bearing, study, load_source);
    finish(out, summary, text, &args.common)
}
