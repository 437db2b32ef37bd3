//! The sine and cosine of an angle that moves a little from one call to the next (a spin or
//! cage angle, one time step apart), by the rotation
//!
//! ```text
//! (sin, cos)(a + d) = (sin a cos d + cos a sin d, cos a cos d - sin a sin d)
//! ```
//!
//! through the change d, whose sine and cosine are short Taylor polynomials: a few
//! multiplications instead of a library sine and cosine, which cost 15-20 ns each and were
//! a tenth of a cascade's time step. Every [`RESEED`] calls, and whenever the angle jumps
//! by more than [`MAX_TURN`], the pair is evaluated afresh, so rounding cannot accumulate
//! beyond a few hundred ulps. The values depend only on the sequence of angles asked for,
//! so a run gives the same results whichever thread runs it and whatever ran before.
//!
//! At constant speed every step turns by the same angle, up to the rounding of the angles
//! themselves (a few ulps of the angle), so the rotation of the last change is kept and
//! used again while the change stays within [`SAME_TURN_ULPS`] ulps of the angle of it:
//! the polynomials were 4 % of a cascade. Each reuse shifts the pair by at most that
//! much, so between reseeds it stays within 64 x 8 ulps of the angle (3e-11 rad at
//! 450 rad; the angle of a step, 0.01-0.2 rad, is known to 1e-16 relative only near 0).

/// Calls between exact evaluations. Each rotation rounds by a few ulps (1e-16), so the
/// pair drifts by at most about 1e-14 between them: far below the rounding of the angle
/// itself after a few seconds at speed (ulp of 1e4 rad is 2e-12).
const RESEED: u32 = 64;

/// A change within this many ulps of the angle of the last one reuses its rotation.
const SAME_TURN_ULPS: f64 = 8.0;

/// Largest change followed by a rotation, rad. The polynomials below are exact to 3e-18
/// up to it. A cascade step of the reference rotor at 750 Hz turns the spin by 0.15 rad:
/// at 0.1 every step above 495 Hz fell back on the library's sine and cosine (2 % of the
/// main job).
const MAX_TURN: f64 = 0.25;

/// sin and cos of an angle followed by rotations; see the module documentation.
#[derive(Debug, Clone)]
pub(crate) struct Turning {
    angle: f64,
    sin_cos: (f64, f64),
    /// Rotations left before the next exact evaluation; 0 before the first call.
    left: u32,
    /// The last change computed and its (sin, cos).
    turn: f64,
    turn_sin_cos: (f64, f64),
}

impl Default for Turning {
    fn default() -> Self {
        Turning {
            angle: 0.0,
            sin_cos: (0.0, 1.0),
            left: 0,
            turn: 0.0,
            turn_sin_cos: (0.0, 1.0),
        }
    }
}

impl Turning {
    /// (sin, cos) of `angle`, to within about 1e-14.
    #[inline]
    pub(crate) fn sin_cos(&mut self, angle: f64) -> (f64, f64) {
        let change = angle - self.angle;
        if self.left == 0 || change.abs() > MAX_TURN || !change.is_finite() {
            self.sin_cos = angle.sin_cos();
            self.left = RESEED;
        } else {
            if (change - self.turn).abs() > SAME_TURN_ULPS * f64::EPSILON * angle.abs() {
                self.turn = change;
                self.turn_sin_cos = small_sin_cos(change);
            }
            self.sin_cos = rotate(self.sin_cos, self.turn_sin_cos);
            self.left -= 1;
        }
        self.angle = angle;
        self.sin_cos
    }
}

/// (sin, cos) of a + b from those of a and b.
#[inline(always)]
pub(crate) fn rotate((sa, ca): (f64, f64), (sb, cb): (f64, f64)) -> (f64, f64) {
    (sa * cb + ca * sb, ca * cb - sa * sb)
}

/// (sin x, cos x) for |x| <= [`MAX_TURN`] by their Taylor series to x^11 and x^12: the
/// first terms left out, x^13/13! and x^14/14!, are below 3e-18 and 5e-20 there. Horner's
/// form with the coefficients 1/k! as constants: multiplications only (a division by a
/// constant stays a division, some ten times slower).
#[inline(always)]
fn small_sin_cos(x: f64) -> (f64, f64) {
    const SIN: [f64; 5] = [
        -1.0 / 6.0,
        1.0 / 120.0,
        -1.0 / 5040.0,
        1.0 / 362_880.0,
        -1.0 / 39_916_800.0,
    ];
    const COS: [f64; 6] = [
        -1.0 / 2.0,
        1.0 / 24.0,
        -1.0 / 720.0,
        1.0 / 40_320.0,
        -1.0 / 3_628_800.0,
        1.0 / 479_001_600.0,
    ];
    let x2 = x * x;
    let sin = x + x * x2 * (SIN[0] + x2 * (SIN[1] + x2 * (SIN[2] + x2 * (SIN[3] + x2 * SIN[4]))));
    let cos = 1.0
        + x2 * (COS[0]
            + x2 * (COS[1] + x2 * (COS[2] + x2 * (COS[3] + x2 * (COS[4] + x2 * COS[5])))));
    (sin, cos)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_polynomials_are_the_sine_and_cosine_to_rounding() {
        // A few roundings of numbers below 1 in the nested products: 2 ulps of 1 (4.4e-16).
        for i in -1000..=1000 {
            let x = MAX_TURN * i as f64 / 1000.0;
            let (s, c) = small_sin_cos(x);
            assert!((s - x.sin()).abs() <= 4.4e-16, "{x}: {s} {}", x.sin());
            assert!((c - x.cos()).abs() <= 4.4e-16, "{x}: {c} {}", x.cos());
        }
    }

    #[test]
    fn a_turned_angle_stays_within_round_off_of_the_exact_one() {
        // A cage at 0.4 of 750 Hz with a 1.2e-5 s step, for 20,000 steps (0.24 s), then
        // jumps back and forth. Between reseeds at most 64 rotations, each by a change
        // reused within 8 ulps of the angle (at most 450 rad: 8 x 1e-13) and rounding by a
        // few ulps of 1: 64 x (8e-13 + 3.3e-16) = 5.1e-11.
        let mut turning = Turning::default();
        let step = 0.4 * 2.0 * std::f64::consts::PI * 750.0 * 1.2e-5;
        let mut worst: f64 = 0.0;
        for k in 0..20_000 {
            let angle = step * k as f64;
            let (s, c) = turning.sin_cos(angle);
            let (se, ce) = angle.sin_cos();
            worst = worst.max((s - se).abs()).max((c - ce).abs());
        }
        for angle in [3.0, -2.0, 1e3, 1e3 + 1e-3] {
            let (s, c) = turning.sin_cos(angle);
            let (se, ce) = angle.sin_cos();
            worst = worst.max((s - se).abs()).max((c - ce).abs());
        }
        assert!(worst <= 5.1e-11, "{worst:e}");
    }

    #[test]
    fn the_same_angles_give_the_same_values() {
        // Two trackers fed the same angles agree bit for bit, and the first call is exact.
        let (mut a, mut b) = (Turning::default(), Turning::default());
        assert_eq!(a.sin_cos(0.3), 0.3f64.sin_cos());
        b.sin_cos(0.3);
        for k in 0..1000 {
            let angle = 0.01 * k as f64;
            assert_eq!(a.sin_cos(angle), b.sin_cos(angle));
        }
    }
}
