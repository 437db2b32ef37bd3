//! Checks of a whole validated model: that its bearings carry it at the operating speeds,
//! that its roller bearings are plausible, and the warnings for values that are legal but
//! unusual.

use super::*;

/// Refuses a rotor that cannot stand: bearings at fewer than two nodes leave it free to
/// tilt (or, with none, to fall), a rigid-body mode at 0 Hz that no rotor analysis can use.
pub(in crate::model) fn supports(model: &Model) -> V<()> {
    let nodes = model.bearing_nodes();
    if nodes.len() >= 2 {
        return Ok(());
    }
    let why = match nodes.first() {
        Some(n) => format!(
            "the rotor rests on bearings at one node only ({n}): it is free to tilt about it"
        ),
        None => "the rotor has no bearing: it is free to fall and to tilt".to_string(),
    };
    Err(InputError::field("bearing", why)
        .help("support it at two nodes at least, with [[bearing]] or [[roller_bearing]] tables"))
}

/// Speeds (rad/s) at which speed-dependent laws are checked: from rest to the top of the
/// operating range, in [`LAW_CHECKS`] steps (only rest when the model states no range).
fn checked_speeds(operating: Option<(f64, f64)>) -> Vec<f64> {
    let top = operating.map_or(0.0, |(_, high)| high);
    (0..=LAW_CHECKS)
        .map(|k| top * k as f64 / LAW_CHECKS as f64)
        .collect()
}

/// Steps of [`checked_speeds`]: a polynomial of the few degrees a clearance law has cannot
/// dip below zero and back between 1 % steps of the range without its coefficients being
/// far larger than any fitted law's.
const LAW_CHECKS: usize = 100;

/// A ring's waviness larger than this many times the clearance scale is refused: waviness is
/// a form error of micrometres, below the clearance; ten times it would jam or free the
/// rollers in turn, which is no longer a waviness but a broken ring.
const MAX_WAVINESS_OVER_CLEARANCE: f64 = 10.0;

/// The smallest clearance scale, as a fraction of the pitch diameter: radial clearances of
/// roller bearings are about 1e-4 to 1e-3 of the diameter (ISO 5753 groups), so a
/// zero-clearance (preloaded) bearing is judged against 1e-4 of it.
const MIN_CLEARANCE_SCALE: f64 = 1e-4;

/// Each roller and ball bearing of `model` checked by [`roller_bearing_plausible`], with the
/// places in `raw` its messages point at.
pub(super) fn bearings_plausible(model: &Model, raw: &ModelFile) -> V<()> {
    for (i, (b, file)) in model
        .roller_bearings
        .iter()
        .zip(&raw.roller_bearing)
        .enumerate()
    {
        let f = file.get_ref();
        let spans = BearingSpans {
            clearance: f.clearance.span(),
            waviness: f
                .waviness
                .iter()
                .map(|w| w.get_ref().amplitude.span())
                .collect(),
            forcing: f.forcing_function.as_ref().map(|l| l.span()),
        };
        roller_bearing_plausible(b, &spans, &format!("roller_bearing[{i}]"), model.operating)?;
    }
    let balls = model.roller_bearings.iter().filter(|b| b.is_ball());
    for (i, (b, file)) in balls.zip(&raw.ball_bearing).enumerate() {
        let f = file.get_ref();
        let spans = BearingSpans {
            clearance: f.clearance.as_ref().map_or(file.span(), |c| c.span()),
            waviness: f
                .waviness
                .iter()
                .map(|w| w.get_ref().amplitude.span())
                .collect(),
            forcing: None,
        };
        roller_bearing_plausible(b, &spans, &format!("ball_bearing[{i}]"), model.operating)?;
    }
    Ok(())
}

/// Where in the file a bearing's checked values are written.
struct BearingSpans {
    clearance: Range<usize>,
    /// Each waviness component's amplitude.
    waviness: Vec<Range<usize>>,
    forcing: Option<Range<usize>>,
}

/// Refuses a roller bearing that cannot exist: a clearance that goes negative or grows past
/// the rollers within the operating speeds, a forcing law whose coefficients turn negative
/// there, waviness far above the clearance.
fn roller_bearing_plausible(
    b: &RollerBearing,
    spans: &BearingSpans,
    field: &str,
    operating: Option<(f64, f64)>,
) -> V<()> {
    let clearance_span = spans.clearance.clone();
    let speeds = checked_speeds(operating);
    let mut largest = 0.0_f64;
    for &w in &speeds {
        let c = b.clearance.at_speed(w);
        if c.is_nan() || c < 0.0 {
            return Err(err(
                &format!("{field}.clearance"),
                clearance_span,
                format!(
                    "the clearance is {} m at {} Hz, within the operating speeds: it must not be \
                     negative",
                    Si(c),
                    Si(w / (2.0 * PI))
                ),
            )
            .help("check the polynomial's coefficients and units"));
        }
        largest = largest.max(c);
    }
    if largest >= b.roller_diameter {
        return Err(err(
            &format!("{field}.clearance"),
            clearance_span,
            format!(
                "a clearance of {} m is not smaller than the rollers ({} m in diameter): the \
                 rings could not hold them",
                Si(largest),
                Si(b.roller_diameter)
            ),
        )
        .help("radial clearances are micrometres: about 1e-4 to 1e-3 of the pitch diameter"));
    }
    let scale = largest.max(MIN_CLEARANCE_SCALE * b.pitch_diameter);
    for (i, (w, span)) in b.waviness.iter().zip(&spans.waviness).enumerate() {
        if w.amplitude > MAX_WAVINESS_OVER_CLEARANCE * scale {
            return Err(err(
                &format!("{field}.waviness[{i}].amplitude"),
                span.clone(),
                format!(
                    "a waviness of {} m is more than {MAX_WAVINESS_OVER_CLEARANCE} times the \
                     clearance scale ({} m): waviness is a form error below the clearance",
                    Si(w.amplitude),
                    Si(scale)
                ),
            )
            .help("waviness amplitudes are micrometres, e.g. \"1 um\""));
        }
    }
    if let (Some(law), Some(lf)) = (&b.forcing_function, &spans.forcing) {
        // a and b are linear in the speed: their signs over the range are those at its ends.
        let ends = [speeds[0], speeds[speeds.len() - 1]];
        if let Some(&w) = ends.iter().find(|&&w| {
            let (a, e) = law.at_speed(w);
            !(a > 0.0 && e > 0.0)
        }) {
            let (a, e) = law.at_speed(w);
            return Err(err(
                &format!("{field}.forcing_function"),
                lf.clone(),
                format!(
                    "at {} Hz, within the operating speeds, the law's stiffness a0 + a1 W = {} \
                     and exponent b0 + b1 W = {}: both must stay positive",
                    Si(w / (2.0 * PI)),
                    Si(a),
                    Si(e)
                ),
            )
            .help("W is in rad/s; `whirl fit-forcing` fits a law over the speeds you give it"));
        }
    }
    Ok(())
}

/// Warnings about a valid but implausible model: values no real rotor has, which usually
/// mean a unit slipped. One sentence each, naming the field.
pub(in crate::model) fn warnings(model: &Model) -> Vec<String> {
    // Ball bearings follow the roller bearings in the model, each table numbered apart.
    let rollers = model
        .roller_bearings
        .iter()
        .filter(|b| !b.is_ball())
        .count();
    let mut out: Vec<String> = model
        .roller_bearings
        .iter()
        .enumerate()
        .filter_map(|(i, b)| {
            let field = if b.is_ball() {
                format!("ball_bearing[{}]", i - rollers)
            } else {
                format!("roller_bearing[{i}]")
            };
            clearance_warning(b, &field, model.operating)
        })
        .collect();
    out.extend(
        model
            .materials
            .iter()
            .enumerate()
            .filter_map(|(i, m)| density_warning(m, &format!("material[{i}]"))),
    );
    let shaft: f64 = model
        .sections
        .iter()
        .map(|s| s.material.density * s.area() * s.length)
        .sum();
    let disks: f64 = model.disks.iter().map(|d| d.mass).sum();
    if shaft < MIN_SHAFT_MASS_FRACTION * (shaft + disks) {
        out.push(format!(
            "shaft: its mass ({} kg) is below {} % of the rotor's ({} kg); a near-massless shaft \
             gives modes of its own at very high frequencies and tiny stable time steps \
             (check the material's density, kg/m^3)",
            Si(shaft),
            100.0 * MIN_SHAFT_MASS_FRACTION,
            Si(shaft + disks)
        ));
    }
    out
}

/// A warning when the bearing's largest clearance from rest to the top operating speed is
/// a large part of the pitch diameter or of the rollers (refused outright when it reaches
/// the roller diameter).
fn clearance_warning(
    b: &RollerBearing,
    field: &str,
    operating: Option<(f64, f64)>,
) -> Option<String> {
    let largest = checked_speeds(operating)
        .iter()
        .map(|&w| b.clearance.at_speed(w))
        .fold(0.0, f64::max);
    let implausible = largest > MAX_PLAUSIBLE_CLEARANCE * b.pitch_diameter
        || largest > MAX_CLEARANCE_PER_ROLLER * b.roller_diameter;
    implausible.then(|| {
        format!(
            "{field}.clearance: {} m is {:.1} % of the roller diameter and {:.2} % of the pitch \
             diameter; radial clearances are micrometres, 0.01 to 0.1 % of the pitch diameter \
             (a unit may be missing: \"20 um\")",
            Si(largest),
            100.0 * largest / b.roller_diameter,
            100.0 * largest / b.pitch_diameter
        )
    })
}

/// A warning when a material's density lies outside [`PLAUSIBLE_DENSITY`].
fn density_warning(m: &Material, field: &str) -> Option<String> {
    let (low, high) = PLAUSIBLE_DENSITY;
    (!(low..=high).contains(&m.density)).then(|| {
        format!(
            "{field}.density: {} kg/m^3 (material `{}`) is outside the {low} to {high} kg/m^3 \
             of engineering solids (polymers about 1000, aluminium 2700, steel 7850, tungsten \
             19300); masses and every frequency follow from it (give it in kg/m^3: steel is \
             7850, not 7.85)",
            Si(m.density),
            m.name
        )
    })
}

/// A clearance above this fraction of the pitch diameter draws a warning (ten times the
/// largest clearance group of ISO 5753).
const MAX_PLAUSIBLE_CLEARANCE: f64 = 0.01;

/// A clearance above this fraction of the roller diameter draws a warning: the largest
/// clearance groups of ISO 5753 stay near 1 % of the rollers (0.1 mm on 10 mm rollers);
/// five times that is no bearing in service.
const MAX_CLEARANCE_PER_ROLLER: f64 = 0.05;

/// Densities (kg/m^3) outside this range draw a warning: below it lie foams, not shaft or
/// disk materials (polymers start near 900); above it nothing, since osmium, the densest
/// element, has 22,590.
const PLAUSIBLE_DENSITY: (f64, f64) = (100.0, 25_000.0);

/// A shaft lighter than this fraction of the rotor draws a warning.
const MIN_SHAFT_MASS_FRACTION: f64 = 0.01;
