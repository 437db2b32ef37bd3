//! Running a map's sweeps on rayon's threads, and what each cost.
//!
//! A sweep parallelises inside itself (the folds, bifurcations and resolution checks on
//! every thread, the condensations' parallel parts), but its path is one thread's work, so
//! on two cores the second is idle much of the time. A map has many independent sweeps, so
//! by default each runs whole on one thread, the values shared among the threads
//! ([`Parallelism::Values`]); a sweep gives the same bits on any number of threads
//! ([`crate::hbm::sweep`]), so the map's answer does not depend on this choice.

use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Mutex;
use std::time::Instant;

use serde::Serialize;

use super::request::MapValue;
use crate::error::{Error, Result};
use crate::hbm::{sweep_with_progress, Sweep, SweepOptions};
use crate::progress::{tell, Progress};

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

/// One value's sweep and its cost.
#[derive(Debug)]
pub struct ValueRun {
    /// The sweep, or why it failed (a map goes on with its other values).
    pub sweep: Result<Sweep>,
    /// Processor time of the sweep, s, where the system tells it (Linux).
    pub cpu_s: Option<f64>,
    /// Wall-clock time of the sweep, s.
    pub wall_s: f64,
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
        done: AtomicUsize::new(0),
        total: values.len(),
        progress,
    };
    let runs = match parallelism {
        Parallelism::Values => across_values(values, options, &counter)?,
        Parallelism::WithinSweeps => values
            .iter()
            .map(|v| one_sweep(v, options, &counter, process_cpu_seconds))
            .collect(),
    };
    let mut runs = runs;
    if let Some(k) = runs
        .iter()
        .position(|r| matches!(r.sweep, Err(Error::Interrupted(_))))
    {
        return Err(runs
            .swap_remove(k)
            .sweep
            .err()
            .unwrap_or_else(|| Error::Interrupted("the map was stopped".into())));
    }
    Ok(runs)
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
        .map(|_| rayon::ThreadPoolBuilder::new().num_threads(1).build())
        .collect::<std::result::Result<Vec<_>, _>>()
        .map_err(|e| Error::Internal(format!("cannot start a thread for a sweep: {e}")))?;
    let next = AtomicUsize::new(0);
    let slots: Mutex<Vec<Option<ValueRun>>> = Mutex::new((0..values.len()).map(|_| None).collect());
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
        .map(|s| s.ok_or_else(|| Error::Internal("a sweep's thread stopped early".into())))
        .collect()
}

/// The sweep of `value`, timed, its processor time read by `cpu` (the thread's or the
/// process's, whichever does the sweep's work alone).
fn one_sweep(
    value: &MapValue,
    options: &SweepOptions,
    counter: &Counter,
    cpu: fn() -> Option<f64>,
) -> ValueRun {
    let (start, cpu_start) = (Instant::now(), cpu());
    let inner = counter.for_value(&value.text);
    let sweep = sweep_with_progress(&value.model, options, Some(&inner));
    counter.finished(&value.text);
    ValueRun {
        sweep,
        cpu_s: cpu().zip(cpu_start).map(|(b, a)| b - a),
        wall_s: start.elapsed().as_secs_f64(),
    }
}

/// Counts the finished values and tells the map's progress, passing its answer (stop or
/// go on) to every sweep.
struct Counter<'a> {
    done: AtomicUsize,
    total: usize,
    progress: Option<&'a Progress>,
}

impl Counter<'_> {
    /// A progress for the sweep of value `text`: the map's, told of the values done.
    fn for_value(&self, text: &str) -> Progress {
        let outer = self.progress.cloned();
        let (text, total) = (text.to_string(), self.total);
        let done = self.done.load(Ordering::Relaxed);
        Progress::new(move |r| {
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
