//! A one-line progress display on stderr during long fits, shown only when
//! stderr is a terminal (quiet in pipes, files and tests).

use std::io::{IsTerminal, Write};
use std::time::{Duration, Instant};

/// Progress line on stderr, redrawn at most 10 times a second.
#[derive(Debug)]
pub struct Progress {
    enabled: bool,
    last: Option<Instant>,
    shown: bool,
}

impl Progress {
    /// Enabled when stderr is a terminal.
    pub fn stderr() -> Progress {
        Progress {
            enabled: std::io::stderr().is_terminal(),
            last: None,
            shown: false,
        }
    }

    /// A silent display.
    pub fn quiet() -> Progress {
        Progress {
            enabled: false,
            last: None,
            shown: false,
        }
    }

    /// Shows `msg` (throttled).
    pub fn show(&mut self, msg: &str) {
        if !self.enabled {
            return;
        }
        let now = Instant::now();
        if self
            .last
            .is_some_and(|t| now.duration_since(t) < Duration::from_millis(100))
        {
            return;
        }
        self.last = Some(now);
        let mut e = std::io::stderr().lock();
        let _ = write!(e, "\r\x1b[K{msg}");
        let _ = e.flush();
        self.shown = true;
    }

    /// Clears the line.
    pub fn finish(&mut self) {
        if self.enabled && self.shown {
            let mut e = std::io::stderr().lock();
            let _ = write!(e, "\r\x1b[K");
            let _ = e.flush();
            self.shown = false;
        }
    }
}

impl Drop for Progress {
    fn drop(&mut self) {
        self.finish();
    }
}
