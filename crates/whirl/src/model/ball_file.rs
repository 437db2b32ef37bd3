//! `[[ball_bearing]]` as written (docs/model-file.md).

use serde::Deserialize;
use toml::Spanned;

use super::schema::{ClearanceFile, Count, DefectFile, WavinessFile, Q};

/// `[[ball_bearing]]`: a deep-groove or angular-contact ball bearing. The geometry is given
/// by the pitch diameter and the radial clearance, or by the two raceway (groove bottom)
/// diameters, whose difference less two balls is twice the clearance.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BallBearingFile {
    pub name: Option<String>,
    pub node: Option<Count>,
    pub z: Option<Q>,
    /// Number of balls Z.
    pub balls: Count,
    /// Ball diameter D (length).
    pub ball_diameter: Q,
    /// Pitch diameter d_m (length), with `clearance`.
    pub pitch_diameter: Option<Q>,
    /// Radial internal clearance (half the diametral P_d), with `pitch_diameter`.
    pub clearance: Option<Spanned<ClearanceFile>>,
    /// Inner raceway groove-bottom diameter (length), with `outer_race_diameter`.
    pub inner_race_diameter: Option<Q>,
    /// Outer raceway groove-bottom diameter (length), with `inner_race_diameter`.
    pub outer_race_diameter: Option<Q>,
    /// Inner groove radius over ball diameter, > 0.5.
    pub inner_conformity: Spanned<f64>,
    /// Outer groove radius over ball diameter, > 0.5.
    pub outer_conformity: Spanned<f64>,
    /// Contact angle with the clearance taken up, degrees (0 for deep groove).
    pub contact_angle: Option<Spanned<f64>>,
    /// Axial load or preload (force), constant.
    pub axial_load: Option<Q>,
    /// Young's modulus of balls and rings, Pa (bearing steel by default).
    pub young_modulus: Option<Spanned<f64>>,
    /// Poisson's ratio of balls and rings (0.3 by default).
    pub poisson_ratio: Option<Spanned<f64>>,
    /// Contact damping per ball on the radial approach rate, N s/m.
    pub contact_damping: Option<Spanned<f64>>,
    /// Angle of the first ball at t = 0, degrees from +x towards +y.
    pub cage_angle: Option<Spanned<f64>>,
    /// Cage speed over shaft speed; from the kinematics at the running contact angle when
    /// absent.
    pub cage_speed_ratio: Option<Spanned<f64>>,
    /// Linearised radial stiffness for modal analysis, N/m.
    pub linear_stiffness: Spanned<f64>,
    /// Linearised radial damping for modal analysis, N s/m.
    pub linear_damping: Option<Spanned<f64>>,
    /// Ring waviness components.
    #[serde(default)]
    pub waviness: Vec<Spanned<WavinessFile>>,
    /// Local raceway defects (spalls).
    #[serde(default)]
    pub defect: Vec<Spanned<DefectFile>>,
    /// Basic dynamic load rating C (force), the catalogue's; ISO 281's formula otherwise.
    pub dynamic_load_rating: Option<Q>,
    /// The `[[housing]]` its outer ring sits in; the ground when absent.
    pub housing: Option<Spanned<String>>,
}
