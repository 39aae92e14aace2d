//! Named pipes (FIFOs) given as files from Python, waited for with Python's
//! signals looked at. Opening a named pipe waits for a program at its other
//! end, in `open(2)`, which Rust retries on `EINTR`: a `Flight.csv_to(FIFO)`
//! with no reader yet, or a `Study(FIFO)` with no writer, would hold the
//! calling thread there, Ctrl-C doing nothing until the other program came
//! (Python's handler only runs when the call returns). Here the wait looks
//! at the signals every [`SIGNAL_CHECK`], so Ctrl-C raises
//! `KeyboardInterrupt` out of it at once, as it does out of a long step.
//!
//! A regular file (or anything else that is not a named pipe) is opened as
//! before: nothing waits.
//!
//! Once open, a pipe can keep a write waiting too: its reader opened it but
//! takes nothing, and the pipe is full. Rust retries a write a signal
//! interrupted, so Ctrl-C did nothing there either. A flight's output files
//! are [`WatchedFile`]s watched by its [`SignalWatch`]: an interrupted write
//! looks at Python's signals, and a handler that raises stops the writing
//! (the output fails and is closed) and its exception is raised out of the
//! call.

use std::fs::File;
use std::io;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::{Receiver, RecvTimeoutError};
use std::sync::{Arc, Mutex, PoisonError};
use std::time::Duration;

use fdm_run::outfile::{WatchedFile, WriteWatch};

use pyo3::exceptions::{PyOSError, PyRuntimeError};
use pyo3::prelude::*;

/// How often a wait (for a named pipe's other end, for a study's runs) looks
/// at Python's signals: short enough that Ctrl-C ends it within a fraction
/// of a second, long enough that the looks cost nothing next to the work.
pub const SIGNAL_CHECK: Duration = Duration::from_millis(20);

/// Whether `path` is a named pipe (following symlinks).
fn is_fifo(path: &Path) -> bool {
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt as _;
        std::fs::metadata(path).is_ok_and(|m| m.file_type().is_fifo())
    }
    #[cfg(not(unix))]
    {
        let _ = path;
        false
    }
}

/// The named pipe `path` opened without waiting, for writing (`write`) or
/// reading: `Ok(None)` while a pipe opened for writing has no reader.
#[cfg(unix)]
fn open_now(path: &Path, write: bool) -> std::io::Result<Option<File>> {
    use std::os::unix::fs::OpenOptionsExt as _;
    match std::fs::OpenOptions::new()
        .read(!write)
        .write(write)
        .custom_flags(libc::O_NONBLOCK)
        .open(path)
    {
        Ok(file) => Ok(Some(file)),
        Err(e) if e.raw_os_error() == Some(libc::ENXIO) => Ok(None),
        Err(e) => Err(e),
    }
}

/// For an output to be written at `path`: when it is a named pipe, waits
/// until a program opens it for reading, looking at Python's signals every
/// [`SIGNAL_CHECK`] with the GIL released between two looks (Ctrl-C raises
/// `KeyboardInterrupt`), and returns the pipe held open for writing. While
/// it is held, the output's own opening of the pipe returns at once. `None`
/// for anything else (nothing waits).
///
/// # Errors
/// The exception of a signal's handler; `OSError` when the pipe cannot be
/// opened.
pub fn await_reader(py: Python<'_>, path: &str) -> PyResult<Option<File>> {
    #[cfg(unix)]
    {
        let path = Path::new(path);
        if !is_fifo(path) {
            return Ok(None);
        }
        loop {
            match open_now(path, true) {
                Ok(Some(held)) => return Ok(Some(held)),
                Ok(None) => {
                    py.check_signals()?;
                    py.detach(|| std::thread::sleep(SIGNAL_CHECK));
                }
                Err(e) => {
                    return Err(PyOSError::new_err(format!("{}: {e}", path.display())));
                }
            }
        }
    }
    #[cfg(not(unix))]
    {
        let _ = (py, path);
        Ok(None)
    }
}

/// `read()` (which opens and reads `path`) with the GIL released; when
/// `path` is a named pipe, on a thread of its own while this one looks at
/// Python's signals every [`SIGNAL_CHECK`]. On a signal whose handler
/// raises, a reader still waiting in `open` for a writer is let go (the
/// pipe is opened for writing and closed at once, without a byte: it reads
/// an empty pipe, and its result is dropped) and the exception is returned
/// at once. (A reader already reading from a writer that sends nothing ends
/// when that writer closes the pipe; the call does not wait for it.)
///
/// # Errors
/// The exception of a signal's handler; `RuntimeError` if the reading
/// thread cannot be started or panics.
pub fn read_interruptibly<T: Send + 'static>(
    py: Python<'_>,
    path: &Path,
    read: impl FnOnce() -> T + Send + 'static,
) -> PyResult<T> {
    if !is_fifo(path) {
        return Ok(py.detach(read));
    }
    let (done, result) = std::sync::mpsc::channel();
    std::thread::Builder::new()
        .name("afit-fdm-pipe".to_owned())
        .spawn(move || {
            let _ = done.send(read());
        })
        .map_err(|e| PyRuntimeError::new_err(format!("cannot start a thread: {e}")))?;
    let mut result = result;
    loop {
        let received;
        (result, received) = recv_detached(py, result, SIGNAL_CHECK);
        match received {
            Ok(value) => return Ok(value),
            Err(RecvTimeoutError::Timeout) => {
                if let Err(e) = py.check_signals() {
                    let_reader_go(path.to_path_buf());
                    return Err(e);
                }
            }
            Err(RecvTimeoutError::Disconnected) => {
                return Err(PyRuntimeError::new_err(format!(
                    "reading {} failed (its thread panicked)",
                    path.display()
                )));
            }
        }
    }
}

/// One wait of at most `timeout` for `receiver`'s next message with the GIL
/// released, for a caller that looks at Python's signals between two waits.
/// The receiver moves into the released section and back out (it is `Send`,
/// not `Sync`: it cannot be borrowed across), so it is returned with what
/// the wait got.
pub fn recv_detached<T: Send>(
    py: Python<'_>,
    receiver: Receiver<T>,
    timeout: Duration,
) -> (Receiver<T>, Result<T, RecvTimeoutError>) {
    py.detach(move || {
        let received = receiver.recv_timeout(timeout);
        (receiver, received)
    })
}

/// Lets a reader waiting in `open` for a writer of the named pipe `path`
/// go: opens it for writing without waiting and closes it at once.
fn let_reader_go(path: PathBuf) {
    #[cfg(unix)]
    {
        let _ = open_now(&path, true);
    }
    #[cfg(not(unix))]
    {
        let _ = path;
    }
}

/// A flight's watch on Python's signals for its output files'
/// ([`WriteWatch`]). A write a signal interrupts runs the signals' handlers
/// (`check_signals`); one that raises (Ctrl-C's `KeyboardInterrupt`) stops
/// every write of the flight's watched files (pipes, sockets, devices: a
/// regular file is not watched, and its bytes are kept) until the next call
/// that writes ([`SignalWatch::arm`]), and its exception waits in the watch
/// for that call to raise it ([`SignalWatch::take_raised`]) instead of the
/// output's error. A handler that does not raise lets the write go on.
#[derive(Debug, Default)]
pub struct SignalWatch {
    stopped: AtomicBool,
    raised: Mutex<Option<PyErr>>,
}

impl SignalWatch {
    /// Writing allowed again, at the start of a call that writes (the
    /// previous call's stop, if any, was raised by it). Without a stop, one
    /// atomic load: every `Flight.step` arms the watch.
    pub fn arm(&self) {
        // A load, not a swap (a locked instruction), in the usual case.
        if self.stopped.load(Ordering::SeqCst) {
            self.stopped.store(false, Ordering::SeqCst);
            *self.raised.lock().unwrap_or_else(PoisonError::into_inner) = None;
        }
    }

    /// The exception of the handler that stopped the writing, once. Without
    /// a stop, one atomic load (the exception is stored before the stop).
    pub fn take_raised(&self) -> Option<PyErr> {
        if !self.stopped.load(Ordering::SeqCst) {
            return None;
        }
        self.raised
            .lock()
            .unwrap_or_else(PoisonError::into_inner)
            .take()
    }

    /// `file` watched by `watch` ([`WatchedFile::watched_by`]).
    pub fn file(watch: &Arc<Self>, file: File) -> WatchedFile {
        WatchedFile::watched_by(file, Arc::clone(watch) as Arc<dyn WriteWatch>)
    }
}

/// The error of every write once a signal stopped them.
fn stopped_error() -> io::Error {
    io::Error::other("writing stopped by a signal while the output waited for its reader")
}

impl WriteWatch for SignalWatch {
    fn interrupted(&self) -> io::Result<()> {
        if self.stopped.load(Ordering::SeqCst) {
            return Err(stopped_error());
        }
        // The calling thread may hold the GIL (a short step) or have
        // released it (a long one); at the interpreter's exit it cannot
        // take it, and the write stops.
        match Python::try_attach(|py| py.check_signals()) {
            Some(Ok(())) => Ok(()),
            Some(Err(raised)) => {
                *self.raised.lock().unwrap_or_else(PoisonError::into_inner) = Some(raised);
                self.stopped.store(true, Ordering::SeqCst);
                Err(stopped_error())
            }
            None => {
                self.stopped.store(true, Ordering::SeqCst);
                Err(stopped_error())
            }
        }
    }

    fn stopped(&self) -> Option<io::Error> {
        self.stopped.load(Ordering::SeqCst).then(stopped_error)
    }
}
