//! The isotropic Jeffcott rotor: a mass m on a shaft of stiffness k with damping c, spinning
//! at w with an unbalance m e, on the coordinates (x, y); and the same rotor inside a rigid
//! clearance ring. Closed forms beside each.

use faer::Mat;
use num_complex::Complex64;
use whirl::fe::SystemMatrices;
use whirl::force::{Kinematics, NonlinearForce};
use whirl::system::System;

/// m (x'' , y'') + c (x', y') + k (x, y) = m e w^2 (cos w t, sin w t).
#[derive(Clone, Copy, Debug)]
pub struct Jeffcott {
    /// m, kg.
    pub mass: f64,
    /// k, N/m.
    pub stiffness: f64,
    /// c, N s/m.
    pub damping: f64,
    /// m e, kg m.
    pub unbalance: f64,
}

impl Jeffcott {
    /// On (x, y), with its unbalance and no nonlinear force.
    pub fn system(&self) -> System {
        let diagonal = |v: f64| Mat::from_fn(2, 2, |i, j| if i == j { v } else { 0.0 });
        System {
            // m e w^2 (cos w t, sin w t) = Re(m e w^2 (1, -i) e^{i w t}).
            unbalance_re: vec![self.unbalance, 0.0],
            unbalance_im: vec![0.0, -self.unbalance],
            ..System::unloaded(SystemMatrices {
                mass: diagonal(self.mass),
                stiffness: diagonal(self.stiffness),
                damping: diagonal(self.damping),
                gyroscopic: diagonal(0.0),
            })
        }
    }

    /// The critical speed, the undamped natural frequency sqrt(k / m), rad/s.
    pub fn critical_speed(&self) -> f64 {
        (self.stiffness / self.mass).sqrt()
    }

    /// zeta = c / (2 sqrt(k m)).
    pub fn damping_ratio(&self) -> f64 {
        self.damping / (2.0 * (self.stiffness * self.mass).sqrt())
    }

    /// The steady forward circular orbit at speed w, the unbalance at `phase` (rad):
    /// x = Re(X e^{i w t}) with X = m e w^2 e^{i phase} / (k - m w^2 + i c w), and Y = -i X.
    pub fn response(&self, w: f64, phase: f64) -> Complex64 {
        Complex64::from_polar(self.unbalance * w * w, phase)
            / Complex64::new(self.stiffness - self.mass * w * w, self.damping * w)
    }

    /// The speed of the largest response: with a force growing as w^2 the amplitude peaks
    /// above the critical speed, at w_n / sqrt(1 - 2 zeta^2).
    pub fn peak_speed(&self) -> f64 {
        let zeta = self.damping_ratio();
        self.critical_speed() / (1.0 - 2.0 * zeta * zeta).sqrt()
    }

    /// The rotor as a model file: a disk of mass m on an isotropic spring-damper k, c at
    /// node 0, its unbalance at `phase_deg`. The single 1 cm shaft element hangs free from
    /// it and weighs 1e-9 kg (density 1e-3), so the disk's translation obeys the equations
    /// above to about 1e-10.
    pub fn model_file(&self, phase_deg: f64) -> String {
        format!(
            r#"
[[material]]
name = "steel"
young_modulus = 2.11e11
density = 1e-3
[[shaft]]
length = 0.01
outer_diameter = 0.01
material = "steel"
elements = 1
[[disk]]
node = 0
mass = {:e}
polar_inertia = 0.05
diametral_inertia = 0.025
[[bearing]]
node = 0
kxx = {k:e}
kyy = {k:e}
cxx = {c:e}
cyy = {c:e}
[[unbalance]]
node = 0
mass_radius = {:e}
phase = {phase_deg:e}
"#,
            self.mass,
            self.unbalance,
            k = self.stiffness,
            c = self.damping,
        )
    }
}

/// A one-mass rotor: a 10 kg disk on an isotropic 1e6 N/m, 150 N s/m support at node 0
/// (critical speed 50.33 Hz, damping ratio 0.0237, half-power band 2.4 Hz), its unbalance
/// 4e-4 kg m (the steady 1X peaks at 0.84 mm). As a model file
/// ([`Jeffcott::model_file`]) the single 1 cm shaft element hangs free from the disk and
/// weighs 1e-9 kg, so the disk's translation obeys m x'' + c x' + k x = m_u e Omega^2
/// cos(Omega t + phi) to about 1e-10.
pub const ONE_MASS: Jeffcott = Jeffcott {
    mass: 10.0,
    stiffness: 1e6,
    damping: 150.0,
    unbalance: 4e-4,
};

/// A rigid ring of clearance gamma around an isotropic rotor, contact linear in the
/// penetration: F = -k_c (r - gamma)_+ e_r on (x, y).
pub struct ClearanceRing {
    pub dofs: [usize; 2],
    pub stiffness: f64,
    pub clearance: f64,
}

impl NonlinearForce for ClearanceRing {
    fn name(&self) -> String {
        "clearance ring".into()
    }
    fn dofs(&self) -> &[usize] {
        &self.dofs
    }
    fn force(&mut self, _: &Kinematics, q: &[f64], _: &[f64], out: &mut [f64]) {
        let r = q[0].hypot(q[1]);
        let factor = if r > self.clearance {
            self.stiffness * (1.0 - self.clearance / r)
        } else {
            0.0
        };
        out[0] = -factor * q[0];
        out[1] = -factor * q[1];
    }
    fn jacobian(
        &mut self,
        _: &Kinematics,
        q: &[f64],
        _: &[f64],
        dfdq: &mut [f64],
        dfdv: &mut [f64],
    ) {
        // d/dq of -k_c (1 - gamma / r) q = -k_c ((1 - gamma / r) I + gamma q q^T / r^3).
        let r = q[0].hypot(q[1]);
        dfdv.fill(0.0);
        if r <= self.clearance {
            dfdq.fill(0.0);
            return;
        }
        let (k, g3) = (self.stiffness, self.clearance / r.powi(3));
        let diagonal = 1.0 - self.clearance / r;
        dfdq.copy_from_slice(&[
            -k * (diagonal + g3 * q[0] * q[0]),
            -k * g3 * q[0] * q[1],
            -k * g3 * q[0] * q[1],
            -k * (diagonal + g3 * q[1] * q[1]),
        ]);
    }
    fn stiffness_bound(&self) -> Vec<f64> {
        vec![self.stiffness, 0.0, 0.0, self.stiffness]
    }
}

/// A Jeffcott rotor inside a [`ClearanceRing`] of contact stiffness k_c and clearance
/// gamma. Its synchronous orbit is an exact forward circle of radius r (the contact force
/// is then a constant-magnitude radial force turning with it).
#[derive(Clone, Copy, Debug)]
pub struct RingRotor {
    pub rotor: Jeffcott,
    /// k_c, N/m.
    pub contact: f64,
    /// gamma, m.
    pub clearance: f64,
}

impl RingRotor {
    /// The rotor with the ring as its nonlinear force.
    pub fn system(&self) -> System {
        System {
            nonlinear: vec![Box::new(ClearanceRing {
                dofs: [0, 1],
                stiffness: self.contact,
                clearance: self.clearance,
            })],
            ..self.rotor.system()
        }
    }

    /// k_eff = k + k_c (1 - gamma / r) in contact (r > gamma), k out of it.
    fn effective_stiffness(&self, r: f64) -> f64 {
        let contact = if r > self.clearance {
            self.contact * (1.0 - self.clearance / r)
        } else {
            0.0
        };
        self.rotor.stiffness + contact
    }

    /// Defect of the closed form m e w^2 = |k_eff - m w^2 + i c w| r, relative to the size
    /// of the terms that cancel in it (as the solver's residual is).
    pub fn defect(&self, w: f64, r: f64) -> f64 {
        let Jeffcott {
            mass,
            damping,
            unbalance,
            ..
        } = self.rotor;
        let k_eff = self.effective_stiffness(r);
        let real = k_eff - mass * w * w;
        let forcing = unbalance * w * w;
        let terms = (k_eff + mass * w * w + damping * w) * r + forcing;
        (real.hypot(damping * w) * r - forcing) / terms
    }

    /// The closed form squared is a quadratic in u = w^2 for each radius r > gamma:
    /// (m^2 r^2 - (m e)^2) u^2 + (c^2 - 2 k_eff m) r^2 u + k_eff^2 r^2 = 0. Its coefficients
    /// (a, b, c).
    fn quadratic(&self, r: f64) -> (f64, f64, f64) {
        let (m, c, me) = (self.rotor.mass, self.rotor.damping, self.rotor.unbalance);
        let k_eff = self.effective_stiffness(r);
        (
            m * m * r * r - me * me,
            (c * c - 2.0 * k_eff * m) * r * r,
            k_eff * k_eff * r * r,
        )
    }

    /// The frequency of the contact branch on its upper side at radius r (the larger root).
    fn upper_frequency(&self, r: f64) -> f64 {
        let (a, b, c) = self.quadratic(r);
        ((-b + (b * b - 4.0 * a * c).sqrt()) / (2.0 * a)).sqrt()
    }

    /// The fold of the contact branch: the largest w on it. Radii with a solution end where
    /// the discriminant vanishes (found by bisection); below that the largest w of the upper
    /// root is bracketed by a scan and refined by golden section.
    pub fn fold(&self) -> f64 {
        let gamma = self.clearance;
        let discriminant = |r: f64| {
            let (a, b, c) = self.quadratic(r);
            b * b - 4.0 * a * c
        };
        let (mut lo, mut hi) = (2.0 * gamma, 100.0 * gamma);
        assert!(discriminant(lo) > 0.0 && discriminant(hi) < 0.0);
        while hi - lo > 1e-14 * hi {
            let mid = 0.5 * (lo + hi);
            if discriminant(mid) > 0.0 {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        let (from, width) = (gamma, (lo - gamma) / 1000.0);
        let best = (1..=1000)
            .map(|i| from + width * i as f64)
            .fold(lo, |best, r| {
                if self.upper_frequency(r) > self.upper_frequency(best) {
                    r
                } else {
                    best
                }
            });
        let (mut a, mut b) = (best - width, (best + width).min(lo));
        let golden = (5f64.sqrt() - 1.0) / 2.0;
        while b - a > 1e-10 * best {
            let (x1, x2) = (b - golden * (b - a), a + golden * (b - a));
            if self.upper_frequency(x1) > self.upper_frequency(x2) {
                b = x2;
            } else {
                a = x1;
            }
        }
        self.upper_frequency(0.5 * (a + b))
    }

    /// The corner where the free orbit's radius m e w^2 / |k - m w^2 + i c w| equals
    /// gamma: with u = w^2, (m^2 - (m e)^2 / gamma^2) u^2 + (c^2 - 2 k m) u + k^2 = 0 (larger
    /// root).
    pub fn corner(&self) -> f64 {
        let Jeffcott {
            mass,
            stiffness,
            damping,
            unbalance,
        } = self.rotor;
        let (a, b, c) = (
            mass * mass - (unbalance / self.clearance).powi(2),
            damping * damping - 2.0 * stiffness * mass,
            stiffness * stiffness,
        );
        ((-b + (b * b - 4.0 * a * c).sqrt()) / (2.0 * a)).sqrt()
    }
}
