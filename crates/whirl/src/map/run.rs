//! Running a map's sweeps on rayon's threads, and what each cost.
//!
//! A sweep parallelises inside itself (the folds, bifurcations and resolution checks on
//! every thread, the condensations' parallel parts), but its path is one thread's work, so
//! on two cores the second is idle much of the time. A map has many independent sweeps, so
//! by default each runs whole on one thread, the values shared among the threads
//! ([`Parallelism::Values`]); a sweep gives the same bits on any number of threads
//! ([`crate::hbm::sweep`]), so the map's answer does not depend on this choice.

use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Arc, Mutex};
use std::time::Instant;

use serde::{Deserialize, Serialize};

use super::bands::{followed_spans, unstable_bands, UnstableBand};
use super::lines::{resonance_lines, ResonanceLine};
use super::request::MapValue;
use crate::error::{Error, Result};
use crate::hbm::{sweep_with_progress, BifurcationKind, Sweep, SweepOptions};
use crate::progress::{tell, Progress};
use crate::units::rad_s_to_hz as hz;

/// How a map spreads its sweeps over rayon's threads.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize)]
#[cfg_attr(feature = "clap", derive(clap::ValueEnum))]
#[serde(rename_all = "snake_case")]
pub enum Parallelism {
    /// Each sweep on one thread, the values shared among the threads.
    #[default]
    Values,
    /// One sweep after another, each on every thread.
    WithinSweeps,
}

/// What one value's sweep leaves for the map: its unstable bands and resonance lines, how
/// far its branch was followed, and its cost. It holds no sweep (a branch's points are
/// large), so it crosses to and from another process (a cluster's worker) as JSON, exactly.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ValueRun {
    /// Why the sweep failed; `None` when it ran (a map goes on with its other values).
    pub failure: Option<String>,
    /// The unstable bands of its branch, in path order (empty when the sweep failed).
    pub bands: Vec<UnstableBand>,
    /// The resonance lines of its branch, in path order.
    pub lines: Vec<ResonanceLine>,
    /// The branch's first loss of stability, the same as `whirl hbm` reports.
    pub first_loss: Option<FirstLoss>,
    /// Points of the branch: what a sweep's cost grows with (0 when it failed).
    pub points: usize,
    /// Why the branch ended, or why the sweep failed.
    pub end: String,
    /// Stretches the path jumped over (not followed), rad/s.
    pub jumps: Vec<(f64, f64)>,
    /// The highest speed the branch reached, rad/s (`-inf` when it has no point).
    pub reached: f64,
    /// The speeds the branch followed, Hz, merged and ascending (the check counts the
    /// cascade's speeds outside them as not followed).
    pub followed_hz: Vec<[f64; 2]>,
    /// Processor time of the sweep, s, where the system tells it (Linux).
    pub cpu_s: Option<f64>,
    /// Wall-clock time of the sweep, s.
    pub wall_s: f64,
}

/// Where a branch first loses stability, and how.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct FirstLoss {
    /// Speed, rad/s.
    pub frequency: f64,
    /// The bifurcation there.
    pub kind: BifurcationKind,
}

impl ValueRun {
    /// What the map keeps of `sweep` (of `value`'s model), with its cost.
    fn of(sweep: &Result<Sweep>, value: &MapValue, cpu_s: Option<f64>, wall_s: f64) -> Self {
        let failed = |why: String| ValueRun {
            failure: Some(why.clone()),
            bands: Vec::new(),
            lines: Vec::new(),
            first_loss: None,
            points: 0,
            end: why,
            jumps: Vec::new(),
            reached: f64::NEG_INFINITY,
            followed_hz: Vec::new(),
            cpu_s,
            wall_s,
        };
        let branch = match sweep {
            Ok(s) => &s.branch,
            Err(e) => return failed(e.to_string()),
        };
        ValueRun {
            failure: None,
            bands: unstable_bands(branch),
            lines: resonance_lines(branch, &value.model),
            first_loss: branch.first_stability_loss().map(|b| FirstLoss {
                frequency: b.frequency,
                kind: b.kind,
            }),
            points: branch.points.len(),
            end: branch.end.reason(),
            jumps: branch.jumps.clone(),
            reached: branch.speed_span().1,
            followed_hz: followed_spans(branch),
            cpu_s,
            wall_s,
        }
    }

    /// Whether the sweep failed.
    pub fn failed(&self) -> bool {
        self.failure.is_some()
    }

    /// The stretches jumped over, Hz.
    pub fn jumps_hz(&self) -> Vec<[f64; 2]> {
        self.jumps.iter().map(|&(a, b)| [hz(a), hz(b)]).collect()
    }
}

/// The sweep of value `value` alone, on one thread, as a map computes it: what a cluster's
/// worker runs ([`super::distributed_map`]).
///
/// # Errors
/// [`Error::Internal`] when the thread cannot be started. A sweep that fails is no error:
/// its run says why.
pub fn value_run(value: &MapValue, options: &SweepOptions) -> Result<ValueRun> {
    let pool = one_thread()?;
    let counter = Counter {
        done: Arc::new(AtomicUsize::new(0)),
        total: 1,
        progress: None,
    };
    pool.install(|| one_sweep(value, options, &counter, thread_cpu_seconds))
}

fn one_thread() -> Result<rayon::ThreadPool> {
    rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .map_err(|e| Error::Internal(format!("cannot start a thread for a sweep: {e}")))
}

/// The sweeps of `values` with `options`, in the order of `values`.
///
/// # Errors
/// [`Error::Interrupted`] when `progress` stopped them; [`Error::Internal`] when a thread
/// pool cannot be started.
pub(super) fn run_sweeps(
    values: &[MapValue],
    options: &SweepOptions,
    parallelism: Parallelism,
    progress: Option<&Progress>,
) -> Result<Vec<ValueRun>> {
    let counter = Counter {
        done: Arc::new(AtomicUsize::new(0)),
        total: values.len(),
        progress,
    };
    match parallelism {
        Parallelism::Values => across_values(values, options, &counter),
        Parallelism::WithinSweeps => values
            .iter()
            .map(|v| one_sweep(v, options, &counter, process_cpu_seconds))
            .collect(),
    }
}

/// Each sweep on a pool of one thread, as many pools as rayon has threads, taking the next
/// value as each finishes.
fn across_values(
    values: &[MapValue],
    options: &SweepOptions,
    counter: &Counter,
) -> Result<Vec<ValueRun>> {
    let workers = rayon::current_num_threads().clamp(1, values.len().max(1));
    let pools = (0..workers)
        .map(|_| one_thread())
        .collect::<Result<Vec<_>>>()?;
    let next = AtomicUsize::new(0);
    let slots: Mutex<Vec<Option<Result<ValueRun>>>> =
        Mutex::new((0..values.len()).map(|_| None).collect());
    std::thread::scope(|scope| {
        for pool in &pools {
            scope.spawn(|| loop {
                let k = next.fetch_add(1, Ordering::Relaxed);
                let Some(value) = values.get(k) else { break };
                let run = pool.install(|| one_sweep(value, options, counter, thread_cpu_seconds));
                if let Ok(mut slots) = slots.lock() {
                    slots[k] = Some(run);
                }
            });
        }
    });
    let slots = slots
        .into_inner()
        .map_err(|_| Error::Internal("a sweep's thread stopped unexpectedly".into()))?;
    slots
        .into_iter()
        .map(|s| s.unwrap_or_else(|| Err(Error::Internal("a sweep's thread stopped early".into()))))
        .collect()
}

/// The sweep of `value`, timed, its processor time read by `cpu` (the thread's or the
/// process's, whichever does the sweep's work alone).
///
/// # Errors
/// [`Error::Interrupted`] when the counter's progress stopped it (any other failure is
/// the run's).
fn one_sweep(
    value: &MapValue,
    options: &SweepOptions,
    counter: &Counter,
    cpu: fn() -> Option<f64>,
) -> Result<ValueRun> {
    let (start, cpu_start) = (Instant::now(), cpu());
    let inner = counter.for_value(&value.text);
    let sweep = sweep_with_progress(&value.model, options, Some(&inner));
    if let Err(Error::Interrupted(why)) = sweep {
        return Err(Error::Interrupted(why));
    }
    counter.finished(&value.text);
    let cpu_s = cpu().zip(cpu_start).map(|(b, a)| b - a);
    Ok(ValueRun::of(
        &sweep,
        value,
        cpu_s,
        start.elapsed().as_secs_f64(),
    ))
}

/// Counts the finished values and tells the map's progress, passing its answer (stop or
/// go on) to every sweep.
struct Counter<'a> {
    done: Arc<AtomicUsize>,
    total: usize,
    progress: Option<&'a Progress>,
}

impl Counter<'_> {
    /// A progress for the sweep of value `text`: the map's, told of the values done by
    /// the time of each report (sweeps on other threads finish meanwhile).
    fn for_value(&self, text: &str) -> Progress {
        let outer = self.progress.cloned();
        let (text, total, count) = (text.to_string(), self.total, Arc::clone(&self.done));
        Progress::new(move |r| {
            let done = count.load(Ordering::Relaxed);
            let message = format!("{done}/{total} values; {text}: {}", r.message);
            tell(outer.as_ref(), done as f64, total as f64, || message)
        })
    }

    fn finished(&self, text: &str) {
        let done = self.done.fetch_add(1, Ordering::Relaxed) + 1;
        let _ = tell(self.progress, done as f64, self.total as f64, || {
            format!("{done}/{} values; {text} done", self.total)
        });
    }
}

/// Processor time of the process, s (every thread), from Linux's `/proc/self/stat` (user
/// and system time in clock ticks of 1/100 s, the kernel's fixed USER_HZ).
pub(super) fn process_cpu_seconds() -> Option<f64> {
    let text = std::fs::read_to_string("/proc/self/stat").ok()?;
    // The command name, in parentheses, may hold spaces: count fields after it.
    let fields: Vec<&str> = text.rsplit_once(')')?.1.split_whitespace().collect();
    let ticks = |k: usize| fields.get(k)?.parse::<f64>().ok();
    // utime and stime are the 14th and 15th fields; the 3rd is the first after the name.
    Some((ticks(11)? + ticks(12)?) / 100.0)
}

/// Processor time of the calling thread, s, from Linux's scheduler statistics (ns).
fn thread_cpu_seconds() -> Option<f64> {
    let text = std::fs::read_to_string("/proc/thread-self/schedstat").ok()?;
    let ns: f64 = text.split_whitespace().next()?.parse().ok()?;
    (ns > 0.0).then_some(1e-9 * ns)
}

crate::given::choice!(Parallelism { "values" => Parallelism::Values, "within-sweeps" => Parallelism::WithinSweeps });
