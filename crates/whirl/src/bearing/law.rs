//! How the roller bearings are modelled ([`ContactLaw`]) and the frequencies their rollers
//! excite (docs/theory.md section 5, thesis figs. 4.7 and 4.9):
//!
//! ```text
//! w_vc = N_b w_c            (varying compliance, eq. 4.4)
//! w_P  = (N_w - 1) w_c      (each waviness component of order N_w, eq. 4.5)
//! w_P  = k N_b w_c          (a ring-fixed outer-ring waviness, N_w = k N_b +- 1)
//! ```
//!
//! with w_c = (1 - D_b/D_p) Omega / 2 the cage speed; [`ContactFrequency`] names them.

use serde::Serialize;

use super::{characteristic_frequencies, forcing_bearings, hertz_bearings, RollerGeometry};
use crate::fe::Bearings;
use crate::force::{no_forces, ForceBuilder};
use crate::model::{Model, Ring, RollerBearing, Waviness, WavinessForm};

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
    /// `varying compliance`, `waviness <ring> order <N_w>`,
    /// `ring-fixed waviness <ring> order <N_w>`, `outer race defect (BPFO)`,
    /// `inner race defect (BPFI)`, `element <j> spot (2 BSF)` or `element <j> spot (FTF)`.
    pub source: String,
    /// N_b for the varying compliance, N_w - 1 for a thesis-form waviness, k N_b (less
    /// N_w Omega / w_c on the inner ring) for a ring-fixed one: multiples of the cage speed.
    pub cage_orders: f64,
    /// The frequency, Hz.
    pub frequency_hz: f64,
}

/// The varying-compliance frequency N_b w_c, every waviness frequency and every defect's
/// lines (`defect_frequencies`) of `bearing` at
/// spin speed `speed` (rad/s), in Hz: (N_w - 1) w_c for the thesis' form, k N_b w_c for an
/// outer ring-fixed waviness of order N_w = k N_b +- 1, |k N_b w_c - N_w Omega| for an
/// inner one (a ring-fixed waviness of another order exerts no force on a centred shaft).
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
        let Some(orders) = waviness_cage_orders(bearing, w) else {
            continue;
        };
        let form = match w.form {
            WavinessForm::Thesis => "",
            WavinessForm::RingFixed => "ring-fixed ",
        };
        out.push(ContactFrequency {
            source: format!("{form}waviness {ring} order {}", w.order),
            cage_orders: orders,
            frequency_hz: hz(orders * geometry.cage_speed(speed)),
        });
    }
    out.extend(defect_frequencies(bearing, speed));
    out
}

/// The lines of `bearing`'s defects at spin speed `speed` (rad/s): BPFO for an outer-race
/// defect, BPFI for an inner-race one, and for a spot on an element 2 BSF (it meets both
/// races once per spin turn) and FTF (it is loaded once per cage turn).
fn defect_frequencies(bearing: &RollerBearing, speed: f64) -> Vec<ContactFrequency> {
    let f = characteristic_frequencies(bearing, speed / (2.0 * std::f64::consts::PI));
    let line = |source: String, frequency_hz: f64| ContactFrequency {
        source,
        cage_orders: frequency_hz / f.ftf,
        frequency_hz,
    };
    let mut out: Vec<ContactFrequency> = bearing
        .defects
        .iter()
        .map(|d| match d.ring {
            Ring::Outer => line("outer race defect (BPFO)".into(), f.bpfo),
            Ring::Inner => line("inner race defect (BPFI)".into(), f.bpfi),
        })
        .collect();
    for d in &bearing.element_defects {
        out.push(line(
            format!("element {} spot (2 BSF)", d.element),
            2.0 * f.bsf,
        ));
        out.push(line(format!("element {} spot (FTF)", d.element), f.ftf));
    }
    out
}

/// The frequency at which waviness `w` of `bearing` acts, in multiples of the cage speed,
/// or `None` for a ring-fixed order the rollers cancel. For a ring-fixed shape roller j
/// meets A cos(N_w (theta_j - phi_ring) + xi); its force sum_j (...) e^(i theta_j) keeps
/// only the harmonics e^(i m theta_j) with m a multiple of N_b, so N_w +- 1 = k N_b, turning
/// at k N_b w_c - N_w w_ring.
fn waviness_cage_orders(bearing: &RollerBearing, w: &Waviness) -> Option<f64> {
    let order = w.order;
    match w.form {
        WavinessForm::Thesis => Some(order as f64 - 1.0),
        WavinessForm::RingFixed => {
            let rollers = bearing.rollers;
            let k_nb = [order + 1, order.saturating_sub(1)]
                .into_iter()
                .find(|m| *m > 0 && m % rollers == 0)?;
            let ring_orders = match w.ring {
                Ring::Outer => 0.0,
                Ring::Inner => order as f64 / bearing.cage_speed_ratio,
            };
            Some((k_nb as f64 - ring_orders).abs())
        }
    }
}

crate::given::choice!(ContactLaw {
    "hertz" => ContactLaw::Hertz,
    "lagrange" => ContactLaw::Lagrange,
    "forcing" => ContactLaw::Forcing,
    "linear" => ContactLaw::Linear,
});
