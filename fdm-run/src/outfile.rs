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

use std::fs::{File, OpenOptions, TryLockError};
use std::io;
use std::path::Path;

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

/// The process holding a `flock` lock on `file`, from `/proc/locks` (Linux).
#[cfg(target_os = "linux")]
fn holder_of(file: &File) -> Option<u32> {
    use std::os::unix::fs::MetadataExt as _;
    let meta = file.metadata().ok()?;
    let dev = meta.dev();
    // The kernel's encoding of a device number (glibc's gnu_dev_major/minor).
    let major = ((dev >> 8) & 0xfff) | ((dev >> 32) & !0xfff);
    let minor = (dev & 0xff) | ((dev >> 12) & !0xff);
    let wanted = format!("{major:02x}:{minor:02x}:{}", meta.ino());
    let locks = std::fs::read_to_string("/proc/locks").ok()?;
    // "1: FLOCK  ADVISORY  WRITE 12345 fd:01:1234567 0 EOF"
    locks.lines().find_map(|line| {
        let fields: Vec<&str> = line.split_whitespace().collect();
        let (kind, pid, id) = (fields.get(1)?, fields.get(4)?, fields.get(5)?);
        (*kind == "FLOCK" && *id == wanted)
            .then(|| pid.parse().ok())
            .flatten()
    })
}

#[cfg(not(target_os = "linux"))]
fn holder_of(_file: &File) -> Option<u32> {
    None
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
