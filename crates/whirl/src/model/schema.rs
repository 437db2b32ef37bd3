//! The model file as written (TOML), before validation.
//!
//! Every table refuses unknown fields, so a typo is an error rather than a silently
//! ignored setting. Values that carry a unit are [`Q`]: a plain number (SI) or a string
//! with a unit (`"20 um"`, `"3000 rpm"`). Every value keeps its byte span in the file so
//! that validation can point at it. The reference for users is `docs/model-file.md`.

mod housing;

pub use housing::{HousingFile, SqueezeFilmFile};

use serde::Deserialize;
use toml::Spanned;

/// A number in SI, or a string with a unit. Which units are accepted depends on the field.
#[derive(Debug, Clone, Deserialize)]
#[serde(untagged)]
pub enum NumOrText {
    /// A plain number: SI.
    Number(f64),
    /// A number with a unit, e.g. `"20 um"`.
    Text(String),
}

/// A quantity as written, with its place in the file.
pub type Q = Spanned<NumOrText>;

/// A whole number (node index, element count) as written, with its place in the file.
pub type Count = Spanned<i64>;

/// The whole model file.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ModelFile {
    /// A name for plots and summaries.
    pub name: Option<String>,
    /// Gravity along -y in m/s^2 (default 9.81; 0 switches it off).
    pub gravity: Option<Spanned<f64>>,
    /// Materials referred to by name.
    #[serde(default)]
    pub material: Vec<Spanned<MaterialFile>>,
    /// Shaft sections, from z = 0 along +z.
    #[serde(default)]
    pub shaft: Vec<Spanned<ShaftSectionFile>>,
    /// Element options for the whole shaft.
    pub elements: Option<ElementOptionsFile>,
    /// Rigid disks.
    #[serde(default)]
    pub disk: Vec<Spanned<DiskFile>>,
    /// Linear bearings and supports.
    #[serde(default)]
    pub bearing: Vec<Spanned<LinearBearingFile>>,
    /// Cylindrical roller bearings with internal radial clearance.
    #[serde(default)]
    pub roller_bearing: Vec<Spanned<RollerBearingFile>>,
    /// Deep-groove and angular-contact ball bearings.
    #[serde(default)]
    pub ball_bearing: Vec<Spanned<super::ball_file::BallBearingFile>>,
    /// Bearing housings, pedestals and casings.
    #[serde(default)]
    pub housing: Vec<Spanned<HousingFile>>,
    /// Rayleigh damping of the rotor (shaft and disks).
    pub damping: Option<Spanned<DampingFile>>,
    /// Unbalances.
    #[serde(default)]
    pub unbalance: Vec<Spanned<UnbalanceFile>>,
    /// Operating speed range, for separation margins.
    pub operating: Option<Spanned<OperatingFile>>,
}

/// `[[material]]`
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MaterialFile {
    pub name: Spanned<String>,
    /// Young's modulus, Pa.
    pub young_modulus: Spanned<f64>,
    /// Density, kg/m^3.
    pub density: Spanned<f64>,
    /// Poisson's ratio (default 0.3).
    pub poisson_ratio: Option<Spanned<f64>>,
}

/// `[[shaft]]`: one section of constant cross-section.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ShaftSectionFile {
    pub length: Q,
    pub outer_diameter: Q,
    pub inner_diameter: Option<Q>,
    pub material: Spanned<String>,
    /// Number of equal beam elements in the section.
    pub elements: Count,
    /// `"euler-bernoulli"` or `"timoshenko"` (default: `elements.beam`).
    pub beam: Option<Spanned<String>>,
    /// Shear factor kappa (default: Cowper's value for a circular tube).
    pub shear_factor: Option<Spanned<f64>>,
}

/// `[elements]`
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ElementOptionsFile {
    pub rotary_inertia: Option<bool>,
    pub gyroscopic: Option<bool>,
    /// Axial force in N, tension positive.
    pub axial_load: Option<Spanned<f64>>,
    /// `"euler-bernoulli"` (default) or `"timoshenko"`.
    pub beam: Option<Spanned<String>>,
}

/// `[[disk]]`: inertias given directly, or computed from geometry and material.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DiskFile {
    pub name: Option<String>,
    pub node: Option<Count>,
    pub z: Option<Q>,
    pub mass: Option<Q>,
    /// kg m^2
    pub polar_inertia: Option<Spanned<f64>>,
    /// kg m^2
    pub diametral_inertia: Option<Spanned<f64>>,
    pub outer_diameter: Option<Q>,
    pub bore: Option<Q>,
    pub width: Option<Q>,
    pub material: Option<Spanned<String>>,
}

/// `[[bearing]]`: a linear support, as 2x2 stiffness and damping, or as a ring of springs.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LinearBearingFile {
    pub name: Option<String>,
    pub node: Option<Count>,
    pub z: Option<Q>,
    pub kxx: Option<Spanned<f64>>,
    pub kyy: Option<Spanned<f64>>,
    pub kxy: Option<Spanned<f64>>,
    pub kyx: Option<Spanned<f64>>,
    pub cxx: Option<Spanned<f64>>,
    pub cyy: Option<Spanned<f64>>,
    pub cxy: Option<Spanned<f64>>,
    pub cyx: Option<Spanned<f64>>,
    /// Number of equal springs in a ring (thesis eq. 2.16-2.20).
    pub springs: Option<Count>,
    /// Stiffness of each spring of the ring, N/m.
    pub spring_stiffness: Option<Spanned<f64>>,
    /// The `[[housing]]` its outer side sits in; the ground when absent.
    pub housing: Option<Spanned<String>>,
}

/// A clearance: constant, or a polynomial in speed (thesis eq. 3.1).
#[derive(Debug, Deserialize)]
#[serde(untagged)]
pub enum ClearanceFile {
    Constant(NumOrText),
    Polynomial(ClearancePolynomialFile),
}

/// `clearance = { coefficients = [...], clearance_unit = "in", speed_unit = "rpm" }`
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ClearancePolynomialFile {
    pub coefficients: Vec<f64>,
    pub clearance_unit: String,
    pub speed_unit: String,
}

/// `contact_stiffness = 4.52e8` or `"palmgren"`.
#[derive(Debug, Deserialize)]
#[serde(untagged)]
pub enum ContactStiffnessFile {
    Value(f64),
    Rule(String),
}

/// `[[roller_bearing]]`
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RollerBearingFile {
    pub name: Option<String>,
    pub node: Option<Count>,
    pub z: Option<Q>,
    pub rollers: Count,
    pub pitch_diameter: Q,
    pub roller_diameter: Q,
    pub roller_length: Q,
    pub clearance: Spanned<ClearanceFile>,
    pub contact_stiffness: Spanned<ContactStiffnessFile>,
    pub contact_exponent: Option<Spanned<f64>>,
    pub contact_damping: Option<Spanned<f64>>,
    /// Angle of the first roller at t = 0, degrees from +x towards +y.
    pub cage_angle: Option<Spanned<f64>>,
    /// Cage speed over shaft speed; from the geometry when absent.
    pub cage_speed_ratio: Option<Spanned<f64>>,
    /// Linearised radial stiffness for modal analysis, N/m.
    pub linear_stiffness: Spanned<f64>,
    /// Linearised radial damping for modal analysis, N s/m.
    pub linear_damping: Option<Spanned<f64>>,
    /// Roller tilt: contact sliced along the roller, following the shaft's slope.
    pub roller_tilt: Option<bool>,
    /// Number of slices along a roller when `roller_tilt` or `skew_angle` is used.
    pub slices: Option<Count>,
    /// Roller skew angle, degrees.
    pub skew_angle: Option<Spanned<f64>>,
    /// Ring waviness components (thesis eq. 3.18, or fixed to the ring).
    #[serde(default)]
    pub waviness: Vec<Spanned<WavinessFile>>,
    /// Local raceway defects (spalls).
    #[serde(default)]
    pub defect: Vec<Spanned<DefectFile>>,
    /// Forcing-function law (thesis eq. 3.12) used by `--contact forcing`.
    pub forcing_function: Option<Spanned<ForcingFunctionFile>>,
    /// Basic dynamic load rating C (force), the catalogue's; ISO 281's formula otherwise.
    pub dynamic_load_rating: Option<Q>,
    /// The `[[housing]]` its outer ring sits in; the ground when absent.
    pub housing: Option<Spanned<String>>,
}

/// `[[roller_bearing.waviness]]`
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WavinessFile {
    /// `"outer"` or `"inner"`.
    pub ring: Spanned<String>,
    /// Waviness order N_w (lobes).
    pub order: Count,
    /// Amplitude (length).
    pub amplitude: Q,
    /// Phase, degrees.
    pub phase: Option<Spanned<f64>>,
    /// `"thesis"` (eq. 3.18 as printed, the default) or `"ring_fixed"`.
    pub form: Option<Spanned<String>>,
}

/// `[[roller_bearing.defect]]`
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DefectFile {
    /// `"outer"`, `"inner"`, or `"element"` for a spot on a roller or ball.
    pub ring: Spanned<String>,
    /// With `ring = "element"`: which roller or ball, 0-based.
    pub element: Option<Count>,
    /// Centre, degrees in the ring's frame.
    pub angle: Option<Spanned<f64>>,
    /// Angular width, degrees.
    pub width: Spanned<f64>,
    /// Largest depth (length).
    pub depth: Q,
}

/// `forcing_function = { a0 = ..., a1 = ..., b0 = ..., b1 = ... }`: in SI with the speed
/// in rad/s, F [N] = (a0 + a1 W) (u_r - gamma)_+ ^ (b0 + b1 W).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ForcingFunctionFile {
    pub a0: f64,
    #[serde(default)]
    pub a1: f64,
    pub b0: f64,
    #[serde(default)]
    pub b1: f64,
}

/// `[damping]`: coefficients, or damping ratios at two frequencies.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DampingFile {
    /// Multiplies M, 1/s.
    pub alpha: Option<f64>,
    /// Multiplies K, s.
    pub beta: Option<f64>,
    pub ratios: Option<Vec<f64>>,
    pub frequencies: Option<Vec<NumOrText>>,
    /// Multiplies alpha and beta however they were given (a study's damping dimension).
    pub scale: Option<f64>,
}

/// `[[unbalance]]`
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct UnbalanceFile {
    pub node: Option<Count>,
    pub z: Option<Q>,
    /// Eccentricity of the disk mass at the node (or of `mass`).
    pub eccentricity: Option<Q>,
    /// Unbalance as mass times radius, kg m.
    pub mass_radius: Option<Spanned<f64>>,
    /// ISO 21940-11 balance quality grade G in mm/s, with `grade_speed`.
    pub grade: Option<Spanned<f64>>,
    pub grade_speed: Option<Q>,
    /// The mass carrying the eccentricity or grade, when no disk sits at the node.
    pub mass: Option<Q>,
    /// Angle of the unbalance at t = 0, degrees from +x towards +y.
    pub phase: Option<Spanned<f64>>,
}

/// `[operating]`
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct OperatingFile {
    pub min_speed: NumOrText,
    pub max_speed: NumOrText,
}
