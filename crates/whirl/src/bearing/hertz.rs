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
use super::power::Power;
use crate::error::{Error, Result};
use crate::force::{Kinematics, NonlinearForce};
use crate::linalg::{rotate, Turning};
use crate::model::ball_law::{BallContactState, BallLaw};
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
    /// The contact exponent n and its power delta^n.
    power: Power,
    /// Approach below which the law is blended ([`HertzBearing::smoothed`]), m; 0 for the
    /// exact law.
    smoothing: f64,
    /// The rollers' directions as [`NonlinearForce::force`] last left them.
    rollers: Rollers,
    /// A ball bearing's contact law (contact angles, axial load); `None` for rollers.
    ball: Option<BallLaw>,
    /// The rings' axial separation of the last evaluation, m: the next solve's start.
    axial: f64,
    /// Each ball's radial approach and its rate at the last evaluation.
    approaches: Vec<(f64, f64)>,
    /// Each ball's contact, the Jacobian's work buffer.
    contacts: Vec<BallContactState>,
}

/// What [`NonlinearForce::force`] keeps between calls: the cage angle followed by rotation
/// and each roller's direction, so that a time step evaluates no sine or cosine.
#[derive(Debug, Clone)]
struct Rollers {
    /// (sin, cos) of each roller's angle at spin angle 0, 2 pi j / N_b + cage angle.
    pitch: Vec<(f64, f64)>,
    /// The cage's turn w_c / w times the spin angle.
    cage: Turning,
    /// sin and cos of each roller's angle at the last call.
    sin: Vec<f64>,
    cos: Vec<f64>,
    /// Each roller's approach and approach rate at the last call, less those of its
    /// slices' offsets and tilt (see [`HertzBearing::roller_motion`]).
    radial: Vec<(f64, f64)>,
    /// The same for the bearing node's rotation: the approach per unit axial offset.
    tilt: Vec<(f64, f64)>,
    /// Largest |z| of a slice, m, and largest skew approach, m.
    reach: (f64, f64),
}

impl Rollers {
    fn new(geometry: &RollerGeometry) -> Rollers {
        let n = geometry.rollers;
        let z_max = geometry.slice_z.iter().fold(0.0f64, |m, z| m.max(z.abs()));
        let skew_max = geometry
            .slice_skew
            .iter()
            .fold(f64::NEG_INFINITY, |m, &s| m.max(s));
        Rollers {
            pitch: (0..n).map(|j| geometry.pitch(j).sin_cos()).collect(),
            cage: Turning::default(),
            sin: vec![0.0; n],
            cos: vec![0.0; n],
            radial: vec![(0.0, 0.0); n],
            tilt: vec![(0.0, 0.0); n],
            reach: (if geometry.tilt { z_max } else { 0.0 }, skew_max),
        }
    }

    /// Turns every roller to its angle at spin angle `phi`.
    fn turn(&mut self, geometry: &RollerGeometry, phi: f64) {
        let cage = self.cage.sin_cos(geometry.cage_ratio * phi);
        for (j, &pitch) in self.pitch.iter().enumerate() {
            (self.sin[j], self.cos[j]) = rotate(pitch, cage);
        }
    }
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
            stiffness: bearing.contact_stiffness / slices,
            damping: bearing.contact_damping / slices,
            power: Power::new(bearing.contact_exponent),
            smoothing: 0.0,
            rollers: Rollers::new(&geometry),
            ball: BallLaw::of(bearing),
            axial: 0.0,
            approaches: vec![(0.0, 0.0); geometry.rollers],
            contacts: Vec::with_capacity(geometry.rollers),
            geometry,
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
        let elastic = self.stiffness * self.power.of(delta);
        let force = elastic + self.damping * rate;
        if force <= 0.0 {
            // A roller never pulls: damping cannot make the contact tensile.
            return (0.0, 0.0, 0.0);
        }
        let k = self.power.exponent() * elastic / delta;
        (force, k, self.damping)
    }

    /// The elastic force K delta^n of a slice and its derivative, blended below the
    /// smoothing scale as in [`Self::slice_force`].
    fn elastic(&self, delta: f64) -> (f64, f64) {
        if delta <= 0.0 {
            return (0.0, 0.0);
        }
        if delta < self.smoothing {
            let top = self.stiffness * self.power.of(self.smoothing);
            let (p, dp) = blend(self.power.exponent(), delta / self.smoothing);
            return (top * p, top * dp / self.smoothing);
        }
        let elastic = self.stiffness * self.power.of(delta);
        (elastic, self.power.exponent() * elastic / delta)
    }

    /// The fade-in of the damping force and its derivative with respect to the approach:
    /// 1 above the smoothing scale, the C2 step of [`Self::smoothed`] below it.
    fn damping_ramp(&self, delta: f64) -> (f64, f64) {
        if delta >= self.smoothing {
            return (1.0, 0.0);
        }
        let t = delta / self.smoothing;
        (
            t * t * t * (10.0 + t * (-15.0 + 6.0 * t)),
            30.0 * t * t * (1.0 - t) * (1.0 - t) / self.smoothing,
        )
    }

    /// True for a ball bearing.
    pub fn is_ball(&self) -> bool {
        self.ball.is_some()
    }

    /// A ball's radial force on the shaft (elastic part plus damping on the radial approach
    /// rate `rate`), never pulling, with its derivatives with respect to the radial
    /// separation r, the axial separation s and `rate`.
    fn ball_radial(&self, contact: &BallContactState, rate: f64) -> (f64, f64, f64, f64) {
        if contact.load <= 0.0 {
            return (0.0, 0.0, 0.0, 0.0);
        }
        let (elastic, dr, ds) = contact.radial();
        let (ramp, dramp) = self.damping_ramp(contact.deformation);
        let force = elastic + self.damping * ramp * rate;
        if force <= 0.0 {
            return (0.0, 0.0, 0.0, 0.0);
        }
        let d_damping = self.damping * dramp * rate;
        (
            force,
            dr + d_damping * contact.cos,
            ds + d_damping * contact.sin,
            self.damping * ramp,
        )
    }

    /// Each ball's radial approach d_j (less the clearance and the race profile) and its rate,
    /// from the rollers' directions and motion left by [`HertzBearing::roller_motion`].
    fn ball_approaches(&mut self, at: &Kinematics) {
        let gamma = self.geometry.clearance.at_speed(at.speed);
        let cage_phase = self.geometry.cage_ratio * at.angle;
        let cage_speed = self.geometry.cage_speed(at.speed);
        for j in 0..self.geometry.rollers {
            let (wavy, wavy_rate) = if self.geometry.is_round() {
                (0.0, 0.0)
            } else {
                self.geometry.waviness_at(j, cage_phase, cage_speed, at)
            };
            let (approach, rate) = self.rollers.radial[j];
            self.approaches[j] = (approach - gamma - wavy, rate - wavy_rate);
        }
    }

    /// Solves the rings' axial separation for the present approaches, from the last one.
    fn solve_axial(&mut self) -> f64 {
        let Some(law) = &self.ball else {
            return 0.0;
        };
        let elastic = |x: f64| self.elastic(x);
        let s = law.axial_separation(self.approaches.iter().map(|a| a.0), self.axial, &elastic);
        self.axial = s;
        s
    }

    /// [`NonlinearForce::force`] of a ball bearing.
    fn ball_force(&mut self, at: &Kinematics, out: &mut [f64]) {
        self.ball_approaches(at);
        let s = self.solve_axial();
        let Some(law) = &self.ball else {
            return;
        };
        let elastic = |x: f64| self.elastic(x);
        let (mut fx, mut fy) = (0.0, 0.0);
        for (j, &(d, rate)) in self.approaches.iter().enumerate() {
            let radial = self.ball_radial(&law.contact(d, s, &elastic), rate).0;
            fx -= self.rollers.cos[j] * radial;
            fy -= self.rollers.sin[j] * radial;
        }
        out.copy_from_slice(&[fx, fy][..out.len()]);
    }

    /// [`NonlinearForce::jacobian`] of a ball bearing. The axial separation s depends on the
    /// shaft's displacement through the axial balance sum_j P_j(d_j, s) = F_a, so
    /// ds/du = -(sum_j dP_j/dd_j g_j) / (sum_j dP_j/ds) enters every ball's radial force;
    /// the damping is radial and leaves the balance alone.
    fn ball_jacobian(&mut self, at: &Kinematics, dfdq: &mut [f64], dfdv: &mut [f64]) {
        self.ball_approaches(at);
        let s = self.solve_axial();
        let mut contacts = std::mem::take(&mut self.contacts);
        let Some(law) = &self.ball else {
            return;
        };
        let elastic = |x: f64| self.elastic(x);
        let w = self.geometry.cage_speed(at.speed);
        contacts.clear();
        contacts.extend(
            self.approaches
                .iter()
                .map(|&(d, _)| law.contact(d, s, &elastic)),
        );
        let (mut stiff_s, mut coupling) = (0.0, [0.0; 2]);
        for (j, c) in contacts.iter().enumerate() {
            let (_, dr, ds) = c.axial();
            stiff_s += ds;
            coupling[0] += dr * self.rollers.cos[j];
            coupling[1] += dr * self.rollers.sin[j];
        }
        let ds_du = if stiff_s > 0.0 {
            [-coupling[0] / stiff_s, -coupling[1] / stiff_s]
        } else {
            [0.0; 2]
        };
        for (j, c) in contacts.iter().enumerate() {
            let (force, dr, ds, dv) = self.ball_radial(c, self.approaches[j].1);
            if force <= 0.0 {
                continue;
            }
            let (sn, cs) = (self.rollers.sin[j], self.rollers.cos[j]);
            let (g, gt) = ([cs, sn], [-sn, cs]);
            for a in 0..2 {
                for b in 0..2 {
                    dfdq[a * 2 + b] -= g[a] * (dr * g[b] + ds * ds_du[b] + dv * w * gt[b]);
                    dfdv[a * 2 + b] -= g[a] * dv * g[b];
                }
            }
        }
        self.contacts = contacts;
    }

    /// [`HertzBearing::rollers`] of a ball bearing: `approach` is each ball's elastic
    /// deformation and `force` its normal load (the radial force over cos(alpha_j)).
    fn ball_states(&self, at: &Kinematics, q: &[f64], v: &[f64]) -> Vec<RollerState> {
        let Some(law) = &self.ball else {
            return Vec::new();
        };
        let w = self.geometry.cage_speed(at.speed);
        let mut motion = Vec::with_capacity(self.geometry.rollers);
        self.geometry.for_each_slice(at, |slice| {
            motion.push((slice.angle, self.approach(slice, w, q, v)));
        });
        let elastic = |x: f64| self.elastic(x);
        let s = law.axial_separation(motion.iter().map(|m| m.1 .0), self.axial, &elastic);
        motion
            .iter()
            .map(|&(angle, (d, rate))| {
                let contact = law.contact(d, s, &elastic);
                let radial = self.ball_radial(&contact, rate).0;
                RollerState {
                    angle,
                    approach: contact.deformation,
                    force: if radial > 0.0 {
                        radial / contact.cos
                    } else {
                        0.0
                    },
                }
            })
            .collect()
    }

    /// [`Self::slice_force`] below the smoothing scale (0 < delta < scale).
    fn blended_force(&self, delta: f64, rate: f64) -> (f64, f64, f64) {
        let (elastic, k) = self.elastic(delta);
        let (ramp, dramp) = self.damping_ramp(delta);
        let force = elastic + self.damping * ramp * rate;
        if force <= 0.0 {
            return (0.0, 0.0, 0.0);
        }
        (force, k + self.damping * dramp * rate, self.damping * ramp)
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

    /// Each roller's share of its slices' approach and rate for displacements `q` and
    /// velocities `v` ([ux, uy] or [ux, uy, tx, ty]) at the rollers' present angles: a slice
    /// at axial offset z has approach radial.0 + z tilt.0 + its offset, and rate
    /// radial.1 + z tilt.1 + its offset's rate ([`Slice::direction`] and
    /// [`Slice::direction_turn`] grouped by z).
    fn roller_motion(&mut self, at: &Kinematics, q: &[f64], v: &[f64]) {
        let w = self.geometry.cage_speed(at.speed);
        let [qx, qy, tx, ty] = padded(q);
        let [vx, vy, wx, wy] = padded(v);
        let r = &mut self.rollers;
        for j in 0..r.sin.len() {
            let (s, c) = (r.sin[j], r.cos[j]);
            r.radial[j] = (c * qx + s * qy, c * vx + s * vy + w * (c * qy - s * qx));
            r.tilt[j] = (c * ty - s * tx, c * wy - s * wx - w * (c * tx + s * ty));
        }
    }

    /// [`NonlinearForce::force`] of a bearing with roller tilt or an out-of-round ring.
    fn tilted_or_wavy_force(&mut self, at: &Kinematics, q: &[f64], v: &[f64], out: &mut [f64]) {
        self.rollers.turn(&self.geometry, at.angle);
        self.roller_motion(at, q, v);
        let (mut fx, mut fy, mut mx, mut my) = (0.0, 0.0, 0.0, 0.0);
        let gamma = self.geometry.clearance.at_speed(at.speed);
        let cage_phase = self.geometry.cage_ratio * at.angle;
        let cage_speed = self.geometry.cage_speed(at.speed);
        let (z_max, skew_max) = self.rollers.reach;
        for j in 0..self.geometry.rollers {
            let (wavy, wavy_rate) = if self.geometry.is_round() {
                (0.0, 0.0)
            } else {
                self.geometry.waviness_at(j, cage_phase, cage_speed, at)
            };
            let (approach, rate) = self.rollers.radial[j];
            let (tilt, tilt_rate) = self.rollers.tilt[j];
            let base = approach - gamma - wavy;
            if base + z_max * tilt.abs() + skew_max <= 0.0 {
                continue;
            }
            // Sums over the slices of Q and of z Q.
            let (mut load, mut moment) = (0.0, 0.0);
            for (k, &z) in self.geometry.slice_z.iter().enumerate() {
                let z = if self.geometry.tilt { z } else { 0.0 };
                let delta = base + z * tilt + self.geometry.slice_skew[k];
                if delta <= 0.0 {
                    continue;
                }
                let q = self.slice_force(delta, rate + z * tilt_rate - wavy_rate).0;
                load += q;
                moment += z * q;
            }
            let (s, c) = (self.rollers.sin[j], self.rollers.cos[j]);
            fx -= c * load;
            fy -= s * load;
            mx += s * moment;
            my -= c * moment;
        }
        out.copy_from_slice(&[fx, fy, mx, my][..out.len()]);
    }

    /// [`NonlinearForce::force`] of a round bearing without roller tilt, in one pass over
    /// the rollers: the same arithmetic as [`Self::tilted_or_wavy_force`] with the tilt and
    /// waviness terms (zero here) left out, so the same forces bit for bit, without storing
    /// each roller's direction and motion first (that pass was a third of the bearing's
    /// time in a cascade).
    fn plain_force(&mut self, at: &Kinematics, q: &[f64], v: &[f64], out: &mut [f64]) {
        let geometry = &self.geometry;
        let cage = self.rollers.cage.sin_cos(geometry.cage_ratio * at.angle);
        let w = geometry.cage_speed(at.speed);
        let gamma = geometry.clearance.at_speed(at.speed);
        let skew_max = self.rollers.reach.1;
        let ([qx, qy], [vx, vy]) = ([q[0], q[1]], [v[0], v[1]]);
        let (mut fx, mut fy) = (0.0, 0.0);
        for &pitch in &self.rollers.pitch {
            let (s, c) = rotate(pitch, cage);
            let base = (c * qx + s * qy) - gamma;
            if base + skew_max <= 0.0 {
                continue;
            }
            let rate = c * vx + s * vy + w * (c * qy - s * qx);
            let mut load = 0.0;
            for &skew in &geometry.slice_skew {
                let delta = base + skew;
                if delta <= 0.0 {
                    continue;
                }
                load += self.slice_force(delta, rate).0;
            }
            fx -= c * load;
            fy -= s * load;
        }
        out[0] = fx;
        out[1] = fy;
    }

    /// Angle, largest approach and force of every roller.
    pub fn rollers(&self, at: &Kinematics, q: &[f64], v: &[f64]) -> Vec<RollerState> {
        if self.is_ball() {
            return self.ball_states(at, q, v);
        }
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

/// The bearing's coordinates [ux, uy] or [ux, uy, tx, ty] as four, the rotations 0 when
/// the bearing has none.
fn padded(x: &[f64]) -> [f64; 4] {
    let mut all = [0.0; 4];
    all[..x.len()].copy_from_slice(x);
    all
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

    /// The sum of [`HertzBearing::add_slice`] over [`RollerGeometry::for_each_slice`] to
    /// round-off, arranged for the time step: the rollers' directions are turned from the
    /// last call's (`Turning`) instead of evaluated, the shaft's motion is projected on
    /// each roller once for all its slices, and a roller that cannot touch over any of its
    /// slices is passed over.
    fn force(&mut self, at: &Kinematics, q: &[f64], v: &[f64], out: &mut [f64]) {
        if self.is_ball() {
            self.rollers.turn(&self.geometry, at.angle);
            self.roller_motion(at, q, v);
            self.ball_force(at, out);
        } else if self.geometry.tilt || !self.geometry.is_round() {
            self.tilted_or_wavy_force(at, q, v, out);
        } else {
            self.plain_force(at, q, v, out);
        }
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
        if self.is_ball() {
            self.rollers.turn(&self.geometry, at.angle);
            self.roller_motion(at, q, v);
            self.ball_jacobian(at, dfdq, dfdv);
            return;
        }
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
        let k = self.power.exponent()
            * self.stiffness
            * HERTZ_BOUND_APPROACH.powf(self.power.exponent() - 1.0);
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

    /// The sum over slices of [`HertzBearing::add_slice`]: the straightforward reference of
    /// [`NonlinearForce::force`], and the magnitude sum |Q| of the slices' forces.
    fn slice_by_slice(
        law: &HertzBearing,
        at: &Kinematics,
        q: &[f64],
        v: &[f64],
    ) -> (Vec<f64>, f64) {
        let (mut out, mut magnitude) = (vec![0.0; q.len()], 0.0);
        let w = law.geometry.cage_speed(at.speed);
        law.geometry.for_each_slice(at, |slice| {
            law.add_slice(slice, w, (q, v), Some(&mut out), None);
            let (delta, rate) = law.approach(slice, w, q, v);
            magnitude += law.slice_force(delta, rate).0;
        });
        (out, magnitude)
    }

    /// The reference bearing with tilt, skew (10 slices) and waviness of both rings.
    fn profiled_bearing() -> RollerBearing {
        let mut b = crate::model::Model::from_toml_str(crate::examples::REFERENCE_ROTOR, None)
            .unwrap()
            .roller_bearings[0]
            .clone();
        b.roller_tilt = true;
        b.slices = 10;
        b.skew_angle = 0.5f64.to_radians();
        b.waviness = vec![
            crate::model::Waviness {
                ring: crate::model::Ring::Inner,
                form: crate::model::WavinessForm::Thesis,
                order: 9,
                amplitude: 1e-6,
                phase: 0.3,
            },
            crate::model::Waviness {
                ring: crate::model::Ring::Outer,
                form: crate::model::WavinessForm::Thesis,
                order: 12,
                amplitude: 0.5e-6,
                phase: -1.0,
            },
        ];
        b
    }

    #[test]
    fn the_one_pass_force_of_a_round_bearing_is_the_general_one_bit_for_bit() {
        // The one-pass form only leaves out terms that are zero without tilt and waviness,
        // so any difference is a changed order of operations or a dropped term.
        let model =
            crate::model::Model::from_toml_str(crate::examples::REFERENCE_ROTOR, None).unwrap();
        let bearing = &model.roller_bearings[0];
        let mut one_pass = HertzBearing::new(bearing, vec![0, 1]).unwrap();
        let mut general = HertzBearing::new(bearing, vec![0, 1]).unwrap();
        let speed = 2.0 * std::f64::consts::PI * 450.0;
        let mut touched = 0;
        for k in 0..3_000 {
            let t = 3.2e-5 * k as f64;
            let at = Kinematics {
                time: t,
                speed,
                angle: speed * t,
            };
            let (s, c) = (0.3 * speed * t).sin_cos();
            let q = [26e-6 * c, 26e-6 * s - 5e-6];
            let v = [-26e-6 * 0.3 * speed * s, 26e-6 * 0.3 * speed * c];
            let (mut a, mut b) = ([0.0; 2], [0.0; 2]);
            one_pass.plain_force(&at, &q, &v, &mut a);
            general.tilted_or_wavy_force(&at, &q, &v, &mut b);
            assert_eq!(a, b, "at step {k}");
            touched += usize::from(a != [0.0; 2]);
        }
        assert!(touched > 1_000, "{touched} steps in contact");
    }

    #[test]
    fn the_time_step_force_is_the_sum_over_slices_to_round_off() {
        let model =
            crate::model::Model::from_toml_str(crate::examples::REFERENCE_ROTOR, None).unwrap();
        let bearings = [
            (model.roller_bearings[0].clone(), vec![0, 1]),
            (profiled_bearing(), vec![0, 1, 2, 3]),
        ];
        for (bearing, dofs) in bearings {
            let mut law = HertzBearing::new(&bearing, dofs.clone()).unwrap();
            let speed = 2.0 * std::f64::consts::PI * 300.0;
            let mut worst: f64 = 0.0;
            let mut touched = 0;
            // 0.06 s of 1.2e-5 s steps (a cascade's), the shaft orbiting at 0.7 of the speed
            // with a radius beyond the 20 um clearance, so rollers enter and leave contact.
            for k in 0..5_000 {
                let t = 1.2e-5 * k as f64;
                let at = Kinematics {
                    time: t,
                    speed,
                    angle: speed * t,
                };
                let (s, c) = (0.7 * speed * t).sin_cos();
                let (r, w) = (24e-6 + 4e-6 * (3.1 * speed * t).sin(), 0.7 * speed);
                let state = [r * c, r * s - 4e-6, 2e-4 * s, -3e-4 * c];
                let rate = [-r * w * s, r * w * c, 2e-4 * w * c, 3e-4 * w * s];
                let (q, v) = (&state[..dofs.len()], &rate[..dofs.len()]);
                let mut fast = vec![0.0; dofs.len()];
                law.force(&at, q, v, &mut fast);
                let (reference, magnitude) = slice_by_slice(&law, &at, q, v);
                touched += usize::from(magnitude > 0.0);
                for (a, b) in fast.iter().zip(&reference) {
                    worst = worst.max((a - b).abs() / magnitude.max(1e-300));
                }
            }
            // The rollers' directions differ by the turned cage angle's error
            // (`linalg::turning`: each step's rotation reused within 8 ulps of the angle,
            // at most 64 x 8 ulps of 113 rad = 7e-12 rad between reseeds, typically a few
            // ulps as the reuse errors take both signs) and the reference's chain of pitch
            // rotations (a few 1e-15). The approach takes that error times |u| = 3e-5 m,
            // and the force the tangent stiffness (1.4e8 N/m) times it: at most 3e-8 N,
            // 1.5e-9 of a light contact's few tens of N (measured: 6e-12). A misplaced term
            // or sign shows at 1e-3 or more.
            assert!(touched > 1_000, "{touched} instants in contact");
            assert!(worst <= 1.5e-9, "{} coordinates: {worst:e}", law.dofs.len());
        }
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
        let top = exact.stiffness * scale.powf(exact.power.exponent());
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
