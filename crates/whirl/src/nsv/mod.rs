//! Non-synchronous vibration over a speed range: the cascade (waterfall) diagram and the
//! NSV at each speed, classified and summarised (docs/theory.md section 8, thesis ch. 5).
//!
//! # The cascade
//!
//! At each spin speed Omega of a sweep, independently of the others, [`cascade`]
//!
//! 1. marches the rotor (full or Craig-Bampton reduced, central difference, from the static
//!    equilibrium under gravity, roller bearings by the chosen
//!    [`ContactLaw`](crate::bearing::ContactLaw)) for
//!    `settle + record` seconds, recording the response node's u_x and u_y;
//! 2. discards the first `settle` seconds and takes the windowed amplitude spectrum of the
//!    chosen component over the rest, scaled to physical zero-to-peak amplitude
//!    ([`crate::post::spectrum`]: `A_k = c_k |X_k| / sum(w)`), with the window-weighted
//!    mean (the static sag) removed;
//! 3. finds the largest peak that is not within `tolerance_bins` of a multiple of the
//!    running speed ([`crate::post::largest_non_synchronous_below`], refined between bins):
//!    the NSV amplitude of docs/theory.md section 8. Its whirl direction comes from the full
//!    spectrum of `x + i y` (forward at +f, backward at -f), and its amplitude in the
//!    record's two halves tells a steady vibration from free vibration still dying away.
//!
//! Then the NSV of every speed is classified ([`NsvClass`]: subharmonic, varying compliance
//! and its sidebands with the running speed, locked whip, combination resonance,
//! super-harmonic, other, unsettled; the rules are in [`classify`]'s documentation), using
//! how its frequency moves over the neighbouring speeds and the lines beside it in its
//! spectrum ([`trend`]), the bearings' contact frequencies (N_b w_c, eq. 4.4) and the
//! natural frequencies of the rotor on linearised bearings (a Campbell diagram).
//! [`Cascade::nsv_summary`] gives the onset speed, the largest NSV and the dominant class.
//!
//! The band kept and searched runs from 0 to `max_frequency_hz` (by default 2.5 times the
//! top speed, or 1.25 times the highest contact frequency there, whichever is higher).
//!
//! # Parallel, deterministic, resumable
//!
//! Speeds run in parallel on rayon's pool; each is a deterministic function of the model
//! and the options, so the results do not depend on the number of threads (keep faer
//! single-threaded, `faer::set_global_parallelism(faer::Par::Seq)`, as the CLI does: faer's
//! own threads would only compete with the speeds). With a checkpoint folder every finished
//! speed is saved at once, atomically (see [`checkpoint`]); a later call with the same
//! model and options loads the finished speeds and computes only the rest, with results
//! identical to an uninterrupted run. A folder holding another cascade is refused.
//!
//! ```no_run
//! use whirl::model::Model;
//! use whirl::nsv::{cascade, CascadeOptions};
//! use whirl::units::{parse_range, Dimension};
//!
//! let model = Model::from_toml_str(whirl::examples::REFERENCE_ROTOR, None)?;
//! let speeds = parse_range("1:750Hz:150", Dimension::AngularSpeed)?;
//! let options = CascadeOptions::new(&model, speeds);
//! let result = cascade(&model, &options, Some("out/cascade.partial".as_ref()), None)?;
//! let summary = result.nsv_summary(whirl::nsv::DEFAULT_THRESHOLD_M);
//! println!("NSV from {:?} Hz, largest {:?}", summary.onset_speed_hz, summary.largest);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

pub mod checkpoint;
pub mod classify;
mod options;
mod point;
mod refine;
mod report;
mod request;
mod starts;
mod summary;
pub mod trend;

use std::borrow::Cow;
use std::path::Path;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::time::Instant;

use rayon::prelude::*;
use serde::Serialize;

pub use crate::given::MAX_MODES;
pub use classify::{NamedFrequency, Nsv, NsvClass, WhirlDirection};
pub(crate) use options::next_five_smooth;
pub use options::{
    default_speeds, even_speeds, records_span, Averaging, CascadeOptions, Component, Refinement,
    Resolved, DEFAULT_ABSOLUTE_ERROR_M, DEFAULT_COMPONENT, DEFAULT_DECIDED_ERROR,
    DEFAULT_MAX_ADDED, DEFAULT_MAX_RECORDS, DEFAULT_MIN_RECORDS, DEFAULT_MIN_SPACING_HZ,
    DEFAULT_ONSET_LEVELS_M, DEFAULT_RECORD, DEFAULT_RELATIVE_ERROR, DEFAULT_SETTLE,
    DEFAULT_SETTLE_MAX, DEFAULT_SPEED_COUNT, DEFAULT_START, DEFAULT_TOLERANCE_BINS, DEFAULT_WINDOW,
};
pub use point::{
    dies_away, measure, negligible, CascadePoint, Measured, NsvPeak, DECAY_PER_STRETCH,
    NEGLIGIBLE_FRACTION, NEGLIGIBLE_M, TRANSIENT_DECAY,
};
pub use refine::SHARP_RATIO;
pub use report::{CascadeReport, CascadeSummary, StartsSummary};
pub use request::{CascadeRequest, CASCADE_OPTIONS, RUN_SETTINGS};
pub use starts::{
    compare_starts, other_start, other_start_options, StartComparison, StartPair,
    STARTS_DIFFER_SIGMAS,
};
pub use summary::{
    ClassCount, GridSpread, LargestNsv, NsvStatistics, NsvSummary, Onset, SpeedLevel,
    DEFAULT_THRESHOLD_M, SUSTAINED_FRACTION, SUSTAINED_WINDOW,
};

use crate::bearing::{bearing_orders, contact_frequencies, BearingOrders};
use crate::error::{Error, Result};
use crate::fe::{assemble_banded, Bearings};
use crate::modal::{campbell, CampbellOptions};
use crate::model::Model;
use crate::progress::{tell, Progress};
use crate::system::Linear;
use checkpoint::Checkpoint;
use classify::Context;
use trend::Reading;

/// Natural frequencies (Campbell branches) compared with sub-synchronous peaks.
const NATURAL_BRANCHES: usize = 6;

/// Computes a batch of a cascade's speeds elsewhere than on this machine's threads (on the
/// workers of a cluster): given `(index, speed)` pairs (speed in rad/s), it hands each
/// finished point to `done` as it arrives, in any order, and returns the first error `done`
/// returns (a checkpoint that cannot be written, or a stop asked for by the progress). Each
/// point must be the one [`cascade_point`] computes for that speed.
pub type PointRunner<'a> =
    &'a dyn Fn(&[(usize, f64)], &mut dyn FnMut(usize, CascadePoint) -> Result<()>) -> Result<()>;

/// A computed cascade: one spectrum and one classified NSV per speed.
#[derive(Debug, Clone, Serialize)]
pub struct Cascade {
    /// The options it was computed with.
    pub options: CascadeOptions,
    /// Step, sampling and band shared by every speed.
    pub resolved: Resolved,
    /// Frequencies of the one-sided bins kept, Hz.
    pub frequency_hz: Vec<f64>,
    /// Frequencies of the full-spectrum bins kept (empty unless `options.full`), Hz.
    pub full_frequency_hz: Vec<f64>,
    /// One point per speed, requested and added, in ascending speed.
    pub points: Vec<CascadePoint>,
    /// Contact frequencies at each speed (N_b w_c, waviness), Hz.
    pub contact_frequencies: Vec<Vec<NamedFrequency>>,
    /// Each roller bearing's characteristic frequencies as orders of the spin speed.
    pub bearing_orders: Vec<BearingOrders>,
    /// Natural frequencies of the rotor on linearised bearings at each speed, Hz.
    pub natural_frequencies: Vec<Vec<NamedFrequency>>,
    /// The classified NSV at each speed; `None` where there is no non-synchronous peak or
    /// the run diverged.
    pub nsv: Vec<Option<Nsv>>,
    /// Speeds loaded from the checkpoint rather than computed.
    pub resumed: usize,
    /// Wall-clock time of this call, s.
    pub wall_time_s: f64,
}

impl Cascade {
    /// The NSV in a few numbers, counting peaks at or above `threshold_m` (m, zero-to-peak;
    /// [`DEFAULT_THRESHOLD_M`] is a sensible start).
    pub fn nsv_summary(&self, threshold_m: f64) -> NsvSummary {
        summary::summarise(
            &self.points,
            &self.nsv,
            threshold_m,
            &self.options.refine.onset_levels_m,
        )
    }

    /// The speeds, Hz.
    pub fn speeds_hz(&self) -> Vec<f64> {
        self.points.iter().map(|p| p.speed_hz).collect()
    }

    /// The speeds, rad/s.
    pub fn speeds(&self) -> Vec<f64> {
        self.points.iter().map(|p| p.speed).collect()
    }
}

/// Computes the cascade of `model` (see the module documentation). With `checkpoint`, the
/// speeds already finished there are loaded and each new one is saved as soon as it is
/// done. `progress` is told how far it has got and may stop it.
///
/// # Errors
/// [`Error::Input`] for bad options (the field is named) or a checkpoint folder holding
/// another cascade (field `checkpoint`); [`Error::Interrupted`] when `progress` stopped it;
/// [`Error::Io`] when the checkpoint cannot be written; [`Error::Diverged`] when the
/// simulation diverged at every requested speed; what the simulation reports for a
/// model it cannot run. A run that diverges at some speed is no error: that point says so.
pub fn cascade(
    model: &Model,
    options: &CascadeOptions,
    checkpoint: Option<&Path>,
    progress: Option<&Progress>,
) -> Result<Cascade> {
    PreparedCascade::new(model, options)?.run(checkpoint, progress)
}

/// [`cascade`] with its speeds computed by `runner` (on a cluster's workers) instead of on
/// this machine's threads: the same rounds of refinement, checkpoint and result.
///
/// # Errors
/// Those of [`cascade`], and the runner's.
pub fn distributed_cascade(
    model: &Model,
    options: &CascadeOptions,
    checkpoint: Option<&Path>,
    progress: Option<&Progress>,
    runner: PointRunner<'_>,
) -> Result<Cascade> {
    PreparedCascade::new(model, options)?.run_on(checkpoint, progress, Some(runner))
}

/// One speed (rad/s) of the cascade of `model` with `options`, as [`cascade`] computes it:
/// what a [`PointRunner`]'s workers compute. Its `added` flag is set by the cascade.
///
/// # Errors
/// [`Error::Input`] for bad options; what the simulation reports for a model it cannot run.
pub fn cascade_point(model: &Model, options: &CascadeOptions, speed: f64) -> Result<CascadePoint> {
    PreparedCascade::new(model, options)?.point(speed)
}

/// A cascade ready to run: its options checked, the model's linear system assembled and
/// Craig-Bampton reduced, and the step, sampling and band worked out. The reduction is the
/// costly part of a cascade's set-up (it grows with the elements, where a speed's march
/// does not) and depends on no speed, so it is made once here and serves the stability
/// limit that sets the step, the checkpoint's key and every speed. [`cascade`] prepares and
/// runs; a caller that needs the checkpoint's key before running (to name the folder)
/// prepares once and does both, and a cluster's worker that computes many speeds of one
/// cascade prepares it once ([`PreparedCascade::owned`], [`PreparedCascade::point`]).
pub struct PreparedCascade<'a> {
    model: Cow<'a, Model>,
    options: Cow<'a, CascadeOptions>,
    /// The model's linear system, shared by every speed.
    linear: Linear,
    resolved: Resolved,
}

impl<'a> PreparedCascade<'a> {
    /// Checks `options` against `model`, then builds what every speed shares.
    ///
    /// # Errors
    /// [`Error::Input`] for bad options (the field is named), checked before anything is
    /// built; what the reduction and the stability limit report for a model they cannot
    /// handle.
    pub fn new(model: &'a Model, options: &'a CascadeOptions) -> Result<Self> {
        options::check(model, options)?;
        Self::build(Cow::Borrowed(model), Cow::Borrowed(options))
    }

    /// As [`PreparedCascade::new`], owning the model and the options: kept by a caller
    /// between calls (a cluster's worker, between its speeds of one cascade).
    ///
    /// # Errors
    /// As [`PreparedCascade::new`].
    pub fn owned(model: Model, options: CascadeOptions) -> Result<PreparedCascade<'static>> {
        options::check(&model, &options)?;
        PreparedCascade::build(Cow::Owned(model), Cow::Owned(options))
    }

    /// Whether this is the cascade of `model` with `options`.
    pub fn is_of(&self, model: &Model, options: &CascadeOptions) -> bool {
        let json = |m: &Model, o: &CascadeOptions| serde_json::to_string(&(m, o)).ok();
        let mine = json(&self.model, &self.options);
        mine.is_some() && mine == json(model, options)
    }

    /// One speed (rad/s), as the cascade computes it ([`cascade_point`]).
    ///
    /// # Errors
    /// As [`cascade_point`].
    pub fn point(&self, speed: f64) -> Result<CascadePoint> {
        let mut planners = point::Planners::new(&self.options, &self.resolved)?;
        point::compute(
            &self.model,
            &self.options,
            &self.resolved,
            &self.linear,
            speed,
            &mut planners,
        )
    }

    /// As [`PreparedCascade::new`], for transients marched with the cascade's settings (a
    /// run-up): a linear model is not refused, its speeds are never computed as a cascade.
    pub(crate) fn for_transient(model: &'a Model, options: &'a CascadeOptions) -> Result<Self> {
        options::check_settings(model, options)?;
        Self::build(Cow::Borrowed(model), Cow::Borrowed(options))
    }

    fn build(model: Cow<'a, Model>, options: Cow<'a, CascadeOptions>) -> Result<Self> {
        let linear = point::linear_system(&model, &options)?;
        let resolved = options::resolve(&model, &options, &linear)?;
        Ok(PreparedCascade {
            model,
            options,
            linear,
            resolved,
        })
    }

    /// Step, sampling and band shared by every speed.
    pub fn resolved(&self) -> &Resolved {
        &self.resolved
    }

    /// The model's linear system every speed marches (reduced as the options say): a
    /// run-up of the same model marches it too ([`crate::runup`]).
    pub(crate) fn linear(&self) -> &Linear {
        &self.linear
    }

    /// The name of this cascade's checkpoint folder ([`checkpoint::key`]).
    ///
    /// # Errors
    /// [`Error::Encode`] when the model cannot be hashed.
    pub fn checkpoint_key(&self) -> Result<String> {
        checkpoint::key_of(&self.model, &self.options, &self.resolved)
    }

    /// Computes the cascade, as [`cascade`] does.
    ///
    /// # Errors
    /// Those of [`cascade`] after the options were checked.
    pub fn run(&self, checkpoint: Option<&Path>, progress: Option<&Progress>) -> Result<Cascade> {
        self.run_on(checkpoint, progress, None)
    }

    /// Computes the cascade as [`PreparedCascade::run`] does, its speeds by `runner` (on a
    /// cluster's workers) instead of on this machine's threads ([`distributed_cascade`]).
    ///
    /// # Errors
    /// As [`distributed_cascade`].
    pub fn run_distributed(
        &self,
        checkpoint: Option<&Path>,
        progress: Option<&Progress>,
        runner: PointRunner<'_>,
    ) -> Result<Cascade> {
        self.run_on(checkpoint, progress, Some(runner))
    }

    fn run_on(
        &self,
        checkpoint: Option<&Path>,
        progress: Option<&Progress>,
        runner: Option<PointRunner<'_>>,
    ) -> Result<Cascade> {
        let start = Instant::now();
        let (model, options): (&Model, &CascadeOptions) = (&self.model, &self.options);
        let resolved = self.resolved;
        let store = checkpoint
            .map(|dir| Checkpoint::open(dir, model, options, &resolved))
            .transpose()?;
        let planners = point::Planners::new(options, &resolved)?;
        let mut run = Run {
            model,
            options,
            resolved: &resolved,
            linear: &self.linear,
            store: store.as_ref(),
            planners: &planners,
            progress,
            runner,
            speeds: options.speeds.clone(),
            points: Vec::new(),
            resumed: 0,
        };
        run.compute_missing()?;
        every_speed_diverged(&run.points)?;
        let mut cascade = assemble_cascade(model, options, resolved, run.sorted_points())?;
        if options.refine.enabled {
            let seeds = refine::resonance_speeds(
                &cascade.speeds(),
                &cascade.contact_frequencies,
                &cascade.natural_frequencies,
                options.refine.min_spacing_hz,
            );
            let tolerance_hz = options.tolerance_bins * resolved.resolution_hz;
            let mut next: Vec<f64> = seeds.into_iter().take(options.refine.max_added).collect();
            if next.is_empty() {
                next = refine::next_speeds(
                    &cascade.points,
                    &cascade.nsv,
                    &options.refine,
                    tolerance_hz,
                    options.refine.max_added,
                );
            }
            while !next.is_empty() {
                run.speeds.extend(next);
                run.compute_missing()?;
                cascade = assemble_cascade(model, options, resolved, run.sorted_points())?;
                let added = run.speeds.len() - options.speeds.len();
                let room = options.refine.max_added.saturating_sub(added);
                next = refine::next_speeds(
                    &cascade.points,
                    &cascade.nsv,
                    &options.refine,
                    tolerance_hz,
                    room,
                );
            }
        }
        cascade.resumed = run.resumed;
        cascade.wall_time_s = start.elapsed().as_secs_f64();
        Ok(cascade)
    }
}

/// A cascade in which every requested speed diverged measured nothing: a summary of it
/// would read "no NSV" (an answer that looks like a result), so it is an error, the same
/// for the command line, a study's point and Python. Refinement is not tried: its speeds
/// come from the same diverging model. Some diverged speeds are kept, listed in the
/// summary.
fn every_speed_diverged(points: &[Option<CascadePoint>]) -> Result<()> {
    let diverged: Vec<&CascadePoint> = points.iter().flatten().collect();
    let first = match diverged.as_slice() {
        [first, ..] if diverged.iter().all(|p| p.diverged.is_some()) => first,
        _ => return Ok(()),
    };
    Err(Error::Diverged {
        time: f64::NAN,
        coordinate: usize::MAX,
        message: format!(
            "the simulation diverged at every one of the {} speeds, so there is no NSV to \
             report; at {:.1} Hz: {}",
            diverged.len(),
            first.speed_hz,
            first.diverged.as_deref().unwrap_or_default()
        ),
    })
}

/// The speeds of a cascade as they are computed, round after round of refinement.
struct Run<'a> {
    model: &'a Model,
    options: &'a CascadeOptions,
    resolved: &'a Resolved,
    /// The model's linear system, shared by every speed.
    linear: &'a Linear,
    store: Option<&'a Checkpoint>,
    planners: &'a point::Planners,
    progress: Option<&'a Progress>,
    /// Computes the missing speeds elsewhere; `None` for this machine's threads.
    runner: Option<PointRunner<'a>>,
    /// Requested speeds, then the added ones in the order they were added (rad/s); a
    /// speed's index here is its key in the checkpoint.
    speeds: Vec<f64>,
    /// The points computed or loaded so far, by index into `speeds`.
    points: Vec<Option<CascadePoint>>,
    /// Points loaded from the checkpoint.
    resumed: usize,
}

impl Run<'_> {
    /// Loads or computes every speed that has no point yet, in parallel.
    fn compute_missing(&mut self) -> Result<()> {
        let requested = self.options.speeds.len();
        for i in self.points.len()..self.speeds.len() {
            let loaded = self.store.and_then(|s| s.load(i, self.speeds[i]));
            self.resumed += usize::from(loaded.is_some());
            self.points.push(loaded);
        }
        let total = self.points.len();
        let resumed = self.resumed;
        let progress = self.progress;
        // Speeds loaded from the checkpoint count in neither `done` nor `total`.
        let report = |done: usize| {
            tell(
                progress,
                (done - resumed) as f64,
                (total - resumed) as f64,
                || {
                    let from_checkpoint = if resumed > 0 {
                        format!(" ({resumed} from the checkpoint)")
                    } else {
                        String::new()
                    };
                    format!("{done}/{total} speeds{from_checkpoint}")
                },
            )
        };
        let already = self.points.iter().flatten().count();
        let stop = AtomicBool::new(report(already).is_break());
        let done = AtomicUsize::new(already);
        let missing: Vec<usize> = (0..total).filter(|&i| self.points[i].is_none()).collect();
        if let Some(runner) = self.runner {
            if !stop.load(Ordering::Relaxed) {
                let batch: Vec<(usize, f64)> =
                    missing.iter().map(|&i| (i, self.speeds[i])).collect();
                let (store, points) = (self.store, &mut self.points);
                let mut done = |i: usize, mut point: CascadePoint| -> Result<()> {
                    if points.get(i).is_none_or(|p| p.is_some()) {
                        return Err(Error::Internal(format!(
                            "the cascade's runner returned speed {i}, which was not asked for"
                        )));
                    }
                    point.added = i >= requested;
                    if let Some(s) = store {
                        s.save(i, &point)?;
                    }
                    points[i] = Some(point);
                    let finished = points.iter().flatten().count();
                    if report(finished).is_break() {
                        stop.store(true, Ordering::Relaxed);
                        return Err(Error::Interrupted(String::new()));
                    }
                    Ok(())
                };
                // A stop asked for by the progress ends the runner; the count below says so.
                if let Err(e) = runner(&batch, &mut done) {
                    if !stop.load(Ordering::Relaxed) {
                        return Err(e);
                    }
                }
            }
            let finished = self.points.iter().flatten().count();
            if finished < total {
                return Err(interrupted(finished, total, self.store));
            }
            return Ok(());
        }
        let (model, options, resolved, linear, store) = (
            self.model,
            self.options,
            self.resolved,
            self.linear,
            self.store,
        );
        let speeds = &self.speeds;
        let computed = missing
            .par_iter()
            .filter(|_| !stop.load(Ordering::Relaxed))
            .map_init(
                || self.planners.clone(),
                |planners, &i| {
                    let mut point =
                        point::compute(model, options, resolved, linear, speeds[i], planners)?;
                    point.added = i >= requested;
                    if let Some(s) = store {
                        s.save(i, &point)?;
                    }
                    let finished = done.fetch_add(1, Ordering::Relaxed) + 1;
                    if report(finished).is_break() {
                        stop.store(true, Ordering::Relaxed);
                    }
                    Ok((i, point))
                },
            )
            .collect::<Result<Vec<_>>>()?;
        for (i, p) in computed {
            self.points[i] = Some(p);
        }
        let finished = self.points.iter().flatten().count();
        if finished < total {
            return Err(interrupted(finished, total, self.store));
        }
        Ok(())
    }

    /// Every point, in ascending speed.
    fn sorted_points(&self) -> Vec<CascadePoint> {
        let mut points: Vec<CascadePoint> = self.points.iter().flatten().cloned().collect();
        points.sort_by(|a, b| a.speed.total_cmp(&b.speed));
        points
    }
}

fn interrupted(done: usize, total: usize, store: Option<&Checkpoint>) -> Error {
    let kept = store.map_or("nothing was kept (no checkpoint folder)".to_string(), |s| {
        format!("they are kept in `{}`", s.dir().display())
    });
    Error::Interrupted(format!(
        "the cascade was stopped after {done} of {total} speeds; {kept}"
    ))
}

/// Frequencies, contact and natural frequencies, and the classified NSV of the points.
fn assemble_cascade(
    model: &Model,
    options: &CascadeOptions,
    resolved: Resolved,
    points: Vec<CascadePoint>,
) -> Result<Cascade> {
    let df = resolved.resolution_hz;
    let frequency_hz = (0..resolved.bins).map(|k| k as f64 * df).collect();
    let full_frequency_hz = if options.full {
        point::full_bins(&resolved).map(|k| k as f64 * df).collect()
    } else {
        Vec::new()
    };
    let speeds: Vec<f64> = points.iter().map(|p| p.speed).collect();
    let contact: Vec<Vec<NamedFrequency>> =
        speeds.iter().map(|&w| contact_bases(model, w)).collect();
    let natural = natural_frequencies(model, &speeds)?;
    let reading = Reading {
        resolution_hz: df,
        window: options.window,
        tolerance_hz: options.tolerance_bins * df,
    };
    let contexts: Vec<Context<'_>> = contact
        .iter()
        .zip(&natural)
        .map(|(contact, natural)| Context { contact, natural })
        .collect();
    let nsv = classify::classify(&points, &contexts, &reading);
    Ok(Cascade {
        options: options.clone(),
        resolved,
        frequency_hz,
        full_frequency_hz,
        points,
        contact_frequencies: contact.clone(),
        bearing_orders: bearing_orders(&model.roller_bearings),
        natural_frequencies: natural,
        nsv,
        resumed: 0,
        wall_time_s: 0.0,
    })
}

/// The varying-compliance and waviness frequencies of every roller bearing at `speed`
/// (rad/s), each frequency once (the bearing is named where two share a source).
fn contact_bases(model: &Model, speed: f64) -> Vec<NamedFrequency> {
    let mut out: Vec<NamedFrequency> = Vec::new();
    for b in &model.roller_bearings {
        for c in contact_frequencies(b, speed) {
            let same = |o: &NamedFrequency| {
                (o.frequency_hz - c.frequency_hz).abs() <= 1e-9 * c.frequency_hz.abs().max(1.0)
            };
            if out.iter().any(same) {
                continue;
            }
            let label = if c.source == "varying compliance" {
                "N_b w_c".to_string()
            } else {
                c.source.clone()
            };
            let name = if out.iter().any(|o| o.name == label) {
                format!("{label} ({})", b.name)
            } else {
                label
            };
            out.push(NamedFrequency {
                name,
                frequency_hz: c.frequency_hz,
            });
        }
    }
    out
}

/// The first [`NATURAL_BRANCHES`] whirl frequencies of the rotor on linearised bearings at
/// each speed, named `mode 1 forward` etc. The Campbell diagram is solved at no more than
/// [`NATURAL_GRID`] even speeds over the cascade's range and read at each cascade speed by
/// linear interpolation along the followed branches (whirl direction from the nearer grid
/// speed): natural frequencies move smoothly with speed, and one eigen-solve per cascade
/// speed was 7 % of the default cascade.
fn natural_frequencies(model: &Model, speeds: &[f64]) -> Result<Vec<Vec<NamedFrequency>>> {
    let system = assemble_banded(model, Bearings::Linearised);
    let grid = natural_grid(speeds);
    let mut campbell_options = CampbellOptions::new(grid.clone());
    campbell_options.modes = NATURAL_BRANCHES.min(system.dofs());
    let diagram = campbell(&system, &campbell_options, None)?;
    Ok(speeds
        .iter()
        .map(|&speed| {
            diagram
                .branches
                .iter()
                .filter_map(|b| {
                    let (frequency_hz, nearest) = along(&grid, &b.frequency_hz, speed)?;
                    Some(NamedFrequency {
                        name: format!("mode {} {}", b.index + 1, b.whirl_at[nearest].name()),
                        frequency_hz,
                    })
                })
                .collect()
        })
        .collect())
}

/// Most speeds of the Campbell diagram behind a cascade's classification. At 21 even speeds
/// over 1-750 Hz (37.5 Hz apart) the interpolated natural frequencies of the reference
/// rotor's first six branches are within 0.0023 Hz of the direct solve at every default
/// cascade speed (the test `the_interpolated_campbell_diagram_matches_the_direct_one`),
/// a thousandth of the 2 Hz bin the peaks are read with.
const NATURAL_GRID: usize = 21;

/// The speeds (rad/s, ascending) the classification's Campbell diagram is solved at: the
/// cascade's own when there are few, else [`NATURAL_GRID`] even speeds from its lowest to
/// its highest.
fn natural_grid(speeds: &[f64]) -> Vec<f64> {
    let mut sorted = speeds.to_vec();
    sorted.sort_by(f64::total_cmp);
    sorted.dedup();
    if sorted.len() <= NATURAL_GRID {
        return sorted;
    }
    let (low, high) = (sorted[0], sorted[sorted.len() - 1]);
    (0..NATURAL_GRID)
        .map(|k| low + (high - low) * k as f64 / (NATURAL_GRID - 1) as f64)
        .collect()
}

/// A branch's frequency (Hz) at `speed`, linear between the grid speeds around it, and the
/// index of the nearer of them; `None` where the branch was lost at either.
fn along(grid: &[f64], frequency_hz: &[f64], speed: f64) -> Option<(f64, usize)> {
    let upper = grid.partition_point(|&w| w < speed).min(grid.len() - 1);
    let lower = upper.saturating_sub(1);
    let (a, b) = (frequency_hz[lower], frequency_hz[upper]);
    if !(a.is_finite() && b.is_finite()) {
        return None;
    }
    if upper == lower || grid[upper] == grid[lower] {
        return Some((b, upper));
    }
    let t = ((speed - grid[lower]) / (grid[upper] - grid[lower])).clamp(0.0, 1.0);
    let nearest = if t < 0.5 { lower } else { upper };
    Some((a + t * (b - a), nearest))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::modal::ModeBranch;

    /// Each cascade speed's natural frequencies read off the coarse diagram against a
    /// Campbell diagram solved at every one of them, on the reference rotor's default grid
    /// (150 speeds, 1-750 Hz). Measured 0.0023 Hz; 0.01 Hz is a two-hundredth of the 2 Hz
    /// bin the classification compares peaks with, so no peak can change class by the
    /// interpolation. The same branches must be present at every speed.
    #[test]
    fn the_interpolated_campbell_diagram_matches_the_direct_one() {
        let model = Model::from_toml_str(crate::examples::REFERENCE_ROTOR, None).unwrap();
        let speeds = default_speeds(&model).unwrap();
        let read = natural_frequencies(&model, &speeds).unwrap();
        let system = assemble_banded(&model, Bearings::Linearised);
        let mut options = CampbellOptions::new(speeds.clone());
        options.modes = NATURAL_BRANCHES;
        let direct = campbell(&system, &options, None).unwrap();
        let mut worst: f64 = 0.0;
        for (k, at_speed) in read.iter().enumerate() {
            let exact: Vec<&ModeBranch> = direct
                .branches
                .iter()
                .filter(|b| b.frequency_hz[k].is_finite())
                .collect();
            assert_eq!(at_speed.len(), exact.len(), "branches at speed {k}");
            for (named, branch) in at_speed.iter().zip(exact) {
                worst = worst.max((named.frequency_hz - branch.frequency_hz[k]).abs());
            }
        }
        assert!(worst < 0.01, "largest interpolation error {worst} Hz");
    }

    #[test]
    fn a_short_cascade_is_solved_at_its_own_speeds() {
        assert_eq!(natural_grid(&[3.0, 1.0, 2.0, 2.0]), vec![1.0, 2.0, 3.0]);
        let many: Vec<f64> = (0..100).map(f64::from).collect();
        let grid = natural_grid(&many);
        assert_eq!(grid.len(), NATURAL_GRID);
        assert_eq!((grid[0], grid[NATURAL_GRID - 1]), (0.0, 99.0));
    }
}
