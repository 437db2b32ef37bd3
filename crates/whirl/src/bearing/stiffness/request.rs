//! A stiffness study as `whirl stiffness` and `whirl.stiffness` ask for it: which bearing,
//! which load (given, or the bearing's share of the rotor weight), which clearances and
//! cage positions, which surfaces on which grid. [`stiffness_report`] makes every choice
//! and checks every value, so the command line and the Python package get the same report
//! from the same request.

use super::{
    force_surface, gravity_load, norm, stiffness_versus_clearance, FrozenBearing, StiffnessOptions,
    StiffnessReport,
};
use crate::error::{Error, InputError, Result};
use crate::given::{unknown_option, Given, SetByName};
use crate::model::{Model, RollerBearing};

/// The clearances studied by default, as a range `start:stop:count`.
pub const DEFAULT_CLEARANCES: &str = "10um:120um:12";
/// The clearances of the force-deflection surfaces by default, comma-separated.
pub const DEFAULT_SURFACE_CLEARANCES: &str = "20um,60um";
/// Direction of a given load by default, degrees from +x towards +y: down, along gravity.
pub const DEFAULT_LOAD_ANGLE_DEG: f64 = -90.0;
/// Cage positions across one roller passage for the averaged stiffness by default.
pub const DEFAULT_CAGE_STEPS: usize = 32;
/// Points per side of the surfaces' displacement grid by default.
pub const DEFAULT_GRID: usize = 41;

/// Most clearances of one study: each is a set of equilibrium solves, and more show
/// nothing a plot could.
const MAX_CLEARANCES: usize = 1000;
/// Most cage positions per passage.
const MAX_CAGE_STEPS: usize = 1000;
/// Most points per side of a surface's grid (401 x 401 cells per surface).
const MAX_GRID: usize = 401;

/// The largest roller approach, as a fraction of the roller diameter, a load may cause:
/// Hertz contact theory holds for approaches of micrometres; a tenth of the roller would
/// crush it (steel yields long before).
const MAX_APPROACH_OVER_ROLLER: f64 = 0.1;

/// Where the load of a study comes from when none is given.
const WEIGHT_SOURCE: &str = "share of the rotor weight: the bearing's reaction in a linear \
                             static solve with gravity, roller bearings at their \
                             linear_stiffness";
/// Where a given load comes from.
const GIVEN_SOURCE: &str = "given";

/// What a stiffness study asks for; [`StiffnessRequest::default`] is every default, the
/// clearances read from [`DEFAULT_CLEARANCES`] and [`DEFAULT_SURFACE_CLEARANCES`] as a
/// user's text would be. The command line, the Python package and a study fill it.
#[derive(Debug, Clone, PartialEq)]
pub struct StiffnessRequest {
    /// The roller bearing, by its order in the model file.
    pub bearing: usize,
    /// Clearances studied, m.
    pub clearances: Vec<f64>,
    /// The load's magnitude, N; `None` for the bearing's share of the rotor weight.
    pub load: Option<f64>,
    /// Direction of a given load, degrees from +x towards +y (-90 = down).
    pub load_angle_deg: f64,
    /// Angle of roller 0 of the frozen cage, degrees; `None` for on the load line.
    pub cage_angle_deg: Option<f64>,
    /// Cage positions across one roller passage.
    pub cage_steps: usize,
    /// Clearances of the force-deflection surfaces, m.
    pub surface_clearances: Vec<f64>,
    /// Points per side of the surfaces' grid.
    pub grid: usize,
}

impl Default for StiffnessRequest {
    fn default() -> StiffnessRequest {
        // The default texts are constants the unit parser reads (a test checks they do).
        let lengths = |text: &str| Given::Text(text.into()).lengths("").unwrap_or_default();
        StiffnessRequest {
            bearing: 0,
            clearances: lengths(DEFAULT_CLEARANCES),
            load: None,
            load_angle_deg: DEFAULT_LOAD_ANGLE_DEG,
            cage_angle_deg: None,
            cage_steps: DEFAULT_CAGE_STEPS,
            surface_clearances: lengths(DEFAULT_SURFACE_CLEARANCES),
            grid: DEFAULT_GRID,
        }
    }
}

/// The options [`StiffnessRequest::set`] knows.
const OPTIONS: [&str; 8] = [
    "bearing",
    "clearances",
    "load",
    "load_angle",
    "cage_angle",
    "cage_steps",
    "surface_clearances",
    "grid",
];

impl SetByName for StiffnessRequest {
    fn set(&mut self, name: &str, value: &Given) -> std::result::Result<(), InputError> {
        let v = value;
        match name {
            "bearing" => self.bearing = v.whole(name, 0, usize::MAX >> 1)?,
            "clearances" => self.clearances = v.lengths(name)?,
            "load" => self.load = Some(v.force(name)?),
            "load_angle" => self.load_angle_deg = v.number(name)?,
            "cage_angle" => self.cage_angle_deg = Some(v.number(name)?),
            "cage_steps" => self.cage_steps = v.whole(name, 1, MAX_CAGE_STEPS)?,
            "surface_clearances" => self.surface_clearances = v.lengths(name)?,
            "grid" => self.grid = v.whole(name, 2, MAX_GRID)?,
            _ => return Err(unknown_option(name, &OPTIONS, "stiffness study")),
        }
        Ok(())
    }
}

/// The stiffness study of `request` on `model`: the bearing picked, its load (given, or its
/// share of the weight: [`gravity_load`]) checked against what contact theory allows, the
/// three stiffnesses at each clearance and the force-deflection surfaces.
///
/// # Errors
/// [`Error::Input`] naming the request's field (`bearing`, `clearances`, `load`,
/// `load_angle`, `cage_angle`, `cage_steps`, `surface_clearances`, `grid`) for a value out of
/// range; [`Error::Unsupported`] for a model without roller bearings; the errors of
/// [`gravity_load`] and [`stiffness_versus_clearance`].
pub fn stiffness_report(model: &Model, request: &StiffnessRequest) -> Result<StiffnessReport> {
    check_request(request)?;
    let bearing = pick_bearing(model, request.bearing)?;
    let (load, load_source) = bearing_load(model, request)?;
    check_load_within_contact(bearing, load)?;
    let study = stiffness_versus_clearance(
        bearing,
        &StiffnessOptions {
            clearances: request.clearances.clone(),
            load,
            cage_angle: request.cage_angle_deg.map(f64::to_radians),
            cage_steps: request.cage_steps,
            fixed_displacement: None,
        },
    )?;
    let extent = surface_extent(bearing, &request.surface_clearances, norm(study.load))?;
    let n = request.grid;
    let axis: Vec<f64> = (0..n)
        .map(|i| -extent + 2.0 * extent * i as f64 / (n - 1) as f64)
        .collect();
    let mut labels = Vec::new();
    let mut surfaces = Vec::new();
    for &c in &request.surface_clearances {
        // Two clearances with one label would be one table twice.
        let label = super::clearance_label(c);
        if !labels.contains(&label) {
            labels.push(label);
            surfaces.push(force_surface(bearing, c, study.cage_angle, &axis, &axis)?);
        }
    }
    Ok(StiffnessReport {
        bearing: bearing.clone(),
        study,
        load_source: load_source.into(),
        surfaces,
    })
}

/// An error about field `field` of the request.
fn invalid(field: &str, message: String) -> Error {
    InputError::field(field, message).into()
}

/// Every value of `request` in its range.
fn check_request(r: &StiffnessRequest) -> Result<()> {
    let lengths = |field: &str, values: &[f64]| -> Result<()> {
        if values.is_empty() || values.len() > MAX_CLEARANCES {
            return Err(invalid(
                field,
                format!("give 1 to {MAX_CLEARANCES} clearances"),
            ));
        }
        match values.iter().find(|c| !(c.is_finite() && **c >= 0.0)) {
            Some(c) => Err(invalid(
                field,
                format!("{c} m: a clearance must not be negative"),
            )),
            None => Ok(()),
        }
    };
    lengths("clearances", &r.clearances)?;
    lengths("surface_clearances", &r.surface_clearances)?;
    if let Some(load) = r.load {
        if !(load.is_finite() && load > 0.0) {
            return Err(invalid(
                "load",
                format!("{load} N: the load must be positive"),
            ));
        }
    }
    if !r.load_angle_deg.is_finite() {
        return Err(invalid(
            "load_angle",
            format!("{} is not an angle in degrees", r.load_angle_deg),
        ));
    }
    if r.cage_angle_deg.is_some_and(|a| !a.is_finite()) {
        return Err(invalid(
            "cage_angle",
            "the angle must be finite degrees".into(),
        ));
    }
    if !(1..=MAX_CAGE_STEPS).contains(&r.cage_steps) {
        return Err(invalid(
            "cage_steps",
            format!(
                "`{}` is not a whole number from 1 to {MAX_CAGE_STEPS}",
                r.cage_steps
            ),
        ));
    }
    if !(2..=MAX_GRID).contains(&r.grid) {
        return Err(invalid(
            "grid",
            format!("`{}` is not a whole number from 2 to {MAX_GRID}", r.grid),
        ));
    }
    Ok(())
}

/// The roller bearing `index` of the model, or an error that lists what there is.
fn pick_bearing(model: &Model, index: usize) -> Result<&RollerBearing> {
    if model.roller_bearings.is_empty() {
        return Err(Error::Unsupported(
            "the model has no [[roller_bearing]]: a stiffness study needs one; add a \
             [[roller_bearing]] table (see docs/model-file.md)"
                .into(),
        ));
    }
    model.roller_bearings.get(index).ok_or_else(|| {
        let list: Vec<String> = model
            .roller_bearings
            .iter()
            .enumerate()
            .map(|(i, b)| format!("{i} = {}", b.name))
            .collect();
        invalid(
            "bearing",
            format!(
                "the model has {} roller bearing(s) ({}); there is no bearing {index}",
                model.roller_bearings.len(),
                list.join(", ")
            ),
        )
    })
}

/// The load vector (N) and where it came from.
fn bearing_load(model: &Model, request: &StiffnessRequest) -> Result<([f64; 2], &'static str)> {
    if let Some(magnitude) = request.load {
        let a = request.load_angle_deg.to_radians();
        return Ok(([magnitude * a.cos(), magnitude * a.sin()], GIVEN_SOURCE));
    }
    let w = gravity_load(model, request.bearing)?;
    if norm(w) > 0.0 {
        Ok((w, WEIGHT_SOURCE))
    } else {
        Err(InputError::field(
            "load",
            "the bearing carries no weight: the model has no gravity",
        )
        .help("give the load, e.g. 100 N")
        .into())
    }
}

/// Refuses a load that would press the rollers further into the rings than contact theory
/// (or the steel) allows. Carried by N rollers of stiffness k and exponent n, a load F needs
/// the most loaded roller's approach delta to satisfy F <= N k delta^n, so
/// delta >= (F / (N k))^(1/n) whatever the clearance: a lower bound that the check uses.
fn check_load_within_contact(bearing: &RollerBearing, load: [f64; 2]) -> Result<()> {
    let force = norm(load);
    let per_roller = force / (bearing.rollers as f64 * bearing.contact_stiffness);
    let approach = per_roller.powf(1.0 / bearing.contact_exponent);
    let limit = MAX_APPROACH_OVER_ROLLER * bearing.roller_diameter;
    if approach > limit {
        return Err(InputError::field(
            "load",
            format!(
                "under {force:.4e} N the most loaded roller of `{}` would be pressed at least \
                 {approach:.4e} m into its rings, more than a tenth of its diameter ({:.4e} m): \
                 far beyond where Hertz contact, or the steel, holds",
                bearing.name, bearing.roller_diameter
            ),
        )
        .help("give a load the bearing can carry, e.g. 1 kN")
        .into());
    }
    Ok(())
}

/// Half-width of the surfaces' grid, m: twice the largest surface clearance, so that the
/// force-free disk fills the middle half; with only zero clearances, ten Hertz deflections
/// under the load.
fn surface_extent(bearing: &RollerBearing, clearances: &[f64], load: f64) -> Result<f64> {
    let largest = clearances.iter().copied().fold(0.0, f64::max);
    if largest > 0.0 {
        return Ok(2.0 * largest);
    }
    Ok(10.0 * FrozenBearing::new(bearing, 0.0, 0.0)?.hertz_deflection(load))
}

impl StiffnessReport {
    /// True when the load is the bearing's share of the rotor weight, false when given.
    pub fn load_from_weight(&self) -> bool {
        self.load_source == WEIGHT_SOURCE
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_default_texts_read_as_a_users_would() {
        let r = StiffnessRequest::default();
        assert_eq!(r.clearances.len(), 12);
        assert!(
            (r.clearances[0] - 10e-6).abs() < 1e-18 && (r.clearances[11] - 120e-6).abs() < 1e-18
        );
        assert_eq!(r.surface_clearances, vec![20e-6, 60e-6]);
    }

    #[test]
    fn options_are_read_by_name_in_any_order() {
        let mut r = StiffnessRequest::default();
        r.set("load_angle", &Given::Number(0.0)).unwrap();
        r.set("load", &Given::Text("2 kN".into())).unwrap();
        r.set("clearances", &Given::Text("20um,60um".into()))
            .unwrap();
        assert_eq!((r.load, r.load_angle_deg), (Some(2000.0), 0.0));
        assert_eq!(r.clearances, vec![20e-6, 60e-6]);
        let e = r.set("load", &Given::Number(-1.0)).unwrap_err();
        assert_eq!(e.field.as_deref(), Some("load"));
        let e = r.set("grid", &Given::Whole(1)).unwrap_err();
        assert_eq!(e.field.as_deref(), Some("grid"));
        assert!(r
            .set("loads", &Given::Number(1.0))
            .unwrap_err()
            .help
            .unwrap()
            .contains("load_angle"));
    }
}
