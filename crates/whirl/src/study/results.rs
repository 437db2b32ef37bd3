//! Running a study's points and what a study concludes from them.
//!
//! Points run one after another (each cascade already spreads its speeds over the cores);
//! a point found in the checkpoint folder is not computed again, and each computed point is
//! saved the moment it is finished. A point whose cascade fails is reported and left out
//! (not saved, so a later run tries it again); the study goes on with the others.

use serde::{Deserialize, Serialize};

use super::fit::{polynomial_fit, PolynomialFit};
use super::ranking::{by_parameter, effect, rank, Effect};
use super::store::Store;
use super::{Point, Study};
use crate::error::Result;

/// The NSV summary of one point's cascade.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct NsvSummary {
    /// Largest non-synchronous amplitude over all speeds, m (0 when there is none).
    pub largest: f64,
    /// Speed where it occurs, Hz.
    pub largest_speed_hz: Option<f64>,
    /// Its frequency, Hz.
    pub largest_frequency_hz: Option<f64>,
    /// Its class (`forward-whip`, `backward-combination-resonance`, ...).
    pub largest_class: Option<String>,
    /// Lowest speed with a significant non-synchronous peak, Hz.
    pub onset_speed_hz: Option<f64>,
    /// Median NSV over the speed range (each speed weighed by its stretch of speed), m.
    #[serde(default)]
    pub median: f64,
    /// 90th percentile of the NSV over the speed range, m.
    #[serde(default)]
    pub p90: f64,
    /// Mean NSV over the speed range, m.
    #[serde(default)]
    pub mean: f64,
    /// The class of NSV seen at most speeds.
    pub dominant_class: Option<String>,
    /// Largest synchronous (1X) amplitude over all speeds, m.
    pub largest_synchronous: f64,
}

impl NsvSummary {
    /// The value of `metric`, m.
    pub fn value(&self, metric: Metric) -> f64 {
        match metric {
            Metric::Largest => self.largest,
            Metric::Median => self.median,
            Metric::P90 => self.p90,
            Metric::Mean => self.mean,
        }
    }
}

/// Which number of a point's NSV the fits and the ranking use.
///
/// Measured on the reference rotor (20 and 120 um) over the grids 1:750Hz:30, :75 and :150
/// with the default refinement, the spread across grids was: largest 1 % and 8 %, mean 6 %
/// and 16 %, median 30 % and 18 %, p90 35 % and 24 %. The mean is the default: an integral
/// over speed converges as the grid is refined by construction, where a maximum over a
/// jagged curve does only as far as the refinement finds its top.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Metric {
    /// The largest NSV over the speeds.
    Largest,
    /// The median NSV over the speed range.
    Median,
    /// The 90th percentile of the NSV over the speed range.
    P90,
    /// The mean NSV over the speed range.
    #[default]
    Mean,
}

impl Metric {
    /// Every metric.
    pub const ALL: [Metric; 4] = [Metric::Mean, Metric::Median, Metric::P90, Metric::Largest];

    /// Name as in study files: `mean`, `median`, `p90`, `largest`.
    pub fn name(self) -> &'static str {
        match self {
            Metric::Largest => "largest",
            Metric::Median => "median",
            Metric::P90 => "p90",
            Metric::Mean => "mean",
        }
    }

    /// What it is, for labels: `mean NSV over the speed range`.
    pub fn describe(self) -> &'static str {
        match self {
            Metric::Largest => "largest NSV",
            Metric::Median => "median NSV over the speed range",
            Metric::P90 => "90th percentile of the NSV over the speed range",
            Metric::Mean => "mean NSV over the speed range",
        }
    }
}

/// A cascade as a colour map: amplitude over speed and frequency (up to the top speed).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CascadeMap {
    /// Speeds, Hz.
    pub speeds_hz: Vec<f64>,
    /// Frequencies, Hz.
    pub frequencies_hz: Vec<f64>,
    /// Amplitude, m: one row per frequency, one column per speed; `None` where the run
    /// diverged. Single precision: it is for plots, and it halves the checkpoint's size.
    pub amplitude: Vec<Vec<Option<f32>>>,
}

/// One finished point, as saved in the checkpoint folder.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PointResult {
    /// The point's key.
    pub key: String,
    /// The NSV summary.
    pub nsv: NsvSummary,
    /// The cascade, for plots.
    pub map: CascadeMap,
    /// Wall-clock time of the cascade, s.
    pub wall_time_s: f64,
    /// Speeds read from the cascade's folder instead of computed: all of them when another
    /// point shares the cascade (the same model and settings, another threshold), some
    /// when an interrupted run is resumed.
    pub resumed_speeds: usize,
}

/// One sweep's outcome.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SweepResult {
    /// The sweep's name.
    pub name: String,
    /// The parameter path.
    pub parameter: String,
    /// The values as written.
    pub values: Vec<String>,
    /// The values in SI, where they are numbers.
    pub values_si: Vec<Option<f64>>,
    /// The largest NSV at each value, m; `None` where the point failed.
    pub largest_nsv: Vec<Option<f64>>,
    /// The study's metric at each value (what the fit and the ranking use), m.
    pub metric_nsv: Vec<Option<f64>>,
    /// The NSV onset speed at each value, Hz.
    pub onset_speed_hz: Vec<Option<f64>>,
    /// The fitted polynomial (thesis eq. 5.1) over the points that did not fail, when the
    /// sweep asks for one.
    pub fit: Option<PolynomialFit>,
    /// Why the fit asked for is missing (too few points left).
    pub fit_error: Option<String>,
}

/// What a study concludes.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct StudyResults {
    /// Each sweep's outcome, in file order.
    pub sweeps: Vec<SweepResult>,
    /// The sweeps from the largest effect on the metric to the smallest.
    pub ranking: Vec<Effect>,
    /// The parameters so ranked, each by the largest effect among its sweeps.
    pub ranking_by_parameter: Vec<Effect>,
}

/// How a point came to be available.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Source {
    /// Computed now.
    Computed,
    /// Read from the checkpoint folder.
    Resumed,
}

/// A point's result, or why its cascade failed.
pub type PointOutcome = std::result::Result<PointResult, String>;

/// Brings every point of `study` to a result: from `store` when it is there, otherwise by
/// `compute`, saving each at once. `report` hears of each point as it becomes available
/// (index, point, how, outcome). A point that fails is kept as its message; only a failure
/// to save stops the study (the finished points stay saved).
///
/// # Errors
/// The first failure to save a point to `store` ([`Error::Io`](crate::Error::Io),
/// [`Error::Encode`](crate::Error::Encode)); failures of `compute` are kept as the point's
/// outcome instead.
pub fn run_points(
    study: &Study,
    store: &Store,
    mut compute: impl FnMut(&Point) -> Result<PointResult>,
    mut report: impl FnMut(usize, &Point, Source, &PointOutcome),
) -> Result<Vec<PointOutcome>> {
    let mut results = Vec::with_capacity(study.points.len());
    for (k, point) in study.points.iter().enumerate() {
        let (outcome, source) = match store.load::<PointResult>(&point.key) {
            Some(saved) if saved.key == point.key => (Ok(saved), Source::Resumed),
            _ => match compute(point) {
                Ok(fresh) => {
                    store.save(&point.key, &fresh)?;
                    (Ok(fresh), Source::Computed)
                }
                Err(e) => (Err(e.to_string()), Source::Computed),
            },
        };
        report(k, point, source, &outcome);
        results.push(outcome);
    }
    if results.iter().all(|r| r.is_ok()) {
        super::store::remove_partial(store.dir());
    }
    Ok(results)
}

/// The sweeps' outcomes, fits and ranking from the outcome of every point (in the order
/// of [`Study::points`]); failed points are left out of fits and ranking.
pub fn analyse(study: &Study, results: &[PointOutcome]) -> StudyResults {
    let mut sweeps = Vec::new();
    let mut effects = Vec::new();
    for sweep in &study.sweeps {
        let done = |p: usize| results[p].as_ref().ok();
        let nsv: Vec<Option<f64>> = sweep
            .points
            .iter()
            .map(|&p| done(p).map(|r| r.nsv.value(study.metric)))
            .collect();
        // (value in SI, metric) of the points that did not fail.
        let pairs: Vec<(Option<f64>, f64)> = sweep
            .values
            .iter()
            .zip(&nsv)
            .filter_map(|(v, n)| Some((v.si, (*n)?)))
            .collect();
        let found: Vec<f64> = pairs.iter().map(|p| p.1).collect();
        let (fit, fit_error) = match sweep.fit_degree {
            None => (None, None),
            Some(degree) => {
                let x: Vec<f64> = pairs.iter().filter_map(|p| p.0).collect();
                match polynomial_fit(&x, &found, degree) {
                    Ok(f) => (Some(f), None),
                    Err(e) => (None, Some(e.to_string())),
                }
            }
        };
        effects.extend(effect(&sweep.name, &sweep.parameter, &found));
        sweeps.push(SweepResult {
            name: sweep.name.clone(),
            parameter: sweep.parameter.clone(),
            values: sweep.values.iter().map(|v| v.text.clone()).collect(),
            values_si: sweep.values.iter().map(|v| v.si).collect(),
            largest_nsv: sweep
                .points
                .iter()
                .map(|&p| done(p).map(|r| r.nsv.largest))
                .collect(),
            metric_nsv: nsv,
            onset_speed_hz: sweep
                .points
                .iter()
                .map(|&p| done(p).and_then(|r| r.nsv.onset_speed_hz))
                .collect(),
            fit,
            fit_error,
        });
    }
    let ranking = rank(effects);
    StudyResults {
        sweeps,
        ranking_by_parameter: by_parameter(&ranking),
        ranking,
    }
}
