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
//! The file format, the measures and the guarantees: docs/studies.md.

use std::io::{BufWriter, IsTerminal, Write};
use std::path::{Path, PathBuf};

use anyhow::Context as _;
use fdm_core::bourg::Bourg;
use fdm_core::model::Model;
use fdm_core::palmer::Palmer;
use fdm_fleet::Precision;
use fdm_run::SharedOutput;
use fdm_study::arrow::ArrowWriter;
use fdm_study::table::{write_csv_header, write_csv_rows};
use fdm_study::{
    FlyOptions, GroundTrack, MeasureOutput, RunStatus, RunTable, Study, StudyModel, SummaryBuilder,
    TrackPlan,
};

use crate::args::{CommonArgs, FleetPrecision, StudyArgs};
use crate::error::CliError;
use crate::models::CliModel;
use crate::progress::StderrProgress;
use crate::signals::SignalSafeWriter;

/// Blocks of runs per chunk and thread: a chunk is flown, written and
/// dropped before the next, so memory stays bounded whatever the number of
/// runs.
const BLOCKS_PER_THREAD_PER_CHUNK: u64 = 8;

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
    let mut study = Study::from_path(&args.file).map_err(|e| usage(e, &args.file))?;
    if let Some(runs) = args.runs {
        study = study.with_runs(runs).map_err(|e| usage(e, &args.file))?;
    }
    if let Some(seed) = args.seed {
        study = study.with_seed(seed);
    }
    let precision = match args.precision {
        FleetPrecision::Exact => Precision::Exact,
        FleetPrecision::Fast => Precision::Fast,
    };
    let out_dir = match &args.out {
        Some(dir) => dir.clone(),
        None => args
            .file
            .parent()
            .map_or_else(|| PathBuf::from("."), Path::to_path_buf),
    };
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
            match study.model() {
                n if n == Palmer::NAME => run_alone::<Palmer>(&study, run, args, &out_dir),
                n if n == Bourg::NAME => run_alone::<Bourg>(&study, run, args, &out_dir),
                other => Err(CliError::usage(format!("no model {other}"))),
            }
        }
        None => batch(&study, precision, args, &out_dir),
    }
}

/// Flies the whole study in chunks, streaming `runs.csv`.
fn batch(
    study: &Study,
    precision: Precision,
    args: &StudyArgs,
    out_dir: &Path,
) -> Result<(), CliError> {
    let threads = args
        .threads
        .unwrap_or_else(|| std::thread::available_parallelism().map_or(1, usize::from));
    let options = FlyOptions { threads, precision };
    let chunk_runs =
        fdm_study::BLOCK_RUNS * BLOCKS_PER_THREAD_PER_CHUNK * u64::try_from(threads).unwrap_or(1);
    let memory = study.memory(chunk_runs);
    let limit = args.memory_limit_mib.saturating_mul(1024 * 1024);
    if memory.total > limit {
        return Err(CliError::usage(format!(
            "the study needs about {} MiB ({} runs × {} bytes kept + {} runs in flight × {} bytes), \
             more than --memory-limit-mib {}",
            memory.total.div_ceil(1024 * 1024),
            study.runs(),
            memory.kept_per_run,
            memory.chunk_runs.min(study.runs()),
            memory.flying_per_run,
            args.memory_limit_mib
        )));
    }
    if let Some(have) = crate::memory::available_bytes().filter(|&have| memory.total > have) {
        return Err(CliError::usage(format!(
            "the study needs about {} MiB; this process has {} MiB available (the machine's \
             available memory, the address-space limit and the cgroup's memory limit)",
            memory.total.div_ceil(1024 * 1024),
            have / (1024 * 1024)
        )));
    }
    let csv_path = out_dir.join("runs.csv");
    // Locked as every output file of a run (docs/cli.md, "One writer per output
    // file"): two studies writing into one directory are refused, not spliced.
    let file = crate::outfile::create_locked(&csv_path)
        .map_err(|e| CliError::usage(format!("cannot create {}: {e}", csv_path.display())))?;
    // Registered with the signal thread: if the process must end at once (a
    // second signal), the file still ends with a whole row.
    let mut csv = SignalSafeWriter::register(file);
    write_csv_header(&mut csv, &study.empty_table())
        .with_context(|| format!("writing {}", csv_path.display()))?;
    let arrow_path = out_dir.join("runs.arrow");
    let arrow_file = crate::outfile::create_locked(&arrow_path)
        .map_err(|e| CliError::usage(format!("cannot create {}: {e}", arrow_path.display())))?;
    let mut arrow = ArrowWriter::new(
        BufWriter::with_capacity(1 << 16, arrow_file),
        &study.empty_table(),
    )
    .with_context(|| format!("writing {}", arrow_path.display()))?;
    let mut summary = SummaryBuilder::new();
    // Every measure's entry, even if a stop comes before the first run.
    summary.add(&RunTable::empty(study.measures()));
    // Touchdown points for the scatter (east = −y, north = x), the first
    // runs' up to the plot's limit.
    let names = study.measure_names();
    let column = |name: &str| names.iter().position(|n| n == name);
    let touchdown_columns = column("touchdown_x_m").zip(column("touchdown_y_m"));
    let mut touchdowns: Vec<(f64, f64)> = Vec::new();
    // The ground tracks of study.svg: a bounded sample (at most 50 runs of
    // at most about 300 points, under 0.5 MB whatever the number of runs).
    let plan = TrackPlan::spread(
        study.runs(),
        study.frames(),
        TrackPlan::DEFAULT_TRACKS,
        TrackPlan::DEFAULT_POINTS,
    );
    let mut tracks: Vec<GroundTrack> = Vec::with_capacity(plan.runs().len());
    let mut progress = StderrProgress::with_enabled(study.runs(), std::io::stderr().is_terminal());
    // A signal (crate::signals) stops the flying within milliseconds, inside
    // the chunk; the runs completed before it, runs 0 to start - 1, are
    // written and summarised as at a normal end.
    let stop = || crate::signals::stop_requested().is_some();
    let mut start = 0;
    while start < study.runs() && !stop() {
        let end = (start + chunk_runs).min(study.runs());
        let (table, chunk_tracks) = study
            .fly_runs_tracked(start..end, &options, stop, &plan)
            .map_err(|e| match e {
                fdm_study::StudyError::Fleet(_) => CliError::usage(e.to_string()),
                e => CliError::runtime(e),
            })?;
        tracks.extend(chunk_tracks);
        if table.is_empty() {
            break;
        }
        write_csv_rows(&mut csv, &table)
            .with_context(|| format!("writing {}", csv_path.display()))?;
        // Each finished chunk on disk (whole rows): what a reader or a
        // killed process sees grows chunk by chunk.
        csv.flush()
            .with_context(|| format!("writing {}", csv_path.display()))?;
        arrow
            .write(&table)
            .with_context(|| format!("writing {}", arrow_path.display()))?;
        summary.add(&table);
        if let Some((x, y)) = touchdown_columns {
            let room = fdm_plot::study::MAX_SCATTER_POINTS.saturating_sub(touchdowns.len());
            touchdowns.extend(
                table.measures[x]
                    .1
                    .iter()
                    .zip(&table.measures[y].1)
                    .filter_map(|(x, y)| Some((-(*y)?, (*x)?)))
                    .take(room),
            );
        }
        start += table.len() as u64;
        progress.tick(start - start % 64);
    }
    progress.finish();
    csv.flush()
        .with_context(|| format!("writing {}", csv_path.display()))?;
    arrow
        .finish()
        .with_context(|| format!("writing {}", arrow_path.display()))?;
    let svg = fdm_plot::study::render(
        summary.measure_values(),
        &touchdowns,
        &tracks,
        plan.frame_step(),
    )?;
    let plot_path = out_dir.join("study.svg");
    std::fs::write(&plot_path, svg).with_context(|| format!("writing {}", plot_path.display()))?;
    let mut summary = summary.finish().with_seed(study.seed());
    if start < study.runs() {
        // Only a stop ends the loop early (errors return above).
        let by = crate::signals::stop_requested().map_or("a signal", crate::signals::signal_name);
        summary = summary.stopped(by, study.runs());
    }
    let json = serde_json::to_string_pretty(&summary).context("summary as JSON")?;
    let summary_path = out_dir.join("summary.json");
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

/// Flies run `run` alone through the run library with the single-flight
/// outputs, and writes its row (`run-I.csv`, the batch's format).
fn run_alone<M: CliModel + StudyModel>(
    study: &Study,
    run: u64,
    args: &StudyArgs,
    out_dir: &Path,
) -> Result<(), CliError> {
    if run >= study.runs() {
        return Err(CliError::usage(format!(
            "--run {run}: the study has runs 0 to {}",
            study.runs() - 1
        )));
    }
    // The batch's row of this run: how many frames it flew (its stop).
    let options = FlyOptions {
        threads: 1,
        precision: Precision::Exact,
    };
    // A signal during this flight ends the command before the flight alone
    // (nothing written; exit 128 + N, crate::signals).
    let batch = study
        .fly_runs_until(run..run + 1, &options, || {
            crate::signals::stop_requested().is_some()
        })
        .map_err(CliError::runtime)?;
    if batch.is_empty() {
        return Ok(());
    }
    if batch.status.first() == Some(&RunStatus::StartRefused) {
        let reason = study
            .scenario::<M>(run, 0)
            .err()
            .map_or_else(|| "refused".to_owned(), |e| e.to_string());
        return Err(CliError::usage(reason));
    }
    let frames = batch.frames.first().copied().unwrap_or(0);
    let scenario = study
        .scenario::<M>(run, frames)
        .map_err(|e| CliError::usage(e.to_string()))?;
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
    let config = crate::config::prepare_study_run(common, scenario.start, scenario.script)?;
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
    let path = out_dir.join(format!("run-{run}.csv"));
    let mut text = Vec::new();
    write_csv_header(&mut text, &table).context("run row")?;
    write_csv_rows(&mut text, &table).context("run row")?;
    std::fs::write(&path, &text).with_context(|| format!("writing {}", path.display()))?;
    Ok(())
}
