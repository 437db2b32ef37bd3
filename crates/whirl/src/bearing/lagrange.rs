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
//! a linear complementarity problem solved exactly by Lemke's pivoting (see
//! `solve_complementarity` for why not an active-set loop). W is small (rollers x rollers) and needs only the block of S on the
//! bearings' coordinates, so a step with contact costs little more than one without.
//!
//! Roller tilt and skew are slice effects of the Hertz law; a rigid roller is one
//! constraint, so a model asking for either is refused (waviness is kept).

use super::geometry::RollerGeometry;
use crate::error::{Error, InputError, Result};
use crate::force::Kinematics;
use crate::model::RollerBearing;

/// Most bearings one set of constraints handles.
const MAX_BEARINGS: usize = 32;

/// Lemke's method ends in a handful of pivots per roller in contact; a solve that needs
/// more than this many per roller is cycling on round-off and is stopped.
const MAX_PIVOTS_PER_ROLLER: usize = 8;

/// Entries of a pivot column below this fraction of its largest are round-off of an entry
/// that is zero (the tableau is scaled to order one).
const PIVOT_TOLERANCE: f64 = 1e-11;

/// Ratios within this relative distance are ties (round-off of equal ratios).
const RATIO_TIE: f64 = 1e-10;

/// A roller outside the problem that the correction pushes in by more than this fraction
/// of the deepest penetration joins it; below that it is round-off of a roller that
/// touches without load.
const PUSHED_IN: f64 = 1e-9;

/// The rollers of several bearings as constraints on the integrator's coordinates.
#[derive(Debug, Clone)]
pub struct LagrangeContacts {
    bearings: Vec<ConstrainedBearing>,
    /// Coordinates of every bearing's (ux, uy), bearing after bearing.
    coordinates: Vec<usize>,
    /// Multipliers of the last step, N, roller after roller.
    lambda: Vec<f64>,
    /// Multipliers at every observed instant, one block of `rollers()` per instant, when
    /// kept (`keep_history`).
    history: Vec<f64>,
    /// Whether `record` keeps the multipliers: only a run that reports per-roller forces
    /// reads them, and a cascade's runs would hold 0.5 kB a step for nothing.
    keeping: bool,
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

/// Roller tilt and skew act through slices of the Hertz law; a rigid roller is one
/// constraint, so a model that asks for either is refused rather than run without it.
fn refuse_slice_effects(bearings: &[RollerBearing]) -> Result<()> {
    for (i, b) in bearings.iter().enumerate() {
        let effect = if b.roller_tilt {
            Some(("roller_tilt", "roller_tilt = false"))
        } else if b.skew_angle != 0.0 {
            Some(("skew_angle", "skew_angle = 0"))
        } else {
            None
        };
        if let Some((field, off)) = effect {
            return Err(InputError::field(
                format!("roller_bearing[{i}].{field}"),
                format!(
                    "bearing '{}': Lagrange-multiplier contacts hold each roller as one rigid \
                     constraint and cannot model {}",
                    b.name,
                    field.replace('_', " ")
                ),
            )
            .help(format!(
                "use the Hertz contact law (`--contact hertz`), which slices the rollers, or set \
                 {off} to run rigid rollers"
            ))
            .into());
        }
    }
    Ok(())
}

/// Buffers sized once, so a step allocates nothing.
#[derive(Debug, Clone, Default)]
struct Work {
    /// Constraint directions: per roller its (cos, sin) and its bearing.
    rows: Vec<(f64, f64, usize)>,
    offsets: Vec<f64>,
    /// Every roller's approach before the correction, m.
    approach: Vec<f64>,
    /// The rollers of the complementarity problem: those that penetrate before the
    /// correction, and any the correction would push in.
    set: Vec<usize>,
    /// W on `set` (k x k, row-major).
    w: Vec<f64>,
    /// The approach of the rollers of `set`.
    predicted: Vec<f64>,
    /// Lemke's tableau, k x (2 k + 2), row-major.
    tableau: Vec<f64>,
    /// The basic variable of each tableau row.
    basis: Vec<usize>,
    /// The multipliers of the rollers of `set`.
    lambda: Vec<f64>,
}

impl Work {
    /// Buffers for `m` rollers.
    fn sized(m: usize) -> Self {
        Work {
            rows: vec![(0.0, 0.0, 0); m],
            offsets: vec![0.0; m],
            approach: vec![0.0; m],
            set: Vec::with_capacity(m),
            w: vec![0.0; m * m],
            predicted: vec![0.0; m],
            tableau: vec![0.0; m * (2 * m + 2)],
            basis: vec![0; m],
            lambda: vec![0.0; m],
        }
    }

    /// J_a S, roller a's direction through S (`s_block`, c x c; not symmetric at speed,
    /// where D holds the gyroscopic matrix).
    fn row_through_s(&self, s_block: &[f64], c: usize, a: usize) -> [f64; 2 * MAX_BEARINGS] {
        let (ca, sa, ba) = self.rows[a];
        let mut motion = [0.0; 2 * MAX_BEARINGS];
        for (l, x) in motion[..c].iter_mut().enumerate() {
            *x = ca * s_block[2 * ba * c + l] + sa * s_block[(2 * ba + 1) * c + l];
        }
        motion
    }

    /// J^T lambda: the rollers' `(roller, multiplier)` gathered on their bearings'
    /// coordinates (on the stack: `new` admits at most `MAX_BEARINGS` bearings).
    fn bearing_loads(
        &self,
        rollers: impl Iterator<Item = (usize, f64)>,
    ) -> [f64; 2 * MAX_BEARINGS] {
        let mut load = [0.0; 2 * MAX_BEARINGS];
        for (j, lambda) in rollers {
            let (cs, sn, b) = self.rows[j];
            load[2 * b] += cs * lambda;
            load[2 * b + 1] += sn * lambda;
        }
        load
    }

    /// Solves the complementarity problem on `set`; returns the pivots used.
    fn solve_set(&mut self, s_block: &[f64], c: usize) -> Result<usize> {
        // Row a of W = J S J^T: J_a S once, then its component along each roller.
        let k = self.set.len();
        for a in 0..k {
            let row = self.row_through_s(s_block, c, self.set[a]);
            for b in 0..k {
                let (cs, sn, bearing) = self.rows[self.set[b]];
                self.w[a * k + b] = cs * row[2 * bearing] + sn * row[2 * bearing + 1];
            }
            self.predicted[a] = self.approach[self.set[a]];
        }
        solve_complementarity(self, k)
    }

    /// Adds to `set` every roller outside it that the correction pushes in beyond
    /// `tolerance`; returns whether any was added.
    fn add_pushed_in(&mut self, s_block: &[f64], c: usize, tolerance: f64) -> bool {
        // (W lambda)_j = J_j S (J^T lambda): the correction's motion of the bearings once,
        // then each roller's share of it, rather than a row of W per roller.
        let k = self.set.len();
        let load = self.bearing_loads(
            self.set
                .iter()
                .copied()
                .zip(self.lambda[..k].iter().copied()),
        );
        let mut motion = [0.0; 2 * MAX_BEARINGS];
        for (i, x) in motion[..c].iter_mut().enumerate() {
            *x = (0..c).map(|l| s_block[i * c + l] * load[l]).sum();
        }
        let mut added = false;
        for j in 0..self.approach.len() {
            if self.set[..k].contains(&j) {
                continue;
            }
            let (cs, sn, b) = self.rows[j];
            let pushed = cs * motion[2 * b] + sn * motion[2 * b + 1];
            if self.approach[j] - pushed > tolerance {
                self.set.push(j);
                added = true;
            }
        }
        added
    }
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
    ///
    /// # Errors
    /// [`Error::Unsupported`] for more than `MAX_BEARINGS` bearings; [`Error::InvalidOption`]
    /// when `coordinates` does not hold two per bearing; [`Error::Input`] naming
    /// `roller_bearing[i].roller_tilt` or `.skew_angle` for a bearing with roller tilt or skew,
    /// which one rigid constraint per roller cannot model; [`Error::Unsupported`] for a ball
    /// bearing under an axial load.
    pub fn new(bearings: &[RollerBearing], coordinates: Vec<usize>) -> Result<Self> {
        if bearings.len() > MAX_BEARINGS {
            return Err(Error::Unsupported(format!(
                "at most {MAX_BEARINGS} bearings can be constrained by Lagrange multipliers"
            )));
        }
        if coordinates.len() != 2 * bearings.len() {
            return Err(Error::InvalidOption(
                "each constrained bearing needs its (ux, uy) coordinates".into(),
            ));
        }
        refuse_slice_effects(bearings)?;
        if let Some(b) = bearings
            .iter()
            .find(|b| b.ball.as_ref().is_some_and(|c| c.axial_load > 0.0))
        {
            return Err(Error::Unsupported(format!(
                "{}: rigid balls under an axial load have no contact angle (it follows from                  the balls' deflection); use the Hertz contact law for this bearing",
                b.name
            )));
        }
        let bearings: Vec<ConstrainedBearing> = bearings
            .iter()
            .map(|b| ConstrainedBearing {
                name: b.name.clone(),
                geometry: RollerGeometry::new(b),
            })
            .collect();
        let m: usize = bearings.iter().map(|b| b.geometry.rollers).sum();
        let work = Work::sized(m);
        Ok(LagrangeContacts {
            bearings,
            coordinates,
            lambda: vec![0.0; m],
            history: Vec::new(),
            keeping: false,
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

    /// Makes `record` keep the multipliers, for `history`.
    pub fn keep_history(&mut self) {
        self.keeping = true;
    }

    /// Clears the record and, when the history is kept, reserves room for `steps` instants.
    pub fn start_recording(&mut self, steps: usize) {
        self.history = Vec::with_capacity(if self.keeping {
            steps * self.rollers()
        } else {
            0
        });
        self.lambda.iter_mut().for_each(|l| *l = 0.0);
        self.worst_penetration = f64::NEG_INFINITY;
        self.most_iterations = 0;
    }

    /// Appends the current multipliers (those acting at the instant being observed) when
    /// the history is kept.
    pub fn record(&mut self) {
        if self.keeping {
            self.history.extend_from_slice(&self.lambda);
        }
    }

    /// Recorded multipliers, N: instant after instant, roller after roller (empty unless
    /// `keep_history` was called).
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
    ///
    /// # Errors
    /// [`Error::Singular`] when a penetrating roller has no compliance (S restricted to
    /// the contacts is zero or not finite); [`Error::NotConverged`] when the
    /// complementarity problem has no solution or is not solved within its pivot limit.
    /// Both messages suggest a shorter step.
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
        w.set.clear();
        let mut deepest = f64::NEG_INFINITY;
        for j in 0..m {
            let (cs, sn, b) = w.rows[j];
            let (ix, iy) = (self.coordinates[2 * b], self.coordinates[2 * b + 1]);
            w.approach[j] = cs * q[ix] + sn * q[iy] + w.offsets[j];
            deepest = deepest.max(w.approach[j]);
            if w.approach[j] > 0.0 {
                w.set.push(j);
            }
        }
        self.lambda.iter_mut().for_each(|l| *l = 0.0);
        if w.set.is_empty() {
            return Ok(ContactStep {
                active: 0,
                iterations: 0,
                penetration: deepest,
            });
        }
        // Only the rollers that penetrate enter the problem (two to five of a bearing's,
        // against all of them): a roller the correction would push in joins, and the
        // problem is solved again, so the answer is that of the problem on every roller.
        let mut iterations = w.solve_set(s_block, c)?;
        while w.add_pushed_in(s_block, c, PUSHED_IN * deepest) {
            iterations += w.solve_set(s_block, c)?;
        }
        for (a, &j) in w.set.iter().enumerate() {
            self.lambda[j] = w.lambda[a];
        }
        // q -= S J^T lambda, J^T lambda gathered per coordinate first.
        let load = w.bearing_loads(w.set.iter().map(|&j| (j, self.lambda[j])));
        for (k, &f) in load[..c].iter().enumerate() {
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

/// Finds lambda >= 0 with delta = predicted - W lambda <= 0 and lambda_j delta_j = 0, the
/// linear complementarity problem s = W lambda - predicted >= 0, by Lemke's complementary
/// pivoting (Cottle, Pang & Stone, *The Linear Complementarity Problem*, 1992, sec. 4.4);
/// returns the pivots used.
///
/// W = J S J^T has rank two per bearing (each bearing moves in a plane), so three rollers
/// of one bearing in contact make any square active-set system singular; an active-set
/// loop then fails or cycles. Lemke's method needs no such solve: it pivots on a tableau and
/// ends at a vertex, for a matrix with a positive semidefinite symmetric part (W is S's
/// block seen through the roller directions, and M/h^2 dominates S^-1). Where three
/// rollers share the load, the split between them is not unique but W lambda, and so the
/// corrected motion, is. Ties in the ratio test are broken lexicographically, which rules
/// out cycling on the degenerate vertices that the rank deficiency produces.
fn solve_complementarity(w: &mut Work, m: usize) -> Result<usize> {
    // Scaled so that the tableau's entries are of order one: W by its largest diagonal
    // entry, the approaches by the deepest one.
    let w_scale = (0..m).fold(0.0f64, |a, j| a.max(w.w[j * m + j].abs()));
    let p_scale = w.predicted[..m].iter().fold(0.0f64, |a, &d| a.max(d.abs()));
    w.lambda[..m].iter_mut().for_each(|l| *l = 0.0);
    if w_scale <= 0.0 || p_scale <= 0.0 || !w_scale.is_finite() || !p_scale.is_finite() {
        return Err(Error::singular(
            "contact compliance",
            "the Lagrange-multiplier contact met a roller with no compliance; reduce the time \
             step"
                .into(),
        ));
    }
    let t = Tableau::new(w, m, w_scale, p_scale);
    let pivots = t.solve(w, m)?;
    for row in 0..m {
        let var = w.basis[row];
        if (m..2 * m).contains(&var) {
            w.lambda[var - m] = t.at(w, row, t.rhs).max(0.0) * p_scale / w_scale;
        }
    }
    Ok(pivots)
}

/// Column layout of Lemke's tableau I s - W z - e z0 = q (q = -predicted, scaled): the
/// slacks s_j, the multipliers z_j, the artificial z0 and the right-hand side.
struct Tableau {
    cols: usize,
    artificial: usize,
    rhs: usize,
}

impl Tableau {
    /// Fills the tableau in `w.tableau` with the slacks as the basis.
    fn new(w: &mut Work, m: usize, w_scale: f64, p_scale: f64) -> Self {
        let t = Tableau {
            cols: 2 * m + 2,
            artificial: 2 * m,
            rhs: 2 * m + 1,
        };
        // Only the problem's rows: the buffer is sized for every roller.
        w.tableau[..m * t.cols].iter_mut().for_each(|x| *x = 0.0);
        for i in 0..m {
            let row = &mut w.tableau[i * t.cols..(i + 1) * t.cols];
            row[i] = 1.0;
            for k in 0..m {
                row[m + k] = -w.w[i * m + k] / w_scale;
            }
            row[t.artificial] = -1.0;
            row[t.rhs] = -w.predicted[i] / p_scale;
            w.basis[i] = i;
        }
        t
    }

    /// Pivots until the artificial variable leaves the basis; returns the pivots made.
    fn solve(&self, w: &mut Work, m: usize) -> Result<usize> {
        // The artificial variable enters at the row of the most negative q, making every
        // right-hand side non-negative; then each leaving variable's complement enters.
        let first = (0..m)
            .min_by(|&a, &b| self.at(w, a, self.rhs).total_cmp(&self.at(w, b, self.rhs)))
            .unwrap_or(0);
        self.pivot(w, first, self.artificial);
        let mut leaving = std::mem::replace(&mut w.basis[first], self.artificial);
        for pivots in 2..=MAX_PIVOTS_PER_ROLLER * m + 2 {
            let entering = if leaving < m {
                leaving + m
            } else {
                leaving - m
            };
            let Some(row) = self.ratio_test(w, m, entering) else {
                return Err(Error::not_converged(
                    "Lagrange-multiplier contact",
                    None,
                    None,
                    "the Lagrange-multiplier contact has no solution at this step (the \
                     rollers cannot hold the predicted motion); reduce the time step"
                        .into(),
                ));
            };
            self.pivot(w, row, entering);
            leaving = std::mem::replace(&mut w.basis[row], entering);
            if leaving == self.artificial {
                return Ok(pivots);
            }
        }
        Err(Error::not_converged(
            "Lagrange-multiplier contact",
            None,
            None,
            "the Lagrange-multiplier contact did not find its contact forces within the pivot \
             limit; reduce the time step"
                .into(),
        ))
    }

    fn at(&self, w: &Work, row: usize, col: usize) -> f64 {
        w.tableau[row * self.cols + col]
    }

    /// The row that leaves when column `col` enters: the smallest ratio rhs / entry over
    /// positive entries; ties go to the artificial variable (which ends the solve), then
    /// lexicographically by the rows of the basis inverse (the slack columns) over the entry.
    fn ratio_test(&self, w: &Work, m: usize, col: usize) -> Option<usize> {
        let largest = (0..m).fold(0.0f64, |a, i| a.max(self.at(w, i, col).abs()));
        let eligible = |i: &usize| self.at(w, *i, col) > PIVOT_TOLERANCE * largest;
        let ratio = |i: usize| self.at(w, i, self.rhs) / self.at(w, i, col);
        let best = (0..m)
            .filter(eligible)
            .map(ratio)
            .fold(f64::INFINITY, f64::min);
        if !best.is_finite() {
            return None;
        }
        let tie = RATIO_TIE * best.abs().max(1.0);
        let mut ties = (0..m).filter(eligible).filter(|&i| ratio(i) <= best + tie);
        let first = ties.next()?;
        if w.basis[first] == self.artificial {
            return Some(first);
        }
        let mut chosen = first;
        for i in ties {
            if w.basis[i] == self.artificial {
                return Some(i);
            }
            if self.lexicographically_smaller(w, m, col, i, chosen) {
                chosen = i;
            }
        }
        Some(chosen)
    }

    /// Whether row `a`'s basis-inverse entries over its pivot-column entry precede row `b`'s.
    fn lexicographically_smaller(
        &self,
        w: &Work,
        m: usize,
        col: usize,
        a: usize,
        b: usize,
    ) -> bool {
        let (pa, pb) = (self.at(w, a, col), self.at(w, b, col));
        for k in 0..m {
            let (xa, xb) = (self.at(w, a, k) / pa, self.at(w, b, k) / pb);
            if (xa - xb).abs() > RATIO_TIE * xa.abs().max(xb.abs()).max(1.0) {
                return xa < xb;
            }
        }
        false
    }

    /// Gauss-Jordan pivot on (row, col).
    fn pivot(&self, w: &mut Work, row: usize, col: usize) {
        let n = self.cols;
        let m = (n - 2) / 2;
        let inv = 1.0 / w.tableau[row * n + col];
        for x in &mut w.tableau[row * n..(row + 1) * n] {
            *x *= inv;
        }
        for other in (0..m).filter(|&r| r != row) {
            let factor = w.tableau[other * n + col];
            if factor != 0.0 {
                for k in 0..n {
                    w.tableau[other * n + k] -= factor * w.tableau[row * n + k];
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Solves the complementarity problem (W, predicted) on its own.
    fn solve(predicted: &[f64], w: &[f64]) -> Vec<f64> {
        let m = predicted.len();
        let mut work = Work::sized(m);
        work.predicted.copy_from_slice(predicted);
        work.w.copy_from_slice(w);
        solve_complementarity(&mut work, m).unwrap();
        work.lambda
    }

    #[test]
    fn complementarity_on_a_small_problem() {
        // W = [[2, 1], [1, 2]], predicted (3, -3). Both active would give lambda = (3, -3),
        // the second pulling; the solution has lambda_1 = 1.5 and delta_2 = -3 - 1.5 < 0.
        let lambda = solve(&[3.0, -3.0], &[2.0, 1.0, 1.0, 2.0]);
        // A few pivots of order-one numbers: round-off of a few ulps.
        assert!(
            (lambda[0] - 1.5).abs() < 1e-14 && lambda[1] == 0.0,
            "{lambda:?}"
        );
    }

    /// One bearing (a plane) held by `n` rollers around it, pushed far into the bottom so
    /// that many rollers penetrate: W = J S J^T has rank two, the case an active-set loop
    /// cannot solve. Returns the roller directions and their predicted approach.
    fn crowded_bearing(n: usize) -> (Vec<(f64, f64)>, Vec<f64>) {
        pushed_bearing(n, (0.4, -3.0))
    }

    /// `n` rollers around a bearing predicted at `push` (the clearance is 1).
    fn pushed_bearing(n: usize, push: (f64, f64)) -> (Vec<(f64, f64)>, Vec<f64>) {
        let gap = 1.0;
        let dirs: Vec<(f64, f64)> = (0..n)
            .map(|j| {
                let (sn, cs) = (2.0 * std::f64::consts::PI * j as f64 / n as f64 + 0.1).sin_cos();
                (cs, sn)
            })
            .collect();
        let predicted = dirs
            .iter()
            .map(|(c, s)| c * push.0 + s * push.1 - gap)
            .collect();
        (dirs, predicted)
    }

    fn w_matrix(dirs: &[(f64, f64)], s: [f64; 4]) -> Vec<f64> {
        let n = dirs.len();
        let mut w = vec![0.0; n * n];
        for (a, &(ca, sa)) in dirs.iter().enumerate() {
            for (b, &(cb, sb)) in dirs.iter().enumerate() {
                w[a * n + b] = ca * (s[0] * cb + s[1] * sb) + sa * (s[2] * cb + s[3] * sb);
            }
        }
        w
    }

    /// The correction S J^T lambda of the bearing's plane motion.
    fn correction(dirs: &[(f64, f64)], s: [f64; 4], lambda: &[f64]) -> (f64, f64) {
        let (fx, fy) = dirs
            .iter()
            .zip(lambda)
            .fold((0.0, 0.0), |(x, y), (&(c, sn), &l)| (x + c * l, y + sn * l));
        (s[0] * fx + s[1] * fy, s[2] * fx + s[3] * fy)
    }

    /// The obviously correct solution of a plane contact: at most two constraints are
    /// active at the corrected point, so every single roller and every pair is tried and the
    /// one satisfying all the complementarity conditions is kept.
    fn by_enumeration(w: &[f64], predicted: &[f64]) -> Vec<f64> {
        let n = predicted.len();
        let feasible = |lambda: &[f64]| {
            lambda.iter().all(|&l| l >= -1e-12)
                && (0..n).all(|j| {
                    predicted[j] - (0..n).map(|k| w[j * n + k] * lambda[k]).sum::<f64>() <= 1e-9
                })
        };
        for a in 0..n {
            let mut lambda = vec![0.0; n];
            lambda[a] = predicted[a] / w[a * n + a];
            if feasible(&lambda) {
                return lambda;
            }
        }
        for a in 0..n {
            for b in a + 1..n {
                let (waa, wab, wba, wbb) = (w[a * n + a], w[a * n + b], w[b * n + a], w[b * n + b]);
                let det = waa * wbb - wab * wba;
                if det.abs() < 1e-12 {
                    continue;
                }
                let mut lambda = vec![0.0; n];
                lambda[a] = (predicted[a] * wbb - wab * predicted[b]) / det;
                lambda[b] = (waa * predicted[b] - wba * predicted[a]) / det;
                if feasible(&lambda) {
                    return lambda;
                }
            }
        }
        panic!("no vertex solves the plane contact");
    }

    #[test]
    fn many_rollers_in_contact_at_once_are_solved_exactly() {
        for (n, s) in [
            (16, [2.0, 0.3, 0.3, 1.0]),
            (32, [2.0, 0.3, 0.3, 1.0]),
            // A skew part as the gyroscopic matrix gives S at speed.
            (32, [1.5, 0.25, -0.15, 1.2]),
        ] {
            let (dirs, predicted) = crowded_bearing(n);
            let penetrating = predicted.iter().filter(|&&d| d > 0.0).count();
            assert!(penetrating >= 3, "{penetrating} rollers penetrate");
            let wm = w_matrix(&dirs, s);
            let lambda = solve(&predicted, &wm);
            // Complementarity: every multiplier pushes, nothing penetrates, and a roller
            // pushes only where it touches. Order-one data after a few dozen pivots: 1e-12
            // is a thousand times the round-off.
            for j in 0..n {
                let delta = predicted[j] - (0..n).map(|k| wm[j * n + k] * lambda[k]).sum::<f64>();
                assert!(
                    lambda[j] >= 0.0 && delta <= 1e-12,
                    "roller {j}: {lambda:?} {delta}"
                );
                assert!(
                    (lambda[j] * delta).abs() <= 1e-12,
                    "roller {j}: {} {delta}",
                    lambda[j]
                );
            }
            // The split between the rollers need not be unique, the motion is.
            let reference = by_enumeration(&wm, &predicted);
            let (ux, uy) = correction(&dirs, s, &lambda);
            let (rx, ry) = correction(&dirs, s, &reference);
            assert!(
                (ux - rx).abs() < 1e-12 && (uy - ry).abs() < 1e-12,
                "n = {n}: ({ux}, {uy}) against ({rx}, {ry})"
            );
        }
    }

    #[test]
    fn the_penetrating_rollers_alone_give_the_same_correction() {
        // The set starts from the penetrating rollers and grows by those pushed in; its
        // answer must be the full problem's. A strongly coupled S (off-diagonal close to
        // the diagonal) makes the correction slide the bearing along the ring, pushing in
        // rollers that did not penetrate before: some of these cases must do so.
        let n = 32;
        let mut grown = 0;
        let around = (0..256).map(|k| {
            let (sn, cs) = (2.0 * std::f64::consts::PI * k as f64 / 256.0).sin_cos();
            (1.01 * cs, 1.01 * sn)
        });
        let pushes: Vec<(f64, f64)> = around.chain([(0.4, -3.0)]).collect();
        for s in [
            [2.0, 0.3, 0.3, 1.0],
            [1.0, 0.99, 0.99, 1.0],
            [1.0, -0.99, -0.99, 1.0],
        ] {
            for &push in &pushes {
                let (dirs, predicted) = pushed_bearing(n, push);
                let mut work = Work::sized(n);
                for (j, &(c, sn)) in dirs.iter().enumerate() {
                    work.rows[j] = (c, sn, 0);
                }
                work.approach.copy_from_slice(&predicted);
                work.set = (0..n).filter(|&j| predicted[j] > 0.0).collect();
                if work.set.is_empty() {
                    continue;
                }
                let first = work.set.len();
                work.solve_set(&s, 2).unwrap();
                while work.add_pushed_in(&s, 2, PUSHED_IN) {
                    work.solve_set(&s, 2).unwrap();
                }
                grown += usize::from(work.set.len() > first);
                let mut lambda = vec![0.0; n];
                for (a, &j) in work.set.iter().enumerate() {
                    lambda[j] = work.lambda[a];
                }
                let full = solve(&predicted, &w_matrix(&dirs, s));
                let (ux, uy) = correction(&dirs, s, &lambda);
                let (rx, ry) = correction(&dirs, s, &full);
                // Order-one data: a thousand round-offs.
                assert!(
                    (ux - rx).abs() < 1e-12 && (uy - ry).abs() < 1e-12,
                    "{push:?}, set of {} (from {first}): ({ux}, {uy}) against ({rx}, {ry})",
                    work.set.len()
                );
            }
        }
        assert!(grown > 0, "no case pushed a roller in");
    }
}
