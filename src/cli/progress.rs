//! Progress on stderr, and how much the command line says (`-q`, `-v`).
//!
//! On a terminal, runs longer than a second show an indicatif bar. Off a terminal (CI logs,
//! pipes, `2> log`), they print one plain line per step instead, named as the output files
//! are (`pose_003 done (4/16, 2.1 s)`), or, for steps without a name, counted and at most
//! one line every [`PLAIN_INTERVAL`] (`poses: 40/160 done (12.5 s)`). `-q` (and `--json`,
//! whose stdout is for programs) hides both; `-v` adds notes on where inputs came from.

use std::io::IsTerminal;
use std::sync::atomic::{AtomicI8, AtomicU64, Ordering};
use std::sync::Mutex;
use std::time::{Duration, Instant};

use indicatif::{ProgressBar, ProgressStyle};

/// The shortest time between two counted plain lines.
pub const PLAIN_INTERVAL: Duration = Duration::from_secs(2);

/// −1 for `-q`, 0 by default, the number of `-v` otherwise.
static VERBOSITY: AtomicI8 = AtomicI8::new(0);

/// Sets how much the command line says: `quiet` (`-q`) or `verbose` (the count of `-v`).
pub fn set_verbosity(quiet: bool, verbose: u8) {
    let v = if quiet {
        -1
    } else {
        i8::try_from(verbose).unwrap_or(i8::MAX)
    };
    VERBOSITY.store(v, Ordering::Relaxed);
}

/// Whether `-q` was given: no progress, no notes.
pub fn is_quiet() -> bool {
    VERBOSITY.load(Ordering::Relaxed) < 0
}

/// Whether `-v` was given.
pub fn is_verbose() -> bool {
    VERBOSITY.load(Ordering::Relaxed) > 0
}

/// Prints `note: …` on stderr unless `-q`.
pub fn note(message: impl std::fmt::Display) {
    if !is_quiet() {
        eprintln!("note: {message}");
    }
}

/// Prints `note: …` on stderr with `-v` only.
pub fn detail(message: impl std::fmt::Display) {
    if is_verbose() {
        eprintln!("note: {message}");
    }
}

/// Progress of `len` steps of `what` ("poses", "samples", "cases"): a bar on a terminal, plain
/// lines off one, nothing with `-q` or when `hidden` (the command's `--json`).
pub fn bar(len: u64, what: &str, hidden: bool) -> Progress {
    let style = if hidden || is_quiet() {
        Style::Hidden
    } else if std::io::stderr().is_terminal() {
        Style::Bar
    } else {
        Style::Plain
    };
    Progress::new(len, what, style)
}

/// How progress shows.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Style {
    /// Nothing.
    Hidden,
    /// An indicatif bar (a terminal).
    Bar,
    /// One line per step on stderr (not a terminal).
    Plain,
}

/// A run's progress (see the module docs). Safe to advance from several threads.
#[derive(Debug)]
pub struct Progress {
    bar: ProgressBar,
    style: Style,
    len: u64,
    what: String,
    done: AtomicU64,
    started: Instant,
    /// When the last counted line was printed.
    last_line: Mutex<Option<Instant>>,
}

impl Progress {
    /// Progress of `len` steps of `what`, shown as `style` says.
    pub fn new(len: u64, what: &str, style: Style) -> Progress {
        let bar = if style == Style::Bar {
            let pb = ProgressBar::new(len);
            let template = format!(
                "{{elapsed_precise}} [{{bar:40}}] {{pos}}/{{len}} {what} (eta {{eta}}) {{msg}}"
            );
            pb.set_style(
                ProgressStyle::with_template(&template)
                    .expect("the template is valid")
                    .progress_chars("=> "),
            );
            pb
        } else {
            ProgressBar::hidden()
        };
        Progress {
            bar,
            style,
            len,
            what: what.to_string(),
            done: AtomicU64::new(0),
            started: Instant::now(),
            last_line: Mutex::new(None),
        }
    }

    /// Shows `name` as the step under way, on the bar (a case's name while it runs).
    pub fn set_message(&self, name: impl Into<String>) {
        self.bar.set_message(name.into());
    }

    /// `k` more unnamed steps are done: off a terminal, a counted line at most every
    /// [`PLAIN_INTERVAL`] and after the last step (`poses: 40/160 done (12.5 s)`).
    pub fn inc(&self, k: u64) {
        self.bar.inc(k);
        let done = self.done.fetch_add(k, Ordering::Relaxed) + k;
        if self.style == Style::Plain {
            if let Some(line) = self.counted_line(done) {
                eprintln!("{line}");
            }
        }
    }

    /// The step `name` (`pose_003`, as its files are named) is done: off a terminal its line,
    /// `pose_003 done (4/16, 2.1 s)` and `: detail` if given; on a terminal the line is
    /// printed above the bar when there is a `detail`.
    pub fn done(&self, name: &str, detail: Option<&str>) {
        self.bar.inc(1);
        let done = self.done.fetch_add(1, Ordering::Relaxed) + 1;
        let line = || self.named_line(name, done, detail);
        match (self.style, detail) {
            (Style::Plain, _) => eprintln!("{}", line()),
            (Style::Bar, Some(_)) => self.bar.suspend(|| eprintln!("{}", line())),
            _ => {}
        }
    }

    fn named_line(&self, name: &str, done: u64, detail: Option<&str>) -> String {
        let elapsed = self.started.elapsed().as_secs_f64();
        let detail = detail.map_or(String::new(), |d| format!(": {d}"));
        format!("{name} done ({done}/{}, {elapsed:.1} s){detail}", self.len)
    }

    /// The counted line after `done` steps, or `None` when one was printed less than
    /// [`PLAIN_INTERVAL`] ago and this is not the last step.
    fn counted_line(&self, done: u64) -> Option<String> {
        let now = Instant::now();
        let mut last = self.last_line.lock().expect("not poisoned");
        let due = last.is_none_or(|t| now.duration_since(t) >= PLAIN_INTERVAL);
        if !(due || done >= self.len) {
            return None;
        }
        *last = Some(now);
        let elapsed = now.duration_since(self.started).as_secs_f64();
        Some(format!(
            "{}: {done}/{} done ({elapsed:.1} s)",
            self.what, self.len
        ))
    }

    /// Runs `f` (which prints) with the bar cleared from the terminal.
    pub fn suspend<R>(&self, f: impl FnOnce() -> R) -> R {
        self.bar.suspend(f)
    }

    /// Removes the bar (plain lines stay in the log).
    pub fn finish_and_clear(&self) {
        self.bar.finish_and_clear();
    }

    /// How progress shows.
    pub fn style(&self) -> Style {
        self.style
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn plain_lines_name_the_step_or_count_at_most_every_interval() {
        let p = Progress::new(16, "poses", Style::Plain);
        let line = p.named_line("pose_003", 4, None);
        assert!(line.starts_with("pose_003 done (4/16, "), "{line}");
        assert!(line.ends_with(" s)"), "{line}");
        let line = p.named_line("pose_003", 4, Some("12 valid"));
        assert!(line.ends_with(" s): 12 valid"), "{line}");
        // Counted: the first prints, the next within the interval does not, the last does.
        assert!(p.counted_line(5).unwrap().starts_with("poses: 5/16 done ("));
        assert_eq!(p.counted_line(6), None);
        assert!(p
            .counted_line(16)
            .unwrap()
            .starts_with("poses: 16/16 done ("));
    }
}
