//! Forcing-function bearing law (thesis eq. 3.12, docs/theory.md section 5): the whole bearing as
//! one radial spring fitted to the Hertz model,
//!
//! ```text
//! F = -f(s) u / u_r,   f(s) = a(W) s_+^b(W),   s = u_r - gamma(W),   u_r = |u|
//! a(W) = a0 + a1 W,   b(W) = b0 + b1 W
//! ```
//!
//! with u = (u_x, u_y) at the bearing node, W the spin speed in rad/s and gamma the
//! clearance. The law is elastic (eq. 3.12 has no damping term) and acts on u_x, u_y only,
//! also for a bearing that models roller tilt. Its Jacobian,
//!
//! ```text
//! dF/du = -( f'(s) e e^T + f(s)/u_r (I - e e^T) ),   e = u / u_r,
//! ```
//!
//! is exact wherever the law is smooth. At the contact edge (s = 0) the force is zero and
//! so is its Jacobian, the one-sided limit for b > 1 (fitted laws have b between the
//! Hertz 10/9 and about 1.6). At u_r = 0, reachable only when gamma <= 0, the direction e is
//! undefined: the force is taken as zero (its average over directions) and the Jacobian as
//! -f'(s) I, the exact limit for gamma = 0 and b >= 1. A fitted law extrapolated to speeds
//! where a(W) or b(W) is no longer positive ([`valid_up_to`]) gives no force there.

use super::contact_coordinates_of;
use super::HERTZ_BOUND_APPROACH;
use crate::error::{Error, InputError, Result};
use crate::fe::Direction;
use crate::force::{Kinematics, NonlinearForce};
use crate::model::{Clearance, ForcingFunction, Model, RollerBearing};

/// A roller bearing modelled by its forcing function, acting on [u_x, u_y] of its node.
#[derive(Debug, Clone)]
pub struct ForcingBearing {
    name: String,
    dofs: [usize; 2],
    law: ForcingFunction,
    clearance: Clearance,
    /// Radial stiffness bound over the speeds of the run, N/m.
    bound: f64,
}

impl ForcingBearing {
    /// The bearing acting on integrator coordinates `dofs` = [u_x, u_y]; its stiffness bound
    /// covers spin speeds `speeds` = (lowest, highest) in rad/s. Fails when the bearing has
    /// no forcing function.
    ///
    /// # Errors
    /// [`Error::Input`] naming `roller_bearing[index].forcing_function` when the bearing has
    /// none, with the command that fits one.
    pub fn new(
        bearing: &RollerBearing,
        index: usize,
        dofs: [usize; 2],
        speeds: (f64, f64),
    ) -> Result<Self> {
        let law = bearing
            .forcing_function
            .ok_or_else(|| missing_law(bearing, index))?;
        Ok(ForcingBearing {
            name: bearing.name.clone(),
            dofs,
            bound: stiffness_bound(&law, speeds),
            law,
            clearance: bearing.clearance.clone(),
        })
    }

    /// Radial force magnitude f and its slope f' at radial deflection `u_r` (m) and spin
    /// speed `speed` (rad/s); (0, 0) out of contact.
    pub fn radial(&self, u_r: f64, speed: f64) -> (f64, f64) {
        radial_force(&self.law, &self.clearance, u_r, speed)
    }
}

/// The error for a bearing without a law, with the command that makes one.
fn missing_law(bearing: &RollerBearing, index: usize) -> Error {
    InputError::field(
        format!("roller_bearing[{index}].forcing_function"),
        format!(
            "{} has no forcing function (thesis eq. 3.12) to model it with",
            bearing.name
        ),
    )
    .help(format!(
        "run `whirl fit-forcing <model file> --bearing {index}` and paste the line it writes \
         to forcing_function.toml into this bearing's [[roller_bearing]] block"
    ))
    .into()
}

/// The lowest speed (rad/s, >= 0) at which the law's coefficient a(W) or exponent b(W)
/// reaches zero, `None` when neither ever does. Above it the law gives no force: a fitted
/// law extrapolated too far.
pub fn valid_up_to(law: &ForcingFunction) -> Option<f64> {
    let root = |c0: f64, c1: f64| (c1 < 0.0).then(|| -c0 / c1);
    match (root(law.a0, law.a1), root(law.b0, law.b1)) {
        (Some(a), Some(b)) => Some(a.min(b)),
        (a, b) => a.or(b),
    }
    .map(|w| w.max(0.0))
}

/// f(s) = a s^b and f'(s) at radial deflection `u_r`; zero beyond [`valid_up_to`].
pub(crate) fn radial_force(
    law: &ForcingFunction,
    clearance: &Clearance,
    u_r: f64,
    speed: f64,
) -> (f64, f64) {
    let s = u_r - clearance.at_speed(speed);
    let (a, b) = law.at_speed(speed);
    if s <= 0.0 || a <= 0.0 || b <= 0.0 {
        return (0.0, 0.0);
    }
    let f = a * s.powf(b);
    (f, b * f / s)
}

/// f'(s) at u_r = 0, where only gamma <= 0 puts the bearing in contact: the one-sided limit
/// a b s^(b-1) at s = -gamma (a at gamma = 0 and b = 1, 0 for b > 1).
fn centre_slope(law: &ForcingFunction, clearance: &Clearance, speed: f64) -> f64 {
    let s = -clearance.at_speed(speed);
    let (a, b) = law.at_speed(speed);
    if s < 0.0 || a <= 0.0 || b <= 0.0 {
        return 0.0;
    }
    a * b * s.powf(b - 1.0)
}

/// The largest radial tangent stiffness over `speeds` at approach
/// [`HERTZ_BOUND_APPROACH`], the approach the Hertz bound uses, N/m. The tangent is
/// f'(s) along e and f(s)/u_r across it; f(s)/u_r <= f'(s) / b (for gamma >= 0, where
/// u_r >= s), so k(W) = f'(s) max(1, 1/b) bounds both. Speeds beyond [`valid_up_to`]
/// carry no force and are left out. log f'(s) = log a + log b + (b - 1) log s is concave
/// in W (a and b are linear), so its maximum over the interval is found by bisection on
/// the sign of its slope.
fn stiffness_bound(law: &ForcingFunction, speeds: (f64, f64)) -> f64 {
    let s = HERTZ_BOUND_APPROACH;
    let (mut lo, mut hi) = speeds;
    if let Some(limit) = valid_up_to(law) {
        if limit <= lo {
            return 0.0;
        }
        // Just inside the limit, where a and b are still positive.
        hi = hi.min(limit * (1.0 - 1e-9));
    }
    let tangent = |w: f64| {
        let (a, b) = law.at_speed(w);
        a * b * s.powf(b - 1.0) * (1.0 / b).max(1.0)
    };
    let slope = |w: f64| {
        let (a, b) = law.at_speed(w);
        law.a1 / a + law.b1 / b + law.b1 * s.ln()
    };
    let peak = if slope(lo) <= 0.0 {
        lo
    } else if slope(hi) >= 0.0 {
        hi
    } else {
        // 60 halvings shrink any speed interval below round-off.
        for _ in 0..60 {
            let mid = 0.5 * (lo + hi);
            if slope(mid) > 0.0 {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        0.5 * (lo + hi)
    };
    tangent(peak)
}

impl NonlinearForce for ForcingBearing {
    fn name(&self) -> String {
        self.name.clone()
    }

    fn dofs(&self) -> &[usize] {
        &self.dofs
    }

    fn force(&mut self, at: &Kinematics, q: &[f64], _: &[f64], out: &mut [f64]) {
        let u_r = q[0].hypot(q[1]);
        let (f, _) = self.radial(u_r, at.speed);
        if f == 0.0 {
            out[..2].fill(0.0);
            return;
        }
        out[0] = -f * q[0] / u_r;
        out[1] = -f * q[1] / u_r;
    }

    fn jacobian(
        &mut self,
        at: &Kinematics,
        q: &[f64],
        _: &[f64],
        dfdq: &mut [f64],
        dfdv: &mut [f64],
    ) {
        dfdv[..4].fill(0.0);
        let u_r = q[0].hypot(q[1]);
        if u_r == 0.0 {
            // The direction is undefined; see the module documentation.
            let k = centre_slope(&self.law, &self.clearance, at.speed);
            dfdq[..4].copy_from_slice(&[-k, 0.0, 0.0, -k]);
            return;
        }
        let (f, slope) = self.radial(u_r, at.speed);
        let e = [q[0] / u_r, q[1] / u_r];
        let across = f / u_r;
        for a in 0..2 {
            for b in 0..2 {
                let identity = if a == b { 1.0 } else { 0.0 };
                dfdq[2 * a + b] = -(slope * e[a] * e[b] + across * (identity - e[a] * e[b]));
            }
        }
    }

    fn stiffness_bound(&self) -> Vec<f64> {
        vec![self.bound, 0.0, 0.0, self.bound]
    }
}

/// The speeds the stiffness bound of a model's forcing-function bearings covers: from rest
/// to 1.2 times the top operating speed (the API 617 margin every speed sweep of whirl
/// covers by default), or rest only when the model states no operating range.
pub fn law_speeds(model: &Model) -> (f64, f64) {
    model
        .operating
        .map_or((0.0, 0.0), |(_, top)| (0.0, 1.2 * top))
}

/// Forcing-function bearings for every roller bearing of `model` (a
/// [`crate::force::ForceBuilder`]), their stiffness bounded over [`law_speeds`]. Fails,
/// naming the bearing and the command that fits one, when a bearing has no
/// `forcing_function`.
///
/// # Errors
/// [`Error::Unsupported`] when a bearing's (ux, uy) are not kept by `coordinate` (see
/// [`contact_coordinates_of`]); [`Error::Input`] from [`ForcingBearing::new`] when a bearing
/// has no `forcing_function`.
pub fn forcing_bearings(
    model: &Model,
    coordinate: &dyn Fn(usize) -> Option<usize>,
) -> Result<Vec<Box<dyn NonlinearForce>>> {
    let speeds = law_speeds(model);
    model
        .roller_bearings
        .iter()
        .enumerate()
        .map(|(i, b)| {
            let c = contact_coordinates_of(b, &[Direction::Ux, Direction::Uy], coordinate)?;
            let force = ForcingBearing::new(b, i, [c[0], c[1]], speeds)?;
            super::mounted(model, b.housing, Box::new(force), coordinate)
        })
        .collect()
}
