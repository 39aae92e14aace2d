//! Recordings from Python: `afit_fdm.replay` and the `Replay` it returns.
//!
//! A recording is the run library's ([`fdm_run::recording`], the format
//! `sim-cli --record` writes and `sim-cli replay` reads; docs/recording.md).
//! [`replay`] reads one (a file, at most [`MAX_RECORDING_BYTES`], or bytes),
//! validates it whole with [`Recording::parse`] (magic, version, header,
//! every block's checksum, the end marker) and flies its frames and resets
//! on a [`Single`] built from the header's aircraft, controls and state, as
//! `sim-cli replay` flies them on its run: the same frames, so the same bits
//! (the Python suite compares both with the CLI's CSV and JSON report).
//! Anything that is not a complete, intact recording of a model this build
//! has raises [`RecordingError`] (a `ValueError`) naming the problem.

use std::io::Read;

use fdm_core::bourg::Bourg;
use fdm_core::fingerprint;
use fdm_core::model::Model;
use fdm_core::palmer::Palmer;
use fdm_core::script::Script;
use fdm_run::recording::{
    recorded_model, Recording, RecordingError as FormatError, Replayed, MAX_RECORDING_BYTES,
};
use numpy::PyArray1;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::{PyBytes, PyDict};

use crate::flight::{AnyFlight, Single};
use crate::models::{status_code, BindModel};
use crate::PyFlight;

pyo3::create_exception!(
    _afit_fdm,
    RecordingError,
    PyValueError,
    "A recording that cannot be replayed: not a recording, another format \
     version, a model this build does not have, truncated or corrupt. The \
     message names the problem (the same words as `sim-cli replay`)."
);

/// Most rows a replay's trajectory may hold (frame 0, one per frame, one per
/// reset): 10 million rows of a Bourg flight are about 2.4 GB of columns.
pub const MAX_TRAJECTORY_ROWS: u64 = 10_000_000;

/// What a replay found and flew.
struct Outcome {
    model: &'static str,
    fps: u32,
    frames: u64,
    resets: u64,
    events: u64,
    origin: (f64, f64, f64),
    /// `(state matches, maths match)` against the end marker's fingerprint.
    fingerprint: Option<(bool, bool)>,
    flight: Box<dyn AnyFlight>,
    /// Column names and values, row by row (as `sim-cli replay --csv`).
    trajectory: Option<(Vec<&'static str>, Vec<Vec<f64>>)>,
}

fn format_error(e: &FormatError) -> PyErr {
    RecordingError::new_err(e.to_string())
}

/// Appends `single`'s row (frame, state, controls, status) to `columns`.
fn push_row<M: BindModel>(single: &Single<M>, columns: &mut [Vec<f64>], scratch: &mut Vec<f64>) {
    let (state_n, control_n) = (M::STATE_FIELDS.len(), M::CONTROL_FIELDS.len());
    scratch.clear();
    scratch.resize(state_n + control_n, 0.0);
    #[allow(clippy::cast_precision_loss)] // frames < 2^53 (MAX_FRAMES is 10^9)
    columns[0].push(single.frame_number() as f64);
    M::state_values(single.current_state(), &mut scratch[..state_n]);
    M::control_values(single.current_controls(), &mut scratch[state_n..]);
    for (column, value) in columns[1..].iter_mut().zip(scratch.iter()) {
        column.push(*value);
    }
    columns[1 + state_n + control_n].push(f64::from(status_code(single.current_status())));
}

/// Parses and flies a recording of model `M`.
fn replay_model<M: BindModel>(bytes: &[u8], trajectory: bool) -> Result<Outcome, PyErr> {
    let recording = Recording::<M>::parse(bytes).map_err(|e| format_error(&e))?;
    let rows = recording
        .frames
        .saturating_add(recording.resets)
        .saturating_add(1);
    if trajectory && rows > MAX_TRAJECTORY_ROWS {
        return Err(PyValueError::new_err(format!(
            "trajectory: the recording has {rows} rows (frames, resets and frame 0), more than \
             the {MAX_TRAJECTORY_ROWS} a trajectory may hold; replay without trajectory=True"
        )));
    }
    let start = &recording.start;
    let mut single = Single::<M>::new(
        start.aircraft.clone(),
        start.controls,
        start.state,
        Script::default(),
        recording.fps,
    );
    let names: Vec<&'static str> = std::iter::once("frame")
        .chain(M::STATE_FIELDS.iter().copied())
        .chain(M::CONTROL_FIELDS.iter().map(|c| c.0))
        .chain(std::iter::once("status"))
        .collect();
    let mut columns: Option<Vec<Vec<f64>>> = trajectory.then(|| vec![Vec::new(); names.len()]);
    let mut scratch = Vec::new();
    if let Some(columns) = columns.as_mut() {
        push_row(&single, columns, &mut scratch);
    }
    for event in recording.events() {
        match event.map_err(|e| format_error(&e))? {
            Replayed::Frames { count, actions } => match columns.as_mut() {
                Some(columns) => {
                    for _ in 0..count {
                        single.step(1, &actions).map_err(PyValueError::new_err)?;
                        push_row(&single, columns, &mut scratch);
                    }
                }
                None => single
                    .step(count, &actions)
                    .map_err(PyValueError::new_err)?,
            },
            Replayed::Reset => {
                AnyFlight::reset(&mut single);
                if let Some(columns) = columns.as_mut() {
                    push_row(&single, columns, &mut scratch);
                }
            }
        }
    }
    let fingerprint = recording.fingerprint.map(|f| {
        (
            f.state == M::state_fingerprint(single.current_state()),
            f.maths == fingerprint::maths(),
        )
    });
    let origin = recording.origin.geodetic();
    Ok(Outcome {
        model: M::NAME,
        fps: recording.fps,
        frames: recording.frames,
        resets: recording.resets,
        events: recording.events,
        origin: (origin.lat_deg, origin.lon_deg, origin.alt_m),
        fingerprint,
        flight: Box::new(single),
        trajectory: columns.map(|c| (names, c)),
    })
}

/// The bytes of `source`: `bytes` as given, or the file a path names (at most
/// [`MAX_RECORDING_BYTES`]).
fn read_source(py: Python<'_>, source: &Bound<'_, PyAny>) -> PyResult<Vec<u8>> {
    if let Ok(bytes) = source.cast::<PyBytes>() {
        return Ok(bytes.as_bytes().to_vec());
    }
    let path = py
        .import("os")?
        .call_method1("fspath", (source,))
        .map_err(|_| {
            pyo3::exceptions::PyTypeError::new_err(
                "source: expected a path (str or os.PathLike) or bytes",
            )
        })?;
    let path: String = path.extract().map_err(|_| {
        pyo3::exceptions::PyTypeError::new_err("source: expected a str path or bytes")
    })?;
    // An io::Error becomes its OSError subclass (FileNotFoundError, ...).
    let os_error =
        |e: std::io::Error| PyErr::from(std::io::Error::new(e.kind(), format!("{path}: {e}")));
    let file = std::fs::File::open(&path).map_err(os_error)?;
    let mut bytes = Vec::new();
    file.take(MAX_RECORDING_BYTES + 1)
        .read_to_end(&mut bytes)
        .map_err(os_error)?;
    if bytes.len() as u64 > MAX_RECORDING_BYTES {
        return Err(RecordingError::new_err(format!(
            "{path}: {}",
            FormatError::TooLarge {
                size: bytes.len() as u64
            }
        )));
    }
    Ok(bytes)
}

/// See `_afit_fdm.pyi`.
#[pyfunction]
#[pyo3(signature = (source, *, trajectory=false))]
pub fn replay(py: Python<'_>, source: &Bound<'_, PyAny>, trajectory: bool) -> PyResult<PyReplay> {
    let bytes = read_source(py, source)?;
    let model = recorded_model(&bytes).map_err(|e| format_error(&e))?;
    let outcome = py.detach(|| match model {
        n if n == Palmer::NAME => replay_model::<Palmer>(&bytes, trajectory),
        n if n == Bourg::NAME => replay_model::<Bourg>(&bytes, trajectory),
        other => Err(format_error(&FormatError::UnknownModel(other.to_owned()))),
    })?;
    let trajectory = match outcome.trajectory {
        Some((names, columns)) => {
            let d = PyDict::new(py);
            for (name, column) in names.into_iter().zip(columns) {
                if name == "frame" || name == "status" {
                    #[allow(clippy::cast_possible_truncation)] // whole numbers < 2^53
                    let ints: Vec<i64> = column.iter().map(|&v| v as i64).collect();
                    d.set_item(name, PyArray1::from_vec(py, ints))?;
                } else {
                    d.set_item(name, PyArray1::from_vec(py, column))?;
                }
            }
            Some(d.unbind())
        }
        None => None,
    };
    Ok(PyReplay {
        model: outcome.model,
        fps: outcome.fps,
        frames: outcome.frames,
        resets: outcome.resets,
        events: outcome.events,
        origin: outcome.origin,
        fingerprint: outcome.fingerprint,
        flight: Py::new(
            py,
            PyFlight {
                inner: outcome.flight,
            },
        )?,
        trajectory,
    })
}

/// A replayed recording: what its header and events held, and the flight
/// flown from them.
#[pyclass(module = "afit_fdm._afit_fdm", name = "Replay", frozen)]
pub struct PyReplay {
    model: &'static str,
    fps: u32,
    frames: u64,
    resets: u64,
    events: u64,
    origin: (f64, f64, f64),
    fingerprint: Option<(bool, bool)>,
    flight: Py<PyFlight>,
    trajectory: Option<Py<PyDict>>,
}

#[pymethods]
impl PyReplay {
    /// The model's name.
    #[getter]
    fn model(&self) -> &'static str {
        self.model
    }
    /// Frames per second (a whole number).
    #[getter]
    fn fps(&self) -> u32 {
        self.fps
    }
    /// Frames flown, across resets.
    #[getter]
    fn frames(&self) -> u64 {
        self.frames
    }
    /// Resets.
    #[getter]
    fn resets(&self) -> u64 {
        self.resets
    }
    /// Events stored (runs of identical frames, and resets).
    #[getter]
    fn events(&self) -> u64 {
        self.events
    }
    /// The earth-frame origin: `(lat_deg, lon_deg, alt_m)`.
    #[getter]
    fn origin(&self) -> (f64, f64, f64) {
        self.origin
    }
    /// Whether the final state is the recorded flight's (its fingerprint in
    /// a version 3 recording); `None` for a recording without one.
    #[getter]
    fn same_final_state(&self) -> Option<bool> {
        self.fingerprint.map(|f| f.0)
    }
    /// Whether the recording was made with this build's maths (version 3);
    /// `None` without a fingerprint.
    #[getter]
    fn same_maths(&self) -> Option<bool> {
        self.fingerprint.map(|f| f.1)
    }
    /// The flight at the end of the replay.
    #[getter]
    fn flight(&self, py: Python<'_>) -> Py<PyFlight> {
        self.flight.clone_ref(py)
    }
    /// With `trajectory=True`: the rows `sim-cli replay --csv` writes, as
    /// columns by name.
    #[getter]
    fn trajectory<'py>(&self, py: Python<'py>) -> Option<Bound<'py, PyDict>> {
        self.trajectory.as_ref().map(|d| d.bind(py).clone())
    }
    fn __repr__(&self) -> String {
        format!(
            "Replay(model={:?}, fps={}, frames={}, resets={})",
            self.model, self.fps, self.frames, self.resets
        )
    }
}
