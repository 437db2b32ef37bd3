//! Progress of long work on stderr: redrawn in place at most four times a second on a
//! terminal; a line every [`LOG_INTERVAL`] otherwise, so a log file or a pipe still learns
//! how far a long run has got.

use std::io::IsTerminal;
use std::ops::ControlFlow;
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use whirl::progress::{Progress, Report};

use crate::interrupt;

/// How often a progress line is written when stderr is not a terminal.
pub const LOG_INTERVAL: Duration = Duration::from_secs(5);

/// How often the line is redrawn on a terminal.
const REDRAW_INTERVAL: Duration = Duration::from_millis(250);

/// Paces the progress lines of one piece of work.
pub struct Pace {
    terminal: bool,
    start: Instant,
    last: Mutex<Instant>,
}

impl Pace {
    /// Starts pacing now; the first line comes after one interval.
    pub fn new() -> Pace {
        Pace {
            terminal: std::io::stderr().is_terminal(),
            start: Instant::now(),
            last: Mutex::new(Instant::now()),
        }
    }

    /// Seconds since the start.
    pub fn elapsed_s(&self) -> f64 {
        self.start.elapsed().as_secs_f64()
    }

    /// Writes `line()` when one is due.
    pub fn show(&self, line: impl FnOnce() -> String) {
        let Ok(mut last) = self.last.lock() else {
            return;
        };
        let interval = if self.terminal {
            REDRAW_INTERVAL
        } else {
            LOG_INTERVAL
        };
        if last.elapsed() < interval {
            return;
        }
        *last = Instant::now();
        if self.terminal {
            eprint!("\r{:70}", line());
        } else {
            eprintln!("{}", line());
        }
    }

    /// Blanks the line on a terminal.
    pub fn clear(&self) {
        if self.terminal {
            eprint!("\r{:70}\r", "");
        }
    }
}

/// `42 s`, `12 min`, `3.2 h`.
pub fn duration_text(seconds: f64) -> String {
    if seconds < 100.0 {
        format!("{seconds:.0} s")
    } else if seconds < 6000.0 {
        format!("{:.0} min", seconds / 60.0)
    } else {
        format!("{:.1} h", seconds / 3600.0)
    }
}

/// The library's [`Progress`] of one piece of work shown on stderr as
/// `label: message, 12 s, about 35 s left` (paced by [`Pace`]), and stopping the work once
/// Ctrl-C was pressed in a command that can stop ([`interrupt::stoppable`]). The [`Pace`]
/// is returned to blank the line when the work ends.
pub fn progress_line(label: String) -> (Progress, Arc<Pace>) {
    let pace = Arc::new(Pace::new());
    let shown = Arc::clone(&pace);
    let progress = Progress::new(move |r: Report<'_>| {
        shown.show(|| line(&label, &r, shown.elapsed_s()));
        if interrupt::requested() {
            ControlFlow::Break(())
        } else {
            ControlFlow::Continue(())
        }
    });
    (progress, pace)
}

/// `work` given a [`progress_line`] labelled `label`, the line blanked when it ends.
pub fn shown<R>(label: &str, work: impl FnOnce(Option<&Progress>) -> R) -> R {
    let (progress, line) = progress_line(label.into());
    let result = work(Some(&progress));
    line.clear();
    result
}

/// `label: message, elapsed`, and the time left from the rate so far when some work is
/// done and some is left.
fn line(label: &str, r: &Report<'_>, elapsed: f64) -> String {
    let left = if r.done > 0.0 && r.done < r.total {
        let seconds = elapsed / r.done * (r.total - r.done);
        format!(", about {} left", duration_text(seconds))
    } else {
        String::new()
    };
    format!("{label}: {}, {}{left}", r.message, duration_text(elapsed))
}
