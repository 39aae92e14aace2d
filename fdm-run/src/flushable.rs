//! Output files that another thread can flush up to their last complete
//! line: what a program ending on a signal (`sim-cli`'s signal thread, when
//! the run does not stop in time) calls to keep every complete CSV row on
//! disk and no half row. Each [`SignalSafeWriter`] is registered in a
//! process-wide list that [`flush_registered`] walks; outputs that are gone
//! leave it when the next one registers.

use std::fs::File;
use std::io::{self, BufWriter, Write};
use std::path::Path;
use std::sync::{Arc, Mutex, MutexGuard, PoisonError, Weak};

type Shared = Arc<Mutex<BufWriter<File>>>;

/// Outputs to flush when a signal ends the run; dead entries are skipped.
static OUTPUTS: Mutex<Vec<Weak<Mutex<BufWriter<File>>>>> = Mutex::new(Vec::new());

fn lock<T>(mutex: &Mutex<T>) -> MutexGuard<'_, T> {
    // A panic elsewhere must not stop the flush: the data is still there.
    mutex.lock().unwrap_or_else(PoisonError::into_inner)
}

/// Flushes every registered output that is still open: what reached it as
/// complete lines is on disk afterwards. Errors are ignored (nowhere to report
/// them while exiting on a signal).
pub fn flush_registered() {
    let outputs = lock(&OUTPUTS);
    for output in outputs.iter().filter_map(Weak::upgrade) {
        let _ = lock(&output).flush();
    }
}

/// A buffered output file that another thread can flush ([`flush_registered`]): the run writes to
/// it as to any [`Write`], and complete lines are handed to a buffer shared with
/// [`flush_registered`]. A partial line stays private until its newline comes,
/// so a signal never leaves half a CSV row in the file.
#[derive(Debug)]
pub struct SignalSafeWriter {
    shared: Shared,
    /// Bytes after the last newline written so far.
    tail: Vec<u8>,
}

/// A partial line longer than this is handed over anyway (output without
/// newlines must not grow without bound).
const MAX_TAIL: usize = 64 * 1024;

impl SignalSafeWriter {
    /// Creates (truncates) `path`, locked against other writers
    /// ([`crate::outfile::create_locked`]), with a 64 KiB buffer and registers it.
    ///
    /// # Errors
    /// The OS error from creating the file.
    pub fn create(path: &Path) -> io::Result<Self> {
        Ok(Self::register(crate::outfile::create_locked(path)?))
    }

    /// Wraps an open file with a 64 KiB buffer and registers it.
    #[must_use]
    pub fn register(file: File) -> Self {
        let shared = Arc::new(Mutex::new(BufWriter::with_capacity(64 * 1024, file)));
        let mut outputs = lock(&OUTPUTS);
        outputs.retain(|w| w.strong_count() > 0);
        outputs.push(Arc::downgrade(&shared));
        Self {
            shared,
            tail: Vec::new(),
        }
    }
}

impl Write for SignalSafeWriter {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        match buf.iter().rposition(|&b| b == b'\n') {
            Some(last) => {
                let mut shared = lock(&self.shared);
                shared.write_all(&self.tail)?;
                self.tail.clear();
                shared.write_all(&buf[..=last])?;
                self.tail.extend_from_slice(&buf[last + 1..]);
            }
            None => {
                self.tail.extend_from_slice(buf);
                if self.tail.len() > MAX_TAIL {
                    lock(&self.shared).write_all(&self.tail)?;
                    self.tail.clear();
                }
            }
        }
        Ok(buf.len())
    }

    fn flush(&mut self) -> io::Result<()> {
        let mut shared = lock(&self.shared);
        shared.write_all(&self.tail)?;
        self.tail.clear();
        shared.flush()
    }
}

impl Drop for SignalSafeWriter {
    fn drop(&mut self) {
        // As BufWriter does on drop: best effort; `flush` reports errors.
        let _ = self.flush();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_complete_lines_reach_the_file_until_flush() {
        let _flushing = lock(&FLUSHING);
        let dir = scratch("lines");
        let path = dir.join("out.csv");
        let mut out = SignalSafeWriter::create(&path).unwrap();
        out.write_all(b"frame,x\n0,1\n1,").unwrap();
        // What the signal thread does.
        flush_registered();
        assert_eq!(std::fs::read_to_string(&path).unwrap(), "frame,x\n0,1\n");
        out.write_all(b"2\n2,3").unwrap();
        flush_registered();
        assert_eq!(
            std::fs::read_to_string(&path).unwrap(),
            "frame,x\n0,1\n1,2\n"
        );
        out.flush().unwrap();
        assert_eq!(
            std::fs::read_to_string(&path).unwrap(),
            "frame,x\n0,1\n1,2\n2,3"
        );
        drop(out);
        std::fs::remove_dir_all(&dir).unwrap();
    }

    /// Held by the tests that call `flush_registered` or look at what is still
    /// buffered: `flush_registered` flushes every test's outputs, and the
    /// tests run in parallel.
    static FLUSHING: Mutex<()> = Mutex::new(());

    /// A directory of this test's own (the lib's tests run in parallel).
    fn scratch(name: &str) -> std::path::PathBuf {
        let dir =
            std::env::temp_dir().join(format!("fdm-run-flushable-{name}-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        dir
    }

    /// The signal thread flushes every registered output (sim-cli's forced exit):
    /// a run with a CSV and another file loses neither; and complete lines
    /// wait in the 64 KiB buffer `create` documents (32 KiB of rows are not on
    /// disk before the flush; a smaller buffer would have written them).
    #[test]
    fn flush_registered_flushes_every_open_output_from_its_64_kib_buffer() {
        let _flushing = lock(&FLUSHING);
        let dir = scratch("two");
        let (first_path, second_path) = (dir.join("first.csv"), dir.join("second.csv"));
        let mut first = SignalSafeWriter::create(&first_path).unwrap();
        let mut second = SignalSafeWriter::create(&second_path).unwrap();
        let row = "0123456789,0123456789,0123456789\n"; // 32 bytes
        let rows = row.repeat(1024); // 32 KiB: half the buffer
        first.write_all(rows.as_bytes()).unwrap();
        second.write_all(b"a,b\n").unwrap();
        assert_eq!(std::fs::read_to_string(&first_path).unwrap(), "");
        assert_eq!(std::fs::read_to_string(&second_path).unwrap(), "");
        flush_registered();
        assert_eq!(std::fs::read_to_string(&first_path).unwrap(), rows);
        assert_eq!(std::fs::read_to_string(&second_path).unwrap(), "a,b\n");
        drop((first, second));
        std::fs::remove_dir_all(&dir).unwrap();
    }

    /// A partial line stays private until its newline comes, unless it grows
    /// longer than 64 KiB ([`MAX_TAIL`]'s doc): exactly 64 KiB without a
    /// newline is not flushed, one byte more is.
    #[test]
    fn a_partial_line_is_handed_over_once_longer_than_64_kib() {
        let _flushing = lock(&FLUSHING);
        let dir = scratch("tail");
        let path = dir.join("out.txt");
        let mut out = SignalSafeWriter::create(&path).unwrap();
        out.write_all(&[b'x'; 64 * 1024]).unwrap();
        flush_registered();
        assert_eq!(std::fs::read(&path).unwrap().len(), 0);
        out.write_all(b"x").unwrap();
        flush_registered();
        assert_eq!(std::fs::read(&path).unwrap().len(), 64 * 1024 + 1);
        drop(out);
        std::fs::remove_dir_all(&dir).unwrap();
    }

    /// Dropping an output writes all of it, a last line without its newline
    /// included, as a `BufWriter` does on drop.
    #[test]
    fn dropping_an_output_writes_its_partial_last_line_too() {
        let dir = scratch("drop");
        let path = dir.join("out.csv");
        let mut out = SignalSafeWriter::create(&path).unwrap();
        out.write_all(b"frame,x\n0,").unwrap();
        drop(out);
        assert_eq!(std::fs::read_to_string(&path).unwrap(), "frame,x\n0,");
        std::fs::remove_dir_all(&dir).unwrap();
    }

    /// Outputs that are gone leave the registry when the next one registers:
    /// a long program that opens and closes many outputs does not grow it
    /// without bound.
    #[test]
    fn closed_outputs_leave_the_registry() {
        let dir = scratch("many");
        for i in 0..200 {
            drop(SignalSafeWriter::create(&dir.join(format!("{i}.csv"))).unwrap());
        }
        let last = SignalSafeWriter::create(&dir.join("last.csv")).unwrap();
        // Other tests of this binary may hold a few outputs open meanwhile.
        let registered = lock(&OUTPUTS).len();
        assert!(registered < 20, "{registered} outputs registered");
        drop(last);
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
