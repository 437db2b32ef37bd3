//! The balance on the kept coordinates: its residual (also refined from a condensation at
//! a nearby frequency), its Jacobian, Newton at one frequency, and the full coefficients
//! recovered from the condensed ones.

use super::{Condensed, CondensedBalance, Recovered};
use crate::error::{Error, Result};
use crate::hbm::balance::HbSolution;
use crate::hbm::fourier::{cos_slot, sin_slot};
use crate::hbm::newton::{
    line_search, relative, GiveUp, Residual, FULL_STEPS, LINE_SEARCH_HALVINGS,
};
use crate::linalg::banded::BandedLu;
use crate::linalg::{multiply, norm, solve_dense};
use faer::Mat;

/// Iterative refinement ([`CondensedBalance::refine`]) has reached round-off when its
/// backward error stops halving below this: a factorisation at w leaves a few 1e-14 on
/// the reference rotor. Refined so far, the condensed residual at w agreed with the one of
/// a condensation at w within 1.5e-12 of its terms (|S x_a| + |g| + |F_nl,a|) over the
/// 20 um sweep's first resonance, against the Newton tolerance of 1e-10; stopped at a
/// backward error of 1e-13 instead, they differed by up to 8e-10: the condensed residual
/// is a small difference of the large terms D_aa x_a and D_ab q_b.
const ROUND_OFF: f64 = 1e-13;

/// Refinement steps at most: from a condensation at a nearby frequency the error shrinks
/// by orders of magnitude per step; where it does not, condensing afresh is cheaper.
const REFINEMENTS: usize = 10;

impl CondensedBalance {
    /// The external force of block r and its w-derivative: the constant force in block 0,
    /// unbalance (w^2 f) and fixed forcing h in block 1 as Re((u + i v) e^{i w t}) =
    /// u cos - v sin, nothing above.
    pub(super) fn external_force(&self, r: usize, frequency: f64) -> (Vec<f64>, Vec<f64>) {
        let p = &self.linear;
        let n = p.size();
        match r {
            0 => (p.constant_force.clone(), vec![0.0; n]),
            1 => {
                let w2 = frequency * frequency;
                let mut f = vec![0.0; 2 * n];
                let mut df = vec![0.0; 2 * n];
                for dof in 0..n {
                    f[dof] = w2 * p.unbalance_re[dof] + p.harmonic_re[dof];
                    f[n + dof] = -(w2 * p.unbalance_im[dof] + p.harmonic_im[dof]);
                    df[dof] = 2.0 * frequency * p.unbalance_re[dof];
                    df[n + dof] = -2.0 * frequency * p.unbalance_im[dof];
                }
                (f, df)
            }
            _ => (vec![0.0; 2 * n], vec![0.0; 2 * n]),
        }
    }

    /// The range of unknowns of block r: slot 0, or slots cos r and sin r, which are
    /// adjacent (cos r = 2r - 1, sin r = 2r).
    fn block_range(&self, r: usize) -> std::ops::Range<usize> {
        let m = self.kept.len();
        match r {
            0 => 0..m,
            _ => cos_slot(r) * m..(sin_slot(r) + 1) * m,
        }
    }

    /// R_a = S x_a - g - F_nl,a and |S x_a| + |g| + |F_nl,a|, the terms that cancel.
    pub fn residual(&mut self, condensed: &Condensed, x: &[f64]) -> (Vec<f64>, f64) {
        let nonlinear = self.reduced.residual(x, condensed.frequency);
        let mut linear = vec![0.0; x.len()];
        let mut external = vec![0.0; x.len()];
        for (r, block) in condensed.blocks.iter().enumerate() {
            let range = self.block_range(r);
            multiply(&block.schur, &x[range.clone()], &mut linear[range.clone()]);
            external[range].copy_from_slice(&block.force);
        }
        let values = (0..x.len())
            .map(|i| linear[i] - external[i] + nonlinear.values[i])
            .collect();
        (values, norm(&linear) + norm(&external) + nonlinear.scale)
    }

    /// [`Self::residual`] at w from a condensation made at another frequency, exact to
    /// round-off: per block, q_b at w solves D_bb(w) q_b = f_b(w) - D_ba(w) x_a by
    /// iterative refinement with the factorised D_bb of `condensed` ([`Self::refine`]),
    /// split as for the condensation into the part of x_a (S x_a = D_aa x_a + D_ab q_b)
    /// and the part of the force (g = f_a - D_ab z), so that the terms that cancel are the
    /// same. `None` where the refinement does not converge (w too far from the
    /// condensation's frequency, or near a resonance of the condensed coordinates).
    ///
    /// A residual without a Jacobian (the line search's trial points, each at its own
    /// frequency) then costs a few banded products and solves with one right-hand side
    /// instead of a condensation (a banded LU and two solves with 2m + 1 right-hand
    /// sides per harmonic).
    pub(crate) fn residual_near(
        &mut self,
        condensed: &Condensed,
        x: &[f64],
        frequency: f64,
    ) -> Option<(Vec<f64>, f64)> {
        let mut linear = vec![0.0; x.len()];
        let mut external = vec![0.0; x.len()];
        for (r, block) in condensed.blocks.iter().enumerate() {
            let range = self.block_range(r);
            if r == 0 {
                // The constant term's K and force do not depend on w.
                multiply(&block.schur, &x[range.clone()], &mut linear[range.clone()]);
                external[range].copy_from_slice(&block.force);
                continue;
            }
            let copies = 2;
            let (a, b) = self.condenser().partition(copies);
            let (force, _) = self.external_force(r, frequency);
            let q_a = &x[range.clone()];
            // Started from the values at the condensation's frequency: q_b = -X q_a and z.
            let mut from_motion = vec![0.0; force.len()];
            let mut x_qa = vec![0.0; b.len()];
            multiply(&block.transfer, q_a, &mut x_qa);
            for (&i, v) in a.iter().zip(q_a) {
                from_motion[i] = *v;
            }
            for (&i, v) in b.iter().zip(&x_qa) {
                from_motion[i] = -v;
            }
            let mut from_force = vec![0.0; force.len()];
            for (&i, v) in b.iter().zip(&block.particular) {
                from_force[i] = *v;
            }
            let no_force = vec![0.0; force.len()];
            let motion = self.refine(r, frequency, &block.lu, &b, &mut from_motion, &no_force)?;
            // Above the first harmonic there is no force, and z = 0.
            let forced = if force.iter().all(|&f| f == 0.0) {
                vec![0.0; force.len()]
            } else {
                self.refine(r, frequency, &block.lu, &b, &mut from_force, &force)?
            };
            for (k, &i) in range.zip(&a) {
                linear[k] = motion[i];
                external[k] = force[i] - forced[i];
            }
        }
        let nonlinear = self.reduced.residual(x, frequency);
        let values = (0..x.len())
            .map(|i| linear[i] - external[i] + nonlinear.values[i])
            .collect();
        Some((values, norm(&linear) + norm(&external) + nonlinear.scale))
    }

    /// Solves D_bb(w) v_b = rhs_b - D_ba(w) v_a for the rest entries `rest` of `v` (a
    /// vector of block r in the layout of
    /// [`Condenser::partition`](super::block::Condenser::partition), its kept entries held)
    /// by iterative refinement from v_b as given, each correction solved with `lu`, D_bb
    /// factorised at another frequency w_0: the error shrinks by |D_bb(w_0)^-1 (D_bb(w) -
    /// D_bb(w_0))| per step, small for a nearby w. It runs until the backward error (the
    /// equation's residual relative to |D| |v| + |rhs|) stops halving below [`ROUND_OFF`]:
    /// the solution is then as exact as a factorisation at w gives. Returns D_r(w) v at the
    /// solution, or `None` when the backward error stops halving above that, or
    /// [`REFINEMENTS`] steps do not reach it.
    fn refine(
        &self,
        r: usize,
        frequency: f64,
        lu: &BandedLu,
        rest: &[usize],
        v: &mut [f64],
        rhs: &[f64],
    ) -> Option<Vec<f64>> {
        let mut previous = f64::INFINITY;
        for _ in 0..REFINEMENTS {
            let (product, magnitude) = self.sparse.apply(r, frequency, v);
            let mut correction: Vec<f64> = rest.iter().map(|&i| rhs[i] - product[i]).collect();
            let terms: Vec<f64> = rest.iter().map(|&i| magnitude[i] + rhs[i].abs()).collect();
            let residual = norm(&correction);
            let backward = residual / norm(&terms);
            if residual == 0.0 || (backward > 0.5 * previous && previous <= ROUND_OFF) {
                return Some(product);
            }
            if !backward.is_finite() || backward > 0.5 * previous {
                return None;
            }
            lu.solve(&mut correction);
            for (&i, c) in rest.iter().zip(&correction) {
                v[i] += c;
            }
            previous = backward;
        }
        None
    }

    /// [`Self::residual`] as the line search takes it.
    fn condensed_residual(&mut self, condensed: &Condensed, x: &[f64]) -> Residual {
        let (values, scale) = self.residual(condensed, x);
        Residual { values, scale }
    }

    /// dR_a/dx_a and dR_a/dw at (x_a, w), exact.
    pub fn linearise(&mut self, condensed: &Condensed, x: &[f64]) -> (Mat<f64>, Vec<f64>) {
        let nonlinear = self.reduced.linearise(x, condensed.frequency);
        let jacobian = self.with_schur(condensed, nonlinear.jacobian);
        let mut frequency_derivative = nonlinear.frequency_derivative;
        for (r, derivative) in self.derivatives_of(condensed).iter().enumerate() {
            let range = self.block_range(r);
            let mut ds_x = vec![0.0; range.len()];
            multiply(&derivative.schur, &x[range.clone()], &mut ds_x);
            for (i, row) in range.enumerate() {
                frequency_derivative[row] += ds_x[i] - derivative.force[i];
            }
        }
        (jacobian, frequency_derivative)
    }

    /// dR_a/dx_a at (x_a, w), exact: Newton at a fixed frequency needs no w-derivatives.
    fn jacobian(&mut self, condensed: &Condensed, x: &[f64]) -> Mat<f64> {
        let nonlinear = self.reduced.linearise(x, condensed.frequency);
        self.with_schur(condensed, nonlinear.jacobian)
    }

    /// `jacobian` (the nonlinear forces' dR_a/dx_a) with the Schur complements added.
    fn with_schur(&self, condensed: &Condensed, mut jacobian: Mat<f64>) -> Mat<f64> {
        for (r, block) in condensed.blocks.iter().enumerate() {
            let range = self.block_range(r);
            for (i, row) in range.clone().enumerate() {
                for (j, col) in range.clone().enumerate() {
                    jacobian[(row, col)] += block.schur[(i, j)];
                }
            }
        }
        jacobian
    }

    /// Harmonic balance at w by Newton-Raphson from `guess` (condensed unknowns); the
    /// linear part is condensed once and every iteration costs O((m (2H + 1))^3).
    ///
    /// The tolerance applies to the condensed residual relative to its own terms (|S x_a| +
    /// |g| + |F_nl,a|).
    ///
    /// Plain Newton first, then Newton with a line search, as
    /// [`HarmonicBalance::solve`](crate::hbm::HarmonicBalance::solve).
    ///
    /// # Errors As [`HarmonicBalance::solve`](crate::hbm::HarmonicBalance::solve): an
    /// unconverged point is never returned.
    pub fn solve(&mut self, frequency: f64, guess: &[f64]) -> Result<HbSolution> {
        self.reduced.check_arguments(frequency, guess)?;
        self.with_condensed(frequency, |hb, condensed| {
            hb.newton(condensed, guess, FULL_STEPS)
                .or_else(|_| hb.newton(condensed, guess, LINE_SEARCH_HALVINGS))
        })?
    }

    /// Newton-Raphson on the condensed residual at the condensation's frequency, each step
    /// shortened up to `halvings` times ([`line_search`]).
    fn newton(
        &mut self,
        condensed: &Condensed,
        guess: &[f64],
        halvings: usize,
    ) -> Result<HbSolution> {
        let frequency = condensed.frequency;
        let options = *self.options();
        let mut x = guess.to_vec();
        let mut last = f64::NAN;
        let mut taken = 0;
        let mut give_up = GiveUp::new(halvings);
        let mut residual = self.condensed_residual(condensed, &x);
        for iteration in 0..=options.max_iterations {
            last = relative(&residual);
            taken = iteration;
            if last <= options.tolerance {
                return Ok(HbSolution {
                    frequency,
                    coefficients: x,
                    iterations: iteration,
                    relative_residual: last,
                });
            }
            if !last.is_finite() || iteration == options.max_iterations || give_up.now(last) {
                break;
            }
            let jacobian = self.jacobian(condensed, &x);
            let step = solve_dense(&jacobian, &residual.values).ok_or_else(|| {
                Error::singular(
                    "Jacobian",
                    format!("condensed harmonic balance at {frequency} rad/s: singular Jacobian"),
                )
            })?;
            (x, residual) = line_search(&x, &step, &residual, halvings, |trial| {
                self.condensed_residual(condensed, trial)
            });
        }
        Err(Error::not_converged(
            "condensed harmonic balance",
            Some(taken),
            Some(last),
            format!(
                "condensed harmonic balance did not converge at {frequency} rad/s after \
             {taken} Newton iterations (relative residual {last:e}, tolerance {:e})",
                options.tolerance
            ),
        ))
    }

    /// The full Fourier coefficients x[slot * n + dof] of a condensed solution: kept from
    /// the path (`keep_recovered`), else from the condensation of its solve when
    /// that was the last, else from a new one.
    ///
    /// # Errors
    /// As [`Self::condense`].
    pub fn recover(&mut self, solution: &HbSolution) -> Result<Vec<f64>> {
        let kept = self
            .recovered
            .get(&solution.frequency.to_bits())
            .and_then(|kept| kept.iter().find(|k| k.condensed == solution.coefficients));
        if let Some(kept) = kept {
            return Ok(kept.full.clone());
        }
        self.with_condensed(solution.frequency, |hb, condensed| {
            hb.recover_with(condensed, &solution.coefficients)
        })
    }

    /// Keeps the full coefficients of `solution`, a point of a path, when the last
    /// condensation was made at its frequency (as it is just after the point was solved
    /// and its tangent taken): a sweep recovers every point after the path, and would
    /// otherwise condense at each point's frequency once more.
    pub(crate) fn keep_recovered(&mut self, solution: &HbSolution) {
        let full = match &self.last {
            Some(last) if last.frequency == solution.frequency => {
                self.recover_with(last, &solution.coefficients)
            }
            _ => return,
        };
        self.recovered
            .entry(solution.frequency.to_bits())
            .or_default()
            .push(Recovered {
                condensed: solution.coefficients.clone(),
                full,
            });
    }

    /// The full coefficients from the condensed ones x: q_a as solved, q_b = z - X q_a
    /// per block.
    fn recover_with(&self, condensed: &Condensed, x: &[f64]) -> Vec<f64> {
        let n = self.linear.size();
        let mut full = vec![0.0; n * (2 * self.harmonics() + 1)];
        for (r, block) in condensed.blocks.iter().enumerate() {
            let range = self.block_range(r);
            let (a, b) = self.condenser().partition(if r == 0 { 1 } else { 2 });
            let start = if r == 0 { 0 } else { cos_slot(r) * n };
            let q_a = &x[range];
            for (i, &index) in a.iter().enumerate() {
                full[start + index] = q_a[i];
            }
            let mut x_qa = vec![0.0; b.len()];
            multiply(&block.transfer, q_a, &mut x_qa);
            for (i, &index) in b.iter().enumerate() {
                full[start + index] = block.particular[i] - x_qa[i];
            }
        }
        full
    }
}
