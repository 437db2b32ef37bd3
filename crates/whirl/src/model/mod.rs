//! The validated rotor model: every number in SI, every reference resolved.
//!
//! Data flows one way: model file (the private `schema`, as written) -> [`Model`] (this
//! module, after the private `validate`) -> finite-element mesh and matrices ([`crate::fe`])
//! -> solvers. The file's format is documented for users in `docs/model-file.md`; only the
//! validated [`Model`] is public.
//!
//! Stations: a feature (disk, bearing, unbalance) sits at a node. The file may give the
//! node index or the axial position `z`; both are kept, so that a re-meshed model (mesh
//! convergence study) can place the feature at the same `z`.

mod ball;
mod ball_file;
pub mod ball_law;
mod housing;
pub mod ross;
mod schema;
mod validate;

pub use ball::{
    ball_stiffness, point_contact, BallContact, PointContact, BEARING_STEEL_MODULUS,
    BEARING_STEEL_POISSON,
};
pub use housing::{Cavitation, Housing, SqueezeFilm};
pub use validate::MAX_ELEMENTS;

/// DOFs per shaft node: ux, uy, tx, ty (the numbering is [`crate::fe`]'s).
pub const DOFS_PER_NODE: usize = 4;

use std::path::{Path, PathBuf};

use serde::Serialize;

use crate::error::{Error, InputError, Result};

/// A material of the shaft or of a disk.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Material {
    /// Name used in the file.
    pub name: String,
    /// Young's modulus, Pa.
    pub young_modulus: f64,
    /// Density, kg/m^3.
    pub density: f64,
    /// Poisson's ratio.
    pub poisson_ratio: f64,
}

/// A shaft section of constant circular (possibly hollow) cross-section.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ShaftSection {
    /// Length, m.
    pub length: f64,
    /// Outer diameter, m.
    pub outer_diameter: f64,
    /// Inner diameter (bore), m; 0 for a solid shaft.
    pub inner_diameter: f64,
    /// Material.
    pub material: Material,
    /// Number of equal beam elements.
    pub elements: usize,
    /// The beam theory of its elements.
    pub beam: BeamTheory,
    /// Shear factor kappa of the cross-section (used by Timoshenko elements).
    pub shear_factor: f64,
}

/// Which beam theory the shaft elements follow.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Default)]
#[serde(rename_all = "kebab-case")]
pub enum BeamTheory {
    /// Plane sections stay normal to the axis (no shear deformation): the default.
    #[default]
    EulerBernoulli,
    /// Shear deformation with the section's shear factor (Timoshenko): needed for short,
    /// thick shafts, where Euler-Bernoulli overestimates the frequencies.
    Timoshenko,
}

impl BeamTheory {
    /// The name used in model files.
    pub fn name(self) -> &'static str {
        match self {
            BeamTheory::EulerBernoulli => "euler-bernoulli",
            BeamTheory::Timoshenko => "timoshenko",
        }
    }
}

impl ShaftSection {
    /// Cross-section area, m^2.
    pub fn area(&self) -> f64 {
        std::f64::consts::PI / 4.0 * (self.outer_diameter.powi(2) - self.inner_diameter.powi(2))
    }

    /// Second moment of area about a diameter, m^4.
    pub fn second_moment(&self) -> f64 {
        std::f64::consts::PI / 64.0 * (self.outer_diameter.powi(4) - self.inner_diameter.powi(4))
    }
}

/// Shear factor kappa of a circular tube of diameters `outer` > `inner` >= 0 (Cowper 1966,
/// "The shear coefficient in Timoshenko's beam theory", J. Appl. Mech. 33):
/// kappa = 6 (1 + nu) (1 + m^2)^2 / ((7 + 6 nu) (1 + m^2)^2 + (20 + 12 nu) m^2), m = inner/outer;
/// 6 (1 + nu) / (7 + 6 nu) for a solid section (0.886 for nu = 0.3).
pub fn circular_shear_factor(outer: f64, inner: f64, poisson_ratio: f64) -> f64 {
    let nu = poisson_ratio;
    let m2 = (inner / outer).powi(2);
    let a = (1.0 + m2).powi(2);
    6.0 * (1.0 + nu) * a / ((7.0 + 6.0 * nu) * a + (20.0 + 12.0 * nu) * m2)
}

/// Options that apply to every beam element.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct ElementOptions {
    /// Include the rotary inertia of the shaft's cross-sections.
    pub rotary_inertia: bool,
    /// Include the shaft's gyroscopic matrix.
    pub gyroscopic: bool,
    /// Axial force, N, tension positive (thesis eq. 2.3).
    pub axial_load: f64,
    /// Beam theory of the sections that do not choose their own.
    pub beam: BeamTheory,
}

impl Default for ElementOptions {
    fn default() -> Self {
        ElementOptions {
            rotary_inertia: true,
            gyroscopic: true,
            axial_load: 0.0,
            beam: BeamTheory::EulerBernoulli,
        }
    }
}

/// Where a feature sits on the shaft.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Station {
    /// Node index (0 at z = 0).
    pub node: usize,
    /// Axial position, m.
    pub z: f64,
}

/// A rigid disk (thesis eq. 2.13-2.14).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Disk {
    /// Name for outputs.
    pub name: String,
    /// Where it sits.
    pub station: Station,
    /// Mass, kg.
    pub mass: f64,
    /// Polar moment of inertia about the spin axis, kg m^2.
    pub polar_inertia: f64,
    /// Diametral moment of inertia, kg m^2.
    pub diametral_inertia: f64,
}

/// A linear bearing: forces -k u - c u' on the node's translations (x, y order).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct LinearBearing {
    /// Name for outputs.
    pub name: String,
    /// Where it sits.
    pub station: Station,
    /// [[kxx, kxy], [kyx, kyy]], N/m.
    pub stiffness: [[f64; 2]; 2],
    /// [[cxx, cxy], [cyx, cyy]], N s/m.
    pub damping: [[f64; 2]; 2],
    /// The housing its outer side sits in (index in [`Model::housings`]); `None`: ground.
    pub housing: Option<usize>,
}

/// Internal radial clearance of a roller bearing (thesis eq. 3.1).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub enum Clearance {
    /// The same at every speed, m.
    Constant(f64),
    /// gamma(Omega) = sum c_i Omega^i with gamma in m and Omega in rad/s.
    Polynomial(Vec<f64>),
}

impl Clearance {
    /// Clearance at spin speed `omega` (rad/s), m.
    pub fn at_speed(&self, omega: f64) -> f64 {
        match self {
            Clearance::Constant(c) => *c,
            Clearance::Polynomial(c) => c.iter().rev().fold(0.0, |acc, &ci| acc * omega + ci),
        }
    }
}

/// A cylindrical roller bearing with internal radial clearance (thesis ch. 3).
/// The inner ring turns with the shaft; the outer ring is fixed.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RollerBearing {
    /// Name for outputs.
    pub name: String,
    /// Where it sits.
    pub station: Station,
    /// Number of rollers N_b.
    pub rollers: usize,
    /// Pitch diameter D_p, m.
    pub pitch_diameter: f64,
    /// Roller diameter D_b, m.
    pub roller_diameter: f64,
    /// Roller length, m.
    pub roller_length: f64,
    /// Internal radial clearance gamma_0.
    pub clearance: Clearance,
    /// Contact stiffness K_c per roller, N/m^n.
    pub contact_stiffness: f64,
    /// Contact exponent n (10/9 for line contact).
    pub contact_exponent: f64,
    /// Contact damping C_c per roller, N s/m.
    pub contact_damping: f64,
    /// Angle of the first roller at t = 0, rad from +x towards +y.
    pub cage_angle: f64,
    /// Cage speed over shaft speed w_c / W: given in the file (a measured cage frequency)
    /// or, by default, the rolling kinematics of a fixed outer ring, (1 - D_b / D_p) / 2.
    pub cage_speed_ratio: f64,
    /// Linearised radial stiffness used by linear analyses (modal, unbalance), N/m.
    pub linear_stiffness: f64,
    /// Linearised radial damping used by linear analyses, N s/m.
    pub linear_damping: f64,
    /// Contact sliced along the roller, each slice's approach following the shaft's slope
    /// at the bearing (roller tilt, thesis eqs. 3.13-3.15).
    pub roller_tilt: bool,
    /// Slices along each roller (1 when neither tilt nor skew is modelled).
    pub slices: usize,
    /// Roller skew angle, rad (thesis eqs. 3.16-3.17).
    pub skew_angle: f64,
    /// Ring waviness components (thesis eq. 3.18, or fixed to the ring).
    pub waviness: Vec<Waviness>,
    /// Local raceway defects (spalls).
    pub defects: Vec<RaceDefect>,
    /// Spots on rolling elements.
    pub element_defects: Vec<ElementDefect>,
    /// Forcing-function law (thesis eq. 3.12), when given.
    pub forcing_function: Option<ForcingFunction>,
    /// The balls' point contacts when the rolling elements are balls (`[[ball_bearing]]`).
    pub ball: Option<BallContact>,
    /// Basic dynamic load rating C from the file (a catalogue's), N; without it the life
    /// takes ISO 281's formula for the geometry ([`crate::bearing::life`]).
    pub dynamic_load_rating: Option<f64>,
    /// The housing its outer ring sits in (index in [`Model::housings`]); `None`: ground.
    pub housing: Option<usize>,
}

/// Which ring is wavy.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Ring {
    /// The fixed outer ring.
    Outer,
    /// The inner ring, turning with the shaft.
    Inner,
}

/// How a waviness component is laid on its ring.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum WavinessForm {
    /// The thesis' eq. 3.18 as printed: roller j loses A cos(N_w (w_c - w_ring) t + 2 pi j /
    /// N_b + xi), the order multiplying the time term only. It is not a shape of the ring
    /// but a roller-phased excitation whose net force turns at (N_w - 1) w_c for any order
    /// (eq. 4.5).
    Thesis,
    /// A shape of the ring, A cos(N_w psi + xi) at the ring's own angle psi: roller j at
    /// theta_j loses A cos(N_w (theta_j - phi_ring) + xi). Its net force on a centred shaft
    /// is zero unless N_w = k N_b +- 1.
    RingFixed,
}

/// One waviness component: the ring's radius varies by `amplitude cos(order ...)`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Waviness {
    /// The wavy ring.
    pub ring: Ring,
    /// Thesis form or fixed to the ring.
    pub form: WavinessForm,
    /// Order N_w.
    pub order: usize,
    /// Amplitude, m.
    pub amplitude: f64,
    /// Phase, rad.
    pub phase: f64,
}

/// A local defect of a raceway (a spall): the race recedes by a raised-cosine dip
/// depth (1 + cos(2 pi s / width)) / 2 for |s| < width / 2, s the angle from the defect's
/// centre in the ring's frame. The dip is smooth so the approach's rate stays finite; a
/// roller is taken to follow the profile (its curvature is not rolled over the edges).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RaceDefect {
    /// The ring it is on.
    pub ring: Ring,
    /// Centre, rad in the ring's frame from +x towards +y (for the inner ring at spin
    /// angle 0).
    pub angle: f64,
    /// Angular width, rad, below 2 pi.
    pub width: f64,
    /// Largest depth, m.
    pub depth: f64,
}

/// A spot on one rolling element: as it spins, the element's surface recedes by the same
/// raised-cosine dip as a [`RaceDefect`] wherever the spot meets a race, outer (spin angle
/// 0 from the spot's centre) or inner (pi): the approach dips twice per spin turn, at
/// 2 BSF relative to the cage.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ElementDefect {
    /// The element, 0-based (element 0 sits at the cage angle).
    pub element: usize,
    /// Spin angle of the spot's centre from the outer contact at spin angle 0, rad.
    pub angle: f64,
    /// Angular width on the element, rad, below pi.
    pub width: f64,
    /// Largest depth, m.
    pub depth: f64,
}

/// Forcing-function bearing law (thesis eq. 3.12):
/// F = (a0 + a1 W) (u_r - gamma)_+^(b0 + b1 W), F in N, u_r in m, W in rad/s.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct ForcingFunction {
    /// N/m^b at rest.
    pub a0: f64,
    /// Change of the coefficient per rad/s.
    pub a1: f64,
    /// Exponent at rest.
    pub b0: f64,
    /// Change of the exponent per rad/s.
    pub b1: f64,
}

impl ForcingFunction {
    /// Coefficient and exponent at spin speed `omega`, rad/s.
    pub fn at_speed(&self, omega: f64) -> (f64, f64) {
        (self.a0 + self.a1 * omega, self.b0 + self.b1 * omega)
    }
}

impl RollerBearing {
    /// Palmgren's line-contact stiffness for one roller, inner and outer raceway contacts
    /// in series, in N/m^(10/9).
    ///
    /// Per contact `delta[mm] = 3.84e-5 Q[N]^0.9 / l[mm]^0.8` (Palmgren), i.e.
    /// Q = k delta^(10/9) with k = (l_mm^0.8 / 3.84e-5 * 1e3)^(10/9) in SI. Two equal
    /// contacts in series: K = (2 k^(-9/10))^(-10/9) = k 2^(-10/9) (docs/theory.md section 5
    /// erratum of thesis eq. 3.6, which used the ball-bearing exponent).
    pub fn palmgren_stiffness(roller_length: f64) -> f64 {
        let n = 10.0 / 9.0;
        let l_mm = roller_length * 1e3;
        let per_contact = (l_mm.powf(0.8) / 3.84e-5 * 1e3).powf(n);
        per_contact * 2f64.powf(-n)
    }
}

/// Rayleigh damping of the rotor: C = alpha M + beta K (shaft and disks only).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Default)]
pub struct RayleighDamping {
    /// Mass-proportional coefficient, 1/s.
    pub alpha: f64,
    /// Stiffness-proportional coefficient, s.
    pub beta: f64,
}

impl RayleighDamping {
    /// Coefficients that give damping ratios `zeta` at circular frequencies `omega` (rad/s):
    /// zeta_i = alpha / (2 w_i) + beta w_i / 2.
    pub fn from_ratios(zeta: [f64; 2], omega: [f64; 2]) -> Self {
        let (w1, w2) = (omega[0], omega[1]);
        let det = w2 * w2 - w1 * w1;
        RayleighDamping {
            alpha: 2.0 * w1 * w2 * (zeta[0] * w2 - zeta[1] * w1) / det,
            beta: 2.0 * (zeta[1] * w2 - zeta[0] * w1) / det,
        }
    }

    /// Damping ratio at circular frequency `omega` (rad/s).
    pub fn ratio_at(&self, omega: f64) -> f64 {
        self.alpha / (2.0 * omega) + self.beta * omega / 2.0
    }
}

/// An unbalance: a force m e Omega^2 turning with the shaft.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Unbalance {
    /// Where it sits.
    pub station: Station,
    /// Mass times eccentricity, kg m.
    pub mass_radius: f64,
    /// Angle at t = 0, rad from +x towards +y.
    pub phase: f64,
}

/// Most bytes read from a model, study or ROSS file: far above any real one (a
/// 10,000-element rotor saved by ROSS is about 10 MB), so that a device or a wrong file
/// (`/dev/zero`) is refused instead of read until memory runs out.
pub const MAX_INPUT_BYTES: u64 = 64 << 20;

/// The text of an input file (model, study, ROSS rotor).
///
/// # Errors
/// The file's own read errors; [`std::io::ErrorKind::InvalidData`] above
/// [`MAX_INPUT_BYTES`] or when it is not UTF-8 text.
pub fn read_input(path: &Path) -> std::io::Result<String> {
    use std::io::Read;
    let mut text = String::new();
    std::fs::File::open(path)?
        .take(MAX_INPUT_BYTES + 1)
        .read_to_string(&mut text)?;
    if text.len() as u64 > MAX_INPUT_BYTES {
        return Err(std::io::Error::new(
            std::io::ErrorKind::InvalidData,
            format!(
                "it holds more than {} MiB, far more than any model, study or rotor file",
                MAX_INPUT_BYTES >> 20
            ),
        ));
    }
    Ok(text)
}

/// The validated model. Build it with [`Model::from_file`] or [`Model::from_toml_str`].
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Model {
    /// Name for plots and summaries.
    pub name: String,
    /// Gravity along -y, m/s^2.
    pub gravity: f64,
    /// Materials as the file defines them, in its order (sections and disks given by their
    /// geometry take theirs by name).
    pub materials: Vec<Material>,
    /// Shaft sections from z = 0.
    pub sections: Vec<ShaftSection>,
    /// Beam element options.
    pub options: ElementOptions,
    /// Rigid disks.
    pub disks: Vec<Disk>,
    /// Linear bearings.
    pub bearings: Vec<LinearBearing>,
    /// Roller bearings.
    pub roller_bearings: Vec<RollerBearing>,
    /// Bearing housings, pedestals and casings.
    pub housings: Vec<Housing>,
    /// Rotor damping.
    pub damping: RayleighDamping,
    /// Unbalances.
    pub unbalances: Vec<Unbalance>,
    /// Operating speed range (min, max), rad/s.
    pub operating: Option<(f64, f64)>,
}

impl Model {
    /// Reads and validates a model file.
    ///
    /// # Errors
    /// [`Error::Io`] when the file cannot be read; the errors of [`Model::from_toml_str`].
    pub fn from_file(path: &Path) -> Result<Model> {
        let text = read_input(path).map_err(|source| Error::Io {
            action: "read the model file",
            path: path.to_path_buf(),
            source,
        })?;
        Model::from_toml_str(&text, Some(path.to_path_buf()))
    }

    /// Validates a model given as TOML text; `file` names it in error messages.
    ///
    /// # Errors
    /// [`Error::Input`] for a syntax error, an unknown or missing field, a value out of its
    /// range or a reference that does not resolve, located in `text`.
    pub fn from_toml_str(text: &str, file: Option<PathBuf>) -> Result<Model> {
        let raw: schema::ModelFile = toml::from_str(text).map_err(|e| {
            let mut err = InputError {
                file: None,
                field: None,
                message: e.message().to_string(),
                help: None,
                span: e.span(),
                line_column: None,
            };
            if err.message.contains("unknown field") {
                err.help = Some("see docs/model-file.md for the fields of each table".into());
            }
            err.locate(file.clone(), text)
        })?;
        validate::validate(raw).map_err(|e| Error::from(e.locate(file, text)))
    }

    /// Warnings about values that are valid but implausible (a clearance of a large part of
    /// the bearing, a density no engineering solid has, a near-massless shaft), one sentence
    /// each naming the field and what to check. Models that
    /// cannot exist are refused by [`Model::from_toml_str`] instead.
    pub fn warnings(&self) -> Vec<String> {
        validate::warnings(self)
    }

    /// Checks that the rotor stands: bearings at two nodes at least. A free or singly
    /// supported shaft is a valid model (a free-free beam has its uses), but no rotor
    /// analysis can use its rigid-body modes, so the command line refuses it.
    ///
    /// # Errors
    /// [`Error::Input`] (field `bearing`) saying how the rotor is supported.
    pub fn check_supports(&self) -> Result<()> {
        validate::supports(self).map_err(Error::from)
    }

    /// Total length of the shaft, m.
    pub fn length(&self) -> f64 {
        self.sections.iter().map(|s| s.length).sum()
    }

    /// Axial positions of the nodes, m.
    pub fn node_positions(&self) -> Vec<f64> {
        node_positions(&self.sections)
    }

    /// Total mass of the shaft sections, kg.
    pub fn shaft_mass(&self) -> f64 {
        self.sections
            .iter()
            .map(|s| s.material.density * s.area() * s.length)
            .sum()
    }

    /// What sits at each node, e.g. `disk; bearing A` (empty where nothing does).
    pub fn node_features(&self) -> Vec<String> {
        let mut f = vec![Vec::<String>::new(); self.node_count()];
        for d in &self.disks {
            f[d.station.node].push(d.name.clone());
        }
        for b in &self.bearings {
            f[b.station.node].push(b.name.clone());
        }
        for b in &self.roller_bearings {
            f[b.station.node].push(b.name.clone());
        }
        for (i, u) in self.unbalances.iter().enumerate() {
            f[u.station.node].push(format!("unbalance {i}"));
        }
        f.into_iter().map(|v| v.join("; ")).collect()
    }

    /// The default speeds of a sweep: `count` speeds from `start` (rad/s) to 1.2 times the
    /// highest operating speed (API 617 asks for margins up to there), or to 800 Hz when
    /// the model states no operating range.
    pub fn default_speeds(&self, start: f64, count: usize) -> Vec<f64> {
        let top = self
            .operating
            .map_or(2.0 * std::f64::consts::PI * 800.0, |(_, max)| 1.2 * max);
        (0..count)
            .map(|i| start + (top - start) * i as f64 / (count - 1) as f64)
            .collect()
    }

    /// Number of nodes.
    pub fn node_count(&self) -> usize {
        self.sections.iter().map(|s| s.elements).sum::<usize>() + 1
    }

    /// Whether some housing has a squeeze-film damper (a nonlinear force even on linear
    /// bearings).
    pub fn has_squeeze_films(&self) -> bool {
        self.housings.iter().any(|h| h.squeeze_film.is_some())
    }

    /// Number of DOFs: four per shaft node, then two per housing.
    pub fn dof_count(&self) -> usize {
        DOFS_PER_NODE * self.node_count() + 2 * self.housings.len()
    }

    /// The DOFs [ux, uy] of housing `h` (see [`Housing`] for the numbering).
    pub fn housing_dofs(&self, h: usize) -> [usize; 2] {
        let first = DOFS_PER_NODE * self.node_count() + 2 * h;
        [first, first + 1]
    }

    /// The DOFs [ux, uy] of what a bearing's outer side sits in: housing `housing`, or
    /// `None` for the ground.
    pub fn outer_dofs(&self, housing: Option<usize>) -> Option<[usize; 2]> {
        housing.map(|h| self.housing_dofs(h))
    }

    /// Nodes that carry a bearing of either kind, sorted, without repeats.
    pub fn bearing_nodes(&self) -> Vec<usize> {
        let mut nodes: Vec<usize> = self
            .bearings
            .iter()
            .map(|b| b.station.node)
            .chain(self.roller_bearings.iter().map(|b| b.station.node))
            .collect();
        nodes.sort_unstable();
        nodes.dedup();
        nodes
    }

    /// The same model with each section meshed with `elements[i]` elements; every feature
    /// keeps its axial position. Fails when a feature does not fall on a node of the new mesh.
    ///
    /// # Errors
    /// [`Error::InvalidOption`] when the sections would have more than [`MAX_ELEMENTS`]
    /// elements in all, or a feature does not fall on a node of the new mesh.
    pub fn remeshed(&self, elements: &[usize]) -> Result<Model> {
        let mut m = self.clone();
        for (s, &n) in m.sections.iter_mut().zip(elements) {
            s.elements = n.max(1);
        }
        let total = m
            .sections
            .iter()
            .fold(0usize, |t, s| t.saturating_add(s.elements));
        if total > MAX_ELEMENTS {
            return Err(Error::InvalidOption(format!(
                "{elements:?} elements: {}",
                validate::too_many_elements(total)
            )));
        }
        let z = m.node_positions();
        let tol = 1e-9 * m.length();
        let place = |st: &mut Station| -> Result<()> {
            st.node = z
                .iter()
                .position(|&zn| (zn - st.z).abs() <= tol)
                .ok_or_else(|| {
                    Error::InvalidOption(format!(
                        "no node at z = {} m with elements {:?}",
                        st.z, elements
                    ))
                })?;
            Ok(())
        };
        for d in &mut m.disks {
            place(&mut d.station)?;
        }
        for b in &mut m.bearings {
            place(&mut b.station)?;
        }
        for b in &mut m.roller_bearings {
            place(&mut b.station)?;
        }
        for u in &mut m.unbalances {
            place(&mut u.station)?;
        }
        Ok(m)
    }
}

/// Axial positions of the nodes of a list of sections, m.
pub(crate) fn node_positions(sections: &[ShaftSection]) -> Vec<f64> {
    let mut z = vec![0.0];
    let mut start = 0.0;
    for s in sections {
        for i in 1..=s.elements {
            z.push(start + s.length * i as f64 / s.elements as f64);
        }
        start += s.length;
    }
    z
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The reference rotor's shaft as two halves of `first` and `second` elements.
    fn halves(first: usize, second: usize) -> String {
        crate::examples::REFERENCE_ROTOR
            .replace("length = \"1.3 m\"", "length = \"0.65 m\"")
            .replace(
                "elements = 20 ",
                &format!(
                    "elements = {first}\n\n[[shaft]]\nlength = \"0.65 m\"\nouter_diameter = \
                     \"55.9 mm\"\nmaterial = \"steel\"\nelements = {second} "
                ),
            )
    }

    #[test]
    fn more_elements_than_round_off_allows_are_refused_in_all_sections_together() {
        // Each section is within the limit; together they pass it, and the section that
        // takes the count past it is blamed, at its line.
        let e = Model::from_toml_str(&halves(6000, 6000), None).unwrap_err();
        let text = e.to_string();
        assert!(
            text.contains("`shaft[1].elements`")
                && text.contains("12000 elements in all, at most 10000")
                && text.contains("line 22"),
            "{text}"
        );
        let model = Model::from_toml_str(&halves(5000, 5000), None).unwrap();
        assert_eq!(model.node_count(), MAX_ELEMENTS + 1);
        // Remeshing (the convergence study, the tests' large models) keeps the same limit.
        let reference = Model::from_toml_str(crate::examples::REFERENCE_ROTOR, None).unwrap();
        let e = reference.remeshed(&[MAX_ELEMENTS + 2]).unwrap_err();
        assert!(e.to_string().contains("10002 elements in all"), "{e}");
        assert!(reference.remeshed(&[MAX_ELEMENTS]).is_ok());
    }

    #[test]
    fn cowper_factor_of_a_solid_and_a_thin_walled_section() {
        // Cowper's values: solid 6(1 + nu)/(7 + 6 nu); thin tube (m -> 1) 2(1 + nu)/(4 + 3 nu).
        let nu = 0.3;
        let solid = circular_shear_factor(1.0, 0.0, nu);
        // Exact algebra: round-off only.
        assert!((solid - 6.0 * 1.3 / 8.8).abs() < 1e-15);
        let thin = circular_shear_factor(1.0, 0.999_999, nu);
        // m = 1 - 1e-6 instead of 1 moves kappa by a few 1e-7.
        assert!((thin - 2.0 * 1.3 / 4.9).abs() < 1e-6);
    }

    #[test]
    fn palmgren_stiffness_of_the_reference_roller() {
        // docs/theory.md section 9: Palmgren with inner and outer in series gives 4.53e8 N/m^(10/9)
        // for a 7 mm roller; the reference value has three digits, hence 0.5 %.
        let k = RollerBearing::palmgren_stiffness(0.007);
        assert!((k / 4.53e8 - 1.0).abs() < 5e-3, "{k}");
    }

    #[test]
    fn rayleigh_from_ratios_reproduces_the_ratios() {
        let w = [
            2.0 * std::f64::consts::PI * 50.0,
            2.0 * std::f64::consts::PI * 254.0,
        ];
        let d = RayleighDamping::from_ratios([0.02, 0.03], w);
        // Exact algebra: only round-off.
        assert!((d.ratio_at(w[0]) - 0.02).abs() < 1e-14);
        assert!((d.ratio_at(w[1]) - 0.03).abs() < 1e-14);
    }

    #[test]
    fn clearance_polynomial_of_table_b1_read_as_inches_versus_rpm() {
        // Table B.1 read as inches versus rpm: 16.1 um at rest, about 43.7 um at 45,000 rpm.
        let a = [0.0006353, 2.129e-7, -9.172e-12, 1.535e-16, -9.53e-22];
        let rpm = 2.0 * std::f64::consts::PI / 60.0;
        let si: Vec<f64> = a
            .iter()
            .enumerate()
            .map(|(i, c)| c * 0.0254 / rpm.powi(i as i32))
            .collect();
        let c = Clearance::Polynomial(si);
        assert!((c.at_speed(0.0) - 16.137e-6).abs() < 1e-9);
        assert!((c.at_speed(45_000.0 * rpm) - 43.746e-6).abs() < 1e-9);
    }
}
