//! `--plot FILE.svg` on any `sim-cli palmer|bourg|replay` run and
//! `sim-cli plot FILE.csv -o FILE.svg` for a CSV written earlier with
//! `--csv`: the CLI's side of the plot. The drawing, the plot as an output
//! of a run and the CSV read back into samples are the library's
//! ([`fdm_plot`]: six panels, bounded memory, [`fdm_plot::PlotOutput`],
//! [`fdm_plot::csv::read_trace_among`], which takes the model the CSV's
//! first line names, `# model: NAME`, among the CLI's registry's models,
//! [`ModelKind::csv_layouts`]; files written before that line by their
//! header); here are the output file created before the run
//! ([`fdm_plot::PlotFile`], [`create`]), and the mapping of errors to exit statuses.

use std::path::Path;

use fdm_plot::csv::CsvReadError;
use fdm_plot::{PlotError, PlotFile};

use crate::error::CliError;
use crate::models::ModelKind;

impl From<PlotError> for CliError {
    /// Every plot failure happens after the input was accepted: a run-time
    /// error (exit status 1), e.g. `writing plot file NAME: REASON`.
    fn from(e: PlotError) -> Self {
        Self::Runtime(anyhow::Error::from(e))
    }
}

impl From<CsvReadError> for CliError {
    /// A CSV that cannot be read or is not a flight CSV is bad input: a
    /// usage error (exit status 2), e.g. `FILE:LINE: WHAT`.
    fn from(e: CsvReadError) -> Self {
        Self::usage(e)
    }
}

/// Creates the `--plot` output file before the run ([`PlotFile::create`]),
/// so that an unwritable path is a usage error (exit status 2) and nothing
/// has been simulated.
///
/// # Errors
/// [`CliError::Usage`] naming the path and the OS reason.
pub fn create(path: &Path) -> Result<PlotFile, CliError> {
    PlotFile::create(path)
        .map_err(|e| CliError::usage(format!("cannot create plot file {}: {e}", path.display())))
}

/// `sim-cli plot FILE.csv -o FILE.svg`: the CSV is read as scripts and
/// recordings are (a regular file or a pipe, nothing else), line by line.
///
/// # Errors
/// [`CliError::Usage`] for an unreadable or malformed CSV or an uncreatable
/// output; [`CliError::Runtime`] if drawing or writing fails.
pub fn run_plot(csv: &Path, output: &Path) -> Result<(), CliError> {
    // Until the SVG is created, a signal ends the process at once: a CSV
    // from a FIFO may wait for its writer (in `open`, where nothing looks
    // at a signal), and there is nothing to finish.
    let before_outputs = crate::signals::before_outputs();
    let file = fdm_run::input::open_input(csv, "CSV", crate::input::waiting)?;
    let name = csv.display().to_string();
    let models = ModelKind::csv_layouts();
    let read = fdm_plot::csv::read_trace_among(std::io::BufReader::new(file), &name, &models)?;
    if let Some(warning) = &read.torn_last_row {
        eprintln!("sim-cli: warning: {warning}");
    }
    // An SVG that is a named pipe waits for its reader as a run's outputs do.
    let _reader = crate::input::await_pipe_readers(&[(Some(output), "-o")])?;
    drop(before_outputs);
    Ok(create(output)?.write(&read.trace)?)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every refusal of the CSV reader is a usage error with its message.
    #[test]
    fn bad_csv_is_a_usage_error_naming_the_line() {
        let err = CliError::from(
            fdm_plot::csv::read_trace("a,b\n1,2\n".as_bytes(), "x.csv").unwrap_err(),
        );
        assert_eq!(err.exit_code(), 2);
        assert!(
            err.to_string().starts_with("x.csv:1: no `frame` column"),
            "{err}"
        );
        let header = "frame,time_s,x,y,z,vx,vy,vz,roll_deg,pitch_deg,fg_heading_deg,airspeed\n";
        let csv = format!("{header}0,0,0,0,0,0,0,0,0,0,0,0\n1,0.1,NaN,0,0,0,0,0,0,0,0,0\n");
        let err = CliError::from(fdm_plot::csv::read_trace(csv.as_bytes(), "x.csv").unwrap_err());
        assert_eq!(err.exit_code(), 2);
        assert!(
            err.to_string()
                .starts_with("x.csv:3: `NaN` is not a finite number"),
            "{err}"
        );
    }
}
