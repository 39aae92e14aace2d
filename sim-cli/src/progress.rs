//! A progress bar on stderr for headless runs.
//!
//! It appears only when stderr is a terminal and the run has already taken
//! [`Progress::DELAY`], so quick runs and redirected output stay clean; it redraws at
//! most every [`Progress::INTERVAL`] and is erased when the run ends. stdout is never
//! touched (it may carry the JSON report).

use std::io::{IsTerminal, Write};
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

/// Whether a bar is on stderr's current line now (drawn and not yet erased).
static BAR_ON_SCREEN: AtomicBool = AtomicBool::new(false);

/// What a message written on stderr outside the bar's own methods (the
/// signal thread's last line) must start with: a newline when a bar is on
/// the current line, so the message does not run into it; else nothing.
#[must_use]
pub fn line_start() -> &'static str {
    if BAR_ON_SCREEN.load(Ordering::Relaxed) {
        "\n"
    } else {
        ""
    }
}

/// The pure part: decides when to draw and what. Times are injected for testing.
#[derive(Debug, Clone)]
pub struct Progress {
    total: u64,
    start: Instant,
    last_draw: Option<Instant>,
}

impl Progress {
    /// No bar before the run has taken this long.
    pub const DELAY: Duration = Duration::from_secs(1);
    /// Minimum time between redraws.
    pub const INTERVAL: Duration = Duration::from_millis(100);

    /// A run of `total` frames starting at `start`.
    #[must_use]
    pub fn new(total: u64, start: Instant) -> Self {
        Self {
            total,
            start,
            last_draw: None,
        }
    }

    /// Whether a bar has been drawn (and therefore must be erased at the end).
    #[must_use]
    pub fn drawn(&self) -> bool {
        self.last_draw.is_some()
    }

    /// The line to draw after `done` frames at time `now`, if a redraw is due.
    pub fn update(&mut self, done: u64, now: Instant) -> Option<String> {
        let elapsed = now.saturating_duration_since(self.start);
        if elapsed < Self::DELAY {
            return None;
        }
        if let Some(last) = self.last_draw {
            if now.saturating_duration_since(last) < Self::INTERVAL {
                return None;
            }
        }
        self.last_draw = Some(now);
        Some(render_bar(done, self.total, elapsed))
    }
}

/// `[=========>          ]  45%  12150/27000 frames  eta 3 s`
#[must_use]
pub fn render_bar(done: u64, total: u64, elapsed: Duration) -> String {
    const WIDTH: u64 = 30;
    let done = done.min(total);
    let fraction = if total == 0 {
        1.0
    } else {
        done as f64 / total as f64
    };
    let filled = (done * WIDTH).checked_div(total).unwrap_or(WIDTH);
    let mut bar = String::with_capacity(WIDTH as usize + 2);
    bar.push('[');
    for i in 0..WIDTH {
        bar.push(if i < filled {
            '='
        } else if i == filled {
            '>'
        } else {
            ' '
        });
    }
    bar.push(']');
    let eta = if done == 0 {
        "eta ?".to_owned()
    } else {
        let remaining = elapsed.as_secs_f64() * (total - done) as f64 / done as f64;
        format!("eta {remaining:.0} s")
    };
    format!(
        "{bar} {:3.0}%  {done}/{total} frames  {eta}",
        fraction * 100.0
    )
}

/// The bar drawn on the real stderr; does nothing when stderr is not a terminal.
#[derive(Debug)]
pub struct StderrProgress {
    inner: Option<Progress>,
}

impl StderrProgress {
    /// Checks the clock only every this many frames (a power of two, so the test is a
    /// mask) to keep `Instant::now` off the hot path.
    const BATCH: u64 = 64;

    /// A bar for a run of `total` frames, active only if stderr is a terminal.
    #[must_use]
    pub fn new(total: u64) -> Self {
        Self::with_enabled(total, std::io::stderr().is_terminal())
    }

    /// A bar that is forced on or off (off in tests).
    #[must_use]
    pub fn with_enabled(total: u64, enabled: bool) -> Self {
        Self {
            inner: enabled.then(|| Progress::new(total, Instant::now())),
        }
    }

    /// Reports that `done` frames are finished.
    pub fn tick(&mut self, done: u64) {
        let Some(p) = &mut self.inner else { return };
        if done & (Self::BATCH - 1) != 0 {
            return;
        }
        if let Some(line) = p.update(done, Instant::now()) {
            // A progress bar is best effort: a failing stderr must not fail the run.
            let mut err = std::io::stderr().lock();
            let _ = write!(err, "\r{line}\x1b[K");
            let _ = err.flush();
            BAR_ON_SCREEN.store(true, Ordering::Relaxed);
        }
    }

    /// Writes `line` and a newline on stderr, erasing the bar first if one is drawn
    /// (a later tick draws it again below the message). Best effort, like the bar.
    pub fn message(&mut self, line: &str) {
        let mut err = std::io::stderr().lock();
        if self.inner.as_ref().is_some_and(Progress::drawn) {
            let _ = write!(err, "\r\x1b[2K");
            BAR_ON_SCREEN.store(false, Ordering::Relaxed);
        }
        let _ = writeln!(err, "{line}");
        let _ = err.flush();
    }

    /// Erases the bar if one was drawn.
    pub fn finish(&mut self) {
        if let Some(p) = self.inner.take() {
            if p.drawn() {
                let mut err = std::io::stderr().lock();
                let _ = write!(err, "\r\x1b[2K");
                let _ = err.flush();
                BAR_ON_SCREEN.store(false, Ordering::Relaxed);
            }
        }
    }
}

impl Drop for StderrProgress {
    fn drop(&mut self) {
        // Also on error paths, so the error message starts on a clean line.
        self.finish();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn waits_then_throttles() {
        let t0 = Instant::now();
        let mut p = Progress::new(1000, t0);
        assert_eq!(p.update(10, t0 + Duration::from_millis(999)), None);
        assert!(!p.drawn());
        let first = p.update(500, t0 + Duration::from_secs(1)).unwrap();
        assert!(first.contains(" 50%"), "{first}");
        assert!(p.drawn());
        assert_eq!(p.update(510, t0 + Duration::from_millis(1050)), None);
        assert!(p.update(520, t0 + Duration::from_millis(1100)).is_some());
    }

    #[test]
    fn bar_text() {
        assert_eq!(
            render_bar(500, 1000, Duration::from_secs(2)),
            "[===============>              ]  50%  500/1000 frames  eta 2 s"
        );
        assert!(render_bar(0, 10, Duration::from_secs(2)).ends_with("eta ?"));
        assert!(render_bar(10, 10, Duration::from_secs(2)).contains("100%"));
        assert!(render_bar(0, 0, Duration::ZERO).contains("100%"));
    }

    /// A message from outside the bar (the signal thread's) starts on a new
    /// line while a bar is on the screen, and on the current one after the
    /// bar is erased.
    #[test]
    fn messages_start_below_a_drawn_bar() {
        let mut p = StderrProgress {
            inner: Some(Progress::new(100, Instant::now() - Duration::from_secs(2))),
        };
        assert_eq!(line_start(), "");
        p.tick(64);
        assert_eq!(line_start(), "\n");
        p.finish();
        assert_eq!(line_start(), "");
    }

    #[test]
    fn disabled_bar_is_silent() {
        let mut p = StderrProgress::with_enabled(100, false);
        p.tick(64);
        p.finish();
    }
}
