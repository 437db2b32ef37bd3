//! Extracting a forcing function (thesis 3.2.2, eq. 3.12) from the Hertz model.
//!
//! For each speed the rotor runs in time on its Hertz bearings (Craig-Bampton reduced,
//! central difference, unbalance and gravity from the model, starting from the static
//! equilibrium). From the settled part of the record, the bearing node's displacement u
//! gives the radial deflection u_r = |u| and the Hertz contact force at that displacement,
//! F = |mean over the cage positions of one roller passage of F_Hertz(u)|:
//!
//! - averaged over the cage, because the law has no roller angle: it can stand only for
//!   the average. At one instant the force at a given u_r scatters by about +-10 % as the
//!   rollers pass (varying compliance); fitted in log-log that scatter flattens each
//!   speed's slope (regression dilution), and the slope is the contact's stiffness. For a
//!   bearing without skew or waviness the cage-averaged force field is central, so its
//!   stiffness across the deflection is f/u_r, exactly the law's.
//! - elastic only: the contact damping is set to zero, because eq. 3.12 is a
//!   force-deflection law without a rate term.
//! - at zero slope: the recorded channels hold translations only, so the shaft's slope at
//!   the bearing is taken as zero (it matters only for a bearing with roller tilt).
//!
//! The law is then fitted to the samples ([`crate::bearing::forcing_regression`]). The speeds run in
//! parallel.

mod report;

pub use report::{ForcingFitReport, ForcingFitSummary};

use std::f64::consts::PI;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Arc;
use std::time::Instant;

use rayon::prelude::*;
use serde::Serialize;

use crate::bearing::forcing_regression::{fit_forcing_law, law_force, own_power_law, quality};
use crate::bearing::forcing_regression::{in_contact, ForcingPoint};
use crate::bearing::{ContactLaw, HertzBearing};
use crate::error::{Error, InputError, Result};
use crate::force::NonlinearForce;
use crate::given::{mode_count, unknown_option, Given, SetByName, MAX_MODES};
use crate::model::{Clearance, ForcingFunction, Model, RollerBearing};
use crate::progress::Progress;
use crate::system::SpeedProfile;
use crate::time::{simulate, SimulationOptions, DEFAULT_MODES};

/// How the Hertz model is run for a fit.
#[derive(Debug, Clone, PartialEq)]
pub struct ForcingFitOptions {
    /// Simulated time per speed, s.
    pub duration: f64,
    /// Time discarded before sampling, s.
    pub settle: f64,
    /// Craig-Bampton fixed-interface modes; `None` for the full model.
    pub reduction: Option<usize>,
    /// Time step, s; `None` for the simulation's default ([`crate::time::STABLE_FRACTION`] of the
    /// central difference's limit).
    pub step: Option<f64>,
    /// Samples kept per speed, evenly spaced over the settled record (2 to
    /// [`MAX_SAMPLES_PER_SPEED`]; a shorter record gives each of its steps once).
    pub samples_per_speed: usize,
}

/// Simulated time per speed by default, s.
pub const DEFAULT_FIT_DURATION: f64 = 0.3;
/// Time discarded before sampling by default, s.
pub const DEFAULT_FIT_SETTLE: f64 = 0.2;

impl Default for ForcingFitOptions {
    fn default() -> Self {
        ForcingFitOptions {
            duration: DEFAULT_FIT_DURATION,
            settle: DEFAULT_FIT_SETTLE,
            reduction: Some(DEFAULT_MODES),
            step: None,
            samples_per_speed: 2000,
        }
    }
}

/// A forcing-function fit as asked for (`whirl fit-forcing`, `whirl.fit_forcing`); `None`
/// is the library's default.
#[derive(Debug, Clone, Default)]
pub struct FitForcingRequest {
    /// Spin speeds to fit at, rad/s (no default: the law is meant for these speeds).
    pub speeds: Option<Vec<f64>>,
    /// The roller bearing, by its order in the model file; `None` for the first.
    pub bearing: Option<usize>,
    /// Simulated time per speed, s; `None` for [`DEFAULT_FIT_DURATION`].
    pub duration: Option<f64>,
    /// Time discarded before sampling, s; `None` for [`DEFAULT_FIT_SETTLE`].
    pub settle: Option<f64>,
    /// Craig-Bampton fixed-interface modes; `None` for [`DEFAULT_MODES`].
    pub reduce: Option<usize>,
}

/// The options [`FitForcingRequest::set`] knows.
const FIT_OPTIONS: [&str; 5] = ["speeds", "bearing", "duration", "settle", "reduce"];

impl FitForcingRequest {
    /// The speeds (rad/s), the bearing and the fit's options, every default filled in.
    ///
    /// # Errors
    /// [`InputError`] naming `speeds` when none were given, `reduce` for a mode count out
    /// of range.
    // Read once per fit; a large error type on this cold path is fine.
    #[allow(clippy::result_large_err)]
    pub fn resolved(
        &self,
    ) -> std::result::Result<(Vec<f64>, usize, ForcingFitOptions), InputError> {
        let speeds = self.speeds.clone().ok_or_else(|| {
            InputError::field("speeds", "the speeds to fit at are needed")
                .help("e.g. 100Hz:500Hz:5: the law is meant for speeds inside this range")
        })?;
        let d = ForcingFitOptions::default();
        let options = ForcingFitOptions {
            duration: self.duration.unwrap_or(d.duration),
            settle: self.settle.unwrap_or(d.settle),
            reduction: Some(mode_count("reduce", self.reduce.unwrap_or(DEFAULT_MODES))?),
            ..d
        };
        Ok((speeds, self.bearing.unwrap_or(0), options))
    }
}

#[allow(clippy::result_large_err)]
impl SetByName for FitForcingRequest {
    fn set(&mut self, name: &str, value: &Given) -> std::result::Result<(), InputError> {
        let v = value;
        match name {
            "speeds" => self.speeds = Some(v.speeds(name)?),
            "bearing" => self.bearing = Some(v.whole(name, 0, usize::MAX >> 1)?),
            "duration" => self.duration = Some(v.time(name)?),
            "settle" => self.settle = Some(v.time(name)?),
            "reduce" => self.reduce = Some(v.whole(name, 1, MAX_MODES)?),
            _ => return Err(unknown_option(name, &FIT_OPTIONS, "forcing-function fit")),
        }
        Ok(())
    }
}

/// The most samples a speed may ask for: they are drawn from the settled record, one step at
/// most once, and a run records at most [`crate::time::MAX_RECORDED_VALUES`] values over at
/// least three series (time, u_x and u_y of the bearing's node), so more cannot exist. Checked
/// before any run, as a request for more could only be a mistake.
pub const MAX_SAMPLES_PER_SPEED: usize = crate::time::MAX_RECORDED_VALUES / 3;

/// Cage positions averaged over per sample. The force is piecewise smooth in the cage
/// angle (a roller's contact opens and closes within the passage); with 64 points the
/// average is within about 1e-3 of its limit.
const CAGE_POSITIONS: usize = 64;

/// Largest displacement (m) before a run counts as diverged: a thousand times any
/// clearance, so only a blown-up integration reaches it.
const DIVERGENCE_BOUND: f64 = 0.1;

/// How well the law fits the samples of one speed.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SpeedFit {
    /// Spin speed, rad/s.
    pub speed: f64,
    /// Samples in contact, used in the fit.
    pub points: usize,
    /// Samples out of contact (s <= 0 or no force), left out.
    pub excluded: usize,
    /// Coefficient of determination of the force, 1 - SS_res / SS_tot.
    pub r_squared: f64,
    /// Root mean square of (F_fit - F) / F.
    pub rms_relative_error: f64,
    /// The straight line in log-log at this speed: F = coefficient s^exponent, N/m^exponent.
    pub coefficient: f64,
    /// Its exponent.
    pub exponent: f64,
    /// Wall-clock time of the simulation, s.
    pub wall_time_s: f64,
}

/// A fitted forcing function and the data behind it.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ForcingFit {
    /// The bearing's name.
    pub bearing: String,
    /// The fitted law, SI with W in rad/s.
    pub law: ForcingFunction,
    /// The bearing's clearance, for the fitted values.
    pub clearance: Clearance,
    /// Samples in contact, speed by speed.
    pub points: Vec<ForcingPoint>,
    /// Quality per speed.
    pub speeds: Vec<SpeedFit>,
    /// Coefficient of determination of the force over all samples.
    pub r_squared: f64,
    /// Root mean square relative force error over all samples.
    pub rms_relative_error: f64,
    /// Levenberg-Marquardt iterations.
    pub iterations: usize,
    /// Time step of the simulations, s.
    pub step: f64,
}

impl ForcingFit {
    /// The law's force at a sample's speed and deflection, N.
    pub fn fitted(&self, p: &ForcingPoint) -> f64 {
        law_force(&self.law, &self.clearance, p)
    }
}

/// The seconds simulated over the parallel runs of several speeds, told to one progress:
/// each run's own reports (its time so far) are summed over the speeds.
struct SimulatedTime {
    /// Seconds simulated at each speed, in microseconds (atomics hold integers).
    done_us: Arc<Vec<AtomicU64>>,
    /// Seconds to simulate over all speeds.
    total: f64,
    progress: Option<Progress>,
}

impl SimulatedTime {
    fn new(speeds: usize, duration: f64, progress: Option<&Progress>) -> Self {
        SimulatedTime {
            done_us: Arc::new((0..speeds).map(|_| AtomicU64::new(0)).collect()),
            total: speeds as f64 * duration,
            progress: progress.cloned(),
        }
    }

    /// The progress of the run at speed `k`: its time so far, told as the sum over all.
    fn of_speed(&self, k: usize) -> Option<Progress> {
        let outer = self.progress.clone()?;
        let (done_us, total) = (Arc::clone(&self.done_us), self.total);
        Some(Progress::new(move |r| {
            done_us[k].store((r.done * 1e6) as u64, Ordering::Relaxed);
            let done: f64 = done_us
                .iter()
                .map(|d| d.load(Ordering::Relaxed) as f64 * 1e-6)
                .sum();
            outer.tell(
                done,
                total,
                &format!(
                    "{done:.2} s of {total:.2} s simulated over {} speeds",
                    done_us.len()
                ),
            )
        }))
    }
}

/// Fits the forcing function of roller bearing `index` of `model` to its Hertz response at
/// `speeds` (rad/s), telling `progress` the seconds simulated over all speeds (a thousand
/// times per speed at most) and stopping when it says so.
///
/// # Errors
/// [`Error::InvalidOption`] when bearing `index` does not exist, `speeds` is empty or holds
/// a speed that is not positive and finite, or `options.samples_per_speed` is below 2 or
/// above [`MAX_SAMPLES_PER_SPEED`] (checked before anything is run or allocated).
/// Without `options.step`, the errors of [`crate::time::stable_step`]. For each speed the
/// errors of [`simulate`] and of [`completed`](crate::time::SimulationResult::completed)
/// ([`Error::Diverged`] when a run diverges); then those of [`fit_forcing_law`]
/// ([`Error::InvalidOption`] when no speed has two distinct deflections in contact,
/// [`Error::NotConverged`] when the least squares do not converge);
/// [`Error::Interrupted`] when `progress` stopped it.
pub fn fit_forcing(
    model: &Model,
    index: usize,
    speeds: &[f64],
    options: &ForcingFitOptions,
    progress: Option<&Progress>,
) -> Result<ForcingFit> {
    let bearing = model.roller_bearings.get(index).ok_or_else(|| {
        Error::InvalidOption(format!(
            "roller bearing {index} does not exist: the model has {} (numbered from 0)",
            model.roller_bearings.len()
        ))
    })?;
    check_request(speeds, options)?;
    let settings = run_settings(options, bearing.station.node);
    // One step for every speed: the limit depends on none.
    let step = settings.time_step(model)?;
    let simulated = SimulatedTime::new(speeds.len(), options.duration, progress);
    let runs = speeds
        .par_iter()
        .enumerate()
        .map(|(k, &w)| {
            let run = SimulationOptions {
                speed: SpeedProfile::Constant(w),
                step: Some(step),
                progress: simulated.of_speed(k),
                ..settings.clone()
            };
            sample_speed(model, bearing, &run, options.samples_per_speed)
        })
        .collect::<Result<Vec<_>>>()?;
    let points: Vec<ForcingPoint> = runs.iter().flat_map(|r| r.points.clone()).collect();
    let (law, iterations) = fit_forcing_law(&points, &bearing.clearance)?;
    let speeds = runs
        .iter()
        .map(|r| speed_fit(r, &law, &bearing.clearance))
        .collect();
    let (r_squared, rms_relative_error) = quality(&points, &law, &bearing.clearance);
    Ok(ForcingFit {
        bearing: bearing.name.clone(),
        law,
        clearance: bearing.clearance.clone(),
        points,
        speeds,
        r_squared,
        rms_relative_error,
        iterations,
        step,
    })
}

fn check_request(speeds: &[f64], options: &ForcingFitOptions) -> Result<()> {
    let bad = |m: String| Err(Error::InvalidOption(m));
    if speeds.is_empty() {
        return bad("give at least one speed to fit the forcing function at".into());
    }
    if let Some(w) = speeds.iter().find(|w| !(w.is_finite() && **w > 0.0)) {
        return bad(format!(
            "speed {w} rad/s: the forcing function is fitted at positive speeds, where the \
             unbalance moves the shaft through a range of deflections"
        ));
    }
    if !(2..=MAX_SAMPLES_PER_SPEED).contains(&options.samples_per_speed) {
        return bad(format!(
            "samples_per_speed = {}: from 2 to {MAX_SAMPLES_PER_SPEED} samples per speed (they \
             are drawn from the settled record, each step at most once, and a run records at \
             most {} values over its time, u_x and u_y)",
            options.samples_per_speed,
            crate::time::MAX_RECORDED_VALUES
        ));
    }
    Ok(())
}

/// The samples of one speed.
struct SpeedRun {
    speed: f64,
    points: Vec<ForcingPoint>,
    excluded: usize,
    wall_time_s: f64,
}

/// The settings of the Hertz runs of a fit (each sets its speed): every step recorded at
/// the bearing's node, nothing per roller.
fn run_settings(options: &ForcingFitOptions, node: usize) -> SimulationOptions {
    SimulationOptions {
        duration: options.duration,
        step: options.step,
        contact: Some(ContactLaw::Hertz),
        reduction: options.reduction,
        settle: Some(options.settle),
        nodes: Some(vec![node]),
        divergence_bound: DIVERGENCE_BOUND,
        record_every: Some(1),
        record_rollers: false,
        ..SimulationOptions::new(SpeedProfile::Constant(0.0))
    }
}

/// Runs the Hertz model as `run` says and samples the bearing's settled force and
/// deflection `samples` times.
fn sample_speed(
    model: &Model,
    bearing: &RollerBearing,
    run: &SimulationOptions,
    samples: usize,
) -> Result<SpeedRun> {
    let start = Instant::now();
    let profile = run.speed;
    let speed = profile.at(0.0).0.speed;
    let result = simulate(model, run)?.completed()?;
    let (ux, uy) = (&result.channels[0].values, &result.channels[1].values);
    let mut elastic = elastic_contact(bearing)?;
    let settled = result.settled_start()..result.time.len();
    let mut points = Vec::with_capacity(samples.min(settled.len()));
    let mut excluded = 0;
    for i in evenly_spaced(settled, samples) {
        let u = [ux[i], uy[i]];
        let p = ForcingPoint {
            speed,
            deflection: u[0].hypot(u[1]),
            force: cage_averaged_force(&mut elastic, &profile, result.time[i], u),
        };
        if in_contact(&p, &bearing.clearance) {
            points.push(p);
        } else {
            excluded += 1;
        }
    }
    Ok(SpeedRun {
        speed,
        points,
        excluded,
        wall_time_s: start.elapsed().as_secs_f64(),
    })
}

/// The bearing's Hertz contact without damping and without tilt, acting on [u_x, u_y].
fn elastic_contact(bearing: &RollerBearing) -> Result<HertzBearing> {
    let elastic = RollerBearing {
        contact_damping: 0.0,
        roller_tilt: false,
        ..bearing.clone()
    };
    HertzBearing::new(&elastic, vec![0, 1])
}

/// Magnitude of the contact force at displacement `u`, averaged over the cage positions
/// of one roller passage from time `t`.
fn cage_averaged_force(
    elastic: &mut HertzBearing,
    profile: &SpeedProfile,
    t: f64,
    u: [f64; 2],
) -> f64 {
    let omega = profile.at(t).0.speed;
    let passage = 2.0 * PI / elastic.geometry().varying_compliance_frequency(omega);
    let mut sum = [0.0; 2];
    for k in 0..CAGE_POSITIONS {
        let (at, _) = profile.at(t + passage * k as f64 / CAGE_POSITIONS as f64);
        let mut f = [0.0; 2];
        elastic.force(&at, &u, &[0.0; 2], &mut f);
        sum[0] += f[0];
        sum[1] += f[1];
    }
    sum[0].hypot(sum[1]) / CAGE_POSITIONS as f64
}

/// Up to `count` indices spread evenly over `range`, first and last included.
fn evenly_spaced(range: std::ops::Range<usize>, count: usize) -> impl Iterator<Item = usize> {
    let len = range.len();
    let count = count.min(len);
    (0..count).map(move |k| {
        let offset = if count > 1 {
            k * (len - 1) / (count - 1)
        } else {
            0
        };
        range.start + offset
    })
}

/// The quality of the fit at one speed, with that speed's own log-log line.
fn speed_fit(run: &SpeedRun, law: &ForcingFunction, clearance: &Clearance) -> SpeedFit {
    let (r_squared, rms_relative_error) = quality(&run.points, law, clearance);
    let (coefficient, exponent) = own_power_law(&run.points, clearance);
    SpeedFit {
        speed: run.speed,
        points: run.points.len(),
        excluded: run.excluded,
        r_squared,
        rms_relative_error,
        coefficient,
        exponent,
        wall_time_s: run.wall_time_s,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn evenly_spaced_includes_both_ends() {
        let i: Vec<usize> = evenly_spaced(10..21, 3).collect();
        assert_eq!(i, vec![10, 15, 20]);
        let all: Vec<usize> = evenly_spaced(0..3, 10).collect();
        assert_eq!(all, vec![0, 1, 2]);
    }

    #[test]
    fn sample_counts_outside_what_a_record_can_hold_are_refused_before_any_run() {
        // The reference rotor at one speed: a refusal must come from the request, since a
        // run would take seconds and its record could not hold the samples anyway.
        let model = Model::from_toml_str(crate::examples::REFERENCE_ROTOR, None).unwrap();
        for samples in [0, 1, MAX_SAMPLES_PER_SPEED + 1, usize::MAX] {
            let options = ForcingFitOptions {
                samples_per_speed: samples,
                ..ForcingFitOptions::default()
            };
            let e = fit_forcing(&model, 0, &[2.0 * PI * 100.0], &options, None).unwrap_err();
            assert!(matches!(e, Error::InvalidOption(_)), "{samples}: {e:?}");
            let text = e.to_string();
            assert!(
                text.contains(&format!("samples_per_speed = {samples}"))
                    && text.contains(&format!("to {MAX_SAMPLES_PER_SPEED}")),
                "{text}"
            );
        }
        // The limit itself is a request a long enough run could meet: not refused up front.
        let options = ForcingFitOptions {
            samples_per_speed: MAX_SAMPLES_PER_SPEED,
            ..ForcingFitOptions::default()
        };
        assert!(check_request(&[1.0], &options).is_ok());
    }
}
