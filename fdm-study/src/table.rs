//! The per-run table: one row per run ([`RunTable`]: its status
//! ([`RunStatus`]), frames, measures, drawn inputs and the fingerprint of
//! its final state), and on disk as `runs.csv`.

use std::io::{self, Write};

use fdm_core::model::FlightStatus;
use serde::Serialize;

use crate::measure::{Measure, Tracker};
use crate::StudyError;

/// How a run ended: its flight status at its last frame, or a start the
/// model refused (e.g. a dispersed speed that cannot be trimmed).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize)]
#[serde(into = "&'static str")]
pub enum RunStatus {
    /// The flight status at the run's last frame.
    Flown(FlightStatus),
    /// The run's start was refused; it was not flown and has no measures.
    StartRefused,
}

impl RunStatus {
    /// Every status code, in the order summaries list them.
    pub const CODES: &'static [&'static str] = &[
        "on_ground",
        "airborne",
        "landed_safe",
        "landed_rough",
        "crashed",
        "diverged",
        "start_refused",
    ];

    /// The status as one word: [`FlightStatus::code`] (`on_ground`,
    /// `airborne`, `landed_safe`, `landed_rough`, `crashed`, `diverged`) or
    /// `start_refused`.
    #[must_use]
    pub const fn code(self) -> &'static str {
        match self {
            Self::Flown(status) => status.code(),
            Self::StartRefused => "start_refused",
        }
    }
}

impl From<RunStatus> for &'static str {
    fn from(status: RunStatus) -> Self {
        status.code()
    }
}

/// The per-run results of some runs of a study, in run order: one row per
/// run, one column per measure, then one column per dispersion (the value
/// the run drew) and the fingerprint of the run's final state. A measure
/// that does not apply to a run (no touchdown, target height never reached,
/// a refused start) is `None`: never NaN.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct RunTable {
    /// The run indices.
    pub run: Vec<u64>,
    /// How each run ended.
    pub status: Vec<RunStatus>,
    /// Frames each run flew (the duration, or up to its stop condition).
    pub frames: Vec<u64>,
    /// Per measure, in the study's order: its name and one value per run.
    pub measures: Vec<(String, Vec<Option<f64>>)>,
    /// Per dispersion, in the study file's order: the column's name
    /// ([`input_column_name`]: `input.` and the dispersion's key) and the
    /// value drawn for each run, the very `f64` the study handed to the
    /// model (also for a refused start, whose draws are often the reason).
    pub inputs: Vec<(String, Vec<f64>)>,
    /// Per run: the fingerprint of its final state (the state at its last
    /// frame, [`fdm_run::RunModel::state_fingerprint`], what a recording of
    /// the run carries); `None` for a refused start.
    pub fingerprint: Vec<Option<u64>>,
}

/// The column name of the input drawn by the dispersion of study-file key
/// `key`: `input.` then the key as written in the file, e.g.
/// `input.initial.speed_kt`, `input.aircraft.mass_kg`,
/// `input.script_delay_s`. The keys carry their units (`_kt`, `_kg`, `_s`,
/// ...); a key without one is dimensionless (`controls.throttle`, a
/// fraction; `aircraft.mass_scale`, a factor).
#[must_use]
pub fn input_column_name(key: &str) -> String {
    format!("input.{key}")
}

/// The fingerprint as `runs.csv` and `runs.arrow` write it: `0x` and 16
/// lowercase hex digits, as `summary.json`'s `maths` and `sim-cli replay`'s
/// messages.
#[must_use]
pub fn fingerprint_text(fingerprint: u64) -> String {
    format!("{fingerprint:#018x}")
}

impl RunTable {
    /// An empty table with the columns of `measures` and no input column.
    #[must_use]
    pub fn empty(measures: &[Measure]) -> Self {
        Self::empty_with_inputs(measures, &[])
    }

    /// An empty table with the columns of `measures` and the input columns
    /// `input_names` (e.g. [`crate::Study::input_names`]).
    #[must_use]
    pub fn empty_with_inputs(measures: &[Measure], input_names: &[String]) -> Self {
        Self {
            measures: measures
                .iter()
                .map(|m| (m.name().to_owned(), Vec::new()))
                .collect(),
            inputs: input_names
                .iter()
                .map(|n| (n.clone(), Vec::new()))
                .collect(),
            ..Self::default()
        }
    }

    /// The names of the value columns: the measures', then the inputs'.
    #[must_use]
    pub fn column_names(&self) -> Vec<String> {
        self.measures
            .iter()
            .map(|(n, _)| n.clone())
            .chain(self.inputs.iter().map(|(n, _)| n.clone()))
            .collect()
    }

    /// Number of rows.
    #[must_use]
    pub fn len(&self) -> usize {
        self.run.len()
    }

    /// Whether the table has no rows.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.run.is_empty()
    }

    /// Appends `other`'s rows after this table's.
    ///
    /// # Errors
    /// [`StudyError::Columns`] when the two tables' measure or input
    /// columns differ.
    pub fn append(&mut self, other: RunTable) -> Result<(), StudyError> {
        if self.column_names() != other.column_names() {
            return Err(StudyError::Columns {
                have: self.column_names(),
                other: other.column_names(),
            });
        }
        self.run.extend(other.run);
        self.status.extend(other.status);
        self.frames.extend(other.frames);
        for ((_, mine), (_, theirs)) in self.measures.iter_mut().zip(other.measures) {
            mine.extend(theirs);
        }
        for ((_, mine), (_, theirs)) in self.inputs.iter_mut().zip(other.inputs) {
            mine.extend(theirs);
        }
        self.fingerprint.extend(other.fingerprint);
        Ok(())
    }

    /// Appends one row: the measures (in `measures`' order) from its
    /// tracker (none without one), its drawn inputs in the table's input
    /// order, its final state's fingerprint.
    pub(crate) fn push(&mut self, row: Row<'_>, measures: &[Measure]) {
        self.run.push(row.run);
        self.status.push(row.status);
        self.frames.push(row.frames);
        for ((_, column), measure) in self.measures.iter_mut().zip(measures) {
            column.push(row.tracker.and_then(|t| t.value(*measure)));
        }
        for ((_, column), value) in self.inputs.iter_mut().zip(row.inputs) {
            column.push(*value);
        }
        self.fingerprint.push(row.fingerprint);
    }
}

/// One row of a [`RunTable`] as it is pushed.
pub(crate) struct Row<'a> {
    pub(crate) run: u64,
    pub(crate) status: RunStatus,
    pub(crate) frames: u64,
    pub(crate) tracker: Option<&'a Tracker>,
    pub(crate) inputs: &'a [f64],
    pub(crate) fingerprint: Option<u64>,
}

/// Writes the header of `runs.csv` for tables with `columns`' columns (an
/// empty table will do, e.g. [`crate::Study::empty_table`]): `run,status`,
/// the measures' names, the inputs' names, then `fingerprint`.
///
/// # Errors
/// The writer's.
pub fn write_csv_header(out: &mut impl Write, columns: &RunTable) -> io::Result<()> {
    write!(out, "run,status")?;
    for name in columns.column_names() {
        write!(out, ",{name}")?;
    }
    writeln!(out, ",fingerprint")
}

/// Writes `table` as a whole `runs.csv`: the header ([`write_csv_header`])
/// and the rows ([`write_csv_rows`]).
///
/// # Errors
/// The writer's.
pub fn write_csv(out: &mut impl Write, table: &RunTable) -> io::Result<()> {
    write_csv_header(out, table)?;
    write_csv_rows(out, table)
}

/// Writes `table`'s rows as `runs.csv` rows: the run, the status code, each
/// measure as the shortest decimal that reads back to the same `f64` (so
/// the text is the bits) or an empty cell where the measure does not apply,
/// each input the same way, then the fingerprint ([`fingerprint_text`]; an
/// empty cell for a refused start).
///
/// # Errors
/// The writer's.
pub fn write_csv_rows(out: &mut impl Write, table: &RunTable) -> io::Result<()> {
    for row in 0..table.len() {
        write!(out, "{},{}", table.run[row], table.status[row].code())?;
        for (_, column) in &table.measures {
            match column[row] {
                Some(v) => write!(out, ",{v:?}")?,
                None => write!(out, ",")?,
            }
        }
        for (_, column) in &table.inputs {
            write!(out, ",{:?}", column[row])?;
        }
        match table.fingerprint.get(row).copied().flatten() {
            Some(f) => writeln!(out, ",{}", fingerprint_text(f))?,
            None => writeln!(out, ",")?,
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use fdm_core::model::FlightStatus;

    /// Empty tables carry their columns' names; a status serialises as its
    /// code; `write_csv` is the header and the rows.
    #[test]
    fn empty_tables_statuses_and_whole_files() {
        let measures = [Measure::MaxHeightM, Measure::FinalTimeS];
        let empty = RunTable::empty(&measures);
        assert_eq!(empty.column_names(), ["max_height_m", "final_time_s"]);
        assert!(empty.is_empty() && empty.inputs.is_empty());
        let inputs = [input_column_name("aircraft.mass_kg")];
        let with = RunTable::empty_with_inputs(&measures, &inputs);
        assert_eq!(
            with.column_names(),
            ["max_height_m", "final_time_s", "input.aircraft.mass_kg"]
        );
        for status in [
            RunStatus::Flown(FlightStatus::Landed(fdm_core::model::LandingState::Crash)),
            RunStatus::StartRefused,
        ] {
            let code: &str = status.into();
            assert_eq!(code, status.code());
            assert!(RunStatus::CODES.contains(&code));
        }
        let table = RunTable {
            run: vec![0],
            status: vec![RunStatus::StartRefused],
            frames: vec![0],
            measures: vec![("max_height_m".into(), vec![None])],
            inputs: vec![("input.aircraft.mass_kg".into(), vec![1000.5])],
            fingerprint: vec![None],
        };
        let mut out = Vec::new();
        write_csv(&mut out, &table).unwrap();
        assert_eq!(
            String::from_utf8(out).unwrap(),
            "run,status,max_height_m,input.aircraft.mass_kg,fingerprint\n0,start_refused,,1000.5,\n"
        );
    }

    #[test]
    fn rows_round_trip_and_leave_missing_cells_empty() {
        let table = RunTable {
            run: vec![3, 4],
            status: vec![
                RunStatus::Flown(FlightStatus::Airborne),
                RunStatus::StartRefused,
            ],
            frames: vec![9, 0],
            measures: vec![("a".into(), vec![Some(0.1 + 0.2), None])],
            inputs: vec![(input_column_name("controls.throttle"), vec![1e-7, 0.75])],
            fingerprint: vec![Some(0x0123_4567_89ab_cdef), None],
        };
        let mut out = Vec::new();
        write_csv_header(&mut out, &table).unwrap();
        write_csv_rows(&mut out, &table).unwrap();
        let text = String::from_utf8(out).unwrap();
        assert_eq!(
            text,
            "run,status,a,input.controls.throttle,fingerprint\n\
             3,airborne,0.30000000000000004,1e-7,0x0123456789abcdef\n\
             4,start_refused,,0.75,\n"
        );
        let back: f64 = "0.30000000000000004".parse().unwrap();
        assert_eq!(back.to_bits(), (0.1f64 + 0.2).to_bits());
        let back: f64 = "1e-7".parse().unwrap();
        assert_eq!(back.to_bits(), 1e-7f64.to_bits());
    }
}
