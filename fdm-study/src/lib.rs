//! Monte Carlo studies of flight dynamics models: a study file (TOML) names
//! a scenario, dispersions over its initial conditions, controls, script
//! timing and the aircraft's physical parameters, the number of runs, a
//! master seed and the measures to take; [`Study::fly_runs`] flies any range
//! of its runs on SIMD fleets ([`fdm_fleet::Fleet`]) into a [`RunTable`];
//! [`summarize`] turns a table into a [`Summary`] (`summary.json`).
//!
//! The contract (also what the Python bindings and Ray shards build on):
//!
//! * range in, table out: `fly_runs(first..end, &options)` gives the rows of
//!   runs `first..end` in run order, and run `i`'s row never depends on the
//!   range, the thread count or the block layout (each run's random values
//!   come from a counter-based stream keyed by the seed and the run index,
//!   [`rng`]);
//! * tables of consecutive ranges join with [`RunTable::append`];
//! * each row carries the values the run drew (one `input.KEY` column per
//!   dispersion, [`Study::dispersed_values`]) and the fingerprint of its
//!   final state ([`RunTable::fingerprint`], as a recording of the run
//!   carries it);
//! * a study can be stopped: [`Study::fly_runs_until`] asks a closure
//!   between blocks and every few frames, and on a stop gives the rows of
//!   the runs completed from the range's start on, without gaps (runs
//!   `first..first + K`), each the same bits as an unstopped flight's;
//!   [`Summary::stopped`] marks the summary of such a table;
//! * a measure that does not apply to a run (no touchdown, target height
//!   never reached, a refused start) is `None`, never NaN; the summary
//!   leaves it out;
//! * with [`fdm_fleet::Precision::Exact`], run `i` flown alone through
//!   `fdm_run` ([`Study::scenario`] with a [`MeasureOutput`] attached, what
//!   `sim-cli study FILE --run I` does) gives the batch's bits.
//!
//! ```
//! use fdm_study::{summarize, FlyOptions, Study};
//!
//! let study = Study::from_toml_str(
//!     r#"
//! model = "palmer"
//! runs = 8
//! seed = 7
//! duration_s = 5.0
//! measures = ["max_height_m", "final_x_m"]
//! [controls]
//! throttle = 1.0
//! alpha_deg = 4.0
//! [[dispersion]]
//! key = "aircraft.mass_kg"
//! distribution = "normal"
//! mean = 1114.0
//! sd = 50.0
//! "#,
//! )?;
//! let options = FlyOptions { threads: 2, ..FlyOptions::default() };
//! let all = study.fly_runs(0..8, &options)?;
//! // Run 5 alone is the same row, bit for bit.
//! let five = study.fly_runs(5..6, &FlyOptions { threads: 1, ..options })?;
//! assert_eq!(five.measures[0].1[0].map(f64::to_bits), all.measures[0].1[5].map(f64::to_bits));
//! let summary = summarize(&all).with_seed(study.seed());
//! assert_eq!(summary.runs, 8);
//! # Ok::<(), fdm_study::StudyError>(())
//! ```
//!
//! | module | what |
//! |---|---|
//! | [`spec`] | the study file, [`Study`] and the models it may name ([`StudyEntry`]) |
//! | [`rng`] | Philox4x32-10 and the samplers' inversions |
//! | [`model`] | what a study needs of a model ([`StudyModel`]) |
//! | [`measure`] | the built-in [`Measure`]s and their [`measure::Tracker`] |
//! | [`memory`] | what a streamed study keeps in memory ([`MemoryEstimate`]) |
//! | [`fly`] | [`Study::fly_runs`] (and [`Study::fly_runs_until`], which can be stopped), [`RunTable`], [`MeasureOutput`] |
//! | [`summary`] | [`summarize`], [`Summary`] |
//! | [`table`] | `runs.csv` (measures, drawn inputs `input.KEY`, `fingerprint`) |
//! | [`track`] | the thinned sample of ground tracks ([`TrackPlan`], [`Study::fly_runs_tracked`]) |
//! | [`arrow`] | `runs.arrow`: the table as an Arrow IPC file |
//! | [`batch`] | a whole study flown chunk by chunk into `runs.csv` and `runs.arrow`, its summary and plot data in bounded memory ([`batch::Batch`], what `sim-cli study` runs) |
//!
//! The file format, the measures and the guarantees are in the project's
//! `docs/studies.md`.

pub mod arrow;
pub mod batch;
pub mod fly;
pub mod measure;
pub mod memory;
pub mod model;
pub mod rng;
pub mod spec;
pub mod summary;
pub mod table;
pub mod track;

pub use fly::{FlyOptions, MeasureOutput, BLOCK_RUNS};
pub use measure::Measure;
pub use memory::{MemoryEstimate, MemoryRefused};
pub use model::StudyModel;
pub use spec::{Distribution, Stop, Study, StudyEntry, MAX_RUNS, MAX_STUDY_FILE_BYTES};
pub use summary::{summarize, MeasureSummary, StoppedEarly, Summary, SummaryBuilder};
pub use table::{RunStatus, RunTable};
pub use track::{GroundTrack, TrackPlan};

/// Why a study could not be read or flown.
#[derive(Debug, thiserror::Error)]
pub enum StudyError {
    /// The study file is not valid: where, which key, what was expected.
    #[error("line {line}, key `{key}`: expected {expected}")]
    Invalid {
        /// The line (from 1).
        line: usize,
        /// The key at fault.
        key: String,
        /// What was expected (and what was found).
        expected: String,
    },
    /// The study file is not the TOML of a study (malformed TOML, an
    /// unknown or missing key, a value of the wrong type): TOML's own
    /// message, which names the key and what was expected.
    #[error("line {line}: {message}")]
    Syntax {
        /// The line (from 1).
        line: usize,
        /// The parser's message.
        message: String,
    },
    /// The study file cannot be read, or is not one to read: missing,
    /// unreadable, neither a regular file nor a pipe (`/dev/zero`, a
    /// directory), larger than [`MAX_STUDY_FILE_BYTES`], or not UTF-8 text
    /// ([`Study::read_file`]).
    #[error("{0}")]
    Input(#[from] fdm_run::input::InputError),
    /// A number of runs outside 1 to [`MAX_RUNS`].
    #[error("{0} runs: expected a whole number from 1 to {MAX_RUNS}")]
    Runs(u64),
    /// Runs asked for past the study's end.
    #[error("runs {start}..{end} are not within the study's {runs} runs")]
    Range {
        /// First run asked for.
        start: u64,
        /// End of the range asked for.
        end: u64,
        /// The study's runs.
        runs: u64,
    },
    /// No worker thread.
    #[error("at least one thread is needed")]
    Threads,
    /// A model other than the study's.
    #[error("the study flies {study}, not {asked}")]
    Model {
        /// The study's model.
        study: &'static str,
        /// The model asked for.
        asked: &'static str,
    },
    /// The fleet refused (e.g. `fast` for a model without it).
    #[error(transparent)]
    Fleet(#[from] fdm_fleet::FleetError),
    /// A run's start was refused (asked for alone).
    #[error("run {run}: the start was refused: {reason}")]
    StartRefused {
        /// The run.
        run: u64,
        /// Why.
        reason: String,
    },
    /// Tables with different measure columns cannot be appended.
    #[error("the tables' measures differ: {have:?} and {other:?}")]
    Columns {
        /// This table's measures.
        have: Vec<String>,
        /// The other table's.
        other: Vec<String>,
    },
    /// A worker thread failed.
    #[error("a worker thread failed")]
    Worker,
    /// The table of the runs asked for would not fit in the memory this
    /// process can still allocate ([`Study::table_bytes_per_run`]).
    #[error(
        "runs {start}..{end}: their table needs about {} MiB ({per_run_bytes} bytes a run, \
         twice that while it grows); this process has {} MiB available: fly fewer runs at a \
         time (a range of runs each call) or stream the study (`sim-cli study`)",
        .needed_bytes.div_ceil(1024 * 1024),
        .available_bytes / (1024 * 1024)
    )]
    TableMemory {
        /// First run asked for.
        start: u64,
        /// End of the range asked for.
        end: u64,
        /// Bytes of the table per run ([`Study::table_bytes_per_run`]).
        per_run_bytes: u64,
        /// Bytes the table needs: twice the runs times `per_run_bytes`
        /// (its columns double as they grow).
        needed_bytes: u64,
        /// Bytes this process can still allocate
        /// ([`fdm_run::memory::available_bytes`]).
        available_bytes: u64,
    },
}

/// The README's example, compiled and run as a doctest so it cannot go stale.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
pub struct ReadmeDoctests;
