//! Roller positions, slices and the motion-independent part of each roller's approach.

use std::f64::consts::PI;

use serde::Serialize;

use crate::force::Kinematics;
use crate::model::{
    Clearance, ElementDefect, RaceDefect, Ring, RollerBearing, Waviness, WavinessForm,
};

/// One contact slice of one roller at one instant.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Slice {
    /// Roller index, 0-based.
    pub roller: usize,
    /// Roller angle theta_j, rad.
    pub angle: f64,
    /// sin and cos of the angle, computed once per roller for all its slices.
    pub sin_cos: (f64, f64),
    /// Axial offset z_k of the slice from the bearing plane, m.
    pub z: f64,
    /// Approach not due to the shaft's motion: -gamma + skew - waviness, m.
    pub offset: f64,
    /// Its rate of change, m/s.
    pub offset_rate: f64,
}

impl Slice {
    /// d(delta)/d(u) for u = [ux, uy, tx, ty] (the first `len` entries are used).
    pub fn direction(&self) -> [f64; 4] {
        let (s, c) = self.sin_cos;
        [c, s, -self.z * s, self.z * c]
    }

    /// d/d(theta) of [`Slice::direction`]; times the cage speed it is the rate of the
    /// direction as the roller orbits.
    pub fn direction_turn(&self) -> [f64; 4] {
        let (s, c) = self.sin_cos;
        [-s, c, -self.z * c, -self.z * s]
    }
}

/// A roller's state for outputs: where it is, how far it presses, what it carries.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct RollerState {
    /// Roller angle, rad.
    pub angle: f64,
    /// Largest approach over its slices, m (positive = penetration).
    pub approach: f64,
    /// Contact force on the roller (sum over slices), N, never negative.
    pub force: f64,
}

/// The kinematics of a roller bearing, independent of the contact law.
#[derive(Debug, Clone, PartialEq)]
pub struct RollerGeometry {
    /// Number of rollers N_b.
    pub rollers: usize,
    /// Cage speed per spin speed, (1 - D_b/D_p)/2 (eq. 3.4).
    pub cage_ratio: f64,
    /// Angle of roller 0 at spin angle 0, rad.
    pub cage_angle: f64,
    /// Internal radial clearance.
    pub clearance: Clearance,
    /// True when the slices follow the shaft's slope (roller tilt).
    pub tilt: bool,
    /// Axial offsets of the slice centres, m.
    pub slice_z: Vec<f64>,
    /// Approach added to each slice by the roller's skew, m.
    pub slice_skew: Vec<f64>,
    /// Ring waviness.
    pub waviness: Vec<Waviness>,
    /// Local raceway defects.
    pub defects: Vec<RaceDefect>,
    /// Spots on rolling elements.
    pub element_defects: Vec<ElementDefect>,
    /// An element's spin relative to the cage per spin angle of the shaft (BSF over the
    /// spin speed).
    pub spin_ratio: f64,
}

impl RollerGeometry {
    /// The geometry of a bearing of the model.
    pub fn new(bearing: &RollerBearing) -> Self {
        let n = bearing.slices.max(1);
        let l = bearing.roller_length;
        // Slice centres across the roller (eq. 3.13 with width l / n).
        let slice_z: Vec<f64> = if n == 1 {
            vec![0.0]
        } else {
            (0..n)
                .map(|k| -0.5 * l + (k as f64 + 0.5) * l / n as f64)
                .collect()
        };
        let outer_radius = 0.5 * (bearing.pitch_diameter + bearing.roller_diameter);
        let slice_skew = slice_z
            .iter()
            .map(|&z| skew_approach(z, bearing.skew_angle, outer_radius))
            .collect();
        RollerGeometry {
            rollers: bearing.rollers,
            cage_ratio: bearing.cage_speed_ratio,
            cage_angle: bearing.cage_angle,
            clearance: bearing.clearance.clone(),
            tilt: bearing.roller_tilt,
            slice_z,
            slice_skew,
            waviness: bearing.waviness.clone(),
            defects: bearing.defects.clone(),
            element_defects: bearing.element_defects.clone(),
            spin_ratio: super::characteristic_frequencies(bearing, 1.0).bsf,
        }
    }

    /// Coordinates the contact acts on: 2 (ux, uy), or 4 with tilt (ux, uy, tx, ty).
    pub fn coordinates(&self) -> usize {
        if self.tilt {
            4
        } else {
            2
        }
    }

    /// True when neither ring has waviness or a defect: no roller's approach then depends
    /// on where it is.
    pub fn is_round(&self) -> bool {
        self.waviness.is_empty() && self.defects.is_empty() && self.element_defects.is_empty()
    }

    /// Cage speed w_c at spin speed `omega`, rad/s.
    pub fn cage_speed(&self, omega: f64) -> f64 {
        self.cage_ratio * omega
    }

    /// Varying-compliance (roller passage) frequency N_b w_c, rad/s (eq. 4.4).
    pub fn varying_compliance_frequency(&self, omega: f64) -> f64 {
        self.rollers as f64 * self.cage_speed(omega)
    }

    /// Waviness vibration frequency (N_w - 1) w_c of an order-N_w waviness, rad/s (eq. 4.5).
    pub fn waviness_frequency(&self, order: usize, omega: f64) -> f64 {
        (order as f64 - 1.0) * self.cage_speed(omega)
    }

    /// Angle of roller `j` at spin angle `phi`, rad.
    pub fn roller_angle(&self, j: usize, phi: f64) -> f64 {
        2.0 * PI * j as f64 / self.rollers as f64 + self.cage_angle + self.cage_ratio * phi
    }

    /// Angle of roller `j` at spin angle 0 (its place in the cage), rad.
    pub fn pitch(&self, j: usize) -> f64 {
        2.0 * PI / self.rollers as f64 * j as f64 + self.cage_angle
    }

    /// Calls `visit` for every slice of every roller at instant `at`.
    pub fn for_each_slice(&self, at: &Kinematics, mut visit: impl FnMut(&Slice)) {
        let gamma = self.clearance.at_speed(at.speed);
        let cage_phase = self.cage_ratio * at.angle;
        let cage_speed = self.cage_speed(at.speed);
        // The rollers' sines and cosines by rotating the first roller's by the pitch, one
        // roller after the other: two sin_cos per call instead of one per roller (they were
        // a quarter of a cascade's time), equal to the direct ones within a few ulps.
        let pitch_step = 2.0 * PI / self.rollers as f64;
        let (step_sin, step_cos) = pitch_step.sin_cos();
        let mut sin_cos = (self.cage_angle + cage_phase).sin_cos();
        for j in 0..self.rollers {
            let pitch = self.pitch(j);
            let (wavy, wavy_rate) = if self.is_round() {
                (0.0, 0.0)
            } else {
                self.waviness_at(j, cage_phase, cage_speed, at)
            };
            let angle = pitch + cage_phase;
            if j > 0 {
                let (s, c) = sin_cos;
                sin_cos = (s * step_cos + c * step_sin, c * step_cos - s * step_sin);
            }
            for (k, &z) in self.slice_z.iter().enumerate() {
                visit(&Slice {
                    roller: j,
                    angle,
                    sin_cos,
                    z: if self.tilt { z } else { 0.0 },
                    offset: -gamma + self.slice_skew[k] - wavy,
                    offset_rate: -wavy_rate,
                });
            }
        }
    }

    /// P_o(j) + P_i(j) and its rate: the waviness (eq. 3.18 or fixed to the ring), the
    /// race defects under roller j and the spots on it, with the cage and ring angles in
    /// place of w t so that speed ramps are followed.
    pub(crate) fn waviness_at(
        &self,
        j: usize,
        cage_phase: f64,
        cage_speed: f64,
        at: &Kinematics,
    ) -> (f64, f64) {
        let pitch = self.pitch(j);
        let mut value = 0.0;
        let mut rate = 0.0;
        for w in &self.waviness {
            let (ring_phase, ring_speed) = ring_motion(w.ring, at);
            let n = w.order as f64;
            let arg = n * (cage_phase - ring_phase) + pitch_multiple(w) * pitch + w.phase;
            value += w.amplitude * arg.cos();
            rate -= w.amplitude * n * (cage_speed - ring_speed) * arg.sin();
        }
        for d in &self.defects {
            let (ring_phase, ring_speed) = ring_motion(d.ring, at);
            let (dip, slope) =
                defect_dip(d.angle, d.width, d.depth, pitch + cage_phase - ring_phase);
            value += dip;
            rate += slope * (cage_speed - ring_speed);
        }
        for d in self.element_defects.iter().filter(|d| d.element == j) {
            // The spot meets the outer race at spin angle 0 and the inner at pi.
            let spin = self.spin_ratio * at.angle;
            for contact in [0.0, PI] {
                let (dip, slope) = defect_dip(d.angle + contact, d.width, d.depth, spin);
                value += dip;
                rate += slope * self.spin_ratio * at.speed;
            }
        }
        (value, rate)
    }
}

/// The ring's angle and speed: the outer ring stands, the inner turns with the shaft.
fn ring_motion(ring: Ring, at: &Kinematics) -> (f64, f64) {
    match ring {
        Ring::Outer => (0.0, 0.0),
        Ring::Inner => (at.angle, at.speed),
    }
}

/// What multiplies roller j's pitch angle in the waviness' argument. Eq. 3.18 as printed
/// takes it once, which makes the whole bearing force oscillate at (N_w - 1) w_c (eq. 4.5)
/// for any order (docs/theory-errata.md); a shape fixed to the ring is met by each roller
/// at its own angle, so the order multiplies the pitch too.
fn pitch_multiple(w: &Waviness) -> f64 {
    match w.form {
        WavinessForm::Thesis => 1.0,
        WavinessForm::RingFixed => w.order as f64,
    }
}

/// The depth of a dip `depth` deep and `width` wide centred at `centre` at `angle` (rad,
/// in the frame of the surface that carries it) and its derivative with respect to that
/// angle, per rad.
fn defect_dip(centre: f64, width: f64, depth: f64, angle: f64) -> (f64, f64) {
    let s = (angle - centre + PI).rem_euclid(2.0 * PI) - PI;
    if s.abs() >= 0.5 * width {
        return (0.0, 0.0);
    }
    let k = 2.0 * PI / width;
    let (sin, cos) = (k * s).sin_cos();
    (0.5 * depth * (1.0 + cos), -0.5 * depth * k * sin)
}

/// Approach of a slice at axial offset `z` of a roller skewed by `alpha` in a raceway of
/// radius `r`: the slice moves sideways by z sin(alpha) and so reaches out to
/// sqrt(r^2 + (z sin alpha)^2). Eq. 3.16 as printed is garbled (its sign would pull a skewed
/// roller away from the ring); this is the geometry it describes.
fn skew_approach(z: f64, alpha: f64, r: f64) -> f64 {
    let s = z * alpha.sin();
    // r (sqrt(1 + x) - 1) without cancellation: r x / (sqrt(1 + x) + 1), x = (s/r)^2.
    let x = (s / r).powi(2);
    r * x / ((1.0 + x).sqrt() + 1.0)
}
