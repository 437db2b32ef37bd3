//! How the roller bearings are modelled ([`ContactLaw`]) and the frequencies their rollers
//! excite (docs/theory.md section 5, thesis figs. 4.7 and 4.9):
//!
//! ```text
//! w_vc = N_b w_c            (varying compliance, eq. 4.4)
//! w_P  = (N_w - 1) w_c      (each waviness component of order N_w, eq. 4.5)
//! ```
//!
//! with w_c = (1 - D_b/D_p) Omega / 2 the cage speed; [`ContactFrequency`] names them.

use serde::Serialize;

use super::{forcing_bearings, hertz_bearings, RollerGeometry};
use crate::fe::Bearings;
use crate::force::{no_forces, ForceBuilder};
use crate::model::{Model, Ring, RollerBearing};

/// How the roller bearings act in a simulation (time marching or harmonic balance).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[cfg_attr(feature = "clap", derive(clap::ValueEnum))]
#[serde(rename_all = "lowercase")]
// In the command line's order (its help lists the laws so).
pub enum ContactLaw {
    /// Hertz line contact per roller (eq. 3.5), with tilt, skew and waviness.
    Hertz,
    /// Rigid rollers: non-penetration enforced by Lagrange multipliers on the central
    /// difference (eqs. 3.7-3.11, 4.6-4.9); the forces are the multipliers.
    Lagrange,
    /// The bearing's forcing function (eq. 3.12): one radial law, no rollers. The record
    /// holds each roller's approach; its forces are NaN.
    Forcing,
    /// Linear springs: each bearing's `linear_stiffness` and `linear_damping` in the
    /// matrices, as in the linear analyses. Nothing is recorded per roller.
    Linear,
}

impl ContactLaw {
    /// Hertz when the model has roller bearings, else linear.
    pub fn default_for(model: &Model) -> ContactLaw {
        if model.roller_bearings.is_empty() {
            ContactLaw::Linear
        } else {
            ContactLaw::Hertz
        }
    }

    /// Short name, as on the command line.
    pub fn name(self) -> &'static str {
        match self {
            ContactLaw::Linear => "linear",
            ContactLaw::Hertz => "hertz",
            ContactLaw::Forcing => "forcing",
            ContactLaw::Lagrange => "lagrange",
        }
    }

    /// Whether the roller bearings' linear stiffness goes into the matrices.
    pub fn bearings(self) -> Bearings {
        match self {
            ContactLaw::Linear => Bearings::Linearised,
            _ => Bearings::NonlinearApart,
        }
    }

    /// The nonlinear forces this law adds to a solver: the Hertz or forcing-function
    /// contacts, or none (linear bearings are in the matrices, rigid rollers are
    /// constraints rather than forces).
    pub fn forces(self) -> ForceBuilder<'static> {
        match self {
            ContactLaw::Hertz => &hertz_bearings,
            ContactLaw::Forcing => &forcing_bearings,
            ContactLaw::Linear | ContactLaw::Lagrange => &no_forces,
        }
    }
}

/// A frequency the rollers excite.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ContactFrequency {
    /// `varying compliance` or `waviness <ring> order <N_w>`.
    pub source: String,
    /// N_b for the varying compliance, N_w - 1 for a waviness: multiples of the cage speed.
    pub cage_orders: f64,
    /// The frequency, Hz.
    pub frequency_hz: f64,
}

/// The varying-compliance frequency N_b w_c and every waviness frequency (N_w - 1) w_c of
/// `bearing` at spin speed `speed` (rad/s), in Hz.
pub fn contact_frequencies(bearing: &RollerBearing, speed: f64) -> Vec<ContactFrequency> {
    let geometry = RollerGeometry::new(bearing);
    let hz = |w: f64| w / (2.0 * std::f64::consts::PI);
    let mut out = vec![ContactFrequency {
        source: "varying compliance".into(),
        cage_orders: bearing.rollers as f64,
        frequency_hz: hz(geometry.varying_compliance_frequency(speed)),
    }];
    for w in &bearing.waviness {
        let ring = match w.ring {
            Ring::Outer => "outer",
            Ring::Inner => "inner",
        };
        out.push(ContactFrequency {
            source: format!("waviness {ring} order {}", w.order),
            cage_orders: w.order as f64 - 1.0,
            frequency_hz: hz(geometry.waviness_frequency(w.order, speed)),
        });
    }
    out
}
