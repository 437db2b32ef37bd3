//! A bearing between the shaft and a housing: its force depends on the shaft's motion
//! relative to the housing's, and acts on both, opposite ([`Housed`]).
//!
//! Every bearing law computes its force from its node's [ux, uy] (and [tx, ty] with roller
//! tilt) as if the outer side stood still; mounted in a housing, the same law sees the
//! relative translations u_shaft - u_housing (the housing does not tilt, see
//! [`crate::model::Housing`]), the shaft receives F and the housing -F on its translations.
//! With T the map from the coordinates [shaft..., housing x, y] to the law's, the
//! Jacobian is T^T-like: dF/dq = S J T with S = [I; -I_2 0].

use crate::error::Result;
use crate::force::{Kinematics, NonlinearForce};
use crate::model::Model;

/// A bearing law acting between its shaft coordinates and a housing's [ux, uy].
pub struct Housed {
    law: Box<dyn NonlinearForce>,
    /// The law's coordinates, then the housing's two.
    dofs: Vec<usize>,
    /// The law's state (relative), force and Jacobians: work buffers.
    q: Vec<f64>,
    v: Vec<f64>,
    f: Vec<f64>,
    jq: Vec<f64>,
    jv: Vec<f64>,
}

impl Housed {
    /// `law` (whose first two coordinates are the shaft's ux and uy) mounted in a housing
    /// whose [ux, uy] are coordinates `housing`.
    pub fn new(law: Box<dyn NonlinearForce>, housing: [usize; 2]) -> Housed {
        let m = law.dofs().len();
        let mut dofs = law.dofs().to_vec();
        dofs.extend(housing);
        Housed {
            law,
            dofs,
            q: vec![0.0; m],
            v: vec![0.0; m],
            f: vec![0.0; m],
            jq: vec![0.0; m * m],
            jv: vec![0.0; m * m],
        }
    }

    /// The law's own coordinate count.
    fn m(&self) -> usize {
        self.q.len()
    }

    /// The relative state into the work buffers.
    fn relative(&mut self, q: &[f64], v: &[f64]) {
        let m = self.m();
        self.q.copy_from_slice(&q[..m]);
        self.v.copy_from_slice(&v[..m]);
        for k in 0..2 {
            self.q[k] -= q[m + k];
            self.v[k] -= v[m + k];
        }
    }

    /// The law's force on the shaft, and its opposite on the housing.
    fn spread_force(&self, out: &mut [f64]) {
        let m = self.m();
        out[..m].copy_from_slice(&self.f);
        out[m] = -self.f[0];
        out[m + 1] = -self.f[1];
    }
}

/// The full Jacobian (row-major, (m + 2) squared) of a law's `j` (m squared) between a
/// shaft and a housing: rows and columns of the housing's x and y are minus the law's.
fn spread_jacobian(j: &[f64], m: usize, out: &mut [f64]) {
    let n = m + 2;
    let sign = |a: usize| if a < m { 1.0 } else { -1.0 };
    let law = |a: usize| if a < m { a } else { a - m };
    for r in 0..n {
        for c in 0..n {
            out[r * n + c] = sign(r) * sign(c) * j[law(r) * m + law(c)];
        }
    }
}

impl NonlinearForce for Housed {
    fn name(&self) -> String {
        self.law.name()
    }
    fn dofs(&self) -> &[usize] {
        &self.dofs
    }
    fn force(&mut self, at: &Kinematics, q: &[f64], v: &[f64], out: &mut [f64]) {
        self.relative(q, v);
        self.law.force(at, &self.q, &self.v, &mut self.f);
        self.spread_force(out);
    }
    fn jacobian(
        &mut self,
        at: &Kinematics,
        q: &[f64],
        v: &[f64],
        dfdq: &mut [f64],
        dfdv: &mut [f64],
    ) {
        self.relative(q, v);
        self.law
            .jacobian(at, &self.q, &self.v, &mut self.jq, &mut self.jv);
        let m = self.m();
        spread_jacobian(&self.jq, m, dfdq);
        spread_jacobian(&self.jv, m, dfdv);
    }
    fn force_and_jacobian(
        &mut self,
        at: &Kinematics,
        q: &[f64],
        v: &[f64],
        out: &mut [f64],
        dfdq: &mut [f64],
        dfdv: &mut [f64],
    ) {
        self.relative(q, v);
        self.law.force_and_jacobian(
            at,
            &self.q,
            &self.v,
            &mut self.f,
            &mut self.jq,
            &mut self.jv,
        );
        self.spread_force(out);
        let m = self.m();
        spread_jacobian(&self.jq, m, dfdq);
        spread_jacobian(&self.jv, m, dfdv);
    }
    fn stiffness_bound(&self) -> Vec<f64> {
        let m = self.m();
        let mut out = vec![0.0; (m + 2) * (m + 2)];
        spread_jacobian(&self.law.stiffness_bound(), m, &mut out);
        out
    }
}

/// `law` as it acts in `model`: alone for a bearing on the ground (`housing` `None`), or
/// between the shaft and housing `housing` (its DOFs mapped to coordinates by
/// `coordinate`).
///
/// # Errors
/// [`crate::error::Error::Unsupported`] when `coordinate` does not keep the housing's DOFs.
pub fn mounted(
    model: &Model,
    housing: Option<usize>,
    law: Box<dyn NonlinearForce>,
    coordinate: &dyn Fn(usize) -> Option<usize>,
) -> Result<Box<dyn NonlinearForce>> {
    let Some(h) = housing else { return Ok(law) };
    let [x, y] = model.housing_dofs(h).map(coordinate);
    match (x, y) {
        (Some(x), Some(y)) => Ok(Box::new(Housed::new(law, [x, y]))),
        _ => Err(crate::error::Error::Unsupported(format!(
            "{}: the DOFs of housing \"{}\" are not kept by the reduction; they must be \
             boundary DOFs",
            law.name(),
            model.housings[h].name
        ))),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::force::LinearSupport;

    /// A linear bearing mounted in a housing is the assembled support's block
    /// [[K, -K], [-K, K]], and its force -K (u_s - u_h) on the shaft, the opposite on the
    /// housing: exact arithmetic on these numbers.
    #[test]
    fn a_housed_linear_support_acts_on_the_relative_motion() {
        let k = [[3.0, 0.5], [-0.25, 2.0]];
        let c = [[0.1, 0.0], [0.0, 0.2]];
        let law = LinearSupport::new("s", [4, 5], k, c);
        let mut housed = Housed::new(Box::new(law), [9, 10]);
        assert_eq!(housed.dofs(), &[4, 5, 9, 10]);
        let at = Kinematics {
            time: 0.0,
            speed: 0.0,
            angle: 0.0,
        };
        let q = [1.0, 2.0, 0.5, -1.0];
        let v = [0.0, 1.0, 2.0, 0.0];
        let mut f = [0.0; 4];
        housed.force(&at, &q, &v, &mut f);
        let rel = [0.5, 3.0];
        let vrel = [-2.0, 1.0];
        for i in 0..2 {
            let expected: f64 = -(0..2)
                .map(|j| k[i][j] * rel[j] + c[i][j] * vrel[j])
                .sum::<f64>();
            assert_eq!(f[i], expected);
            assert_eq!(f[i + 2], -expected);
        }
        let (mut jq, mut jv) = ([0.0; 16], [0.0; 16]);
        housed.jacobian(&at, &q, &v, &mut jq, &mut jv);
        for r in 0..4 {
            for col in 0..4 {
                let s = if (r < 2) == (col < 2) { 1.0 } else { -1.0 };
                assert_eq!(jq[r * 4 + col], -s * k[r % 2][col % 2]);
                assert_eq!(jv[r * 4 + col], -s * c[r % 2][col % 2]);
            }
        }
    }
}
