//! The progress bar of long runs: shown on a terminal only, and only once a run
//! has lasted long enough for it to help.

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use packbed::config::Config;
use packbed::mechanics::Breaks;
use std::io::IsTerminal;
use std::time::{Duration, Instant};

/// Runs shorter than this never show a bar: it would only flicker.
const SHOW_AFTER: Duration = Duration::from_millis(500);

/// Counts placed particles against an estimated total.
pub struct Progress {
    bar: Option<ProgressBar>,
    start: Instant,
    shown: bool,
    /// Time and count of the first report.
    first: Option<(Instant, u64)>,
}

impl Progress {
    /// A bar for `config`, or a silent one if `quiet` or stderr is not a terminal.
    pub fn new(config: &Config, quiet: bool) -> Progress {
        let bar = terminal_bar(
            quiet,
            Some(config.estimated_particles()),
            ProgressDrawTarget::hidden(),
            "{spinner} {human_pos}/~{human_len} particles  {msg}  [{bar:30}]",
        );
        Progress {
            bar,
            start: Instant::now(),
            shown: false,
            first: None,
        }
    }

    /// Records that `placed` particles are in the bed.
    pub fn update(&mut self, placed: u64) {
        let Some(bar) = &self.bar else { return };
        if !self.shown && self.start.elapsed() >= SHOW_AFTER {
            bar.set_draw_target(ProgressDrawTarget::stderr());
            self.shown = true;
        }
        // The total is a guess; never let the bar claim more than 100 %.
        if bar.length().is_some_and(|len| placed >= len) {
            bar.set_length(placed + placed / 10 + 1);
        }
        bar.set_position(placed);
        // Rate and ETA from the first report on: deposition runs at a steady pace
        // once the base layer (which reports nothing) is done, and indicatif's
        // own estimate is thrown off by that silent start.
        let now = Instant::now();
        let (t0, n0) = *self.first.get_or_insert((now, placed));
        let secs = now.duration_since(t0).as_secs_f64();
        if secs > 0.0 && placed > n0 {
            let rate = (placed - n0) as f64 / secs;
            let left = bar.length().unwrap_or(placed).saturating_sub(placed) as f64 / rate;
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

/// Counts the bonds `packbed fragment` has broken: against the number asked
/// for, or with a spinner until failure (when is not known in advance).
pub struct BreakProgress {
    bar: Option<ProgressBar>,
    start: Instant,
    shown: bool,
}

impl BreakProgress {
    /// A bar for `breaks`, or a silent one if `quiet` or stderr is not a terminal.
    pub fn new(breaks: Breaks, quiet: bool) -> BreakProgress {
        let (len, template) = match breaks {
            Breaks::Count(n) => (
                Some(n),
                "{spinner} {human_pos}/{human_len} bonds broken  ETA {eta}  [{bar:30}]",
            ),
            Breaks::Failure => (
                None,
                "{spinner} {human_pos} bonds broken (until failure)  {elapsed}",
            ),
        };
        BreakProgress {
            bar: terminal_bar(quiet, len, ProgressDrawTarget::hidden(), template),
            start: Instant::now(),
            shown: false,
        }
    }

    /// Records that `broken` bonds are broken.
    pub fn update(&mut self, broken: u64) {
        let Some(bar) = &self.bar else { return };
        if !self.shown && self.start.elapsed() >= SHOW_AFTER {
            bar.set_draw_target(ProgressDrawTarget::stderr());
            self.shown = true;
        }
        bar.set_position(broken);
    }

    /// Removes the bar from the terminal.
    pub fn finish(&self) {
        if let Some(bar) = &self.bar {
            bar.finish_and_clear();
        }
    }
}
