//! Reading outside input: the run library's ([`fdm_run::input`]: files of
//! bounded size, a regular file or a pipe, the same-file check, text and
//! numbers shown in messages); here its refusals as usage errors (exit
//! status 2), the note on stderr while a named pipe waits for its writer,
//! and the number parsers of the options.

pub use fdm_run::input::{clash, show_number, show_path, Echo, InputError};

use crate::error::CliError;

impl From<InputError> for CliError {
    /// A refused input file is a usage error (exit status 2).
    fn from(e: InputError) -> Self {
        Self::usage(e)
    }
}

/// Refuses an output `path` that is one of `others` (a run's other files
/// with their option names, [`clash`]): the usage error `message(name)`.
///
/// # Errors
/// [`CliError::Usage`] when `path` clashes.
pub fn refuse_clash(
    path: &std::path::Path,
    others: &[(Option<&std::path::Path>, &str)],
    message: impl FnOnce(&str) -> String,
) -> Result<(), CliError> {
    clash(path, others).map_or(Ok(()), |name| Err(CliError::usage(message(name))))
}

/// Says on stderr what `sim-cli` is waiting for when opening a named pipe
/// waits for its writer (Ctrl-C stops it, as any run), instead of hanging
/// silently: the `waiting` of [`fdm_run::input::open_input`].
pub fn waiting(note: String) {
    eprintln!("sim-cli: {note}");
}
