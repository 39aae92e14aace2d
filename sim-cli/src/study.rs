//! `sim-cli study FILE.toml`: a Monte Carlo study (fdm-study) flown on the
//! SIMD fleets, streamed to `runs.csv` and `runs.arrow` block by block, summarised in
//! `summary.json` and on the terminal; and `--run I`, run I flown alone with
//! every output of a single flight, bit-identical to the batch's row.
//!
//! A signal (crate::signals) stops the batch inside the chunk in flight: the
//! runs completed, 0 to K - 1, are written and summarised, and the summary
//! says the study was stopped; `--run I` stops at the next frame and writes no
//! `run-I.csv` for a flight cut short.
//!
//! The study file's `model` is looked up in the CLI's registry
//! ([`ModelKind::study_models`]), so every model `sim-cli` flies can be
//! studied. The flying, the streaming and the summary are the library's
//! ([`fdm_study::batch`]: [`Batch`], [`fdm_study::batch::scenario_alone`]);
//! here are the options, the output files (created locked, the CSV
//! registered with the signal thread), the memory checks' inputs (the
//! check is [`fdm_study::MemoryEstimate::check`]), `study.svg`
//! (drawn by `fdm_plot::study`), `summary.json`, the progress bar and the
//! printing.
//!
//! The file format, the measures and the guarantees: docs/studies.md.

use std::io::{BufWriter, IsTerminal, Write};
use std::path::Path;

use anyhow::Context as _;
use fdm_fleet::Precision;
use fdm_run::SharedOutput;
use fdm_study::batch::{AloneError, Batch, BatchError};
use fdm_study::table::write_csv;
use fdm_study::{FlyOptions, MeasureOutput, Study};

use crate::args::{CommonArgs, StudyArgs};
use crate::error::CliError;
use crate::models::{CliModel, ModelKind, WithModel};
use crate::progress::StderrProgress;
use crate::signals::SignalSafeWriter;

fn usage(e: impl std::fmt::Display, file: &Path) -> CliError {
    CliError::usage(format!("{}: {e}", file.display()))
}

/// Runs `sim-cli study`.
///
/// # Errors
/// [`CliError::Usage`] (exit 2) for a bad study file or options, or a study
/// that will not fit in `--memory-limit-mib`; [`CliError::Runtime`] for a
/// failure while flying or writing.
pub fn run(args: &StudyArgs) -> Result<(), CliError> {
    // Until the outputs are created a signal ends the process at once: a
    // study file that is a named pipe waits in `open` for its writer.
    let before_outputs = crate::signals::before_outputs();
    // The message of a file that cannot be read names it already.
    let text = Study::read_file(&args.file, crate::input::waiting)
        .map_err(|e| CliError::usage(e.to_string()))?;
    drop(before_outputs);
    // The CLI's registry, which may have models the run library's does not.
    let mut study = Study::from_toml_str_among(&text, &ModelKind::study_models())
        .map_err(|e| usage(e, &args.file))?;
    if let Some(runs) = args.runs {
        study = study.with_runs(runs).map_err(|e| usage(e, &args.file))?;
    }
    if let Some(seed) = args.seed {
        study = study.with_seed(seed);
    }
    let precision: Precision = args.precision.into();
    let out_dir = (args.out.clone()).unwrap_or_else(|| Study::default_out_dir(&args.file));
    std::fs::create_dir_all(&out_dir)
        .map_err(|e| CliError::usage(format!("cannot create --out {}: {e}", out_dir.display())))?;
    match args.run {
        Some(run) => {
            if precision == Precision::Fast {
                return Err(CliError::usage(
                    "--run flies the run alone with exact maths; --precision fast is for batches \
                     (fly the batch with --precision exact to compare run by run)",
                ));
            }
            let alone = Alone {
                study: &study,
                run,
                args,
                out_dir: &out_dir,
            };
            ModelKind::named(study.model()).map_or_else(
                || Err(CliError::usage(format!("no model {}", study.model()))),
                |kind| kind.with(alone),
            )
        }
        None => batch(&study, precision, args, &out_dir),
    }
}

/// Flies the whole study in chunks ([`Batch`]), streaming `runs.csv` and
/// `runs.arrow`, then writes `study.svg` and `summary.json` and prints the
/// summary.
fn batch(
    study: &Study,
    precision: Precision,
    args: &StudyArgs,
    out_dir: &Path,
) -> Result<(), CliError> {
    let threads = args.threads.unwrap_or(FlyOptions::default().threads);
    let options = FlyOptions { threads, precision };
    let mut batch = Batch::new(study, options, fdm_plot::study::MAX_SCATTER_POINTS);
    let available = crate::memory::available_bytes();
    (batch.memory())
        .check(study.runs(), args.memory_limit_mib, available)
        .map_err(CliError::usage)?;
    let csv_path = out_dir.join("runs.csv");
    let arrow_path = out_dir.join("runs.arrow");
    let plot_path = out_dir.join("study.svg");
    let summary_path = out_dir.join("summary.json");
    // Any of the four that is a named pipe is waited for out loud (and a
    // signal meanwhile ends the command at once), as the runs' outputs are:
    // held open to the end, the writes below find their readers there.
    let _readers = crate::input::await_pipe_readers(&[
        (Some(&csv_path), "runs.csv"),
        (Some(&arrow_path), "runs.arrow"),
        (Some(&plot_path), "study.svg"),
        (Some(&summary_path), "summary.json"),
    ])?;
    // A write error with the file's path as its context (`writing PATH: REASON`).
    let writing = |e: BatchError| match e {
        BatchError::Fly(fdm_study::StudyError::Fleet(_)) => CliError::usage(e.to_string()),
        BatchError::Fly(e) => CliError::runtime(e),
        BatchError::Csv(e) => CliError::Runtime(
            anyhow::Error::new(e).context(format!("writing {}", csv_path.display())),
        ),
        BatchError::Arrow(e) => CliError::Runtime(
            anyhow::Error::new(e).context(format!("writing {}", arrow_path.display())),
        ),
    };
    // Locked as every output file of a run (docs/cli.md, "One writer per output
    // file"): two studies writing into one directory are refused, not spliced.
    let file = fdm_run::outfile::create_locked(&csv_path)
        .map_err(|e| CliError::usage(format!("cannot create {}: {e}", csv_path.display())))?;
    // Registered with the signal thread: if the process must end at once (a
    // second signal), the file still ends with a whole row.
    let mut csv = SignalSafeWriter::register(file);
    batch.write_csv_header(&mut csv).map_err(writing)?;
    let arrow_file = fdm_run::outfile::create_locked(&arrow_path)
        .map_err(|e| CliError::usage(format!("cannot create {}: {e}", arrow_path.display())))?;
    let mut arrow = batch
        .arrow_writer(BufWriter::with_capacity(1 << 16, arrow_file))
        .map_err(writing)?;
    let mut progress = StderrProgress::with_enabled(study.runs(), std::io::stderr().is_terminal());
    // A signal (crate::signals) stops the flying within milliseconds, inside
    // the chunk; the runs completed before it are written and summarised as
    // at a normal end.
    let stop = || crate::signals::stop_requested().is_some();
    while batch
        .fly_chunk(&mut csv, &mut arrow, stop)
        .map_err(writing)?
    {
        progress.tick(batch.completed() - batch.completed() % 64);
    }
    progress.finish();
    csv.flush().map_err(|e| writing(BatchError::Csv(e)))?;
    arrow.finish().map_err(|e| writing(BatchError::Arrow(e)))?;
    let svg = fdm_plot::study::render(
        batch.measure_values(),
        batch.touchdowns(),
        batch.tracks(),
        batch.frame_step(),
    )?;
    std::fs::write(&plot_path, svg).with_context(|| format!("writing {}", plot_path.display()))?;
    let by = crate::signals::stop_requested().map_or("a signal", crate::signals::signal_name);
    let summary = batch.summary_stopped_by(by);
    let json = serde_json::to_string_pretty(&summary).context("summary as JSON")?;
    std::fs::write(&summary_path, format!("{json}\n"))
        .with_context(|| format!("writing {}", summary_path.display()))?;
    let mut stdout = std::io::stdout().lock();
    if args.json {
        writeln!(stdout, "{json}")
    } else {
        write!(stdout, "{}", summary.to_text())
    }
    .and_then(|()| stdout.flush())
    .context("writing to stdout")?;
    Ok(())
}

/// `--run I` as a job for the study's model, chosen through the registry
/// ([`ModelKind::with`]).
struct Alone<'a> {
    study: &'a Study,
    run: u64,
    args: &'a StudyArgs,
    out_dir: &'a Path,
}

impl WithModel for Alone<'_> {
    type Output = Result<(), CliError>;

    /// Flies run `run` alone through the run library with the single-flight
    /// outputs, and writes its row (`run-I.csv`, the batch's format).
    fn call<M: CliModel>(self) -> Self::Output {
        let Self {
            study,
            run,
            args,
            out_dir,
        } = self;
        if run >= study.runs() {
            return Err(CliError::usage(format!(
                "--run {run}: the study has runs 0 to {}",
                study.runs() - 1
            )));
        }
        // Its start, script and the frames it flies in the batch (its stop). A
        // signal during that flight ends the command before the flight alone
        // (nothing written; exit 128 + N, crate::signals).
        let stop = || crate::signals::stop_requested().is_some();
        let scenario = match fdm_study::batch::scenario_alone::<M>(study, run, stop) {
            Ok(Some(scenario)) => scenario,
            Ok(None) => return Ok(()),
            Err(AloneError::Fly(e)) => return Err(CliError::runtime(e)),
            Err(e @ AloneError::Refused(_)) => return Err(CliError::usage(e)),
        };
        let frames = scenario.frames;
        // The run's row, waited for out loud when it is a named pipe (before
        // the flight's own outputs, which prepare_model waits for).
        let name = format!("run-{run}.csv");
        let path = out_dir.join(&name);
        let _reader = crate::input::await_pipe_readers(&[(Some(&path), &name)])?;
        let common = CommonArgs {
            fps: study.fps(),
            headless: true,
            frames: Some(frames),
            duration: None,
            script: None,
            json: args.json,
            realtime: false,
            csv: args.csv.clone(),
            plot: args.plot.clone(),
            fg: args.fg.clone(),
            origin: scenario.origin,
            start: crate::start::StartArgs::default(),
            dis: crate::dis::FlightDisArgs::default(),
            record: args.record.clone(),
            acmi: args.acmi.clone(),
        };
        let measures = SharedOutput::new(MeasureOutput::<M>::new(
            study,
            run,
            scenario.start.aircraft.clone(),
        ));
        // The flight outputs of the options (headless) with the run's own
        // start and script.
        let mut config = crate::config::prepare_model(common, scenario.start)?;
        config.scenario.script = scenario.script;
        let attached = measures.clone();
        crate::flight::run_model_with(config, move |flight| flight.attach(attached))?;
        let table = measures
            .take()
            .map(|m| m.table())
            .unwrap_or_else(|| study.empty_table());
        // A signal ended the flight early (its own outputs are finished for the
        // frames flown, as `sim-cli palmer`'s): its measures are not the batch's
        // row, so run-I.csv is not written.
        if crate::signals::stop_requested().is_some() && table.frames.first() != Some(&frames) {
            return Ok(());
        }
        let mut text = Vec::new();
        write_csv(&mut text, &table).context("run row")?;
        std::fs::write(&path, &text).with_context(|| format!("writing {}", path.display()))?;
        Ok(())
    }
}
