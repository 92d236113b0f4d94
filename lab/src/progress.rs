//! A one-line progress display on stderr during long fits (an `indicatif`
//! spinner with a message), drawn only when stderr is a terminal: quiet in
//! pipes, files and tests.

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use std::io::IsTerminal;

/// Progress line on stderr, redrawn at most 10 times a second.
#[derive(Debug)]
pub struct Progress {
    bar: ProgressBar,
}

impl Progress {
    /// Enabled when stderr is a terminal.
    pub fn stderr() -> Progress {
        if !std::io::stderr().is_terminal() {
            return Progress::quiet();
        }
        let bar = ProgressBar::with_draw_target(None, ProgressDrawTarget::stderr_with_hz(10));
        if let Ok(style) = ProgressStyle::with_template("{spinner} {msg}") {
            bar.set_style(style);
        }
        Progress { bar }
    }

    /// A silent display.
    pub fn quiet() -> Progress {
        Progress {
            bar: ProgressBar::hidden(),
        }
    }

    /// Shows `msg` (throttled to the refresh rate).
    pub fn show(&mut self, msg: &str) {
        if !self.bar.is_hidden() {
            self.bar.set_message(msg.to_owned());
            self.bar.tick();
        }
    }

    /// Clears the line.
    pub fn finish(&mut self) {
        self.bar.finish_and_clear();
    }
}

impl Drop for Progress {
    fn drop(&mut self) {
        self.finish();
    }
}
