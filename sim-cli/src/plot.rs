//! `--plot FILE.svg` on any `sim-cli palmer|bourg|replay` run and
//! `sim-cli plot FILE.csv -o FILE.svg` for a CSV written earlier with
//! `--csv`: the CLI's side of the plot. The drawing and the plot as an
//! output of a run are the library's ([`fdm_plot`]: six panels, bounded
//! memory, [`fdm_plot::PlotOutput`]); here are the output file, created
//! before the run ([`PlotFile`]), and the CSV read back into samples
//! ([`trace_from_csv`]).
//!
//! A CSV gives the samples a run gives: the model is the registry's whose
//! `--csv` header the file has; the status is the CSV's `status` column
//! ([`DisplayStatus::from_number`]) or, in older files without it, is
//! recomputed row by row with [`FlightStatus::update`] from the height and
//! the climb rate exactly as the simulation computed it. After a reset (a row
//! whose time goes back) the plot's time axis continues
//! ([`fdm_plot::TraceBuilder`]). The CSV keeps every sample; the plot of a
//! two-hour run at 100 fps is a few hundred kilobytes.

use std::fs::File;
use std::io::{BufRead, Read as _};
use std::path::{Path, PathBuf};

use fdm_core::model::{DisplayStatus, FlightStatus};
use fdm_plot::{PlotError, PlotOutput, PlotSample, TraceBuilder};

pub use fdm_plot::Trace;

use crate::error::CliError;
use crate::input::Echo;
use crate::models::{CliModel, Details, ModelKind, WithModel};

impl From<PlotError> for CliError {
    /// Every plot failure happens after the input was accepted: a run-time
    /// error (exit status 1), e.g. `writing plot file NAME: REASON`.
    fn from(e: PlotError) -> Self {
        Self::Runtime(anyhow::Error::from(e))
    }
}

/// The `--plot` output file, created before the run so that an unwritable path
/// is a usage error (exit status 2) and nothing has been simulated.
#[derive(Debug)]
pub struct PlotFile {
    path: PathBuf,
    file: File,
}

impl PlotFile {
    /// Creates (truncates) `path`.
    ///
    /// # Errors
    /// [`CliError::Usage`] naming the path and the OS reason.
    pub fn create(path: &Path) -> Result<Self, CliError> {
        let file = crate::outfile::create_locked(path).map_err(|e| {
            CliError::usage(format!("cannot create plot file {}: {e}", path.display()))
        })?;
        Ok(Self {
            path: path.to_owned(),
            file,
        })
    }

    /// The plot of a run titled `title` as an output to attach to it: it
    /// samples every frame and writes the SVG when the run finishes.
    #[must_use]
    pub fn into_output(self, title: &str) -> PlotOutput<File> {
        PlotOutput::new(self.file, self.path.display().to_string(), title)
    }

    /// Draws `trace` and writes the SVG.
    ///
    /// # Errors
    /// [`CliError::Runtime`] if drawing or writing fails.
    pub fn write(mut self, trace: &Trace) -> Result<(), CliError> {
        let name = self.path.display().to_string();
        fdm_plot::write_svg(&mut self.file, &name, trace)?;
        Ok(())
    }
}

/// Columns `trace_from_csv` reads, besides the model's speed column.
const CSV_NEEDED: [&str; 8] = [
    "frame",
    "time_s",
    "x",
    "y",
    "z",
    "vz",
    "roll_deg",
    "pitch_deg",
];

/// Largest CSV `sim-cli plot` reads: 8 GiB, some 25 million rows (a day at
/// 300 fps). Memory stays bounded whatever the size ([`TraceBuilder`]).
pub const MAX_CSV_BYTES: u64 = 8 << 30;

/// Longest CSV line accepted: 64 KiB (a row of `--csv` is a few hundred bytes).
pub const MAX_CSV_LINE_BYTES: u64 = 64 * 1024;

/// A CSV read back by [`trace_from_csv`].
#[derive(Debug, Clone, PartialEq)]
pub struct CsvTrace {
    /// The flight, ready to draw.
    pub trace: Trace,
    /// Set when the last row was torn (the file does not end with a newline,
    /// as when the writing run was killed mid-row): what was left out.
    pub torn_last_row: Option<String>,
}

/// Reads one line of at most [`MAX_CSV_LINE_BYTES`] into `line` (cleared
/// first); `Ok(false)` at the end of the input. The newline is kept.
fn read_csv_line(
    reader: &mut impl BufRead,
    line: &mut Vec<u8>,
    name: &str,
    line_no: usize,
    read_total: &mut u64,
) -> Result<bool, CliError> {
    line.clear();
    let n = reader
        .by_ref()
        .take(MAX_CSV_LINE_BYTES + 1)
        .read_until(b'\n', line)
        .map_err(|e| CliError::usage(format!("cannot read {name}: {e}")))?;
    if u64::try_from(line.len()).unwrap_or(u64::MAX) > MAX_CSV_LINE_BYTES {
        return Err(CliError::usage(format!(
            "{name}:{line_no}: a line longer than {} KiB: not a CSV written by sim-cli --csv",
            MAX_CSV_LINE_BYTES / 1024
        )));
    }
    *read_total += u64::try_from(n).unwrap_or(u64::MAX);
    if *read_total > MAX_CSV_BYTES {
        return Err(CliError::usage(format!(
            "{name} is larger than the {} GiB limit",
            MAX_CSV_BYTES >> 30
        )));
    }
    Ok(n > 0)
}

/// What [`trace_from_csv`] knows of a model's CSV, from the model registry.
struct CsvModel {
    /// The model's title ([`fdm_core::model::Model::TITLE`]).
    title: &'static str,
    /// Its name as the error message shows it: `Palmer`, `Bourg`.
    shown: String,
    /// The columns its `--csv` files have after `frame,time_s`.
    columns: Vec<&'static str>,
    /// [`Details::CSV_SPEED_COLUMN`].
    speed_column: &'static str,
    /// [`Details::METRES_PER_UNIT`].
    metres_per_unit: f64,
}

struct DescribeCsv;

impl WithModel for DescribeCsv {
    type Output = CsvModel;
    fn call<M: CliModel>(self) -> CsvModel {
        let name = <M::Details as Details>::MODEL;
        let mut shown = name[..1].to_ascii_uppercase();
        shown.push_str(&name[1..]);
        CsvModel {
            title: M::TITLE,
            shown,
            columns: fdm_run::csv::FlightRow::<M>::columns(),
            speed_column: <M::Details as Details>::CSV_SPEED_COLUMN,
            metres_per_unit: <M::Details as Details>::METRES_PER_UNIT,
        }
    }
}

/// The model that wrote a CSV with this `header`, and its speed column's
/// index: the registered model whose `--csv` header it is, or for older and
/// hand-made files the first (in registry order) whose speed column it has.
fn csv_model(header: &[String]) -> Result<(CsvModel, usize), String> {
    let models: Vec<CsvModel> = <ModelKind as clap::ValueEnum>::value_variants()
        .iter()
        .map(|kind| kind.with(DescribeCsv))
        .collect();
    let column = |wanted: &str| header.iter().position(|c| c == wanted);
    let written_by = |m: &CsvModel| header.len() == m.columns.len() + 2 && header[2..] == m.columns;
    let message = models
        .iter()
        .map(|m| format!("`{}` ({})", m.speed_column, m.shown))
        .collect::<Vec<_>>()
        .join(" or ");
    let found = match models.iter().position(written_by) {
        Some(i) => Some(i),
        None => models.iter().position(|m| column(m.speed_column).is_some()),
    };
    let model = found
        .and_then(|i| models.into_iter().nth(i))
        .ok_or_else(|| format!("no {message} column: not a CSV written by sim-cli --csv"))?;
    let speed = column(model.speed_column).ok_or_else(|| {
        format!(
            "no `{}` column: not a CSV written by sim-cli --csv",
            model.speed_column
        )
    })?;
    Ok((model, speed))
}

/// Reads a CSV written by `--csv` back into a [`Trace`] titled `<model> from <name>`,
/// line by line in bounded memory ([`TraceBuilder`], [`MAX_CSV_LINE_BYTES`],
/// [`MAX_CSV_BYTES`]).
///
/// The model is the registry's whose `--csv` header the file has; in older
/// or hand-made files, the first whose speed column it has
/// ([`Details::CSV_SPEED_COLUMN`]: Palmer's `airspeed` in m/s with positions
/// in metres, Bourg's `speed` in ft/s with positions in feet). The status
/// is the `status` column when there is one
/// ([`DisplayStatus::from_number`]); in older files without it, it is
/// recomputed from the rows: [`FlightStatus::initial`] at every frame 0 and
/// [`FlightStatus::update`] after every other row, from the height and the climb
/// rate in metres, as the simulation did before the ground contact; Bourg's
/// `stalling` column gives the stall.
///
/// A last row without its newline is a torn row (the writing run was killed
/// mid-row): it is left out and reported in [`CsvTrace::torn_last_row`].
///
/// # Errors
/// [`CliError::Usage`] naming `name` and the line for anything that is not such
/// a CSV, including a value that is not a finite number.
pub fn trace_from_csv(mut reader: impl BufRead, name: &str) -> Result<CsvTrace, CliError> {
    let bad = |line: usize, what: String| CliError::usage(format!("{name}:{line}: {what}"));
    let mut buffer = Vec::new();
    let mut read_total = 0u64;
    if !read_csv_line(&mut reader, &mut buffer, name, 1, &mut read_total)? {
        return Err(CliError::usage(format!("{name}: empty CSV file")));
    }
    let header_text = std::str::from_utf8(&buffer).map_err(|_| {
        bad(
            1,
            "not UTF-8 text: not a CSV written by sim-cli --csv".to_owned(),
        )
    })?;
    let header: Vec<String> = header_text
        .trim_end_matches(['\n', '\r'])
        .split(',')
        .map(str::to_owned)
        .collect();
    let column = |wanted: &str| header.iter().position(|c| c == wanted);
    let mut index = [0usize; CSV_NEEDED.len()];
    for (slot, wanted) in index.iter_mut().zip(CSV_NEEDED) {
        *slot = column(wanted).ok_or_else(|| {
            bad(
                1,
                format!("no `{wanted}` column: not a CSV written by sim-cli --csv"),
            )
        })?;
    }
    let [frame_i, time_i, x_i, y_i, z_i, vz_i, roll_i, pitch_i] = index;
    let heading_i = column("fg_heading_deg");
    let (model, speed_i) = csv_model(&header).map_err(|what| bad(1, what))?;
    let (scale, model) = (model.metres_per_unit, model.title);
    let stall_i = column("stalling");
    let status_i = column("status");
    let mut builder = TraceBuilder::new(format!("{model} from {name}"));
    let mut status = FlightStatus::OnGround;
    let mut values = Vec::with_capacity(header.len());
    let mut torn_last_row = None;
    let mut line_no = 1;
    while read_csv_line(&mut reader, &mut buffer, name, line_no + 1, &mut read_total)? {
        line_no += 1;
        if buffer.last() != Some(&b'\n') {
            // The end of the input without a newline: a torn row.
            torn_last_row = Some(format!(
                "{name}:{line_no}: the last row is incomplete (no newline at the end of the \
                 file, as when the run writing it was killed): plotted up to line {}",
                line_no - 1
            ));
            break;
        }
        let line = std::str::from_utf8(&buffer)
            .map_err(|_| bad(line_no, "not UTF-8 text".to_owned()))?
            .trim_end_matches(['\n', '\r']);
        if line.is_empty() {
            continue;
        }
        values.clear();
        for field in line.split(',') {
            let value = field.trim().parse::<f64>().map_err(|_| {
                bad(
                    line_no,
                    format!("`{}` is not a number", Echo::new(field, 40)),
                )
            })?;
            if !value.is_finite() {
                return Err(bad(
                    line_no,
                    format!(
                        "`{}` is not a finite number (sim-cli --csv never writes one)",
                        Echo::new(field, 40)
                    ),
                ));
            }
            values.push(value);
        }
        if values.len() != header.len() {
            return Err(bad(
                line_no,
                format!("{} fields, the header has {}", values.len(), header.len()),
            ));
        }
        let height_m = values[z_i] * scale;
        let recorded = status_i.map(|i| {
            DisplayStatus::from_number(values[i])
                .ok_or_else(|| bad(line_no, format!("`{}` is not a status number", values[i])))
        });
        status = match recorded {
            Some(r) => r?.status,
            None if values[frame_i] == 0.0 => FlightStatus::initial(height_m),
            None => status.update(height_m, values[vz_i] * scale),
        };
        builder.push(PlotSample {
            time_s: values[time_i],
            height_m,
            airspeed_mps: values[speed_i] * scale,
            roll_deg: values[roll_i],
            pitch_deg: values[pitch_i],
            heading_deg: heading_i.map_or(f64::NAN, |i| values[i]),
            north_m: values[x_i] * scale,
            east_m: -values[y_i] * scale,
            status,
            stalling: stall_i.is_some_and(|i| values[i] != 0.0),
            reset: false,
        });
    }
    let trace = builder.finish();
    if trace.samples.is_empty() {
        return Err(CliError::usage(format!("{name}: no data rows to plot")));
    }
    Ok(CsvTrace {
        trace,
        torn_last_row,
    })
}

/// `sim-cli plot FILE.csv -o FILE.svg`: the CSV is read as scripts and
/// recordings are (a regular file or a pipe, nothing else), line by line.
///
/// # Errors
/// [`CliError::Usage`] for an unreadable or malformed CSV or an uncreatable
/// output; [`CliError::Runtime`] if drawing or writing fails.
pub fn run_plot(csv: &Path, output: &Path) -> Result<(), CliError> {
    let file = crate::input::open_input(csv, "CSV")?;
    let name = csv.display().to_string();
    let read = trace_from_csv(std::io::BufReader::new(file), &name)?;
    if let Some(warning) = &read.torn_last_row {
        eprintln!("sim-cli: warning: {warning}");
    }
    PlotFile::create(output)?.write(&read.trace)
}

#[cfg(test)]
mod tests {
    use super::*;
    use fdm_core::model::LandingState;
    use fdm_plot::flight::segments;
    #[test]
    fn csv_status_is_recomputed_like_the_simulation() {
        // Palmer-like columns; climbs, then comes down at -6 m/s: a crash.
        let csv = "frame,time_s,x,y,z,vx,vy,vz,roll_deg,pitch_deg,fg_heading_deg,airspeed\n\
                   0,0,0,0,0,0,0,0,0,0,0,0\n\
                   1,0.1,1,0,1,10,0,2,0,5,0,10\n\
                   2,0.2,2,-1,-0.5,10,0,-6,0,-5,0,12\n\
                   0,0,0,0,0,0,0,0,0,0,0,0\n";
        let t = trace_from_csv(csv.as_bytes(), "t.csv").unwrap().trace;
        let statuses: Vec<_> = t.samples.iter().map(|s| s.status).collect();
        assert_eq!(
            statuses,
            [
                FlightStatus::OnGround,
                FlightStatus::Airborne,
                FlightStatus::Landed(LandingState::Crash),
                FlightStatus::OnGround
            ]
        );
        assert_eq!(t.samples[2].east_m, 1.0);
        assert_eq!(segments(&t.samples).len(), 2);
        assert_eq!(t.title, "Palmer Cessna 172 from t.csv");
    }

    /// Every registered model's `--csv` header is recognised as that model,
    /// with its speed column; a header naming no model's speed column is
    /// refused with every model's column in the message.
    #[test]
    fn the_registry_names_the_model_of_a_csv() {
        for kind in <ModelKind as clap::ValueEnum>::value_variants() {
            let described = kind.with(DescribeCsv);
            let mut header = vec!["frame".to_owned(), "time_s".to_owned()];
            header.extend(described.columns.iter().map(|c| (*c).to_owned()));
            let (model, speed) = csv_model(&header).unwrap();
            assert_eq!(model.title, described.title);
            assert_eq!(header[speed], described.speed_column);
        }
        let header: Vec<String> = ["frame", "time_s", "x"].map(str::to_owned).to_vec();
        let Err(message) = csv_model(&header) else {
            panic!("a header without a speed column was accepted")
        };
        assert_eq!(
            message,
            "no `airspeed` (Palmer) or `speed` (Bourg) column: not a CSV written by sim-cli --csv"
        );
    }

    #[test]
    fn bad_csv_is_a_usage_error_naming_the_line() {
        let err = trace_from_csv("a,b\n1,2\n".as_bytes(), "x.csv").unwrap_err();
        assert_eq!(err.exit_code(), 2);
        assert!(
            err.to_string().starts_with("x.csv:1: no `frame` column"),
            "{err}"
        );
        let csv = "frame,time_s,x,y,z,vz,roll_deg,pitch_deg,speed\n0,0,0,0,0,0,0,0,oops\n";
        let err = trace_from_csv(csv.as_bytes(), "x.csv").unwrap_err();
        assert_eq!(err.to_string(), "x.csv:2: `oops` is not a number");
        let err = trace_from_csv("".as_bytes(), "x.csv").unwrap_err();
        assert_eq!(err.to_string(), "x.csv: empty CSV file");
    }

    const PALMER_HEADER: &str =
        "frame,time_s,x,y,z,vx,vy,vz,roll_deg,pitch_deg,fg_heading_deg,airspeed\n";

    #[test]
    fn non_finite_values_are_refused_with_their_line() {
        for bad in ["NaN", "inf", "-inf", "1e999"] {
            let csv =
                format!("{PALMER_HEADER}0,0,0,0,0,0,0,0,0,0,0,0\n1,0.1,{bad},0,0,0,0,0,0,0,0,0\n");
            let err = trace_from_csv(csv.as_bytes(), "x.csv").unwrap_err();
            assert_eq!(err.exit_code(), 2);
            assert!(
                err.to_string()
                    .starts_with(&format!("x.csv:3: `{bad}` is not a finite number")),
                "{err}"
            );
        }
    }

    #[test]
    fn a_torn_last_row_is_left_out_with_a_warning() {
        let csv =
            format!("{PALMER_HEADER}0,0,0,0,0,0,0,0,0,0,0,0\n1,0.1,1,0,1,1,0,0,0,0,0,1\n2,0.2,2,0");
        let read = trace_from_csv(csv.as_bytes(), "x.csv").unwrap();
        assert_eq!(read.trace.samples.len(), 2);
        let warning = read.torn_last_row.unwrap();
        assert!(
            warning.starts_with("x.csv:4: the last row is incomplete"),
            "{warning}"
        );
        assert!(warning.ends_with("plotted up to line 3"), "{warning}");
        // A complete file has no warning.
        let whole = format!("{PALMER_HEADER}0,0,0,0,0,0,0,0,0,0,0,0\n");
        assert_eq!(
            trace_from_csv(whole.as_bytes(), "x.csv")
                .unwrap()
                .torn_last_row,
            None
        );
    }

    #[test]
    fn an_endless_line_is_refused_at_the_line_limit() {
        let endless = std::io::repeat(b'1');
        let err = trace_from_csv(std::io::BufReader::new(endless), "x.csv").unwrap_err();
        assert!(
            err.to_string()
                .starts_with("x.csv:1: a line longer than 64 KiB"),
            "{err}"
        );
    }
}
