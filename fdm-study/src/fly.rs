//! Flying a study's runs: blocks of runs on SIMD fleets, on several threads,
//! into a [`RunTable`]; and [`MeasureOutput`], the same measures for a run
//! flown alone through `fdm_run`.

use std::ops::Range;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::Mutex;

use fdm_core::model::{FlightStatus, Model};
use fdm_core::script::Script;
use fdm_fleet::{Fleet, Precision};
use fdm_run::{Event, Frame, Output, OutputError};

use crate::measure::{needs_view, Measure, Tracker};
use crate::memory::MemoryEstimate;
use crate::model::{StudyJob, StudyModel};
use crate::spec::{FlyJob, MemoryJob, RunSetup, Stop, Study};
use crate::table::{Row, RunStatus, RunTable};
use crate::track::{GroundTrack, TrackPlan};
use crate::StudyError;

/// Runs per block: each block is one set of fleets flown on one thread, its
/// rows appended in run order. Small enough to balance threads and keep a
/// block's states in cache, large enough that the per-block set-up is noise.
pub const BLOCK_RUNS: u64 = 1024;

/// Frames between two looks at the stop request of
/// [`Study::fly_runs_until`] inside a block: often enough that a block of
/// [`BLOCK_RUNS`] runs gives up within milliseconds, rarely enough that the
/// caller's check costs nothing next to the frames.
const STOP_CHECK_FRAMES: u64 = 16;

/// How [`Study::fly_runs`] flies.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct FlyOptions {
    /// Worker threads (at least 1).
    pub threads: usize,
    /// The fleets' maths: `Exact` (every run bit-identical to the run flown
    /// alone) or `Fast` (Palmer only).
    pub precision: Precision,
}

impl Default for FlyOptions {
    /// One thread per available core, exact maths.
    fn default() -> Self {
        Self {
            threads: std::thread::available_parallelism().map_or(1, usize::from),
            precision: Precision::Exact,
        }
    }
}

/// Whether a run stops now under `stop`.
fn stops(stop: Stop, tracker: &Tracker) -> bool {
    match stop {
        Stop::Duration => false,
        Stop::Touchdown => tracker.touched_down() || tracker.status().is_final(),
    }
}

impl Study {
    /// Flies runs `runs.start..runs.end` (in run order) on `options.threads`
    /// threads with `options.precision`, in blocks of [`BLOCK_RUNS`] runs on
    /// SIMD fleets. The result for run `i` never depends on the range, the
    /// thread count or the block layout: each run's values come from its own
    /// random stream, and each fleet lane is flown alone.
    ///
    /// Runs whose aircraft is the same share a fleet; with dispersed
    /// physical parameters every run flies in a fleet of its own (still on
    /// the fleet's lanes, so with the same bits).
    ///
    /// # Errors
    /// [`StudyError::Range`] for runs past [`Study::runs`], a precision the
    /// model has not ([`StudyError::Fleet`]), no thread, or a table of the
    /// runs that would not fit in the memory this process can still
    /// allocate ([`StudyError::TableMemory`], before anything is flown).
    pub fn fly_runs(&self, runs: Range<u64>, options: &FlyOptions) -> Result<RunTable, StudyError> {
        self.fly_runs_until(runs, options, || false)
    }

    /// [`Study::fly_runs`] that can be stopped: `stop` is asked before each
    /// block and every few frames while one flies (from every worker
    /// thread, so it should be cheap, e.g. an atomic load); once it has
    /// answered `true`, the blocks in flight are given up, no new block is
    /// started, and the result is the rows of the runs completed before
    /// the stop that follow each other from `runs.start` on: runs
    /// `runs.start..runs.start + K` for some `K` from 0 to the range's
    /// length, in run order, without gaps (a block finished after one
    /// that was given up is dropped too). Each row is the same bits as
    /// [`Study::fly_runs`] gives for that run; the runs `K..` can be flown
    /// later (`fly_runs_until(runs.start + K..runs.end, ..)`) and the
    /// tables joined with [`RunTable::append`].
    ///
    /// The table is shorter than the range only when `stop` answered
    /// `true`; a stop that comes after the last block has finished changes
    /// nothing. A block is [`BLOCK_RUNS`] runs, so a stop loses at most
    /// that many runs' work per thread.
    ///
    /// ```
    /// use std::sync::atomic::{AtomicBool, Ordering};
    /// use fdm_study::{FlyOptions, Study};
    ///
    /// let study = Study::from_toml_str(
    ///     "model = \"palmer\"\nruns = 3000\nduration_s = 1.0\nmeasures = [\"max_height_m\"]\n",
    /// )?;
    /// // Already asked to stop (e.g. by a signal handler): nothing is flown.
    /// let stop = AtomicBool::new(true);
    /// let table = study.fly_runs_until(0..3000, &FlyOptions::default(), || {
    ///     stop.load(Ordering::Relaxed)
    /// })?;
    /// assert!(table.is_empty());
    /// // Never asked: the whole range, as `fly_runs` gives it.
    /// let all = study.fly_runs_until(0..3000, &FlyOptions::default(), || false)?;
    /// assert_eq!(all.len(), 3000);
    /// # Ok::<(), fdm_study::StudyError>(())
    /// ```
    ///
    /// # Errors
    /// As [`Study::fly_runs`].
    pub fn fly_runs_until(
        &self,
        runs: Range<u64>,
        options: &FlyOptions,
        stop: impl Fn() -> bool + Sync,
    ) -> Result<RunTable, StudyError> {
        self.fly_runs_tracked(runs, options, stop, &TrackPlan::none())
            .map(|(table, _)| table)
    }

    /// [`Study::fly_runs_until`] that also keeps the thinned ground tracks
    /// of the runs of `plan` within `runs` (those of the rows returned,
    /// in run order): each the positions at the frames the plan keeps,
    /// the same bits as the run flown alone gives at those frames. The
    /// table is [`Study::fly_runs_until`]'s, bit for bit.
    ///
    /// ```
    /// use fdm_study::track::TrackPlan;
    /// use fdm_study::{FlyOptions, Study};
    ///
    /// let study = Study::from_toml_str(
    ///     "model = \"palmer\"\nruns = 100\nduration_s = 2.0\nmeasures = [\"final_x_m\"]\n",
    /// )?;
    /// let plan = TrackPlan::spread(study.runs(), study.frames(), 4, 10);
    /// assert_eq!(plan.runs(), [0, 25, 50, 75]);
    /// let (table, tracks) =
    ///     study.fly_runs_tracked(20..80, &FlyOptions::default(), || false, &plan)?;
    /// assert_eq!(table.len(), 60);
    /// let tracked: Vec<u64> = tracks.iter().map(|t| t.run).collect();
    /// assert_eq!(tracked, [25, 50, 75]);
    /// // 60 frames in steps of 6: frames 0, 6, ..., 60.
    /// assert_eq!(tracks[0].frames.len(), 11);
    /// # Ok::<(), fdm_study::StudyError>(())
    /// ```
    ///
    /// # Errors
    /// As [`Study::fly_runs`].
    pub fn fly_runs_tracked(
        &self,
        runs: Range<u64>,
        options: &FlyOptions,
        stop: impl Fn() -> bool + Sync,
        plan: &TrackPlan,
    ) -> Result<(RunTable, Vec<GroundTrack>), StudyError> {
        if runs.start > runs.end || runs.end > self.runs() {
            return Err(StudyError::Range {
                start: runs.start,
                end: runs.end,
                runs: self.runs(),
            });
        }
        if options.threads == 0 {
            return Err(StudyError::Threads);
        }
        self.check_table_memory(&runs, fdm_run::memory::available_bytes())?;
        self.entry().fly(FlyJob {
            study: self,
            runs,
            threads: options.threads,
            precision: options.precision,
            stop: &stop,
            plan,
        })
    }

    /// Flies one block of runs of model `M` (keeping the tracks of
    /// `plan`'s runs); `None` when `halt` answered `true` before the block
    /// was finished (the block is given up).
    #[allow(clippy::too_many_lines)]
    fn fly_block<M: StudyModel>(
        &self,
        runs: Range<u64>,
        precision: Precision,
        halt: &dyn Fn() -> bool,
        plan: &TrackPlan,
    ) -> Option<(RunTable, Vec<GroundTrack>)> {
        if halt() {
            return None;
        }
        let measures = self.measures();
        let count = usize::try_from(runs.end - runs.start).unwrap_or(0);
        let mut trackers: Vec<Option<Tracker>> = Vec::with_capacity(count);
        let mut statuses = vec![RunStatus::StartRefused; count];
        let mut frames = vec![0u64; count];
        let mut fingerprints: Vec<Option<u64>> = vec![None; count];
        let mut tracks: Vec<Option<GroundTrack>> = vec![None; count];
        let mut setups: Vec<Option<RunSetup<M>>> = Vec::with_capacity(count);
        // The draws of each run, from the same values its set-up is built
        // from: the `input.*` columns are the values flown.
        let mut drawn: Vec<Vec<f64>> = Vec::with_capacity(count);
        for run in runs.clone() {
            let values = self.run_values(run);
            setups.push(self.setup_from::<M>(&values).ok());
            drawn.push(values.drawn);
            trackers.push(None);
        }
        // Groups of runs sharing an aircraft, in run order.
        let mut groups: Vec<(M::Aircraft, Vec<usize>)> = Vec::new();
        for (i, setup) in setups.iter().enumerate() {
            let Some(setup) = setup else { continue };
            let aircraft = &setup.start.aircraft;
            let found = if self.disperses_aircraft() {
                groups.iter_mut().rev().take(8).find(|(a, _)| a == aircraft)
            } else {
                groups.first_mut()
            };
            match found {
                Some((_, members)) => members.push(i),
                None => groups.push((aircraft.clone(), vec![i])),
            }
        }
        let needs_bank = needs_view(measures);
        let dt = M::time_step(f64::from(self.fps()));
        for (aircraft, members) in groups {
            let Ok(mut fleet) = Fleet::<M>::try_new(aircraft.clone()) else {
                continue;
            };
            let mut scripts: Vec<&Script<M::Action>> = Vec::with_capacity(members.len());
            let mut group_trackers = Vec::with_capacity(members.len());
            let mut group_fingerprints: Vec<Option<u64>> = vec![None; members.len()];
            let mut group_tracks: Vec<Option<GroundTrack>> = Vec::with_capacity(members.len());
            for &i in &members {
                let Some(setup) = &setups[i] else { continue };
                fleet.push(setup.start.state, setup.start.controls);
                scripts.push(&setup.script);
                let run = runs.start + i as u64;
                group_tracks.push(plan.tracks(run).then(|| {
                    let mut track = GroundTrack::new(run);
                    track.keep(
                        0,
                        <M as fdm_fleet::LaneModel>::position_m(&setup.start.state).into(),
                    );
                    track
                }));
                let mut tracker = Tracker::new(self.fps(), self.target_height_m(), needs_bank);
                tracker.observe::<M>(
                    0,
                    &aircraft,
                    &setup.start.controls,
                    &setup.start.state,
                    FlightStatus::initial(M::height_m(&setup.start.state)),
                );
                group_trackers.push(tracker);
            }
            let mut stopped: Vec<bool> = group_trackers
                .iter()
                .map(|t| stops(self.stop(), t))
                .collect();
            // A run stopped at its start: its final state is its start.
            for (j, &i) in members.iter().enumerate() {
                if let (true, Some(setup)) = (stopped[j], &setups[i]) {
                    group_fingerprints[j] = Some(M::state_fingerprint(&setup.start.state));
                }
            }
            let mut flying = stopped.iter().filter(|s| !**s).count();
            let mut frame = 0;
            while frame < self.frames() && flying > 0 {
                if frame % STOP_CHECK_FRAMES == 0 && halt() {
                    return None;
                }
                frame += 1;
                for (j, script) in scripts.iter().enumerate() {
                    if stopped[j] {
                        continue;
                    }
                    let Some(before) = fleet.controls(j) else {
                        continue;
                    };
                    let mut controls = M::begin_frame(before);
                    for action in script.actions_at(frame) {
                        controls = M::apply(&aircraft, controls, action);
                    }
                    if controls != before {
                        let _ = fleet.set_controls(j, controls);
                    }
                }
                // `Fleet::fly_with` fails only for a precision the model has
                // not, checked before any block is flown.
                let _ = fleet.fly_with(dt, precision);
                for (j, tracker) in group_trackers.iter_mut().enumerate() {
                    if stopped[j] {
                        continue;
                    }
                    let Some(state) = fleet.state(j) else {
                        continue;
                    };
                    if let (Some(status), Some(controls)) = (fleet.status(j), fleet.controls(j)) {
                        tracker.observe::<M>(frame, &aircraft, &controls, &state, status);
                    }
                    let stops_now = stops(self.stop(), tracker);
                    let last = stops_now || frame == self.frames();
                    if let Some(track) = &mut group_tracks[j] {
                        if plan.keeps(frame, last) {
                            track.keep(
                                frame,
                                <M as fdm_fleet::LaneModel>::position_m(&state).into(),
                            );
                        }
                    }
                    if last {
                        // The run's final state: at its stop, or the
                        // study's last frame.
                        group_fingerprints[j] = Some(M::state_fingerprint(&state));
                    }
                    if stops_now {
                        stopped[j] = true;
                        flying -= 1;
                    }
                }
            }
            for (((&i, tracker), fingerprint), track) in members
                .iter()
                .zip(group_trackers)
                .zip(group_fingerprints)
                .zip(group_tracks)
            {
                statuses[i] = RunStatus::Flown(tracker.status());
                frames[i] = tracker.frames();
                trackers[i] = Some(tracker);
                fingerprints[i] = fingerprint;
                tracks[i] = track;
            }
        }
        let mut table = self.empty_table();
        for (k, run) in runs.enumerate() {
            table.push(
                Row {
                    run,
                    status: statuses[k],
                    frames: frames[k],
                    tracker: trackers[k].as_ref(),
                    inputs: &drawn[k],
                    fingerprint: fingerprints[k],
                },
                measures,
            );
        }
        Some((table, tracks.into_iter().flatten().collect()))
    }
}

/// A block's (or a range's) rows and the ground tracks kept.
type Flown = (RunTable, Vec<GroundTrack>);

impl StudyJob for FlyJob<'_> {
    type Output = Result<(RunTable, Vec<GroundTrack>), StudyError>;

    fn call<M: StudyModel>(self) -> Result<(RunTable, Vec<GroundTrack>), StudyError> {
        let FlyJob {
            study,
            runs,
            threads,
            precision,
            stop,
            plan,
        } = self;
        Fleet::<M>::check_precision(precision)?;
        // Latched: once the caller has asked to stop, every worker gives up
        // (even if the caller's answer would change back).
        let stopped = AtomicBool::new(false);
        let halt = || {
            stopped.load(Ordering::Relaxed) || {
                let now = stop();
                if now {
                    stopped.store(true, Ordering::Relaxed);
                }
                now
            }
        };
        let blocks: Vec<Range<u64>> = (runs.start..runs.end)
            .step_by(usize::try_from(BLOCK_RUNS).unwrap_or(1024))
            .map(|start| start..(start + BLOCK_RUNS).min(runs.end))
            .collect();
        let results: Vec<Mutex<Option<Flown>>> = blocks.iter().map(|_| Mutex::new(None)).collect();
        let next = AtomicUsize::new(0);
        let threads = threads.min(blocks.len()).max(1);
        std::thread::scope(|scope| {
            for _ in 0..threads {
                scope.spawn(|| loop {
                    let b = next.fetch_add(1, Ordering::Relaxed);
                    let Some(block) = blocks.get(b) else { break };
                    let Some(table) = study.fly_block::<M>(block.clone(), precision, &halt, plan)
                    else {
                        break;
                    };
                    if let Ok(mut slot) = results[b].lock() {
                        *slot = Some(table);
                    }
                });
            }
        });
        let mut table = study.empty_table();
        let mut tracks = Vec::new();
        let stopped = stopped.into_inner();
        for slot in results {
            match slot.into_inner().ok().flatten() {
                Some((block, block_tracks)) => {
                    table.append(block)?;
                    tracks.extend(block_tracks);
                }
                // The first block not flown ends the completed runs; the
                // blocks after it are dropped, so the rows have no gap.
                None if stopped => break,
                None => return Err(StudyError::Worker),
            }
        }
        Ok((table, tracks))
    }
}

/// The study's measures of a run flown alone through `fdm_run` (an
/// [`Output`]): attach it to the run's [`fdm_run::Run`] (or `sim-cli study
/// --run I`'s flight) from frame 0 on; it computes the measures with the
/// same code as the batch, so an exact run gives the batch's bits. It stops
/// observing at the study's stop condition; a reset ends its observations.
#[derive(Debug, Clone)]
pub struct MeasureOutput<M: Model> {
    aircraft: M::Aircraft,
    tracker: Tracker,
    stop: Stop,
    stopped: bool,
    run: u64,
    measures: Vec<Measure>,
    input_names: Vec<String>,
    inputs: Vec<f64>,
    fingerprint: Option<u64>,
}

impl<M: StudyModel> MeasureOutput<M> {
    /// The measures of run `run` of `study`, flown with `aircraft`.
    #[must_use]
    pub fn new(study: &Study, run: u64, aircraft: M::Aircraft) -> Self {
        Self {
            aircraft,
            tracker: Tracker::new(
                study.fps(),
                study.target_height_m(),
                needs_view(study.measures()),
            ),
            stop: study.stop(),
            stopped: false,
            run,
            measures: study.measures().to_vec(),
            input_names: study.input_names(),
            inputs: study
                .dispersed_values(run)
                .into_iter()
                .map(|(_, v)| v)
                .collect(),
            fingerprint: None,
        }
    }

    /// The run's row: its status, frames, measures, drawn inputs and the
    /// fingerprint of the last state observed (`None` before any frame).
    #[must_use]
    pub fn table(&self) -> RunTable {
        let mut table = RunTable::empty_with_inputs(&self.measures, &self.input_names);
        table.push(
            Row {
                run: self.run,
                status: RunStatus::Flown(self.tracker.status()),
                frames: self.tracker.frames(),
                tracker: Some(&self.tracker),
                inputs: &self.inputs,
                fingerprint: self.fingerprint,
            },
            &self.measures,
        );
        table
    }
}

impl<M: StudyModel> Output<M> for MeasureOutput<M> {
    fn frame(&mut self, frame: &Frame<'_, M>) -> Result<(), OutputError> {
        if self.stopped || frame.event == Event::Reset {
            self.stopped = true;
            return Ok(());
        }
        self.tracker.observe::<M>(
            frame.number,
            &self.aircraft,
            frame.controls,
            frame.state,
            frame.status,
        );
        self.fingerprint = Some(M::state_fingerprint(frame.state));
        self.stopped = stops(self.stop, &self.tracker);
        Ok(())
    }
}

impl Study {
    /// The memory a study of [`Study::runs`] runs flown in chunks of
    /// `chunk_runs` takes, by the sizes of its data structures (the
    /// program's own code and stacks aside).
    #[must_use]
    pub fn memory(&self, chunk_runs: u64) -> MemoryEstimate {
        self.entry().memory(MemoryJob {
            study: self,
            chunk_runs,
        })
    }

    /// Bytes one run takes in a [`RunTable`]: its index, status, frames,
    /// one `Option<f64>` per measure, one `f64` per drawn input and its
    /// fingerprint.
    #[must_use]
    pub fn table_bytes_per_run(&self) -> u64 {
        use core::mem::size_of;
        let bytes = size_of::<u64>() * 2
            + size_of::<RunStatus>()
            + self.measures().len() * size_of::<Option<f64>>()
            + self.input_names().len() * size_of::<f64>()
            + size_of::<Option<u64>>();
        bytes as u64
    }

    /// Refuses `runs` whose table (twice [`Study::table_bytes_per_run`]
    /// each: its columns double as they grow) exceeds `available_bytes`,
    /// before anything is flown: a clear error, not a table that grows
    /// until the machine runs out of memory. `None`: nothing to check
    /// against.
    fn check_table_memory(
        &self,
        runs: &Range<u64>,
        available_bytes: Option<u64>,
    ) -> Result<(), StudyError> {
        let per_run_bytes = self.table_bytes_per_run();
        let needed_bytes = (runs.end - runs.start)
            .saturating_mul(per_run_bytes)
            .saturating_mul(2);
        match available_bytes {
            Some(available_bytes) if needed_bytes > available_bytes => {
                Err(StudyError::TableMemory {
                    start: runs.start,
                    end: runs.end,
                    per_run_bytes,
                    needed_bytes,
                    available_bytes,
                })
            }
            _ => Ok(()),
        }
    }
}

impl StudyJob for MemoryJob<'_> {
    type Output = MemoryEstimate;

    fn call<M: StudyModel>(self) -> MemoryEstimate {
        use core::mem::size_of;
        let measures = self.study.measures().len();
        let script_rules = self.study.script_rules::<M>();
        let kept = (measures * crate::summary::SummaryBuilder::BYTES_PER_VALUE) as u64;
        let flying = size_of::<Option<RunSetup<M>>>()
            + script_rules * size_of::<fdm_core::script::Rule<M::Action>>()
            + Fleet::<M>::bytes_per_aircraft()
            + 2 * size_of::<Option<Tracker>>()
            + size_of::<u64>() * 2
            + size_of::<RunStatus>()
            + measures * size_of::<Option<f64>>()
            // The drawn inputs (the run's values and the table's column)
            // and the fingerprint (the block's and the table's).
            + 2 * self.study.input_names().len() * size_of::<f64>()
            + 4 * size_of::<Option<u64>>()
            + size_of::<Option<GroundTrack>>()
            + size_of::<bool>();
        let flying = flying as u64;
        let runs = self.study.runs();
        MemoryEstimate {
            kept_per_run: kept,
            flying_per_run: flying,
            chunk_runs: self.chunk_runs,
            total: runs
                .saturating_mul(kept)
                .saturating_add(self.chunk_runs.min(runs).saturating_mul(flying)),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_study_over_the_limit_or_the_available_memory_is_refused_with_its_numbers() {
        let estimate = MemoryEstimate {
            kept_per_run: 40,
            flying_per_run: 1000,
            chunk_runs: 4096,
            total: 3 * 1024 * 1024 + 1,
        };
        assert_eq!(estimate.check(10, 4, None), Ok(()));
        assert_eq!(
            estimate.check(10, 3, None).unwrap_err().to_string(),
            "the study needs about 4 MiB (10 runs × 40 bytes kept + 10 runs in flight × 1000 \
             bytes), more than --memory-limit-mib 3"
        );
        assert_eq!(
            estimate
                .check(10, 4, Some(2 * 1024 * 1024))
                .unwrap_err()
                .to_string(),
            "the study needs about 4 MiB; this process has 2 MiB available (the machine's \
             available memory, the address-space limit and the cgroup's memory limit)"
        );
        assert_eq!(estimate.check(10, 4, Some(estimate.total)), Ok(()));
        // Exactly the limit fits.
        let at_limit = MemoryEstimate {
            total: 3 * 1024 * 1024,
            ..estimate
        };
        assert_eq!(at_limit.check(10, 3, None), Ok(()));
    }

    /// A range of runs is refused when it ends before it starts or past the
    /// study's runs; an empty range within them flies nothing.
    #[test]
    fn a_range_of_runs_is_within_the_study() {
        let study = Study::from_toml_str(
            "model = \"palmer\"\nruns = 3\nduration_s = 0.5\nmeasures = [\"final_x_m\"]\n",
        )
        .unwrap();
        let options = FlyOptions::default();
        for empty in [0..0, 2..2, 3..3] {
            assert_eq!(
                study.fly_runs(empty.clone(), &options).unwrap().len(),
                0,
                "{empty:?}"
            );
        }
        assert_eq!(study.fly_runs(1..3, &options).unwrap().run, [1, 2]);
        for bad in [(2, 1), (0, 4), (3, 4)] {
            assert!(
                matches!(
                    study.fly_runs(bad.0..bad.1, &options),
                    Err(StudyError::Range { start, end, runs: 3 }) if (start, end) == bad
                ),
                "{bad:?}"
            );
        }
    }

    /// Two measures, one dispersion: 8 (run) + 8 (frames) + the status +
    /// 2 × 16 (`Option<f64>`) + 8 (the input) + 16 (`Option<u64>`) bytes.
    fn two_measures_one_input() -> Study {
        Study::from_toml_str(
            "model = \"palmer\"\nruns = 1099511627776\nduration_s = 1.0\n\
             measures = [\"max_height_m\", \"final_x_m\"]\n\
             [[dispersion]]\nkey = \"initial.speed_kt\"\ndistribution = \"uniform\"\n\
             low = 60.0\nhigh = 70.0\n",
        )
        .unwrap()
    }

    #[test]
    fn a_tables_bytes_per_run_are_its_columns() {
        let study = two_measures_one_input();
        let status = core::mem::size_of::<RunStatus>() as u64;
        assert_eq!(study.table_bytes_per_run(), 8 + 8 + status + 32 + 8 + 16);
    }

    #[test]
    fn a_range_whose_table_does_not_fit_is_refused_before_it_flies() {
        let study = two_measures_one_input();
        let per = study.table_bytes_per_run();
        // Twice the table fits exactly: flown; one byte less: refused.
        assert!(study.check_table_memory(&(5..15), Some(20 * per)).is_ok());
        assert!(study.check_table_memory(&(5..15), None).is_ok());
        let refused = study.check_table_memory(&(5..15), Some(20 * per - 1));
        assert!(
            matches!(
                refused,
                Err(StudyError::TableMemory {
                    start: 5,
                    end: 15,
                    per_run_bytes,
                    needed_bytes,
                    available_bytes,
                }) if per_run_bytes == per && needed_bytes == 20 * per
                    && available_bytes == 20 * per - 1
            ),
            "{refused:?}"
        );
        // The whole range of 2^40 runs (petabytes of table) on this
        // machine: refused at once, with the numbers, nothing flown.
        let started = std::time::Instant::now();
        let refused = study
            .fly_runs(0..study.runs(), &crate::FlyOptions::default())
            .unwrap_err();
        assert!(started.elapsed().as_secs() < 10, "{:?}", started.elapsed());
        let needed_mib = (study.runs() * per * 2).div_ceil(1024 * 1024);
        assert!(
            refused.to_string().starts_with(&format!(
                "runs 0..1099511627776: their table needs about {needed_mib} MiB ({per} bytes a \
                 run, twice that while it grows); this process has "
            )),
            "{refused}"
        );
        // A range that fits is flown as before.
        let table = study.fly_runs(0..3, &crate::FlyOptions::default()).unwrap();
        assert_eq!(table.len(), 3);
    }
}
