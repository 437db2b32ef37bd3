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

mod block;
mod matrices;
mod residual;

use block::{Condenser, RestPairs};
use matrices::{bandwidth, PlainMatrices, SparseMatrices};

use std::collections::HashMap;
use std::sync::OnceLock;

use faer::Mat;
use rayon::prelude::*;

use super::stability::{FloquetModel, FloquetProblem, Stability};
use super::{HarmonicBalance, HbOptions};
use crate::error::Result;
use crate::fe::SystemMatrices;
use crate::force::{Kinematics, NonlinearForce};
use crate::linalg::banded::BandedLu;
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
    /// # Errors The errors of [`System::check`] and of [`HarmonicBalance::new`] for the
    /// condensed problem: [`Error::InvalidOption`](crate::error::Error::InvalidOption) for
    /// sizes that differ, a nonlinear force on a coordinate outside the problem, or
    /// `options.samples` not above twice `options.harmonics`.
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
    /// # Errors [`Error::Singular`](crate::error::Error::Singular) or
    /// [`Error::NotConverged`](crate::error::Error::NotConverged) when the reduction or the
    /// monodromy fails.
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
    /// # Errors [`Error::Singular`](crate::error::Error::Singular) when D_bb is singular: w
    /// sits on a resonance of the linear part with the kept coordinates held fixed, where
    /// the rest cannot be condensed.
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
