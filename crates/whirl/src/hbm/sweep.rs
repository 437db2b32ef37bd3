//! The periodic response of a model followed over a speed range: the problem built from the
//! model file (full finite-element model, roller bearings as a [`CageModel`] or the
//! forcing-function law), condensed onto the bearing coordinates, started from the static
//! equilibrium, continued in speed with Floquet stability at every point. What `whirl hbm`
//! runs.

use std::time::Instant;

use serde::Serialize;

use super::bearings::{caged_bearings, CageModel};
use super::branch::{Branch, BranchEnd};
use super::condensation::DEFAULT_STABILITY_MODES;
use super::continuation::{continuation, continuation_sharing, solutions_at, ContinuationOptions};
use super::fourier::{check_counts, cos_slot, sin_slot, MAX_SAMPLES};
use super::parallel::on_threads;
use super::periodic::{Derivatives, Periodic};
use super::resolution;
use super::stability::{FloquetProblem, Stability};
use super::{default_samples, CondensedBalance, HbOptions, HbSolution};
use crate::bearing::forcing_bearings;
use crate::bearing::ContactLaw;
use crate::error::{Error, Result};
use crate::fe::Bearings;
use crate::force::no_forces;
use crate::model::Model;
use crate::progress::{tell, Progress};
use crate::reduce::CraigBampton;
use crate::system::build;
use crate::system::System;
use crate::time::static_equilibrium;
use crate::units::rad_s_to_hz;

/// What to solve.
#[derive(Debug, Clone, Serialize)]
pub struct SweepOptions {
    /// First speed, rad/s.
    pub from: f64,
    /// Last speed, rad/s.
    pub to: f64,
    /// Harmonics H of the running speed.
    pub harmonics: usize,
    /// AFT samples per period; `None` for [`default_samples`].
    pub samples: Option<usize>,
    /// Contact law of the roller bearings: Hertz or the forcing function.
    pub contact: ContactLaw,
    /// How the Hertz bearings' roller passage is made periodic.
    pub cage: CageModel,
    /// Approach below which the Hertz law is blended to bounded curvature, m
    /// ([`HertzBearing::smoothed`](crate::bearing::HertzBearing::smoothed)); 0 (the
    /// default) for the exact law. On the reference rotor (H = 5, 10 and 20 um, sweeps
    /// from 1 Hz ending exactly at 100, 200 and 330 Hz) 0.01 um moves the disk 1X by at most
    /// 2.4e-5 and the bearing 1X and 2X by at most 8.3e-5 relative, but Hill's
    /// bifurcations by up to 2.5 Hz (docs/theory.md, section 7): the exact law stays the
    /// default.
    pub contact_smoothing: f64,
    /// Floquet stability (monodromy matrix) at every point.
    pub stability: bool,
    /// Fixed-interface modes of the stability model ([`CondensedBalance::stability`]).
    pub stability_modes: usize,
    /// Solve on a Craig-Bampton model with this many fixed-interface modes (as the time
    /// integrators do) instead of the full model; `None` for the full model. The
    /// condensation is exact either way, so this only trades the reduction's truncation
    /// error for speed.
    pub reduction: Option<usize>,
    /// Step control.
    pub continuation: ContinuationOptions,
    /// Speeds (rad/s) at which to solve exactly on every crossing of the branch
    /// ([`Sweep::at_speeds`]), e.g. to compare with time marching there.
    pub exact_speeds: Vec<f64>,
}

/// The roller bearings' contact law of a sweep by default: harmonic balance needs a force
/// law of the displacement.
pub const DEFAULT_CONTACT: ContactLaw = ContactLaw::Hertz;

/// The approach below which the Hertz law is blended to bounded curvature, by default, m:
/// none, the exact law.
pub const DEFAULT_CONTACT_SMOOTHING: f64 = 0.0;

impl SweepOptions {
    /// From `from` to `to` (rad/s) with `harmonics` harmonics, Hertz bearings averaged over
    /// the roller passage, with stability.
    pub fn new(from: f64, to: f64, harmonics: usize) -> SweepOptions {
        SweepOptions {
            from,
            to,
            harmonics,
            samples: None,
            contact: DEFAULT_CONTACT,
            cage: CageModel::DEFAULT,
            contact_smoothing: DEFAULT_CONTACT_SMOOTHING,
            stability: true,
            stability_modes: DEFAULT_STABILITY_MODES,
            reduction: None,
            // Contacts that open and close make the tangent wiggle on a small scale; 0.5 rad
            // instead of 0.15 halves the points on the reference rotor, and folds are still
            // located on the branch.
            continuation: ContinuationOptions {
                max_turn: 0.5,
                ..ContinuationOptions::default()
            },
            exact_speeds: Vec::new(),
        }
    }

    /// A sentence saying how the bearings are modelled, for every output.
    pub fn describe_bearings(&self) -> String {
        match self.contact {
            ContactLaw::Hertz if self.contact_smoothing > 0.0 => format!(
                "Hertz contacts blended to bounded curvature below an approach of {:.3} um, {}",
                self.contact_smoothing * 1e6,
                self.cage.describe()
            ),
            ContactLaw::Hertz => format!("Hertz contacts, {}", self.cage.describe()),
            ContactLaw::Forcing => "forcing-function law (eq. 3.12), no rollers".into(),
            ContactLaw::Linear | ContactLaw::Lagrange => self.contact.name().into(),
        }
    }
}

/// A followed branch with every point's full Fourier coefficients.
#[derive(Debug, Clone, Serialize)]
pub struct Sweep {
    /// The branch (condensed coefficients, stability, folds, bifurcations).
    pub branch: Branch,
    /// Coefficients x[slot * n + c] of every branch point in the solver's n coordinates:
    /// the model's DOFs, or the Craig-Bampton coordinates with a reduction.
    pub coefficients: Vec<Vec<f64>>,
    /// Number of coordinates n.
    pub dofs: usize,
    /// The reduction the coefficients are in, if any.
    #[serde(skip)]
    pub reduction: Option<CraigBampton>,
    /// The solutions at each of [`SweepOptions::exact_speeds`], in that order.
    pub at_speeds: Vec<AtSpeed>,
    /// How the bearings were modelled.
    pub bearings: String,
    /// The speed (rad/s) the branch was followed up from to reach the first speed, where
    /// Newton from the static equilibrium did not converge at it; `None` when it did.
    pub approached_from: Option<f64>,
    /// Wall-clock time of the continuation, stability and recovery, s.
    pub wall_time_s: f64,
}

impl Sweep {
    /// Harmonics H.
    pub fn harmonics(&self) -> usize {
        self.branch.options.harmonics
    }

    /// Amplitude (zero to peak) of harmonic `r` of DOF `dof` at branch point `point`; the
    /// constant term for r = 0.
    pub fn amplitude(&self, point: usize, dof: usize, r: usize) -> f64 {
        self.amplitude_of(&self.coefficients[point], dof, r)
    }

    /// As [`Sweep::amplitude`], for coefficients in the same layout (those of a branch
    /// point, or of an [`AtSpeed`] solution).
    pub fn amplitude_of(&self, coefficients: &[f64], dof: usize, r: usize) -> f64 {
        let coefficient = |slot: usize| self.physical(coefficients, dof, slot);
        if r == 0 {
            return coefficient(0);
        }
        coefficient(cos_slot(r)).hypot(coefficient(sin_slot(r)))
    }

    /// Fourier coefficient `slot` of physical DOF `dof` in `coefficients`.
    fn physical(&self, coefficients: &[f64], dof: usize, slot: usize) -> f64 {
        let n = self.dofs;
        let x = &coefficients[slot * n..(slot + 1) * n];
        match &self.reduction {
            None => x[dof],
            Some(cb) => (0..n).map(|j| cb.transform[(dof, j)] * x[j]).sum(),
        }
    }
}

/// One periodic solution at an exact speed where the branch crosses it.
#[derive(Debug, Clone, Serialize)]
pub struct AtSpeed {
    /// Speed, rad/s.
    pub speed: f64,
    /// Index of the branch point before the crossing: solutions are in path order, and
    /// more than one means the branch crosses the speed on coexisting orbits.
    pub after: usize,
    /// Coefficients in the layout of [`Sweep::coefficients`].
    pub coefficients: Vec<f64>,
    /// Floquet stability (computed even when the sweep skips it).
    pub stability: Stability,
}

/// The harmonic balance problem of `model` at speed `speed` (rad/s), and the static
/// equilibrium to start from.
///
/// # Errors
/// Linear and Lagrange bearings are refused (with what to use instead); bearings with
/// waviness under the Hertz law ([`CagedBearing`](super::bearings::CagedBearing)); a static
/// equilibrium that does not converge.
pub fn model_problem(
    model: &Model,
    reduction: Option<usize>,
    speed: f64,
    contact: ContactLaw,
    cage: CageModel,
    smoothing: f64,
) -> Result<(System, Vec<f64>, Option<CraigBampton>)> {
    if model.roller_bearings.is_empty() && !model.has_squeeze_films() {
        return Err(Error::Unsupported(
            "the model has no roller bearing and no squeeze-film damper: its periodic \
             response is linear; use `whirl unbalance`"
                .into(),
        ));
    }
    let hertz =
        move |m: &Model, c: &dyn Fn(usize) -> Option<usize>| caged_bearings(m, c, cage, smoothing);
    let apart = Bearings::NonlinearApart;
    let built = match contact {
        ContactLaw::Hertz => build(model, reduction, apart, &hertz)?,
        ContactLaw::Forcing => build(model, reduction, apart, &forcing_bearings)?,
        // The films are the nonlinearity (the solvers' systems always take their force).
        ContactLaw::Linear if model.has_squeeze_films() => {
            build(model, reduction, Bearings::Linearised, &no_forces)?
        }
        ContactLaw::Linear => {
            return Err(Error::Unsupported(
                "linear bearings give a linear periodic response: use `whirl unbalance`".into(),
            ))
        }
        ContactLaw::Lagrange => {
            return Err(Error::Unsupported(
                "rigid (Lagrange-multiplier) rollers exist only in the central difference; \
                 harmonic balance needs a force law: use hertz or forcing"
                    .into(),
            ))
        }
    };
    let mut problem = built.system;
    let rest = vec![0.0; problem.size()];
    let equilibrium = static_equilibrium(&mut problem, &rest, speed)?;
    Ok((problem, equilibrium, built.coordinates.reduction))
}

/// Follows the periodic response of `model` from `options.from` to `options.to`.
///
/// # Errors
/// As [`model_problem`], or when the first point does not converge; a branch that stops
/// early is returned with why ([`super::BranchEnd`]).
pub fn sweep(model: &Model, options: &SweepOptions) -> Result<Sweep> {
    sweep_with_progress(model, options, None)
}

/// As [`sweep`], telling `progress` how far the path has got (the highest frequency it
/// has tried, in Hz from `options.from` to `options.to`; the stability, solved after the
/// path, is not reported). `progress` may stop the sweep.
///
/// # Errors
/// As [`sweep`]; [`Error::Interrupted`] when `progress` stopped it.
pub fn sweep_with_progress(
    model: &Model,
    options: &SweepOptions,
    progress: Option<&Progress>,
) -> Result<Sweep> {
    // On one of rayon's threads: the parallel parts of every condensation and AFT then
    // start on the path's thread and are shared with an idle one, instead of the path's
    // thread waking the pool and sleeping until it is done, tens of thousands of times.
    rayon::scope(|_| follow_sweep(model, options, progress))
}

/// [`sweep_with_progress`] on the calling thread.
fn follow_sweep(
    model: &Model,
    options: &SweepOptions,
    progress: Option<&Progress>,
) -> Result<Sweep> {
    check(options)?;
    let start = Instant::now();
    let (balance, equilibrium, reduction) = condensed_problem(model, options)?;
    // The equilibrium holds every coordinate of the model.
    let dofs = equilibrium.len();
    let mut hb = Reporting::new(balance, progress, options);
    // A copy of the problem for each other thread of rayon's: the folds and bifurcations
    // are located on all of them, and the bifurcations checked. The copies are built from the model as `hb` was, so every job gives the
    // bits it would on `hb` ([`continuation_sharing`]).
    let another = || condensed_problem(model, options).map(|(balance, ..)| balance);
    let mut helpers = (1..rayon::current_num_threads())
        .map(|_| Ok(Reporting::new(another()?, None, options)))
        .collect::<Result<Vec<_>>>()?;
    // Start at the static equilibrium: the unbalance force is small at the first speed.
    let mut guess = vec![0.0; hb.inner.unknowns()];
    for (i, &d) in hb.inner.kept().iter().enumerate() {
        guess[i] = equilibrium[d];
    }
    let mut continuation_options = options.continuation;
    continuation_options.stability = options.stability;
    let (guess, approached_from) =
        start_on_branch(&mut hb, options.from, guess, &continuation_options)?;
    let mut branch = continuation_sharing(
        &mut hb,
        &mut helpers,
        options.from,
        options.to,
        &guess,
        &continuation_options,
    )
    .map_err(|e| with_cage_hint(e, options))?;
    let coefficients = branch
        .points
        .iter()
        .map(|p| hb.inner.recover(&p.solution))
        .collect::<Result<Vec<_>>>()?;
    let at_speeds = solutions_at_speeds(&mut hb.inner, &branch, &options.exact_speeds)?;
    let problems = std::iter::once(hb)
        .chain(helpers)
        .map(|h| h.inner)
        .collect();
    check_resolution(problems, &mut branch, options.stability_modes)?;
    Ok(Sweep {
        branch,
        coefficients,
        at_speeds,
        dofs,
        reduction,
        bearings: options.describe_bearings(),
        approached_from,
        wall_time_s: start.elapsed().as_secs_f64(),
    })
}

/// `e` from a path that failed, with a hint where the cage is frozen under Hertz contacts.
fn with_cage_hint(e: Error, options: &SweepOptions) -> Error {
    match (options.contact, options.cage) {
        (ContactLaw::Hertz, CageModel::Frozen) => e.map_message(|m| {
            format!(
                "{m}. With the cage frozen, a single roller under the load leaves the journal \
                 free sideways inside the clearance: set the bearing's cage_angle half a \
                 roller pitch off, or use the passage average"
            )
        }),
        _ => e,
    }
}

/// Every solution of `branch` at each of `speeds` (rad/s), in that order, with its full
/// coefficients.
fn solutions_at_speeds(
    hb: &mut CondensedBalance,
    branch: &Branch,
    speeds: &[f64],
) -> Result<Vec<AtSpeed>> {
    let mut at_speeds = Vec::new();
    for &speed in speeds {
        for c in solutions_at(hb, branch, speed)?.crossings {
            at_speeds.push(AtSpeed {
                speed,
                after: c.after,
                coefficients: hb.recover(&c.solution)?,
                stability: c.stability,
            });
        }
    }
    Ok(at_speeds)
}

/// Where Newton from the static equilibrium is trusted: at 1 Hz (rad/s) the unbalance
/// force of any rotor is small against its bearings' static load.
const STANDSTILL: f64 = std::f64::consts::TAU;

/// The start of a sweep at `from`: `guess` (the static equilibrium) where Newton converges
/// from it, or else the orbit at `from` of the branch followed up from [`STANDSTILL`], with
/// that speed. Higher up the unbalance can carry the orbit far from equilibrium (at 60 um
/// of clearance Newton fails at 100 Hz), and a start on the branch from standstill makes the
/// answer the same as a sweep's from the bottom of the range.
///
/// # Errors
/// Newton's failure at `from` when the branch from standstill does not reach it either.
fn start_on_branch(
    hb: &mut Reporting,
    from: f64,
    guess: Vec<f64>,
    options: &ContinuationOptions,
) -> Result<(Vec<f64>, Option<f64>)> {
    if from <= STANDSTILL {
        return Ok((guess, None));
    }
    let direct = match hb.solve(from, &guess) {
        Ok(_) => return Ok((guess, None)),
        Err(e) => e,
    };
    let approach = ContinuationOptions {
        stability: false,
        ..*options
    };
    match continuation(hb, STANDSTILL, from, &guess, &approach) {
        Ok(branch) if matches!(branch.end, BranchEnd::Reached) => {
            let last = branch
                .points
                .last()
                .map(|p| p.solution.coefficients.clone());
            Ok((last.unwrap_or(guess), Some(STANDSTILL)))
        }
        Ok(_) | Err(_) => Err(direct.map_message(|m| {
            format!(
                "{m}. Newton started from the static equilibrium, and the branch followed up \
                 from 1 Hz does not reach this speed either: start the sweep lower"
            )
        })),
    }
}

/// The condensed harmonic balance of `model` as `options` ask, the static equilibrium (at
/// the first speed) to start from, and the reduction when one is asked for.
///
/// # Errors
/// As [`model_problem`] and [`CondensedBalance::new`].
fn condensed_problem(
    model: &Model,
    options: &SweepOptions,
) -> Result<(CondensedBalance, Vec<f64>, Option<CraigBampton>)> {
    let (problem, equilibrium, reduction) = model_problem(
        model,
        options.reduction,
        options.from,
        options.contact,
        options.cage,
        options.contact_smoothing,
    )?;
    let mut hb_options = HbOptions::new(options.harmonics);
    if let Some(samples) = options.samples {
        hb_options.samples = samples;
    }
    let balance =
        CondensedBalance::new(problem, hb_options)?.with_stability_modes(options.stability_modes);
    Ok((balance, equilibrium, reduction))
}

/// Checks every bifurcation of `branch` at twice its AFT samples and twice the
/// `stability_modes` of its stability model ([`super::resolution`]): two Newton solves and
/// two monodromy matrices of twice the states each (on the reference rotor with the default
/// counts, 1-750 Hz: 4.8 s of the sweep's 36 s of CPU). Not checked when twice the samples
/// exceed [`MAX_SAMPLES`].
///
/// The checks are independent (each condenses at its own speeds, and a condensation is
/// reused only at the speed it was made at), so they run on rayon's threads, each thread
/// with its own copy of the problem, one of `problems` ([`on_threads`]): every check gives
/// the bits a single thread would.
///
/// # Errors
/// When a Floquet problem cannot be built or solved.
fn check_resolution(
    problems: Vec<CondensedBalance>,
    branch: &mut Branch,
    stability_modes: usize,
) -> Result<()> {
    let samples = 2 * branch.options.samples;
    let count = branch.bifurcations.len();
    if count == 0 || samples > MAX_SAMPLES {
        return Ok(());
    }
    let mut fine = problems
        .into_iter()
        .map(|hb| {
            Ok(hb
                .with_samples(samples)?
                .with_stability_modes(2 * stability_modes))
        })
        .collect::<Result<Vec<_>>>()?;
    let checked = on_threads(&mut fine, count, |fine, k| {
        resolution::check(fine, branch, &branch.bifurcations[k])
    })?;
    for (bifurcation, check) in branch.bifurcations.iter_mut().zip(checked) {
        bifurcation.resolution = Some(check);
    }
    Ok(())
}

/// A harmonic balance that tells a [`Progress`] how far the path has got, and asks the
/// path to stop once told to.
struct Reporting<'a> {
    inner: CondensedBalance,
    progress: Option<&'a Progress>,
    /// The sweep's range and the highest frequency tried so far, rad/s.
    from: f64,
    to: f64,
    furthest: f64,
    /// The progress said stop.
    stopped: bool,
}

/// How far behind the furthest speed reached a solve is named in the progress, Hz.
const BEHIND_HZ: f64 = 0.05;

impl Reporting<'_> {
    /// `inner` reporting to `progress` over the sweep's range.
    fn new<'a>(
        inner: CondensedBalance,
        progress: Option<&'a Progress>,
        options: &SweepOptions,
    ) -> Reporting<'a> {
        Reporting {
            inner,
            progress,
            from: options.from,
            to: options.to,
            furthest: options.from,
            stopped: false,
        }
    }

    fn report(&mut self, frequency: f64) {
        if self.progress.is_none() {
            return;
        }
        self.furthest = self.furthest.max(frequency).min(self.to);
        let (top, to) = (rad_s_to_hz(self.furthest), rad_s_to_hz(self.to));
        // Behind the furthest speed the path is turning back past a fold, or, once it has
        // reached the end, the changes of stability are being located: say where.
        let at = rad_s_to_hz(frequency);
        let behind = top - at > BEHIND_HZ;
        let flow = tell(
            self.progress,
            top - rad_s_to_hz(self.from),
            to - rad_s_to_hz(self.from),
            || {
                if behind {
                    format!("{top:.1} Hz of {to:.1} Hz (solving at {at:.1} Hz)")
                } else {
                    format!("{top:.1} Hz of {to:.1} Hz")
                }
            },
        );
        self.stopped |= flow.is_break();
    }
}

impl Periodic for Reporting<'_> {
    fn options(&self) -> &HbOptions {
        self.inner.options()
    }
    fn solve(&mut self, frequency: f64, guess: &[f64]) -> Result<HbSolution> {
        self.report(frequency);
        Periodic::solve(&mut self.inner, frequency, guess)
    }
    fn residual_at(&mut self, x: &[f64], frequency: f64) -> (Vec<f64>, f64) {
        self.report(frequency);
        self.inner.residual_at(x, frequency)
    }
    fn derivatives(&mut self, x: &[f64], frequency: f64) -> Derivatives {
        self.inner.derivatives(x, frequency)
    }
    fn floquet_problem(&mut self, x: &[f64], frequency: f64) -> Result<FloquetProblem> {
        self.inner.floquet_problem(x, frequency)
    }
    fn stop_requested(&self) -> bool {
        self.stopped
    }
    fn on_path(&mut self, solution: &HbSolution) {
        self.inner.on_path(solution);
    }
}

fn check(options: &SweepOptions) -> Result<()> {
    let bad = |m: String| Err(Error::InvalidOption(m));
    if !(options.from.is_finite() && options.from > 0.0 && options.to.is_finite()) {
        return bad(format!(
            "harmonic balance needs positive speeds, got {} to {} rad/s",
            options.from, options.to
        ));
    }
    if options.to <= options.from {
        return bad(format!(
            "the last speed ({} rad/s) must exceed the first ({} rad/s)",
            options.to, options.from
        ));
    }
    // Before the model is built: the counts size every buffer of the transforms.
    let samples = options
        .samples
        .unwrap_or_else(|| default_samples(options.harmonics));
    check_counts(options.harmonics, samples)
}
