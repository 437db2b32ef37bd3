//! Progress of long work on stderr: redrawn in place at most four times a second on a
//! terminal; a line every [`LOG_INTERVAL`] otherwise, so a log file or a pipe still learns
//! how far a long run has got.

use std::io::IsTerminal;
use std::sync::Mutex;
use std::time::{Duration, Instant};

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
