//! `--csv FILE`: one row per frame, buffered.
//!
//! Layout: a header `frame,time_s,<columns>`, a row for the initial state as frame 0,
//! then one row after every step. Numbers use Rust's shortest round-trip form
//! (exponent notation for very large or small magnitudes); NaN and infinities are
//! written as `NaN`, `inf`, `-inf`, which Python and pandas read back.
//!
//! Each model supplies its columns through [`CsvRecord`]; [`crate::snapshot::Snapshot`]
//! implements it (the common columns, then the model's
//! [`Details::CSV_COLUMNS`](crate::models::Details::CSV_COLUMNS)).

use std::fmt::Write as _;
use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::Path;

use anyhow::Context as _;

use crate::error::CliError;

/// A value that can be written as one CSV row.
pub trait CsvRecord {
    /// Column names after `frame,time_s`. Must not change during a run.
    fn csv_columns(&self) -> Vec<&'static str>;
    /// Simulated time, seconds (the `time_s` column).
    fn time_s(&self) -> f64;
    /// Appends one value per column, in [`Self::csv_columns`] order.
    fn csv_values(&self, out: &mut Vec<f64>);
}

/// A buffered CSV writer for per-frame rows.
#[derive(Debug)]
pub struct CsvWriter<W: Write> {
    out: W,
    /// Shown in error messages.
    name: String,
    columns: Option<usize>,
    values: Vec<f64>,
    line: String,
}

impl CsvWriter<BufWriter<File>> {
    /// Creates (truncates) `path`. Called before the run starts, so a failure is a
    /// usage error (exit status 2) and nothing has been simulated.
    ///
    /// # Errors
    /// [`CliError::Usage`] naming the path and the OS reason.
    pub fn create(path: &Path) -> Result<Self, CliError> {
        let file = crate::outfile::create_locked(path).map_err(|e| {
            CliError::usage(format!("cannot create CSV file {}: {e}", path.display()))
        })?;
        Ok(Self::new(
            BufWriter::with_capacity(64 * 1024, file),
            path.display().to_string(),
        ))
    }
}

impl<W: Write> CsvWriter<W> {
    /// Wraps any writer; `name` identifies it in error messages.
    pub fn new(out: W, name: impl Into<String>) -> Self {
        Self {
            out,
            name: name.into(),
            columns: None,
            values: Vec::new(),
            line: String::new(),
        }
    }

    /// Whether the header has been written.
    #[must_use]
    pub fn has_header(&self) -> bool {
        self.columns.is_some()
    }

    /// Writes the header line `frame,time_s,<columns>`.
    ///
    /// # Errors
    /// [`CliError::Runtime`] if the header was already written or writing fails.
    pub fn write_header(&mut self, columns: &[&str]) -> Result<(), CliError> {
        if self.columns.is_some() {
            return Err(CliError::runtime(format!(
                "internal error: CSV header for {} written twice",
                self.name
            )));
        }
        self.columns = Some(columns.len());
        self.line.clear();
        self.line.push_str("frame,time_s");
        for c in columns {
            self.line.push(',');
            self.line.push_str(c);
        }
        self.line.push('\n');
        self.flush_line()
    }

    /// Writes one row: `frame`, `time_s`, then `values`.
    ///
    /// # Errors
    /// [`CliError::Runtime`] if the header is missing, the number of values does not
    /// match it (a bug in a [`CsvRecord`] impl), or writing fails.
    pub fn write_row(&mut self, frame: u64, time_s: f64, values: &[f64]) -> Result<(), CliError> {
        match self.columns {
            Some(n) if n == values.len() => {}
            Some(n) => {
                return Err(CliError::runtime(format!(
                    "internal error: CSV row for {} has {} values, header has {n}",
                    self.name,
                    values.len()
                )))
            }
            None => {
                return Err(CliError::runtime(format!(
                    "internal error: CSV row for {} before its header",
                    self.name
                )))
            }
        }
        self.line.clear();
        // Writing into a String cannot fail.
        let _ = write!(self.line, "{frame},");
        push_number(&mut self.line, time_s);
        for &v in values {
            self.line.push(',');
            push_number(&mut self.line, v);
        }
        self.line.push('\n');
        self.flush_line()
    }

    /// Writes `record` as frame `frame`, writing the header first if needed.
    ///
    /// # Errors
    /// As [`Self::write_header`] and [`Self::write_row`].
    pub fn write_record(&mut self, frame: u64, record: &impl CsvRecord) -> Result<(), CliError> {
        if self.columns.is_none() {
            self.write_header(&record.csv_columns())?;
        }
        let mut values = std::mem::take(&mut self.values);
        values.clear();
        record.csv_values(&mut values);
        let result = self.write_row(frame, record.time_s(), &values);
        self.values = values;
        result
    }

    /// Flushes and returns the inner writer.
    ///
    /// # Errors
    /// [`CliError::Runtime`] if flushing fails (e.g. disk full).
    pub fn finish(mut self) -> Result<W, CliError> {
        self.out
            .flush()
            .with_context(|| format!("writing CSV file {}", self.name))?;
        Ok(self.out)
    }

    fn flush_line(&mut self) -> Result<(), CliError> {
        self.out
            .write_all(self.line.as_bytes())
            .with_context(|| format!("writing CSV file {}", self.name))?;
        Ok(())
    }
}

/// Appends `v` in the shortest form that reads back to the same bits. Rust's
/// `Display` never uses an exponent, which would print 1e-300 with 300 zeros, so
/// magnitudes outside [1e-5, 1e16) use `LowerExp` (also shortest round-trip).
fn push_number(line: &mut String, v: f64) {
    let a = v.abs();
    let _ = if v == 0.0 || !v.is_finite() || (1e-5..1e16).contains(&a) {
        write!(line, "{v}")
    } else {
        write!(line, "{v:e}")
    };
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::snapshot::samples;

    #[test]
    fn header_and_rows() {
        let mut w = CsvWriter::new(Vec::new(), "mem");
        w.write_header(&["a", "b"]).unwrap();
        w.write_row(0, 0.0, &[1.5, -2.0]).unwrap();
        w.write_row(1, 0.1, &[1e-300, f64::NAN]).unwrap();
        let text = String::from_utf8(w.finish().unwrap()).unwrap();
        assert_eq!(text, "frame,time_s,a,b\n0,0,1.5,-2\n1,0.1,1e-300,NaN\n");
    }

    #[test]
    fn numbers_round_trip() {
        for v in [
            0.1,
            1.0 / 3.0,
            123_456_789.123_456_79,
            1e16,
            9.99e-6,
            -1e-5,
            5e-324,
        ] {
            let mut s = String::new();
            push_number(&mut s, v);
            assert_eq!(s.parse::<f64>().unwrap().to_bits(), v.to_bits(), "{s}");
            assert!(s.len() < 30, "{s}");
        }
    }

    #[test]
    fn rejects_wrong_width_and_missing_header() {
        let mut w = CsvWriter::new(Vec::new(), "mem");
        assert!(w.write_row(0, 0.0, &[]).is_err());
        w.write_header(&["a"]).unwrap();
        assert!(w.write_header(&["a"]).is_err());
        assert_eq!(w.write_row(0, 0.0, &[1.0, 2.0]).unwrap_err().exit_code(), 1);
    }

    #[test]
    fn records_write_their_header_once() {
        let snap = samples::bourg();
        let mut w = CsvWriter::new(Vec::new(), "mem");
        w.write_record(0, &snap).unwrap();
        w.write_record(1, &snap).unwrap();
        let text = String::from_utf8(w.finish().unwrap()).unwrap();
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(lines.len(), 3);
        assert!(lines[0].starts_with("frame,time_s,x,y,z,"));
        assert!(lines[2].starts_with("1,60.000000000000746,1234.5678901234567,"));
        assert_eq!(lines[0].split(',').count(), lines[1].split(',').count());
    }

    #[test]
    fn unwritable_path_is_a_usage_error() {
        let err = CsvWriter::create(Path::new("/nonexistent-dir/x.csv")).unwrap_err();
        assert_eq!(err.exit_code(), 2);
        assert!(err.to_string().contains("/nonexistent-dir/x.csv"));
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
        let err = w.write_header(&["a"]).unwrap_err();
        assert_eq!(err.exit_code(), 1);
        assert_eq!(err.one_line(), "writing CSV file out.csv: disk full");
    }
}
