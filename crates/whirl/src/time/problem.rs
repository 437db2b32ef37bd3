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

use super::forces::{Kinematics, NonlinearForce};
use crate::error::{Error, Result};

/// Spin speed over time.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum SpeedProfile {
    /// Constant speed, rad/s.
    Constant(f64),
    /// Linear ramp from `from` to `to` (rad/s) over `duration` (s), then constant.
    Ramp { from: f64, to: f64, duration: f64 },
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
    /// Number of coordinates.
    pub fn size(&self) -> usize {
        self.mass.nrows()
    }

    /// Checks sizes and the nonlinear forces' coordinates.
    pub fn check(&self) -> Result<()> {
        let n = self.size();
        let square = |m: &Mat<f64>| m.nrows() == n && m.ncols() == n;
        if !(square(&self.stiffness) && square(&self.damping) && square(&self.gyroscopic))
            || self.constant_force.len() != n
            || self.unbalance_re.len() != n
            || self.unbalance_im.len() != n
        {
            return Err(Error::Numerical(
                "time problem matrices and vectors differ in size".into(),
            ));
        }
        for f in &self.nonlinear {
            if let Some(&d) = f.dofs().iter().find(|&&d| d >= n) {
                return Err(Error::Numerical(format!(
                    "{} acts on coordinate {d} of {n}",
                    f.name()
                )));
            }
        }
        Ok(())
    }

    /// Linear external force at time t (gravity and unbalance) into `out`.
    pub fn external_force(&self, t: f64, out: &mut [f64]) -> Kinematics {
        let (k, accel) = self.speed.at(t);
        let (s, c) = k.angle.sin_cos();
        let w2 = k.speed * k.speed;
        for i in 0..out.len() {
            let (fr, fi) = (self.unbalance_re[i], self.unbalance_im[i]);
            // Re(f (w^2 - i w') e^{i phi}) = w^2 Re(f e^{i phi}) + w' Im(f e^{i phi}).
            let re = fr * c - fi * s;
            let im = fr * s + fi * c;
            out[i] = self.constant_force[i] + w2 * re + accel * im;
        }
        k
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

/// A dense row-major matrix for the small products of the time-step loop, where a plain
/// loop over contiguous rows vectorises and has no call overhead.
#[derive(Debug, Clone)]
pub(crate) struct Dense {
    pub cols: usize,
    pub data: Vec<f64>,
}

impl Dense {
    pub fn from_mat(m: &Mat<f64>) -> Dense {
        let (rows, cols) = (m.nrows(), m.ncols());
        let mut data = Vec::with_capacity(rows * cols);
        for i in 0..rows {
            for j in 0..cols {
                data.push(m[(i, j)]);
            }
        }
        Dense { cols, data }
    }

    /// out += self * x.
    #[inline]
    pub fn mul_add(&self, x: &[f64], out: &mut [f64]) {
        for (row, o) in self.data.chunks_exact(self.cols).zip(out.iter_mut()) {
            *o += row.iter().zip(x).map(|(a, b)| a * b).sum::<f64>();
        }
    }
}
