//! Static response under gravity: deflection, slope, bending moment and shear force along
//! the shaft, bearing reactions and the loads of the rollers.
//!
//! The displacements solve K q = F_g (linear bearings, and roller bearings by their
//! `linear_stiffness`), or the nonlinear equilibrium K q - F_g - F_c(q) = 0 with each
//! roller bearing's Hertz contacts ([`crate::time::static_equilibrium`]). The internal
//! forces come from each element's end forces
//!
//! ```text
//! f_e = K_e u_e - f_g,e        (f_g,e: the element's own consistent gravity load)
//! ```
//!
//! which are exact at the nodes for the uniform load of the shaft's weight (the element
//! solves the static beam equations; disks and bearings load the nodes). With the bending
//! moment M = E I d(beta)/dz (beta the section rotation, w' for Euler-Bernoulli; positive
//! when the shaft sags, i.e. concave up) and the shear force V = dM/dz, the principle of
//! virtual work on an element [a, b] gives, per plane with nodal values (w, beta),
//!
//! ```text
//! f_w(a) = V(a),   f_beta(a) = -M(a),   f_w(b) = -V(b),   f_beta(b) = M(b)
//! ```
//!
//! In whirl's DOFs the x plane is (ux, ty) = (w, beta) and the y plane (uy, tx) = (w, -beta).
//! Every interior node is reported twice, as the end of the element on its left and the
//! start of the one on its right, so the shear force's jumps at disks and bearings show.

mod report;
mod sections;
mod supports;

pub use report::StaticSummary;
pub use sections::{station_forces, Station};
pub use supports::{BearingReaction, RollerLoad};

use serde::Serialize;

use crate::bearing::hertz_bearings;
use crate::error::{Error, Result};
use crate::fe::{band_reach, dof, stiffness_product, Bearings, Direction};
use crate::force::{no_forces, ForceBuilder};
use crate::model::Model;
use crate::system::banded;
use crate::time::statics::{equilibrium, Product, Structure};

/// How roller bearings carry the load; by default by their contacts.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize)]
#[cfg_attr(feature = "clap", derive(clap::ValueEnum))]
#[serde(rename_all = "lowercase")]
pub enum RollerSupport {
    /// Hertz line contact per roller, with the clearance: the rotor drops through its
    /// clearance onto the rollers below.
    #[default]
    Hertz,
    /// The bearing's `linear_stiffness`, as in the linear analyses.
    Linear,
}

/// The largest deflection along the shaft.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct MaxDeflection {
    /// Radial deflection sqrt(ux^2 + uy^2), m.
    pub value: f64,
    /// Node where it occurs.
    pub node: usize,
    /// Its axial position, m.
    pub z: f64,
}

/// The static response of a model under gravity.
#[derive(Debug, Clone, Serialize)]
pub struct StaticResult {
    /// Stations along the shaft, by z; interior nodes twice (left and right element).
    pub stations: Vec<Station>,
    /// One reaction per bearing, linear bearings first, then roller bearings.
    pub reactions: Vec<BearingReaction>,
    /// Weight of the rotor (shaft and disks), N.
    pub weight: f64,
    /// The largest deflection.
    pub max_deflection: MaxDeflection,
    /// How roller bearings carried the load.
    pub roller_support: RollerSupport,
    /// Gravity, m/s^2.
    pub gravity: f64,
    /// Every DOF's displacement, m or rad (global numbering, see [`crate::fe`]).
    pub displacements: Vec<f64>,
}

impl StaticResult {
    /// Sum of the bearings' forces on the shaft, [x, y], N: [0, weight] in equilibrium.
    pub fn total_reaction(&self) -> [f64; 2] {
        self.reactions
            .iter()
            .fold([0.0, 0.0], |s, r| [s[0] + r.force[0], s[1] + r.force[1]])
    }
}

/// Most bytes the static response's bands may take ([`fits_on_bands`]): a sixth of the 24 GB
/// machine it was measured on. A plain mesh never comes near it (10,000 elements: 64 MB in
/// all).
const MAX_BAND_BYTES: f64 = 4e9;

/// Bands of the model's size and width held at once: M, K, G and C and their parts
/// ([`crate::fe::BandedSystem`]), K_ww, its symmetric part and their factors.
const BANDS_HELD: f64 = 12.0;

/// Refuses, before anything is allocated, a model whose bands would not fit: a bearing
/// between the shaft and a housing widens them to reach the housing's DOFs, numbered after
/// all the shaft's, so their memory grows as the square of the elements (330 MB measured at
/// 500 elements of `examples/reference_rotor_sfd.toml` with linear rollers).
///
/// # Errors
/// [`Error::Unsupported`] above [`MAX_BAND_BYTES`], naming the size and the fix.
fn fits_on_bands(model: &Model, bearings: Bearings) -> Result<()> {
    let (n, reach) = (model.dof_count(), band_reach(model, bearings));
    let bytes = BANDS_HELD * 8.0 * n as f64 * (2 * reach + 1) as f64;
    if bytes <= MAX_BAND_BYTES {
        return Ok(());
    }
    Err(Error::Unsupported(format!(
        "the model has {n} DOFs and a bearing in a housing couples DOFs {reach} apart (the \
         housing's follow all the shaft's): the static response's banded matrices would \
         take about {:.1} GB, more than its {:.0} GB. Use fewer elements: the static \
         deflection converges with few (it is a smooth curve), e.g. 200",
        bytes / 1e9,
        MAX_BAND_BYTES / 1e9
    )))
}

/// Static response of `model` under its gravity, roller bearings carried as `rollers` says.
///
/// The structure is held on its bands and the balance condensed onto the contacts'
/// coordinates ([`crate::time::static_equilibrium`]'s method), so memory and time grow
/// linearly with the elements: every mesh a model may have is solved (but for a bearing in
/// a housing, which widens the bands; see `fits_on_bands`).
///
/// # Errors
/// [`Error::NotConverged`] or [`Error::Singular`] when the equilibrium cannot be found (a
/// rotor not held by its bearings); [`Error::Unsupported`] when a bearing in a housing
/// widens the bands past memory (`fits_on_bands`).
pub fn static_response(model: &Model, rollers: RollerSupport) -> Result<StaticResult> {
    let (bearings, forces): (Bearings, ForceBuilder<'_>) = match rollers {
        RollerSupport::Hertz => (Bearings::NonlinearApart, &hertz_bearings),
        RollerSupport::Linear => (Bearings::Linearised, &no_forces),
    };
    fits_on_bands(model, bearings)?;
    let mut problem = banded(model, bearings, forces)?;
    // K x element by element, from each element's deformation (see
    // [`crate::fe::element_forces`]): a fine mesh's deflection keeps its digits.
    let product = problem.matrices.parts.as_ref().map(|parts| {
        move |x: &[f64], out: &mut [f64]| {
            stiffness_product(model, &parts.support_stiffness, x, out);
        }
    });
    let structure = Structure {
        stiffness: &problem.matrices.stiffness,
        mass: &problem.matrices.mass,
        constant_force: &problem.constant_force,
        product: product.as_ref().map(|p| p as &Product<'_>),
    };
    let rest = vec![0.0; problem.matrices.dofs()];
    let q = equilibrium(&structure, &mut problem.nonlinear, &rest, 0.0)?;
    if q.iter().any(|v| !v.is_finite()) {
        return Err(Error::singular(
            "stiffness matrix",
            "the static deflection is not finite: check that the bearings hold the rotor".into(),
        ));
    }
    let weight = -(0..model.node_count())
        .map(|node| problem.constant_force[dof(node, Direction::Uy)])
        .sum::<f64>();
    let stations = station_forces(model, &q);
    let reactions = supports::reactions(model, &q, rollers)?;
    let z = model.node_positions();
    let max_deflection = (0..z.len())
        .map(|node| MaxDeflection {
            value: q[dof(node, Direction::Ux)].hypot(q[dof(node, Direction::Uy)]),
            node,
            z: z[node],
        })
        .fold(None, |best: Option<MaxDeflection>, m| match best {
            Some(b) if b.value >= m.value => Some(b),
            _ => Some(m),
        })
        .ok_or_else(|| Error::InvalidOption("the shaft has no nodes".into()))?;
    Ok(StaticResult {
        stations,
        reactions,
        weight,
        max_deflection,
        roller_support: rollers,
        gravity: model.gravity,
        displacements: q,
    })
}

crate::given::choice!(RollerSupport { "hertz" => RollerSupport::Hertz, "linear" => RollerSupport::Linear });
