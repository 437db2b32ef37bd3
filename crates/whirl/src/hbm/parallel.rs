//! Jobs over copies of one problem on rayon's threads, with the results, and the first
//! error, that one thread running them in turn would give.

use crate::error::Result;
use rayon::prelude::*;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};

/// Runs `job(problem, k)` for every k in 0..`count` on rayon's threads, each thread with
/// one of `problems` (copies of the same problem: a job must give the same bits on any of
/// them, whatever they ran before), and returns the results in order of k. A thread takes
/// the next k in turn, and none starts a job once one has failed: every job before a
/// failed one was taken before it and so finished, and the error returned is the first in
/// order, the one a single thread running the jobs in turn would stop at.
///
/// # Errors
/// The first job's error in order of k.
pub(super) fn on_threads<P: Send, T: Send>(
    problems: &mut [P],
    count: usize,
    job: impl Fn(&mut P, usize) -> Result<T> + Sync,
) -> Result<Vec<T>> {
    let next = AtomicUsize::new(0);
    let failed = AtomicBool::new(false);
    let mut done: Vec<(usize, Result<T>)> = problems
        .par_iter_mut()
        .flat_map_iter(|problem| {
            let mut mine = Vec::new();
            while !failed.load(Ordering::Relaxed) {
                let k = next.fetch_add(1, Ordering::Relaxed);
                if k >= count {
                    break;
                }
                let result = job(problem, k);
                if result.is_err() {
                    failed.store(true, Ordering::Relaxed);
                }
                mine.push((k, result));
            }
            mine
        })
        .collect();
    done.sort_by_key(|&(k, _)| k);
    done.into_iter().map(|(_, result)| result).collect()
}
