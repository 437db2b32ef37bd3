//! The single-DOF oscillator m x'' + c x' + k x = f(t), linear and with a hardening cubic
//! spring (Duffing), with their closed forms.

use faer::Mat;
use num_complex::Complex64;
use whirl::fe::SystemMatrices;
use whirl::force::CubicSpring;
use whirl::system::System;

fn one(x: f64) -> Mat<f64> {
    Mat::from_fn(1, 1, |_, _| x)
}

/// m x'' + c x' + k x = f(t) on one coordinate.
#[derive(Clone, Copy, Debug)]
pub struct Oscillator {
    /// m, kg.
    pub mass: f64,
    /// k, N/m.
    pub stiffness: f64,
    /// c, N s/m.
    pub damping: f64,
}

impl Oscillator {
    /// Mass m, natural frequency `wn` (rad/s) and damping ratio `zeta`:
    /// k = m wn^2, c = 2 zeta m wn.
    pub fn tuned(mass: f64, wn: f64, zeta: f64) -> Oscillator {
        Oscillator {
            mass,
            stiffness: mass * wn * wn,
            damping: 2.0 * zeta * mass * wn,
        }
    }

    /// Its 1 x 1 matrices (no gyroscopic term).
    pub fn matrices(&self) -> SystemMatrices {
        SystemMatrices {
            mass: one(self.mass),
            stiffness: one(self.stiffness),
            damping: one(self.damping),
            gyroscopic: one(0.0),
        }
    }

    /// The oscillator with no load and no nonlinear force.
    pub fn system(&self) -> System {
        System::unloaded(self.matrices())
    }

    /// Steady state under Re(F e^{i w t}): x = Re(X e^{i w t}), X = F / (k - m w^2 + i c w).
    pub fn steady_state(&self, force: f64, w: f64) -> Complex64 {
        Complex64::new(force, 0.0)
            / Complex64::new(self.stiffness - self.mass * w * w, self.damping * w)
    }
}

/// The Duffing oscillator m x'' + c x' + k x + k3 x^3 = F cos(w t).
#[derive(Clone, Copy, Debug)]
pub struct Duffing {
    /// m, kg.
    pub mass: f64,
    /// c, N s/m.
    pub damping: f64,
    /// k, N/m.
    pub stiffness: f64,
    /// k3, N/m^3.
    pub cubic: f64,
    /// F, N.
    pub force: f64,
    /// Largest |x| expected, m: the cubic spring's stability bound.
    pub reach: f64,
}

impl Duffing {
    /// Unforced: k in the matrices, k3 x^3 as a nonlinear force.
    pub fn system(&self) -> System {
        System {
            nonlinear: vec![Box::new(CubicSpring::new(0, 0.0, self.cubic, self.reach))],
            ..Oscillator {
                mass: self.mass,
                stiffness: self.stiffness,
                damping: self.damping,
            }
            .system()
        }
    }

    /// The one-harmonic (first-order harmonic balance) relation
    /// [(k - m w^2 + 3/4 k3 A^2)^2 + (c w)^2] A^2 - F^2, over F^2.
    pub fn defect(&self, frequency: f64, amplitude: f64) -> f64 {
        let stiffness = self.stiffness - self.mass * frequency * frequency
            + 0.75 * self.cubic * amplitude.powi(2);
        let damping = self.damping * frequency;
        ((stiffness * stiffness + damping * damping) * amplitude * amplitude
            - self.force * self.force)
            / (self.force * self.force)
    }

    /// Folds of the one-harmonic relation: with u = A^2, a = k - m w^2, b = 3/4 k3, the
    /// curve g(u, w) = ((a + b u)^2 + (c w)^2) u - F^2 = 0 turns where dg/du = 0. Newton on
    /// both from a nearby start (u, w) gives them to round-off; returns the fold's w.
    pub fn fold(&self, mut u: f64, mut w: f64) -> f64 {
        let (m, c, k, f) = (self.mass, self.damping, self.stiffness, self.force);
        let b = 0.75 * self.cubic;
        for _ in 0..50 {
            let a = k - m * w * w;
            let da = -2.0 * m * w;
            let cw2 = (c * w).powi(2);
            let g = ((a + b * u).powi(2) + cw2) * u - f * f;
            let gu = (a + b * u).powi(2) + cw2 + 2.0 * b * u * (a + b * u);
            let gw = (2.0 * (a + b * u) * da + 2.0 * c * c * w) * u;
            let guu = 4.0 * b * (a + b * u) + 2.0 * b * (a + b * u) + 2.0 * b * b * u;
            let guw = 2.0 * (a + b * u) * da + 2.0 * c * c * w + 2.0 * b * u * da;
            let det = gu * guw - gw * guu;
            let (du, dw) = ((g * guw - gw * gu) / det, (gu * gu - guu * g) / det);
            u -= du;
            w -= dw;
            if du.abs() + dw.abs() < 1e-15 {
                break;
            }
        }
        w
    }
}
