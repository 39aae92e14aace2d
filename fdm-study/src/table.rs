//! The per-run table on disk: `runs.csv`.

use std::io::{self, Write};

use crate::fly::RunTable;

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
    use crate::fly::RunStatus;
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
