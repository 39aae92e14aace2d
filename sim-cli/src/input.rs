//! Reading outside input: the run library's ([`fdm_run::input`]: files of
//! bounded size, a regular file or a pipe, the same-file check, text and
//! numbers shown in messages); here its refusals as usage errors (exit
//! status 2), the note on stderr while a named pipe waits for its writer,
//! and the number parsers of the options.

pub use fdm_run::input::{clash, show_number, show_path, Echo, InputError, MAX_INPUT_BYTES};

use crate::error::CliError;

impl From<InputError> for CliError {
    /// A refused input file is a usage error (exit status 2).
    fn from(e: InputError) -> Self {
        Self::usage(e)
    }
}

/// Says on stderr what `sim-cli` is waiting for when opening a named pipe
/// waits for its writer (Ctrl-C stops it, as any run), instead of hanging
/// silently: the `waiting` of [`fdm_run::input::open_input`].
pub fn waiting(note: String) {
    eprintln!("sim-cli: {note}");
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
