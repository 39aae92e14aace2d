//! A whole study flown in chunks and streamed to its outputs: the rows of
//! every chunk appended to `runs.csv` and `runs.arrow` as soon as they are
//! flown (so memory stays bounded whatever the number of runs), the summary
//! built as they go, and what the study's plot needs kept in bounded memory
//! (touchdown points, a thinned sample of ground tracks, [`TrackPlan`]).
//! What `sim-cli study FILE.toml` does ([`Batch`]); the caller creates the
//! files, draws the plot and writes the summary.
//!
//! A stop request (a closure, e.g. a signal handler's flag) ends the flying
//! within milliseconds inside the chunk in flight; the runs completed before
//! it, 0 to K - 1, are written and summarised as at a normal end
//! ([`Batch::completed`], [`crate::Summary::stopped`]).
//!
//! ```
//! use fdm_study::batch::Batch;
//! use fdm_study::{FlyOptions, Study};
//!
//! let study = Study::from_toml_str(
//!     "model = \"palmer\"\nruns = 4\nduration_s = 1.0\nmeasures = [\"max_height_m\"]\n",
//! )?;
//! let mut batch = Batch::new(&study, FlyOptions { threads: 1, ..FlyOptions::default() }, 100);
//! let (mut csv, mut arrow) = (Vec::new(), Vec::new());
//! batch.write_csv_header(&mut csv)?;
//! let mut arrow_writer = batch.arrow_writer(&mut arrow)?;
//! while batch.fly_chunk(&mut csv, &mut arrow_writer, || false)? {}
//! arrow_writer.finish()?;
//! assert_eq!(batch.completed(), 4);
//! assert_eq!(String::from_utf8_lossy(&csv).lines().count(), 1 + 4);
//! assert_eq!(batch.summary().runs, 4);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

use std::io::{self, Write};

use crate::arrow::ArrowWriter;
use crate::fly::{FlyOptions, BLOCK_RUNS};
use crate::memory::MemoryEstimate;
use crate::spec::Study;
use crate::summary::{Summary, SummaryBuilder};
use crate::table::{write_csv_header, write_csv_rows, RunTable};
use crate::track::{GroundTrack, TrackPlan};
use crate::StudyError;

/// Blocks of runs per chunk and thread: a chunk is flown, written and
/// dropped before the next, so memory stays bounded whatever the number of
/// runs.
pub const BLOCKS_PER_THREAD_PER_CHUNK: u64 = 8;

/// Why a chunk was not flown or written.
#[derive(Debug, thiserror::Error)]
pub enum BatchError {
    /// Flying failed (e.g. the fleet refused the precision:
    /// [`StudyError::Fleet`]).
    #[error(transparent)]
    Fly(#[from] StudyError),
    /// Writing or flushing the CSV failed.
    #[error("writing the runs' CSV")]
    Csv(#[source] io::Error),
    /// Writing the Arrow file failed.
    #[error("writing the runs' Arrow file")]
    Arrow(#[source] io::Error),
}

/// A study being flown chunk by chunk into its outputs.
#[derive(Debug)]
pub struct Batch<'a> {
    study: &'a Study,
    options: FlyOptions,
    chunk_runs: u64,
    plan: TrackPlan,
    summary: SummaryBuilder,
    /// The `touchdown_x_m` and `touchdown_y_m` measure columns, if measured.
    touchdown_columns: Option<(usize, usize)>,
    touchdowns: Vec<(f64, f64)>,
    max_touchdowns: usize,
    tracks: Vec<GroundTrack>,
    completed: u64,
}

impl<'a> Batch<'a> {
    /// Runs flown at once with `threads` threads:
    /// [`BLOCK_RUNS`] × [`BLOCKS_PER_THREAD_PER_CHUNK`] per thread.
    #[must_use]
    pub fn chunk_runs(threads: usize) -> u64 {
        BLOCK_RUNS * BLOCKS_PER_THREAD_PER_CHUNK * u64::try_from(threads).unwrap_or(1)
    }

    /// A batch of every run of `study`, flown with `options`, keeping at
    /// most `max_touchdowns` touchdown points (the first runs') and the
    /// ground tracks of [`TrackPlan::spread`]'s default sample (at most 50
    /// runs of about 300 points, under 0.5 MB whatever the number of runs).
    #[must_use]
    pub fn new(study: &'a Study, options: FlyOptions, max_touchdowns: usize) -> Self {
        let plan = TrackPlan::spread(
            study.runs(),
            study.frames(),
            TrackPlan::DEFAULT_TRACKS,
            TrackPlan::DEFAULT_POINTS,
        );
        let mut summary = SummaryBuilder::new();
        // Every measure's entry, even if a stop comes before the first run.
        summary.add(&RunTable::empty(study.measures()));
        let names = study.measure_names();
        let column = |name: &str| names.iter().position(|n| n == name);
        Self {
            study,
            chunk_runs: Self::chunk_runs(options.threads),
            options,
            tracks: Vec::with_capacity(plan.runs().len()),
            plan,
            summary,
            touchdown_columns: column("touchdown_x_m").zip(column("touchdown_y_m")),
            touchdowns: Vec::new(),
            max_touchdowns,
            completed: 0,
        }
    }

    /// The memory the batch needs ([`Study::memory`] of a chunk).
    #[must_use]
    pub fn memory(&self) -> MemoryEstimate {
        self.study.memory(self.chunk_runs)
    }

    /// Writes the CSV's header line.
    ///
    /// # Errors
    /// [`BatchError::Csv`] if writing fails.
    pub fn write_csv_header(&self, csv: &mut impl Write) -> Result<(), BatchError> {
        write_csv_header(csv, &self.study.empty_table()).map_err(BatchError::Csv)
    }

    /// The Arrow file's writer on `out` (its schema written).
    ///
    /// # Errors
    /// [`BatchError::Arrow`] if writing fails.
    pub fn arrow_writer<W: Write>(&self, out: W) -> Result<ArrowWriter<W>, BatchError> {
        ArrowWriter::new(out, &self.study.empty_table()).map_err(BatchError::Arrow)
    }

    /// Flies the next chunk of runs and appends its rows to `csv` (flushed:
    /// what a reader or a killed process sees grows chunk by chunk) and
    /// `arrow`, unless every run is flown or `stop()` says so. Returns
    /// whether a chunk was flown (`false`: the batch is over; a stop inside
    /// the chunk keeps the runs completed before it).
    ///
    /// # Errors
    /// [`BatchError::Fly`] if flying fails, [`BatchError::Csv`] or
    /// [`BatchError::Arrow`] if writing does.
    pub fn fly_chunk<C: Write, A: Write>(
        &mut self,
        csv: &mut C,
        arrow: &mut ArrowWriter<A>,
        stop: impl Fn() -> bool + Sync,
    ) -> Result<bool, BatchError> {
        let start = self.completed;
        if start >= self.study.runs() || stop() {
            return Ok(false);
        }
        let end = (start + self.chunk_runs).min(self.study.runs());
        let (table, chunk_tracks) =
            self.study
                .fly_runs_tracked(start..end, &self.options, stop, &self.plan)?;
        self.tracks.extend(chunk_tracks);
        if table.is_empty() {
            return Ok(false);
        }
        write_csv_rows(csv, &table).map_err(BatchError::Csv)?;
        csv.flush().map_err(BatchError::Csv)?;
        arrow.write(&table).map_err(BatchError::Arrow)?;
        self.summary.add(&table);
        if let Some((x, y)) = self.touchdown_columns {
            // Touchdown points for the scatter (east = −y, north = x).
            let room = self.max_touchdowns.saturating_sub(self.touchdowns.len());
            self.touchdowns.extend(
                table.measures[x]
                    .1
                    .iter()
                    .zip(&table.measures[y].1)
                    .filter_map(|(x, y)| Some((-(*y)?, (*x)?)))
                    .take(room),
            );
        }
        self.completed += table.len() as u64;
        Ok(true)
    }

    /// Runs flown and written so far: runs `0..completed`.
    #[must_use]
    pub fn completed(&self) -> u64 {
        self.completed
    }

    /// Every measure's values so far (the summary's histograms).
    #[must_use]
    pub fn measure_values(&self) -> &[(String, Vec<f64>)] {
        self.summary.measure_values()
    }

    /// Touchdown points so far, `(east_m, north_m)`, at most the batch's
    /// `max_touchdowns`.
    #[must_use]
    pub fn touchdowns(&self) -> &[(f64, f64)] {
        &self.touchdowns
    }

    /// The sampled ground tracks so far.
    #[must_use]
    pub fn tracks(&self) -> &[GroundTrack] {
        &self.tracks
    }

    /// Frames between two points of a ground track.
    #[must_use]
    pub fn frame_step(&self) -> u64 {
        self.plan.frame_step()
    }

    /// The summary of the runs flown, with the study's seed (the caller
    /// marks it [`Summary::stopped`] when [`Self::completed`] is short of
    /// the study's runs, or calls [`Self::summary_stopped_by`]).
    #[must_use]
    pub fn summary(self) -> Summary {
        self.summary.finish().with_seed(self.study.seed())
    }

    /// [`Self::summary`], marked as stopped by `by` (e.g. `SIGTERM`) when
    /// the batch ended before the study's last run (only a stop ends the
    /// flying early: an error returns from [`Self::fly_chunk`]).
    #[must_use]
    pub fn summary_stopped_by(self, by: &str) -> Summary {
        let (completed, runs) = (self.completed, self.study.runs());
        let summary = self.summary();
        if completed < runs {
            summary.stopped(by, runs)
        } else {
            summary
        }
    }
}

/// Why a run was not made ready to fly alone ([`scenario_alone`]).
#[derive(Debug, thiserror::Error)]
pub enum AloneError {
    /// Flying the run in a batch of one (to learn where it stops) failed.
    #[error(transparent)]
    Fly(StudyError),
    /// The run's start is refused (its drawn conditions cannot be flown or
    /// trimmed): why.
    #[error("{0}")]
    Refused(String),
}

/// Run `run` of `study` as a scenario of the run library, to fly alone with
/// every output of a single flight (`sim-cli study FILE --run I`): its
/// start, script and origin, and as many frames as it flies in the batch
/// (its stop), so that with a [`crate::MeasureOutput`] attached its row is
/// the batch's, bit for bit. The batch of one is flown with exact maths on
/// one thread; `Ok(None)` when `stop()` ended it first.
///
/// # Errors
/// [`AloneError::Fly`] if that flight fails, [`AloneError::Refused`] if the
/// run's start is refused.
pub fn scenario_alone<M: crate::StudyModel>(
    study: &Study,
    run: u64,
    stop: impl Fn() -> bool + Sync,
) -> Result<Option<fdm_run::Scenario<M>>, AloneError> {
    let options = FlyOptions {
        threads: 1,
        precision: fdm_fleet::Precision::Exact,
    };
    let batch = study
        .fly_runs_until(run..run + 1, &options, stop)
        .map_err(AloneError::Fly)?;
    if batch.is_empty() {
        return Ok(None);
    }
    if batch.status.first() == Some(&crate::RunStatus::StartRefused) {
        let reason = study
            .scenario::<M>(run, 0)
            .err()
            .map_or_else(|| "refused".to_owned(), |e| e.to_string());
        return Err(AloneError::Refused(reason));
    }
    let frames = batch.frames.first().copied().unwrap_or(0);
    study
        .scenario::<M>(run, frames)
        .map(Some)
        .map_err(|e| AloneError::Refused(e.to_string()))
}

#[cfg(test)]
mod tests {
    use super::*;
    use fdm_core::palmer::Palmer;

    fn study() -> Study {
        Study::from_toml_str(
            "model = \"palmer\"\nruns = 3\nduration_s = 1.0\n\
             measures = [\"max_height_m\", \"touchdown_x_m\", \"touchdown_y_m\"]\n",
        )
        .unwrap()
    }

    #[test]
    fn a_stop_before_the_first_chunk_writes_the_headers_and_no_row() {
        let study = study();
        let mut batch = Batch::new(&study, FlyOptions::default(), 10);
        let mut csv = Vec::new();
        batch.write_csv_header(&mut csv).unwrap();
        let mut arrow = batch.arrow_writer(Vec::new()).unwrap();
        assert!(!batch.fly_chunk(&mut csv, &mut arrow, || true).unwrap());
        assert_eq!(batch.completed(), 0);
        assert_eq!(String::from_utf8(csv).unwrap().lines().count(), 1);
        let summary = batch.summary_stopped_by("SIGTERM");
        assert_eq!(summary.runs, 0);
        assert_eq!(
            summary.stopped.map(|s| (s.by, s.runs_planned)),
            Some(("SIGTERM".to_owned(), 3))
        );
    }

    #[test]
    fn a_batch_flown_to_its_end_is_not_stopped() {
        let study = study();
        let mut batch = Batch::new(&study, FlyOptions::default(), 10);
        let (mut csv, mut arrow) = (Vec::new(), batch.arrow_writer(Vec::new()).unwrap());
        while batch.fly_chunk(&mut csv, &mut arrow, || false).unwrap() {}
        assert_eq!(batch.summary_stopped_by("SIGTERM").stopped, None);
    }

    #[test]
    fn every_run_is_flown_once_and_the_touchdowns_are_bounded() {
        let study = study();
        let mut batch = Batch::new(&study, FlyOptions::default(), 1);
        let mut csv = Vec::new();
        let mut arrow = batch.arrow_writer(Vec::new()).unwrap();
        let mut chunks = 0;
        while batch.fly_chunk(&mut csv, &mut arrow, || false).unwrap() {
            chunks += 1;
        }
        assert_eq!(chunks, 1);
        assert_eq!(batch.completed(), 3);
        assert!(batch.touchdowns().len() <= 1);
        assert_eq!(batch.measure_values().len(), study.measure_names().len());
        assert_eq!(String::from_utf8(csv).unwrap().lines().count(), 3);
    }

    /// What the batch keeps for the plots, against the table of the same
    /// runs: the touchdown scatter is each touched-down run's `(east,
    /// north)` = `(−touchdown_y_m, touchdown_x_m)`, in run order, at most
    /// `max_touchdowns`; every run of a study of 4 is tracked from frame 0
    /// every `frame_step` frames to its last frame, where (the study stops
    /// at touchdown) it is at its touchdown point. A chunk is
    /// `BLOCK_RUNS × BLOCKS_PER_THREAD_PER_CHUNK` runs per thread.
    #[test]
    fn the_scatter_and_the_tracks_are_the_runs_touchdowns_and_frames() {
        let study = Study::from_toml_str(
            "model = \"palmer\"\nruns = 4\nseed = 3\nduration_s = 40.0\nstop = \"touchdown\"\n\
             measures = [\"touchdown_x_m\", \"touchdown_y_m\"]\n\
             script = \"1-20 throttle-down\"\n\
             [initial]\naltitude_ft = 150.0\nspeed_kt = 65.0\nheading_deg = 30.0\ntrim = true\n\
             [[dispersion]]\nkey = \"initial.speed_kt\"\ndistribution = \"uniform\"\n\
             low = 60.0\nhigh = 70.0\n",
        )
        .unwrap();
        let options = FlyOptions {
            threads: 1,
            ..FlyOptions::default()
        };
        let table = study.fly_runs(0..4, &options).unwrap();
        let mut batch = Batch::new(&study, options, 3);
        let (mut csv, mut arrow) = (Vec::new(), batch.arrow_writer(Vec::new()).unwrap());
        while batch.fly_chunk(&mut csv, &mut arrow, || false).unwrap() {}
        let (x, y) = (&table.measures[0].1, &table.measures[1].1);
        let points: Vec<(f64, f64)> = x
            .iter()
            .zip(y)
            .filter_map(|(x, y)| Some((-(*y)?, (*x)?)))
            .collect();
        assert_eq!(points.len(), 4, "every run touches down");
        // Heading 30 degrees: north and east of the start, both non-zero.
        assert!(
            points.iter().all(|&(e, n)| e > 0.0 && n > 0.0),
            "{points:?}"
        );
        assert_eq!(batch.touchdowns(), &points[..3]);
        let step = TrackPlan::spread(4, study.frames(), 50, 300).frame_step();
        assert_eq!((batch.frame_step(), step), (4, 4));
        assert_eq!(batch.tracks().len(), 4);
        for (run, track) in batch.tracks().iter().enumerate() {
            assert_eq!(track.run, run as u64);
            let last = table.frames[run];
            let mut want: Vec<u64> = (0..=last).step_by(4).collect();
            if want.last() != Some(&last) {
                want.push(last);
            }
            assert_eq!(track.frames, want, "run {run}");
            let [px, py, _] = *track.position_m.last().unwrap();
            assert_eq!((px, py), (x[run].unwrap(), y[run].unwrap()), "run {run}");
        }
        assert_eq!(
            Batch::chunk_runs(1),
            BLOCK_RUNS * BLOCKS_PER_THREAD_PER_CHUNK
        );
        assert_eq!(
            Batch::chunk_runs(3),
            3 * BLOCK_RUNS * BLOCKS_PER_THREAD_PER_CHUNK
        );
    }

    /// The scenario of a run flown alone has the frames the batch flew.
    #[test]
    fn a_run_alone_stops_where_the_batch_does() {
        let study = study();
        let table = study.fly_runs(1..2, &FlyOptions::default()).unwrap();
        let scenario = scenario_alone::<Palmer>(&study, 1, || false)
            .unwrap()
            .unwrap();
        assert_eq!(Some(&scenario.frames), table.frames.first());
        assert!(scenario_alone::<Palmer>(&study, 1, || true)
            .unwrap()
            .is_none());
        assert!(matches!(
            scenario_alone::<Palmer>(&study, 3, || false),
            Err(AloneError::Fly(StudyError::Range { .. }))
        ));
    }
}
