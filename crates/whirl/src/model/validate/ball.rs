//! `[[ball_bearing]]` -> a [`RollerBearing`] whose rollers are balls ([`BallContact`]).

use super::*;
use crate::model::ball_file::BallBearingFile;
use crate::model::ball_law::BallLaw;

/// Bounds of a groove's conformity f = r / D: at 1/2 the groove fits the ball exactly (a
/// contact ellipse of infinite length), at 1 the groove is a flat; bearings use 0.505-0.57.
const CONFORMITY: (f64, f64) = (0.5, 1.0);

/// The pitch diameter and the clearance, as the file fixes them.
struct BallGeometry {
    pitch: f64,
    clearance: Clearance,
}

pub(super) fn ball_bearing(
    raw: &Spanned<BallBearingFile>,
    field: &str,
    nodes: &Nodes,
) -> V<RollerBearing> {
    let b = raw.get_ref();
    let f = |name: &str| format!("{field}.{name}");
    let station = nodes.station(&b.node, &b.z, field, raw.span())?;
    let balls = count(&b.balls, &f("balls"), 3, 1000)?;
    let ball = positive_q(&b.ball_diameter, Dimension::Length, &f("ball_diameter"))?;
    let geometry = geometry(b, ball, field, raw.span())?;
    let pitch = geometry.pitch;
    if ball >= pitch || balls as f64 * ball >= PI * pitch {
        return Err(err(
            &f("balls"),
            b.balls.span(),
            format!(
                "{balls} balls of diameter {} m do not fit on a pitch circle of diameter {} m",
                Si(ball),
                Si(pitch)
            ),
        ));
    }
    let inner_conformity = conformity(&b.inner_conformity, &f("inner_conformity"))?;
    let outer_conformity = conformity(&b.outer_conformity, &f("outer_conformity"))?;
    let angle = opt_f64(&b.contact_angle, &f("contact_angle"), 0.0)?;
    if !(0.0..90.0).contains(&angle) {
        return Err(err(
            &f("contact_angle"),
            b.contact_angle.as_ref().map_or(raw.span(), |a| a.span()),
            format!(
                "a radial or angular-contact bearing's contact angle lies in [0, 90) degrees, \
                 got {angle}"
            ),
        )
        .help("0 for a deep-groove bearing, 15 to 40 for angular contact"));
    }
    let axial_load = match &b.axial_load {
        Some(q) => non_negative_q(q, Dimension::Force, &f("axial_load"))?,
        None => 0.0,
    };
    if angle > 0.0 && axial_load == 0.0 {
        return Err(err(
            &f("axial_load"),
            raw.span(),
            format!(
                "an angular-contact bearing ({angle} degrees) holds its contact angle only \
                 under an axial load: without one its balls would slide to the groove bottoms"
            ),
        )
        .help("give axial_load, the preload or thrust the bearing carries (e.g. \"500 N\")"));
    }
    let young_modulus = match &b.young_modulus {
        Some(e) => positive(*e.get_ref(), e.span(), &f("young_modulus"), "Pa")?,
        None => BEARING_STEEL_MODULUS,
    };
    let poisson_ratio = opt_f64(&b.poisson_ratio, &f("poisson_ratio"), BEARING_STEEL_POISSON)?;
    if !(0.0..0.5).contains(&poisson_ratio) {
        return Err(err(
            &f("poisson_ratio"),
            b.poisson_ratio.as_ref().map_or(raw.span(), |p| p.span()),
            format!("must lie in [0, 0.5), got {poisson_ratio}"),
        ));
    }
    let mut contact = BallContact {
        inner_conformity,
        outer_conformity,
        contact_angle: angle.to_radians(),
        axial_load,
        running_angle: angle.to_radians(),
        young_modulus,
        poisson_ratio,
    };
    let gamma = geometry.clearance.at_speed(0.0);
    let reach = contact.centre_distance(ball) * contact.contact_angle.cos();
    if gamma >= reach {
        return Err(err(
            &f("clearance"),
            raw.span(),
            format!(
                "a radial clearance of {} m is not smaller than the grooves' reach A cos(alpha) \
                 = {} m (A = (f_i + f_o - 1) D): the balls would leave their grooves",
                Si(gamma),
                Si(reach)
            ),
        )
        .help("radial clearances are micrometres; check the unit (\"10 um\")"));
    }
    let stiffness = running_stiffness(&mut contact, balls, ball, pitch, gamma);
    let (race_defects, element_defects) = defects(&b.defect, field, balls)?;
    Ok(RollerBearing {
        housing: None,
        name: b
            .name
            .clone()
            .unwrap_or_else(|| format!("ball bearing {}", station.node)),
        station,
        rollers: balls,
        pitch_diameter: pitch,
        roller_diameter: ball,
        roller_length: ball,
        clearance: geometry.clearance,
        contact_stiffness: stiffness,
        contact_exponent: 1.5,
        contact_damping: opt_non_negative(&b.contact_damping, &f("contact_damping"), "N s/m")?,
        cage_angle: opt_f64(&b.cage_angle, &f("cage_angle"), 0.0)?.to_radians(),
        cage_speed_ratio: cage_speed_ratio(
            &b.cage_speed_ratio,
            ball * contact.running_angle.cos() / pitch,
            &f("cage_speed_ratio"),
        )?,
        linear_stiffness: non_negative(
            *b.linear_stiffness.get_ref(),
            b.linear_stiffness.span(),
            &f("linear_stiffness"),
            "N/m",
        )?,
        linear_damping: opt_non_negative(&b.linear_damping, &f("linear_damping"), "N s/m")?,
        roller_tilt: false,
        slices: 1,
        skew_angle: 0.0,
        waviness: b
            .waviness
            .iter()
            .enumerate()
            .map(|(i, w)| waviness(w, &f(&format!("waviness[{i}]"))))
            .collect::<V<Vec<_>>>()?,
        defects: race_defects,
        element_defects,
        forcing_function: None,
        ball: Some(contact),
        dynamic_load_rating: b
            .dynamic_load_rating
            .as_ref()
            .map(|c| positive_q(c, Dimension::Force, &f("dynamic_load_rating")))
            .transpose()?,
    })
}

/// The pitch diameter and clearance, from `pitch_diameter` and `clearance` or from the two
/// raceway diameters.
fn geometry(b: &BallBearingFile, ball: f64, field: &str, span: Range<usize>) -> V<BallGeometry> {
    let f = |name: &str| format!("{field}.{name}");
    match (
        &b.pitch_diameter,
        &b.clearance,
        &b.inner_race_diameter,
        &b.outer_race_diameter,
    ) {
        (Some(p), Some(c), None, None) => Ok(BallGeometry {
            pitch: positive_q(p, Dimension::Length, &f("pitch_diameter"))?,
            clearance: clearance(c, &f("clearance"))?,
        }),
        (None, None, Some(i), Some(o)) => {
            let inner = positive_q(i, Dimension::Length, &f("inner_race_diameter"))?;
            let outer = positive_q(o, Dimension::Length, &f("outer_race_diameter"))?;
            let gap = 0.5 * (outer - inner);
            if gap <= ball {
                return Err(err(
                    &f("ball_diameter"),
                    b.ball_diameter.span(),
                    format!(
                        "a ball of {} m does not fit the {} m between the races (half the \
                         difference of the raceway diameters {} m and {} m)",
                        Si(ball),
                        Si(gap),
                        Si(outer),
                        Si(inner)
                    ),
                )
                .help("the raceway diameters are the groove bottoms; the outer is the larger"));
            }
            Ok(BallGeometry {
                pitch: 0.5 * (outer + inner),
                clearance: Clearance::Constant(gap - ball),
            })
        }
        _ => Err(err(
            field,
            span,
            "give either pitch_diameter and clearance, or inner_race_diameter and \
             outer_race_diameter",
        )),
    }
}

fn conformity(raw: &Spanned<f64>, field: &str) -> V<f64> {
    let v = finite(*raw.get_ref(), raw.span(), field)?;
    let (low, high) = CONFORMITY;
    if v > low && v < high {
        return Ok(v);
    }
    Err(err(
        field,
        raw.span(),
        format!(
            "a groove's radius over the ball's diameter lies strictly between {low} (a groove \
             no wider than the ball) and {high}, got {v}"
        ),
    )
    .help("deep-groove bearings use 0.515 to 0.53"))
}

/// The contact angle under the axial load alone with the shaft centred (each ball's radial
/// approach -gamma), into `contact.running_angle`, and K_n at that angle. K_n depends on the
/// angle only through D cos(alpha) / d_m; three rounds bring the pair to round-off.
fn running_stiffness(
    contact: &mut BallContact,
    balls: usize,
    ball: f64,
    pitch: f64,
    gamma: f64,
) -> f64 {
    let a = contact.centre_distance(ball);
    let law = BallLaw {
        centre_distance: a,
        radial_reach: a * contact.contact_angle.cos(),
        axial_load: contact.axial_load,
    };
    let mut k = ball_stiffness(ball, pitch, contact, contact.running_angle).2;
    for _ in 0..3 {
        let elastic = |x: f64| {
            let q = k * x.max(0.0).powf(1.5);
            (q, 1.5 * k * x.max(0.0).sqrt())
        };
        let s = law.axial_separation(std::iter::repeat_n(-gamma, balls), 0.0, &elastic);
        contact.running_angle = s.atan2(law.radial_reach - gamma);
        k = ball_stiffness(ball, pitch, contact, contact.running_angle).2;
    }
    k
}
