//! Hertz line contact per roller slice (thesis eq. 3.5, docs/theory.md section 5):
//!
//! ```text
//! Q = K_s delta^n + C_s d(delta)/dt   when delta > 0 and the sum is compressive, else 0
//! F = -sum Q d(delta)/du               (the rotor is pushed back towards the centre)
//! ```
//!
//! d(delta)/dt is the total derivative: the shaft's velocity, the orbiting of the roller
//! (w_c times d(delta)/d(theta)) and the waviness passing under it. The exact Jacobian
//! follows from the same expression, so implicit integrators, the static solver and the
//! harmonic balance use the law unchanged.

use super::geometry::{RollerGeometry, RollerState, Slice};
use crate::error::{Error, Result};
use crate::force::{Kinematics, NonlinearForce};
use crate::model::RollerBearing;

/// Approach used to bound the contact's tangent stiffness for the explicit stability
/// limit, m. At 100 um a roller of the reference bearing carries about 16 kN, far beyond
/// any load it meets, and the bound grows only as delta^(1/9).
pub const HERTZ_BOUND_APPROACH: f64 = 1e-4;

/// A roller bearing with Hertz contacts, acting on the bearing node's coordinates.
#[derive(Debug, Clone)]
pub struct HertzBearing {
    name: String,
    dofs: Vec<usize>,
    geometry: RollerGeometry,
    /// Contact stiffness of one slice, N/m^n.
    stiffness: f64,
    /// Contact damping of one slice, N s/m.
    damping: f64,
    exponent: f64,
    /// Approach below which the law is blended ([`HertzBearing::smoothed`]), m; 0 for the
    /// exact law.
    smoothing: f64,
}

impl HertzBearing {
    /// The bearing acting on integrator coordinates `dofs`: [ux, uy], or [ux, uy, tx, ty]
    /// when the bearing models roller tilt.
    ///
    /// # Errors
    /// [`Error::InvalidOption`] when `dofs` does not hold as many coordinates as the bearing
    /// needs (2, or 4 with roller tilt).
    pub fn new(bearing: &RollerBearing, dofs: Vec<usize>) -> Result<Self> {
        let geometry = RollerGeometry::new(bearing);
        if dofs.len() != geometry.coordinates() {
            return Err(Error::InvalidOption(format!(
                "{} needs {} coordinates, got {}",
                bearing.name,
                geometry.coordinates(),
                dofs.len()
            )));
        }
        let slices = geometry.slice_z.len() as f64;
        Ok(HertzBearing {
            name: bearing.name.clone(),
            dofs,
            geometry,
            stiffness: bearing.contact_stiffness / slices,
            damping: bearing.contact_damping / slices,
            exponent: bearing.contact_exponent,
            smoothing: 0.0,
        })
    }

    /// The law with bounded curvature at contact entry, for harmonic balance: below the
    /// approach `scale` (m) the elastic force K delta^n is replaced by the quintic that
    /// starts at zero with zero slope and curvature and meets K delta^n with its slope and
    /// curvature at `scale` (`blend`), and the damping is faded in by the C2 step
    /// 10 t^3 - 15 t^4 + 6 t^5 of t = delta / scale. At and above `scale` the law is the
    /// exact one. Hertz's curvature n (n - 1) K delta^(n - 2) grows without bound as the
    /// contact opens (delta^(-8/9) for a line contact) and the damping force jumps by
    /// C d(delta)/dt when it closes, so a harmonic balance residual sampled over a period
    /// has a kink wherever a sample enters contact, at any step of a continuation. Per slice
    /// the force differs from Hertz's by at most K scale^n + C |d(delta)/dt|, and only while
    /// 0 < delta < scale (docs/theory.md, section 7).
    pub fn smoothed(mut self, scale: f64) -> HertzBearing {
        self.smoothing = scale.max(0.0);
        self
    }

    /// The bearing's kinematics.
    pub fn geometry(&self) -> &RollerGeometry {
        &self.geometry
    }

    /// Approach and approach rate of a slice for displacements `q`, velocities `v`.
    fn approach(&self, slice: &Slice, cage_speed: f64, q: &[f64], v: &[f64]) -> (f64, f64) {
        let g = slice.direction();
        let gt = slice.direction_turn();
        let mut delta = slice.offset;
        let mut rate = slice.offset_rate;
        for a in 0..q.len() {
            delta += g[a] * q[a];
            rate += g[a] * v[a] + cage_speed * gt[a] * q[a];
        }
        (delta, rate)
    }

    /// Slice force and its derivatives with respect to approach and approach rate.
    fn slice_force(&self, delta: f64, rate: f64) -> (f64, f64, f64) {
        if delta <= 0.0 {
            return (0.0, 0.0, 0.0);
        }
        if delta < self.smoothing {
            return self.blended_force(delta, rate);
        }
        let elastic = self.stiffness * delta.powf(self.exponent);
        let force = elastic + self.damping * rate;
        if force <= 0.0 {
            // A roller never pulls: damping cannot make the contact tensile.
            return (0.0, 0.0, 0.0);
        }
        let k = self.exponent * elastic / delta;
        (force, k, self.damping)
    }

    /// [`Self::slice_force`] below the smoothing scale (0 < delta < scale).
    fn blended_force(&self, delta: f64, rate: f64) -> (f64, f64, f64) {
        let scale = self.smoothing;
        let t = delta / scale;
        let top = self.stiffness * scale.powf(self.exponent);
        let (p, dp) = blend(self.exponent, t);
        let (ramp, dramp) = (
            t * t * t * (10.0 + t * (-15.0 + 6.0 * t)),
            30.0 * t * t * (1.0 - t) * (1.0 - t),
        );
        let force = top * p + self.damping * ramp * rate;
        if force <= 0.0 {
            return (0.0, 0.0, 0.0);
        }
        (
            force,
            (top * dp + self.damping * dramp * rate) / scale,
            self.damping * ramp,
        )
    }

    /// Adds what one slice at cage speed `cage_speed` gives: its force to `force`, and its
    /// tangents to `tangents` (dF/dq and dF/dv, row-major, m x m for the m coordinates),
    /// each where asked for. What [`NonlinearForce::force`] and
    /// [`NonlinearForce::jacobian`] sum over the slices of [`RollerGeometry::for_each_slice`],
    /// for callers that keep the slices of fixed roller positions; the approach and the law
    /// are evaluated once for both.
    pub fn add_slice(
        &self,
        slice: &Slice,
        cage_speed: f64,
        (q, v): (&[f64], &[f64]),
        force: Option<&mut [f64]>,
        tangents: Option<(&mut [f64], &mut [f64])>,
    ) {
        let (delta, rate) = self.approach(slice, cage_speed, q, v);
        let (value, k, c) = self.slice_force(delta, rate);
        if value <= 0.0 {
            return;
        }
        let g = slice.direction();
        if let Some(out) = force {
            for (o, ga) in out.iter_mut().zip(g) {
                *o -= value * ga;
            }
        }
        if let Some((dfdq, dfdv)) = tangents {
            let m = q.len();
            let gt = slice.direction_turn();
            // F = -Q g with dQ/du = k g + c w_c g_theta and dQ/dv = c g.
            for a in 0..m {
                for b in 0..m {
                    dfdq[a * m + b] -= g[a] * (k * g[b] + c * cage_speed * gt[b]);
                    dfdv[a * m + b] -= g[a] * c * g[b];
                }
            }
        }
    }

    /// Angle, largest approach and force of every roller.
    pub fn rollers(&self, at: &Kinematics, q: &[f64], v: &[f64]) -> Vec<RollerState> {
        let cage_speed = self.geometry.cage_speed(at.speed);
        let mut out = vec![
            RollerState {
                angle: 0.0,
                approach: f64::NEG_INFINITY,
                force: 0.0,
            };
            self.geometry.rollers
        ];
        self.geometry.for_each_slice(at, |slice| {
            let (delta, rate) = self.approach(slice, cage_speed, q, v);
            let r = &mut out[slice.roller];
            r.angle = slice.angle;
            r.approach = r.approach.max(delta);
            r.force += self.slice_force(delta, rate).0;
        });
        out
    }
}

/// The quintic p(t) = c3 t^3 + c4 t^4 + c5 t^5 and its derivative at t: p(0) = p'(0) =
/// p''(0) = 0, and p, p', p'' equal to those of t^n at t = 1, so that K scale^n p(delta /
/// scale) joins K delta^n with two continuous derivatives. Solving the three conditions at
/// t = 1 gives c5 = (n - 3)(n - 4)/2, c4 = (n - 3)(5 - n), c3 = 1 - c4 - c5. For the
/// exponents a model accepts (1 to 2), p' = t^2 (3 c3 + 4 c4 t + 5 c5 t^2) has no real root
/// (16 c4^2 < 60 c3 c5): the blend rises monotonically from 0 to 1.
fn blend(n: f64, t: f64) -> (f64, f64) {
    let c5 = 0.5 * (n - 3.0) * (n - 4.0);
    let c4 = (n - 3.0) * (5.0 - n);
    let c3 = 1.0 - c4 - c5;
    let t2 = t * t;
    (
        t2 * t * (c3 + t * (c4 + t * c5)),
        t2 * (3.0 * c3 + t * (4.0 * c4 + t * 5.0 * c5)),
    )
}

impl NonlinearForce for HertzBearing {
    fn name(&self) -> String {
        self.name.clone()
    }

    fn dofs(&self) -> &[usize] {
        &self.dofs
    }

    fn force(&mut self, at: &Kinematics, q: &[f64], v: &[f64], out: &mut [f64]) {
        out.iter_mut().for_each(|f| *f = 0.0);
        let cage_speed = self.geometry.cage_speed(at.speed);
        self.geometry.for_each_slice(at, |slice| {
            self.add_slice(slice, cage_speed, (q, v), Some(&mut *out), None);
        });
    }

    fn jacobian(
        &mut self,
        at: &Kinematics,
        q: &[f64],
        v: &[f64],
        dfdq: &mut [f64],
        dfdv: &mut [f64],
    ) {
        dfdq.iter_mut().for_each(|x| *x = 0.0);
        dfdv.iter_mut().for_each(|x| *x = 0.0);
        let cage_speed = self.geometry.cage_speed(at.speed);
        self.geometry.for_each_slice(at, |slice| {
            self.add_slice(
                slice,
                cage_speed,
                (q, v),
                None,
                Some((&mut *dfdq, &mut *dfdv)),
            );
        });
    }

    fn stiffness_bound(&self) -> Vec<f64> {
        let m = self.dofs.len();
        let k = self.exponent * self.stiffness * HERTZ_BOUND_APPROACH.powf(self.exponent - 1.0);
        let mut bound = vec![0.0; m * m];
        let rest = Kinematics {
            time: 0.0,
            speed: 0.0,
            angle: 0.0,
        };
        self.geometry.for_each_slice(&rest, |slice| {
            let g = slice.direction();
            for a in 0..m {
                for b in 0..m {
                    bound[a * m + b] += k * g[a] * g[b];
                }
            }
        });
        bound
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// One slice of the reference bearing's law (line contact, K and C per slice), exact
    /// and smoothed below `scale`.
    fn laws(scale: f64) -> (HertzBearing, HertzBearing) {
        let model =
            crate::model::Model::from_toml_str(crate::examples::REFERENCE_ROTOR, None).unwrap();
        let exact = HertzBearing::new(&model.roller_bearings[0], vec![0, 1]).unwrap();
        (exact.clone(), exact.smoothed(scale))
    }

    #[test]
    fn the_blend_joins_hertz_with_value_slope_and_curvature() {
        let scale = 1e-8;
        let (exact, smooth) = laws(scale);
        // Force and tangent at the join, and the curvature by central differences of the
        // tangent 2e-6 of the scale either side of it: for n = 10/9 the quintic's third
        // derivative at the join is about 170 times its curvature (per unit of
        // delta / scale), so the curvature moves by 3.4e-4 over that offset; the
        // differences' round-off is near 1e-8.
        let h = 1e-6 * scale;
        let curvature = |law: &HertzBearing, at: f64| {
            (law.slice_force(at + h, 0.0).1 - law.slice_force(at - h, 0.0).1) / (2.0 * h)
        };
        let (below, above) = (scale * (1.0 - 2e-6), scale * (1.0 + 2e-6));
        let (fb, kb, _) = smooth.slice_force(scale, 0.0);
        let (fa, ka, _) = exact.slice_force(scale, 0.0);
        assert!((fb - fa).abs() <= 1e-12 * fa, "{fb} vs {fa}");
        assert!((kb - ka).abs() <= 1e-12 * ka, "{kb} vs {ka}");
        let (ci, co) = (curvature(&smooth, below), curvature(&exact, above));
        assert!((ci - co).abs() <= 2e-3 * co.abs(), "{ci} vs {co}");
        // Zero force, slope and curvature where the contact opens: at t = 1e-6 of the
        // scale the cubic leading term gives p = 5.6e-18 and p' / n = 1.5e-11.
        let tiny = 1e-6 * scale;
        let (f0, k0, _) = smooth.slice_force(tiny, 0.0);
        assert!(f0 <= 1e-16 * fa && k0 <= 1e-10 * ka, "{f0} {k0}");
    }

    #[test]
    fn the_smoothed_law_departs_from_hertz_only_below_the_scale_and_within_the_bound() {
        let scale = 1e-8;
        let (exact, smooth) = laws(scale);
        let top = exact.stiffness * scale.powf(exact.exponent);
        let mut largest: f64 = 0.0;
        for i in 1..400 {
            let delta = 2.0 * scale * i as f64 / 400.0;
            for rate in [-1e-2, 0.0, 1e-2] {
                let (a, b) = (
                    smooth.slice_force(delta, rate).0,
                    exact.slice_force(delta, rate).0,
                );
                if delta >= scale {
                    assert_eq!(a, b, "exact above the scale");
                } else {
                    // Both elastic parts lie in [0, K scale^n] and both are monotone; the
                    // damping part is faded, never enlarged.
                    let bound = top + exact.damping * rate.abs();
                    assert!((a - b).abs() <= bound, "{delta}: {a} vs {b}");
                    largest = largest.max((a - b).abs() / bound);
                }
                assert!(a >= 0.0, "a roller never pulls");
            }
        }
        assert!(largest > 0.1, "the blend must differ somewhere: {largest}");
    }

    #[test]
    fn the_smoothed_tangent_is_the_derivative_of_the_force() {
        let scale = 1e-8;
        let (_, smooth) = laws(scale);
        for (delta, rate) in [
            (0.2e-8, 1e-3),
            (0.5e-8, -1e-4),
            (0.9e-8, 0.0),
            (0.7e-8, 2e-2),
        ] {
            let (f, k, c) = smooth.slice_force(delta, rate);
            let (hd, hr) = (1e-6 * scale, 1e-6);
            let kd = (smooth.slice_force(delta + hd, rate).0
                - smooth.slice_force(delta - hd, rate).0)
                / (2.0 * hd);
            let cd = (smooth.slice_force(delta, rate + hr).0
                - smooth.slice_force(delta, rate - hr).0)
                / (2.0 * hr);
            assert!(f > 0.0);
            // Central differences of a polynomial of degree 5: error O(h^2), far below 1e-6.
            assert!((kd - k).abs() <= 1e-6 * k.abs(), "{delta}: {kd} vs {k}");
            assert!(
                (cd - c).abs() <= 1e-6 * c.abs().max(1e-12),
                "{delta}: {cd} vs {c}"
            );
        }
    }

    #[test]
    fn the_blend_rises_monotonically_for_every_accepted_exponent() {
        for n in [1.0, 10.0 / 9.0, 1.5, 2.0] {
            let (mut last, mut t) = (0.0, 0.0f64);
            while t < 1.0 {
                t += 1e-3;
                let (p, dp) = blend(n, t.min(1.0));
                assert!(p >= last && dp >= 0.0, "n = {n}, t = {t}: {p} {dp}");
                last = p;
            }
            assert!((last - 1.0).abs() < 1e-12, "n = {n}: {last}");
        }
    }
}
