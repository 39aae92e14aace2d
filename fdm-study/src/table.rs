//! The per-run table: one row per run ([`RunTable`]: its status
//! ([`RunStatus`]), frames and measures), and on disk as `runs.csv`.

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
/// run, one column per measure. A measure that does not apply to a run (no
/// touchdown, target height never reached, a refused start) is `None`:
/// never NaN.
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
}

impl RunTable {
    /// An empty table with the columns of `measures`.
    #[must_use]
    pub fn empty(measures: &[Measure]) -> Self {
        Self {
            measures: measures
                .iter()
                .map(|m| (m.name().to_owned(), Vec::new()))
                .collect(),
            ..Self::default()
        }
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
    /// [`StudyError::Columns`] when the two tables' measure columns differ.
    pub fn append(&mut self, other: RunTable) -> Result<(), StudyError> {
        let names = |t: &RunTable| {
            t.measures
                .iter()
                .map(|(n, _)| n.clone())
                .collect::<Vec<_>>()
        };
        if names(self) != names(&other) {
            return Err(StudyError::Columns {
                have: names(self),
                other: names(&other),
            });
        }
        self.run.extend(other.run);
        self.status.extend(other.status);
        self.frames.extend(other.frames);
        for ((_, mine), (_, theirs)) in self.measures.iter_mut().zip(other.measures) {
            mine.extend(theirs);
        }
        Ok(())
    }

    pub(crate) fn push(
        &mut self,
        run: u64,
        status: RunStatus,
        frames: u64,
        tracker: Option<&Tracker>,
        measures: &[Measure],
    ) {
        self.run.push(run);
        self.status.push(status);
        self.frames.push(frames);
        for ((_, column), measure) in self.measures.iter_mut().zip(measures) {
            column.push(tracker.and_then(|t| t.value(*measure)));
        }
    }
}

/// Writes the header of `runs.csv`: `run,status,` then the measures' names.
///
/// # Errors
/// The writer's.
pub fn write_csv_header(out: &mut impl Write, measure_names: &[String]) -> io::Result<()> {
    write!(out, "run,status")?;
    for name in measure_names {
        write!(out, ",{name}")?;
    }
    writeln!(out)
}

/// Writes `table`'s rows as `runs.csv` rows: the run, the status code, then
/// each measure as the shortest decimal that reads back to the same `f64`
/// (so the text is the bits), or an empty cell where the measure does not
/// apply.
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
        writeln!(out)?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use fdm_core::model::FlightStatus;

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
        };
        let mut out = Vec::new();
        write_csv_header(&mut out, &["a".to_owned()]).unwrap();
        write_csv_rows(&mut out, &table).unwrap();
        let text = String::from_utf8(out).unwrap();
        assert_eq!(
            text,
            "run,status,a\n3,airborne,0.30000000000000004\n4,start_refused,\n"
        );
        let back: f64 = "0.30000000000000004".parse().unwrap();
        assert_eq!(back.to_bits(), (0.1f64 + 0.2).to_bits());
    }
}
