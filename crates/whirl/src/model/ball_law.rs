//! A ball bearing's contact law: the contact angle of each ball follows from its
//! deflection, and the rings' axial separation from the axial load (Harris, *Rolling
//! Bearing Analysis*, the chapter on internal load distribution; docs/theory.md
//! section 5, "Ball bearings").
//!
//! Ball j at angle theta_j sees the inner groove's curvature centre moved from the outer's
//! by s axially and r_j radially,
//!
//! ```text
//! r_j = A cos(alpha_0) + d_j,   d_j = u_x cos theta_j + u_y sin theta_j - gamma - P(j)
//! rho_j = sqrt(s^2 + r_j^2),    delta_j = rho_j - A,     Q_j = K_n delta_j^(3/2)
//! tan(alpha_j) = s / r_j,       sum_j Q_j sin(alpha_j) = F_a
//! ```
//!
//! d_j is the roller bearing's approach (`bearing::geometry::RollerGeometry`: clearance, waviness,
//! defects), so a deep-groove bearing without axial load (alpha_0 = 0, F_a = 0, s = 0) is
//! the roller law with exponent 3/2. The finite-element model is lateral: the axial load is
//! prescribed and s is solved for it at every evaluation; the rotor feels the radial
//! components -Q_j cos(alpha_j) (cos theta_j, sin theta_j). The contact damping acts on the
//! radial approach rate, as a roller's does.

use super::RollerBearing;

/// One ball's elastic contact at given radial and axial separations.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct BallContactState {
    /// Elastic deformation delta (positive = loaded), m.
    pub deformation: f64,
    /// Normal load Q, N.
    pub load: f64,
    /// dQ/d(delta), N/m.
    pub load_rate: f64,
    /// cos and sin of the contact angle.
    pub cos: f64,
    /// sin of the contact angle.
    pub sin: f64,
    /// Distance between the groove centres rho, m.
    pub rho: f64,
}

impl BallContactState {
    /// Radial part Q cos(alpha) and its derivatives with respect to r and s.
    pub fn radial(&self) -> (f64, f64, f64) {
        let (q, k, c, sn, rho) = (self.load, self.load_rate, self.cos, self.sin, self.rho);
        (q * c, k * c * c + q * sn * sn / rho, c * sn * (k - q / rho))
    }

    /// Axial part Q sin(alpha) and its derivatives with respect to r and s.
    pub fn axial(&self) -> (f64, f64, f64) {
        let (q, k, c, sn, rho) = (self.load, self.load_rate, self.cos, self.sin, self.rho);
        (
            q * sn,
            c * sn * (k - q / rho),
            k * sn * sn + q * c * c / rho,
        )
    }
}

/// The geometry a ball's contact needs, with the prescribed axial load.
#[derive(Debug, Clone, PartialEq)]
pub struct BallLaw {
    /// Groove centre distance at first touch, A = (f_i + f_o - 1) D, m.
    pub centre_distance: f64,
    /// A cos(alpha_0), m: the radial separation of the groove centres at zero approach.
    pub radial_reach: f64,
    /// Axial load F_a, N.
    pub axial_load: f64,
}

/// Iterations of the axial solve; bisection halves the bracket at least every other step, so
/// 200 reaches round-off from any bracket.
const AXIAL_ITERATIONS: usize = 200;

impl BallLaw {
    /// The law of a ball bearing, `None` for a roller bearing.
    pub fn of(bearing: &RollerBearing) -> Option<BallLaw> {
        let ball = bearing.ball.as_ref()?;
        let a = ball.centre_distance(bearing.roller_diameter);
        Some(BallLaw {
            centre_distance: a,
            radial_reach: a * ball.contact_angle.cos(),
            axial_load: ball.axial_load,
        })
    }

    /// The contact of a ball with radial approach `d` (m) at axial separation `s` (m), with
    /// `elastic` giving (Q, dQ/d delta) of a deformation.
    pub fn contact(&self, d: f64, s: f64, elastic: &dyn Fn(f64) -> (f64, f64)) -> BallContactState {
        let r = self.radial_reach + d;
        let rho = r.hypot(s);
        let deformation = rho - self.centre_distance;
        // A groove centre on the far side of the bearing's axis (r <= 0) is a displacement of
        // the order of A (a millimetre), never a contact.
        if deformation <= 0.0 || r <= 0.0 {
            return BallContactState {
                deformation,
                ..Default::default()
            };
        }
        let (load, load_rate) = elastic(deformation);
        BallContactState {
            deformation,
            load,
            load_rate,
            cos: r / rho,
            sin: s / rho,
            rho,
        }
    }

    /// The axial separation s >= 0 of the groove centres at which the balls with radial
    /// approaches `approaches` carry the axial load: sum Q_j sin(alpha_j) = F_a, by Newton's
    /// method kept inside a bracket (the sum grows monotonically with s from 0 at s = 0),
    /// started from `guess`. Without axial load the rings stay centred: s = 0.
    pub fn axial_separation(
        &self,
        approaches: impl Iterator<Item = f64> + Clone,
        guess: f64,
        elastic: &dyn Fn(f64) -> (f64, f64),
    ) -> f64 {
        if self.axial_load <= 0.0 {
            return 0.0;
        }
        let balance = |s: f64| {
            approaches
                .clone()
                .fold((-self.axial_load, 0.0), |(g, dg), d| {
                    let (p, _, dp) = self.contact(d, s, elastic).axial();
                    (g + p, dg + dp)
                })
        };
        // The bracket's top: where the balls' axial loads exceed F_a, found by doubling.
        let mut hi = guess.max(1e-3 * self.centre_distance);
        while balance(hi).0 <= 0.0 {
            hi *= 2.0;
            if hi > 1e3 * self.centre_distance {
                // Unreachable for any finite load; keep the solve total.
                return hi;
            }
        }
        let (mut lo, mut s) = (0.0, guess.clamp(0.0, hi));
        for _ in 0..AXIAL_ITERATIONS {
            let (g, dg) = balance(s);
            if g.abs() <= 1e-13 * self.axial_load {
                break;
            }
            if g > 0.0 {
                hi = s;
            } else {
                lo = s;
            }
            let newton = s - g / dg;
            s = if dg > 0.0 && newton > lo && newton < hi {
                newton
            } else {
                0.5 * (lo + hi)
            };
            if hi - lo <= 1e-15 * self.centre_distance {
                break;
            }
        }
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_parts_derivatives_are_those_of_the_contact() {
        // 209-like: A = 0.04 x 12.7 mm, 15 degrees, K = 7e9 N/m^1.5.
        let a = 0.04 * 12.7e-3;
        let law = BallLaw {
            centre_distance: a,
            radial_reach: a * 15f64.to_radians().cos(),
            axial_load: 1e3,
        };
        let k = 7e9;
        let elastic = |x: f64| (k * x.powf(1.5), 1.5 * k * x.sqrt());
        let (d, s) = (8e-6, a * 0.3);
        let h = 1e-11;
        let at = |d: f64, s: f64| law.contact(d, s, &elastic);
        let (r0, rr, rs) = at(d, s).radial();
        let (p0, pr, ps) = at(d, s).axial();
        let diff = |f: &dyn Fn(f64, f64) -> f64, dd: f64, ds: f64| {
            (f(d + dd, s + ds) - f(d - dd, s - ds)) / (2.0 * h)
        };
        let radial = |d: f64, s: f64| at(d, s).radial().0;
        let axial = |d: f64, s: f64| at(d, s).axial().0;
        // Central differences with h = 1e-11 m on loads of ~100 N: truncation (h^2 Q''') and
        // round-off (1e-16 Q / h) both near 1e-6 of the derivative.
        for (exact, numeric) in [
            (rr, diff(&radial, h, 0.0)),
            (rs, diff(&radial, 0.0, h)),
            (pr, diff(&axial, h, 0.0)),
            (ps, diff(&axial, 0.0, h)),
        ] {
            assert!(
                (exact - numeric).abs() <= 1e-5 * exact.abs().max(1e3),
                "{exact} {numeric}"
            );
        }
        assert!(r0 > 0.0 && p0 > 0.0);
    }
}
