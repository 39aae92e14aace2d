//! The headless loop: a fixed number of frames as fast as possible, then the
//! report.

use std::time::Instant;

use anyhow::Context as _;

use super::{link_warning, Flight};
use crate::error::CliError;
use crate::pacer::FramePacer;
use crate::progress::StderrProgress;
use crate::report::{RealtimeReport, Report};

/// Runs `frames` frames (each the flight's script's rules for the frame,
/// [`Flight::step`]) and returns the final report: as fast as possible, or
/// with `realtime` one frame per 1/fps of wall-clock time like the interactive
/// loop (so FlightGear, reading at the frame rate, sees every frame; frames
/// that miss their deadline are counted as overruns in the report). The
/// run's outputs get every frame from the run; the caller finishes them.
///
/// # Errors
/// The first failing step or output ([`CliError::Runtime`]).
pub fn run_headless<F: Flight>(
    flight: &mut F,
    fps: u32,
    frames: u64,
    realtime: bool,
    progress: &mut StderrProgress,
) -> Result<Report<F::Details>, CliError> {
    let mut pacer = realtime.then(|| FramePacer::new(FramePacer::period_for(fps), Instant::now()));
    let mut flown = 0;
    let links = flight.links();
    for frame in 1..=frames {
        // A signal ends the run here, as if this were its last frame: the
        // caller finishes every output (crate::signals).
        if crate::signals::stop_requested().is_some() {
            break;
        }
        flight.step(&[]).with_context(|| format!("frame {frame}"))?;
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
