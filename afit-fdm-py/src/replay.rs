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
//!
//! As `sim-cli replay` (docs/recording.md):
//! * a recording cut before its end marker (its recording run killed, the
//!   machine stopped) raises [`RecordingCutError`] with the CLI's words
//!   (where it was cut, how many frames are intact); `salvage=True` flies
//!   those frames instead ([`Recording::parse_salvaging`]) and the replay
//!   says where the cut was;
//! * a frame that diverges (a non-finite state) stops the replay there:
//!   [`ReplayDivergedError`], with the replay up to that frame.

use std::io::Read;

use fdm_core::fingerprint;
use fdm_core::model::FlightStatus;
use fdm_core::script::Script;
use fdm_run::recording::{
    recorded_model, Cut, Recording, RecordingError as FormatError, Replayed, MAX_RECORDING_BYTES,
};
use numpy::PyArray1;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::{PyBytes, PyDict};

use crate::flight::{AnyFlight, Single};
use crate::models::{status_code, with_model, BindModel, ModelJob, RegisteredModel};
use crate::PyFlight;

pyo3::create_exception!(
    _afit_fdm,
    RecordingError,
    PyValueError,
    "A recording that cannot be replayed: not a recording, another format \
     version, a model this build does not have, truncated or corrupt. The \
     message names the problem (the same words as `sim-cli replay`)."
);

pyo3::create_exception!(
    _afit_fdm,
    RecordingCutError,
    RecordingError,
    "A recording cut before its end marker (its recording run was killed, or \
     the machine stopped), refused as `sim-cli replay` reports it: where it \
     was cut (`at_byte`) and how many frames before the cut are intact \
     (`frames`). `replay(..., salvage=True)` flies those frames."
);

pyo3::create_exception!(
    _afit_fdm,
    ReplayDivergedError,
    PyValueError,
    "The replay stopped at a frame whose state is not finite, as `sim-cli \
     replay` stops (exit status 1): `frame` is that frame (since the start or \
     the last reset), `replay` the replay up to it (its flight at that frame, \
     status `diverged`; its trajectory without the diverged row, as the \
     CLI's CSV)."
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
    /// Where a salvaged recording was cut.
    cut: Option<Cut>,
    /// The diverged frame and the library's message, when the replay
    /// stopped there.
    diverged: Option<(u64, String)>,
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

/// The cut recording's exception, `NAME: cut at byte B ...` as `sim-cli
/// replay` words it.
fn cut_error(py: Python<'_>, name: &str, cut: Cut) -> PyErr {
    let err = RecordingCutError::new_err(format!(
        "{name}: {cut} (the file is truncated); replay(..., salvage=True) flies them (a cut \
         recording has no fingerprint to check them against)"
    ));
    let value = err.value(py);
    let _ = value.setattr("at_byte", cut.at_byte);
    let _ = value.setattr("frames", cut.frames);
    err
}

/// Parses and flies a recording of model `M` (up to its cut with
/// `salvage`); `Ok(Err(cut))` for a cut recording without `salvage`
/// (nothing flown).
fn replay_model<M: BindModel>(
    bytes: &[u8],
    trajectory: bool,
    salvage: bool,
) -> Result<Result<Outcome, Cut>, PyErr> {
    let (recording, cut) = Recording::<M>::parse_salvaging(bytes).map_err(|e| format_error(&e))?;
    if let (Some(cut), false) = (cut, salvage) {
        return Ok(Err(cut));
    }
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
    let mut diverged = None;
    'replay: for event in recording.events() {
        match event.map_err(|e| format_error(&e))? {
            Replayed::Frames { count, actions } => {
                for _ in 0..count {
                    single.step(1, &actions).map_err(PyValueError::new_err)?;
                    // As sim-cli's run: a diverged frame ends the replay
                    // before anything is written from it.
                    if single.current_status() == FlightStatus::Diverged {
                        let frame = single.frame_number();
                        let error = fdm_run::RunError::Diverged {
                            model: M::NAME,
                            frame,
                            dt: format!("{:?}", M::time_step(f64::from(recording.fps))),
                        };
                        diverged = Some((frame, format!("frame {frame}: {error}")));
                        break 'replay;
                    }
                    if let Some(columns) = columns.as_mut() {
                        push_row(&single, columns, &mut scratch);
                    }
                }
            }
            Replayed::Reset => {
                AnyFlight::reset(&mut single).map_err(PyValueError::new_err)?;
                if let Some(columns) = columns.as_mut() {
                    push_row(&single, columns, &mut scratch);
                }
            }
        }
    }
    let fingerprint = recording
        .fingerprint
        .filter(|_| diverged.is_none())
        .map(|f| {
            (
                f.state == M::state_fingerprint(single.current_state()),
                f.maths == fingerprint::maths(),
            )
        });
    let origin = recording.origin.geodetic();
    Ok(Ok(Outcome {
        model: M::NAME,
        fps: recording.fps,
        frames: recording.frames,
        resets: recording.resets,
        events: recording.events,
        origin: (origin.lat_deg, origin.lon_deg, origin.alt_m),
        fingerprint,
        flight: Box::new(single),
        trajectory: columns.map(|c| (names, c)),
        cut,
        diverged,
    }))
}

/// The bytes of `source`: `bytes` as given, or the file a path names (at most
/// [`MAX_RECORDING_BYTES`]).
fn read_source(py: Python<'_>, source: &Bound<'_, PyAny>) -> PyResult<(String, Vec<u8>)> {
    if let Ok(bytes) = source.cast::<PyBytes>() {
        return Ok(("the recording".to_owned(), bytes.as_bytes().to_vec()));
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
    // A named pipe waits for its writer: without the GIL, Ctrl-C looked at.
    let file = std::path::PathBuf::from(&path);
    let bytes = crate::pipes::read_interruptibly(py, &file.clone(), move || {
        let mut bytes = Vec::new();
        std::fs::File::open(&file)?
            .take(MAX_RECORDING_BYTES + 1)
            .read_to_end(&mut bytes)
            .map(|_| bytes)
    })?
    .map_err(os_error)?;
    if bytes.len() as u64 > MAX_RECORDING_BYTES {
        return Err(RecordingError::new_err(format!(
            "{path}: {}",
            FormatError::TooLarge {
                size: bytes.len() as u64
            }
        )));
    }
    Ok((path, bytes))
}

/// See `_afit_fdm.pyi`.
#[pyfunction]
#[pyo3(signature = (source, *, trajectory=false, salvage=false))]
pub fn replay(
    py: Python<'_>,
    source: &Bound<'_, PyAny>,
    #[pyo3(from_py_with = crate::args::trajectory)] trajectory: bool,
    #[pyo3(from_py_with = crate::args::salvage)] salvage: bool,
) -> PyResult<PyReplay> {
    let (name, bytes) = read_source(py, source)?;
    let model = recorded_model(&bytes).map_err(|e| format_error(&e))?;
    struct Replay<'a> {
        bytes: &'a [u8],
        trajectory: bool,
        salvage: bool,
    }
    impl ModelJob for Replay<'_> {
        type Output = Result<Result<Outcome, Cut>, PyErr>;
        fn call<M: RegisteredModel>(self) -> Self::Output {
            replay_model::<M>(self.bytes, self.trajectory, self.salvage)
        }
    }
    let job = Replay {
        bytes: &bytes,
        trajectory,
        salvage,
    };
    let outcome = py.detach(|| {
        with_model(model, job)
            .unwrap_or_else(|| Err(format_error(&FormatError::UnknownModel(model.to_owned()))))
    })?;
    let outcome = outcome.map_err(|cut| cut_error(py, &name, cut))?;
    let diverged = outcome.diverged.clone();
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
    let replay = PyReplay {
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
        cut: outcome.cut.map(|c| (c.at_byte, c.frames)),
    };
    match diverged {
        None => Ok(replay),
        Some((frame, message)) => {
            let err = ReplayDivergedError::new_err(message);
            let value = err.value(py);
            value.setattr("frame", frame)?;
            value.setattr("replay", Py::new(py, replay)?)?;
            Err(err)
        }
    }
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
    cut: Option<(u64, u64)>,
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
    /// With `salvage=True`, for a cut recording: `(at_byte, frames)`, where
    /// it was cut and the frames before the cut (all that was flown);
    /// `None` for a complete recording.
    #[getter]
    fn cut(&self) -> Option<(u64, u64)> {
        self.cut
    }
    fn __repr__(&self) -> String {
        format!(
            "Replay(model={:?}, fps={}, frames={}, resets={})",
            self.model, self.fps, self.frames, self.resets
        )
    }
}
