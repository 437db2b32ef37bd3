//! A second-order system ready to march in time, in the integrator's coordinates:
//!
//! ```text
//! M q'' + (C + Omega(t) G) q' + K q = F_0 + Re(f (Omega^2 - i Omega') e^{i phi(t)}) + sum F_nl
//! ```
//!
//! F_0 is constant (gravity), f the unbalance phasor per Omega^2 (see
//! [`crate::fe::unbalance_force`]); the Omega' term is the tangential force of an unbalance
//! on a shaft that speeds up. The gyroscopic effect of angular acceleration (a stiffness
//! proportional to Omega') is neglected, as is usual for run-ups.

use faer::Mat;

use crate::error::{Error, Result};
use crate::force::{Kinematics, NonlinearForce};

/// Spin speed over time.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum SpeedProfile {
    /// Constant speed, rad/s.
    Constant(f64),
    /// Linear ramp from `from` to `to` (rad/s) over `duration` (s), then constant.
    Ramp {
        /// Starting speed, rad/s.
        from: f64,
        /// Final speed, rad/s.
        to: f64,
        /// Time to reach it, s.
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
            SpeedProfile::Ramp { from, to, duration } => {
                let rate = (to - from) / duration;
                if t <= duration {
                    let k = Kinematics {
                        time: t,
                        speed: from + rate * t,
                        angle: from * t + 0.5 * rate * t * t,
                    };
                    (k, rate)
                } else {
                    let end = from * duration + 0.5 * rate * duration * duration;
                    (
                        Kinematics {
                            time: t,
                            speed: to,
                            angle: end + to * (t - duration),
                        },
                        0.0,
                    )
                }
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
}

/// The system to integrate.
pub struct TimeProblem {
    /// Mass matrix.
    pub mass: Mat<f64>,
    /// Stiffness matrix (without the nonlinear forces).
    pub stiffness: Mat<f64>,
    /// Damping matrix.
    pub damping: Mat<f64>,
    /// Gyroscopic matrix (times the spin speed).
    pub gyroscopic: Mat<f64>,
    /// Constant force (gravity).
    pub constant_force: Vec<f64>,
    /// Real part of the unbalance phasor per Omega^2.
    pub unbalance_re: Vec<f64>,
    /// Imaginary part of the unbalance phasor per Omega^2.
    pub unbalance_im: Vec<f64>,
    /// Nonlinear forces.
    pub nonlinear: Vec<Box<dyn NonlinearForce>>,
    /// Spin speed over time.
    pub speed: SpeedProfile,
}

impl TimeProblem {
    /// M, K, C and G, for what looks at all four (their band structure).
    pub(crate) fn matrices(&self) -> [&Mat<f64>; 4] {
        [&self.mass, &self.stiffness, &self.damping, &self.gyroscopic]
    }

    /// The acceleration M^-1 (F - (C + Omega G) v - K q) under the total force `force`
    /// (external and nonlinear), used to start the integrators.
    pub(crate) fn acceleration(&self, q: &[f64], v: &[f64], force: &[f64], speed: f64) -> Vec<f64> {
        let n = self.size();
        let mut rhs = Mat::<f64>::from_fn(n, 1, |i, _| {
            force[i]
                - (0..n)
                    .map(|j| {
                        self.stiffness[(i, j)] * q[j]
                            + (self.damping[(i, j)] + speed * self.gyroscopic[(i, j)]) * v[j]
                    })
                    .sum::<f64>()
        });
        faer::linalg::solvers::Solve::solve_in_place(&self.mass.partial_piv_lu(), rhs.as_mut());
        (0..n).map(|i| rhs[(i, 0)]).collect()
    }

    /// Number of coordinates.
    pub fn size(&self) -> usize {
        self.mass.nrows()
    }

    /// Checks sizes and the nonlinear forces' coordinates.
    ///
    /// # Errors
    /// [`Error::InvalidOption`] when the stiffness, damping or gyroscopic matrix is not square
    /// of the mass matrix's size, a force vector has another length, or a nonlinear force acts
    /// on a coordinate outside the problem.
    pub fn check(&self) -> Result<()> {
        let n = self.size();
        let square = |m: &Mat<f64>| m.nrows() == n && m.ncols() == n;
        if !(square(&self.stiffness) && square(&self.damping) && square(&self.gyroscopic))
            || self.constant_force.len() != n
            || self.unbalance_re.len() != n
            || self.unbalance_im.len() != n
        {
            return Err(Error::InvalidOption(
                "time problem matrices and vectors differ in size".into(),
            ));
        }
        for f in &self.nonlinear {
            if let Some(&d) = f.dofs().iter().find(|&&d| d >= n) {
                return Err(Error::InvalidOption(format!(
                    "{} acts on coordinate {d} of {n}",
                    f.name()
                )));
            }
        }
        Ok(())
    }

    /// The spin kinematics at time t and the coefficients [c_re, c_im] that give the
    /// unbalance force as c_re u_re + c_im u_im (u = `unbalance_re`, `unbalance_im`):
    ///
    /// ```text
    /// Re(f (w^2 - i w') e^{i phi}) = (w^2 cos phi + w' sin phi) u_re + (-w^2 sin phi + w' cos phi) u_im
    /// ```
    ///
    /// The one definition of the time dependence of the linear force: integrators that keep
    /// products with u_re and u_im precomputed scale them by these coefficients.
    pub fn unbalance_coefficients(&self, t: f64) -> (Kinematics, [f64; 2]) {
        let (k, accel) = self.speed.at(t);
        let (s, c) = k.angle.sin_cos();
        let w2 = k.speed * k.speed;
        (k, [w2 * c + accel * s, accel * c - w2 * s])
    }

    /// Linear external force at time t (gravity and unbalance) into `out`.
    pub fn external_force(&self, t: f64, out: &mut [f64]) -> Kinematics {
        let (k, [c_re, c_im]) = self.unbalance_coefficients(t);
        for i in 0..out.len() {
            out[i] =
                self.constant_force[i] + c_re * self.unbalance_re[i] + c_im * self.unbalance_im[i];
        }
        k
    }

    /// The coordinates some nonlinear force acts on, ascending and without repeats.
    pub fn nonlinear_dofs(&self) -> Vec<usize> {
        let mut dofs: Vec<usize> = self
            .nonlinear
            .iter()
            .flat_map(|f| f.dofs().iter().copied())
            .collect();
        dofs.sort_unstable();
        dofs.dedup();
        dofs
    }

    /// Adds the nonlinear forces at (q, v) into `out`; `scratch_*` hold one force's values.
    pub fn add_nonlinear(
        &mut self,
        at: &Kinematics,
        q: &[f64],
        v: &[f64],
        out: &mut [f64],
        scratch: &mut NlScratch,
    ) {
        for f in self.nonlinear.iter_mut() {
            let m = scratch.gather(f.dofs(), q, v);
            f.force(at, &scratch.q[..m], &scratch.v[..m], &mut scratch.f[..m]);
            for a in 0..m {
                out[scratch.idx[a]] += scratch.f[a];
            }
        }
    }

    /// Total tangent stiffness bound of the nonlinear forces, as a dense matrix.
    pub fn nonlinear_stiffness_bound(&self) -> Mat<f64> {
        let n = self.size();
        let mut k = Mat::<f64>::zeros(n, n);
        for f in &self.nonlinear {
            let dofs = f.dofs();
            let b = f.stiffness_bound();
            let m = dofs.len();
            for a in 0..m {
                for c in 0..m {
                    k[(dofs[a], dofs[c])] += b[a * m + c];
                }
            }
        }
        k
    }

    /// Adds the nonlinear forces' tangent stiffness (-dF/dq) and damping (-dF/dv) at (q, v).
    pub fn add_nonlinear_tangent(
        &mut self,
        at: &Kinematics,
        q: &[f64],
        v: &[f64],
        kt: &mut Mat<f64>,
        ct: &mut Mat<f64>,
        scratch: &mut NlScratch,
    ) {
        for f in self.nonlinear.iter_mut() {
            let m = scratch.gather(f.dofs(), q, v);
            f.jacobian(
                at,
                &scratch.q[..m],
                &scratch.v[..m],
                &mut scratch.jq[..m * m],
                &mut scratch.jv[..m * m],
            );
            for a in 0..m {
                for c in 0..m {
                    let (i, j) = (scratch.idx[a], scratch.idx[c]);
                    kt[(i, j)] -= scratch.jq[a * m + c];
                    ct[(i, j)] -= scratch.jv[a * m + c];
                }
            }
        }
    }

    /// Work buffers sized for the largest nonlinear force.
    pub fn scratch(&self) -> NlScratch {
        let m = self
            .nonlinear
            .iter()
            .map(|f| f.dofs().len())
            .max()
            .unwrap_or(0);
        NlScratch {
            idx: vec![0; m],
            q: vec![0.0; m],
            v: vec![0.0; m],
            f: vec![0.0; m],
            jq: vec![0.0; m * m],
            jv: vec![0.0; m * m],
        }
    }
}

/// Work buffers for evaluating nonlinear forces without allocating.
#[derive(Debug, Clone)]
pub struct NlScratch {
    idx: Vec<usize>,
    q: Vec<f64>,
    v: Vec<f64>,
    f: Vec<f64>,
    jq: Vec<f64>,
    jv: Vec<f64>,
}

impl NlScratch {
    /// Copies a force's coordinates and their displacements and velocities; returns the count.
    fn gather(&mut self, dofs: &[usize], q: &[f64], v: &[f64]) -> usize {
        for (a, &d) in dofs.iter().enumerate() {
            self.idx[a] = d;
            self.q[a] = q[d];
            self.v[a] = v[d];
        }
        dofs.len()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unbalance_coefficients_give_the_complex_force() {
        let problem = TimeProblem {
            mass: Mat::identity(2, 2),
            stiffness: Mat::zeros(2, 2),
            damping: Mat::zeros(2, 2),
            gyroscopic: Mat::zeros(2, 2),
            constant_force: vec![1.0, -2.0],
            unbalance_re: vec![0.3, -0.1],
            unbalance_im: vec![0.2, 0.5],
            nonlinear: Vec::new(),
            speed: SpeedProfile::Ramp {
                from: 10.0,
                to: 300.0,
                duration: 2.0,
            },
        };
        let mut out = [0.0; 2];
        for t in [0.0, 0.7, 1.9, 2.5] {
            let (k, accel) = problem.speed.at(t);
            problem.external_force(t, &mut out);
            let spin = num_complex::Complex64::new(k.speed * k.speed, -accel)
                * num_complex::Complex64::from_polar(1.0, k.angle);
            for i in 0..2 {
                let f =
                    num_complex::Complex64::new(problem.unbalance_re[i], problem.unbalance_im[i]);
                let expected = problem.constant_force[i] + (f * spin).re;
                // A few roundings of numbers up to 1e5 (Omega^2).
                assert!((out[i] - expected).abs() < 1e-10 * expected.abs().max(1.0));
            }
        }
    }
}
