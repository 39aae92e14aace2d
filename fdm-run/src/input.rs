//! Reading outside input safely, and the files a run writes: files of
//! bounded size, the same-file check, text and numbers shown in messages,
//! and output files locked against a second writer.
//!
//! Input files (scripts, recordings, CSV files read back) are read with
//! [`read_text`] or [`read_bytes`]:
//!
//! * a **regular file** is accepted up to the caller's limit
//!   ([`MAX_INPUT_BYTES`] for scripts); its size is checked before anything
//!   is read;
//! * a **pipe** (`yes | sim-cli ... --script /dev/stdin`, a named FIFO,
//!   `<(...)` process substitution) is read up to that limit and refused as
//!   soon as it gives one byte more, so an endless producer costs at most the
//!   limit and a few milliseconds;
//! * anything else (a character device such as `/dev/zero`, `/dev/urandom`
//!   or a terminal, a directory, a socket, a block device) is refused without
//!   being read.
//!
//! Every refusal is an [`InputError`]. Text from the input that ends up in a
//! message goes through [`Echo`], which escapes control characters and cuts
//! it short.

use std::fs::{self, File};
use std::io::{self, Read};
use std::path::Path;
use std::sync::mpsc;
use std::time::Duration;

pub use fdm_core::script::Echo;

/// Largest accepted script: 16 MiB. A script line is some 20 bytes, so this
/// is several hundred thousand rules, far beyond any hand-written script.
pub const MAX_INPUT_BYTES: u64 = 16 * 1024 * 1024;

/// Characters of a path shown in messages (paths are longer than tokens).
const PATH_CHARS: usize = 160;

/// How long opening a named pipe may wait for its writer before the caller
/// is told ([`open_input`]'s `waiting`).
const FIFO_NOTE_AFTER: Duration = Duration::from_secs(1);

/// Why an input file was refused; `what` names the input ("script") and
/// `path` is the path as shown ([`show_path`]).
#[derive(Debug, thiserror::Error)]
pub enum InputError {
    /// The path cannot be opened or read.
    #[error("cannot read {what} {path}: {source}")]
    Unreadable {
        /// What the input is.
        what: String,
        /// The path, as shown.
        path: String,
        /// The operating system's reason.
        source: io::Error,
    },
    /// The path is neither a regular file nor a pipe.
    #[error("cannot read {what} {path}: it is {kind}; give a regular file or a pipe")]
    NotAFileOrPipe {
        /// What the input is.
        what: String,
        /// The path, as shown.
        path: String,
        /// What it is instead ("a directory", "a character device", ...).
        kind: &'static str,
    },
    /// More bytes than the limit.
    #[error("{what} {path} is larger than the {limit_mib} MiB limit")]
    TooLarge {
        /// What the input is.
        what: String,
        /// The path, as shown.
        path: String,
        /// The limit, in whole MiB.
        limit_mib: u64,
    },
    /// Text that is not UTF-8.
    #[error("{what} {path}:{line}: not UTF-8 text (invalid byte at offset {offset})")]
    NotUtf8 {
        /// What the input is.
        what: String,
        /// The path, as shown.
        path: String,
        /// The line of the first invalid byte (from 1).
        line: usize,
        /// The first invalid byte's offset in the file.
        offset: usize,
    },
}

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
/// messages ("script"), `waiting` is as [`open_input`]'s. See the module
/// docs for what is accepted.
///
/// # Errors
/// [`InputError`]: a missing or unreadable path, a path that is neither a
/// regular file nor a pipe, more than `limit` bytes, or text that is not UTF-8.
pub fn read_text(
    path: &Path,
    what: &str,
    limit: u64,
    waiting: impl FnOnce(String) + Send + 'static,
) -> Result<String, InputError> {
    let bytes = read_bytes(path, what, limit, waiting)?;
    String::from_utf8(bytes).map_err(|e| {
        let offset = e.utf8_error().valid_up_to();
        let line = 1 + e.as_bytes()[..offset]
            .iter()
            .filter(|&&b| b == b'\n')
            .count();
        InputError::NotUtf8 {
            what: what.to_owned(),
            path: show_path(path),
            line,
            offset,
        }
    })
}

/// Reads `path` as bytes, at most `limit` of them, accepting what
/// [`read_text`] accepts (a regular file or a pipe); `what` names it in
/// messages ("recording"), `waiting` is as [`open_input`]'s.
///
/// # Errors
/// As [`read_text`], except for the UTF-8 check.
pub fn read_bytes(
    path: &Path,
    what: &str,
    limit: u64,
    waiting: impl FnOnce(String) + Send + 'static,
) -> Result<Vec<u8>, InputError> {
    let too_big = || InputError::TooLarge {
        what: what.to_owned(),
        path: show_path(path),
        limit_mib: limit / (1024 * 1024),
    };
    if fs::metadata(path).is_ok_and(|meta| meta.is_file() && meta.len() > limit) {
        return Err(too_big());
    }
    let file = open_input(path, what, waiting)?;
    let mut bytes = Vec::new();
    // One byte past the limit tells "exactly at the limit" from "more" (a file can
    // also grow between the size check and the read).
    file.take(limit.saturating_add(1))
        .read_to_end(&mut bytes)
        .map_err(|source| unreadable(path, what, source))?;
    if u64::try_from(bytes.len()).unwrap_or(u64::MAX) > limit {
        return Err(too_big());
    }
    Ok(bytes)
}

fn unreadable(path: &Path, what: &str, source: io::Error) -> InputError {
    InputError::Unreadable {
        what: what.to_owned(),
        path: show_path(path),
        source,
    }
}

/// Opens `path` for reading if it is a regular file or a pipe (see the module
/// docs); `what` names it in messages ("CSV").
///
/// Opening a named pipe waits until a program opens it for writing; past
/// a second, `waiting` is called (once, on another thread) with a note
/// saying what is awaited, for the caller to show instead of hanging
/// silently.
///
/// # Errors
/// [`InputError`]: a missing or unreadable path, or a path that is neither
/// a regular file nor a pipe.
pub fn open_input(
    path: &Path,
    what: &str,
    waiting: impl FnOnce(String) + Send + 'static,
) -> Result<File, InputError> {
    // Follows symlinks, so /dev/stdin is judged by what stdin really is.
    let meta = fs::metadata(path).map_err(|e| unreadable(path, what, e))?;
    let file_type = meta.file_type();
    let pipe = is_pipe(file_type);
    if !file_type.is_file() && !pipe {
        return Err(InputError::NotAFileOrPipe {
            what: what.to_owned(),
            path: show_path(path),
            kind: kind_of(file_type),
        });
    }
    if !pipe {
        return File::open(path).map_err(|e| unreadable(path, what, e));
    }
    let note = format!(
        "waiting for a program to open the pipe {} for writing ({what}); Ctrl-C stops",
        show_path(path)
    );
    noting_a_wait(note, waiting, || File::open(path)).map_err(|e| unreadable(path, what, e))
}

/// Opens the named pipe `path` for writing when it is one, waiting until a
/// program opens it for reading (as the OS makes a writer wait); past a
/// second, `waiting` is called (once, on another thread) with a note saying
/// what is awaited (`what`: the output, e.g. "--csv"), for the caller to
/// show instead of hanging silently. `None` for anything else (nothing
/// waits). An output's own opening of the pipe, while this one is held
/// open, finds the reader there and returns at once.
///
/// # Errors
/// The OS error from opening the pipe.
pub fn await_pipe_reader(
    path: &Path,
    what: &str,
    waiting: impl FnOnce(String) + Send + 'static,
) -> io::Result<Option<File>> {
    if !fs::metadata(path).is_ok_and(|meta| is_pipe(meta.file_type())) {
        return Ok(None);
    }
    let note = format!(
        "waiting for a program to open the pipe {} for reading ({what}); Ctrl-C stops",
        show_path(path)
    );
    noting_a_wait(note, waiting, || {
        fs::OpenOptions::new().write(true).open(path)
    })
    .map(Some)
}

/// `open()`, with `waiting(note)` called on another thread if it has not
/// returned within [`FIFO_NOTE_AFTER`].
fn noting_a_wait<T>(
    note: String,
    waiting: impl FnOnce(String) + Send + 'static,
    open: impl FnOnce() -> T,
) -> T {
    let (opened, wait) = mpsc::channel::<()>();
    let noter = std::thread::spawn(move || {
        if wait.recv_timeout(FIFO_NOTE_AFTER) == Err(mpsc::RecvTimeoutError::Timeout) {
            waiting(note);
        }
    });
    let file = open();
    drop(opened);
    let _ = noter.join();
    file
}

/// Whether `a` and `b` are the same file: the same path, or [`same_file`],
/// else the same canonical path. `/dev/null` is no file's clash: what is
/// written there overwrites nothing, and reading it gives nothing written.
fn same_output(a: &Path, b: &Path) -> bool {
    if is_dev_null(a) || is_dev_null(b) {
        return false;
    }
    a == b
        || same_file(a, b)
        || match (a.canonicalize(), b.canonicalize()) {
            (Ok(a), Ok(b)) => a == b,
            _ => false,
        }
}

/// The name of the first of `others` (a run's other files with their
/// option names) that is `path`'s file: an output that would overwrite it.
#[must_use]
pub fn clash<'a>(path: &Path, others: &[(Option<&Path>, &'a str)]) -> Option<&'a str> {
    others
        .iter()
        .find(|(other, _)| other.is_some_and(|o| same_output(path, o)))
        .map(|&(_, name)| name)
}

/// Whether `path` is `/dev/null` (by any name: [`same_file`]), where what is
/// written overwrites nothing and nobody reads it.
#[must_use]
pub fn is_dev_null(path: &Path) -> bool {
    same_file(path, Path::new("/dev/null"))
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

/// One function with the platforms inside (not one per platform), so that
/// its mutants exist once, on the platform that builds them.
fn same_inode(a: &fs::Metadata, b: &fs::Metadata) -> bool {
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt as _;
        a.dev() == b.dev() && a.ino() == b.ino()
    }
    #[cfg(not(unix))]
    {
        // No portable file identity here; `same_file` callers also compare
        // canonical paths on such systems.
        let _ = (a, b);
        false
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn temp_dir(name: &str) -> std::path::PathBuf {
        let dir = std::env::temp_dir().join(format!("fdm-run-input-{name}-{}", std::process::id()));
        fs::create_dir_all(&dir).unwrap();
        dir
    }

    #[test]
    fn regular_files_up_to_the_limit() {
        let dir = temp_dir("limit");
        let path = dir.join("s.txt");
        fs::write(&path, "1-2 thrust-up\n").unwrap();
        assert_eq!(
            read_text(&path, "script", 14, drop).unwrap(),
            "1-2 thrust-up\n"
        );
        let err = read_text(&path, "script", 13, drop).unwrap_err();
        assert!(matches!(err, InputError::TooLarge { .. }), "{err}");
        assert!(err.to_string().contains("larger than"), "{err}");
        fs::remove_dir_all(&dir).unwrap();
    }

    /// The scripts' limit is the 16 MiB that docs/cli.md promises: a
    /// script of exactly 16 MiB is read, one byte more is refused by its
    /// size. (Sparse files: nothing is written to the disk.)
    #[test]
    fn a_script_of_16_mib_is_read_and_one_byte_more_refused() {
        let dir = temp_dir("16mib");
        let path = dir.join("s.txt");
        let file = File::create(&path).unwrap();
        file.set_len(16 * 1024 * 1024).unwrap();
        let text = read_text(&path, "script", MAX_INPUT_BYTES, drop).unwrap();
        assert_eq!(text.len(), 16 * 1024 * 1024);
        file.set_len(16 * 1024 * 1024 + 1).unwrap();
        let err = read_text(&path, "script", MAX_INPUT_BYTES, drop).unwrap_err();
        assert!(
            err.to_string().ends_with("is larger than the 16 MiB limit"),
            "{err}"
        );
        fs::remove_dir_all(&dir).unwrap();
    }

    /// A pipe is read to its end, up to the limit; a producer that goes on
    /// past it is refused after limit + 1 bytes. (An anonymous pipe opened
    /// by its `/dev/fd` path, as a shell's `<(...)` hands one over.)
    #[cfg(target_os = "linux")]
    #[test]
    fn pipes_are_read_up_to_the_limit() {
        use std::io::Write as _;
        use std::os::fd::AsRawFd as _;
        fn through_a_pipe(bytes: &'static [u8], limit: u64) -> Result<String, InputError> {
            let (reader, mut writer) = io::pipe().unwrap();
            let path = std::path::PathBuf::from(format!("/dev/fd/{}", reader.as_raw_fd()));
            let producer = std::thread::spawn(move || {
                // The reader may stop early (the limit): a broken pipe is fine.
                let _ = writer.write_all(bytes);
            });
            let text = read_text(&path, "script", limit, drop);
            drop(reader);
            producer.join().unwrap();
            text
        }
        assert_eq!(
            through_a_pipe(b"1-2 thrust-up\n", 14).unwrap(),
            "1-2 thrust-up\n"
        );
        let err = through_a_pipe(&[b'x'; 1 << 20], 1 << 19).unwrap_err();
        assert!(matches!(err, InputError::TooLarge { .. }), "{err}");
    }

    /// A named pipe made by `mkfifo` in a fresh directory.
    #[cfg(unix)]
    fn fifo(name: &str) -> (std::path::PathBuf, std::path::PathBuf) {
        let dir = temp_dir(name);
        let path = dir.join("pipe");
        let made = std::process::Command::new("mkfifo")
            .arg(&path)
            .status()
            .unwrap();
        assert!(made.success());
        (dir, path)
    }

    /// What `waiting` was told, collected from its thread.
    #[cfg(unix)]
    fn notes() -> (impl FnOnce(String) + Send + 'static, mpsc::Receiver<String>) {
        let (tx, rx) = mpsc::channel();
        (
            move |note| {
                let _ = tx.send(note);
            },
            rx,
        )
    }

    /// Reading a named pipe whose writer comes late waits for it, and past
    /// [`FIFO_NOTE_AFTER`] says so once; a regular file and a pipe whose
    /// writer is there at once are read without a note.
    #[cfg(unix)]
    #[test]
    fn a_named_pipe_read_before_its_writer_comes_is_noted_once() {
        let (dir, path) = fifo("late-writer");
        let writer_path = path.clone();
        let (waiting, told) = notes();
        // The writer comes once the note is out (so no timing can race
        // them), or after 30 s without one.
        let writer = std::thread::spawn(move || {
            let first = told.recv_timeout(Duration::from_secs(30));
            fs::write(writer_path, "1-2 thrust-up\n").unwrap();
            first
                .into_iter()
                .chain(told.try_iter())
                .collect::<Vec<String>>()
        });
        let text = read_text(&path, "script", MAX_INPUT_BYTES, waiting).unwrap();
        let told = writer.join().unwrap();
        assert_eq!(text, "1-2 thrust-up\n");
        assert_eq!(told.len(), 1, "{told:?}");
        assert!(
            told[0].starts_with("waiting for a program to open the pipe ")
                && told[0].ends_with(" for writing (script); Ctrl-C stops"),
            "{told:?}"
        );

        let file = dir.join("s.txt");
        fs::write(&file, "x").unwrap();
        let (waiting, told) = notes();
        assert_eq!(read_text(&file, "script", 1, waiting).unwrap(), "x");
        assert_eq!(told.try_iter().count(), 0);
        fs::remove_dir_all(&dir).unwrap();
    }

    /// An output that is a named pipe waits for its reader (noted past
    /// [`FIFO_NOTE_AFTER`]) and is held open for writing; anything else is
    /// `None`, opened for nothing, and nothing is noted.
    #[cfg(unix)]
    #[test]
    fn an_output_pipe_waits_for_its_reader() {
        let (dir, path) = fifo("late-reader");
        let reader_path = path.clone();
        let (waiting, told) = notes();
        // The reader comes once the note is out, or after 30 s without one.
        let reader = std::thread::spawn(move || {
            let first = told.recv_timeout(Duration::from_secs(30));
            let text = fs::read_to_string(reader_path).unwrap();
            let told: Vec<String> = first.into_iter().chain(told.try_iter()).collect();
            (text, told)
        });
        let mut held = await_pipe_reader(&path, "--csv", waiting)
            .unwrap()
            .expect("a pipe is held open");
        io::Write::write_all(&mut held, b"frame\n").unwrap();
        drop(held);
        let (text, told) = reader.join().unwrap();
        assert_eq!(text, "frame\n");
        assert_eq!(told.len(), 1, "{told:?}");
        assert!(
            told[0].ends_with(" for reading (--csv); Ctrl-C stops"),
            "{told:?}"
        );

        let file = dir.join("out.csv");
        fs::write(&file, "kept").unwrap();
        for path in [
            file.as_path(),
            &dir.join("missing.csv"),
            Path::new("/dev/null"),
        ] {
            let (waiting, told) = notes();
            assert!(await_pipe_reader(path, "--csv", waiting).unwrap().is_none());
            assert_eq!(told.try_iter().count(), 0);
        }
        assert_eq!(fs::read_to_string(&file).unwrap(), "kept");
        fs::remove_dir_all(&dir).unwrap();
    }

    /// Two outputs given the same path clash even before the file exists
    /// (no canonical path yet), and so do two spellings of an existing one
    /// and a hard link to it; two existing files do not.
    #[test]
    fn the_same_new_path_twice_clashes() {
        let dir = temp_dir("new");
        let new = dir.join("out.csv");
        assert_eq!(clash(&new, &[(Some(&new), "--csv")]), Some("--csv"));
        assert_eq!(
            clash(
                &new,
                &[(None, "--dis"), (Some(&dir.join("b.csv")), "--acmi")]
            ),
            None
        );
        fs::write(&new, "x").unwrap();
        let other = dir.join("b.csv");
        fs::write(&other, "x").unwrap();
        assert_eq!(clash(&new, &[(Some(&other), "--acmi")]), None);
        // A hard link is the same file under another canonical path (known
        // by its inode: unix only).
        #[cfg(unix)]
        {
            let hard = dir.join("hard.csv");
            fs::hard_link(&new, &hard).unwrap();
            assert_eq!(clash(&new, &[(Some(&hard), "--acmi")]), Some("--acmi"));
        }
        let dotted = dir.join(".").join("out.csv");
        assert_eq!(clash(&new, &[(Some(&dotted), "--acmi")]), Some("--acmi"));
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
            let err = read_text(Path::new(path), "script", MAX_INPUT_BYTES, drop).unwrap_err();
            assert!(matches!(err, InputError::NotAFileOrPipe { .. }), "{err}");
            assert!(err.to_string().contains(kind), "{err}");
        }
    }

    #[test]
    fn invalid_utf8_names_the_line() {
        let dir = temp_dir("utf8");
        let path = dir.join("s.txt");
        fs::write(&path, b"1-2 thrust-up\n3-4 \xff\n").unwrap();
        let err = read_text(&path, "script", MAX_INPUT_BYTES, drop).unwrap_err();
        assert!(
            err.to_string()
                .ends_with(":2: not UTF-8 text (invalid byte at offset 18)"),
            "{err}"
        );
        fs::remove_dir_all(&dir).unwrap();
    }

    #[cfg(unix)]
    /// Two outputs on `/dev/null` (a caller discarding both) do not clash;
    /// two on one file, by any name, do.
    #[cfg(unix)]
    #[test]
    fn dev_null_clashes_with_nothing() {
        let null = Path::new("/dev/null");
        assert_eq!(clash(null, &[(Some(null), "--csv")]), None);
        let dir = temp_dir("null");
        let file = dir.join("a.csv");
        fs::write(&file, "x").unwrap();
        assert_eq!(clash(&file, &[(Some(null), "--csv")]), None);
        assert_eq!(clash(null, &[(Some(&file), "--csv")]), None);
        assert_eq!(
            clash(&file, &[(Some(null), "--acmi"), (Some(&file), "--csv")]),
            Some("--csv")
        );
        fs::remove_dir_all(&dir).unwrap();
    }

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
