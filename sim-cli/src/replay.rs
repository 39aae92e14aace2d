//! `sim-cli replay FILE`: flies a recording (docs/recording.md) again,
//! headless, and reports like a headless flight (`--json`, `--csv`,
//! `--plot`, `--fg`; the summary on stderr when an output file is the
//! standard output).
//!
//! The replay builds the same [`ModelFlight`] the recorded run had (model,
//! aircraft, fps, origin, controls and state from the header) and feeds it
//! the recorded frames and resets (the run library's
//! [`fdm_run::replay::replay`]), so every state is bit-identical to the
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

use anyhow::Context as _;

use crate::args::{ModelKind, ReplayArgs};
use crate::config::{create_csv, Outputs};
use crate::error::CliError;
use crate::flight::ModelFlight;
use crate::input::refuse_clash;
use crate::input::{show_path, waiting, Echo};
use crate::models::{CliModel, WithModel};
use crate::progress::StderrProgress;
use crate::recording::{
    recorded_model_name, Recording, RecordingError, Replayed, MAX_RECORDING_BYTES,
};
use crate::report::{RealtimeReport, Report};
use crate::run::{finish_report, link_warning, Flight};
use fdm_core::fingerprint;
use fdm_run::input::read_bytes;
use fdm_run::links::LinkSettings;
use fdm_run::replay::{replay, ReplayError, ReplayOptions, ReplayTarget};
use fgnet::address::FgTarget;

pub use fdm_run::replay::{check_fingerprint, Verdict};

/// Flies the recorded events on `flight` (which starts where the recording
/// starts) through the run library's [`replay`]: each run of frames steps
/// the flight with its actions, a reset resets it. The run hands its outputs
/// every frame as the recorded flight's did (the CSV: frame 0 at the start
/// and after each reset, then the frame number since the last reset). A
/// signal ends the replay before the next frame; the caller finishes the
/// outputs for the frames replayed (crate::signals).
///
/// # Errors
/// A failing step, reset or output ([`CliError::Runtime`], `frame N: ...`
/// or `reset: ...`), or an event that does not decode ([`CliError::Usage`];
/// not after [`Recording::parse`]).
pub fn replay_flight<F: Flight>(
    flight: &mut F,
    events: impl IntoIterator<Item = Result<Replayed<F::Action>, RecordingError>>,
    fps: u32,
    total_frames: u64,
    realtime: bool,
    progress: &mut StderrProgress,
) -> Result<Report<F::Details>, CliError> {
    let links = flight.links();
    let options = ReplayOptions { fps, realtime };
    let stop = || crate::signals::stop_requested().is_some();
    let end = replay(&mut Target(flight), events, &options, stop, |done| {
        if let Some(message) = links.take_failure() {
            progress.message(&link_warning(&message));
        }
        progress.tick(done);
    })
    .map_err(|e| match e {
        ReplayError::Step { frame, source } => {
            CliError::Runtime(source.context(format!("frame {frame}")))
        }
        ReplayError::Reset(e) => CliError::Runtime(e.context("reset")),
        ReplayError::Event(e) => CliError::usage(e),
    })?;
    progress.finish();
    // `frames` is `total_frames` unless a signal stopped the replay early.
    debug_assert!(end.frames <= total_frames);
    let mut report = Report::new(fps, end.frames, &flight.snapshot());
    report.realtime = end.overruns.map(|overruns| RealtimeReport { overruns });
    Ok(report)
}

/// A [`Flight`] as the run library's replay target.
struct Target<'a, F>(&'a mut F);

impl<F: Flight> ReplayTarget<F::Action> for Target<'_, F> {
    type Error = anyhow::Error;

    fn step(&mut self, actions: &[F::Action]) -> anyhow::Result<()> {
        self.0.step(actions)
    }

    fn reset(&mut self) -> anyhow::Result<()> {
        self.0.reset()
    }
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
        let fg = self.args.fg.as_ref().map(FgTarget::resolve).transpose()?;
        let recording_file = Some(self.args.file.as_path());
        let others = [
            (recording_file, "recording"),
            (self.args.csv.as_deref(), "--csv"),
            (self.args.plot.as_deref(), "--plot"),
        ];
        let summary_on_stderr = crate::config::summary_on_stderr(
            &[
                (self.args.csv.as_deref(), "--csv"),
                (self.args.plot.as_deref(), "--plot"),
                (self.args.acmi.acmi.as_deref(), "--acmi"),
            ],
            self.args.json,
            false,
        )?;
        // An output that is a named pipe first waits for its reader, saying so.
        let _readers = crate::input::await_pipe_readers(&[
            (self.args.csv.as_deref(), "--csv"),
            (self.args.plot.as_deref(), "--plot"),
            (self.args.acmi.acmi.as_deref(), "--acmi"),
        ])?;
        let csv = (self.args.csv.as_deref())
            .map(|path| {
                refuse_clash(path, &others[..1], |_| {
                    format!("--csv {} would overwrite the recording", show_path(path))
                })?;
                create_csv(path)
            })
            .transpose()?;
        let plot = (self.args.plot.as_deref())
            .map(|path| {
                refuse_clash(path, &others[..2], |name| {
                    format!("--plot {} would overwrite the {name} file", show_path(path))
                })?;
                crate::plot::create(path)
            })
            .transpose()?;
        let links = LinkSettings {
            fg,
            dis: self.args.dis.resolve()?,
        };
        let acmi = crate::acmi::create(
            &self.args.acmi,
            M::NAME,
            recording.fps,
            &recording.origin,
            &others,
        )?;
        let outputs = Outputs {
            links,
            csv,
            plot,
            record: None,
            acmi,
        };
        // With --plot the flight is sampled as a run's --plot samples it (the
        // same output, fdm_plot::PlotOutput), so the two SVGs are the same
        // bytes.
        let mut flight = ModelFlight::<M>::with_outputs(recording.scenario(), outputs, |_| Ok(()))?;
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
        let report = finish_report(&mut flight, report, self.args.fg.is_some())?;
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
        crate::print_report(&text, summary_on_stderr)?;
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
        let Some(text) = verdict.describe("sim-cli") else {
            return Ok(());
        };
        if let Verdict::DifferentFlight { .. } = verdict {
            return Err(CliError::DifferentFlight(format!("{file}: {text}")));
        }
        let note = verdict == Verdict::Unchecked;
        let kind = if note { "note" } else { "warning" };
        progress.message(&format!("sim-cli: {kind}: {file}: {text}"));
        Ok(())
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
    // A signal while a FIFO waits for its writer ends the process at once:
    // no output exists yet.
    let before_outputs = crate::signals::before_outputs();
    let bytes = read_bytes(path, "recording", MAX_RECORDING_BYTES, waiting)?;
    drop(before_outputs);
    let name = recorded_model_name(&bytes)
        .map_err(|e| CliError::usage(format!("{}: {e}", show_path(path))))?;
    // The CLI's registry, which may have models the run library's does not.
    let kind = ModelKind::named(&name).ok_or_else(|| {
        let ours: Vec<&str> = ModelKind::ALL.iter().map(|kind| kind.name()).collect();
        CliError::usage(format!(
            "{}: recorded with model `{}`, which this sim-cli does not have ({})",
            show_path(path),
            Echo::short(&name),
            ours.join(", ")
        ))
    })?;
    kind.with(ReplayJob {
        bytes: &bytes,
        args,
    })
}
