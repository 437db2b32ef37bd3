//! The nonlinear-force interface every solver uses (thesis eq. 2.4, F_nl(q, q', t)): the
//! time integrators, the static solver and harmonic balance see forces only through
//! [`NonlinearForce`], and the contact laws of [`crate::bearing`] implement it.
//!
//! A force acts on a few named coordinates of the solver (physical DOFs of the full
//! model, or boundary DOFs of a Craig-Bampton model, which are physical too). It gives its
//! value and its Jacobian at given displacement, velocity and time, so explicit methods use
//! the value and implicit methods and the static solver use the Jacobian as well.
//! Linear supports and a cubic spring implement it here; a [`ForceBuilder`] makes the
//! forces of a model once the solver's coordinates are known.

use crate::error::Result;
use crate::model::Model;

/// Spin kinematics at an instant.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Kinematics {
    /// Time, s.
    pub time: f64,
    /// Spin speed, rad/s.
    pub speed: f64,
    /// Spin angle (integral of the speed), rad.
    pub angle: f64,
}

/// A force that depends on the motion of a few coordinates.
pub trait NonlinearForce: Send {
    /// A name for messages and outputs.
    fn name(&self) -> String;
    /// The coordinates it acts on; `force` and `jacobian` use this order.
    fn dofs(&self) -> &[usize];
    /// Force on the rotor at those coordinates, given their displacements `q` and
    /// velocities `v` (both in `dofs()` order).
    fn force(&mut self, at: &Kinematics, q: &[f64], v: &[f64], out: &mut [f64]);
    /// Jacobians dF/dq and dF/dv, row-major `dofs().len()` squared. The tangent stiffness
    /// is -dF/dq and the tangent damping -dF/dv.
    fn jacobian(
        &mut self,
        at: &Kinematics,
        q: &[f64],
        v: &[f64],
        dfdq: &mut [f64],
        dfdv: &mut [f64],
    );
    /// [`Self::force`] and [`Self::jacobian`] at one state, the same values as the two
    /// calls: for a caller that needs both (the harmonic balance evaluates its residual
    /// and then its Jacobian at each Newton iterate). A force whose law is costly
    /// evaluates it once for both.
    fn force_and_jacobian(
        &mut self,
        at: &Kinematics,
        q: &[f64],
        v: &[f64],
        out: &mut [f64],
        dfdq: &mut [f64],
        dfdv: &mut [f64],
    ) {
        self.force(at, q, v, out);
        self.jacobian(at, q, v, dfdq, dfdv);
    }
    /// The largest tangent stiffness -dF/dq expected during a run (row-major), used for the
    /// explicit stability limit.
    fn stiffness_bound(&self) -> Vec<f64>;
}

/// A linear support on (ux, uy): F = -K u - C v.
#[derive(Debug, Clone)]
pub struct LinearSupport {
    name: String,
    dofs: [usize; 2],
    stiffness: [[f64; 2]; 2],
    damping: [[f64; 2]; 2],
}

impl LinearSupport {
    /// A support on coordinates `dofs` = [ux, uy].
    pub fn new(
        name: impl Into<String>,
        dofs: [usize; 2],
        stiffness: [[f64; 2]; 2],
        damping: [[f64; 2]; 2],
    ) -> Self {
        LinearSupport {
            name: name.into(),
            dofs,
            stiffness,
            damping,
        }
    }
}

impl NonlinearForce for LinearSupport {
    fn name(&self) -> String {
        self.name.clone()
    }
    fn dofs(&self) -> &[usize] {
        &self.dofs
    }
    fn force(&mut self, _: &Kinematics, q: &[f64], v: &[f64], out: &mut [f64]) {
        for i in 0..2 {
            out[i] = -(0..2)
                .map(|j| self.stiffness[i][j] * q[j] + self.damping[i][j] * v[j])
                .sum::<f64>();
        }
    }
    fn jacobian(
        &mut self,
        _: &Kinematics,
        _: &[f64],
        _: &[f64],
        dfdq: &mut [f64],
        dfdv: &mut [f64],
    ) {
        for i in 0..2 {
            for j in 0..2 {
                dfdq[2 * i + j] = -self.stiffness[i][j];
                dfdv[2 * i + j] = -self.damping[i][j];
            }
        }
    }
    fn stiffness_bound(&self) -> Vec<f64> {
        vec![
            self.stiffness[0][0],
            self.stiffness[0][1],
            self.stiffness[1][0],
            self.stiffness[1][1],
        ]
    }
}

/// A hardening spring on one coordinate: F = -k1 u - k3 u^3 (the Duffing nonlinearity),
/// used to test integrators on a smooth nonlinearity.
#[derive(Debug, Clone)]
pub struct CubicSpring {
    dof: [usize; 1],
    linear: f64,
    cubic: f64,
    /// Largest |u| expected, for the stability bound.
    reach: f64,
}

impl CubicSpring {
    /// A spring on coordinate `dof`; `reach` is the largest displacement expected.
    pub fn new(dof: usize, linear: f64, cubic: f64, reach: f64) -> Self {
        CubicSpring {
            dof: [dof],
            linear,
            cubic,
            reach,
        }
    }
}

impl NonlinearForce for CubicSpring {
    fn name(&self) -> String {
        format!("cubic spring on coordinate {}", self.dof[0])
    }
    fn dofs(&self) -> &[usize] {
        &self.dof
    }
    fn force(&mut self, _: &Kinematics, q: &[f64], _: &[f64], out: &mut [f64]) {
        out[0] = -self.linear * q[0] - self.cubic * q[0].powi(3);
    }
    fn jacobian(
        &mut self,
        _: &Kinematics,
        q: &[f64],
        _: &[f64],
        dfdq: &mut [f64],
        dfdv: &mut [f64],
    ) {
        dfdq[0] = -self.linear - 3.0 * self.cubic * q[0] * q[0];
        dfdv[0] = 0.0;
    }
    fn stiffness_bound(&self) -> Vec<f64> {
        vec![self.linear + 3.0 * self.cubic.max(0.0) * self.reach * self.reach]
    }
}

/// Builds the nonlinear forces of a model, given how physical DOFs map to the solver's
/// coordinates (`None` for a DOF the solver does not keep).
pub type ForceBuilder<'a> =
    &'a dyn Fn(&Model, &dyn Fn(usize) -> Option<usize>) -> Result<Vec<Box<dyn NonlinearForce>>>;

/// The force builder of a model without nonlinear forces.
///
/// # Errors
/// None: it returns no forces; the `Result` is that of a [`ForceBuilder`].
pub fn no_forces(
    _: &Model,
    _: &dyn Fn(usize) -> Option<usize>,
) -> Result<Vec<Box<dyn NonlinearForce>>> {
    Ok(Vec::new())
}
