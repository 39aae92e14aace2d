//! Reading outside input safely: files of bounded size, the same-file check, and
//! text and numbers shown in messages.
//!
//! Input files (scripts today, recordings later) are read with [`read_text`]:
//!
//! * a **regular file** is accepted up to [`MAX_INPUT_BYTES`] (16 MiB); its size is
//!   checked before anything is read;
//! * a **pipe** (`yes | sim-cli ... --script /dev/stdin`, a named FIFO, `<(...)`
//!   process substitution) is read up to that limit and refused as soon as it
//!   gives one byte more, so an endless producer costs at most 16 MiB and a few
//!   milliseconds;
//! * anything else (a character device such as `/dev/zero`, `/dev/urandom` or a
//!   terminal, a directory, a socket, a block device) is refused without being read.
//!
//! Every refusal is a usage error (exit status 2). Text from the input that ends up
//! in a message goes through [`Echo`], which escapes control characters and cuts it
//! short.

use std::fs::{self, File};
use std::io::Read;
use std::path::Path;
use std::sync::mpsc;
use std::time::Duration;

pub use fdm_core::script::Echo;

use crate::error::CliError;

/// Largest accepted input file: 16 MiB. A script line is some 20 bytes, so this
/// is several hundred thousand rules, far beyond any hand-written script.
pub const MAX_INPUT_BYTES: u64 = 16 * 1024 * 1024;

/// Characters of a path shown in messages (paths are longer than tokens).
const PATH_CHARS: usize = 160;

/// A path as shown in messages: escaped and cut short like any echoed input.
#[must_use]
pub fn show_path(path: &Path) -> String {
    Echo::new(&path.to_string_lossy(), PATH_CHARS).to_string()
}

/// A number as shown in messages: Rust's shortest form when it is short, else
/// scientific notation (`1e308`, not 309 digits).
#[must_use]
pub fn show_number(value: f64) -> String {
    fdm_core::message::ShortNumber(value).to_string()
}

/// What a path is, for the refusal message.
fn kind_of(file_type: fs::FileType) -> &'static str {
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt as _;
        if file_type.is_char_device() {
            return "a character device";
        }
        if file_type.is_block_device() {
            return "a block device";
        }
        if file_type.is_socket() {
            return "a socket";
        }
    }
    if file_type.is_dir() {
        "a directory"
    } else {
        "not a regular file"
    }
}

fn is_pipe(file_type: fs::FileType) -> bool {
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt as _;
        file_type.is_fifo()
    }
    #[cfg(not(unix))]
    {
        let _ = file_type;
        false
    }
}

/// Reads `path` as UTF-8 text of at most `limit` bytes; `what` names it in
/// messages ("script"). See the module docs for what is accepted.
///
/// # Errors
/// [`CliError::Usage`] for a missing or unreadable path, a path that is neither a
/// regular file nor a pipe, more than `limit` bytes, or text that is not UTF-8.
pub fn read_text(path: &Path, what: &str, limit: u64) -> Result<String, CliError> {
    let shown = show_path(path);
    let bytes = read_bytes(path, what, limit)?;
    String::from_utf8(bytes).map_err(|e| {
        let bad = e.utf8_error().valid_up_to();
        let line = 1 + e.as_bytes()[..bad].iter().filter(|&&b| b == b'\n').count();
        CliError::usage(format!(
            "{what} {shown}:{line}: not UTF-8 text (invalid byte at offset {bad})"
        ))
    })
}

/// Reads `path` as bytes, at most `limit` of them, accepting what
/// [`read_text`] accepts (a regular file or a pipe); `what` names it in
/// messages ("recording").
///
/// # Errors
/// As [`read_text`], except for the UTF-8 check.
pub fn read_bytes(path: &Path, what: &str, limit: u64) -> Result<Vec<u8>, CliError> {
    let shown = show_path(path);
    let cannot = |e: std::io::Error| CliError::usage(format!("cannot read {what} {shown}: {e}"));
    let too_big = || {
        CliError::usage(format!(
            "{what} {shown} is larger than the {} MiB limit",
            limit / (1024 * 1024)
        ))
    };
    if fs::metadata(path).is_ok_and(|meta| meta.is_file() && meta.len() > limit) {
        return Err(too_big());
    }
    let file = open_input(path, what)?;
    let mut bytes = Vec::new();
    // One byte past the limit tells "exactly at the limit" from "more" (a file can
    // also grow between the size check and the read).
    file.take(limit.saturating_add(1))
        .read_to_end(&mut bytes)
        .map_err(cannot)?;
    if u64::try_from(bytes.len()).unwrap_or(u64::MAX) > limit {
        return Err(too_big());
    }
    Ok(bytes)
}

/// How long opening a named pipe may wait for its writer before saying so.
const FIFO_NOTE_AFTER: Duration = Duration::from_secs(1);

/// Opens `path` for reading if it is a regular file or a pipe (see the module
/// docs); `what` names it in messages ("CSV").
///
/// Opening a named pipe waits until a program opens it for writing; past
/// a second, a note on stderr says what sim-cli is waiting for
/// (Ctrl-C stops it, as any run), instead of hanging silently.
///
/// # Errors
/// [`CliError::Usage`] for a missing or unreadable path, or a path that is
/// neither a regular file nor a pipe.
pub fn open_input(path: &Path, what: &str) -> Result<File, CliError> {
    let shown = show_path(path);
    let cannot = |e: std::io::Error| CliError::usage(format!("cannot read {what} {shown}: {e}"));
    // Follows symlinks, so /dev/stdin is judged by what stdin really is.
    let meta = fs::metadata(path).map_err(cannot)?;
    let file_type = meta.file_type();
    let pipe = is_pipe(file_type);
    if !file_type.is_file() && !pipe {
        return Err(CliError::usage(format!(
            "cannot read {what} {shown}: it is {}; give a regular file or a pipe",
            kind_of(file_type)
        )));
    }
    if !pipe {
        return File::open(path).map_err(cannot);
    }
    let (opened, wait) = mpsc::channel::<()>();
    let note = format!(
        "sim-cli: waiting for a program to open the pipe {shown} for writing ({what}); \
         Ctrl-C stops"
    );
    let noter = std::thread::spawn(move || {
        if wait.recv_timeout(FIFO_NOTE_AFTER) == Err(mpsc::RecvTimeoutError::Timeout) {
            eprintln!("{note}");
        }
    });
    let file = File::open(path);
    drop(opened);
    let _ = noter.join();
    file.map_err(cannot)
}

/// A finite number, or a one-line message echoing `text`.
///
/// # Errors
/// `text` is not a finite number.
pub fn parse_finite(text: &str) -> Result<f64, String> {
    match text.trim().parse::<f64>() {
        Ok(v) if v.is_finite() => Ok(v),
        _ => Err(format!("`{}` is not a finite number", Echo::short(text))),
    }
}

/// A finite number in `lo..=hi` (`unit` ends the message), or a one-line
/// message echoing `text` as given.
///
/// # Errors
/// `text` is not a finite number in the range.
pub fn parse_in_range(text: &str, lo: f64, hi: f64, unit: &str) -> Result<f64, String> {
    let v = parse_finite(text)?;
    if (lo..=hi).contains(&v) {
        Ok(v)
    } else {
        // The text as given, not `v`: 1e308 printed as a float has 309 digits.
        Err(format!(
            "`{}` is outside {lo}..{hi}{unit}",
            Echo::short(text.trim())
        ))
    }
}

/// Whether `a` and `b` are the same file: the same path, or [`same_file`],
/// else the same canonical path.
fn same_output(a: &Path, b: &Path) -> bool {
    a == b
        || same_file(a, b)
        || match (a.canonicalize(), b.canonicalize()) {
            (Ok(a), Ok(b)) => a == b,
            _ => false,
        }
}

/// The name of the first of `others` (a run's other files with their
/// option names) that is `path`'s file: an output that would overwrite it.
pub fn clash<'a>(path: &Path, others: &[(Option<&Path>, &'a str)]) -> Option<&'a str> {
    others
        .iter()
        .find(|(other, _)| other.is_some_and(|o| same_output(path, o)))
        .map(|&(_, name)| name)
}

/// Whether two paths name the same file: same device and inode, so hard links and
/// symlinks are caught whatever the names. A path that does not exist (yet) is
/// not the same file as anything.
#[must_use]
pub fn same_file(a: &Path, b: &Path) -> bool {
    match (fs::metadata(a), fs::metadata(b)) {
        (Ok(a), Ok(b)) => same_inode(&a, &b),
        _ => false,
    }
}

#[cfg(unix)]
fn same_inode(a: &fs::Metadata, b: &fs::Metadata) -> bool {
    use std::os::unix::fs::MetadataExt as _;
    a.dev() == b.dev() && a.ino() == b.ino()
}

#[cfg(not(unix))]
fn same_inode(_a: &fs::Metadata, _b: &fs::Metadata) -> bool {
    // No portable file identity here; `same_file` callers also compare
    // canonical paths on such systems.
    false
}

#[cfg(test)]
mod tests {
    use super::*;

    fn temp_dir(name: &str) -> std::path::PathBuf {
        let dir = std::env::temp_dir().join(format!("sim-cli-input-{name}-{}", std::process::id()));
        fs::create_dir_all(&dir).unwrap();
        dir
    }

    #[test]
    fn regular_files_up_to_the_limit() {
        let dir = temp_dir("limit");
        let path = dir.join("s.txt");
        fs::write(&path, "1-2 thrust-up\n").unwrap();
        assert_eq!(read_text(&path, "script", 14).unwrap(), "1-2 thrust-up\n");
        let err = read_text(&path, "script", 13).unwrap_err();
        assert_eq!(err.exit_code(), 2);
        assert!(err.to_string().contains("larger than"), "{err}");
        fs::remove_dir_all(&dir).unwrap();
    }

    #[cfg(unix)]
    #[test]
    fn character_devices_and_directories_are_refused_unread() {
        for (path, kind) in [
            ("/dev/zero", "a character device"),
            ("/dev/urandom", "a character device"),
            ("/", "a directory"),
        ] {
            let err = read_text(Path::new(path), "script", MAX_INPUT_BYTES).unwrap_err();
            assert_eq!(err.exit_code(), 2);
            assert!(err.to_string().contains(kind), "{err}");
        }
    }

    #[test]
    fn invalid_utf8_names_the_line() {
        let dir = temp_dir("utf8");
        let path = dir.join("s.txt");
        fs::write(&path, b"1-2 thrust-up\n3-4 \xff\n").unwrap();
        let err = read_text(&path, "script", MAX_INPUT_BYTES).unwrap_err();
        assert!(
            err.to_string()
                .ends_with(":2: not UTF-8 text (invalid byte at offset 18)"),
            "{err}"
        );
        fs::remove_dir_all(&dir).unwrap();
    }

    #[cfg(unix)]
    #[test]
    fn same_file_sees_hard_links_and_symlinks() {
        let dir = temp_dir("same");
        let a = dir.join("a.txt");
        fs::write(&a, "x").unwrap();
        let hard = dir.join("hard.txt");
        fs::hard_link(&a, &hard).unwrap();
        let soft = dir.join("soft.txt");
        std::os::unix::fs::symlink(&a, &soft).unwrap();
        let other = dir.join("other.txt");
        fs::write(&other, "x").unwrap();
        assert!(same_file(&a, &hard));
        assert!(same_file(&soft, &hard));
        assert!(!same_file(&a, &other));
        assert!(!same_file(&a, &dir.join("missing.txt")));
        fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn numbers_and_paths_in_messages_are_short() {
        assert_eq!(show_number(1e308), "1e308");
        assert_eq!(show_number(0.25), "0.25");
        assert_eq!(show_number(-3.0), "-3");
        assert_eq!(show_path(Path::new("a\u{1b}[2J.txt")), "a\\u{1b}[2J.txt");
    }
}
