//! Roller contacts as constraints enforced by Lagrange multipliers inside the central
//! difference (thesis eqs. 3.7-3.11, 4.6-4.9; forward-increment Lagrange multipliers,
//! Carpenter, Taylor & Katona 1991; docs/theory.md section 5).
//!
//! The central difference gives q_{n+1} = q^_{n+1} + S F_c with S = (M/h^2 + D/2h)^-1 and
//! q^ the prediction without contact. Every roller j is a constraint
//! delta_j = J_j q + d_j(t) <= 0 with J_j = (cos theta_j, sin theta_j) on its bearing's
//! (ux, uy) and d_j = -gamma - waviness. With contact forces F_c = -J^T lambda the
//! constraints at t_{n+1} read
//!
//! ```text
//! delta = delta^ - W lambda,   W = J S J^T,   lambda >= 0,   delta <= 0,   lambda_j delta_j = 0
//! ```
//!
//! solved by an active-set loop: rollers that penetrate join, rollers whose multiplier
//! would pull leave, until every multiplier is compressive and no roller penetrates beyond
//! round-off. W is small (rollers x rollers) and needs only the block of S on the
//! bearings' coordinates, so a step with contact costs little more than one without.
//!
//! Roller tilt and skew are slice effects of the Hertz law; with rigid constraints one
//! constraint per roller is kept and tilt and skew are ignored (waviness is kept).

use super::geometry::RollerGeometry;
use crate::error::{Error, Result};
use crate::model::RollerBearing;
use crate::time::{solve_small, Kinematics};

/// Most bearings one set of constraints handles.
const MAX_BEARINGS: usize = 32;

/// The rollers of several bearings as constraints on the integrator's coordinates.
#[derive(Debug, Clone)]
pub struct LagrangeContacts {
    bearings: Vec<ConstrainedBearing>,
    /// Coordinates of every bearing's (ux, uy), bearing after bearing.
    coordinates: Vec<usize>,
    /// Multipliers of the last step, N, roller after roller.
    lambda: Vec<f64>,
    /// Multipliers at every observed instant, one block of `rollers()` per instant.
    history: Vec<f64>,
    /// Largest penetration left after any correction, m.
    worst_penetration: f64,
    /// Most active-set iterations any step needed.
    most_iterations: usize,
    /// Work buffers of the complementarity solve.
    work: Work,
}

#[derive(Debug, Clone)]
struct ConstrainedBearing {
    name: String,
    geometry: RollerGeometry,
}

/// Buffers sized once, so a step allocates nothing.
#[derive(Debug, Clone, Default)]
struct Work {
    /// Constraint directions: per roller its (cos, sin) and its bearing.
    rows: Vec<(f64, f64, usize)>,
    offsets: Vec<f64>,
    predicted: Vec<f64>,
    w: Vec<f64>,
    active: Vec<bool>,
    system: Vec<f64>,
    rhs: Vec<f64>,
    index: Vec<usize>,
}

/// Outcome of one corrected step.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactStep {
    /// Rollers in contact.
    pub active: usize,
    /// Active-set iterations.
    pub iterations: usize,
    /// Largest remaining penetration, m (<= round-off).
    pub penetration: f64,
}

impl LagrangeContacts {
    /// Constraints for `bearings`, whose (ux, uy) are the coordinates `coordinates[2 b..2 b + 2]`.
    pub fn new(bearings: &[RollerBearing], coordinates: Vec<usize>) -> Result<Self> {
        if bearings.len() > MAX_BEARINGS {
            return Err(Error::Numerical(format!(
                "at most {MAX_BEARINGS} bearings can be constrained by Lagrange multipliers"
            )));
        }
        if coordinates.len() != 2 * bearings.len() {
            return Err(Error::Numerical(
                "each constrained bearing needs its (ux, uy) coordinates".into(),
            ));
        }
        let bearings: Vec<ConstrainedBearing> = bearings
            .iter()
            .map(|b| {
                let mut plain = b.clone();
                plain.roller_tilt = false;
                plain.slices = 1;
                plain.skew_angle = 0.0;
                ConstrainedBearing {
                    name: b.name.clone(),
                    geometry: RollerGeometry::new(&plain),
                }
            })
            .collect();
        let m: usize = bearings.iter().map(|b| b.geometry.rollers).sum();
        let work = Work {
            rows: vec![(0.0, 0.0, 0); m],
            offsets: vec![0.0; m],
            predicted: vec![0.0; m],
            w: vec![0.0; m * m],
            active: vec![false; m],
            system: vec![0.0; m * m],
            rhs: vec![0.0; m],
            index: vec![0; m],
        };
        Ok(LagrangeContacts {
            bearings,
            coordinates,
            lambda: vec![0.0; m],
            history: Vec::new(),
            worst_penetration: f64::NEG_INFINITY,
            most_iterations: 0,
            work,
        })
    }

    /// The coordinates the constraints act on (each bearing's ux, uy).
    pub fn coordinates(&self) -> &[usize] {
        &self.coordinates
    }

    /// Number of rollers over all bearings.
    pub fn rollers(&self) -> usize {
        self.lambda.len()
    }

    /// Bearing names, in order.
    pub fn names(&self) -> Vec<String> {
        self.bearings.iter().map(|b| b.name.clone()).collect()
    }

    /// Contact forces (multipliers) of the last step, N, roller after roller.
    pub fn multipliers(&self) -> &[f64] {
        &self.lambda
    }

    /// Clears the record and reserves room for `steps` instants.
    pub fn start_recording(&mut self, steps: usize) {
        self.history = Vec::with_capacity(steps * self.rollers());
        self.lambda.iter_mut().for_each(|l| *l = 0.0);
        self.worst_penetration = f64::NEG_INFINITY;
        self.most_iterations = 0;
    }

    /// Appends the current multipliers (those acting at the instant being observed).
    pub fn record(&mut self) {
        self.history.extend_from_slice(&self.lambda);
    }

    /// Recorded multipliers, N: instant after instant, roller after roller.
    pub fn history(&self) -> &[f64] {
        &self.history
    }

    /// Largest penetration after correction over the run, m (round-off when it worked).
    pub fn largest_penetration(&self) -> f64 {
        self.worst_penetration
    }

    /// Most active-set iterations a step needed.
    pub fn most_iterations(&self) -> usize {
        self.most_iterations
    }

    /// Corrects the predicted `q` (all coordinates) at instant `at` so that no roller
    /// penetrates. `s_block` is S restricted to `coordinates()` (row-major c x c) and
    /// `s_columns(c, out)` adds column `c` of S (in `coordinates()` order) times a factor:
    /// the caller owns S and its storage.
    pub fn correct(
        &mut self,
        at: &Kinematics,
        q: &mut [f64],
        s_block: &[f64],
        mut add_column: impl FnMut(usize, f64, &mut [f64]),
    ) -> Result<ContactStep> {
        self.constraint_rows(at);
        let m = self.rollers();
        let c = self.coordinates.len();
        let w = &mut self.work;
        let mut any = false;
        for j in 0..m {
            let (cs, sn, b) = w.rows[j];
            let (ix, iy) = (self.coordinates[2 * b], self.coordinates[2 * b + 1]);
            w.predicted[j] = cs * q[ix] + sn * q[iy] + w.offsets[j];
            any |= w.predicted[j] > 0.0;
        }
        self.lambda.iter_mut().for_each(|l| *l = 0.0);
        if !any {
            return Ok(ContactStep {
                active: 0,
                iterations: 0,
                penetration: w.predicted.iter().fold(f64::NEG_INFINITY, |a, &d| a.max(d)),
            });
        }
        // W = J S J^T through the 2x2 blocks of S between bearings.
        for a in 0..m {
            let (ca, sa, ba) = w.rows[a];
            for b in 0..m {
                let (cb, sb, bb) = w.rows[b];
                let s = |i: usize, k: usize| s_block[(2 * ba + i) * c + 2 * bb + k];
                w.w[a * m + b] =
                    ca * (s(0, 0) * cb + s(0, 1) * sb) + sa * (s(1, 0) * cb + s(1, 1) * sb);
            }
        }
        let scale = w.predicted.iter().fold(0.0f64, |a, &d| a.max(d.abs()));
        let iterations = solve_complementarity(w, &mut self.lambda, 1e-10 * scale)?;
        // q -= S J^T lambda, J^T lambda gathered per coordinate first (on the stack: `new`
        // admits at most MAX_BEARINGS bearings).
        let mut push = [0.0; 2 * MAX_BEARINGS];
        let per_coordinate = &mut push[..c];
        for j in 0..m {
            let (cs, sn, b) = w.rows[j];
            per_coordinate[2 * b] += cs * self.lambda[j];
            per_coordinate[2 * b + 1] += sn * self.lambda[j];
        }
        for (k, &f) in per_coordinate.iter().enumerate() {
            if f != 0.0 {
                add_column(k, -f, q);
            }
        }
        let mut penetration = f64::NEG_INFINITY;
        let mut active = 0;
        for j in 0..m {
            let (cs, sn, b) = w.rows[j];
            let (ix, iy) = (self.coordinates[2 * b], self.coordinates[2 * b + 1]);
            penetration = penetration.max(cs * q[ix] + sn * q[iy] + w.offsets[j]);
            active += usize::from(self.lambda[j] > 0.0);
        }
        self.worst_penetration = self.worst_penetration.max(penetration);
        self.most_iterations = self.most_iterations.max(iterations);
        Ok(ContactStep {
            active,
            iterations,
            penetration,
        })
    }

    /// Directions and offsets of every roller's constraint at `at`.
    fn constraint_rows(&mut self, at: &Kinematics) {
        let mut row = 0;
        for (b, bearing) in self.bearings.iter().enumerate() {
            let w = &mut self.work;
            bearing.geometry.for_each_slice(at, |slice| {
                let (s, c) = slice.sin_cos;
                w.rows[row] = (c, s, b);
                w.offsets[row] = slice.offset;
                row += 1;
            });
        }
    }
}

/// Finds lambda >= 0 with delta = predicted - W lambda <= tol and lambda_j delta_j = 0 by
/// an active-set loop; returns the iterations used.
fn solve_complementarity(w: &mut Work, lambda: &mut [f64], tol: f64) -> Result<usize> {
    let m = lambda.len();
    for j in 0..m {
        w.active[j] = w.predicted[j] > 0.0;
    }
    for iteration in 1..=4 * m + 10 {
        solve_active(w, lambda)?;
        // A pulling multiplier leaves the set (the most negative first).
        let pulling = (0..m)
            .filter(|&j| w.active[j] && lambda[j] < 0.0)
            .min_by(|&a, &b| lambda[a].total_cmp(&lambda[b]));
        if let Some(j) = pulling {
            w.active[j] = false;
            continue;
        }
        // A penetrating free roller joins (the deepest first).
        let mut deepest = None;
        let mut depth = tol;
        for j in (0..m).filter(|&j| !w.active[j]) {
            let delta = w.predicted[j] - (0..m).map(|k| w.w[j * m + k] * lambda[k]).sum::<f64>();
            if delta > depth {
                depth = delta;
                deepest = Some(j);
            }
        }
        match deepest {
            Some(j) => w.active[j] = true,
            None => return Ok(iteration),
        }
    }
    Err(Error::Numerical(
        "the Lagrange-multiplier contact did not settle on an active set; reduce the time step"
            .into(),
    ))
}

/// Solves W_aa lambda_a = predicted_a on the active set (Gaussian elimination with partial
/// pivoting in preallocated buffers); inactive multipliers are zero.
fn solve_active(w: &mut Work, lambda: &mut [f64]) -> Result<()> {
    let m = lambda.len();
    let mut k = 0;
    for j in 0..m {
        lambda[j] = 0.0;
        if w.active[j] {
            w.index[k] = j;
            k += 1;
        }
    }
    for a in 0..k {
        for b in 0..k {
            w.system[a * k + b] = w.w[w.index[a] * m + w.index[b]];
        }
        w.rhs[a] = w.predicted[w.index[a]];
    }
    let (a, rhs) = (&mut w.system[..k * k], &mut w.rhs[..k]);
    solve_small(a, rhs);
    if rhs.iter().any(|x| !x.is_finite()) {
        return Err(Error::Numerical(
            "dependent roller constraints in the Lagrange-multiplier contact".into(),
        ));
    }
    for a in 0..k {
        lambda[w.index[a]] = rhs[a];
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn complementarity_on_a_small_problem() {
        // Two rollers on one coordinate pair: W = [[2, 1], [1, 2]], predicted (3, -3).
        // Both active would give lambda = (3, -3): the second pulls, leaves; then
        // lambda_1 = 1.5 and delta_2 = -3 - 1.5 < 0.
        let mut w = Work {
            rows: vec![(1.0, 0.0, 0); 2],
            offsets: vec![0.0; 2],
            predicted: vec![3.0, -3.0],
            w: vec![2.0, 1.0, 1.0, 2.0],
            active: vec![false; 2],
            system: vec![0.0; 4],
            rhs: vec![0.0; 2],
            index: vec![0; 2],
        };
        let mut lambda = vec![0.0; 2];
        solve_complementarity(&mut w, &mut lambda, 1e-12).unwrap();
        assert!(
            (lambda[0] - 1.5).abs() < 1e-15 && lambda[1] == 0.0,
            "{lambda:?}"
        );
    }
}
