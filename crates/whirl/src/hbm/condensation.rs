//! Exact dynamic condensation per harmonic of the linear coordinates onto those that carry
//! nonlinear forces, so a Newton step costs the same for any model size.
//!
//! The linear operator is block diagonal over harmonics: slot 0 holds K and harmonic r the
//! real form of the complex dynamic stiffness on (cos r, sin r),
//!
//! ```text
//! D_r(w) = [ Z_r      r w D ]     Z_r = K - (r w)^2 M,  D = C + w G.
//!          [ -r w D   Z_r   ]
//! ```
//!
//! Split each block into the nonlinear coordinates (a) and the rest (b). The forces on b are
//! linear, so q_b = D_bb^-1 (f_b - D_ba q_a) exactly, and the residual on a becomes
//!
//! ```text
//! R_a = S q_a - g - F_nl,a,   S = D_aa - D_ab D_bb^-1 D_ba,   g = f_a - D_ab D_bb^-1 f_b.
//! ```
//!
//! S and g depend on w only, so they are made once per frequency ([`Condensed`]), and their
//! exact w-derivatives, which continuation needs, from the same factorisation when asked for:
//! dX = D_bb^-1 (dD_ba - dD_bb X) with X = D_bb^-1 D_ba gives dS = dD_aa - dD_ab X - D_ab dX,
//! and likewise for g. The nonlinear forces are evaluated by the same AFT as the full
//! problem, on a problem holding only the a coordinates.

use std::collections::HashMap;
use std::sync::OnceLock;

use faer::Mat;
use rayon::prelude::*;

use super::balance::{line_search, relative, GiveUp, Residual, FULL_STEPS, LINE_SEARCH_HALVINGS};
use super::fourier::{cos_slot, sin_slot};
use super::stability::{FloquetModel, FloquetProblem, Stability};
use super::{HarmonicBalance, HbOptions, HbSolution};
use crate::error::{Error, Result};
use crate::fe::SystemMatrices;
use crate::force::{Kinematics, NonlinearForce};
use crate::linalg::banded::BandedLu;
use crate::linalg::{multiply, norm, solve_dense};
use crate::reduce::CraigBampton;
use crate::system::System;

/// A nonlinear force renumbered onto the condensed coordinates.
struct Renumbered {
    force: Box<dyn NonlinearForce>,
    dofs: Vec<usize>,
}

impl NonlinearForce for Renumbered {
    fn name(&self) -> String {
        self.force.name()
    }
    fn dofs(&self) -> &[usize] {
        &self.dofs
    }
    fn force(&mut self, at: &Kinematics, q: &[f64], v: &[f64], out: &mut [f64]) {
        self.force.force(at, q, v, out);
    }
    fn jacobian(
        &mut self,
        at: &Kinematics,
        q: &[f64],
        v: &[f64],
        dfdq: &mut [f64],
        dfdv: &mut [f64],
    ) {
        self.force.jacobian(at, q, v, dfdq, dfdv);
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
        self.force.force_and_jacobian(at, q, v, out, dfdq, dfdv);
    }
    fn stiffness_bound(&self) -> Vec<f64> {
        self.force.stiffness_bound()
    }
}

/// One block of the condensed linear part at one frequency.
struct Block {
    /// S, the Schur complement on a.
    schur: Mat<f64>,
    /// g, the external force reduced onto a.
    force: Vec<f64>,
    /// X = D_bb^-1 D_ba and z = D_bb^-1 f_b, for q_b = z - X q_a.
    transfer: Mat<f64>,
    particular: Vec<f64>,
    /// D_ab, for the w-derivatives.
    coupling: Mat<f64>,
    /// D_bb factorised, for the w-derivatives ([`Condenser::differentiate`]) and for
    /// residuals at nearby frequencies ([`CondensedBalance::refine`]).
    lu: BandedLu,
    /// What the w-derivatives read besides: the entries (with their derivatives) as
    /// formed for the values, and [X | z] row by row.
    entries: BlockEntries,
    solution: Vec<f64>,
}

/// The entries of a block and their w-derivatives, by part.
struct BlockEntries {
    rest_rest: RestPairs,
    rest_kept: Vec<(f64, f64)>,
    kept_rest: Vec<(f64, f64)>,
    kept_kept: Vec<(f64, f64)>,
}

/// The w-derivatives of one block.
struct BlockDerivative {
    /// dS/dw.
    schur: Mat<f64>,
    /// dg/dw.
    force: Vec<f64>,
}

/// The linear part condensed onto the nonlinear coordinates at one frequency: block 0 for
/// the constant term, block r for harmonic r.
pub struct Condensed {
    /// Frequency w, rad/s.
    pub frequency: f64,
    blocks: Vec<Block>,
    /// The blocks' w-derivatives, made the first time they are asked for
    /// ([`CondensedBalance::derivatives_of`]): a residual alone (a line-search trial, a
    /// solution's recovery, Newton at fixed frequency) does not need them, and they cost
    /// about as much again as the values (a second solve with 2m + 1 right-hand sides).
    derivatives: OnceLock<Vec<BlockDerivative>>,
}

/// Harmonic balance on the coordinates that carry nonlinear forces, with the linear rest
/// condensed exactly. Unknowns x_a[slot * m + i] for the i-th of [`Self::kept`].
pub struct CondensedBalance {
    /// The linear part (its `nonlinear` is empty: the forces live in `reduced`).
    linear: System,
    /// The nonlinear forces on the kept coordinates, with zero linear part: its residual is
    /// -F_nl,a and its Jacobian -dF_nl,a/dx_a.
    reduced: HarmonicBalance,
    kept: Vec<usize>,
    rest: Vec<usize>,
    /// Half-bandwidth of the linear matrices among the `rest` coordinates.
    rest_bandwidth: usize,
    /// The linear matrices for entry-wise reads.
    plain: PlainMatrices,
    /// The same by rows of nonzeros, for products with vectors.
    sparse: SparseMatrices,
    /// The last condensation, reused at the same frequency.
    last: Option<Condensed>,
    /// Path points recovered from their own condensation while it was the last
    /// ([`Self::keep_recovered`]), by their frequency's bits.
    recovered: HashMap<u64, Vec<Recovered>>,
    /// Whether residuals at other frequencies are refined from `last`
    /// ([`Self::residual_near`]).
    refining: bool,
    /// Fixed-interface modes of the stability model.
    stability_modes: usize,
    /// The linear part of the stability model, made at the first stability request.
    stability_model: Option<FloquetModel>,
}

/// A solution's condensed coefficients and the full ones recovered from them.
struct Recovered {
    condensed: Vec<f64>,
    full: Vec<f64>,
}

/// Fixed-interface modes kept in the stability model by default, chosen by the
/// convergence of the reference rotor's bifurcations (20 um, H = 5, 160 samples, 1-750 Hz;
/// BENCHMARKS.md, harmonic balance): with 4, 8 and 12 modes the list above 100 Hz changes from one
/// count to the next (4 modes miss the period doubling at 160-171 Hz that time marching of
/// the same model shows, and find one at 39.5-40.3 Hz that it refutes); with 16 and 24 it
/// is the same within 1 Hz. The monodromy's cost grows as the cube of the states.
pub const DEFAULT_STABILITY_MODES: usize = 16;

impl CondensedBalance {
    /// Sets up condensed harmonic balance for `problem`.
    ///
    /// # Errors
    /// The errors of [`System::check`] and of [`HarmonicBalance::new`] for the
    /// condensed problem: [`Error::InvalidOption`] for sizes that differ, a nonlinear force
    /// on a coordinate outside the problem, or `options.samples` not above twice
    /// `options.harmonics`.
    pub fn new(mut problem: System, options: HbOptions) -> Result<CondensedBalance> {
        problem.check()?;
        let kept = problem.nonlinear_dofs();
        let forces = std::mem::take(&mut problem.nonlinear);
        let rest: Vec<usize> = (0..problem.size())
            .filter(|d| kept.binary_search(d).is_err())
            .collect();
        let rest_bandwidth = bandwidth(&problem, &rest);
        let plain = PlainMatrices::new(&problem);
        let sparse = SparseMatrices::new(&plain);
        let m = kept.len();
        let renumbered = forces
            .into_iter()
            .map(|force| {
                let dofs = force
                    .dofs()
                    .iter()
                    // `kept` holds every one of these, sorted: its position is where it sorts.
                    .map(|d| kept.partition_point(|k| k < d))
                    .collect();
                Box::new(Renumbered { force, dofs }) as Box<dyn NonlinearForce>
            })
            .collect();
        let reduced = System {
            nonlinear: renumbered,
            ..System::unloaded(SystemMatrices {
                mass: Mat::zeros(m, m),
                stiffness: Mat::zeros(m, m),
                damping: Mat::zeros(m, m),
                gyroscopic: Mat::zeros(m, m),
            })
        };
        Ok(CondensedBalance {
            linear: problem,
            reduced: HarmonicBalance::new(reduced, options)?,
            kept,
            rest,
            rest_bandwidth,
            plain,
            sparse,
            last: None,
            recovered: HashMap::new(),
            refining: false,
            stability_modes: DEFAULT_STABILITY_MODES,
            stability_model: None,
        })
    }

    /// Sets the number of fixed-interface modes of the stability model (see
    /// [`Self::stability`]).
    pub fn with_stability_modes(mut self, modes: usize) -> CondensedBalance {
        self.stability_modes = modes;
        self.stability_model = None;
        self
    }

    /// The same problem sampled `samples` times per period; the condensation and the
    /// stability model, which do not depend on the count, are kept.
    ///
    /// # Errors
    /// As [`HarmonicBalance::new`], for a count not above 2H or above the most.
    pub fn with_samples(self, samples: usize) -> Result<CondensedBalance> {
        Ok(CondensedBalance {
            reduced: self.reduced.with_samples(samples)?,
            ..self
        })
    }

    /// Floquet stability of the condensed solution `x` at w (rad/s).
    ///
    /// The monodromy matrix needs the linear part in time, which the condensation per
    /// harmonic does not give; it is integrated instead on a Craig-Bampton model of the
    /// linear part whose boundary is the kept coordinates, with `stability_modes`
    /// fixed-interface modes (8 coordinates, 16 states on the reference rotor). The
    /// nonlinear forces act on the kept coordinates only, so their tangents enter exactly;
    /// only the linear rest is truncated, to its lowest modes.
    ///
    /// # Errors
    /// [`Error::Singular`] or [`Error::NotConverged`] when the reduction or the monodromy
    /// fails.
    pub fn stability(&mut self, x: &[f64], frequency: f64) -> Result<Stability> {
        self.floquet_problem(x, frequency)?.solve()
    }

    /// The Floquet problem of [`Self::stability`], to solve later.
    ///
    /// # Errors
    /// As [`Self::stability`].
    pub fn floquet_problem(&mut self, x: &[f64], frequency: f64) -> Result<FloquetProblem> {
        self.reduced.check_arguments(frequency, x)?;
        let model = match self.stability_model.take() {
            Some(model) => model,
            None => self.stability_basis()?,
        };
        // The reduced problem's forces act on all m kept coordinates, numbered 0..m, which
        // are the reduction's first m (boundary) coordinates: both ascending.
        let tangents = self.reduced.sampled_tangents(x, frequency);
        let problem = model.problem(frequency, &tangents);
        self.stability_model = Some(model);
        Ok(problem)
    }

    /// The linear part reduced by Craig-Bampton onto the kept coordinates and the lowest
    /// fixed-interface modes.
    fn stability_basis(&self) -> Result<FloquetModel> {
        let cb = CraigBampton::new(&self.linear.matrices, &self.kept, self.stability_modes)?;
        FloquetModel::new(&cb.reduced)
    }

    /// The coordinates kept (those carrying nonlinear forces), ascending.
    pub fn kept(&self) -> &[usize] {
        &self.kept
    }

    /// Number of unknowns, m (2H + 1).
    pub fn unknowns(&self) -> usize {
        self.reduced.unknowns()
    }

    /// The discretisation and Newton settings.
    pub fn options(&self) -> &HbOptions {
        self.reduced.options()
    }

    fn harmonics(&self) -> usize {
        self.options().harmonics
    }

    /// The linear part condensed at frequency w.
    ///
    /// # Errors
    /// [`Error::Singular`] when D_bb is singular: w sits on a resonance of the linear part
    /// with the kept coordinates held fixed, where the rest cannot be condensed.
    pub fn condense(&self, frequency: f64) -> Result<Condensed> {
        let forces: Vec<_> = (0..=self.harmonics())
            .map(|r| self.external_force(r, frequency).0)
            .collect();
        // The blocks are independent: each is condensed on one of rayon's threads, every
        // block with the same arithmetic as alone, and collected in order (the bits do not
        // depend on the threads). A block is 0.1-0.3 ms on the reference rotor, well above
        // the pool's overhead.
        let condenser = self.condenser();
        let blocks = forces
            .into_par_iter()
            .enumerate()
            .map(|(r, force)| condenser.condense_block(&condenser.harmonic(r, frequency), &force))
            .collect::<Result<Vec<_>>>()?;
        Ok(Condensed {
            frequency,
            blocks,
            derivatives: OnceLock::new(),
        })
    }

    /// The w-derivatives of the blocks of `condensed`, made at the first call (on rayon's
    /// threads, as the blocks) and kept with it.
    fn derivatives_of<'c>(&self, condensed: &'c Condensed) -> &'c [BlockDerivative] {
        condensed.derivatives.get_or_init(|| {
            let frequency = condensed.frequency;
            let forces: Vec<_> = (0..=self.harmonics())
                .map(|r| self.external_force(r, frequency).1)
                .collect();
            let condenser = self.condenser();
            condensed
                .blocks
                .par_iter()
                .zip(forces)
                .map(|(block, df)| condenser.differentiate(block, &df))
                .collect()
        })
    }

    /// What the condensation of a block reads.
    fn condenser(&self) -> Condenser<'_> {
        Condenser {
            plain: &self.plain,
            kept: &self.kept,
            rest: &self.rest,
            rest_bandwidth: self.rest_bandwidth,
        }
    }

    /// Runs `task` with the condensation at w, reusing the last one when it was made at the
    /// same w: the continuation corrector asks for the residual and then the derivatives at
    /// each frequency it tries, and condensing costs more than the reduced Newton step.
    pub(crate) fn with_condensed<T>(
        &mut self,
        frequency: f64,
        task: impl FnOnce(&mut Self, &Condensed) -> T,
    ) -> Result<T> {
        let condensed = match self.last.take() {
            Some(last) if last.frequency == frequency => last,
            _ => self.condense(frequency)?,
        };
        let value = task(self, &condensed);
        self.last = Some(condensed);
        Ok(value)
    }

    /// Whether residuals at frequencies without a condensation are refined from the last
    /// one (see [`Self::residual_near`]).
    pub(crate) fn refining(&self) -> bool {
        self.refining
    }

    /// Turns the refinement of [`Self::refining`] on or off.
    pub(crate) fn set_refining(&mut self, on: bool) {
        self.refining = on;
    }

    /// Runs `exact` with the condensation at w when the last one was made there; otherwise
    /// `near` with the last one, made at another frequency, and where that gives nothing
    /// (no condensation yet, or [`Self::refine`] failed), `exact` with a new one at w.
    pub(crate) fn with_nearby<T>(
        &mut self,
        frequency: f64,
        near: impl FnOnce(&mut Self, &Condensed) -> Option<T>,
        exact: impl FnOnce(&mut Self, &Condensed) -> T,
    ) -> Result<T> {
        if let Some(last) = self.last.take() {
            let near_value = if last.frequency == frequency {
                None
            } else {
                near(self, &last)
            };
            self.last = Some(last);
            if let Some(value) = near_value {
                return Ok(value);
            }
        }
        self.with_condensed(frequency, exact)
    }

    /// The external force of block r and its w-derivative: the constant force in block 0,
    /// unbalance (w^2 f) and fixed forcing h in block 1 as Re((u + i v) e^{i w t}) =
    /// u cos - v sin, nothing above.
    fn external_force(&self, r: usize, frequency: f64) -> (Vec<f64>, Vec<f64>) {
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
    /// vector of block r in the layout of [`Condenser::partition`], its kept entries held) by
    /// iterative refinement from v_b as given, each correction solved with `lu`, D_bb
    /// factorised at another frequency w_0: the error shrinks by
    /// |D_bb(w_0)^-1 (D_bb(w) - D_bb(w_0))| per step, small for a nearby w. It runs until
    /// the backward error (the equation's residual relative to |D| |v| + |rhs|) stops
    /// halving below [`ROUND_OFF`]: the solution is then as exact as a factorisation at w
    /// gives. Returns D_r(w) v at the solution, or `None` when the backward error stops
    /// halving above that, or [`REFINEMENTS`] steps do not reach it.
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
    /// The tolerance applies to the condensed residual relative to its own terms
    /// (|S x_a| + |g| + |F_nl,a|).
    ///
    /// Plain Newton first, then Newton with a line search, as [`HarmonicBalance::solve`].
    ///
    /// # Errors
    /// As [`HarmonicBalance::solve`]: an unconverged point is never returned.
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

/// What condensing a block reads: the linear matrices and the split of the coordinates,
/// all shared, so the harmonics are condensed on several threads at once (the balance
/// itself holds its nonlinear forces, which are not `Sync`).
struct Condenser<'a> {
    plain: &'a PlainMatrices,
    /// The coordinates kept and condensed, ascending, as [`CondensedBalance`]'s.
    kept: &'a [usize],
    rest: &'a [usize],
    /// Half-bandwidth of the linear matrices among the `rest` coordinates.
    rest_bandwidth: usize,
}

impl Condenser<'_> {
    /// Row/column indices of the kept and condensed coordinates in a block of
    /// `copies` (1 for the constant term, 2 for cos and sin) copies of the n coordinates.
    /// Kept ones are in slot order (all cos, then all sin), as the unknowns; condensed ones
    /// interleave the copies of each coordinate, which keeps D_bb banded.
    fn partition(&self, copies: usize) -> (Vec<usize>, Vec<usize>) {
        let n = self.plain.n;
        let kept = (0..copies)
            .flat_map(|c| self.kept.iter().map(move |d| c * n + d))
            .collect();
        let rest = self
            .rest
            .iter()
            .flat_map(|d| (0..copies).map(move |c| c * n + d))
            .collect();
        (kept, rest)
    }

    /// Harmonic r's dynamic stiffness at w.
    fn harmonic(&self, r: usize, frequency: f64) -> HarmonicBlock<'_> {
        HarmonicBlock {
            matrices: self.plain,
            r,
            frequency,
        }
    }

    /// Condenses one block D with its force f. One factorisation of D_bb serves X and z
    /// here and their w-derivatives later ([`Self::differentiate`]). Only entries within
    /// the band of D_bb are formed, so the cost grows linearly with the model size.
    fn condense_block(&self, block: &HarmonicBlock<'_>, f: &[f64]) -> Result<Block> {
        let frequency = block.frequency;
        let copies = f.len() / self.plain.n;
        let (a, b) = self.partition(copies);
        let band = self.rest_band(copies);
        let d_bb = self.rest_pairs(block, copies);
        let singular = || {
            Error::singular(
                "condensed linear part",
                format!(
                    "condensation at {frequency} rad/s: the linear part with the nonlinear \
                 coordinates held is singular (a resonance of the condensed coordinates)"
                ),
            )
        };
        let lu =
            BandedLu::new(b.len(), band, band, |i, k| d_bb.entry(i, k).0).ok_or_else(singular)?;
        // [X | z] = D_bb^-1 [D_ba | f_b], row by row (one column per kept coordinate, then z).
        let (nb, cols) = (b.len(), a.len() + 1);
        let d_ba = self.entries(block, copies, Part::Rest, Part::Kept);
        let mut solution = vec![0.0; nb * cols];
        for (i, row) in solution.chunks_mut(cols).enumerate() {
            for (j, r) in row.iter_mut().take(a.len()).enumerate() {
                *r = d_ba[i * a.len() + j].0;
            }
            row[a.len()] = f[b[i]];
        }
        lu.solve_rows(&mut solution, cols);
        if !solution.iter().all(|v| v.is_finite()) {
            return Err(singular());
        }
        let (transfer, particular) = split(&solution, nb, a.len());
        let d_ab = self.entries(block, copies, Part::Kept, Part::Rest);
        let d_aa = self.entries(block, copies, Part::Kept, Part::Kept);
        let coupling = matrix(&d_ab, a.len(), |e| e.0);
        let schur = matrix(&d_aa, a.len(), |e| e.0) - &coupling * &transfer;
        let force = pick(f, &a) - &coupling * &particular;
        Ok(Block {
            schur,
            force: column(force),
            transfer,
            particular: column(particular),
            coupling,
            lu,
            entries: BlockEntries {
                rest_rest: d_bb,
                rest_kept: d_ba,
                kept_rest: d_ab,
                kept_kept: d_aa,
            },
            solution,
        })
    }

    /// The w-derivatives of a block condensed by [`Self::condense_block`], df/dw its
    /// force's: [dX | dz] = D_bb^-1 ([dD_ba | df_b] - dD_bb [X | z]) with the same
    /// factorisation, then dS = dD_aa - dD_ab X - D_ab dX and dg = df_a - dD_ab z - D_ab dz.
    fn differentiate(&self, values: &Block, df: &[f64]) -> BlockDerivative {
        let copies = df.len() / self.plain.n;
        let (a, b) = self.partition(copies);
        let band = self.rest_band(copies);
        let entries = &values.entries;
        let (d_bb, d_ba) = (&entries.rest_rest, &entries.rest_kept);
        let (nb, cols) = (b.len(), a.len() + 1);
        let particular = Mat::from_fn(nb, 1, |i, _| values.particular[i]);
        let solution = &values.solution;
        let mut derivative_solution = vec![0.0; nb * cols];
        for (i, row) in derivative_solution.chunks_mut(cols).enumerate() {
            for (j, r) in row.iter_mut().take(a.len()).enumerate() {
                *r = d_ba[i * a.len() + j].1;
            }
            row[a.len()] = df[b[i]];
            for k in i.saturating_sub(band)..(i + band + 1).min(nb) {
                let c = d_bb.entry(i, k).1;
                if c != 0.0 {
                    for (r, y) in row.iter_mut().zip(&solution[k * cols..(k + 1) * cols]) {
                        *r -= c * y;
                    }
                }
            }
        }
        values.lu.solve_rows(&mut derivative_solution, cols);
        let (d_transfer, d_particular) = split(&derivative_solution, nb, a.len());
        let d_coupling = matrix(&entries.kept_rest, a.len(), |e| e.1);
        let schur = matrix(&entries.kept_kept, a.len(), |e| e.1)
            - &d_coupling * &values.transfer
            - &values.coupling * &d_transfer;
        let force = pick(df, &a) - &d_coupling * &particular - &values.coupling * &d_particular;
        BlockDerivative {
            schur,
            force: column(force),
        }
    }

    /// Half-bandwidth of D_bb in a block of `copies` copies: interleaved, its rows couple
    /// at most `copies` times the band of the coordinates apart.
    fn rest_band(&self, copies: usize) -> usize {
        copies * (self.rest_bandwidth + 1) - 1
    }

    /// The entries of D_bb and dD_bb/dw in a block of `copies` copies, formed once per
    /// pair of condensed coordinates within the matrices' band.
    fn rest_pairs(&self, block: &HarmonicBlock<'_>, copies: usize) -> RestPairs {
        let (count, reach) = (self.rest.len(), self.rest_bandwidth);
        let span = 2 * reach + 1;
        let mut pairs = vec![PairEntries::ZERO; count * span];
        for (ic, &row) in self.rest.iter().enumerate() {
            for kc in ic.saturating_sub(reach)..(ic + reach + 1).min(count) {
                pairs[ic * span + kc + reach - ic] = block.pair(row, self.rest[kc]);
            }
        }
        RestPairs {
            pairs,
            // One or two copies: a shift and a mask instead of divisions in the inner loops.
            shift: copies.trailing_zeros(),
            reach,
        }
    }

    /// The entries of a block of `copies` copies, and their w-derivatives, on the rows of
    /// the coordinates `rows` and the columns of `cols`, row-major in the layout of
    /// [`Self::partition`]; each pair of coordinates is formed once for all its copies.
    fn entries(
        &self,
        block: &HarmonicBlock<'_>,
        copies: usize,
        rows: Part,
        cols: Part,
    ) -> Vec<(f64, f64)> {
        let (row_dofs, col_dofs) = (self.dofs(rows), self.dofs(cols));
        let width = copies * col_dofs.len();
        let mut out = vec![(0.0, 0.0); copies * row_dofs.len() * width];
        for (ic, &row) in row_dofs.iter().enumerate() {
            for (jc, &col) in col_dofs.iter().enumerate() {
                let pair = block.pair(row, col);
                for (ci, cj) in (0..copies).flat_map(|ci| (0..copies).map(move |cj| (ci, cj))) {
                    let i = rows.position(ic, ci, row_dofs.len(), copies);
                    let j = cols.position(jc, cj, col_dofs.len(), copies);
                    out[i * width + j] = pair.at(ci, cj);
                }
            }
        }
        out
    }

    /// The coordinates of `part`.
    fn dofs(&self, part: Part) -> &[usize] {
        match part {
            Part::Kept => self.kept,
            Part::Rest => self.rest,
        }
    }
}

/// The kept (a) or the condensed (b) coordinates of a block.
#[derive(Clone, Copy)]
enum Part {
    Kept,
    Rest,
}

impl Part {
    /// Row (or column) of copy `copy` of the `index`-th of `count` coordinates in a block
    /// of `copies` copies, as [`Condenser::partition`] lays them out: kept ones in slot
    /// order (all cos, then all sin), condensed ones interleaving the copies.
    fn position(self, index: usize, copy: usize, count: usize, copies: usize) -> usize {
        match self {
            Part::Kept => copy * count + index,
            Part::Rest => copies * index + copy,
        }
    }
}

/// The matrix of `part` (the value or the w-derivative) of row-major entries with `rows`
/// rows.
fn matrix(entries: &[(f64, f64)], rows: usize, part: impl Fn((f64, f64)) -> f64) -> Mat<f64> {
    let cols = entries.len() / rows;
    Mat::from_fn(rows, cols, |i, j| part(entries[i * cols + j]))
}

/// The entries `rows` of v as a column.
fn pick(v: &[f64], rows: &[usize]) -> Mat<f64> {
    Mat::from_fn(rows.len(), 1, |i, _| v[rows[i]])
}

/// A column's entries.
fn column(m: Mat<f64>) -> Vec<f64> {
    (0..m.nrows()).map(|i| m[(i, 0)]).collect()
}

/// The row-major solution [Y | y] of `rows` rows and `kept` + 1 columns as the matrix Y
/// and the column y.
fn split(solution: &[f64], rows: usize, kept: usize) -> (Mat<f64>, Mat<f64>) {
    let cols = kept + 1;
    (
        Mat::from_fn(rows, kept, |i, j| solution[i * cols + j]),
        Mat::from_fn(rows, 1, |i, _| solution[i * cols + kept]),
    )
}

/// The dynamic stiffness of one harmonic r at w: the constant term's K for r = 0, else the
/// real form D_r(w) on (cos r, sin r) of the module documentation; entries are made on
/// demand for rows and columns given as (copy, coordinate), copy 0 for cos and 1 for sin.
struct HarmonicBlock<'a> {
    matrices: &'a PlainMatrices,
    r: usize,
    frequency: f64,
}

impl HarmonicBlock<'_> {
    /// The entries of D_r and dD_r/dw that the coordinates `row` and `col` give in every
    /// pair of copies.
    fn pair(&self, row: usize, col: usize) -> PairEntries {
        let p = self.matrices;
        let at = row * p.n + col;
        if self.r == 0 {
            return PairEntries {
                diagonal: (p.stiffness[at], 0.0),
                coupling: (0.0, 0.0),
            };
        }
        let (rf, w) = (self.r as f64, self.frequency);
        let rw = rf * w;
        let damping = p.damping[at] + w * p.gyroscopic[at];
        PairEntries {
            diagonal: (
                p.stiffness[at] - rw * rw * p.mass[at],
                -2.0 * rf * rw * p.mass[at],
            ),
            // d(r w (C + w G))/dw = r (C + 2 w G).
            coupling: (rw * damping, rf * (damping + w * p.gyroscopic[at])),
        }
    }
}

/// D_bb's entries by pairs of condensed coordinates: pair (ic, kc) at
/// `ic * (2 reach + 1) + kc + reach - ic` for |ic - kc| <= reach, the half-bandwidth of the
/// matrices among them (coordinates further apart are not coupled).
struct RestPairs {
    pairs: Vec<PairEntries>,
    /// log2 of the copies (1 or 2).
    shift: u32,
    reach: usize,
}

impl RestPairs {
    /// Entry (i, k) of D_bb and of its w-derivative, rows and columns interleaving the
    /// copies of each coordinate; zero outside the band.
    fn entry(&self, i: usize, k: usize) -> (f64, f64) {
        let (ic, kc) = (i >> self.shift, k >> self.shift);
        if ic.abs_diff(kc) > self.reach {
            return (0.0, 0.0);
        }
        let copy = (1 << self.shift) - 1;
        self.pairs[ic * (2 * self.reach + 1) + kc + self.reach - ic].at(i & copy, k & copy)
    }
}

/// Entry (value, w-derivative) of D_r for one pair of coordinates: Z_r on the copies'
/// diagonal, r w D from sin to cos and -r w D from cos to sin.
#[derive(Clone, Copy)]
struct PairEntries {
    diagonal: (f64, f64),
    coupling: (f64, f64),
}

impl PairEntries {
    const ZERO: PairEntries = PairEntries {
        diagonal: (0.0, 0.0),
        coupling: (0.0, 0.0),
    };

    /// The entry in the row of copy `row` and the column of copy `col` (0 cos, 1 sin).
    fn at(self, row: usize, col: usize) -> (f64, f64) {
        match (row, col) {
            (0, 0) | (1, 1) => self.diagonal,
            (0, _) => self.coupling,
            _ => (-self.coupling.0, -self.coupling.1),
        }
    }
}

/// M, K, C and G row-major: the condensation reads single entries in its inner loops.
struct PlainMatrices {
    n: usize,
    mass: Vec<f64>,
    stiffness: Vec<f64>,
    damping: Vec<f64>,
    gyroscopic: Vec<f64>,
}

impl PlainMatrices {
    fn new(p: &System) -> PlainMatrices {
        let n = p.size();
        let plain = |m: &Mat<f64>| (0..n * n).map(|k| m[(k / n, k % n)]).collect::<Vec<f64>>();
        PlainMatrices {
            n,
            mass: plain(&p.matrices.mass),
            stiffness: plain(&p.matrices.stiffness),
            damping: plain(&p.matrices.damping),
            gyroscopic: plain(&p.matrices.gyroscopic),
        }
    }
}

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

/// M, K, C and G by rows of the nonzeros of any of them, for products of D_r(w) with
/// vectors.
struct SparseMatrices {
    n: usize,
    /// Row i's entries are `starts[i]..starts[i + 1]`.
    starts: Vec<usize>,
    columns: Vec<usize>,
    /// K, M, C and G at each entry.
    values: Vec<[f64; 4]>,
}

impl SparseMatrices {
    fn new(p: &PlainMatrices) -> SparseMatrices {
        let n = p.n;
        let mut starts = vec![0];
        let (mut columns, mut values) = (Vec::new(), Vec::new());
        for i in 0..n {
            for j in 0..n {
                let at = i * n + j;
                let entry = [p.stiffness[at], p.mass[at], p.damping[at], p.gyroscopic[at]];
                if entry.iter().any(|&e| e != 0.0) {
                    columns.push(j);
                    values.push(entry);
                }
            }
            starts.push(columns.len());
        }
        SparseMatrices {
            n,
            starts,
            columns,
            values,
        }
    }

    /// D_r(w) v for a vector v of block r laid out as copies of the n coordinates (one for
    /// r = 0, cos then sin otherwise; the real form of the module documentation), and
    /// |D_r(w)| |v| row by row, the size of the terms summed.
    fn apply(&self, r: usize, frequency: f64, v: &[f64]) -> (Vec<f64>, Vec<f64>) {
        let n = self.n;
        let mut y = vec![0.0; v.len()];
        let mut size = vec![0.0; v.len()];
        let rw = r as f64 * frequency;
        for i in 0..n {
            for e in self.starts[i]..self.starts[i + 1] {
                let j = self.columns[e];
                let [k, m, c, g] = self.values[e];
                if r == 0 {
                    y[i] += k * v[j];
                    size[i] += (k * v[j]).abs();
                    continue;
                }
                let z = k - rw * rw * m;
                let coupling = rw * (c + frequency * g);
                y[i] += z * v[j] + coupling * v[n + j];
                y[n + i] += z * v[n + j] - coupling * v[j];
                size[i] += (z * v[j]).abs() + (coupling * v[n + j]).abs();
                size[n + i] += (z * v[n + j]).abs() + (coupling * v[j]).abs();
            }
        }
        (y, size)
    }
}

/// The largest |i - j| over nonzero entries (i, j) of M, K, C and G among `dofs` (indices
/// into `dofs`).
fn bandwidth(problem: &System, dofs: &[usize]) -> usize {
    let matrices = problem.matrices.all();
    let mut width = 0;
    for (i, &r) in dofs.iter().enumerate() {
        for (j, &c) in dofs.iter().enumerate().skip(i + width + 1) {
            if matrices
                .iter()
                .any(|m| m[(r, c)] != 0.0 || m[(c, r)] != 0.0)
            {
                width = j - i;
            }
        }
    }
    width
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fe;
    use crate::force::CubicSpring;
    use crate::model::Model;

    /// The reference rotor on its linearised bearings with hardening cubic springs on both
    /// directions of both bearings (the four kept coordinates), unbalance and a constant
    /// load, so that every harmonic block carries motion and the first a force.
    fn cubic_reference_rotor() -> System {
        let model = Model::from_toml_str(crate::examples::REFERENCE_ROTOR, None).unwrap();
        let matrices = fe::assemble(&model, fe::Bearings::Linearised);
        let n = matrices.dofs();
        let unbalance = fe::unbalance_force(&model, n);
        let dofs = [
            fe::dof(0, fe::Direction::Ux),
            fe::dof(0, fe::Direction::Uy),
            fe::dof(20, fe::Direction::Ux),
            fe::dof(20, fe::Direction::Uy),
        ];
        System {
            constant_force: (0..n)
                .map(|d| if d == dofs[1] { -200.0 } else { 0.0 })
                .collect(),
            unbalance_re: unbalance.iter().map(|f| f.re).collect(),
            unbalance_im: unbalance.iter().map(|f| f.im).collect(),
            nonlinear: dofs
                .iter()
                .map(|&d| Box::new(CubicSpring::new(d, 0.0, 3e19, 1e-4)) as Box<dyn NonlinearForce>)
                .collect(),
            ..System::unloaded(matrices)
        }
    }

    #[test]
    fn a_residual_refined_from_a_condensation_at_another_speed_is_the_one_condensed_there() {
        let mut hb = CondensedBalance::new(cubic_reference_rotor(), HbOptions::new(3)).unwrap();
        let x: Vec<f64> = (0..hb.unknowns())
            .map(|i| 3e-6 * ((i * 7) as f64 * 0.618).sin())
            .collect();
        let w0 = std::f64::consts::TAU * 180.0;
        let near = hb.condense(w0).unwrap();
        let (stale, _) = hb.residual(&near, &x);
        for relative in [1e-6, 1e-4, 3e-3] {
            let w = w0 * (1.0 + relative);
            let (refined, _) = hb
                .residual_near(&near, &x, w)
                .expect("the refinement converges this near");
            let at = hb.condense(w).unwrap();
            let (direct, scale) = hb.residual(&at, &x);
            let worst = |other: &[f64]| {
                direct
                    .iter()
                    .zip(other)
                    .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()))
            };
            // Both are the condensed residual at w, each to its own round-off (the residual
            // is a small difference of large terms): the refined one must be as good as the
            // factorisation's, far below the Newton tolerance of 1e-10 of the scale, while
            // the residual of the condensation at w0 differs by the change of speed.
            assert!(
                worst(&refined) < 1e-12 * scale,
                "{relative:e}: refined {:e} of {scale:e}",
                worst(&refined)
            );
            assert!(worst(&stale) > 1e3 * worst(&refined).max(1e-14 * scale));
        }
    }
}
