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
    clearance_label, stiffness_report, StiffnessReport, StiffnessRequest, DEFAULT_CAGE_STEPS,
    DEFAULT_CLEARANCES, DEFAULT_GRID, DEFAULT_LOAD_ANGLE_DEG, DEFAULT_SURFACE_CLEARANCES,
};
use whirl::report::{index_list, Report};
use whirl::units::{parse_quantity, parse_range, Dimension};

use super::{default_is, finish, load, option_error, report_summary, Common, Outcome};
use crate::output::Output;

/// `whirl stiffness`
#[derive(Debug, clap::Args)]
pub struct Args {
    #[command(flatten)]
    pub common: Common,
    /// Which roller bearing, by its order in the model file [default: 0, the first].
    #[arg(long, value_name = "INDEX")]
    pub bearing: Option<usize>,
    #[arg(long, value_name = "RANGE", value_parser = clearance_range,
          help = default_is("Clearances `start:stop:count`, e.g. `10um:120um:12`; plain numbers are m.", DEFAULT_CLEARANCES))]
    pub clearances: Option<Clearances>,
    /// Load the rotor puts on the bearing, e.g. `60N` or `2kN` [default: the bearing's share
    /// of the rotor weight, from a linear static solve with gravity].
    #[arg(long, value_name = "FORCE", value_parser = force)]
    pub load: Option<f64>,
    #[arg(long, value_name = "DEG", requires = "load", value_parser = degrees, allow_hyphen_values = true,
          help = default_is("Direction of `--load`, degrees from +x towards +y (-90 = down, along gravity).", DEFAULT_LOAD_ANGLE_DEG))]
    pub load_angle: Option<f64>,
    /// Angle of roller 0 for the frozen cage, degrees from +x towards +y [default: on the
    /// load line].
    #[arg(long, value_name = "DEG", value_parser = degrees, allow_hyphen_values = true)]
    pub cage_angle: Option<f64>,
    #[arg(long, value_name = "N",
          help = default_is("Cage positions across one roller passage for the averaged stiffness (1 to 1000).", DEFAULT_CAGE_STEPS))]
    pub cage_steps: Option<usize>,
    #[arg(long, value_name = "LIST", value_delimiter = ',', value_parser = clearance,
          help = default_is("Clearances of the force-deflection surfaces, comma-separated.", DEFAULT_SURFACE_CLEARANCES))]
    pub surface_clearances: Option<Vec<f64>>,
    #[arg(long, value_name = "N",
          help = default_is("Points per side of the surfaces' displacement grid (2 to 401).", DEFAULT_GRID))]
    pub grid: Option<usize>,
}

/// Clearances in m from `start:stop:count`.
#[derive(Debug, Clone)]
pub struct Clearances(pub Vec<f64>);

/// Clap parser of a clearance range (the library checks the values).
fn clearance_range(text: &str) -> Result<Clearances, String> {
    parse_range(text, Dimension::Length)
        .map(Clearances)
        .map_err(|e| e.to_string())
}

/// Clap parser of one clearance (the library checks the value).
fn clearance(text: &str) -> Result<f64, String> {
    parse_quantity(text, Dimension::Length).map_err(|e| e.to_string())
}

/// Clap parser of a load (the library checks the value).
fn force(text: &str) -> Result<f64, String> {
    parse_quantity(text, Dimension::Force).map_err(|e| e.to_string())
}

/// Clap parser of an angle in degrees.
fn degrees(text: &str) -> Result<f64, String> {
    match text.trim().parse::<f64>() {
        Ok(a) if a.is_finite() => Ok(a),
        _ => Err(format!("`{text}` is not an angle in degrees (e.g. -90)")),
    }
}

/// The library's request from the command line: its defaults, and the flags given.
fn request(args: &Args) -> StiffnessRequest {
    let d = StiffnessRequest::default();
    StiffnessRequest {
        bearing: args.bearing.unwrap_or(d.bearing),
        clearances: args.clearances.clone().map_or(d.clearances, |c| c.0),
        load: args.load,
        load_angle_deg: args.load_angle.unwrap_or(d.load_angle_deg),
        cage_angle_deg: args.cage_angle,
        cage_steps: args.cage_steps.unwrap_or(d.cage_steps),
        surface_clearances: args
            .surface_clearances
            .clone()
            .unwrap_or(d.surface_clearances),
        grid: args.grid.unwrap_or(d.grid),
    }
}

fn text(report: &StiffnessReport) -> String {
    let (bearing, study) = (&report.bearing, &report.study);
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
        if report.load_from_weight() {
            "share of the weight"
        } else {
            "--load"
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

pub fn run(args: &Args) -> miette::Result<Outcome> {
    let loaded = load(&args.common.model)?;
    let report = stiffness_report(&loaded.model, &request(args)).map_err(option_error)?;
    let tables = report.tables();
    let mut out = Output::begin(&args.common.out_dir("stiffness"))?;
    out.table_named(&tables, "stiffness")?;
    out.table_named(&tables, "passage")?;
    for surface in &report.surfaces {
        let label = clearance_label(surface.clearance);
        out.table_named(&tables, &format!("surfaces_{label}"))?;
    }
    out.figures(whirl_figures::stiffness(&report), args.common.rpm)?;
    let summary = report_summary("stiffness", &loaded, &report)?;
    let text = text(&report);
    finish(out, summary, text, &args.common)
}
