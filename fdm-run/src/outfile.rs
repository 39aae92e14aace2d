//! Output files that two runs cannot write at once.
//!
//! Every file `sim-cli` writes for a run (`--csv`, `--record`, `--plot`,
//! `sim-cli plot -o`, a study's `runs.csv`) is opened with [`create_locked`]:
//! opened without truncating, locked exclusively (an advisory `flock` lock,
//! held until the file is closed, which the OS does for a killed process
//! too), and only then emptied. A second run naming the same file, through
//! any path or link, finds it locked before it has changed a byte of it, and
//! is refused (by `sim-cli` with exit status 2) with the process that holds
//! it, read from `/proc/locks` where there is one. Before this, two
//! runs writing the same `--csv` both exited 0 and spliced their rows into one
//! file.
//!
//! Only a regular file is locked and emptied. A device (`/dev/null`), a pipe
//! (`/dev/stdout` piped into another program) or a socket has no contents to
//! empty (emptying one fails with "Invalid argument"), and two runs writing
//! `/dev/null` at once are not a mistake: such a file is opened for writing
//! as it is.
//!
//! An output file that is a pipe can wait: a write blocks while the program
//! at the other end takes nothing. A program embedding the run that has its
//! own way of answering signals (Python's `KeyboardInterrupt`) wraps such a
//! file in a [`WatchedFile`]: a write a signal interrupts asks the program's
//! [`WriteWatch`] whether to go on waiting or to stop.

use std::fs::{File, OpenOptions, TryLockError};
use std::io::{self, Seek, SeekFrom, Write};
use std::path::Path;
use std::sync::Arc;

/// What a [`WatchedFile`] asks when one of its writes was interrupted by a
/// signal: the embedding program's answer to signals (Python's handlers, for
/// the Python package), looked at while a write waits for a pipe's reader.
///
/// The contract: once [`WriteWatch::interrupted`] has returned an error,
/// [`WriteWatch::stopped`] returns one until the program says otherwise,
/// so that every later write to a file it watches fails at once instead of
/// waiting again.
pub trait WriteWatch: Send + Sync + std::fmt::Debug {
    /// A write was interrupted by a signal (`EINTR`, nothing written) or
    /// cut short (as a signal cuts a write into a pipe): `Ok` to go on
    /// writing (and waiting), an error to stop.
    ///
    /// # Errors
    /// The error the write fails with, when the program wants to stop.
    fn interrupted(&self) -> io::Result<()>;

    /// The error every write to a watched file fails with, before it is
    /// tried, once writing has been stopped; `None` to write.
    fn stopped(&self) -> Option<io::Error>;
}

/// An output file whose writes, when a signal interrupts one, ask a
/// [`WriteWatch`] whether to go on. Without a watch, or for a regular file
/// (whose writes never wait for another program, and whose bytes are kept
/// whatever a signal does), it writes as the [`File`] does: an interrupted
/// write is retried by the caller, as [`Write::write_all`] and
/// [`std::io::BufWriter`] retry it.
#[derive(Debug)]
pub struct WatchedFile {
    file: File,
    watch: Option<Arc<dyn WriteWatch>>,
}

impl WatchedFile {
    /// `file`, not watched.
    #[must_use]
    pub fn new(file: File) -> Self {
        Self { file, watch: None }
    }

    /// `file` watched by `watch`, unless it is a regular file (or its kind
    /// cannot be read): only a pipe, a socket or a device can keep a write
    /// waiting.
    #[must_use]
    pub fn watched_by(file: File, watch: Arc<dyn WriteWatch>) -> Self {
        let waits = file.metadata().is_ok_and(|m| !m.is_file());
        Self {
            file,
            watch: waits.then_some(watch),
        }
    }

    /// The file.
    #[must_use]
    pub fn file(&self) -> &File {
        &self.file
    }
}

impl Write for WatchedFile {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        let Some(watch) = &self.watch else {
            return self.file.write(buf);
        };
        let file = &mut self.file;
        watched_write(watch.as_ref(), buf.len(), || file.write(buf))
    }

    fn flush(&mut self) -> io::Result<()> {
        self.file.flush()
    }
}

impl Seek for WatchedFile {
    fn seek(&mut self, position: SeekFrom) -> io::Result<u64> {
        self.file.seek(position)
    }
}

/// One write of `len` bytes (`write`) under `watch`: refused before it is
/// tried once writing has stopped; a write a signal interrupted (`EINTR`,
/// nothing written) asks the watch, whose error fails it (and whose `Ok`
/// lets the caller retry it, as [`Write::write_all`] does); a write cut
/// short tells the watch, and its bytes are counted.
fn watched_write(
    watch: &dyn WriteWatch,
    len: usize,
    write: impl FnOnce() -> io::Result<usize>,
) -> io::Result<usize> {
    if let Some(stopped) = watch.stopped() {
        return Err(stopped);
    }
    let written = write();
    match &written {
        Err(e) if e.kind() == io::ErrorKind::Interrupted => watch.interrupted()?,
        // Bytes went out before the signal: they are counted, and a
        // stop (by the contract) fails the write of the rest.
        Ok(n) if *n < len => {
            let _ = watch.interrupted();
        }
        _ => {}
    }
    written
}

/// Creates `path` for writing, as [`File::create`] does, but refuses a file
/// another process is writing through this function (see the module docs).
/// A path that is not a regular file (a device, a pipe) is opened as it is.
///
/// # Errors
/// The OS error from opening or emptying the file; for a file that another
/// process holds, an error of kind [`io::ErrorKind::WouldBlock`] saying which
/// process.
pub fn create_locked(path: &Path) -> io::Result<File> {
    let file = OpenOptions::new()
        .write(true)
        .create(true)
        .truncate(false)
        .open(path)?;
    if !file.metadata()?.is_file() {
        return Ok(file);
    }
    match file.try_lock() {
        Ok(()) => {}
        Err(TryLockError::WouldBlock) => {
            let holder = holder_of(&file).map_or_else(
                || "another process".to_owned(),
                |pid| format!("another process (pid {pid})"),
            );
            return Err(io::Error::new(
                io::ErrorKind::WouldBlock,
                format!("it is being written by {holder}; refusing to write it too"),
            ));
        }
        Err(TryLockError::Error(e)) => return Err(e),
    }
    file.set_len(0)?;
    Ok(file)
}

/// The major and minor numbers of a device number as `stat` gives it
/// (glibc's `gnu_dev_major` and `gnu_dev_minor`: the major's low 12 bits at
/// bit 8 and the rest from bit 44, the minor's low 8 bits at bit 0 and the
/// rest from bit 20), as `/proc/locks` prints them.
#[cfg(target_os = "linux")]
fn major_minor(dev: u64) -> (u64, u64) {
    let major = ((dev >> 8) & 0xfff) | ((dev >> 32) & !0xfff);
    // glibc's masks: the minor's high part is bits 20..44, the major's from
    // 44. (Linux's own numbers, 12-bit majors and 20-bit minors, never reach
    // bit 32; glibc's encoding, and this decoding, allow 32 bits of each.)
    let minor = (dev & 0xff) | ((dev >> 12) & 0xffff_ff00);
    (major, minor)
}

/// The process holding a `flock` lock on `file`: read from `/proc/locks` on
/// Linux; unknown (`None`) elsewhere.
// One function with the platform inside it, not one per platform: a second
// `holder_of` compiled only off Linux had mutants no test here can run, and
// excluding them meant pinning a line number.
fn holder_of(file: &File) -> Option<u32> {
    #[cfg(target_os = "linux")]
    {
        use std::os::unix::fs::MetadataExt as _;
        let meta = file.metadata().ok()?;
        let (major, minor) = major_minor(meta.dev());
        let wanted = format!("{major:02x}:{minor:02x}:{}", meta.ino());
        flock_holder(&std::fs::read_to_string("/proc/locks").ok()?, &wanted)
    }
    #[cfg(not(target_os = "linux"))]
    {
        let _ = file;
        None
    }
}

/// The pid of the `FLOCK` line of `locks` (the text of `/proc/locks`) on the
/// file `wanted` (`MAJOR:MINOR:INODE`, as the kernel prints it).
#[cfg(target_os = "linux")]
fn flock_holder(locks: &str, wanted: &str) -> Option<u32> {
    // "1: FLOCK  ADVISORY  WRITE 12345 fd:01:1234567 0 EOF"; a process
    // waiting for the lock has a line "1: -> FLOCK ...", which is skipped.
    locks.lines().find_map(|line| {
        let fields: Vec<&str> = line.split_whitespace().collect();
        let (kind, pid, id) = (fields.get(1)?, fields.get(4)?, fields.get(5)?);
        (*kind == "FLOCK" && *id == wanted)
            .then(|| pid.parse().ok())
            .flatten()
    })
}

/// A pipe into a `cat` child, for the tests of writing into a pipe: the
/// child (its stdout piped back to the test) and a path that opens the
/// pipe's writing end (`/proc/PID/fd/N`, what `/dev/stdout` is when the
/// output is piped into another program). The test drops the child's stdin
/// once it has opened the path, so that `cat` ends with the writer.
#[cfg(all(test, target_os = "linux"))]
pub(crate) fn pipe_into_cat() -> (std::process::Child, String) {
    use std::process::{Command, Stdio};
    let child = Command::new("cat")
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .spawn()
        .unwrap();
    let fd = std::os::unix::io::AsRawFd::as_raw_fd(child.stdin.as_ref().unwrap());
    let path = format!("/proc/{}/fd/{fd}", std::process::id());
    (child, path)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_second_writer_is_refused_and_the_file_left_alone() {
        let dir = std::env::temp_dir().join(format!("outfile-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("a.csv");
        let mut first = create_locked(&path).unwrap();
        io::Write::write_all(&mut first, b"row 1\n").unwrap();
        // A second open file description (as another process has) is refused.
        let err = create_locked(&path).unwrap_err();
        assert_eq!(err.kind(), io::ErrorKind::WouldBlock);
        let expected = format!("another process (pid {})", std::process::id());
        #[cfg(target_os = "linux")]
        assert!(err.to_string().contains(&expected), "{err}");
        assert_eq!(std::fs::read(&path).unwrap(), b"row 1\n", "not truncated");
        drop(first);
        // Released on close: the next run may write it (and empties it).
        let again = create_locked(&path).unwrap();
        assert_eq!(again.metadata().unwrap().len(), 0);
        drop(again);
        let _ = std::fs::remove_dir_all(&dir);
    }

    /// `/dev/null` (a character device: it cannot be emptied, and emptying
    /// it was an "Invalid argument" error) is opened as it is, by two
    /// writers at once, and takes what is written.
    #[cfg(unix)]
    #[test]
    fn a_device_is_opened_as_it_is_by_every_writer() {
        let path = Path::new("/dev/null");
        let mut first = create_locked(path).unwrap();
        let mut second = create_locked(path).unwrap();
        io::Write::write_all(&mut first, b"row 1\n").unwrap();
        io::Write::write_all(&mut second, b"row 1\n").unwrap();
    }

    /// A watch that answers "go on" to the first `go_on` interruptions and
    /// "stop" from then on, counting them. (Interruptions by real signals,
    /// with the handler Python installs, are tested by the Python package's
    /// `test_interrupt.py`: this crate has no unsafe code to install one.)
    #[derive(Debug, Default)]
    struct CountingWatch {
        go_on: usize,
        seen: std::sync::atomic::AtomicUsize,
        stopped: std::sync::atomic::AtomicBool,
    }

    impl WriteWatch for CountingWatch {
        fn interrupted(&self) -> io::Result<()> {
            use std::sync::atomic::Ordering::SeqCst;
            if self.seen.fetch_add(1, SeqCst) < self.go_on {
                return Ok(());
            }
            self.stopped.store(true, SeqCst);
            Err(io::Error::other("stopped by the watch"))
        }
        fn stopped(&self) -> Option<io::Error> {
            self.stopped
                .load(std::sync::atomic::Ordering::SeqCst)
                .then(|| io::Error::other("stopped by the watch"))
        }
    }

    fn pipe_file() -> (io::PipeReader, File) {
        let (reader, writer) = io::pipe().unwrap();
        (reader, File::from(std::os::fd::OwnedFd::from(writer)))
    }

    /// A stopped watch fails a pipe's writes before they are tried (the
    /// reader gets nothing), and leaves a regular file alone: its writes
    /// never wait, and its bytes are kept.
    #[cfg(unix)]
    #[test]
    fn a_stopped_watch_fails_a_pipes_writes_and_leaves_a_regular_file_alone() {
        use std::io::Read as _;
        let watch = Arc::new(CountingWatch::default());
        watch
            .stopped
            .store(true, std::sync::atomic::Ordering::SeqCst);
        let (mut reader, writer) = pipe_file();
        let mut pipe = WatchedFile::watched_by(writer, watch.clone());
        let err = pipe.write_all(b"row 1\n").unwrap_err();
        assert_eq!(err.to_string(), "stopped by the watch");
        drop(pipe);
        let mut got = Vec::new();
        reader.read_to_end(&mut got).unwrap();
        assert!(got.is_empty());

        let dir = std::env::temp_dir().join(format!("watched-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("a.csv");
        let mut file = WatchedFile::watched_by(File::create(&path).unwrap(), watch.clone());
        file.write_all(b"row 1\n").unwrap();
        drop(file);
        assert_eq!(std::fs::read(&path).unwrap(), b"row 1\n");
        assert_eq!(watch.seen.load(std::sync::atomic::Ordering::SeqCst), 0);
        let _ = std::fs::remove_dir_all(&dir);
    }

    /// The interruptions a real signal causes, as the OS reports them
    /// (`EINTR` with nothing written; fewer bytes written than asked), and
    /// the watch's answers: each case as `watched_write` meets it. (Real
    /// signals are the Python package's `test_interrupt.py`: see
    /// [`CountingWatch`].)
    #[test]
    fn an_interrupted_write_asks_the_watch_and_a_stop_fails_the_writes_after_it() {
        use std::sync::atomic::Ordering::SeqCst;
        let interrupted = || Err(io::Error::from(io::ErrorKind::Interrupted));
        // "Go on": the interruption is handed back for the caller to retry.
        let go_on = CountingWatch {
            go_on: usize::MAX,
            ..CountingWatch::default()
        };
        let err = watched_write(&go_on, 6, interrupted).unwrap_err();
        assert_eq!(err.kind(), io::ErrorKind::Interrupted);
        assert_eq!(go_on.seen.load(SeqCst), 1);
        assert!(go_on.stopped().is_none());
        // A write cut short is counted as written, and the watch told.
        assert_eq!(watched_write(&go_on, 6, || Ok(4)).unwrap(), 4);
        assert_eq!(go_on.seen.load(SeqCst), 2);
        // A whole write, or another error, does not ask the watch.
        assert_eq!(watched_write(&go_on, 6, || Ok(6)).unwrap(), 6);
        let broken = watched_write(&go_on, 6, || Err(io::ErrorKind::BrokenPipe.into()));
        assert_eq!(broken.unwrap_err().kind(), io::ErrorKind::BrokenPipe);
        assert_eq!(go_on.seen.load(SeqCst), 2);

        // "Stop": the watch's error fails the interrupted write, and every
        // later one before it is tried.
        let stop = CountingWatch::default();
        let err = watched_write(&stop, 6, interrupted).unwrap_err();
        assert_eq!(err.to_string(), "stopped by the watch");
        let mut tried = false;
        let err = watched_write(&stop, 6, || {
            tried = true;
            Ok(6)
        })
        .unwrap_err();
        assert_eq!(err.to_string(), "stopped by the watch");
        assert!(!tried, "a stopped watch refuses a write before it is tried");
        assert_eq!(stop.seen.load(SeqCst), 1);

        // A write cut short under a watch that stops: its bytes still
        // count, and the next write is refused.
        let cut = CountingWatch::default();
        assert_eq!(watched_write(&cut, 6, || Ok(2)).unwrap(), 2);
        assert!(watched_write(&cut, 4, || Ok(4)).is_err());
    }

    /// The holder is the pid of the `FLOCK` line on the file: not a POSIX
    /// or OFD lock's, not another file's, not a waiter's (`->`).
    #[cfg(target_os = "linux")]
    #[test]
    fn the_holder_is_the_flock_line_on_the_file() {
        let locks = "1: POSIX  ADVISORY  WRITE 111 fd:01:1234 0 EOF\n\
                     2: FLOCK  ADVISORY  WRITE 222 fd:01:9999 0 EOF\n\
                     3: OFDLCK ADVISORY  READ  -1 fd:01:1234 0 EOF\n\
                     4: FLOCK  ADVISORY  WRITE 444 fd:01:1234 0 EOF\n\
                     4: -> FLOCK  ADVISORY  WRITE 555 fd:01:1234 0 EOF\n";
        assert_eq!(flock_holder(locks, "fd:01:1234"), Some(444));
        assert_eq!(flock_holder(locks, "fd:01:9999"), Some(222));
        assert_eq!(flock_holder(locks, "fd:02:1234"), None);
        assert_eq!(flock_holder("", "fd:01:1234"), None);
    }

    /// Device numbers decode to the major and minor they were made of
    /// (glibc's `gnu_dev_makedev`, written out here), the large ones too: a
    /// minor from 256 has bits in the high part (device-mapper and NVMe
    /// partitions, the anonymous devices of overlay and FUSE file systems),
    /// which the files of this machine's tests may not; a major from 4096
    /// is glibc's encoding only (Linux's majors have 12 bits).
    #[cfg(target_os = "linux")]
    #[test]
    fn device_numbers_decode_to_their_major_and_minor() {
        let makedev = |major: u64, minor: u64| {
            ((major & 0xfff) << 8)
                | ((major & !0xfff) << 32)
                | (minor & 0xff)
                | ((minor & !0xff) << 12)
        };
        for (major, minor) in [
            (0, 0),
            (8, 1),
            (0, 46),
            (259, 3),
            (4095, 255),
            (4096, 256),
            (0xfff_ffff, 0xfff_ffff),
            (0x12_3456, 0xab_cdef),
        ] {
            assert_eq!(
                major_minor(makedev(major, minor)),
                (major, minor),
                "{major}:{minor}"
            );
        }
    }

    /// A pipe (what `/dev/stdout` is when the output is piped into another
    /// program) is written, not emptied or locked: the reader gets the bytes.
    #[cfg(target_os = "linux")]
    #[test]
    fn a_pipe_is_written_as_it_is() {
        use std::io::Read as _;
        let (mut child, path) = pipe_into_cat();
        let mut pipe = create_locked(Path::new(&path)).unwrap();
        io::Write::write_all(&mut pipe, b"row 1\n").unwrap();
        drop(pipe);
        drop(child.stdin.take());
        let mut got = String::new();
        child
            .stdout
            .take()
            .unwrap()
            .read_to_string(&mut got)
            .unwrap();
        assert!(child.wait().unwrap().success());
        assert_eq!(got, "row 1\n");
    }
}
