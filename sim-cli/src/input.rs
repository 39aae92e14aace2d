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

/// Waits for a reader of each of `outputs` (with their option names) that
/// is a named pipe, with a note on stderr after a second ([`waiting`]), as an
/// input pipe waits for its writer, and returns those pipes held open: while
/// they are, the outputs' own opening of them returns at once.
///
/// A signal during the wait ends the process at once
/// ([`crate::signals::before_outputs`]): call this before creating any output.
///
/// # Errors
/// [`CliError::Usage`] naming the output whose pipe cannot be opened.
pub fn await_pipe_readers(
    outputs: &[(Option<&std::path::Path>, &str)],
) -> Result<Vec<std::fs::File>, CliError> {
    // `open` blocks until a reader comes, where no frame looks at a signal;
    // nothing has been written, into the pipes or elsewhere.
    let _before_outputs = crate::signals::before_outputs();
    let mut held = Vec::new();
    for &(path, name) in outputs {
        let Some(path) = path else { continue };
        let pipe = fdm_run::input::await_pipe_reader(path, name, waiting)
            .map_err(|e| CliError::usage(format!("cannot open {name} {}: {e}", show_path(path))))?;
        held.extend(pipe);
    }
    Ok(held)
}

/// Says on stderr what `sim-cli` is waiting for when opening a named pipe
/// waits for the program at its other end (Ctrl-C stops it at once: the
/// callers hold [`crate::signals::before_outputs`]), instead of hanging
/// silently: the `waiting` of [`fdm_run::input::open_input`].
pub fn waiting(note: String) {
    eprintln!("sim-cli: {note}");
}
