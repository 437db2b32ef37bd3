//! Long work run on a thread of its own while Python's thread watches it: Ctrl-C (which
//! Python sees only on its main thread) stops the work, and a Python callable is told how
//! far it has got. Every call into Python happens on Python's own thread.

use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::Arc;
use std::time::Duration;

use pyo3::prelude::*;

use crate::error::WhirlError;

/// How often the watching thread looks at the signals and the progress.
const POLL: Duration = Duration::from_millis(100);

/// Shared between the work and its watcher (and whatever the work hands it to, hence the
/// `Arc` it comes in).
#[derive(Default)]
pub struct Watch {
    stop: AtomicBool,
    done: AtomicUsize,
    total: AtomicUsize,
}

impl Watch {
    /// Records progress; true when the work is asked to stop.
    pub fn tell(&self, done: usize, total: usize) -> bool {
        self.done.store(done, Ordering::Relaxed);
        self.total.store(total, Ordering::Relaxed);
        self.stopped()
    }

    /// Whether the work is asked to stop (Ctrl-C, or the progress callable said so).
    pub fn stopped(&self) -> bool {
        self.stop.load(Ordering::Relaxed)
    }

    fn progress(&self) -> (usize, usize) {
        (
            self.done.load(Ordering::Relaxed),
            self.total.load(Ordering::Relaxed),
        )
    }
}

/// Steps a fraction of the work is told in: `progress(done, FRACTION_STEPS)`.
pub const FRACTION_STEPS: usize = 1000;

/// The library's progress for work that tells the fraction it has done: it tells `watch`
/// in thousandths and stops the work when the watch is asked to stop.
pub fn fraction_progress(watch: &Arc<Watch>) -> whirl::progress::Progress {
    let told = Arc::clone(watch);
    whirl::progress::Progress::new(move |p| {
        let done = (p.fraction() * FRACTION_STEPS as f64).round() as usize;
        if told.tell(done, FRACTION_STEPS) {
            std::ops::ControlFlow::Break(())
        } else {
            std::ops::ControlFlow::Continue(())
        }
    })
}

/// Runs `work` on a thread of its own, without the GIL, and returns its result. Meanwhile
/// Ctrl-C asks it to stop (its result then says it was interrupted) and `progress(done,
/// total)` is called when the counts change; a true return asks the work to stop too.
pub fn run_watched<T: Send>(
    py: Python<'_>,
    progress: Option<&Bound<'_, PyAny>>,
    work: impl FnOnce(&Arc<Watch>) -> T + Send,
) -> PyResult<T> {
    let watch = Arc::new(Watch::default());
    std::thread::scope(|scope| {
        let handle = scope.spawn(|| work(&watch));
        let mut told = (usize::MAX, usize::MAX);
        let mut failure = None;
        loop {
            let finished = handle.is_finished();
            if failure.is_none() {
                if let Err(e) = py.check_signals() {
                    watch.stop.store(true, Ordering::Relaxed);
                    failure = Some(e);
                }
            }
            let now = watch.progress();
            if let (Some(callback), true) = (progress, now != told && now.1 > 0) {
                told = now;
                match callback.call1(now).and_then(|r| r.is_truthy()) {
                    Ok(true) => watch.stop.store(true, Ordering::Relaxed),
                    Ok(false) => {}
                    Err(e) => {
                        watch.stop.store(true, Ordering::Relaxed);
                        failure.get_or_insert(e);
                    }
                }
            }
            if finished {
                break;
            }
            py.detach(|| std::thread::sleep(POLL));
        }
        let result = handle
            .join()
            .map_err(|_| WhirlError::new_err("a whirl computation stopped unexpectedly (a bug)"))?;
        match failure {
            // The progress display itself failed: that error, not the work's.
            Some(e) if !e.is_instance_of::<pyo3::exceptions::PyKeyboardInterrupt>(py) => Err(e),
            _ => Ok(result),
        }
    })
}

/// Runs `work` as [`run_watched`] does, without a progress callable: the library's progress
/// handed to it stops it at Ctrl-C (its error then says it was interrupted).
pub fn stoppable<T: Send>(
    py: Python<'_>,
    work: impl FnOnce(&whirl::progress::Progress) -> whirl::Result<T> + Send,
) -> PyResult<whirl::Result<T>> {
    run_watched(py, None, |watch| work(&fraction_progress(watch)))
}
