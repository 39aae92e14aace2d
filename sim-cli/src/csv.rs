//! `--csv FILE`: one row per frame, written by the run library's
//! [`fdm_run::csv::CsvOutput`] attached to the run (the layout and number
//! format are documented there and in docs/cli.md). Each row is a
//! [`fdm_run::csv::FlightRow`]: the common columns, then the model's
//! [`CsvModel::CSV_COLUMNS`](fdm_run::csv::CsvModel::CSV_COLUMNS), then the
//! display status.

pub use fdm_run::csv::{CsvError, CsvWriter};

use crate::error::CliError;

impl From<CsvError> for CliError {
    /// Every CSV failure happens after the input was accepted: a run-time
    /// error (exit status 1), `writing CSV file NAME: REASON` for the file.
    fn from(e: CsvError) -> Self {
        Self::Runtime(anyhow::Error::from(e))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::io::Write;

    #[test]
    fn a_bad_row_is_a_runtime_error() {
        let mut w = CsvWriter::new(Vec::new(), "mem");
        w.write_header(&["a"]).unwrap();
        let err = CliError::from(w.write_row(0, 0.0, &[1.0, 2.0]).unwrap_err());
        assert_eq!(err.exit_code(), 1);
    }

    struct Failing;
    impl Write for Failing {
        fn write(&mut self, _: &[u8]) -> std::io::Result<usize> {
            Err(std::io::Error::other("disk full"))
        }
        fn flush(&mut self) -> std::io::Result<()> {
            Ok(())
        }
    }

    #[test]
    fn write_failure_is_a_runtime_error_naming_the_file() {
        let mut w = CsvWriter::new(Failing, "out.csv");
        let err = CliError::from(w.write_header(&["a"]).unwrap_err());
        assert_eq!(err.exit_code(), 1);
        assert_eq!(err.one_line(), "writing CSV file out.csv: disk full");
    }
}
