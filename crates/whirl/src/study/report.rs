//! What a study reports ([`crate::report`]): each point's NSV, each sweep's NSV versus its
//! parameter with the fits, and the ranking of the parameters, as `whirl study` writes
//! them.

use serde::Serialize;

use super::fit::PolynomialFit;
use super::ranking::Effect;
use super::results::{Metric, NsvSummary, PointOutcome, StudyResults, SweepResult};
use super::Study;
use crate::report::{Report, Table};

/// A study's points computed and analysed.
#[derive(Debug, Clone)]
pub struct StudyReport {
    /// The study.
    pub study: Study,
    /// Each point's result or why it failed, in [`Study::points`] order.
    pub results: Vec<PointOutcome>,
    /// The sweeps, fits and ranking.
    pub outcome: StudyResults,
}

/// The key numbers of a [`StudyReport`].
#[derive(Debug, Clone, Serialize)]
pub struct StudySummary {
    /// The model file.
    pub model_file: String,
    /// Title.
    pub title: String,
    /// The NSV statistic of the fits and the ranking.
    pub metric: Metric,
    /// What it is.
    pub metric_description: &'static str,
    /// Each point.
    pub points: Vec<PointSummary>,
    /// Each sweep.
    pub sweeps: Vec<SweepResult>,
    /// The sweeps by their effect on the metric, largest first.
    pub ranking: Vec<Effect>,
    /// The same per parameter.
    pub ranking_by_parameter: Vec<Effect>,
    /// Points that failed.
    pub failed_points: usize,
    /// Computing time of the cascades, summed, s.
    pub cascade_time_s: f64,
}

/// One point: its NSV, or why it failed.
#[derive(Debug, Clone, Serialize)]
#[serde(untagged)]
pub enum PointSummary {
    /// A computed point.
    Done {
        /// Its fingerprint.
        key: String,
        /// What differs from the base.
        label: String,
        /// Its NSV.
        nsv: NsvSummary,
        /// Its cascade's computing time, s.
        wall_time_s: f64,
    },
    /// A failed point.
    Failed {
        /// Its fingerprint.
        key: String,
        /// What differs from the base.
        label: String,
        /// Why it failed.
        error: String,
    },
}

impl Report for StudyReport {
    type Summary = StudySummary;

    fn summary(&self) -> StudySummary {
        let (study, results) = (&self.study, &self.results);
        StudySummary {
            model_file: study.model_file.display().to_string(),
            title: study.title.clone(),
            metric: study.metric,
            metric_description: study.metric.describe(),
            points: study
                .points
                .iter()
                .zip(results)
                .map(|(p, r)| match r {
                    Ok(r) => PointSummary::Done {
                        key: p.key.clone(),
                        label: p.label(),
                        nsv: r.nsv.clone(),
                        wall_time_s: r.wall_time_s,
                    },
                    Err(e) => PointSummary::Failed {
                        key: p.key.clone(),
                        label: p.label(),
                        error: e.clone(),
                    },
                })
                .collect(),
            sweeps: self.outcome.sweeps.clone(),
            ranking: self.outcome.ranking.clone(),
            ranking_by_parameter: self.outcome.ranking_by_parameter.clone(),
            failed_points: results.iter().filter(|r| r.is_err()).count(),
            cascade_time_s: results.iter().flatten().map(|r| r.wall_time_s).sum(),
        }
    }

    /// `points` (each point's NSV or error), `sweeps` (the NSV at each value of each
    /// sweep), `fits` (the polynomial of each sweep that asked for one), `ranking` and
    /// `ranking_by_parameter` (effects on the metric, largest first).
    fn tables(&self) -> Vec<Table> {
        vec![
            self.points_table(),
            sweeps_table(&self.outcome.sweeps),
            fits_table(&self.outcome.sweeps),
            ranking_table("ranking", &self.outcome.ranking),
            ranking_table("ranking_by_parameter", &self.outcome.ranking_by_parameter),
        ]
    }
}

impl StudyReport {
    fn points_table(&self) -> Table {
        let r = &self.results;
        let nsv = |f: fn(&NsvSummary) -> f64| {
            r.iter()
                .map(move |r| r.as_ref().map_or(f64::NAN, |r| f(&r.nsv)))
        };
        let class = |f: fn(&NsvSummary) -> Option<String>| {
            r.iter()
                .map(move |r| r.as_ref().ok().and_then(|r| f(&r.nsv)).unwrap_or_default())
        };
        let mut t = Table::new("points");
        t.counts("point", 0..r.len())
            .text("changes", self.study.points.iter().map(|p| p.label()))
            .numbers("largest_nsv_m", nsv(|n| n.largest))
            .numbers(
                "largest_nsv_speed_hz",
                nsv(|n| n.largest_speed_hz.unwrap_or(f64::NAN)),
            )
            .numbers(
                "largest_nsv_frequency_hz",
                nsv(|n| n.largest_frequency_hz.unwrap_or(f64::NAN)),
            )
            .text("largest_nsv_class", class(|n| n.largest_class.clone()))
            .numbers(
                "onset_speed_hz",
                nsv(|n| n.onset_speed_hz.unwrap_or(f64::NAN)),
            )
            .numbers("median_nsv_m", nsv(|n| n.median))
            .numbers("p90_nsv_m", nsv(|n| n.p90))
            .numbers("mean_nsv_m", nsv(|n| n.mean))
            .text("dominant_class", class(|n| n.dominant_class.clone()))
            .numbers("largest_1x_m", nsv(|n| n.largest_synchronous))
            .numbers(
                "wall_time_s",
                r.iter()
                    .map(|r| r.as_ref().map_or(f64::NAN, |r| r.wall_time_s)),
            )
            .text(
                "error",
                r.iter()
                    .map(|r| r.as_ref().err().cloned().unwrap_or_default()),
            );
        t
    }
}

/// The NSV at each value of each sweep.
fn sweeps_table(sweeps: &[SweepResult]) -> Table {
    let rows: Vec<(usize, &SweepResult, usize)> = sweeps
        .iter()
        .enumerate()
        .flat_map(|(i, s)| (0..s.values.len()).map(move |j| (i, s, j)))
        .collect();
    let mut t = Table::new("sweeps");
    t.counts("sweep", rows.iter().map(|r| r.0))
        .text("name", rows.iter().map(|(_, s, _)| s.name.as_str()))
        .text(
            "parameter",
            rows.iter().map(|(_, s, _)| s.parameter.as_str()),
        )
        .text("value", rows.iter().map(|(_, s, j)| s.values[*j].as_str()))
        .optional("value_si", rows.iter().map(|(_, s, j)| s.values_si[*j]))
        .optional(
            "largest_nsv_m",
            rows.iter().map(|(_, s, j)| s.largest_nsv[*j]),
        )
        .optional(
            "metric_nsv_m",
            rows.iter().map(|(_, s, j)| s.metric_nsv[*j]),
        )
        .optional(
            "onset_speed_hz",
            rows.iter().map(|(_, s, j)| s.onset_speed_hz[*j]),
        );
    t
}

/// The polynomial of each sweep that has one: degree, coefficients p1..p4 in the fit's
/// order (missing beyond the degree), fit quality.
fn fits_table(sweeps: &[SweepResult]) -> Table {
    let fits: Vec<(usize, &SweepResult, &PolynomialFit)> = sweeps
        .iter()
        .enumerate()
        .filter_map(|(i, s)| Some((i, s, s.fit.as_ref()?)))
        .collect();
    let mut t = Table::new("fits");
    t.counts("sweep", fits.iter().map(|f| f.0))
        .text("name", fits.iter().map(|(_, s, _)| s.name.as_str()))
        .counts(
            "degree",
            fits.iter().map(|(_, _, f)| f.coefficients.len() - 1),
        );
    for k in 0..4 {
        t.optional(
            format!("p{}", k + 1),
            fits.iter().map(|(_, _, f)| f.coefficients.get(k).copied()),
        );
    }
    t.numbers("r_squared", fits.iter().map(|(_, _, f)| f.r_squared))
        .numbers(
            "rms_residual_m",
            fits.iter().map(|(_, _, f)| f.rms_residual),
        );
    t
}

/// Effects on the study's metric, largest first.
fn ranking_table(name: &str, effects: &[Effect]) -> Table {
    let mut t = Table::new(name);
    t.counts("rank", (0..effects.len()).map(|k| k + 1))
        .text("sweep", effects.iter().map(|e| e.sweep.as_str()))
        .text("parameter", effects.iter().map(|e| e.parameter.as_str()))
        .numbers("smallest_metric_m", effects.iter().map(|e| e.smallest))
        .numbers("largest_metric_m", effects.iter().map(|e| e.largest))
        .optional("relative_change", effects.iter().map(|e| e.relative_change));
    t
}
