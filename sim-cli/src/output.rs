//! Standard output that was closed before `sim-cli` started.
//!
//! When a program is started with stdout closed (`sim-cli ... >&-`), the Rust
//! runtime opens `/dev/null` read-write in its place before `main`, so every
//! write "succeeds" and the report is silently lost. [`check_stdout`] recognises
//! that state (descriptor 1 open read-write on `/dev/null`) and turns it into an
//! error. A stdout redirected to `/dev/null` by a shell (`> /dev/null`, opened
//! write-only) is a deliberate choice and passes. A full device (`> /dev/full`)
//! needs no check: the write itself fails and is reported.
//!
//! Limitation: a parent that hands over `/dev/null` opened read-write on purpose
//! (Python's `subprocess.DEVNULL`, libuv's "ignore") looks exactly the same and is
//! refused too; such callers can pass a write-only `/dev/null` instead.

use crate::error::CliError;

/// Whether descriptor 1 is the read-write `/dev/null` the runtime puts in place
/// of a closed stdout (see the module docs).
#[must_use]
pub fn stdout_was_closed() -> bool {
    #[cfg(unix)]
    {
        use rustix::fs::{fcntl_getfl, fstat, stat, FileType, OFlags};
        let stdout = std::io::stdout();
        let (Ok(fd_stat), Ok(null), Ok(flags)) =
            (fstat(&stdout), stat("/dev/null"), fcntl_getfl(&stdout))
        else {
            // fstat on descriptor 1 itself failing means it is not open at all.
            return fstat(&stdout).is_err();
        };
        FileType::from_raw_mode(fd_stat.st_mode) == FileType::CharacterDevice
            && fd_stat.st_rdev == null.st_rdev
            && (flags & OFlags::RWMODE) == OFlags::RDWR
    }
    #[cfg(not(unix))]
    {
        false
    }
}

/// Refuses to run when stdout was closed at start, since everything `sim-cli`
/// prints there (reports, the HUD, `fgfs-command`'s line) would be lost.
///
/// # Errors
/// [`CliError::Runtime`] (exit status 1) saying so.
pub fn check_stdout() -> Result<(), CliError> {
    if stdout_was_closed() {
        return Err(CliError::runtime(
            "stdout is closed, so the output would be lost (redirect it to a file, \
             or to /dev/null with `> /dev/null` to discard it)",
        ));
    }
    Ok(())
}
