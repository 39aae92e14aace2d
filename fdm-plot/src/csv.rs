//! A flight CSV (`sim-cli --csv`, `afit_fdm.Flight.csv_to`; docs/cli.md,
//! "CSV output") read back into a plot's samples ([`read_trace`]): what
//! `sim-cli plot FILE.csv` draws.
//!
//! The CSV says which model wrote it: its first line is `# model: NAME`
//! ([`fdm_run::csv::MODEL_LINE_PREFIX`]), NAME the registry's name of the
//! model, so the model (its title, speed column and unit) is looked up by
//! that name among the models the reader knows ([`CsvLayout`]: the run
//! library's registry for [`read_trace`], the caller's for
//! [`read_trace_among`]), not guessed. A model line naming no model, or
//! a model the reader does not know, is refused ([`LineProblem::NoModelName`],
//! [`LineProblem::UnknownModel`]).
//!
//! The legacy path: files written before the model line (and hand-made
//! ones) start with the header. Their model is the one whose CSV header
//! ([`fdm_run::csv::FlightRow::columns`]) the file has, or else the first
//! (in registry order) whose speed column ([`CsvModel::CSV_SPEED_COLUMN`])
//! it has. The status is the CSV's `status` column
//! ([`DisplayStatus::from_number`]) or, in older files without it, is
//! recomputed row by row with [`FlightStatus::update`] from the height and
//! the climb rate exactly as the simulation computed it. After a reset (a
//! row whose time goes back) the plot's time axis continues
//! ([`TraceBuilder`]). Memory stays bounded whatever the file's size; the
//! plot of a two-hour run at 100 fps is a few hundred kilobytes.

use std::fmt;
use std::io::{BufRead, Read as _};

use fdm_core::model::{DisplayStatus, FlightStatus, Model};
use fdm_core::script::Echo;
use fdm_run::csv::{CsvModel, FlightRow, MODEL_LINE_PREFIX};
use fdm_run::model::{with_model, ModelJob, MODELS};

use crate::flight::{PlotSample, Trace, TraceBuilder};

/// Columns [`read_trace`] reads, besides the model's speed column.
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

/// Largest CSV [`read_trace`] reads: 8 GiB, some 25 million rows (a day at
/// 300 fps). Memory stays bounded whatever the size ([`TraceBuilder`]).
pub const MAX_CSV_BYTES: u64 = 8 << 30;

/// Longest CSV line accepted: 64 KiB (a row of `--csv` is a few hundred bytes).
pub const MAX_CSV_LINE_BYTES: u64 = 64 * 1024;

/// Characters of a bad field shown in messages.
const FIELD_CHARS: usize = 40;

/// A CSV read back by [`read_trace`].
#[derive(Debug, Clone, PartialEq)]
pub struct CsvTrace {
    /// The flight, ready to draw.
    pub trace: Trace,
    /// Set when the last row was torn (the file does not end with a newline,
    /// as when the writing run was killed mid-row): what was left out.
    pub torn_last_row: Option<String>,
}

/// What is wrong with one line of a CSV ([`CsvReadError::Line`]).
#[derive(Debug, Clone, PartialEq)]
pub enum LineProblem {
    /// The line is longer than [`MAX_CSV_LINE_BYTES`].
    TooLong,
    /// The header is not UTF-8.
    HeaderNotUtf8,
    /// A row is not UTF-8.
    NotUtf8,
    /// The header lacks a column every flight CSV has (or the speed column
    /// of the model its model line names).
    MissingColumn(&'static str),
    /// A first line starting with `#` that is not `# model: NAME`
    /// (the line, escaped and cut short).
    NoModelName(String),
    /// The model line names a model the reader does not know: the name
    /// (escaped and cut short) and the known models' names.
    UnknownModel {
        /// The name on the model line.
        name: String,
        /// The models the reader knows, e.g. `palmer, bourg`.
        known: String,
    },
    /// The header has no model's speed column: each model's column and
    /// name, e.g. ``"`airspeed` (Palmer) or `speed` (Bourg)"``.
    NoModel(String),
    /// A field that is not a number (escaped and cut short).
    NotANumber(String),
    /// A field that is not a finite number (escaped and cut short).
    NotFinite(String),
    /// A row whose field count is not the header's.
    Width {
        /// Fields in the row.
        fields: usize,
        /// Columns in the header.
        header: usize,
    },
    /// A `status` value that is no display status's number.
    NotAStatus(f64),
}

impl fmt::Display for LineProblem {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        const NOT_OURS: &str = "not a CSV written by sim-cli --csv";
        match self {
            Self::TooLong => write!(
                f,
                "a line longer than {} KiB: {NOT_OURS}",
                MAX_CSV_LINE_BYTES / 1024
            ),
            Self::HeaderNotUtf8 => write!(f, "not UTF-8 text: {NOT_OURS}"),
            Self::NotUtf8 => write!(f, "not UTF-8 text"),
            Self::MissingColumn(column) => write!(f, "no `{column}` column: {NOT_OURS}"),
            Self::NoModelName(line) => write!(
                f,
                "`{line}` is not a model line `{MODEL_LINE_PREFIX}NAME`: {NOT_OURS}"
            ),
            Self::UnknownModel { name, known } => write!(
                f,
                "written by model `{name}`, which this reader does not know ({known})"
            ),
            Self::NoModel(columns) => write!(f, "no {columns} column: {NOT_OURS}"),
            Self::NotANumber(field) => write!(f, "`{field}` is not a number"),
            Self::NotFinite(field) => write!(
                f,
                "`{field}` is not a finite number (sim-cli --csv never writes one)"
            ),
            Self::Width { fields, header } => {
                write!(f, "{fields} fields, the header has {header}")
            }
            Self::NotAStatus(value) => write!(f, "`{value}` is not a status number"),
        }
    }
}

/// Why a CSV was not read: every case is the input's fault.
#[derive(Debug, thiserror::Error)]
pub enum CsvReadError {
    /// Reading failed.
    #[error("cannot read {name}: {source}")]
    Read {
        /// The input's name.
        name: String,
        /// What the OS said.
        source: std::io::Error,
    },
    /// The input is larger than [`MAX_CSV_BYTES`].
    #[error("{name} is larger than the {} GiB limit", MAX_CSV_BYTES >> 30)]
    TooLarge {
        /// The input's name.
        name: String,
    },
    /// The input is empty.
    #[error("{name}: empty CSV file")]
    Empty {
        /// The input's name.
        name: String,
    },
    /// The input has a header but no data row.
    #[error("{name}: no data rows to plot")]
    NoRows {
        /// The input's name.
        name: String,
    },
    /// A line is not what a flight CSV holds.
    #[error("{name}:{line}: {problem}")]
    Line {
        /// The input's name.
        name: String,
        /// The line's number, from 1.
        line: usize,
        /// What is wrong with it.
        problem: LineProblem,
    },
}

/// Reads one line of at most [`MAX_CSV_LINE_BYTES`] into `line` (cleared
/// first); `Ok(false)` at the end of the input. The newline is kept.
fn read_csv_line(
    reader: &mut impl BufRead,
    line: &mut Vec<u8>,
    name: &str,
    line_no: usize,
    read_total: &mut u64,
) -> Result<bool, CsvReadError> {
    line.clear();
    let n = reader
        .by_ref()
        .take(MAX_CSV_LINE_BYTES + 1)
        .read_until(b'\n', line)
        .map_err(|source| CsvReadError::Read {
            name: name.to_owned(),
            source,
        })?;
    if u64::try_from(line.len()).unwrap_or(u64::MAX) > MAX_CSV_LINE_BYTES {
        return Err(CsvReadError::Line {
            name: name.to_owned(),
            line: line_no,
            problem: LineProblem::TooLong,
        });
    }
    *read_total += u64::try_from(n).unwrap_or(u64::MAX);
    if *read_total > MAX_CSV_BYTES {
        return Err(CsvReadError::TooLarge {
            name: name.to_owned(),
        });
    }
    Ok(n > 0)
}

/// What [`read_trace_among`] knows of one model's CSV: made from the model
/// type by [`CsvLayout::of`], so that a program with models of its own (such
/// as `sim-cli`'s registry) can read their CSVs.
#[derive(Debug, Clone, PartialEq)]
pub struct CsvLayout {
    /// The registry's name of the model ([`Model::NAME`]), as the CSV's
    /// model line gives it.
    name: &'static str,
    /// The model's title ([`Model::TITLE`]).
    title: &'static str,
    /// Its name as the error message shows it: `Palmer`, `Bourg`.
    shown: String,
    /// The columns its CSV files have after `frame,time_s`.
    columns: Vec<&'static str>,
    /// [`CsvModel::CSV_SPEED_COLUMN`].
    speed_column: &'static str,
    /// [`CsvModel::METRES_PER_UNIT`].
    metres_per_unit: f64,
}

impl CsvLayout {
    /// Model `M`'s CSV layout.
    #[must_use]
    pub fn of<M: CsvModel>() -> Self {
        let name = <M as Model>::NAME;
        let mut shown = name.get(..1).unwrap_or_default().to_ascii_uppercase();
        shown.push_str(name.get(1..).unwrap_or_default());
        Self {
            name,
            title: M::TITLE,
            shown,
            columns: FlightRow::<M>::columns(),
            speed_column: M::CSV_SPEED_COLUMN,
            metres_per_unit: M::METRES_PER_UNIT,
        }
    }

    /// The model's registry name ([`Model::NAME`]).
    #[must_use]
    pub fn name(&self) -> &'static str {
        self.name
    }
}

struct DescribeCsv;

impl ModelJob for DescribeCsv {
    type Output = CsvLayout;
    fn call<M: CsvModel>(self) -> CsvLayout {
        CsvLayout::of::<M>()
    }
}

/// The CSV layouts of the run library's registry ([`MODELS`]), in registry
/// order: the models [`read_trace`] knows.
#[must_use]
pub fn layouts() -> Vec<CsvLayout> {
    MODELS
        .iter()
        .filter_map(|name| with_model(name, DescribeCsv))
        .collect()
}

/// The model named `name` by a CSV's model line, among `models`, and its
/// speed column's index in `header`.
fn named_model<'m>(
    name: &str,
    header: &[String],
    models: &'m [CsvLayout],
) -> Result<(&'m CsvLayout, usize), LineProblem> {
    let model =
        models
            .iter()
            .find(|m| m.name == name)
            .ok_or_else(|| LineProblem::UnknownModel {
                name: Echo::new(name, FIELD_CHARS).to_string(),
                known: models.iter().map(|m| m.name).collect::<Vec<_>>().join(", "),
            })?;
    let speed = header
        .iter()
        .position(|c| c == model.speed_column)
        .ok_or(LineProblem::MissingColumn(model.speed_column))?;
    Ok((model, speed))
}

/// The legacy path, for a CSV without a model line: the model that wrote a
/// CSV with this `header`, and its speed column's index: the model whose CSV
/// header it is, or for older and hand-made files the first (in `models`'
/// order) whose speed column it has.
fn csv_model<'m>(
    header: &[String],
    models: &'m [CsvLayout],
) -> Result<(&'m CsvLayout, usize), LineProblem> {
    let column = |wanted: &str| header.iter().position(|c| c == wanted);
    let written_by =
        |m: &CsvLayout| header.len() == m.columns.len() + 2 && header[2..] == m.columns;
    let found = match models.iter().position(written_by) {
        Some(i) => Some(i),
        None => models.iter().position(|m| column(m.speed_column).is_some()),
    };
    let Some(i) = found else {
        let columns = models
            .iter()
            .map(|m| format!("`{}` ({})", m.speed_column, m.shown))
            .collect::<Vec<_>>()
            .join(" or ");
        return Err(LineProblem::NoModel(columns));
    };
    let model = &models[i];
    let speed = column(model.speed_column).ok_or(LineProblem::MissingColumn(model.speed_column))?;
    Ok((model, speed))
}

/// Reads a flight CSV back into a [`Trace`] titled `<model> from <name>`,
/// line by line in bounded memory ([`TraceBuilder`], [`MAX_CSV_LINE_BYTES`],
/// [`MAX_CSV_BYTES`]); `name` names the input in the title and in errors.
/// The models it knows are the run library's registry ([`layouts`]);
/// [`read_trace_among`] reads with a caller's list.
///
/// # Errors
/// As [`read_trace_among`].
pub fn read_trace(reader: impl BufRead, name: &str) -> Result<CsvTrace, CsvReadError> {
    read_trace_among(reader, name, &layouts())
}

/// Reads a flight CSV written by one of `models` back into a [`Trace`]
/// titled `<model> from <name>`, line by line in bounded memory
/// ([`TraceBuilder`], [`MAX_CSV_LINE_BYTES`], [`MAX_CSV_BYTES`]); `name`
/// names the input in the title and in errors.
///
/// The model is the one the first line names, `# model: NAME`
/// ([`MODEL_LINE_PREFIX`]), and the header is the second line. The legacy
/// path: a file without the model line (written before it, or by hand)
/// starts with the header, and its model is the one whose CSV header it is,
/// or else the first whose speed column it has
/// ([`CsvModel::CSV_SPEED_COLUMN`]: Palmer's `airspeed` in m/s with
/// positions in metres, Bourg's `speed` in ft/s with positions in feet).
/// The status is the `status` column when there is one
/// ([`DisplayStatus::from_number`]); in older files without it, it is
/// recomputed from the rows: [`FlightStatus::initial`] at every frame 0 and
/// [`FlightStatus::update`] after every other row, from the height and the
/// climb rate in metres, as the simulation did before the ground contact;
/// Bourg's `stalling` column gives the stall.
///
/// A last row without its newline is a torn row (the writing run was killed
/// mid-row): it is left out and reported in [`CsvTrace::torn_last_row`].
///
/// # Errors
/// [`CsvReadError`] naming `name` (and the line) for anything that is not
/// such a CSV, including a first line `#...` that is not a model line
/// ([`LineProblem::NoModelName`]), a model not among `models`
/// ([`LineProblem::UnknownModel`]) and a value that is not a finite number.
pub fn read_trace_among(
    mut reader: impl BufRead,
    name: &str,
    models: &[CsvLayout],
) -> Result<CsvTrace, CsvReadError> {
    let bad = |line: usize, problem: LineProblem| CsvReadError::Line {
        name: name.to_owned(),
        line,
        problem,
    };
    let mut buffer = Vec::new();
    let mut read_total = 0u64;
    if !read_csv_line(&mut reader, &mut buffer, name, 1, &mut read_total)? {
        return Err(CsvReadError::Empty {
            name: name.to_owned(),
        });
    }
    // The model line, when there is one; the header is the next line.
    let mut model_name = None;
    let mut header_no = 1;
    if buffer.first() == Some(&b'#') {
        let text = std::str::from_utf8(&buffer).map_err(|_| bad(1, LineProblem::HeaderNotUtf8))?;
        let text = text.trim_end_matches(['\n', '\r']);
        let named = text
            .strip_prefix(MODEL_LINE_PREFIX)
            .map(str::trim)
            .filter(|n| !n.is_empty())
            .ok_or_else(|| {
                bad(
                    1,
                    LineProblem::NoModelName(Echo::new(text, FIELD_CHARS).to_string()),
                )
            })?;
        model_name = Some(named.to_owned());
        header_no = 2;
        if !read_csv_line(&mut reader, &mut buffer, name, 2, &mut read_total)? {
            return Err(CsvReadError::Line {
                name: name.to_owned(),
                line: 2,
                problem: LineProblem::MissingColumn("frame"),
            });
        }
    }
    let header_text =
        std::str::from_utf8(&buffer).map_err(|_| bad(header_no, LineProblem::HeaderNotUtf8))?;
    let header: Vec<String> = header_text
        .trim_end_matches(['\n', '\r'])
        .split(',')
        .map(str::to_owned)
        .collect();
    let column = |wanted: &str| header.iter().position(|c| c == wanted);
    let mut index = [0usize; CSV_NEEDED.len()];
    for (slot, wanted) in index.iter_mut().zip(CSV_NEEDED) {
        *slot = column(wanted).ok_or_else(|| bad(header_no, LineProblem::MissingColumn(wanted)))?;
    }
    let [frame_i, time_i, x_i, y_i, z_i, vz_i, roll_i, pitch_i] = index;
    let heading_i = column("fg_heading_deg");
    let (model, speed_i) = match &model_name {
        Some(named) => named_model(named, &header, models),
        None => csv_model(&header, models),
    }
    .map_err(|problem| match problem {
        LineProblem::UnknownModel { .. } => bad(1, problem),
        _ => bad(header_no, problem),
    })?;
    let (scale, model) = (model.metres_per_unit, model.title);
    let stall_i = column("stalling");
    let status_i = column("status");
    let mut builder = TraceBuilder::new(format!("{model} from {name}"));
    let mut status = FlightStatus::OnGround;
    let mut values = Vec::with_capacity(header.len());
    let mut torn_last_row = None;
    let mut line_no = header_no;
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
            .map_err(|_| bad(line_no, LineProblem::NotUtf8))?
            .trim_end_matches(['\n', '\r']);
        if line.is_empty() {
            continue;
        }
        values.clear();
        for field in line.split(',') {
            let shown = || Echo::new(field, FIELD_CHARS).to_string();
            let value = field
                .trim()
                .parse::<f64>()
                .map_err(|_| bad(line_no, LineProblem::NotANumber(shown())))?;
            if !value.is_finite() {
                return Err(bad(line_no, LineProblem::NotFinite(shown())));
            }
            values.push(value);
        }
        if values.len() != header.len() {
            return Err(bad(
                line_no,
                LineProblem::Width {
                    fields: values.len(),
                    header: header.len(),
                },
            ));
        }
        let height_m = values[z_i] * scale;
        let recorded = status_i.map(|i| {
            DisplayStatus::from_number(values[i])
                .ok_or_else(|| bad(line_no, LineProblem::NotAStatus(values[i])))
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
        return Err(CsvReadError::NoRows {
            name: name.to_owned(),
        });
    }
    Ok(CsvTrace {
        trace,
        torn_last_row,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::flight::segments;
    use fdm_core::model::LandingState;

    #[test]
    fn csv_status_is_recomputed_like_the_simulation() {
        // Palmer-like columns; climbs, then comes down at -6 m/s: a crash.
        let csv = "frame,time_s,x,y,z,vx,vy,vz,roll_deg,pitch_deg,fg_heading_deg,airspeed\n\
                   0,0,0,0,0,0,0,0,0,0,0,0\n\
                   1,0.1,1,0,1,10,0,2,0,5,0,10\n\
                   2,0.2,2,-1,-0.5,10,0,-6,0,-5,0,12\n\
                   0,0,0,0,0,0,0,0,0,0,0,0\n";
        let t = read_trace(csv.as_bytes(), "t.csv").unwrap().trace;
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

    /// Every registered model's CSV header is recognised as that model,
    /// with its speed column; a header naming no model's speed column is
    /// refused with every model's column in the message.
    #[test]
    fn the_registry_names_the_model_of_a_csv() {
        let all = layouts();
        assert_eq!(all.len(), MODELS.len());
        for described in &all {
            let mut header = vec!["frame".to_owned(), "time_s".to_owned()];
            header.extend(described.columns.iter().map(|c| (*c).to_owned()));
            let (model, speed) = csv_model(&header, &all).unwrap();
            assert_eq!(model.title, described.title);
            assert_eq!(header[speed], described.speed_column);
        }
        let header: Vec<String> = ["frame", "time_s", "x"].map(str::to_owned).to_vec();
        let Err(problem) = csv_model(&header, &all) else {
            panic!("a header without a speed column was accepted")
        };
        assert_eq!(
            problem.to_string(),
            "no `airspeed` (Palmer) or `speed` (Bourg) column: not a CSV written by sim-cli --csv"
        );
    }

    /// A CSV as written today (by the run library's writer: the model line,
    /// then the header) is read as the model its first line names, even
    /// when its columns would make the legacy path take another model;
    /// the same rows without the model line (a legacy file) are still read.
    #[test]
    fn the_model_line_names_the_model() {
        use fdm_run::csv::{CsvOutput, CsvWriter};
        use fdm_run::{Run, Scenario, SharedOutput, Start};
        fn written<M: CsvModel>() -> String {
            let mut run = Run::new(Scenario::<M>::new(Start::thesis(), 30, 3).unwrap()).unwrap();
            let csv = SharedOutput::new(CsvOutput::new(
                CsvWriter::new(Vec::new(), "mem"),
                FlightRow::<M>::of,
            ));
            run.attach(csv.clone()).unwrap();
            run.run_to_end().unwrap();
            run.finish().unwrap();
            String::from_utf8(csv.take().unwrap().into_inner().finish().unwrap()).unwrap()
        }
        for (text, model) in [
            (written::<fdm_core::palmer::Palmer>(), "palmer"),
            (written::<fdm_core::bourg::Bourg>(), "bourg"),
        ] {
            let first = text.lines().next().unwrap();
            assert_eq!(first, format!("# model: {model}"));
            let read = read_trace(text.as_bytes(), "f.csv").unwrap();
            assert_eq!(read.trace.samples.len(), 4, "{model}");
            let legacy = text.split_once('\n').unwrap().1;
            assert_eq!(read_trace(legacy.as_bytes(), "f.csv").unwrap(), read);
        }
        // Bourg's name over a file that has both speed columns: Bourg's
        // (feet), where the legacy path takes Palmer's (the first).
        let both = "frame,time_s,x,y,z,vx,vy,vz,roll_deg,pitch_deg,airspeed,speed\n\
                    0,0,0,0,10,0,0,0,0,0,50,100\n";
        let legacy = read_trace(both.as_bytes(), "b.csv").unwrap().trace;
        assert_eq!(legacy.title, "Palmer Cessna 172 from b.csv");
        assert_eq!(legacy.samples[0].height_m, 10.0);
        let named = format!("# model: bourg\n{both}");
        let named = read_trace(named.as_bytes(), "b.csv").unwrap().trace;
        assert!(named.title.starts_with("Bourg"), "{}", named.title);
        assert_eq!(named.samples[0].height_m, 10.0 * 0.3048);
        assert_eq!(named.samples[0].airspeed_mps, 100.0 * 0.3048);
    }

    /// A model line naming no model or a model the reader does not know,
    /// or a comment line that is not a model line, is refused with a typed
    /// error naming the file and line 1; a named model whose speed column
    /// the header lacks is refused at the header, line 2.
    #[test]
    fn a_bad_model_line_is_refused() {
        let rows = format!("{PALMER_HEADER}0,0,0,0,0,0,0,0,0,0,0,0\n");
        let err = read_trace(format!("# model: cessna\n{rows}").as_bytes(), "m.csv").unwrap_err();
        assert!(
            matches!(
                &err,
                CsvReadError::Line {
                    line: 1,
                    problem: LineProblem::UnknownModel { .. },
                    ..
                }
            ),
            "{err:?}"
        );
        assert_eq!(
            err.to_string(),
            "m.csv:1: written by model `cessna`, which this reader does not know (palmer, bourg)"
        );
        for line in ["# model:", "# model:   ", "# a comment", "#"] {
            let err = read_trace(format!("{line}\n{rows}").as_bytes(), "m.csv").unwrap_err();
            assert!(
                matches!(
                    &err,
                    CsvReadError::Line {
                        line: 1,
                        problem: LineProblem::NoModelName(_),
                        ..
                    }
                ),
                "{line}: {err:?}"
            );
            assert!(
                err.to_string().starts_with("m.csv:1: `#")
                    && err
                        .to_string()
                        .contains("is not a model line `# model: NAME`"),
                "{err}"
            );
        }
        let err = read_trace(format!("# model: bourg\n{rows}").as_bytes(), "m.csv").unwrap_err();
        assert_eq!(
            err.to_string(),
            "m.csv:2: no `speed` column: not a CSV written by sim-cli --csv"
        );
        // Only the registry's models are known by `read_trace`; a caller's
        // list may have fewer.
        let palmer_only = [CsvLayout::of::<fdm_core::palmer::Palmer>()];
        let err = read_trace_among(
            format!("# model: bourg\n{rows}").as_bytes(),
            "m.csv",
            &palmer_only,
        )
        .unwrap_err();
        assert_eq!(
            err.to_string(),
            "m.csv:1: written by model `bourg`, which this reader does not know (palmer)"
        );
        let ok = read_trace_among(
            format!("# model: palmer\n{rows}").as_bytes(),
            "m.csv",
            &palmer_only,
        );
        assert_eq!(ok.unwrap().trace.samples.len(), 1);
        // A model line and nothing else.
        let err = read_trace("# model: palmer\n".as_bytes(), "m.csv").unwrap_err();
        assert!(
            err.to_string().starts_with("m.csv:2: no `frame` column"),
            "{err}"
        );
    }

    #[test]
    fn bad_csv_is_refused_naming_the_line() {
        let err = read_trace("a,b\n1,2\n".as_bytes(), "x.csv").unwrap_err();
        assert!(matches!(err, CsvReadError::Line { line: 1, .. }), "{err:?}");
        assert!(
            err.to_string().starts_with("x.csv:1: no `frame` column"),
            "{err}"
        );
        let csv = "frame,time_s,x,y,z,vz,roll_deg,pitch_deg,speed\n0,0,0,0,0,0,0,0,oops\n";
        let err = read_trace(csv.as_bytes(), "x.csv").unwrap_err();
        assert_eq!(err.to_string(), "x.csv:2: `oops` is not a number");
        let err = read_trace("".as_bytes(), "x.csv").unwrap_err();
        assert_eq!(err.to_string(), "x.csv: empty CSV file");
    }

    const PALMER_HEADER: &str =
        "frame,time_s,x,y,z,vx,vy,vz,roll_deg,pitch_deg,fg_heading_deg,airspeed\n";

    #[test]
    fn non_finite_values_are_refused_with_their_line() {
        for bad in ["NaN", "inf", "-inf", "1e999"] {
            let csv =
                format!("{PALMER_HEADER}0,0,0,0,0,0,0,0,0,0,0,0\n1,0.1,{bad},0,0,0,0,0,0,0,0,0\n");
            let err = read_trace(csv.as_bytes(), "x.csv").unwrap_err();
            assert!(matches!(err, CsvReadError::Line { line: 3, .. }), "{err:?}");
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
        let read = read_trace(csv.as_bytes(), "x.csv").unwrap();
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
            read_trace(whole.as_bytes(), "x.csv").unwrap().torn_last_row,
            None
        );
    }

    #[test]
    fn an_endless_line_is_refused_at_the_line_limit() {
        let endless = std::io::repeat(b'1');
        let err = read_trace(std::io::BufReader::new(endless), "x.csv").unwrap_err();
        assert!(
            err.to_string()
                .starts_with("x.csv:1: a line longer than 64 KiB"),
            "{err}"
        );
    }
}
