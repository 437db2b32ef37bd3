//! One convention for the progress of long work: a time simulation, a harmonic-balance
//! sweep, a cascade, a study's points. The work tells a [`Progress`] how far it has got
//! ([`Report`]: `done` of `total`, and a message a display can show as it is), and the
//! answer says whether to go on: `ControlFlow::Break(())` stops the work at its next safe
//! point, which then ends as its documentation says (a simulation with
//! [`crate::time::RunStatus::Stopped`], a sweep or a cascade with
//! [`crate::Error::Interrupted`], the cascade's finished speeds kept in its checkpoint).
//! A display paces itself: a simulation reports at most a thousand times, a sweep at every
//! solve, a cascade after every speed, the linear analyses (Campbell diagram, unbalance
//! response, FRF, critical-speed map, mesh convergence) after every speed, frequency,
//! stiffness or mesh (`map_told`).

use std::fmt;
use std::ops::ControlFlow;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Arc;

use rayon::prelude::*;

use crate::error::{Error, Result};

/// How far a piece of long work has got.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Report<'a> {
    /// Work done, in the units of `total` (seconds simulated, hertz swept, speeds
    /// computed). Work loaded rather than computed (a cascade's speeds from its
    /// checkpoint) is in neither, so `done / total` paces an estimate of the time left.
    pub done: f64,
    /// The work to do; it may grow (a cascade's refinement adds speeds).
    pub total: f64,
    /// How far, in words: `37/150 speeds (12 from the checkpoint)`, `12.3 Hz of 330.0 Hz`.
    pub message: &'a str,
}

impl Report<'_> {
    /// The fraction done, from 0 to 1 (1 when there is nothing to do).
    pub fn fraction(&self) -> f64 {
        if self.total > 0.0 {
            (self.done / self.total).clamp(0.0, 1.0)
        } else {
            1.0
        }
    }
}

/// Told how far long work has got; returns whether it goes on. Cheap to clone (shared), and
/// callable from the worker threads of a parallel cascade.
#[derive(Clone)]
pub struct Progress(Arc<dyn Fn(Report<'_>) -> ControlFlow<()> + Send + Sync>);

impl Progress {
    /// A progress that calls `tell` with each report.
    pub fn new(tell: impl Fn(Report<'_>) -> ControlFlow<()> + Send + Sync + 'static) -> Self {
        Progress(Arc::new(tell))
    }

    /// Tells of `done` of `total`, with `message`; returns whether to go on.
    pub fn tell(&self, done: f64, total: f64, message: &str) -> ControlFlow<()> {
        (self.0)(Report {
            done,
            total,
            message,
        })
    }
}

impl fmt::Debug for Progress {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("Progress(..)")
    }
}

/// Tells `progress`, when there is one; going on when there is none.
pub(crate) fn tell(
    progress: Option<&Progress>,
    done: f64,
    total: f64,
    message: impl FnOnce() -> String,
) -> ControlFlow<()> {
    progress.map_or(ControlFlow::Continue(()), |p| {
        p.tell(done, total, &message())
    })
}

/// `work` applied to every item in parallel, in order, telling `progress` after each item:
/// `done` counts from `before` (items finished by earlier calls of the same analysis) of
/// `total`, with the message `done/total noun`. A stop asked by `progress` ends the map with
/// [`Error::Interrupted`] naming `what` was stopped; the first error of `work` ends it too.
pub(crate) fn map_told<T: Sync, R: Send>(
    items: &[T],
    progress: Option<&Progress>,
    (before, total): (usize, usize),
    (what, noun): (&str, &str),
    work: impl Fn(&T) -> Result<R> + Sync,
) -> Result<Vec<R>> {
    let done = AtomicUsize::new(before);
    items
        .par_iter()
        .map(|item| {
            let r = work(item)?;
            let now = done.fetch_add(1, Ordering::Relaxed) + 1;
            match tell(progress, now as f64, total as f64, || {
                format!("{now}/{total} {noun}")
            }) {
                ControlFlow::Continue(()) => Ok(r),
                ControlFlow::Break(()) => Err(Error::Interrupted(format!(
                    "{what} was stopped after {now} of {total} {noun}: nothing was kept"
                ))),
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use std::sync::Mutex;

    use super::*;

    #[test]
    fn map_told_counts_every_item_and_stops_when_asked() {
        let seen = Arc::new(Mutex::new(Vec::new()));
        let log = Arc::clone(&seen);
        let progress = Progress::new(move |r| {
            log.lock()
                .unwrap()
                .push((r.done, r.total, r.message.to_string()));
            ControlFlow::Continue(())
        });
        let squares = map_told(&[1, 2, 3], Some(&progress), (2, 5), ("x", "items"), |v| {
            Ok(v * v)
        })
        .unwrap();
        assert_eq!(squares, vec![1, 4, 9]);
        let mut seen = seen.lock().unwrap().clone();
        seen.sort_by(|a, b| a.0.total_cmp(&b.0));
        let expected: Vec<(f64, f64, String)> = (3..=5)
            .map(|d| (d as f64, 5.0, format!("{d}/5 items")))
            .collect();
        assert_eq!(seen, expected);

        let stop = Progress::new(|_| ControlFlow::Break(()));
        let e = map_told(&[1, 2], Some(&stop), (0, 2), ("the map", "items"), |&v| {
            Ok(v)
        })
        .unwrap_err();
        assert!(matches!(e, Error::Interrupted(m) if m.starts_with("the map was stopped")));
    }
}
