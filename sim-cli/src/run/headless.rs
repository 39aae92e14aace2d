//! The headless loop: a fixed number of frames as fast as possible, then the
//! report.

use std::io::Write;
use std::time::Instant;

use anyhow::Context as _;
use fdm_core::script::{Script, ScriptCursor};

use super::{link_warning, Flight};
use crate::csv::CsvWriter;
use crate::error::CliError;
use crate::pacer::FramePacer;
use crate::progress::StderrProgress;
use crate::report::{RealtimeReport, Report};

/// Steps frame `frame` (1-based): the script's actions for that frame in file order
/// (through `cursor`, a sweep over the rules: linear in frames plus rules),
/// then `keys`, then one model step, then the CSV row.
pub(super) fn step_frame<F: Flight, W: Write>(
    flight: &mut F,
    script: &Script<F::Action>,
    cursor: &mut ScriptCursor,
    frame: u64,
    keys: &[F::Action],
    buffer: &mut Vec<F::Action>,
    csv: Option<&mut CsvWriter<W>>,
) -> Result<(), CliError> {
    buffer.clear();
    buffer.extend(cursor.actions(script, frame));
    buffer.extend_from_slice(keys);
    flight
        .step(buffer)
        .with_context(|| format!("frame {frame}"))?;
    if let Some(csv) = csv {
        csv.write_record(frame, &flight.snapshot())?;
    }
    Ok(())
}

/// Runs `frames` frames and returns the final report: as fast as possible, or
/// with `realtime` one frame per 1/fps of wall-clock time like the interactive
/// loop (so FlightGear, reading at the frame rate, sees every frame; frames
/// that miss their deadline are counted as overruns in the report). Writes the
/// initial state as CSV frame 0 and a row after every step. The caller
/// finishes (flushes) the CSV writer.
///
/// # Errors
/// The first failing step or CSV write ([`CliError::Runtime`]).
pub fn run_headless<F: Flight, W: Write>(
    flight: &mut F,
    script: &Script<F::Action>,
    fps: u32,
    frames: u64,
    realtime: bool,
    mut csv: Option<&mut CsvWriter<W>>,
    progress: &mut StderrProgress,
) -> Result<Report<F::Details>, CliError> {
    let mut pacer = realtime.then(|| FramePacer::new(FramePacer::period_for(fps), Instant::now()));
    if let Some(csv) = csv.as_deref_mut() {
        csv.write_record(0, &flight.snapshot())?;
    }
    let mut buffer = Vec::new();
    let mut cursor = ScriptCursor::new();
    let mut flown = 0;
    let links = flight.links();
    for frame in 1..=frames {
        // A signal ends the run here, as if this were its last frame: the
        // caller finishes every output (crate::signals).
        if crate::signals::stop_requested().is_some() {
            break;
        }
        step_frame(
            flight,
            script,
            &mut cursor,
            frame,
            &[],
            &mut buffer,
            csv.as_deref_mut(),
        )?;
        if let Some(message) = links.take_failure() {
            progress.message(&link_warning(&message));
        }
        progress.tick(frame);
        flown = frame;
        if let Some(pacer) = pacer.as_mut() {
            let sleep = pacer.finish_frame(Instant::now());
            if !sleep.is_zero() {
                std::thread::sleep(sleep);
            }
        }
    }
    progress.finish();
    let mut report = Report::new(fps, flown, &flight.snapshot());
    report.realtime = pacer.map(|p| RealtimeReport {
        overruns: p.overruns(),
    });
    Ok(report)
}
