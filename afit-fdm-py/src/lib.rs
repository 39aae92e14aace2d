//! The `afit_fdm._afit_fdm` extension module: Python bindings of the
//! workspace's flight models ([`flight`]: one aircraft, `Flight`) and fleets
//! ([`fleet`]: many aircraft as NumPy columns, `Fleet`). The Python package
//! `afit_fdm` (in `python/afit_fdm/`) re-exports them and adds the Gymnasium
//! environments; its documentation is `python/afit_fdm/_afit_fdm.pyi` and
//! the README's Python section.

pub mod args;
#[cfg(feature = "dis")]
pub mod dis;
pub mod fleet;
pub mod flight;
pub mod models;
pub mod outputs;
pub mod pipes;
pub mod replay;
pub mod start;
pub mod study;
pub mod task;
pub mod task_io;

use fdm_core::model::ScriptAction;
use fdm_fleet::Precision;
use numpy::PyArray1;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};

use fleet::{AnyFleet, Buffers};
use flight::AnyFlight;
use models::{status_code, with_model, BindModel, ModelJob, RegisteredModel, MODELS};
use start::StartSpec;

fn unknown_model(model: &str) -> PyErr {
    PyValueError::new_err(format!(
        "model: {model:?} is not a model (models: {})",
        MODELS.join(", ")
    ))
}

/// Frames a long `Flight.step` flies between two looks at Python's pending
/// signals ([`in_chunks`]): about 15 to 150 ms at 0.25 to 2 µs a frame (the
/// step alone; with a recording or outputs).
const FLIGHT_FRAMES_PER_SIGNAL_CHECK: u64 = 1 << 16;

/// Flies `total` frames by calls of `fly`, `chunk` frames at a time, and
/// looks at Python's pending signals between two calls: a signal whose
/// handler raises (Ctrl-C's `KeyboardInterrupt`) stops the step there and is
/// raised, the frames flown so far staying flown (whole frames: the state is
/// one the aircraft reached). Without a signal the frames are the same
/// ones, bit for bit, as one call would fly: a frame is the same step
/// whatever the chunk it is flown in. Off the main thread Python runs no
/// handlers, so the step runs to its end.
fn in_chunks(
    py: Python<'_>,
    total: u64,
    chunk: u64,
    mut fly: impl FnMut(u64) -> PyResult<()>,
) -> PyResult<()> {
    let mut left = total;
    while left > 0 {
        let frames = left.min(chunk);
        fly(frames)?;
        left -= frames;
        if left > 0 {
            py.check_signals()?;
        }
    }
    Ok(())
}

/// Reads `**controls` of a single flight: name → finite number.
fn named_controls(kwargs: Option<&Bound<'_, PyDict>>) -> PyResult<Vec<(String, f64)>> {
    let mut out = Vec::new();
    if let Some(kwargs) = kwargs {
        for (k, v) in kwargs.iter() {
            let name: String = k.extract()?;
            let value = fleet::Column::extract(&v, &name, 1)?;
            match value {
                fleet::Column::Scalar(x) => out.push((name, x)),
                fleet::Column::Values(_) => {
                    return Err(pyo3::exceptions::PyTypeError::new_err(format!(
                        "{name}: expected a number"
                    )))
                }
            }
        }
    }
    Ok(out)
}

/// `os.fspath(path)` as a `str`.
fn fspath(py: Python<'_>, path: &Bound<'_, PyAny>) -> PyResult<String> {
    py.import("os")?
        .call_method1("fspath", (path,))
        .and_then(|p| p.extract())
        .map_err(|_| pyo3::exceptions::PyTypeError::new_err("path: expected a str path"))
}

/// An earth-frame origin `(lat_deg, lon_deg, alt_m)`, the default without one.
fn read_origin(origin: Option<(f64, f64, f64)>) -> PyResult<fdm_core::geodesy::GeodeticOrigin> {
    match origin {
        Some((lat, lon, alt)) => fdm_core::geodesy::GeodeticOrigin::new(lat, lon, alt)
            .map_err(|e| PyValueError::new_err(format!("origin: {e}"))),
        None => Ok(fdm_core::geodesy::GeodeticOrigin::default()),
    }
}

/// An output that could not be attached: `OSError` or `ValueError`.
fn attach_error((os, message): outputs::AttachError) -> PyErr {
    if os {
        pyo3::exceptions::PyOSError::new_err(message)
    } else {
        PyValueError::new_err(message)
    }
}

/// One aircraft of a model, flown frame by frame as `sim-cli` flies it.
#[pyclass(module = "afit_fdm._afit_fdm", name = "Flight")]
pub struct PyFlight {
    pub(crate) inner: Box<dyn AnyFlight>,
}

impl PyFlight {
    /// For the output `what` to `path`: its refusals first, then, when
    /// `path` is a named pipe, the wait for its reader with Ctrl-C looked at
    /// ([`pipes::await_reader`]); the pipe held open until the output has
    /// opened it.
    fn await_reader(
        &self,
        py: Python<'_>,
        what: &str,
        path: &str,
    ) -> PyResult<Option<std::fs::File>> {
        self.inner.check_output(what, path).map_err(attach_error)?;
        pipes::await_reader(py, path)
    }

    /// Runs `call`, which may write the flight's recording and outputs,
    /// with its [`pipes::SignalWatch`] armed: when a signal's handler
    /// raised while a write waited for a pipe's reader (stopping the
    /// writing), its exception (Ctrl-C's `KeyboardInterrupt`) is what the
    /// call raises, not the output's error it caused.
    fn writing<T>(&mut self, call: impl FnOnce(&mut dyn AnyFlight) -> PyResult<T>) -> PyResult<T> {
        self.inner.signal_watch().arm();
        let result = call(&mut *self.inner);
        match self.inner.signal_watch().take_raised() {
            Some(raised) => Err(raised),
            None => result,
        }
    }
}

#[pymethods]
impl PyFlight {
    /// See `_afit_fdm.pyi`.
    #[new]
    #[pyo3(signature = (model, *, fps=30, altitude_ft=None, speed_kt=None, heading_deg=None, trim=false, script=None, **controls))]
    #[allow(clippy::too_many_arguments)]
    fn new(
        #[pyo3(from_py_with = args::model)] model: String,
        #[pyo3(from_py_with = args::fps)] fps: u32,
        #[pyo3(from_py_with = args::altitude_ft)] altitude_ft: Option<f64>,
        #[pyo3(from_py_with = args::speed_kt)] speed_kt: Option<f64>,
        #[pyo3(from_py_with = args::heading_deg)] heading_deg: Option<f64>,
        #[pyo3(from_py_with = args::trim)] trim: bool,
        #[pyo3(from_py_with = args::script)] script: Option<String>,
        controls: Option<&Bound<'_, PyDict>>,
    ) -> PyResult<Self> {
        let (model, script) = (model.as_str(), script.as_deref());
        let spec = StartSpec {
            altitude_ft,
            speed_kt,
            heading_deg,
            trim,
        };
        let controls = named_controls(controls)?;
        struct NewFlight<'a> {
            fps: u32,
            spec: &'a StartSpec,
            controls: &'a [(String, f64)],
            script: Option<&'a str>,
        }
        impl ModelJob for NewFlight<'_> {
            type Output = PyResult<Box<dyn AnyFlight>>;
            fn call<M: RegisteredModel>(self) -> Self::Output {
                if self.spec.trim {
                    for (name, what) in M::TRIM_SETS {
                        if self.controls.iter().any(|(n, _)| n == name) {
                            return Err(PyValueError::new_err(format!(
                                "{name}: cannot be given with trim=True (the trim sets {what})"
                            )));
                        }
                    }
                }
                flight::new_single::<M>(self.fps, self.spec, self.controls, self.script)
            }
        }
        let job = NewFlight {
            fps,
            spec: &spec,
            controls: &controls,
            script,
        };
        let inner = with_model(model, job).ok_or_else(|| unknown_model(model))??;
        Ok(Self { inner })
    }

    /// Steps `n` frames; `actions` (script action names) are applied on each
    /// of them after the script's.
    #[pyo3(signature = (n=1, actions=None))]
    fn step(
        &mut self,
        py: Python<'_>,
        #[pyo3(from_py_with = args::n_frames)] n: u64,
        #[pyo3(from_py_with = args::actions)] actions: Option<Vec<String>>,
    ) -> PyResult<()> {
        let actions = actions.unwrap_or_default();
        self.writing(|inner| {
            if n < 256 {
                // Too short to be worth releasing the GIL.
                return inner.step(n, &actions).map_err(PyValueError::new_err);
            }
            in_chunks(py, n, FLIGHT_FRAMES_PER_SIGNAL_CHECK, |frames| {
                py.detach(|| inner.step(frames, &actions))
                    .map_err(PyValueError::new_err)
            })
        })
    }

    /// Starts recording this flight to `path` (see `_afit_fdm.pyi`).
    #[pyo3(signature = (path, *, origin=None))]
    fn record_to(
        &mut self,
        py: Python<'_>,
        path: &Bound<'_, PyAny>,
        #[pyo3(from_py_with = args::origin)] origin: Option<(f64, f64, f64)>,
    ) -> PyResult<()> {
        let path = fspath(py, path)?;
        let origin = read_origin(origin)?;
        let _reader = self.await_reader(py, "record_to", &path)?;
        self.writing(|inner| inner.record_to(&path, &origin).map_err(attach_error))
    }

    /// Seals and closes the recording; returns the frames it holds.
    fn stop_recording(&mut self) -> PyResult<u64> {
        self.writing(|inner| {
            inner
                .stop_recording()
                .map(|(_, frames)| frames)
                .map_err(PyValueError::new_err)
        })
    }

    /// The path being recorded to, or `None`.
    #[getter]
    fn recording(&self) -> Option<String> {
        self.inner.recording_path().map(str::to_owned)
    }

    /// An independent copy of the flight (see `_afit_fdm.pyi`).
    fn copy(&self) -> Self {
        Self {
            inner: self.inner.duplicate(),
        }
    }

    /// `copy.copy(flight)`: [`PyFlight::copy`].
    fn __copy__(&self) -> Self {
        self.copy()
    }

    /// `pickle`'s recipe: `Flight._from_pickle` of the flight's bytes
    /// ([`flight::AnyFlight::pickled`]): the copy [`PyFlight::copy`]
    /// makes, across processes (`multiprocessing`, Ray).
    fn __reduce__<'py>(
        &self,
        py: Python<'py>,
    ) -> PyResult<(Bound<'py, PyAny>, (Bound<'py, pyo3::types::PyBytes>,))> {
        let restore = py.get_type::<Self>().getattr("_from_pickle")?;
        let bytes = pyo3::types::PyBytes::new(py, &self.inner.pickled());
        Ok((restore, (bytes,)))
    }

    /// The flight `pickle` made of `data` ([`flight::restore`]).
    #[classmethod]
    fn _from_pickle(_cls: &Bound<'_, pyo3::types::PyType>, data: &[u8]) -> PyResult<Self> {
        Ok(Self {
            inner: flight::restore(data)?,
        })
    }

    /// `copy.deepcopy(flight)`: [`PyFlight::copy`] (a flight holds no
    /// Python objects to copy deeply).
    fn __deepcopy__(&self, memo: &Bound<'_, PyAny>) -> Self {
        let _ = memo;
        self.copy()
    }

    /// Back to the start: state, controls, status, frame 0, script from frame 1.
    fn reset(&mut self) -> PyResult<()> {
        self.writing(|inner| inner.reset().map_err(PyValueError::new_err))
    }

    /// Writes the flight as Tacview ACMI to `path` (see `_afit_fdm.pyi`).
    #[pyo3(signature = (path, *, origin=None, reference_time=None, title=None))]
    fn acmi_to(
        &mut self,
        py: Python<'_>,
        path: &Bound<'_, PyAny>,
        #[pyo3(from_py_with = args::origin)] origin: Option<(f64, f64, f64)>,
        #[pyo3(from_py_with = args::reference_time)] reference_time: Option<String>,
        #[pyo3(from_py_with = args::title)] title: Option<String>,
    ) -> PyResult<()> {
        let (reference_time, title) = (reference_time.as_deref(), title.as_deref());
        let path = fspath(py, path)?;
        let origin = read_origin(origin)?;
        let _reader = self.await_reader(py, "acmi_to", &path)?;
        self.writing(|inner| {
            inner
                .acmi_to(&path, &origin, reference_time, title)
                .map_err(attach_error)
        })
    }

    /// Writes the flight's CSV to `path` (see `_afit_fdm.pyi`).
    #[pyo3(signature = (path, *, origin=None))]
    fn csv_to(
        &mut self,
        py: Python<'_>,
        path: &Bound<'_, PyAny>,
        #[pyo3(from_py_with = args::origin)] origin: Option<(f64, f64, f64)>,
    ) -> PyResult<()> {
        let path = fspath(py, path)?;
        let origin = read_origin(origin)?;
        let _reader = self.await_reader(py, "csv_to", &path)?;
        self.writing(|inner| inner.csv_to(&path, &origin).map_err(attach_error))
    }

    /// Sends the flight to FlightGear at `target` (see `_afit_fdm.pyi`).
    #[pyo3(signature = (target, *, origin=None))]
    fn flightgear_to(
        &mut self,
        #[pyo3(from_py_with = args::target)] target: String,
        #[pyo3(from_py_with = args::origin)] origin: Option<(f64, f64, f64)>,
    ) -> PyResult<()> {
        let target = target.as_str();
        let origin = read_origin(origin)?;
        self.inner
            .flightgear_to(target, &origin)
            .map_err(attach_error)
    }

    /// The FlightGear link's counts so far (the `fg` object of
    /// `sim-cli --fg ... --json`), or `None` without a link.
    #[getter]
    fn flightgear_report<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyDict>>> {
        let Some(stats) = self.inner.flightgear_report() else {
            return Ok(None);
        };
        let report = PyDict::new(py);
        report.set_item("sent", stats.sent)?;
        report.set_item("failed", stats.failed)?;
        Ok(Some(report))
    }

    /// Publishes the flight as a DIS entity to `target` (see `_afit_fdm.pyi`).
    #[cfg(feature = "dis")]
    #[pyo3(signature = (target, *, origin=None, entity=1, callsign=None, site=1, application=1, exercise=1, version=7, dr="rvw", position_threshold_m=1.0, orientation_threshold_deg=3.0, heartbeat_s=5.0, every_frame=false))]
    #[allow(clippy::too_many_arguments)]
    fn dis_to(
        &mut self,
        #[pyo3(from_py_with = args::target)] target: String,
        #[pyo3(from_py_with = args::origin)] origin: Option<(f64, f64, f64)>,
        #[pyo3(from_py_with = args::entity)] entity: u16,
        #[pyo3(from_py_with = args::callsign)] callsign: Option<String>,
        #[pyo3(from_py_with = args::site)] site: u16,
        #[pyo3(from_py_with = args::application)] application: u16,
        #[pyo3(from_py_with = args::exercise)] exercise: u8,
        #[pyo3(from_py_with = args::version)] version: u8,
        #[pyo3(from_py_with = args::dr)] dr: &str,
        #[pyo3(from_py_with = args::position_threshold_m)] position_threshold_m: f64,
        #[pyo3(from_py_with = args::orientation_threshold_deg)] orientation_threshold_deg: f64,
        #[pyo3(from_py_with = args::heartbeat_s)] heartbeat_s: f64,
        #[pyo3(from_py_with = args::every_frame)] every_frame: bool,
    ) -> PyResult<()> {
        let target = target.as_str();
        let origin = read_origin(origin)?;
        let config = dis::flight_dis(&dis::DisArgs {
            target,
            entity,
            callsign,
            site,
            application,
            exercise,
            version,
            dr,
            position_threshold_m,
            orientation_threshold_deg,
            heartbeat_s,
            every_frame,
        })?;
        self.inner.dis_to(&config, &origin).map_err(attach_error)
    }

    /// The DIS output's counts so far (the `dis` object of `sim-cli --json`),
    /// or `None` without a DIS output.
    #[cfg(feature = "dis")]
    #[getter]
    fn dis_report<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyAny>>> {
        let Some(report) = self.inner.dis_report() else {
            return Ok(None);
        };
        let text = serde_json::to_string(&report)
            .map_err(|e| PyValueError::new_err(format!("dis_report: {e}")))?;
        Ok(Some(py.import("json")?.call_method1("loads", (text,))?))
    }

    /// The attached outputs, e.g. `["acmi /tmp/f.acmi", "csv /tmp/f.csv"]`.
    #[getter]
    fn outputs(&self) -> Vec<String> {
        self.inner.outputs()
    }

    /// Finishes and detaches every output (see `_afit_fdm.pyi`).
    fn close_outputs(&mut self) -> PyResult<()> {
        self.writing(|inner| {
            inner
                .close_outputs()
                .map_err(pyo3::exceptions::PyOSError::new_err)
        })
    }

    /// Sets controls by name (validated; e.g. `throttle=0.5`).
    #[pyo3(signature = (**controls))]
    fn set_controls(&mut self, controls: Option<&Bound<'_, PyDict>>) -> PyResult<()> {
        let values = named_controls(controls)?;
        self.inner.set_controls(&values).map_err(flight::to_py)
    }

    /// The model's name.
    #[getter]
    fn model(&self) -> &'static str {
        self.inner.model()
    }

    /// Frames stepped.
    #[getter]
    fn frame(&self) -> u64 {
        self.inner.frame()
    }

    /// Frames per second.
    #[getter]
    fn fps(&self) -> f64 {
        self.inner.fps()
    }

    /// The time step, s.
    #[getter]
    fn dt_s(&self) -> f64 {
        self.inner.dt_s()
    }

    /// Simulated time, s.
    #[getter]
    fn time_s(&self) -> f64 {
        self.inner.view().time_s
    }

    /// The model's state by name.
    #[getter]
    fn state<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let d = PyDict::new(py);
        for (k, v) in self.inner.state() {
            d.set_item(k, v)?;
        }
        Ok(d)
    }

    /// The controls by name.
    #[getter]
    fn controls<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let d = PyDict::new(py);
        for (k, v) in self.inner.controls() {
            d.set_item(k, v)?;
        }
        Ok(d)
    }

    /// The common `FlightView` by name (SI units, shared earth frame).
    #[getter]
    fn view<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        flight::view_dict(py, &self.inner.view())
    }

    /// The flight status as a word (`on_ground`, `airborne`, `landed_safe`,
    /// `landed_rough`, `crashed`, `diverged`).
    #[getter]
    fn status(&self) -> &'static str {
        self.inner.status().code()
    }

    /// The flight status as its integer code (0..5, `afit_fdm.Status`).
    #[getter]
    fn status_code(&self) -> u8 {
        status_code(self.inner.status())
    }

    /// The model's script action names.
    #[getter]
    fn actions(&self) -> Vec<&'static str> {
        self.inner.action_names().to_vec()
    }

    fn __repr__(&self) -> String {
        format!(
            "Flight(model={:?}, fps={}, frame={}, status={:?})",
            self.inner.model(),
            self.inner.fps(),
            self.inner.frame(),
            self.inner.status().code()
        )
    }
}

/// A task's arguments ([`fleet::TaskArgs`]), for `Fleet.task_step` and
/// `Fleet.task_observe`.
fn task_args<'a>(
    task: task::Task,
    (target_alt_ft, target_heading_deg): (&'a [f64], &'a [f64]),
    max_steps: i64,
) -> fleet::TaskArgs<'a> {
    fleet::TaskArgs {
        task,
        target_alt_ft,
        target_heading_deg,
        max_steps,
    }
}

/// Many aircraft of one model, stepped by the SIMD fleet kernels.
#[pyclass(module = "afit_fdm._afit_fdm", name = "Fleet")]
pub struct PyFleet {
    inner: Box<dyn AnyFleet>,
    buffers: Buffers,
    views: Py<PyDict>,
    last_step: (f64, f64),
}

fn read_mask(mask: Option<&Bound<'_, PyAny>>, n: usize) -> PyResult<Option<Vec<bool>>> {
    let Some(mask) = mask.filter(|m| !m.is_none()) else {
        return Ok(None);
    };
    if !(mask.hasattr("dtype")? && mask.getattr("dtype")?.str()? == "bool") {
        return Err(pyo3::exceptions::PyTypeError::new_err(
            "mask: expected a bool NumPy array",
        ));
    }
    let shape: Vec<usize> = mask.getattr("shape")?.extract()?;
    if shape != [n] {
        return Err(PyValueError::new_err(format!(
            "mask: expected shape ({n},), got {shape:?}"
        )));
    }
    let array: numpy::PyReadonlyArray1<'_, bool> = mask.extract()?;
    Ok(Some(array.as_array().iter().copied().collect()))
}

impl PyFleet {
    /// The Python fleet around `inner`: its state views made and filled.
    fn from_inner(py: Python<'_>, inner: Box<dyn AnyFleet>) -> PyResult<Self> {
        let fields = inner.state_fields();
        let buffers = Buffers::new(py, fields.len(), inner.len())?;
        buffers.with_mut(py, |c, s| inner.gather(c, s))?;
        let views = PyDict::new(py);
        let columns = buffers.columns_view.bind(py);
        for (i, name) in fields.iter().enumerate() {
            views.set_item(*name, columns.get_item(i)?)?;
        }
        Ok(Self {
            inner,
            buffers,
            views: views.unbind(),
            last_step: (0.0, 0.0),
        })
    }
}

#[pymethods]
impl PyFleet {
    /// See `_afit_fdm.pyi`.
    #[new]
    #[pyo3(signature = (model, n, *, fps=30, precision="exact", parallel=true, altitude_ft=None, speed_kt=None, heading_deg=None, trim=false, **controls))]
    #[allow(clippy::too_many_arguments)]
    fn new(
        py: Python<'_>,
        #[pyo3(from_py_with = args::model)] model: String,
        #[pyo3(from_py_with = args::n_aircraft)] n: usize,
        #[pyo3(from_py_with = args::fps)] fps: u32,
        #[pyo3(from_py_with = args::precision)] precision: &str,
        #[pyo3(from_py_with = args::parallel)] parallel: bool,
        altitude_ft: Option<&Bound<'_, PyAny>>,
        speed_kt: Option<&Bound<'_, PyAny>>,
        heading_deg: Option<&Bound<'_, PyAny>>,
        #[pyo3(from_py_with = args::trim)] trim: bool,
        controls: Option<&Bound<'_, PyDict>>,
    ) -> PyResult<Self> {
        let model = model.as_str();
        let fps = f64::from(fps);
        let precision_value: Precision = precision
            .parse()
            .map_err(|e| PyValueError::new_err(format!("precision: {e}")))?;
        let start = [
            ("altitude_ft", altitude_ft),
            ("speed_kt", speed_kt),
            ("heading_deg", heading_deg),
        ];
        struct NewFleet<'a, 'py> {
            n: usize,
            fps: f64,
            precision: Precision,
            parallel: bool,
            start: [(&'a str, Option<&'a Bound<'py, PyAny>>); 3],
            trim: bool,
            controls: Option<&'a Bound<'py, PyDict>>,
        }
        impl ModelJob for NewFleet<'_, '_> {
            type Output = PyResult<Box<dyn AnyFleet>>;
            fn call<M: RegisteredModel>(self) -> Self::Output {
                let (s, c) = fleet::read_arguments(
                    M::CONTROL_FIELDS,
                    M::NAME,
                    self.n,
                    self.start,
                    self.trim,
                    self.controls,
                )?;
                fleet::new_lanes::<M>(self.n, self.fps, self.precision, self.parallel, &s, &c)
            }
        }
        let job = NewFleet {
            n,
            fps,
            precision: precision_value,
            parallel,
            start,
            trim,
            controls,
        };
        let inner = with_model(model, job).ok_or_else(|| unknown_model(model))??;
        Self::from_inner(py, inner)
    }

    /// An independent copy of the fleet (see `_afit_fdm.pyi`).
    fn copy(&self, py: Python<'_>) -> PyResult<Self> {
        Self::from_inner(py, self.inner.duplicate())
    }

    /// `copy.copy(fleet)`: [`PyFleet::copy`].
    fn __copy__(&self, py: Python<'_>) -> PyResult<Self> {
        self.copy(py)
    }

    /// `copy.deepcopy(fleet)`: [`PyFleet::copy`] (the copy's state views
    /// are its own arrays, as a deep copy's are).
    fn __deepcopy__(&self, py: Python<'_>, memo: &Bound<'_, PyAny>) -> PyResult<Self> {
        let _ = memo;
        self.copy(py)
    }

    /// `pickle`'s recipe: `Fleet._from_pickle` of the fleet's bytes
    /// ([`fleet::pickle`]): the copy [`PyFleet::copy`] makes, across
    /// processes (`multiprocessing`, Ray).
    fn __reduce__<'py>(
        &self,
        py: Python<'py>,
    ) -> PyResult<(Bound<'py, PyAny>, (Bound<'py, pyo3::types::PyBytes>,))> {
        let restore = py.get_type::<Self>().getattr("_from_pickle")?;
        let inner = &self.inner;
        let data = py.detach(|| inner.pickled());
        Ok((restore, (pyo3::types::PyBytes::new(py, &data),)))
    }

    /// The fleet `pickle` made of `data` ([`fleet::pickle::restore`]).
    #[classmethod]
    fn _from_pickle(
        _cls: &Bound<'_, pyo3::types::PyType>,
        py: Python<'_>,
        data: &[u8],
    ) -> PyResult<Self> {
        let inner = py.detach(|| fleet::pickle::restore(data))?;
        Self::from_inner(py, inner)
    }

    /// Steps every aircraft `frames` frames with the GIL released, then
    /// refreshes the state views.
    #[pyo3(signature = (frames=1))]
    fn step(
        &mut self,
        py: Python<'_>,
        #[pyo3(from_py_with = args::frames)] frames: u64,
    ) -> PyResult<()> {
        let inner = &mut self.inner;
        let per_check = fleet::frames_per_signal_check(inner.len());
        let (flown, start, end) = self.buffers.with_mut(py, |c, s| {
            let start = fleet::now_s();
            let flown = in_chunks(py, frames, per_check, |frames| {
                py.detach(|| inner.fly(frames))
                    .map_err(|e| PyValueError::new_err(e.to_string()))
            });
            // The views show the frames flown, also those before a signal.
            py.detach(|| inner.gather(c, s));
            (flown, start, fleet::now_s())
        })?;
        self.last_step = (start, end);
        flown
    }

    /// Restarts the aircraft selected by `mask` (all without one).
    #[pyo3(signature = (mask=None, *, altitude_ft=None, speed_kt=None, heading_deg=None, trim=false, **controls))]
    #[allow(clippy::too_many_arguments)]
    fn reset(
        &mut self,
        py: Python<'_>,
        mask: Option<&Bound<'_, PyAny>>,
        altitude_ft: Option<&Bound<'_, PyAny>>,
        speed_kt: Option<&Bound<'_, PyAny>>,
        heading_deg: Option<&Bound<'_, PyAny>>,
        #[pyo3(from_py_with = args::trim)] trim: bool,
        controls: Option<&Bound<'_, PyDict>>,
    ) -> PyResult<()> {
        let n = self.inner.len();
        let mask = read_mask(mask, n)?;
        let (s, c) = fleet::read_arguments(
            self.inner.control_fields(),
            self.inner.model(),
            n,
            [
                ("altitude_ft", altitude_ft),
                ("speed_kt", speed_kt),
                ("heading_deg", heading_deg),
            ],
            trim,
            controls,
        )?;
        self.inner.reset(mask.as_deref(), &s, &c)?;
        let inner = &self.inner;
        self.buffers.with_mut(py, |cols, st| inner.gather(cols, st))
    }

    /// Sets controls of the aircraft selected by `mask` (all without one).
    #[pyo3(signature = (mask=None, **controls))]
    fn set_controls(
        &mut self,
        mask: Option<&Bound<'_, PyAny>>,
        controls: Option<&Bound<'_, PyDict>>,
    ) -> PyResult<()> {
        let n = self.inner.len();
        let mask = read_mask(mask, n)?;
        let (_, c) = fleet::read_arguments(
            self.inner.control_fields(),
            self.inner.model(),
            n,
            [
                ("altitude_ft", None),
                ("speed_kt", None),
                ("heading_deg", None),
            ],
            false,
            controls,
        )?;
        self.inner.set_controls(&c, mask.as_deref())
    }

    /// One step of a Gymnasium task for every aircraft (`afit_fdm.gym`'s
    /// engine; see `_afit_fdm.pyi`).
    #[pyo3(signature = (actions, frames, task, target_alt_ft, target_heading_deg, steps, max_steps, obs, reward, terminated, truncated, *, observe=true, views=true))]
    #[allow(clippy::too_many_arguments)]
    fn task_step(
        &mut self,
        py: Python<'_>,
        actions: &Bound<'_, PyAny>,
        #[pyo3(from_py_with = args::frames)] frames: u64,
        #[pyo3(from_py_with = args::task)] task: String,
        target_alt_ft: &Bound<'_, PyAny>,
        target_heading_deg: &Bound<'_, PyAny>,
        steps: &Bound<'_, PyAny>,
        #[pyo3(from_py_with = args::max_steps)] max_steps: i64,
        obs: &Bound<'_, PyAny>,
        reward: &Bound<'_, PyAny>,
        terminated: &Bound<'_, PyAny>,
        truncated: &Bound<'_, PyAny>,
        #[pyo3(from_py_with = args::observe)] observe: bool,
        #[pyo3(from_py_with = args::views)] views: bool,
    ) -> PyResult<()> {
        let task = task::Task::named(&task).map_err(PyValueError::new_err)?;
        let n = self.inner.len();
        let k = self.inner.task_actions();
        let actions = task_io::actions(py, actions, n, k)?;
        let targets = task_io::Targets::read(target_alt_ft, target_heading_deg, n)?;
        let mut steps = task_io::steps(steps, n)?;
        let mut outs = task_io::Outs::read(
            obs,
            reward,
            terminated,
            truncated,
            n,
            self.inner.task_observations(),
        )?;
        let inner = &mut self.inner;
        let buffers = &self.buffers;
        let (mut columns, mut status) = buffers.borrow_mut(py)?;
        let (columns, status) = fleet::buffer_slices(&mut columns, &mut status)?;
        // Without views the state columns are left as they are (no slice of
        // them to write): the statuses are still written.
        let columns = if views { columns } else { &mut [] };
        let steps = steps
            .as_slice_mut()
            .map_err(|e| PyValueError::new_err(e.to_string()))?;
        let targets = targets.slices()?;
        let outs = outs.slices()?;
        let values = actions.values()?;
        let args = task_args(task, targets, max_steps);
        let start = fleet::now_s();
        // A step of more frames than one look at the signals allows is the
        // actions set with the first stretch of frames, the rest flown in
        // stretches with a look at Python's signals between two (as `step`),
        // then the outputs filled: what one call gives, bit for bit
        // (`AnyFleet::task_step`'s contract), and Ctrl-C stops it.
        let per_check = fleet::frames_per_signal_check(n);
        let first = frames.min(per_check);
        let mut outs = Some(outs.into_task_out(columns, status));
        let observe_now = if observe && first == frames {
            outs.take().map(|out| (&args, out))
        } else {
            None
        };
        py.detach(|| inner.task_step(values, first, steps, observe_now))
            .map_err(PyValueError::new_err)?;
        let rest = in_chunks(py, frames - first, per_check, |frames| {
            py.detach(|| inner.fly(frames))
                .map_err(|e| PyValueError::new_err(e.to_string()))
        });
        // Also after a signal: the outputs and the statuses show the frames
        // flown so far, as `step`'s views do.
        if let Some(out) = outs.filter(|_| observe) {
            py.detach(|| inner.task_observe(&args, steps, out));
        }
        self.last_step = (start, fleet::now_s());
        rest
    }

    /// Fills the task's outputs for the fleet as it is (after resets), as
    /// `task_step(..., observe=True)` does after stepping.
    #[allow(clippy::too_many_arguments)]
    fn task_observe(
        &mut self,
        py: Python<'_>,
        #[pyo3(from_py_with = args::task)] task: String,
        target_alt_ft: &Bound<'_, PyAny>,
        target_heading_deg: &Bound<'_, PyAny>,
        steps: &Bound<'_, PyAny>,
        #[pyo3(from_py_with = args::max_steps)] max_steps: i64,
        obs: &Bound<'_, PyAny>,
        reward: &Bound<'_, PyAny>,
        terminated: &Bound<'_, PyAny>,
        truncated: &Bound<'_, PyAny>,
    ) -> PyResult<()> {
        let task = task::Task::named(&task).map_err(PyValueError::new_err)?;
        let n = self.inner.len();
        let targets = task_io::Targets::read(target_alt_ft, target_heading_deg, n)?;
        let steps = task_io::steps(steps, n)?;
        let mut outs = task_io::Outs::read(
            obs,
            reward,
            terminated,
            truncated,
            n,
            self.inner.task_observations(),
        )?;
        let inner = &self.inner;
        let (mut columns, mut status) = self.buffers.borrow_mut(py)?;
        let (columns, status) = fleet::buffer_slices(&mut columns, &mut status)?;
        let targets = targets.slices()?;
        let steps = steps
            .as_slice()
            .map_err(|e| PyValueError::new_err(e.to_string()))?;
        let outs = outs.slices()?;
        py.detach(|| {
            let args = task_args(task, targets, max_steps);
            inner.task_observe(&args, steps, outs.into_task_out(columns, status));
        });
        Ok(())
    }

    /// The state columns by name: read-only views, refreshed in place.
    #[getter]
    fn state<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        self.views.bind(py).copy()
    }

    /// One state column by name (a read-only view).
    fn __getitem__<'py>(&self, py: Python<'py>, name: &str) -> PyResult<Bound<'py, PyAny>> {
        self.views.bind(py).get_item(name)?.ok_or_else(|| {
            pyo3::exceptions::PyKeyError::new_err(format!(
                "{name:?} is not a state field of {} (fields: {})",
                self.inner.model(),
                self.inner.state_fields().join(", ")
            ))
        })
    }

    /// The whole `(fields, n)` state array, read-only.
    #[getter]
    fn columns<'py>(&self, py: Python<'py>) -> Bound<'py, PyAny> {
        self.buffers.columns_view.bind(py).clone()
    }

    /// Statuses as a read-only `uint8` view (codes of `afit_fdm.Status`).
    #[getter]
    fn status<'py>(&self, py: Python<'py>) -> Bound<'py, PyAny> {
        self.buffers.status_view.bind(py).clone()
    }

    /// The controls by name, as new arrays.
    #[getter]
    fn controls<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let d = PyDict::new(py);
        for ((name, _, _), column) in self
            .inner
            .control_fields()
            .iter()
            .zip(self.inner.controls())
        {
            d.set_item(*name, PyArray1::from_vec(py, column))?;
        }
        Ok(d)
    }

    /// Names of the state columns, in `columns` order.
    #[getter]
    fn fields(&self) -> Vec<&'static str> {
        self.inner.state_fields().to_vec()
    }

    /// The model's name.
    #[getter]
    fn model(&self) -> &'static str {
        self.inner.model()
    }

    /// Frames per second.
    #[getter]
    fn fps(&self) -> f64 {
        self.inner.fps()
    }

    /// `"exact"` or `"fast"`.
    #[getter]
    fn precision(&self) -> &'static str {
        self.inner.precision().name()
    }

    /// The instruction set the kernel runs on.
    #[getter]
    fn instruction_set(&self) -> &'static str {
        self.inner.instruction_set()
    }

    /// `(start, end)` of the last `step`'s work, seconds on a process-wide
    /// monotonic clock, measured inside Rust with the GIL released.
    #[getter]
    fn last_step_interval(&self) -> (f64, f64) {
        self.last_step
    }

    fn __len__(&self) -> usize {
        self.inner.len()
    }

    fn __repr__(&self) -> String {
        format!(
            "Fleet(model={:?}, n={}, fps={}, precision={:?})",
            self.inner.model(),
            self.inner.len(),
            self.inner.fps(),
            self.inner.precision().name()
        )
    }
}

/// The models' facts: state fields, controls with ranges, action names.
fn describe<M: BindModel>(py: Python<'_>) -> PyResult<Bound<'_, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("title", M::TITLE)?;
    d.set_item("state_fields", PyList::new(py, M::STATE_FIELDS)?)?;
    d.set_item("controls", M::CONTROL_FIELDS.to_vec())?;
    d.set_item("actions", PyList::new(py, M::Action::NAMES)?)?;
    Ok(d)
}

#[pymodule]
fn _afit_fdm(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add_class::<PyFlight>()?;
    m.add_class::<PyFleet>()?;
    m.add_class::<study::PyStudy>()?;
    m.add_class::<replay::PyReplay>()?;
    m.add_function(wrap_pyfunction!(replay::replay, m)?)?;
    m.add("RecordingError", py.get_type::<replay::RecordingError>())?;
    m.add(
        "RecordingCutError",
        py.get_type::<replay::RecordingCutError>(),
    )?;
    m.add(
        "ReplayDivergedError",
        py.get_type::<replay::ReplayDivergedError>(),
    )?;
    m.add_function(wrap_pyfunction!(study::summarize_columns, m)?)?;
    m.add_function(wrap_pyfunction!(task_io::math_atan2, m)?)?;
    m.add_function(wrap_pyfunction!(task_io::math_hypot, m)?)?;
    m.add("STATUS_CODES", study::status_codes().to_vec())?;
    struct Describe<'a, 'py>(Python<'py>, &'a Bound<'py, PyDict>);
    impl ModelJob for Describe<'_, '_> {
        type Output = PyResult<()>;
        fn call<M: RegisteredModel>(self) -> PyResult<()> {
            self.1.set_item(M::NAME, describe::<M>(self.0)?)
        }
    }
    let models = PyDict::new(py);
    for name in MODELS {
        with_model(name, Describe(py, &models)).ok_or_else(|| unknown_model(name))??;
    }
    m.add("MODELS", models)?;
    m.add("MAX_FPS", fdm_run::MAX_FPS)?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
