//! Progress on stderr: the library's [`Event`]s as lines prefixed with the elapsed time.

use crate::pipeline::Event;
use std::time::Instant;

/// Progress lines on stderr, prefixed with the elapsed time.
pub struct Progress {
    start: Instant,
    quiet: bool,
}

impl Progress {
    /// Progress lines unless `quiet` or `-q`.
    pub fn new(quiet: bool) -> Progress {
        Progress {
            start: Instant::now(),
            quiet: quiet || super::quiet(),
        }
    }

    /// One progress line on stderr, with the seconds since the start.
    pub fn line(&self, msg: &str) {
        if !self.quiet {
            let seconds = self.start.elapsed().as_secs_f64();
            super::err_line(format_args!("[{seconds:7.2}s] {msg}"));
        }
    }

    /// Seconds since the start.
    pub fn elapsed(&self) -> f64 {
        self.start.elapsed().as_secs_f64()
    }

    /// When the run started (the clock of every line, and of `--time-limit`).
    pub fn started(&self) -> Instant {
        self.start
    }

    /// Shows one event of a pipeline, a line each of the lines it reads as.
    pub fn event(&self, e: Event<'_>) {
        if !self.quiet {
            e.to_string().lines().for_each(|l| self.line(l));
        }
    }
}
