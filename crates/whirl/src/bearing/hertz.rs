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
        })
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
        let elastic = self.stiffness * delta.powf(self.exponent);
        let force = elastic + self.damping * rate;
        if force <= 0.0 {
            // A roller never pulls: damping cannot make the contact tensile.
            return (0.0, 0.0, 0.0);
        }
        let k = self.exponent * elastic / delta;
        (force, k, self.damping)
    }

    /// Adds the force of one slice at cage speed `cage_speed` to `out`: what
    /// [`NonlinearForce::force`] sums over the slices of [`RollerGeometry::for_each_slice`],
    /// for callers that keep the slices of fixed roller positions.
    pub fn add_slice_force(
        &self,
        slice: &Slice,
        cage_speed: f64,
        q: &[f64],
        v: &[f64],
        out: &mut [f64],
    ) {
        let (delta, rate) = self.approach(slice, cage_speed, q, v);
        let (force, _, _) = self.slice_force(delta, rate);
        if force > 0.0 {
            let g = slice.direction();
            for (o, ga) in out.iter_mut().zip(g) {
                *o -= force * ga;
            }
        }
    }

    /// Adds the tangent of one slice to `dfdq` and `dfdv` (row-major, m x m for the m
    /// coordinates), as [`Self::add_slice_force`] adds its force.
    pub fn add_slice_jacobian(
        &self,
        slice: &Slice,
        cage_speed: f64,
        q: &[f64],
        v: &[f64],
        dfdq: &mut [f64],
        dfdv: &mut [f64],
    ) {
        let m = q.len();
        let (delta, rate) = self.approach(slice, cage_speed, q, v);
        let (force, k, c) = self.slice_force(delta, rate);
        if force <= 0.0 {
            return;
        }
        let g = slice.direction();
        let gt = slice.direction_turn();
        // F = -Q g with dQ/du = k g + c w_c g_theta and dQ/dv = c g.
        for a in 0..m {
            for b in 0..m {
                dfdq[a * m + b] -= g[a] * (k * g[b] + c * cage_speed * gt[b]);
                dfdv[a * m + b] -= g[a] * c * g[b];
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
            self.add_slice_force(slice, cage_speed, q, v, out);
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
            self.add_slice_jacobian(slice, cage_speed, q, v, dfdq, dfdv);
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
