//! What continuation asks of a harmonic balance ([`Periodic`]), answered by the full model
//! ([`HarmonicBalance`]) and by the condensed one ([`CondensedBalance`]).

use super::balance::{HarmonicBalance, HbSolution};
use super::condensation::CondensedBalance;
use super::stability::{FloquetModel, FloquetProblem};
use super::HbOptions;
use crate::error::Result;
use faer::Mat;

/// What continuation asks of a harmonic balance, so that the full ([`HarmonicBalance`]) and
/// the condensed ([`CondensedBalance`]) problem are followed by the same path code.
pub trait Periodic {
    /// The discretisation and Newton settings.
    fn options(&self) -> &HbOptions;
    /// Newton-Raphson at one frequency; never returns an unconverged point.
    fn solve(&mut self, frequency: f64, guess: &[f64]) -> Result<HbSolution>;
    /// R(x, w) and |terms that cancel in it|; not finite where it cannot be evaluated.
    fn residual_at(&mut self, x: &[f64], frequency: f64) -> (Vec<f64>, f64);
    /// dR/dx and dR/dw at (x, w).
    fn derivatives(&mut self, x: &[f64], frequency: f64) -> Derivatives;
    /// The Floquet problem (monodromy matrix) of the periodic solution (x, w).
    fn floquet_problem(&mut self, x: &[f64], frequency: f64) -> Result<FloquetProblem>;
    /// Whether the caller asked the path to stop (asked before each step).
    fn stop_requested(&self) -> bool {
        false
    }
    /// Lets [`Self::residual_at`] compute residuals as exactly but more cheaply, with other
    /// round-off (the condensed problem refines them from a condensation at a nearby
    /// frequency). On only while folds and bifurcations are located between the points of
    /// a path already followed: the path itself keeps its arithmetic, because where it
    /// goes on the non-smooth reference branches hangs on round-off (with refined
    /// residuals throughout, the 60 um sweep stopped at 45.96 Hz instead of reaching
    /// 750 Hz).
    fn refine_residuals(&mut self, _on: bool) {}
    /// Told of each point of the path once it is on the path for good, just after it was
    /// solved or reached, so that what the point's frequency made can be kept for it (the
    /// condensed problem keeps the point's full coefficients from its condensation, which
    /// recovering them later would make again).
    fn on_path(&mut self, _solution: &HbSolution) {}
}

/// dR/dx and dR/dw.
pub struct Derivatives {
    /// dR/dx.
    pub jacobian: Mat<f64>,
    /// dR/dw at fixed x.
    pub frequency_derivative: Vec<f64>,
}

impl Periodic for HarmonicBalance {
    fn options(&self) -> &HbOptions {
        HarmonicBalance::options(self)
    }
    fn solve(&mut self, frequency: f64, guess: &[f64]) -> Result<HbSolution> {
        HarmonicBalance::solve(self, frequency, guess)
    }
    fn residual_at(&mut self, x: &[f64], frequency: f64) -> (Vec<f64>, f64) {
        let r = self.residual(x, frequency);
        (r.values, r.scale)
    }
    fn derivatives(&mut self, x: &[f64], frequency: f64) -> Derivatives {
        let lin = self.linearise(x, frequency);
        Derivatives {
            jacobian: lin.jacobian,
            frequency_derivative: lin.frequency_derivative,
        }
    }
    /// The monodromy matrix of the whole model (2n states): for small models; a large
    /// one is condensed ([`CondensedBalance`]).
    fn floquet_problem(&mut self, x: &[f64], frequency: f64) -> Result<FloquetProblem> {
        self.check_arguments(frequency, x)?;
        let tangents = self.sampled_tangents(x, frequency);
        Ok(FloquetModel::new(&self.problem().matrices)?.problem(frequency, &tangents))
    }
}

/// The condensed problem is condensed at every frequency the corrector tries (the Schur
/// complement depends on w); while refining ([`Periodic::refine_residuals`]) a residual
/// alone (the line search's trial points, the predictor) is refined from the last
/// condensation instead, exact to round-off. Where condensation fails (a resonance of the
/// condensed coordinates) the residual is NaN, which the corrector treats as a failed
/// step.
impl Periodic for CondensedBalance {
    fn options(&self) -> &HbOptions {
        CondensedBalance::options(self)
    }
    fn solve(&mut self, frequency: f64, guess: &[f64]) -> Result<HbSolution> {
        CondensedBalance::solve(self, frequency, guess)
    }
    fn residual_at(&mut self, x: &[f64], frequency: f64) -> (Vec<f64>, f64) {
        if !self.refining() {
            return self
                .with_condensed(frequency, |hb, condensed| hb.residual(condensed, x))
                .unwrap_or_else(|_| (vec![f64::NAN; x.len()], f64::NAN));
        }
        self.with_nearby(
            frequency,
            |hb, condensed| hb.residual_near(condensed, x, frequency),
            |hb, condensed| hb.residual(condensed, x),
        )
        .unwrap_or_else(|_| (vec![f64::NAN; x.len()], f64::NAN))
    }
    fn derivatives(&mut self, x: &[f64], frequency: f64) -> Derivatives {
        let (jacobian, frequency_derivative) = self
            .with_condensed(frequency, |hb, condensed| hb.linearise(condensed, x))
            .unwrap_or_else(|_| {
                (
                    Mat::from_fn(x.len(), x.len(), |_, _| f64::NAN),
                    vec![f64::NAN; x.len()],
                )
            });
        Derivatives {
            jacobian,
            frequency_derivative,
        }
    }
    /// The monodromy matrix of a Craig-Bampton model of the linear part
    /// ([`CondensedBalance::stability`]).
    fn floquet_problem(&mut self, x: &[f64], frequency: f64) -> Result<FloquetProblem> {
        CondensedBalance::floquet_problem(self, x, frequency)
    }
    fn refine_residuals(&mut self, on: bool) {
        self.set_refining(on);
    }
    fn on_path(&mut self, solution: &HbSolution) {
        self.keep_recovered(solution);
    }
}
