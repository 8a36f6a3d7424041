//! The progress bars of long runs: shown on a terminal only, and only once a
//! run has lasted long enough for them to help.

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use packbed::Breaks;
use std::io::IsTerminal;
use std::time::{Duration, Instant};

/// Runs shorter than this never show a bar: it would only flicker.
const SHOW_AFTER: Duration = Duration::from_millis(500);

/// Counts against an estimated total (particles placed, bonds broken).
pub struct Progress {
    bar: Option<ProgressBar>,
    start: Instant,
    shown: bool,
    /// Time and count of the first report.
    first: Option<(Instant, u64)>,
}

impl Progress {
    /// Particles placed against an `estimate`; silent if `quiet` or stderr
    /// is not a terminal.
    pub fn new(estimate: u64, quiet: bool) -> Progress {
        Progress::with(
            quiet,
            Some(estimate),
            "{spinner} {human_pos}/~{human_len} particles  {msg}  [{bar:30}]",
        )
    }

    /// Bonds broken by `packbed fragment`: against the number asked for, or
    /// with a spinner until failure (when is not known in advance).
    pub fn breaks(breaks: Breaks, quiet: bool) -> Progress {
        match breaks {
            Breaks::Count(n) => Progress::with(
                quiet,
                Some(n),
                "{spinner} {human_pos}/{human_len} bonds broken  ETA {eta}  [{bar:30}]",
            ),
            Breaks::Failure => Progress::with(
                quiet,
                None,
                "{spinner} {human_pos} bonds broken (until failure)  {elapsed}",
            ),
        }
    }

    fn with(quiet: bool, len: Option<u64>, template: &str) -> Progress {
        Progress {
            bar: terminal_bar(quiet, len, ProgressDrawTarget::hidden(), template),
            start: Instant::now(),
            shown: false,
            first: None,
        }
    }

    /// Records that the count is now `done`.
    pub fn update(&mut self, done: u64) {
        let Some(bar) = &self.bar else { return };
        if !self.shown && self.start.elapsed() >= SHOW_AFTER {
            bar.set_draw_target(ProgressDrawTarget::stderr());
            self.shown = true;
        }
        // The total is a guess; never let the bar claim more than 100 %.
        if bar.length().is_some_and(|len| done >= len) {
            bar.set_length(done + done / 10 + 1);
        }
        bar.set_position(done);
        // Rate and ETA from the first report on: deposition runs at a steady pace
        // once the base layer (which reports nothing) is done, and indicatif's
        // own estimate is thrown off by that silent start.
        let now = Instant::now();
        let (t0, n0) = *self.first.get_or_insert((now, done));
        let secs = now.duration_since(t0).as_secs_f64();
        if secs > 0.0 && done > n0 {
            let rate = (done - n0) as f64 / secs;
            let left = bar.length().unwrap_or(done).saturating_sub(done) as f64 / rate;
            bar.set_message(format!("{rate:.0}/s  ETA {left:.0} s"));
        }
    }

    /// Removes the bar from the terminal.
    pub fn finish(&self) {
        if let Some(bar) = &self.bar {
            bar.finish_and_clear();
        }
    }
}

/// A bar drawn with `template`, or none if `quiet` or stderr is not a terminal.
pub fn terminal_bar(
    quiet: bool,
    len: Option<u64>,
    target: ProgressDrawTarget,
    template: &str,
) -> Option<ProgressBar> {
    (!quiet && std::io::stderr().is_terminal()).then(|| {
        let bar = ProgressBar::with_draw_target(len, target);
        let style =
            ProgressStyle::with_template(template).unwrap_or_else(|_| ProgressStyle::default_bar());
        bar.set_style(style.progress_chars("=> "));
        bar
    })
}
