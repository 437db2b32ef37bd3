//! The NSV map: where the synchronous orbit of a rotor on roller bearings is unstable, over
//! its speed and one model parameter (clearance, damping, unbalance, roller count), and by
//! which bifurcation each unstable band opens (docs/theory.md section 7).
//!
//! For each value p_j of the parameter the map follows the periodic (synchronous) response
//! q(t; w, p_j) by harmonic balance over the speed range, with the Floquet multipliers mu of
//! every orbit ([`crate::hbm::sweep`]). Non-synchronous vibration can only grow where that
//! orbit is unstable, |mu| > 1 for some multiplier, so the unstable bands in (w, p) bound
//! where it can appear, and the multiplier that crosses the unit circle at a band's edge
//! says how: +1 a fold (a jump to another orbit) or symmetry breaking, -1 period doubling
//! (w/2), a complex pair Neimark-Sacker (an incommensurate frequency: NSV proper).
//!
//! - [`request`]: the parameter, its values and the sweeps' settings, each value's model
//!   made by editing the model file's text as a study does ([`crate::study::path`]).
//! - [`bands`]: the unstable bands of one sweep, from its own bifurcations.
//! - [`lines`]: the resonance lines of one sweep, where NSV can appear on a stable orbit.
//! - [`check`]: the map against default cascades at a few values.
//! - [`report`]: the summary, the tables and the design query (which values keep the orbit
//!   stable below a speed).
//! - [`Parallelism`]: the sweeps one per thread, or each on every thread.

pub mod bands;
pub mod check;
pub mod lines;
pub mod report;
pub mod request;
mod run;

use std::time::Instant;

pub use bands::{unstable_bands, Edge, Growing, Growth, UnstableBand};
pub use check::{CascadeCheck, Disagreement};
pub use lines::{resonance_lines, Excitation, ResonanceLine};
pub use report::{growing_text, ClearBelow, Clearance, MapEntry, MapReport, MapSummary};
pub use request::{MapRequest, MapValue, DEFAULT_PARAMETER, MAX_VALUES};
pub use run::{Parallelism, ValueRun};

use crate::error::Result;
use crate::nsv::{cascade, even_speeds, CascadeOptions, DEFAULT_SPEED_COUNT};
use crate::progress::Progress;

/// The map `request` asks for, its sweeps one per thread.
///
/// # Errors
/// As [`MapRequest::values`]: a bad parameter path, no values, a value the model refuses.
/// A sweep that fails does not stop the map: its value reports why.
pub fn map(request: &MapRequest) -> Result<MapReport> {
    map_with(request, Parallelism::default(), None)
}

/// As [`map`], the sweeps spread over rayon's threads as `parallelism` says, telling
/// `progress` of the values done; `progress` may stop the map.
///
/// # Errors
/// As [`map`]; [`crate::Error::Interrupted`] when `progress` stopped it.
pub fn map_with(
    request: &MapRequest,
    parallelism: Parallelism,
    progress: Option<&Progress>,
) -> Result<MapReport> {
    let values = request.values()?;
    let options = request.sweep_options();
    let (start, cpu_start) = (Instant::now(), run::process_cpu_seconds());
    let runs = run::run_sweeps(&values, &options, parallelism, progress)?;
    let entries = values
        .into_iter()
        .zip(runs)
        .map(|(value, run)| {
            let sweep = run.sweep.as_ref().ok();
            MapEntry {
                bands: sweep.map_or(Vec::new(), |s| unstable_bands(&s.branch)),
                lines: sweep.map_or(Vec::new(), |s| resonance_lines(&s.branch, &value.model)),
                value,
                run,
            }
        })
        .collect::<Vec<MapEntry>>();
    let checks = request
        .check
        .iter()
        .map(|text| check_value(&entries, text, request, progress))
        .collect::<Result<_>>()?;
    let mut report = MapReport {
        parameter: request.parameter().to_string(),
        options,
        entries,
        checks,
        confirmation: None,
        clear_below: request.clear_below,
        parallelism,
        threads: rayon::current_num_threads(),
        cpu_s: run::process_cpu_seconds()
            .zip(cpu_start)
            .map(|(b, a)| b - a),
        wall_s: start.elapsed().as_secs_f64(),
    };
    if let (true, Some(speed)) = (request.confirm, request.clear_below) {
        report.confirmation = confirm_query(&report, speed, request, progress)?;
    }
    Ok(report)
}

/// The default cascade of the largest value clear below `speed` (rad/s), from the map's
/// first speed up to it, against the check's level; `None` when no value is clear.
///
/// # Errors
/// As [`crate::nsv::cascade`]; [`crate::Error::Interrupted`] when `progress` stopped it.
fn confirm_query(
    report: &MapReport,
    speed: f64,
    request: &MapRequest,
    progress: Option<&Progress>,
) -> Result<Option<check::Confirmation>> {
    let query = report.clear_below(speed);
    let Some(value) = query.largest_clear else {
        return Ok(None);
    };
    let Some(entry) = report.entries.iter().find(|e| e.value.text == value) else {
        return Ok(None);
    };
    let model = &entry.value.model;
    let options = CascadeOptions::new(model, even_speeds(request.from, speed, DEFAULT_SPEED_COUNT));
    let cascade = cascade(model, &options, None, progress)?;
    Ok(Some(check::confirm(
        &value,
        &cascade,
        request.check_level(),
    )))
}

/// The default cascade of the value written `text` (one of `entries`, as
/// [`MapRequest::values`] checked) over the map's speed range, against its bands and lines.
///
/// # Errors
/// As [`crate::nsv::cascade`] (a diverging start);
/// [`crate::Error::Interrupted`] when `progress` stopped it.
fn check_value(
    entries: &[MapEntry],
    text: &str,
    request: &MapRequest,
    progress: Option<&Progress>,
) -> Result<CascadeCheck> {
    let wanted = crate::study::plain_text(&request::toml_value(text));
    let entry = entries
        .iter()
        .find(|e| e.value.text == wanted)
        .ok_or_else(|| {
            crate::Error::Internal(format!("the checked value {wanted} was not mapped"))
        })?;
    let model = &entry.value.model;
    let speeds = even_speeds(request.from, request.to, DEFAULT_SPEED_COUNT);
    let options = CascadeOptions::new(model, speeds);
    let cascade = cascade(model, &options, None, progress)?;
    let followed = entry
        .run
        .sweep
        .as_ref()
        .map_or(Vec::new(), |s| bands::followed_spans(&s.branch));
    let predicted = check::Predicted {
        followed: &followed,
        bands: &entry.bands,
        lines: &entry.lines,
    };
    Ok(check::check(
        &entry.value.text,
        &cascade,
        &predicted,
        request.check_level(),
        check::DEFAULT_SPEED_TOLERANCE_HZ,
    ))
}
