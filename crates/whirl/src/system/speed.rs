//! The spin speed over time and the unbalance force's time dependence.

use crate::force::Kinematics;

/// Spin speed over time.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum SpeedProfile {
    /// Constant speed, rad/s.
    Constant(f64),
    /// Constant `from` (rad/s) until `start` (s), then a linear ramp to `to` (rad/s) over
    /// `duration` (s), then constant `to`.
    Ramp {
        /// Starting speed, rad/s.
        from: f64,
        /// Final speed, rad/s.
        to: f64,
        /// When the ramp begins, s (0 to ramp from the first step).
        start: f64,
        /// Time to reach `to` from the ramp's beginning, s.
        duration: f64,
    },
}

impl SpeedProfile {
    /// Speed, angle and acceleration at time t.
    pub fn at(&self, t: f64) -> (Kinematics, f64) {
        match *self {
            SpeedProfile::Constant(w) => (
                Kinematics {
                    time: t,
                    speed: w,
                    angle: w * t,
                },
                0.0,
            ),
            SpeedProfile::Ramp {
                from,
                to,
                start,
                duration,
            } => {
                let rate = (to - from) / duration;
                // Time into the ramp, within it.
                let ramping = (t - start).clamp(0.0, duration);
                let after = (t - start - duration).max(0.0);
                let before = t.min(start);
                let k = Kinematics {
                    time: t,
                    speed: from + rate * ramping,
                    angle: from * (before + ramping) + 0.5 * rate * ramping * ramping + to * after,
                };
                let accel = if t >= start && t <= start + duration {
                    rate
                } else {
                    0.0
                };
                (k, accel)
            }
        }
    }

    /// Largest speed, rad/s.
    pub fn max_speed(&self) -> f64 {
        match *self {
            SpeedProfile::Constant(w) => w.abs(),
            SpeedProfile::Ramp { from, to, .. } => from.abs().max(to.abs()),
        }
    }

    /// True for a constant speed.
    pub fn is_constant(&self) -> bool {
        matches!(self, SpeedProfile::Constant(_))
    }

    /// The spin kinematics at time t and the coefficients [c_re, c_im] that give the
    /// unbalance force as c_re u_re + c_im u_im (u = [`super::System::unbalance_re`], [`super::System::unbalance_im`]):
    ///
    /// ```text
    /// Re(f (w^2 - i w') e^{i phi}) = (w^2 cos phi + w' sin phi) u_re + (-w^2 sin phi + w' cos phi) u_im
    /// ```
    ///
    /// The one definition of the time dependence of the linear force: integrators that keep
    /// products with u_re and u_im precomputed scale them by these coefficients.
    pub fn unbalance_coefficients(&self, t: f64) -> (Kinematics, [f64; 2]) {
        self.unbalance_coefficients_by(t, f64::sin_cos)
    }

    /// [`Self::unbalance_coefficients`] with (sin phi, cos phi) from `sin_cos`: a time step
    /// loop follows the spin angle by rotation ([`crate::linalg::Turning`]).
    pub(crate) fn unbalance_coefficients_by(
        &self,
        t: f64,
        sin_cos: impl FnOnce(f64) -> (f64, f64),
    ) -> (Kinematics, [f64; 2]) {
        let (k, accel) = self.at(t);
        let (s, c) = sin_cos(k.angle);
        let w2 = k.speed * k.speed;
        (k, [w2 * c + accel * s, accel * c - w2 * s])
    }
}
