//! Monte Carlo studies ([`fdm_study`]) from Python: `_Study`, a parsed study
//! file whose runs are flown into plain NumPy columns, and
//! `summarize_columns`, the summary (`summary.json`'s shape) of such
//! columns. The Python class `afit_fdm.Study` and its table
//! (`python/afit_fdm/study.py`) are built on these; the columns are plain
//! data so that a table can cross a process boundary (Ray) and be merged.

use std::ops::Range;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::{self, RecvTimeoutError};

use fdm_core::model::{FlightStatus, LandingState};
use fdm_fleet::Precision;
use fdm_study::{summarize, FlyOptions, RunStatus, RunTable, Study, StudyError};
use numpy::{PyArray1, PyReadonlyArray1};
use pyo3::exceptions::{PyMemoryError, PyOSError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};

use crate::pipes::{recv_detached, SIGNAL_CHECK};

/// Every [`RunStatus`], in the order of [`RunStatus::CODES`]: a status's
/// position here is its code in the `status_code` column.
const STATUSES: [RunStatus; 7] = [
    RunStatus::Flown(FlightStatus::OnGround),
    RunStatus::Flown(FlightStatus::Airborne),
    RunStatus::Flown(FlightStatus::Landed(LandingState::Safe)),
    RunStatus::Flown(FlightStatus::Landed(LandingState::Rough)),
    RunStatus::Flown(FlightStatus::Landed(LandingState::Crash)),
    RunStatus::Flown(FlightStatus::Diverged),
    RunStatus::StartRefused,
];

/// A status's position in [`RunStatus::CODES`].
fn status_index(status: RunStatus) -> u8 {
    let index = STATUSES
        .iter()
        .position(|s| *s == status)
        .expect("every RunStatus is in STATUSES");
    u8::try_from(index).expect("seven statuses")
}

/// A study error as the Python exception a user expects: `OSError` for a
/// file that cannot be opened or read (missing, a directory, `/dev/zero`),
/// `MemoryError` for a table too large, `ValueError` for everything else
/// (a file too large or not UTF-8 among them, as `bytes.decode` refuses).
fn py_err(e: StudyError) -> PyErr {
    use fdm_run::input::InputError;
    match e {
        StudyError::Input(InputError::Unreadable { .. } | InputError::NotAFileOrPipe { .. }) => {
            PyOSError::new_err(e.to_string())
        }
        StudyError::TableMemory { .. } => PyMemoryError::new_err(e.to_string()),
        other => PyValueError::new_err(other.to_string()),
    }
}

/// A parsed, validated study file (see `_afit_fdm.pyi`).
#[pyclass(module = "afit_fdm._afit_fdm", name = "_Study", frozen)]
pub struct PyStudy {
    study: Study,
    text: String,
}

impl PyStudy {
    fn build(text: String, runs: Option<u64>, seed: Option<u64>) -> PyResult<Self> {
        let mut study = Study::from_toml_str(&text).map_err(py_err)?;
        if let Some(runs) = runs {
            study = study.with_runs(runs).map_err(py_err)?;
        }
        if let Some(seed) = seed {
            study = study.with_seed(seed);
        }
        Ok(Self { study, text })
    }
}

#[pymethods]
impl PyStudy {
    /// See `_afit_fdm.pyi`.
    #[staticmethod]
    #[pyo3(signature = (text, *, runs=None, seed=None))]
    fn from_toml(
        #[pyo3(from_py_with = crate::args::text)] text: String,
        #[pyo3(from_py_with = crate::args::runs)] runs: Option<u64>,
        #[pyo3(from_py_with = crate::args::seed)] seed: Option<u64>,
    ) -> PyResult<Self> {
        Self::build(text, runs, seed)
    }

    /// See `_afit_fdm.pyi`.
    #[staticmethod]
    #[pyo3(signature = (path, *, runs=None, seed=None))]
    fn from_path(
        py: Python<'_>,
        #[pyo3(from_py_with = crate::args::path)] path: std::path::PathBuf,
        #[pyo3(from_py_with = crate::args::runs)] runs: Option<u64>,
        #[pyo3(from_py_with = crate::args::seed)] seed: Option<u64>,
    ) -> PyResult<Self> {
        // A named pipe waits for its writer: without the GIL, Ctrl-C looked at.
        let file = path.clone();
        let text =
            crate::pipes::read_interruptibly(py, &path, move || Study::read_file(&file, |_| {}))?
                .map_err(py_err)?;
        Self::build(text, runs, seed)
    }

    /// The study file's text (without the runs/seed overrides).
    #[getter]
    fn text(&self) -> &str {
        &self.text
    }

    /// Number of runs.
    #[getter]
    fn runs(&self) -> u64 {
        self.study.runs()
    }

    /// The master seed.
    #[getter]
    fn seed(&self) -> u64 {
        self.study.seed()
    }

    /// The model's name.
    #[getter]
    fn model(&self) -> &'static str {
        self.study.model()
    }

    /// The measures' names, in the study's order.
    #[getter]
    fn measure_names(&self) -> Vec<String> {
        self.study.measure_names()
    }

    /// The drawn inputs' column names (`input.` and each dispersion's key),
    /// in the file's order.
    #[getter]
    fn input_names(&self) -> Vec<String> {
        self.study.input_names()
    }

    /// See `_afit_fdm.pyi`.
    #[pyo3(signature = (first, end, *, threads=None, precision="exact"))]
    fn fly_columns<'py>(
        &self,
        py: Python<'py>,
        #[pyo3(from_py_with = crate::args::first)] first: u64,
        #[pyo3(from_py_with = crate::args::end)] end: u64,
        #[pyo3(from_py_with = crate::args::threads)] threads: Option<usize>,
        #[pyo3(from_py_with = crate::args::precision)] precision: &str,
    ) -> PyResult<Bound<'py, PyDict>> {
        let precision: Precision = precision
            .parse()
            .map_err(|e| PyValueError::new_err(format!("precision: {e}")))?;
        let mut options = FlyOptions {
            precision,
            ..FlyOptions::default()
        };
        if let Some(threads) = threads {
            if threads == 0 {
                return Err(PyValueError::new_err(
                    "threads: at least one thread is needed",
                ));
            }
            options.threads = threads;
        }
        if first > end {
            return Err(PyValueError::new_err(format!(
                "runs {first}..{end}: the first run is past the end"
            )));
        }
        let range: Range<u64> = first..end;
        let table = fly_interruptibly(py, &self.study, range, &options)?;
        columns(py, table)
    }
}

/// The runs `range` of `study`, flown on a scoped thread while the calling
/// thread (the GIL released between checks) asks Python every
/// [`SIGNAL_CHECK`] whether a signal is pending. A signal whose handler
/// raises (Ctrl-C's `KeyboardInterrupt`) sets the stop flag of
/// [`Study::fly_runs_until`], waits for the fly to return (at most a block
/// per thread, see there) and is raised; the partial table is dropped.
/// Without a signal the table is [`Study::fly_runs`]'s, bit for bit: the
/// flag is never set. Off the main thread `check_signals` does nothing, so
/// the study then runs to its end as before.
fn fly_interruptibly(
    py: Python<'_>,
    study: &Study,
    range: Range<u64>,
    options: &FlyOptions,
) -> PyResult<RunTable> {
    let stop = AtomicBool::new(false);
    std::thread::scope(|scope| {
        let (done, mut finished) = mpsc::channel();
        let stop = &stop;
        let flier = scope.spawn(move || {
            let table = study.fly_runs_until(range, options, || stop.load(Ordering::Relaxed));
            // The receiver only goes away when the caller has its answer.
            let _ = done.send(());
            table
        });
        let mut interrupt: Option<PyErr> = None;
        loop {
            let waited;
            (finished, waited) = recv_detached(py, finished, SIGNAL_CHECK);
            match waited {
                // Done, or the flier panicked (its sender dropped): join
                // below says which.
                Ok(()) | Err(RecvTimeoutError::Disconnected) => break,
                Err(RecvTimeoutError::Timeout) => {
                    if interrupt.is_none() {
                        if let Err(e) = py.check_signals() {
                            stop.store(true, Ordering::Relaxed);
                            interrupt = Some(e);
                        }
                    }
                }
            }
        }
        let table = flier
            .join()
            .unwrap_or_else(|panic| std::panic::resume_unwind(panic));
        match interrupt {
            Some(e) => Err(e),
            None => table.map_err(py_err),
        }
    })
}

/// A table as a dict of NumPy columns: `run` (uint64), `status_code` (uint8,
/// an index into `STATUS_CODES`), `frames` (uint64), `measures`: a list
/// of `(name, values float64, applies bool)`, `values` 0.0 where the measure
/// does not apply; `inputs`: a list of `(name, values float64)`, the values
/// each run drew; `fingerprint` (uint64, 0 where there is none) and
/// `has_fingerprint` (bool, false for a refused start).
fn columns(py: Python<'_>, table: RunTable) -> PyResult<Bound<'_, PyDict>> {
    let out = PyDict::new(py);
    let codes: Vec<u8> = table.status.iter().map(|s| status_index(*s)).collect();
    out.set_item("run", PyArray1::from_vec(py, table.run))?;
    out.set_item("status_code", PyArray1::from_vec(py, codes))?;
    out.set_item("frames", PyArray1::from_vec(py, table.frames))?;
    let measures = PyList::empty(py);
    for (name, column) in table.measures {
        let values: Vec<f64> = column.iter().map(|v| v.unwrap_or(0.0)).collect();
        let applies: Vec<bool> = column.iter().map(Option::is_some).collect();
        measures.append((
            name,
            PyArray1::from_vec(py, values),
            PyArray1::from_vec(py, applies),
        ))?;
    }
    out.set_item("measures", measures)?;
    let inputs = PyList::empty(py);
    for (name, column) in table.inputs {
        inputs.append((name, PyArray1::from_vec(py, column)))?;
    }
    out.set_item("inputs", inputs)?;
    let has: Vec<bool> = table.fingerprint.iter().map(Option::is_some).collect();
    let fingerprint: Vec<u64> = table.fingerprint.iter().map(|f| f.unwrap_or(0)).collect();
    out.set_item("fingerprint", PyArray1::from_vec(py, fingerprint))?;
    out.set_item("has_fingerprint", PyArray1::from_vec(py, has))?;
    Ok(out)
}

/// See `_afit_fdm.pyi`.
#[pyfunction]
#[pyo3(signature = (run, status_code, frames, measures, *, seed))]
pub fn summarize_columns(
    run: PyReadonlyArray1<'_, u64>,
    status_code: PyReadonlyArray1<'_, u8>,
    frames: PyReadonlyArray1<'_, u64>,
    measures: Vec<(
        String,
        PyReadonlyArray1<'_, f64>,
        PyReadonlyArray1<'_, bool>,
    )>,
    seed: u64,
) -> PyResult<String> {
    let n = run.len()?;
    if status_code.len()? != n || frames.len()? != n {
        return Err(PyValueError::new_err(
            "columns: run, status_code and frames differ in length",
        ));
    }
    let status = status_code
        .as_array()
        .iter()
        .map(|&c| {
            STATUSES.get(usize::from(c)).copied().ok_or_else(|| {
                PyValueError::new_err(format!(
                    "status_code: {c} is not a status code (0 to {})",
                    STATUSES.len() - 1
                ))
            })
        })
        .collect::<PyResult<Vec<_>>>()?;
    let mut columns = Vec::with_capacity(measures.len());
    for (name, values, applies) in &measures {
        if values.len()? != n || applies.len()? != n {
            return Err(PyValueError::new_err(format!(
                "measure {name}: {} values and {} flags for {n} runs",
                values.len()?,
                applies.len()?
            )));
        }
        let column: Vec<Option<f64>> = values
            .as_array()
            .iter()
            .zip(applies.as_array().iter())
            .map(|(&v, &a)| a.then_some(v))
            .collect();
        columns.push((name.clone(), column));
    }
    let table = RunTable {
        run: run.as_array().to_vec(),
        status,
        frames: frames.as_array().to_vec(),
        measures: columns,
        // The summary is of the status and the measures only.
        ..RunTable::default()
    };
    let summary = summarize(&table).with_seed(seed);
    serde_json::to_string(&summary).map_err(|e| PyValueError::new_err(format!("summary: {e}")))
}

/// The status codes, in `status_code` order.
pub fn status_codes() -> &'static [&'static str] {
    RunStatus::CODES
}
