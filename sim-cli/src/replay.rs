//! `sim-cli replay FILE`: flies a recording (docs/recording.md) again,
//! headless, and reports like a headless flight (`--json`, `--csv`,
//! `--plot`, `--fg`).
//!
//! The replay builds the same [`ModelFlight`] the recorded run had (model,
//! aircraft, fps, origin, controls and state from the header) and feeds it
//! the recorded frames and resets, so every state is bit-identical to the
//! original's: the JSON report equals the headless original's, and the CSV
//! equals the original's CSV (a reset writes a new frame 0, as in an
//! interactive flight), and the `--plot` SVG equals the original run's.
//!
//! `--realtime` paces the replay at 1/fps of wall-clock time per frame, as it
//! does headless flights, so that FlightGear (`--fg`) shows every frame.
//! `--dis` publishes the replayed aircraft as a DIS entity, as the flight
//! itself would ([`crate::dis`]).
//!
//! A recording of format version 3 carries the flight's fingerprint
//! ([`Recording::fingerprint`]): after the last frame the replay compares its
//! own final state with it ([`check_fingerprint`]). Another final state is a
//! [`CliError::DifferentFlight`] (exit status 4); other maths alone only a
//! warning (the flight may still be the same); a recording without a
//! fingerprint (versions 1 and 2, a cut recording) a note that nothing was
//! checked.

use std::io::{self, Write};
use std::time::Instant;

use anyhow::Context as _;

use crate::args::{ModelKind, ReplayArgs};
use crate::config::{Mode, RunConfig};
use crate::csv::CsvWriter;
use crate::error::CliError;
use crate::flight::ModelFlight;
use crate::input::{read_bytes, show_path};
use crate::models::{CliModel, WithModel};
use crate::pacer::FramePacer;
use crate::plot::PlotFile;
use crate::progress::StderrProgress;
use crate::recording::{recorded_model, Recording, RecordingError, Replayed, MAX_RECORDING_BYTES};
use crate::report::{RealtimeReport, Report};
use crate::run::{link_warning, Flight};
use crate::signals::SignalSafeWriter;
use fdm_core::fingerprint::{self, Fingerprint};
use fdm_run::acmi::AcmiOutput;

/// Flies the recorded events on `flight` (which starts where the recording
/// starts): each run of frames steps the flight with its actions, a reset
/// resets it. The run hands its outputs every frame as the recorded flight's
/// did (the CSV: frame 0 at the start and after each reset, then the frame
/// number since the last reset).
///
/// # Errors
/// A failing step, reset or output ([`CliError::Runtime`]), or an event
/// that does not decode ([`CliError::Usage`]; not after [`Recording::parse`]).
pub fn replay_flight<F: Flight>(
    flight: &mut F,
    events: impl IntoIterator<Item = Result<Replayed<F::Action>, RecordingError>>,
    fps: u32,
    total_frames: u64,
    realtime: bool,
    progress: &mut StderrProgress,
) -> Result<Report<F::Details>, CliError> {
    let mut pacer = realtime.then(|| FramePacer::new(FramePacer::period_for(fps), Instant::now()));
    let mut frame = 0_u64;
    let mut done = 0_u64;
    let links = flight.links();
    'replay: for event in events {
        match event.map_err(CliError::usage)? {
            Replayed::Frames { count, actions } => {
                for _ in 0..count {
                    // A signal ends the replay here; the caller finishes the
                    // outputs for the frames replayed (crate::signals).
                    if crate::signals::stop_requested().is_some() {
                        break 'replay;
                    }
                    frame += 1;
                    done += 1;
                    flight
                        .step(&actions)
                        .with_context(|| format!("frame {frame}"))?;
                    if let Some(message) = links.take_failure() {
                        progress.message(&link_warning(&message));
                    }
                    progress.tick(done);
                    if let Some(pacer) = pacer.as_mut() {
                        let sleep = pacer.finish_frame(Instant::now());
                        if !sleep.is_zero() {
                            std::thread::sleep(sleep);
                        }
                    }
                }
            }
            Replayed::Reset => {
                flight.reset().context("reset")?;
                frame = 0;
            }
        }
    }
    progress.finish();
    // `done` is `total_frames` unless a signal stopped the replay early.
    debug_assert!(done <= total_frames);
    let mut report = Report::new(fps, done, &flight.snapshot());
    report.realtime = pacer.map(|p| RealtimeReport {
        overruns: p.overruns(),
    });
    Ok(report)
}

/// Replays a recording of model `M` as `args` ask.
struct ReplayJob<'a> {
    bytes: &'a [u8],
    args: &'a ReplayArgs,
}

impl WithModel for ReplayJob<'_> {
    type Output = Result<(), CliError>;

    fn call<M: CliModel>(self) -> Self::Output {
        let file = show_path(&self.args.file);
        // A recording cut before its end marker (the recording run killed, the
        // machine stopped) is replayed up to its last intact block; the exit
        // status (3) and the last stderr line say so.
        let (recording, cut) = Recording::<M>::parse_salvaging(self.bytes)
            .map_err(|e| CliError::usage(format!("{file}: {e}")))?;
        let fg = match &self.args.fg {
            Some(target) => Some(
                target
                    .resolve()
                    .map_err(|e| CliError::usage(e.to_string()))?,
            ),
            None => None,
        };
        let csv = match &self.args.csv {
            Some(path) => {
                if path == &self.args.file || crate::input::same_file(path, &self.args.file) {
                    return Err(CliError::usage(format!(
                        "--csv {} would overwrite the recording",
                        show_path(path)
                    )));
                }
                let out = SignalSafeWriter::create(path).map_err(|e| {
                    CliError::usage(format!("cannot create CSV file {}: {e}", show_path(path)))
                })?;
                Some(CsvWriter::new(out, show_path(path)))
            }
            None => None,
        };
        let plot = match &self.args.plot {
            Some(path) => {
                for (other, name) in [
                    (Some(&self.args.file), "recording"),
                    (self.args.csv.as_ref(), "--csv"),
                ] {
                    if other.is_some_and(|o| path == o || crate::input::same_file(path, o)) {
                        return Err(CliError::usage(format!(
                            "--plot {} would overwrite the {name} file",
                            show_path(path)
                        )));
                    }
                }
                Some(PlotFile::create(path)?)
            }
            None => None,
        };
        let run = RunConfig {
            fps: recording.fps,
            mode: Mode::Headless {
                frames: recording.frames,
                json: self.args.json,
                realtime: self.args.realtime,
            },
            csv: None,
            fg,
            origin: recording.origin,
            plot: None,
            dis: self.args.dis.resolve()?,
        };
        let acmi = crate::acmi::create(
            self.args.acmi.acmi.as_deref(),
            self.args.acmi.acmi_reference_time.as_ref(),
            M::NAME,
            recording.fps,
            &recording.origin,
            &[
                (Some(self.args.file.as_path()), "recording"),
                (self.args.csv.as_deref(), "--csv"),
                (self.args.plot.as_deref(), "--plot"),
            ],
        )?;
        let mut flight = ModelFlight::<M>::new(&run, recording.start.clone())?;
        if let Some(csv) = csv {
            flight.attach_csv(csv)?;
        }
        if let Some(acmi) = acmi {
            flight.attach(AcmiOutput::<M>::new(acmi))?;
        }
        // With --plot the flight is sampled as a run's --plot samples it (the
        // same output, fdm_plot::PlotOutput), so the two SVGs are the same
        // bytes.
        if let Some(plot) = plot {
            flight.attach(plot.into_output(M::TITLE))?;
        }
        let mut progress = StderrProgress::new(recording.frames);
        let report = replay_flight(
            &mut flight,
            recording.events(),
            recording.fps,
            recording.frames,
            self.args.realtime,
            &mut progress,
        );
        // The outputs (--csv, --acmi, --plot) are completed even when the
        // replay stopped early.
        let finished = flight.finish();
        let mut report = report?;
        finished?;
        let links = flight.links();
        if run.fg.is_some() {
            report.fg = links.fg_stats();
        }
        report.dis = links.dis_report();
        let text = if self.args.json {
            report.to_json().context("encoding the JSON report")?
        } else {
            format!(
                "{}\nreplayed {}: {} frames, {} resets",
                report.human_summary(),
                file,
                recording.frames,
                recording.resets
            )
        };
        let mut out = io::stdout().lock();
        writeln!(out, "{text}")
            .and_then(|()| out.flush())
            .context("writing to stdout")?;
        if let Some(cut) = cut {
            return Err(CliError::Incomplete(format!(
                "{file}: {cut}; they were replayed (a cut recording has no fingerprint to check \
                 them against)"
            )));
        }
        if crate::signals::stop_requested().is_some() {
            // Stopped early: not the whole flight, nothing to compare.
            return Ok(());
        }
        let verdict = check_fingerprint(
            recording.fingerprint,
            M::state_fingerprint(&flight.state()),
            fingerprint::maths(),
        );
        match verdict {
            Verdict::Same => Ok(()),
            Verdict::Unchecked => {
                progress.message(&format!(
                    "sim-cli: note: {file}: this recording (format version 1 or 2) has no \
                     fingerprint; the replay was not checked against the recorded flight"
                ));
                Ok(())
            }
            Verdict::OtherMaths { recorded, ours } => {
                progress.message(&format!(
                    "sim-cli: warning: {file}: the recording was made with different maths \
                     (maths fingerprint {recorded:#018x}, this sim-cli's {ours:#018x}); the \
                     replay still ended in the recorded final state"
                ));
                Ok(())
            }
            Verdict::DifferentFlight {
                recorded,
                replayed,
                maths,
            } => {
                let why = match maths {
                    Some((recorded_maths, ours)) => format!(
                        "; the recording was made with different maths (maths fingerprint \
                         {recorded_maths:#018x}, this sim-cli's {ours:#018x})"
                    ),
                    None => {
                        "; the maths are the same, so the build or the machine differs".to_owned()
                    }
                };
                Err(CliError::DifferentFlight(format!(
                    "{file}: the replay flew a different flight: its final state's fingerprint is \
                     {replayed:#018x}, the recording's {recorded:#018x}{why}"
                )))
            }
        }
    }
}

/// What comparing a replay's end with the recording's fingerprint found.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Verdict {
    /// The final state and the maths are the recording's.
    Same,
    /// The recording carries no fingerprint.
    Unchecked,
    /// The final state is the recording's, the maths are not.
    OtherMaths {
        /// The recording's maths fingerprint.
        recorded: u64,
        /// This build's.
        ours: u64,
    },
    /// The final state is not the recording's.
    DifferentFlight {
        /// The recording's state fingerprint.
        recorded: u64,
        /// The replay's.
        replayed: u64,
        /// The recording's and this build's maths fingerprints, when they differ.
        maths: Option<(u64, u64)>,
    },
}

/// Compares a replay's final state (`replayed`, [`fdm_run::RunModel::state_fingerprint`])
/// and this build's maths (`maths`, [`fingerprint::maths`]) with the
/// recording's fingerprint.
#[must_use]
pub fn check_fingerprint(recorded: Option<Fingerprint>, replayed: u64, maths: u64) -> Verdict {
    let Some(recorded) = recorded else {
        return Verdict::Unchecked;
    };
    let other_maths = (recorded.maths != maths).then_some((recorded.maths, maths));
    if recorded.state != replayed {
        return Verdict::DifferentFlight {
            recorded: recorded.state,
            replayed,
            maths: other_maths,
        };
    }
    match other_maths {
        None => Verdict::Same,
        Some((recorded, ours)) => Verdict::OtherMaths { recorded, ours },
    }
}

/// `sim-cli replay`: reads (at most [`MAX_RECORDING_BYTES`]), validates
/// and replays a recording.
///
/// # Errors
/// [`CliError::Usage`] (exit status 2) for an unreadable, too large,
/// truncated, corrupt, wrong-version or unknown-model file, naming the
/// problem; [`CliError::Runtime`] for failures while replaying.
pub fn run(args: &ReplayArgs) -> Result<(), CliError> {
    let path = &args.file;
    let bytes = read_bytes(path, "recording", MAX_RECORDING_BYTES)?;
    let kind =
        recorded_model(&bytes).map_err(|e| CliError::usage(format!("{}: {e}", show_path(path))))?;
    let kind = ModelKind::named(kind).ok_or_else(|| {
        CliError::usage(format!(
            "{}: {}",
            show_path(path),
            RecordingError::UnknownModel(kind.to_owned())
        ))
    })?;
    kind.with(ReplayJob {
        bytes: &bytes,
        args,
    })
}
