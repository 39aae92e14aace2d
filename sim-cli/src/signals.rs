//! Ending a run on a signal without wrecking the terminal or losing output.
//!
//! [`install`] starts a thread that waits for SIGTERM, SIGHUP, SIGINT or SIGQUIT
//! (`kill`, `timeout`, a closed terminal window, Ctrl-\ or Ctrl-C outside raw
//! mode). On the first one it asks the run to stop ([`stop_requested`]): the run
//! loops (headless, interactive, replay, fleet, `dis-listen`) look at it once a
//! frame (or every 200 ms while listening; `study` every 16 frames of the blocks
//! in flight, keeping the runs completed), end the run as if its last frame had
//! come, and every output is finished as on a normal end: the CSV flushed, the
//! recording closed with its end marker, the plot and the ACMI file written, the
//! JSON report printed for the frames flown. `main` then prints
//! `sim-cli: stopped by SIGTERM` on stderr and exits with status 128 + the signal
//! number (143, 129, 130, 131), as shells report a process killed by that signal.
//!
//! When the run does not stop within [`GRACE`] (blocked somewhere), or a second
//! signal comes, the signal thread ends the process itself:
//!
//! 1. takes the stdout lock and keeps it, so the run loop cannot draw another
//!    HUD frame after the terminal is restored;
//! 2. restores the terminal ([`crate::terminal::restore`]: raw mode off, main
//!    screen, cursor shown) if an interactive run had changed it;
//! 3. flushes every output file registered through [`SignalSafeWriter`] (the
//!    `--csv` file), up to the last complete line;
//! 4. prints the same line and exits with the same status.
//!
//! Steps 1 to 3 run on a thread of their own and get [`FLUSH_LIMIT`]: a
//! pipe whose reader reads nothing (or a terminal stopped with Ctrl-S) would
//! block them for good. Past it the process exits anyway, and the line says
//! an output took nothing.
//!
//! Before a run has created any output it has nothing to finish, and it may be
//! blocked where no frame comes to look at the request: opening a named pipe
//! that waits for its writer (a `--script` FIFO) or its reader (a `--csv` FIFO),
//! or reading an input. The code there holds a [`BeforeOutputs`] guard
//! ([`before_outputs`]). While one is held, a signal (or one that came less
//! than [`GRACE`] before) ends the process at once, as in the steps above but
//! with the plain `sim-cli: stopped by SIGINT` line of a normal stop and its
//! status: no output file has been created or truncated yet, and nothing has
//! been written into a pipe the user named, so nothing is left half-made.
//!
//! A panic restores the terminal through [`crate::terminal::install_panic_hook`].
use std::io::{self, Write};
use std::sync::atomic::{AtomicI32, Ordering};
use std::sync::{Mutex, MutexGuard, PoisonError};
use std::time::{Duration, Instant};

/// The outputs the forced exit flushes (step 3): the run library's.
pub use fdm_run::flushable::{flush_registered, SignalSafeWriter};

use signal_hook::consts::signal::{SIGHUP, SIGINT, SIGQUIT, SIGTERM};
use signal_hook::iterator::Signals;

/// The signals that end a run cleanly, with their names.
pub const HANDLED: [(i32, &str); 4] = [
    (SIGTERM, "SIGTERM"),
    (SIGHUP, "SIGHUP"),
    (SIGINT, "SIGINT"),
    (SIGQUIT, "SIGQUIT"),
];

/// The exit status for a run ended by `signal`: 128 + its number.
#[must_use]
pub fn exit_status(signal: i32) -> i32 {
    128 + signal
}

/// How long the run has to finish its outputs after a signal before the
/// signal thread ends the process itself (flushing only the CSV).
pub const GRACE: Duration = Duration::from_secs(3);

/// The signal that asked the run to stop (0: none yet).
static STOP: AtomicI32 = AtomicI32::new(0);

/// How many [`BeforeOutputs`] guards are alive. A mutex, not an atomic: the
/// signal thread holds it from seeing a guard until the process has exited,
/// so the run cannot drop its guard and create (truncate) an output while
/// the process is being ended (the guard's drop waits for the lock).
static BEFORE_OUTPUTS: Mutex<usize> = Mutex::new(0);

/// Held while the run has created no output yet: opening a named pipe that
/// waits for the program at its other end, reading an input. While one is
/// alive, a signal ends the process at once (module docs) instead of
/// waiting up to [`GRACE`] for a run that may be blocked in `open`.
///
/// Drop it before the first output is created: a signal ending the process
/// then could leave that output half-made.
#[derive(Debug)]
#[must_use = "the guard covers the code until it is dropped"]
pub struct BeforeOutputs {
    /// Made by [`before_outputs`] only, so that the count stays right.
    _private: (),
}

/// A [`BeforeOutputs`] guard: a signal ends the process at once until it is
/// dropped.
pub fn before_outputs() -> BeforeOutputs {
    *lock(&BEFORE_OUTPUTS) += 1;
    BeforeOutputs { _private: () }
}

impl Drop for BeforeOutputs {
    fn drop(&mut self) {
        // Blocks for good if the signal thread is ending the process: the run
        // goes no further (no output is created meanwhile).
        let mut count = lock(&BEFORE_OUTPUTS);
        *count = count.saturating_sub(1);
    }
}

/// The signal that asked the run to stop, if one came: the run loops end the
/// run at the next frame and finish their outputs; `main` then exits with
/// [`exit_status`].
#[must_use]
pub fn stop_requested() -> Option<i32> {
    match STOP.load(Ordering::Relaxed) {
        0 => None,
        signal => Some(signal),
    }
}

/// The name of a handled signal (`SIGTERM`), or "a signal".
#[must_use]
pub fn signal_name(signal: i32) -> &'static str {
    HANDLED
        .iter()
        .find(|(number, _)| *number == signal)
        .map_or("a signal", |(_, name)| *name)
}

fn lock<T>(mutex: &Mutex<T>) -> MutexGuard<'_, T> {
    // A panic elsewhere must not stop the flush: the data is still there.
    mutex.lock().unwrap_or_else(PoisonError::into_inner)
}

/// Starts the signal thread (see the module docs). Call once, early in `main`.
///
/// # Errors
/// The OS error when the handlers or the thread cannot be set up; the run can
/// go on without them (signals then act as before: no restore, no flush).
pub fn install() -> io::Result<()> {
    let mut signals = Signals::new(HANDLED.map(|(number, _)| number))?;
    std::thread::Builder::new()
        .name("sim-cli-signals".to_owned())
        .spawn(move || {
            let Some(signal) = signals.forever().next() else {
                return;
            };
            STOP.store(signal, Ordering::Relaxed);
            // The run loops see the request within a frame; give them GRACE
            // to finish every output, and end the process here only if they
            // do not (or a second signal insists). A run that has no output
            // yet (it may be blocked opening a pipe, where no frame comes)
            // is ended at once, also when it gets there during the grace.
            let deadline = Instant::now() + GRACE;
            while Instant::now() < deadline {
                end_if_before_outputs(signal);
                if signals.pending().next().is_some() {
                    break;
                }
                std::thread::sleep(Duration::from_millis(20));
            }
            terminate(signal);
        })?;
    Ok(())
}

/// Ends the process on `signal` if a [`BeforeOutputs`] guard is alive, with
/// the line and status of a normal stop: there is nothing to finish.
fn end_if_before_outputs(signal: i32) {
    let count = lock(&BEFORE_OUTPUTS);
    if *count > 0 {
        // `count` stays locked into exit (see BEFORE_OUTPUTS).
        end(signal, "", count);
    }
}

/// Restores the terminal, flushes the outputs and exits with 128 + `signal`.
fn terminate(signal: i32) -> ! {
    let why = format!(
        " (the run did not finish its outputs within {} s)",
        GRACE.as_secs()
    );
    end(signal, &why, ())
}

/// How long ending the process waits for the terminal's restore and the
/// registered outputs' flush (module docs): a pipe whose reader stopped reading
/// (or a terminal stopped with Ctrl-S) blocks them for good, and so does the
/// run blocked writing there while it holds the output's or stdout's lock.
pub const FLUSH_LIMIT: Duration = Duration::from_secs(1);

/// Restores the terminal, flushes the registered outputs, prints
/// `sim-cli: stopped by SIG...` and `why` on stderr and exits with 128 +
/// `signal`, keeping `held` (a lock) until the process is gone. The restore
/// and the flush run on a thread of their own and get [`FLUSH_LIMIT`]; past
/// it the process exits anyway, and the message says what was not flushed.
fn end<T>(signal: i32, why: &str, held: T) -> ! {
    let (done, finished) = std::sync::mpsc::channel::<()>();
    let finisher = std::thread::Builder::new()
        .name("sim-cli-exit".to_owned())
        .spawn(move || {
            let stdout = io::stdout();
            // Held until the process exits: no HUD frame after the restore.
            // (The lock is reentrant, so `restore` can still write through
            // it; std's exit-time flush only tries the lock.)
            let mut stdout_held = stdout.lock();
            crate::terminal::restore();
            flush_registered();
            // What the run printed and std's exit would have flushed (it
            // only tries the lock this thread keeps).
            let _ = stdout_held.flush();
            let _ = done.send(());
            loop {
                std::thread::park();
            }
        });
    let finished = finisher.is_ok() && finished.recv_timeout(FLUSH_LIMIT).is_ok();
    let unflushed = if finished {
        String::new()
    } else {
        format!(
            "; an output or the terminal took nothing for {} s: what was not written to it is lost",
            FLUSH_LIMIT.as_secs()
        )
    };
    let _ = writeln!(
        io::stderr(),
        "{}sim-cli: stopped by {}{why}{unflushed}",
        crate::progress::line_start(),
        signal_name(signal),
    );
    // Keep the lock alive into exit.
    let _ = &held;
    std::process::exit(exit_status(signal))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn exit_statuses_are_128_plus_the_signal() {
        let statuses: Vec<i32> = HANDLED.iter().map(|&(s, _)| exit_status(s)).collect();
        assert_eq!(statuses, [143, 129, 130, 131]);
    }
}
