//! A minimal timing harness for `cargo bench`: runs a closure repeatedly and reports the
//! median and the fastest run. Criterion would add minutes to a cold build on two cores for
//! the same numbers.

use std::time::{Duration, Instant};

/// Times `f` `runs` times after one warm-up run and prints median and minimum.
pub fn time<T>(name: &str, runs: usize, mut f: impl FnMut() -> T) -> Duration {
    std::hint::black_box(f());
    let mut samples: Vec<Duration> = (0..runs)
        .map(|_| {
            let start = Instant::now();
            std::hint::black_box(f());
            start.elapsed()
        })
        .collect();
    samples.sort();
    let median = samples[samples.len() / 2];
    println!(
        "{name:<55} median {:>10.3} ms   min {:>10.3} ms   ({runs} runs)",
        median.as_secs_f64() * 1e3,
        samples[0].as_secs_f64() * 1e3
    );
    median
}
