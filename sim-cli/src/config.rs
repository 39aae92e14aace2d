//! From parsed arguments to a validated run configuration: everything that can be
//! wrong with the input is found here, before anything runs, and reported as a
//! usage error (exit status 2).

use std::path::Path;

use fdm_core::model::Model;
use fdm_core::script::{Script, ScriptAction};

use crate::args::CommonArgs;
use crate::csv::CsvWriter;
use crate::error::CliError;
use crate::input::{refuse_clash, show_path, waiting};
use crate::signals::SignalSafeWriter;
use fdm_plot::PlotFile;
use fdm_run::links::LinkSettings;
use fdm_run::Scenario;
use fgnet::address::FgTarget;

/// How the run is driven.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Mode {
    /// As fast as possible for a fixed number of frames, then report.
    Headless {
        /// Frames to step.
        frames: u64,
        /// Print the JSON report on stdout.
        json: bool,
        /// Pace frames at 1/fps of wall-clock time (`--realtime`).
        realtime: bool,
        /// Print the summary on stderr: an output file is the standard
        /// output ([`summary_on_stderr`]), whose bytes it would break.
        summary_on_stderr: bool,
    },
    /// Keyboard in, HUD out, paced at the frame rate, until the user quits.
    Interactive,
}

/// A flight's outputs, validated and created before anything flies (so an
/// unwritable path is a usage error and nothing has run). The frame rate and
/// the origin they need are the scenario's.
#[derive(Debug, Default)]
pub struct Outputs {
    /// The FlightGear link's resolved target (`--fg`, or the default when
    /// interactive) and DIS (`--dis`); `None` sends nothing.
    pub links: LinkSettings,
    /// The CSV output, already created; flushed by the signal thread if a
    /// signal ends the run ([`crate::signals`]).
    pub csv: Option<CsvWriter<SignalSafeWriter>>,
    /// The `--plot` output, already created (like the CSV).
    pub plot: Option<PlotFile>,
    /// The `--record` file, already created.
    pub record: Option<RecordFile>,
    /// The `--acmi` file, already created.
    pub acmi: Option<fdm_run::acmi::AcmiWriter>,
}

/// How the aircraft starts (and restarts on a reset): the run library's.
pub use fdm_run::Start;

/// A validated `sim-cli <model>` run of model `M`.
#[derive(Debug)]
pub struct ModelConfig<M: Model> {
    /// The run library's scenario: how the aircraft starts (and restarts on
    /// reset), the origin, the frame rate, the frames of a headless run (0
    /// interactive: the user ends it) and the scripted controls (empty
    /// without `--script`).
    pub scenario: Scenario<M>,
    /// Headless or interactive.
    pub mode: Mode,
    /// The outputs, created.
    pub outputs: Outputs,
}

/// The `--record` output, created before the run: the run library's.
pub use fdm_run::recording::RecordFile;

/// Model `M`'s start from the initial-condition options
/// ([`crate::start::StartArgs::options`], refusals as
/// [`crate::start::refused`] words them), printing a trim's result on stderr.
///
/// # Errors
/// [`CliError::Usage`] for options out of range or a trim that fails.
pub fn start_model<M: Model>(
    controls: M::Controls,
    args: &crate::start::StartArgs,
) -> Result<Start<M>, CliError> {
    let (start, report) = (args.options())
        .start::<M>(M::default_aircraft(), controls)
        .map_err(crate::start::refused)?;
    if let Some(report) = report {
        eprintln!("sim-cli: {} trimmed: {report}", M::NAME);
    }
    Ok(start)
}

/// The mode implied by the options, or why they do not fit together.
///
/// # Errors
/// [`CliError::Usage`] for --json / --frames / --duration without --headless, a
/// headless run without a length, or a duration that is too long.
pub fn resolve_mode(args: &CommonArgs) -> Result<Mode, CliError> {
    let summary_on_stderr = summary_on_stderr(&output_files(args), args.json, !args.headless)?;
    if !args.headless {
        for (given, name) in [
            (args.json, "--json"),
            (args.realtime, "--realtime"),
            (args.frames.is_some(), "--frames"),
            (args.duration.is_some(), "--duration"),
        ] {
            if given {
                return Err(CliError::usage(format!("{name} needs --headless")));
            }
        }
        return Ok(Mode::Interactive);
    }
    let frames = match (args.frames, args.duration) {
        (Some(frames), None) => frames,
        (None, Some(seconds)) => frames_for_duration(seconds, args.fps)?,
        (None, None) => {
            return Err(CliError::usage(
                "--headless needs --frames N or --duration SECONDS",
            ))
        }
        // clap rejects this combination already; kept for callers that build args by hand.
        (Some(_), Some(_)) => {
            return Err(CliError::usage(
                "--frames and --duration cannot be used together",
            ))
        }
    };
    Ok(Mode::Headless {
        frames,
        json: args.json,
        realtime: args.realtime,
        summary_on_stderr,
    })
}

/// The run's output files, with their options.
fn output_files(args: &CommonArgs) -> [(Option<&Path>, &'static str); 4] {
    [
        (args.csv.as_deref(), "--csv"),
        (args.plot.as_deref(), "--plot"),
        (args.record.as_deref(), "--record"),
        (args.acmi.acmi.as_deref(), "--acmi"),
    ]
}

/// Whether a headless run's summary goes to stderr: when one of its output
/// files (`outputs`, with their options) is the standard output itself, the
/// path `/dev/stdout` (e.g. `--csv /dev/stdout | another-program`) or the
/// file the standard output is redirected to, so that the output's bytes
/// are all the standard output holds. Not when both are `/dev/null` (a
/// caller that discards both).
///
/// # Errors
/// [`CliError::Usage`] for such an output with `json` (the JSON report is
/// the standard output's) or in an `interactive` run (its display is).
pub fn summary_on_stderr(
    outputs: &[(Option<&Path>, &str)],
    json: bool,
    interactive: bool,
) -> Result<bool, CliError> {
    let stdout = Path::new("/dev/stdout");
    // `/dev/null` is no one's output: a caller that discards stdout and
    // names `/dev/null` as an output too gets the run it always got.
    let Some((path, name)) = outputs.iter().find_map(|&(path, name)| {
        path.filter(|p| fdm_run::input::same_file(p, stdout) && !fdm_run::input::is_dev_null(p))
            .map(|p| (p, name))
    }) else {
        return Ok(false);
    };
    let why = if interactive {
        "the interactive display draws there (use --headless)"
    } else if json {
        "--json prints its report there"
    } else {
        return Ok(true);
    };
    Err(CliError::usage(format!(
        "{name} {} is the standard output, and {why}",
        show_path(path)
    )))
}

/// frames = round(seconds × fps), checked against [`fdm_run::MAX_FRAMES`]: the run
/// library's [`fdm_run::scenario::frames_for_duration`], its error named
/// `--duration`.
///
/// # Errors
/// [`CliError::Usage`] for a negative or non-finite duration or too many frames
/// (also when seconds × fps overflows to infinity: the duration is fine, the
/// product is too long).
pub fn frames_for_duration(seconds: f64, fps: u32) -> Result<u64, CliError> {
    fdm_run::scenario::frames_for_duration(seconds, fps)
        .map_err(|e| CliError::usage(format!("--duration {e}")))
}

/// Reads and parses a script ([`fdm_run::scenario::load_script`]: errors
/// name the file and line as `FILE:LINE: message`). A signal while it is
/// read (a FIFO waiting for its writer) ends the process at once
/// ([`crate::signals::before_outputs`]): call this before creating any output.
///
/// # Errors
/// [`CliError::Usage`] for a file that cannot be read or its first bad line.
pub fn load_script<A: ScriptAction>(path: &Path) -> Result<Script<A>, CliError> {
    let _before_outputs = crate::signals::before_outputs();
    fdm_run::scenario::load_script(path, waiting).map_err(CliError::usage)
}

/// Creates the `--csv` file (registered with the signal thread).
///
/// # Errors
/// [`CliError::Usage`] naming the path and the reason.
pub fn create_csv(path: &Path) -> Result<CsvWriter<SignalSafeWriter>, CliError> {
    let out = SignalSafeWriter::create(path)
        .map_err(|e| CliError::usage(format!("cannot create CSV file {}: {e}", show_path(path))))?;
    Ok(CsvWriter::new(out, show_path(path)))
}

/// Creates the `--record` file after checking it is none of the input or
/// output files.
fn create_record(args: &CommonArgs) -> Result<Option<RecordFile>, CliError> {
    let Some(path) = &args.record else {
        return Ok(None);
    };
    let others = [
        (args.script.as_deref(), "--script"),
        (args.csv.as_deref(), "--csv"),
        (args.plot.as_deref(), "--plot"),
    ];
    refuse_clash(path, &others, |name| {
        format!("--record {} is also the {name} file", path.display())
    })?;
    RecordFile::create(path)
        .map(Some)
        .map_err(|e| CliError::usage(format!("cannot create recording {}: {e}", path.display())))
}

/// Model `model`'s run from the options every flight shares: the mode, the
/// script read, the outputs resolved and created (CSV, plot, recording, ACMI
/// last, so that no earlier error leaves a truncated file behind), put
/// together with its `start` ([`start_model`]).
///
/// # Errors
/// [`CliError::Usage`] for anything wrong with the input.
pub fn prepare_model<M: Model>(
    args: CommonArgs,
    start: Start<M>,
) -> Result<ModelConfig<M>, CliError> {
    let mode = resolve_mode(&args)?;
    let loaded = args.script.as_deref().map(load_script).transpose()?;
    if mode == Mode::Interactive {
        crate::terminal::require_terminal()?;
    }
    let dis = args.dis.resolve()?;
    let fg = match (&args.fg, mode) {
        (Some(target), _) => Some(target.resolve()?),
        (None, Mode::Interactive) => Some(FgTarget::default().resolve()?),
        (None, Mode::Headless { .. }) => None,
    };
    // Created last, so that no earlier error leaves a truncated file behind;
    // an output that is a named pipe first waits for its reader, saying so.
    let _readers = crate::input::await_pipe_readers(&output_files(&args))?;
    let script = args.script.as_deref();
    let others = [(script, "--script"), (args.csv.as_deref(), "--csv")];
    let csv = (args.csv.as_deref())
        .map(|path| {
            refuse_clash(path, &others[..1], |name| {
                format!("--csv {} would overwrite the {name} file", show_path(path))
            })?;
            create_csv(path)
        })
        .transpose()?;
    let plot = (args.plot.as_deref())
        .map(|path| {
            refuse_clash(path, &others, |name| {
                format!("--plot {} would overwrite the {name} file", path.display())
            })?;
            crate::plot::create(path)
        })
        .transpose()?;
    let record = create_record(&args)?;
    let acmi = crate::acmi::create(
        &args.acmi,
        M::NAME,
        args.fps,
        &args.origin,
        &[
            (script, "--script"),
            (args.csv.as_deref(), "--csv"),
            (args.plot.as_deref(), "--plot"),
            (args.record.as_deref(), "--record"),
        ],
    )?;
    let frames = match mode {
        Mode::Headless { frames, .. } => frames,
        Mode::Interactive => 0,
    };
    Ok(ModelConfig {
        scenario: Scenario {
            start,
            origin: args.origin,
            fps: args.fps,
            frames,
            script: loaded.unwrap_or_default(),
        },
        mode,
        outputs: Outputs {
            links: LinkSettings { fg, dis },
            csv,
            plot,
            record,
            acmi,
        },
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::args::{Cli, Command};
    use clap::{FromArgMatches, Parser};

    fn common(extra: &[&str]) -> CommonArgs {
        let argv = ["sim-cli", "bourg"].iter().chain(extra).copied();
        match Cli::try_parse_from(argv).unwrap().command {
            Command::Fly(fly) => CommonArgs::from_arg_matches(&fly.args).unwrap(),
            _ => unreachable!(),
        }
    }

    #[test]
    fn modes() {
        assert_eq!(resolve_mode(&common(&[])).unwrap(), Mode::Interactive);
        assert_eq!(
            resolve_mode(&common(&["--headless", "--frames", "900", "--json"])).unwrap(),
            Mode::Headless {
                frames: 900,
                json: true,
                realtime: false,
                summary_on_stderr: false,
            }
        );
        assert_eq!(
            resolve_mode(&common(&["--headless", "--duration", "1.5", "--fps", "10"])).unwrap(),
            Mode::Headless {
                frames: 15,
                json: false,
                realtime: false,
                summary_on_stderr: false,
            }
        );
        assert_eq!(
            resolve_mode(&common(&["--headless", "--frames", "3", "--realtime"])).unwrap(),
            Mode::Headless {
                frames: 3,
                json: false,
                realtime: true,
                summary_on_stderr: false,
            }
        );
    }

    #[test]
    fn mode_errors_are_usage_errors() {
        for (argv, needle) in [
            (&["--json"][..], "--json needs --headless"),
            (&["--frames", "3"][..], "--frames needs --headless"),
            (&["--duration", "3"][..], "--duration needs --headless"),
            (&["--headless"][..], "--headless needs --frames"),
            (
                &["--headless", "--duration", "1e300"][..],
                "more than 1000000000",
            ),
        ] {
            let err = resolve_mode(&common(argv)).unwrap_err();
            assert_eq!(err.exit_code(), 2);
            assert!(err.to_string().contains(needle), "{err}");
        }
    }

    #[test]
    fn duration_rounds_to_nearest_frame() {
        assert_eq!(frames_for_duration(1.0 / 30.0 * 2.4, 30).unwrap(), 2);
        assert_eq!(frames_for_duration(0.05, 30).unwrap(), 2); // 1.5 rounds away from zero
        assert_eq!(frames_for_duration(0.0, 30).unwrap(), 0);
        assert_eq!(frames_for_duration(2.5, 10).unwrap(), 25);
        assert!(frames_for_duration(f64::NAN, 30).is_err());
    }

    #[test]
    fn overlong_durations_say_too_many_frames_in_short_numbers() {
        let err = frames_for_duration(1e308, 10_000).unwrap_err();
        assert_eq!(
            err.to_string(),
            "--duration 1e308 at 10000 fps is more than 1000000000 frames"
        );
        let err = frames_for_duration(1e300, 30).unwrap_err();
        assert_eq!(
            err.to_string(),
            "--duration 1e300 at 30 fps is 3e301 frames, more than 1000000000"
        );
        let err = frames_for_duration(f64::INFINITY, 30).unwrap_err();
        assert!(
            err.to_string().contains("not a non-negative number"),
            "{err}"
        );
    }
}
