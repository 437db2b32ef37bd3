//! Cylindrical roller bearing with internal radial clearance (thesis chapter 3, docs/theory.md
//! section 5).
//!
//! The inner ring turns with the shaft, the outer ring is fixed, the rollers orbit at the
//! cage speed w_c = (1 - D_b/D_p) Omega / 2 (eq. 3.4). Roller j sits at
//! theta_j = 2 pi j / N_b + theta_cage0 + (1 - D_b/D_p) phi / 2 with phi the spin angle, which
//! is eq. 3.3 at constant speed and stays right during a speed ramp. A roller touches the
//! outer ring only when its approach (eq. 3.2, 3.19)
//!
//! ```text
//! delta_jk = u_x cos theta_j + u_y sin theta_j + z_k (t_y cos theta_j - t_x sin theta_j)
//!            - gamma(Omega) + h_skew,k - P_o(j) - P_i(j)
//! ```
//!
//! is positive. Without tilt or skew each roller is one line contact (k = 1, z = 0); with
//! them the roller is cut into slices at axial offsets z_k (eq. 3.13), each carrying
//! 1/n_slices of the contact stiffness and damping, so that an aligned sliced roller
//! carries exactly the unsliced force. [`geometry`] holds these kinematics, [`hertz`] the
//! contact law as a [`crate::force::NonlinearForce`]. [`forcing`] replaces the rollers by
//! one radial law (eq. 3.12) that [`crate::time::forcing_fit`] samples from the Hertz
//! model's response and [`forcing_regression`] fits. [`law`] names the contact laws a
//! solver can choose ([`ContactLaw`], with the forces each builds) and the frequencies the
//! rollers excite; [`frequencies`] the bearing's characteristic frequencies (BPFO, BPFI,
//! BSF, FTF).
//!
//! A ball bearing is a roller bearing whose rollers are balls: the ball law adds the point
//! contact's angle and the axial load to the same kinematics and solvers
//! ([`crate::model::ball_law`], beside the model, whose validation finds a bearing's running
//! contact angle with it).
//!
//! This module is below the solvers: it imports nothing from `time`, `hbm` or `nsv`.

pub mod forcing;
pub mod forcing_regression;
pub mod frequencies;
pub mod geometry;
pub mod hertz;
pub mod housed;
pub mod lagrange;
pub mod law;
pub(crate) mod least_squares;
pub mod life;
mod power;
pub mod stiffness;

pub use forcing::{forcing_bearings, law_speeds, valid_up_to, ForcingBearing};
pub use forcing_regression::{fit_forcing_law, ForcingPoint};
pub use frequencies::{
    bearing_orders, characteristic_frequencies, BearingOrders, CharacteristicFrequencies,
};
pub use geometry::{RollerGeometry, RollerState};
pub use hertz::{HertzBearing, HERTZ_BOUND_APPROACH};
pub use housed::{mounted, Housed};
pub use lagrange::{ContactStep, LagrangeContacts};
pub use law::{contact_frequencies, ContactFrequency, ContactLaw};
pub use life::{bearing_life, dynamic_load_rating, BearingLife, LifeLoads, RatingSource};
pub use power::Power;

use crate::error::{Error, Result};
use crate::fe::{dof, Direction};
use crate::force::NonlinearForce;
use crate::model::{Model, RollerBearing};

/// Integrator coordinates of a bearing's contact: its node's [ux, uy] (and [tx, ty] with
/// roller tilt), through `coordinate`, which maps a physical DOF to its coordinate.
///
/// # Errors
/// The errors of [`contact_coordinates_of`].
pub fn contact_coordinates(
    bearing: &RollerBearing,
    coordinate: &dyn Fn(usize) -> Option<usize>,
) -> Result<Vec<usize>> {
    let mut directions = vec![Direction::Ux, Direction::Uy];
    if bearing.roller_tilt {
        directions.extend([Direction::Tx, Direction::Ty]);
    }
    contact_coordinates_of(bearing, &directions, coordinate)
}

/// Integrator coordinates of the bearing node's `directions`, through `coordinate`.
///
/// # Errors
/// [`Error::Unsupported`] when `coordinate` does not keep one of the DOFs (a reduction
/// that does not have them among its boundary DOFs).
pub fn contact_coordinates_of(
    bearing: &RollerBearing,
    directions: &[Direction],
    coordinate: &dyn Fn(usize) -> Option<usize>,
) -> Result<Vec<usize>> {
    let node = bearing.station.node;
    directions
        .iter()
        .map(|&d| {
            coordinate(dof(node, d)).ok_or_else(|| {
                Error::Unsupported(format!(
                    "{} at node {node}: its DOFs are not kept by the reduction; they must be \
                     boundary DOFs",
                    bearing.name
                ))
            })
        })
        .collect()
}

/// Hertz contacts of every roller bearing of `model` (a [`crate::force::ForceBuilder`]).
///
/// # Errors
/// The errors of [`contact_coordinates`] ([`Error::Unsupported`] for a bearing whose DOFs
/// the reduction does not keep); [`HertzBearing::new`] cannot fail with them.
pub fn hertz_bearings(
    model: &Model,
    coordinate: &dyn Fn(usize) -> Option<usize>,
) -> Result<Vec<Box<dyn NonlinearForce>>> {
    model
        .roller_bearings
        .iter()
        .map(|b| {
            let force = HertzBearing::new(b, contact_coordinates(b, coordinate)?)?;
            mounted(model, b.housing, Box::new(force), coordinate)
        })
        .collect()
}
