//! Per-frame CSV: one row per frame, buffered ([`CsvWriter`]), and the same
//! as an [`Output`] of a run ([`CsvOutput`]).
//!
//! Layout: for a record that names its model ([`CsvRecord::csv_model`], as
//! every flight CSV's [`FlightRow`] does), first one comment line
//! `# model: NAME` ([`MODEL_LINE_PREFIX`] and the registry's name of the model
//! that wrote it, e.g. `# model: palmer`), so a reader such as `sim-cli plot`
//! knows the model without guessing it from the columns; then a header
//! `frame,time_s,<columns>`, a row for the initial state as frame 0, then one
//! row after every step (and frame 0 again after a reset). The comment line is
//! the only line starting with `#` (pandas: `read_csv(path, comment='#')`).
//! Numbers use Rust's shortest round-trip form (exponent notation for very
//! large or small magnitudes); NaN and infinities are written as `NaN`,
//! `inf`, `-inf`, which Python and pandas read back.
//!
//! What a row holds is the caller's: a [`CsvRecord`] names its columns and
//! gives their values (`sim-cli --csv` writes its report's snapshot: the
//! common columns, the model's own, the display status; docs/cli.md).
//! [`FlightRow`] is that row made from a run's [`Frame`], for the models of
//! the registry ([`CsvModel`]): what `afit_fdm.Flight.csv_to` writes, the
//! same bytes as `sim-cli --csv` (the Python suite compares them).

use std::fmt::Write as _;
use std::io::Write;

use fdm_core::model::{FlightStatus, Model};

pub use crate::model::CsvModel;
use crate::output::{Event, Frame, Output, OutputError, Placement};

/// A value that can be written as one CSV row.
pub trait CsvRecord {
    /// Column names after `frame,time_s`. Must not change during a run.
    fn csv_columns(&self) -> Vec<&'static str>;
    /// Simulated time, seconds (the `time_s` column).
    fn time_s(&self) -> f64;
    /// Appends one value per column, in [`Self::csv_columns`] order.
    fn csv_values(&self, out: &mut Vec<f64>);
    /// The registry's name of the model that wrote the row
    /// ([`Model::NAME`]), written before the header as `# model: NAME`
    /// ([`MODEL_LINE_PREFIX`]); `None` (the default): no model line.
    fn csv_model(&self) -> Option<&'static str> {
        None
    }
}

/// How a flight CSV's first line starts: `# model: NAME`, NAME being the
/// registry's name of the model that wrote the file ([`Model::NAME`]:
/// `palmer`, `bourg`, ...). The header follows on the next line.
pub const MODEL_LINE_PREFIX: &str = "# model: ";

/// Why a CSV row or header was not written.
#[derive(Debug, thiserror::Error)]
pub enum CsvError {
    /// The header was written twice (a bug of the caller).
    #[error("internal error: CSV header for {0} written twice")]
    HeaderTwice(String),
    /// A row before the header (a bug of the caller).
    #[error("internal error: CSV row for {0} before its header")]
    NoHeader(String),
    /// A row whose width is not the header's (a bug in a [`CsvRecord`]).
    #[error("internal error: CSV row for {name} has {values} values, header has {header}")]
    Width {
        /// The writer's name.
        name: String,
        /// Values in the row.
        values: usize,
        /// Columns in the header (after `frame,time_s`).
        header: usize,
    },
    /// Writing or flushing failed (e.g. disk full); the cause is the source.
    #[error("writing CSV file {name}")]
    Io {
        /// The writer's name (its path, shown in messages).
        name: String,
        /// What the OS said.
        #[source]
        source: std::io::Error,
    },
}

impl CsvError {
    /// Whether this is a bug of the caller rather than of the file.
    #[must_use]
    pub fn is_internal(&self) -> bool {
        !matches!(self, Self::Io { .. })
    }
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

    /// Writes the model line `# model: NAME` ([`MODEL_LINE_PREFIX`]), which
    /// comes before the header.
    ///
    /// # Errors
    /// [`CsvError::HeaderTwice`] if the header was already written,
    /// [`CsvError::Io`] if writing fails.
    pub fn write_model_line(&mut self, model: &str) -> Result<(), CsvError> {
        if self.columns.is_some() {
            return Err(CsvError::HeaderTwice(self.name.clone()));
        }
        self.line.clear();
        self.line.push_str(MODEL_LINE_PREFIX);
        self.line.push_str(model);
        self.line.push('\n');
        self.flush_line()
    }

    /// Writes the header line `frame,time_s,<columns>`.
    ///
    /// # Errors
    /// [`CsvError::HeaderTwice`] if the header was already written,
    /// [`CsvError::Io`] if writing fails.
    pub fn write_header(&mut self, columns: &[&str]) -> Result<(), CsvError> {
        if self.columns.is_some() {
            return Err(CsvError::HeaderTwice(self.name.clone()));
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
    /// [`CsvError::NoHeader`] if the header is missing, [`CsvError::Width`]
    /// if the number of values does not match it, [`CsvError::Io`] if
    /// writing fails.
    pub fn write_row(&mut self, frame: u64, time_s: f64, values: &[f64]) -> Result<(), CsvError> {
        match self.columns {
            Some(n) if n == values.len() => {}
            Some(n) => {
                return Err(CsvError::Width {
                    name: self.name.clone(),
                    values: values.len(),
                    header: n,
                })
            }
            None => return Err(CsvError::NoHeader(self.name.clone())),
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

    /// Writes `record` as frame `frame`, writing the model line (when the
    /// record names its model, [`CsvRecord::csv_model`]) and the header
    /// first if needed.
    ///
    /// # Errors
    /// As [`Self::write_model_line`], [`Self::write_header`] and
    /// [`Self::write_row`].
    pub fn write_record(&mut self, frame: u64, record: &impl CsvRecord) -> Result<(), CsvError> {
        if self.columns.is_none() {
            if let Some(model) = record.csv_model() {
                self.write_model_line(model)?;
            }
            self.write_header(&record.csv_columns())?;
        }
        let mut values = std::mem::take(&mut self.values);
        values.clear();
        record.csv_values(&mut values);
        let result = self.write_row(frame, record.time_s(), &values);
        self.values = values;
        result
    }

    /// Flushes the inner writer.
    ///
    /// # Errors
    /// [`CsvError::Io`] if flushing fails (e.g. disk full).
    pub fn flush(&mut self) -> Result<(), CsvError> {
        self.out.flush().map_err(|source| CsvError::Io {
            name: self.name.clone(),
            source,
        })
    }

    /// Flushes and returns the inner writer.
    ///
    /// # Errors
    /// [`CsvError::Io`] if flushing fails (e.g. disk full).
    pub fn finish(mut self) -> Result<W, CsvError> {
        self.flush()?;
        Ok(self.out)
    }

    fn flush_line(&mut self) -> Result<(), CsvError> {
        self.out
            .write_all(self.line.as_bytes())
            .map_err(|source| CsvError::Io {
                name: self.name.clone(),
                source,
            })
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

/// A run's CSV as an [`Output`]: frame 0 when attached and after every reset,
/// then a row after every flown frame; a diverged step writes no row (the run
/// stops there). `row` makes each frame's [`CsvRecord`] from the [`Frame`]
/// (the columns are the caller's). [`Output::finish`] flushes; take the
/// writer back with [`CsvOutput::into_inner`].
#[derive(Debug)]
pub struct CsvOutput<W: Write, F> {
    writer: CsvWriter<W>,
    row: F,
}

impl<W: Write, F> CsvOutput<W, F> {
    /// Rows made by `row`, written to `writer`.
    pub fn new(writer: CsvWriter<W>, row: F) -> Self {
        Self { writer, row }
    }

    /// The writer (flushed by [`Output::finish`], not here).
    pub fn into_inner(self) -> CsvWriter<W> {
        self.writer
    }
}

impl<M, W, F, R> Output<M> for CsvOutput<W, F>
where
    M: Model,
    W: Write,
    F: FnMut(&Frame<'_, M>) -> R,
    R: CsvRecord,
{
    fn frame(&mut self, frame: &Frame<'_, M>) -> Result<(), OutputError> {
        if frame.event == Event::Step && frame.status == FlightStatus::Diverged {
            return Ok(());
        }
        let record = (self.row)(frame);
        Ok(self.writer.write_record(frame.number, &record)?)
    }

    fn finish(&mut self) -> Result<(), OutputError> {
        Ok(self.writer.flush()?)
    }
}

/// The columns every model's flight CSV has after `frame,time_s`: the
/// position and velocity in the model's earth frame and own unit (Palmer
/// metres, Bourg feet), the WGS-84 placement (as FlightGear gets it), in
/// this order. The model's own columns ([`CsvModel::CSV_COLUMNS`]) and
/// `status` follow.
pub const COMMON_COLUMNS: &[&str] = &[
    "x",
    "y",
    "z",
    "vx",
    "vy",
    "vz",
    "lat_deg",
    "lon_deg",
    "alt_m",
    "roll_deg",
    "pitch_deg",
    "fg_heading_deg",
];

/// The flight CSV's `status` number: 0 on ground, 1 airborne, 2 landed
/// safe, 3 landed rough, 4 crashed, 5 diverged, 6 stalling (airborne while
/// the model reports a stall).
#[must_use]
pub fn status_number(status: FlightStatus, stalling: bool) -> f64 {
    f64::from(fdm_core::model::DisplayStatus::new(status, stalling).number())
}

/// One row of a flight's CSV, made from a run's [`Frame`]: `time_s` (the
/// model's clock), [`COMMON_COLUMNS`], the model's [`CsvModel::CSV_COLUMNS`],
/// `status` ([`status_number`]). The file names its model first:
/// `# model: NAME` ([`MODEL_LINE_PREFIX`], [`Model::NAME`]).
///
/// ```
/// use fdm_core::palmer::Palmer;
/// use fdm_run::csv::{CsvOutput, CsvWriter, FlightRow};
/// use fdm_run::{Run, Scenario, SharedOutput, Start};
///
/// let mut run = Run::new(Scenario::<Palmer>::new(Start::thesis(), 30, 3)?)?;
/// let csv = SharedOutput::new(CsvOutput::new(CsvWriter::new(Vec::new(), "mem"), FlightRow::<Palmer>::of));
/// run.attach(csv.clone())?;
/// run.run_to_end()?;
/// run.finish()?;
/// let text = String::from_utf8(csv.take().unwrap().into_inner().finish()?)?;
/// assert!(text.starts_with("# model: palmer\nframe,time_s,x,y,z,vx,vy,vz,lat_deg,lon_deg,alt_m,"));
/// assert_eq!(text.lines().count(), 2 + 4);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Debug, Clone, Copy)]
pub struct FlightRow<M: Model> {
    time_s: f64,
    state: M::State,
    controls: M::Controls,
    placement: Placement,
    status: FlightStatus,
    stalling: bool,
}

impl<M: CsvModel> FlightRow<M> {
    /// The row of `frame`.
    #[must_use]
    pub fn of(frame: &Frame<'_, M>) -> Self {
        Self {
            time_s: frame.view.time_s,
            state: *frame.state,
            controls: *frame.controls,
            placement: *frame.placement,
            status: frame.status,
            stalling: frame.view.stalling,
        }
    }

    /// The columns after `frame,time_s`.
    #[must_use]
    pub fn columns() -> Vec<&'static str> {
        let mut columns = COMMON_COLUMNS.to_vec();
        columns.extend_from_slice(M::CSV_COLUMNS);
        columns.push("status");
        columns
    }
}

impl<M: CsvModel> CsvRecord for FlightRow<M> {
    fn csv_columns(&self) -> Vec<&'static str> {
        Self::columns()
    }

    fn time_s(&self) -> f64 {
        self.time_s
    }

    fn csv_model(&self) -> Option<&'static str> {
        Some(M::NAME)
    }

    fn csv_values(&self, out: &mut Vec<f64>) {
        out.extend_from_slice(&M::native_position(&self.state));
        out.extend_from_slice(&M::native_velocity(&self.state));
        let (g, a) = (self.placement.geodetic, self.placement.attitude);
        out.extend_from_slice(&[
            g.lat_deg,
            g.lon_deg,
            g.alt_m,
            a.roll_deg,
            a.pitch_deg,
            a.heading_deg,
        ]);
        M::csv_values(&self.controls, &self.state, out);
        out.push(status_number(self.status, self.stalling));
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{Run, Scenario, SharedOutput, Start};
    use fdm_core::palmer::{Palmer, PalmerAction};

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
        assert!(matches!(
            w.write_row(0, 0.0, &[]),
            Err(CsvError::NoHeader(_))
        ));
        w.write_header(&["a"]).unwrap();
        assert!(matches!(
            w.write_header(&["a"]),
            Err(CsvError::HeaderTwice(_))
        ));
        let err = w.write_row(0, 0.0, &[1.0, 2.0]).unwrap_err();
        assert!(err.is_internal());
        assert_eq!(
            err.to_string(),
            "internal error: CSV row for mem has 2 values, header has 1"
        );
    }

    /// `has_header` is false on a new writer (also after the model line)
    /// and true once the header is out.
    #[test]
    fn has_header_follows_the_header_line() {
        let mut w = CsvWriter::new(Vec::new(), "mem");
        assert!(!w.has_header());
        w.write_model_line("palmer").unwrap();
        assert!(!w.has_header());
        w.write_header(&["x"]).unwrap();
        assert!(w.has_header());
        w.write_row(0, 0.5, &[2.0]).unwrap();
        assert!(w.has_header());
        let text = String::from_utf8(w.finish().unwrap()).unwrap();
        assert_eq!(text, "# model: palmer\nframe,time_s,x\n0,0.5,2\n");
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

    /// Takes every byte; its flush fails (a file whose buffered bytes
    /// cannot reach the disk) and is counted.
    #[derive(Default)]
    struct FlushFails {
        bytes: Vec<u8>,
        flushes: usize,
    }
    impl Write for FlushFails {
        fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
            self.bytes.extend_from_slice(buf);
            Ok(buf.len())
        }
        fn flush(&mut self) -> std::io::Result<()> {
            self.flushes += 1;
            Err(std::io::Error::other("no space left"))
        }
    }

    /// How a flight CSV's rows are made ([`FlightRow::of`]).
    type RowOf<M> = fn(&Frame<'_, M>) -> FlightRow<M>;

    /// A run of model `M` from `start` at 30 frames a second for `frames`
    /// frames, a flight CSV to `out` attached (named `out.csv`), and the
    /// handle to that output.
    fn flight_csv<M: CsvModel, W: Write + 'static>(
        start: Start<M>,
        frames: u64,
        out: W,
    ) -> (Run<M>, SharedOutput<CsvOutput<W, RowOf<M>>>) {
        let mut run = Run::new(Scenario::new(start, 30, frames).unwrap()).unwrap();
        let row: RowOf<M> = FlightRow::<M>::of;
        let csv = SharedOutput::new(CsvOutput::new(CsvWriter::new(out, "out.csv"), row));
        run.attach(csv.clone()).unwrap();
        (run, csv)
    }

    /// A failing flush is the caller's error, not lost: from the writer's
    /// `flush` and `finish`, and from the output's `finish` (the run's end),
    /// which flushes once.
    #[test]
    fn a_failing_flush_is_reported() {
        let mut w = CsvWriter::new(FlushFails::default(), "out.csv");
        w.write_header(&["a"]).unwrap();
        let err = w.flush().unwrap_err();
        assert_eq!(err.to_string(), "writing CSV file out.csv");
        assert!(matches!(w.finish(), Err(CsvError::Io { .. })));

        let (mut run, csv) = flight_csv(Start::<Palmer>::thesis(), 2, FlushFails::default());
        run.run_to_end().unwrap();
        let err = run.finish().unwrap_err();
        assert!(err.to_string().contains("out.csv"), "{err}");
        let inner = csv.take().unwrap().into_inner();
        assert_eq!(inner.out.flushes, 1);
        assert_eq!(
            String::from_utf8_lossy(&inner.out.bytes).lines().count(),
            2 + 3
        );
    }

    #[test]
    fn write_failure_names_the_file_and_keeps_the_cause() {
        let mut w = CsvWriter::new(Failing, "out.csv");
        let err = w.write_header(&["a"]).unwrap_err();
        assert!(!err.is_internal());
        assert_eq!(err.to_string(), "writing CSV file out.csv");
        let source = std::error::Error::source(&err).map(ToString::to_string);
        assert_eq!(source.as_deref(), Some("disk full"));
    }

    /// A row of the model's clock, altitude and throttle.
    struct Row {
        time_s: f64,
        alt_m: f64,
        throttle: f64,
    }

    impl CsvRecord for Row {
        fn csv_columns(&self) -> Vec<&'static str> {
            vec!["alt_m", "throttle"]
        }
        fn time_s(&self) -> f64 {
            self.time_s
        }
        fn csv_values(&self, out: &mut Vec<f64>) {
            out.extend_from_slice(&[self.alt_m, self.throttle]);
        }
    }

    /// A run with a [`CsvOutput`] attached: frame 0 at the start, one row
    /// per flown frame, frame 0 again after a reset; read back, every row
    /// has the frame's numbers to the bit (the shortest round-trip form
    /// parses back exactly: no tolerance).
    #[test]
    fn the_output_writes_a_row_per_frame_that_reads_back() {
        let scenario = Scenario::<Palmer>::new(Start::thesis(), 30, 0).unwrap();
        let mut run = Run::new(scenario).unwrap();
        let csv = SharedOutput::new(CsvOutput::new(
            CsvWriter::new(Vec::new(), "mem"),
            |f: &Frame<'_, Palmer>| Row {
                time_s: f.view.time_s,
                alt_m: f.placement.geodetic.alt_m,
                throttle: f.controls.throttle,
            },
        ));
        run.attach(csv.clone()).unwrap();
        let now = |run: &Run<Palmer>, k: u64| {
            (
                k,
                run.view().time_s,
                run.placement().geodetic.alt_m,
                run.controls().unwrap().throttle,
            )
        };
        let mut expected = vec![now(&run, 0)];
        for k in 1..=45_u64 {
            run.step_actions(&[PalmerAction::ThrottleUp]).unwrap();
            expected.push(now(&run, k));
        }
        run.reset().unwrap();
        expected.push(now(&run, 0));
        run.finish().unwrap();
        let bytes = csv.take().unwrap().into_inner().finish().unwrap();
        let text = String::from_utf8(bytes).unwrap();
        let mut lines = text.lines();
        assert_eq!(lines.next(), Some("frame,time_s,alt_m,throttle"));
        let rows: Vec<(u64, f64, f64, f64)> = lines
            .map(|l| {
                let v: Vec<&str> = l.split(',').collect();
                assert_eq!(v.len(), 4, "{l}");
                (
                    v[0].parse().unwrap(),
                    v[1].parse().unwrap(),
                    v[2].parse().unwrap(),
                    v[3].parse().unwrap(),
                )
            })
            .collect();
        assert_eq!(rows.len(), 47);
        for (got, want) in rows.iter().zip(&expected) {
            assert_eq!(got.0, want.0);
            assert_eq!(got.1.to_bits(), want.1.to_bits(), "frame {}", want.0);
            assert_eq!(got.2.to_bits(), want.2.to_bits(), "frame {}", want.0);
            assert_eq!(got.3.to_bits(), want.3.to_bits(), "frame {}", want.0);
        }
        // The throttle went up: the rows are not all the start's.
        assert!(rows[45].3 > rows[0].3);
    }

    /// A flight CSV names its model on its first line, `# model: NAME`
    /// (the registry's name), before the header; a record that names no
    /// model (the default) has no such line.
    #[test]
    fn a_flight_csv_names_its_model_first() {
        fn text<M: CsvModel>() -> String {
            let (mut run, csv) = flight_csv(Start::<M>::thesis(), 1, Vec::new());
            run.run_to_end().unwrap();
            run.finish().unwrap();
            String::from_utf8(csv.take().unwrap().into_inner().finish().unwrap()).unwrap()
        }
        for (text, name) in [
            (text::<Palmer>(), "palmer"),
            (text::<fdm_core::bourg::Bourg>(), "bourg"),
        ] {
            let mut lines = text.lines();
            assert_eq!(
                lines.next(),
                Some(format!("{MODEL_LINE_PREFIX}{name}").as_str())
            );
            assert!(lines.next().unwrap().starts_with("frame,time_s,x,y,z,"));
            assert_eq!(lines.count(), 2, "frames 0 and 1");
            assert_eq!(text.matches('#').count(), 1, "{text}");
        }
        let mut w = CsvWriter::new(Vec::new(), "mem");
        w.write_header(&["a"]).unwrap();
        assert!(matches!(
            w.write_model_line("palmer"),
            Err(CsvError::HeaderTwice(_))
        ));
    }

    /// A flight's CSV through [`FlightRow`]: `time_s` is the model's clock
    /// (frame / fps as the run's view has it, to the bit), and the step that
    /// diverges writes no row: the file ends with the last finite frame. The
    /// start (huge but finite, as in `run_flightgear`'s test) overflows on
    /// its first step.
    #[test]
    fn flight_rows_carry_the_clock_and_no_diverged_frame() {
        fn fly(start: Start<Palmer>, frames: u64) -> (Vec<Vec<f64>>, Vec<f64>) {
            let (mut run, csv) = flight_csv(start, frames, Vec::new());
            let mut clock = vec![run.view().time_s];
            for _ in 0..frames {
                if run.step_frame(&[]).is_err() {
                    break;
                }
                clock.push(run.view().time_s);
            }
            let _ = run.finish();
            let bytes = csv.take().unwrap().into_inner().finish().unwrap();
            let text = String::from_utf8(bytes).unwrap();
            let rows = text
                .lines()
                .skip(2)
                .map(|l| l.split(',').map(|v| v.parse().unwrap()).collect())
                .collect();
            (rows, clock)
        }
        let (rows, clock) = fly(Start::thesis(), 4);
        assert_eq!(rows.len(), 5);
        for (k, (row, t)) in rows.iter().zip(&clock).enumerate() {
            assert_eq!(row[0], k as f64);
            assert_eq!(row[1].to_bits(), t.to_bits(), "frame {k}");
        }
        assert!(clock[4] > 0.13 && clock[4] < 0.134, "{clock:?}");

        let diverging = Start::<Palmer> {
            state: fdm_core::palmer::PalmerState {
                position_m: nalgebra::Vector3::new(0.0, 0.0, 30.0),
                velocity_mps: nalgebra::Vector3::new(1e150, 0.0, 0.0),
                ..fdm_core::palmer::PalmerState::at_rest()
            },
            ..Start::thesis()
        };
        let (rows, clock) = fly(diverging, 3);
        assert_eq!((rows.len(), clock.len()), (1, 1), "{rows:?}");
        assert_eq!(rows[0][0], 0.0);
        assert!(rows[0].iter().all(|v| v.is_finite()), "{rows:?}");
    }

    /// A [`FlightRow`] has one value per column for both models, `status`
    /// last ([`status_number`] of the frame: airborne, 1, for the thesis
    /// starts), and Bourg's flags as 0 or 1.
    #[test]
    fn flight_rows_have_a_value_per_column() {
        fn row<M: CsvModel>() -> (Vec<&'static str>, Vec<f64>) {
            let run = Run::new(Scenario::<M>::new(Start::thesis(), 30, 0).unwrap()).unwrap();
            let (view, placement) = (run.view(), run.placement());
            let (controls, state) = (run.controls().unwrap(), run.state().unwrap());
            let frame = Frame {
                event: Event::Start,
                number: 0,
                flown: 0,
                fps: 30,
                actions: &[],
                controls: &controls,
                state: &state,
                view: &view,
                placement: &placement,
                status: FlightStatus::Airborne,
            };
            let mut values = Vec::new();
            FlightRow::<M>::of(&frame).csv_values(&mut values);
            (FlightRow::<M>::columns(), values)
        }
        let (columns, values) = row::<Palmer>();
        assert_eq!(columns.len(), values.len());
        assert_eq!(
            (columns.last(), values.last()),
            (Some(&"status"), Some(&1.0))
        );
        let (columns, values) = row::<fdm_core::bourg::Bourg>();
        assert_eq!(columns.len(), values.len());
        assert_eq!(
            columns[columns.len() - 4..],
            ["flaps", "stalling", "pitch_trim", "status"]
        );
        assert!(values[values.len() - 4..values.len() - 2]
            .iter()
            .all(|&x| x == 0.0 || x == 1.0));
        assert_eq!(values.last(), Some(&1.0));
    }
}
