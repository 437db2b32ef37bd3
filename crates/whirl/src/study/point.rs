//! One point of a study: its cascade ([`crate::nsv::cascade`]) and what the study keeps of
//! it (the NSV summary and the colour map).

use std::path::Path;

use super::results::{CascadeMap, NsvSummary, PointResult};
use super::Point;
use crate::error::{InputError, Result};
use crate::nsv::{cascade, Cascade, CascadeOptions};
use crate::progress::Progress;

/// The cascade options of a point: the cascade's defaults, changed where the study's
/// `[cascade]` table says so (its [`crate::nsv::CascadeRequest`], as the command line and
/// the Python package ask). Without speeds, the cascade's default speeds
/// ([`crate::nsv::default_speeds`]), as on the command line.
///
/// # Errors
/// [`Error::Input`](crate::Error::Input) when the point's `[cascade]` settings do not fit
/// its model (e.g. no speeds and no operating range).
pub fn cascade_options(point: &Point) -> Result<CascadeOptions> {
    let s = &point.cascade;
    s.options(&point.model).map_err(|e| match e {
        // The only way the request fails: no speeds and no range to take the default from;
        // named as the study file's field.
        crate::Error::Input(_) if s.speeds.is_none() => InputError::field(
            "cascade.speeds",
            "the model has no [operating] speed range to take the speeds from",
        )
        .help("give them, e.g. speeds = \"1:750Hz:150\" in [cascade]")
        .into(),
        e => e,
    })
}

/// Computes a point's cascade (resuming from, and saving speeds in, `checkpoint`) and
/// keeps what the study needs of it.
///
/// # Errors
/// The errors of [`cascade_options`] and of [`crate::nsv::cascade`] (including
/// [`Error::Interrupted`](crate::Error::Interrupted) when stopped on request).
pub fn compute(
    point: &Point,
    checkpoint: Option<&Path>,
    progress: Option<&Progress>,
) -> Result<PointResult> {
    let options = cascade_options(point)?;
    let c = cascade(&point.model, &options, checkpoint, progress)?;
    let threshold = point.cascade.threshold_m();
    Ok(point_result(&point.key, &c, threshold))
}

/// The NSV summary and colour map of a cascade. The map stops at the top speed (where
/// the 1X line leaves it): the NSV of interest lies below, and the band above it (up to the
/// contact frequencies, 13 kHz with 32 rollers) would multiply the checkpoint's size.
pub fn point_result(key: &str, c: &Cascade, threshold: f64) -> PointResult {
    let summary = c.nsv_summary(threshold);
    let largest = summary.largest.as_ref();
    let speeds_hz = c.speeds_hz();
    let top = speeds_hz.iter().copied().fold(0.0, f64::max);
    let rows = c.frequency_hz.iter().take_while(|&&f| f <= top).count();
    let amplitude = (0..rows)
        .map(|k| {
            c.points
                .iter()
                .map(|p| p.amplitude.get(k).map(|&a| a as f32))
                .collect()
        })
        .collect();
    PointResult {
        key: key.to_string(),
        nsv: NsvSummary {
            largest: largest.map_or(0.0, |l| l.amplitude_m),
            largest_speed_hz: largest.map(|l| l.speed_hz),
            largest_frequency_hz: largest.map(|l| l.frequency_hz),
            largest_class: largest.map(|l| l.class.name().to_string()),
            onset_speed_hz: summary.onset_speed_hz,
            median: summary.statistics.map_or(0.0, |st| st.median_m),
            p90: summary.statistics.map_or(0.0, |st| st.p90_m),
            mean: summary.statistics.map_or(0.0, |st| st.mean_m),
            dominant_class: summary.dominant_class.map(|c| c.name().to_string()),
            largest_synchronous: c.points.iter().map(|p| p.one_x_m).fold(0.0, f64::max),
        },
        map: CascadeMap {
            speeds_hz,
            frequencies_hz: c.frequency_hz[..rows].to_vec(),
            amplitude,
        },
        wall_time_s: c.wall_time_s,
        resumed_speeds: c.resumed,
    }
}
