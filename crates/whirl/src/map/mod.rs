//! The NSV map: where the synchronous orbit of a rotor on roller bearings is unstable, over
//! its speed and one model parameter (clearance, damping, unbalance, roller count), and by
//! which bifurcation each unstable band opens (docs/theory.md section 7).
//!
//! For each value p_j of the parameter the map follows the periodic (synchronous) response
//! q(t; w, p_j) by harmonic balance over the speed range, with the Floquet multipliers mu of
//! every orbit ([`crate::hbm::sweep()`]). Non-synchronous vibration can only grow where that
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
//! - [`Parallelism`]: the sweeps one per thread, or each on every thread;
//!   [`distributed_map`]: each value's sweep on a cluster's worker ([`map_value`]).

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
pub use run::{FirstLoss, Parallelism, ValueRun};

use crate::error::{Error, Result};
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
    let clock = Clock {
        start,
        cpu_start,
        remote_cpu_s: 0.0,
    };
    assemble(request, values, runs, parallelism, clock, progress)
}

/// Computes the sweeps of the values given by index, handing each value's run to the
/// callback as it arrives (in any order): the map's work sent elsewhere, such as to a
/// cluster's workers, each of which runs [`map_value`].
pub type ValueRunner<'a> =
    &'a dyn Fn(&[usize], &mut dyn FnMut(usize, ValueRun) -> Result<()>) -> Result<()>;

/// [`map`] with every value's sweep computed by `runner` (on a cluster's workers) instead
/// of on this machine's threads: the same report, to the bit. The checks' and the
/// confirmation's cascades run here. The report's processor time adds the workers' sweeps
/// to this process's.
///
/// # Errors
/// Those of [`map`], the runner's, and [`Error::Internal`] when the runner leaves a value
/// out or gives one twice.
pub fn distributed_map(
    request: &MapRequest,
    progress: Option<&Progress>,
    runner: ValueRunner<'_>,
) -> Result<MapReport> {
    let values = request.values()?;
    let (start, cpu_start) = (Instant::now(), run::process_cpu_seconds());
    let mut slots: Vec<Option<ValueRun>> = vec![None; values.len()];
    let indices: Vec<usize> = (0..values.len()).collect();
    let mut done = 0usize;
    runner(&indices, &mut |j, run| {
        let slot = slots.get_mut(j).ok_or_else(|| {
            Error::Internal(format!("the runner gave value {j} of {}", indices.len()))
        })?;
        if slot.replace(run).is_some() {
            return Err(Error::Internal(format!("the runner gave value {j} twice")));
        }
        done += 1;
        let total = indices.len();
        let told = crate::progress::tell(progress, done as f64, total as f64, || {
            format!("{done}/{total} values")
        });
        if told.is_break() {
            return Err(Error::Interrupted(format!(
                "the map was stopped after {done} of {total} values"
            )));
        }
        Ok(())
    })?;
    let runs = slots
        .into_iter()
        .enumerate()
        .map(|(j, r)| r.ok_or_else(|| Error::Internal(format!("the runner left value {j} out"))))
        .collect::<Result<Vec<_>>>()?;
    let clock = Clock {
        start,
        cpu_start,
        remote_cpu_s: runs.iter().filter_map(|r| r.cpu_s).sum(),
    };
    assemble(request, values, runs, Parallelism::Values, clock, progress)
}

/// Value `index`'s sweep (of [`MapRequest::values`]), on one thread, as the map computes
/// it: what a [`ValueRunner`]'s workers compute.
///
/// # Errors
/// As [`MapRequest::values`]; [`Error::InvalidOption`] for an index past the values.
pub fn map_value(request: &MapRequest, index: usize) -> Result<ValueRun> {
    let values = request.values()?;
    let value = values.get(index).ok_or_else(|| {
        Error::InvalidOption(format!(
            "the map has {} values; there is no value {index}",
            values.len()
        ))
    })?;
    run::value_run(value, &request.sweep_options())
}

/// When a map started, and the processor time its sweeps took elsewhere.
struct Clock {
    start: Instant,
    cpu_start: Option<f64>,
    remote_cpu_s: f64,
}

/// The report of `values` and their runs: the checks and the confirmation run, the cost
/// read off `clock`.
///
/// # Errors
/// As [`check_value`] and [`confirm_query`].
fn assemble(
    request: &MapRequest,
    values: Vec<MapValue>,
    runs: Vec<ValueRun>,
    parallelism: Parallelism,
    clock: Clock,
    progress: Option<&Progress>,
) -> Result<MapReport> {
    let entries: Vec<MapEntry> = values
        .into_iter()
        .zip(runs)
        .map(|(value, run)| MapEntry { value, run })
        .collect();
    let checks = request
        .check
        .iter()
        .map(|text| check_value(&entries, text, request, progress))
        .collect::<Result<_>>()?;
    let mut report = MapReport {
        parameter: request.parameter().to_string(),
        options: request.sweep_options(),
        entries,
        checks,
        confirmation: None,
        clear_below: request.clear_below,
        parallelism,
        threads: rayon::current_num_threads(),
        cpu_s: None,
        wall_s: 0.0,
    };
    if let (true, Some(speed)) = (request.confirm, request.clear_below) {
        report.confirmation = confirm_query(&report, speed, request, progress)?;
    }
    report.cpu_s = run::process_cpu_seconds()
        .zip(clock.cpu_start)
        .map(|(b, a)| b - a + clock.remote_cpu_s);
    report.wall_s = clock.start.elapsed().as_secs_f64();
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
    let predicted = check::Predicted {
        followed: &entry.run.followed_hz,
        bands: &entry.run.bands,
        lines: &entry.run.lines,
    };
    Ok(check::check(
        &entry.value.text,
        &cascade,
        &predicted,
        request.check_level(),
        check::DEFAULT_SPEED_TOLERANCE_HZ,
    ))
}
