//! One aircraft: `afit_fdm.Flight`.
//!
//! [`Single`] is the engine: the one place that runs a frame. A frame is the ECS's, as
//! `sim-cli` flies it (docs/cli.md): [`Model::begin_frame`](fdm_core::model::Model::begin_frame), the script's
//! actions for the frame (frames counted from 1, file order), the actions
//! given to `step`, then [`fdm_core::model::fly`] (the model's step, the
//! ground contact and the flight status). `fdm-ecs/tests/ecs_parity.rs` and
//! `fdm-core/tests/ground_contact.rs` prove that the ECS frame is exactly this;
//! the Python suite compares every frame with `sim-cli --csv`.
//!
//! Recording and outputs are the run library's: its recording writer
//! ([`fdm_run::recording`]) and its [`fdm_run::Output`]s ([`crate::outputs`]),
//! handed every frame as `fdm_run::Run` hands them (frame 0 when attached,
//! each flown frame, each reset).

use std::fs::File;
use std::path::Path;
use std::sync::Arc;

use fdm_core::geodesy::GeodeticOrigin;
use fdm_core::model::{fly, FlightStatus, FlightView, ScriptAction};
use fdm_core::script::{Echo, Script, ScriptCursor};
use fdm_run::recording::{RecordWriteError, RecordWriter, SyncedFile};
use fdm_run::{Event, RunModel, Start};
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::models::BindModel;
use crate::outputs::{AttachError, FrameData, Outputs};
use crate::pipes::SignalWatch;
use crate::start::StartSpec;

/// A recording in progress: the run library's writer (`fdm_run::recording`,
/// the format `sim-cli --record` writes) on a file, and where it is.
struct Recorder<M: RunModel> {
    writer: RecordWriter<M::Action, SyncedFile>,
    path: String,
    /// Frames recorded, across resets.
    frames: u64,
}

impl<M: RunModel> std::fmt::Debug for Recorder<M> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Recorder")
            .field("path", &self.path)
            .finish_non_exhaustive()
    }
}

impl<M: RunModel> Drop for Recorder<M> {
    /// A flight dropped while recording still seals its recording (best
    /// effort: an error here has no one to go to; `stop_recording` reports it).
    fn drop(&mut self) {
        let _ = self.writer.finish();
    }
}

/// One aircraft of model `M` with its controls, status, script and clock.
#[derive(Debug)]
pub struct Single<M: BindModel> {
    aircraft: M::Aircraft,
    start: (M::Controls, M::State),
    controls: M::Controls,
    state: M::State,
    status: FlightStatus,
    script: Script<M::Action>,
    cursor: ScriptCursor,
    frame: u64,
    /// Frames flown since the flight began, across resets (the outputs'
    /// clock).
    flown: u64,
    fps: u32,
    dt: M::TimeStep,
    /// Controls were set by name since the start or the last reset: the
    /// flight is no longer where a recording's header would say it starts.
    controls_set: bool,
    recorder: Option<Recorder<M>>,
    outputs: Outputs<M>,
    /// The frame's actions in order (script's, then the caller's) while a
    /// recording or an output is on, reused.
    frame_actions: Vec<M::Action>,
    /// Python's signals looked at by the output files' waiting writes.
    watch: Arc<SignalWatch>,
}

impl<M: BindModel> Single<M> {
    /// An aircraft starting from `controls` and `state`.
    pub fn new(
        aircraft: M::Aircraft,
        controls: M::Controls,
        state: M::State,
        script: Script<M::Action>,
        fps: u32,
    ) -> Self {
        Self {
            aircraft,
            start: (controls, state),
            controls,
            state,
            status: FlightStatus::initial(M::height_m(&state)),
            script,
            cursor: ScriptCursor::new(),
            frame: 0,
            flown: 0,
            fps,
            dt: M::time_step(f64::from(fps)),
            controls_set: false,
            recorder: None,
            outputs: Outputs::default(),
            frame_actions: Vec::new(),
            watch: Arc::default(),
        }
    }

    /// `n` frames, each with `actions` after the script's; each frame is
    /// recorded when a recording is on, and handed to the outputs.
    ///
    /// # Errors
    /// Writing the recording or an output failed (the frame was flown; the
    /// recording or that output is closed, with what it had, and off).
    pub fn step(&mut self, n: u64, actions: &[M::Action]) -> Result<(), String> {
        if self.recorder.is_some() || !self.outputs.is_empty() {
            for _ in 0..n {
                self.step_observed(actions)?;
            }
            return Ok(());
        }
        for _ in 0..n {
            self.frame += 1;
            self.flown += 1;
            let mut controls = M::begin_frame(self.controls);
            for action in self.cursor.actions(&self.script, self.frame) {
                controls = M::apply(&self.aircraft, controls, action);
            }
            for &action in actions {
                controls = M::apply(&self.aircraft, controls, action);
            }
            self.controls = controls;
            (self.state, self.status) = fly::<M>(
                &self.aircraft,
                &self.controls,
                self.status,
                &self.state,
                self.dt,
            );
        }
        Ok(())
    }

    /// One frame as [`Self::step`] flies it, its actions (the script's, then
    /// `actions`: what the model applied, in order) handed to the recording,
    /// then the frame to the outputs.
    fn step_observed(&mut self, actions: &[M::Action]) -> Result<(), String> {
        self.frame += 1;
        self.flown += 1;
        let mut frame_actions = std::mem::take(&mut self.frame_actions);
        frame_actions.clear();
        frame_actions.extend(self.cursor.actions(&self.script, self.frame));
        frame_actions.extend_from_slice(actions);
        let mut controls = M::begin_frame(self.controls);
        for &action in &frame_actions {
            controls = M::apply(&self.aircraft, controls, action);
        }
        self.controls = controls;
        (self.state, self.status) = fly::<M>(
            &self.aircraft,
            &self.controls,
            self.status,
            &self.state,
            self.dt,
        );
        let mut recorded = Ok(());
        if let Some(recorder) = self.recorder.as_mut() {
            let written = recorder.writer.frame(&frame_actions);
            recorder.frames += 1;
            recorder
                .writer
                .set_final_state(M::state_fingerprint(&self.state));
            recorded = self.check_written(written);
        }
        let emitted = self.emit(Event::Step, &frame_actions);
        self.frame_actions = frame_actions;
        recorded.and(emitted)
    }

    /// The flight now as its outputs see it.
    fn frame_data<'a>(
        &'a self,
        event: Event,
        actions: &'a [M::Action],
        view: &'a FlightView,
    ) -> FrameData<'a, M> {
        FrameData {
            event,
            number: self.frame,
            flown: self.flown,
            fps: self.fps,
            actions,
            controls: &self.controls,
            state: &self.state,
            view,
            status: self.status,
        }
    }

    /// Hands the outputs the flight as it is now.
    fn emit(&mut self, event: Event, actions: &[M::Action]) -> Result<(), String> {
        if self.outputs.is_empty() {
            return Ok(());
        }
        let view = self.view();
        let mut outputs = std::mem::take(&mut self.outputs);
        let emitted = outputs.emit(&self.frame_data(event, actions, &view));
        self.outputs = outputs;
        emitted
    }

    /// Refuses `path` for a new file of `what` (`record_to`, `csv_to`,
    /// `acmi_to`) when the flight already writes that file (the same path,
    /// or the same file by another name: [`fdm_run::input::clash`], as
    /// `sim-cli` refuses `--csv F --acmi F`): the two would overwrite each
    /// other's bytes.
    fn refuse_clash(&self, what: &str, path: &str) -> Result<(), AttachError> {
        let mut others: Vec<(Option<&Path>, String)> = Vec::new();
        if let Some(recorder) = &self.recorder {
            others.push((Some(Path::new(&recorder.path)), "recording".to_owned()));
        }
        for (file, label) in self.outputs.files() {
            others.push((Some(Path::new(file)), format!("output `{label}`")));
        }
        let named: Vec<(Option<&Path>, &str)> =
            others.iter().map(|(p, n)| (*p, n.as_str())).collect();
        match fdm_run::input::clash(Path::new(path), &named) {
            Some(name) => Err((
                false,
                format!("{what}: {path} is already written by this flight's {name}"),
            )),
            None => Ok(()),
        }
    }

    /// Refuses a recording now: one in progress, or a flight not at its
    /// start (the recording's header holds the start).
    fn refuse_recording(&self) -> Result<(), AttachError> {
        if let Some(recorder) = &self.recorder {
            return Err((
                false,
                format!("record_to: already recording to {}", recorder.path),
            ));
        }
        if self.frame != 0 || self.controls_set {
            return Err((
                false,
                format!(
                    "record_to: a recording starts where the flight starts (its header holds \
                     the start, and a reset goes back to it), but this flight is at frame {}{}; \
                     call reset() first",
                    self.frame,
                    if self.controls_set {
                        " with controls set by value"
                    } else {
                        ""
                    }
                ),
            ));
        }
        Ok(())
    }

    /// Attaches an output made by `attach` (with the flight as it is now,
    /// its frame 0 for the output).
    fn attach_with(
        &mut self,
        attach: impl FnOnce(&mut Outputs<M>, &FrameData<'_, M>) -> Result<(), AttachError>,
    ) -> Result<(), AttachError> {
        let view = self.view();
        let mut outputs = std::mem::take(&mut self.outputs);
        let attached = attach(&mut outputs, &self.frame_data(Event::Start, &[], &view));
        self.outputs = outputs;
        attached
    }

    /// A writer's error closes the recording and becomes the caller's.
    fn check_written(&mut self, written: Result<(), RecordWriteError>) -> Result<(), String> {
        match written {
            Ok(()) => Ok(()),
            Err(e) => {
                let path = self
                    .recorder
                    .take()
                    .map(|r| r.path.clone())
                    .unwrap_or_default();
                Err(format!(
                    "recording to {path}: {e} (the recording is stopped)"
                ))
            }
        }
    }

    fn view(&self) -> FlightView {
        M::view(&self.aircraft, &self.controls, &self.state)
    }

    /// Frames since the start or the last reset.
    pub fn frame_number(&self) -> u64 {
        self.frame
    }

    /// The model's state now.
    pub fn current_state(&self) -> &M::State {
        &self.state
    }

    /// The controls now.
    pub fn current_controls(&self) -> &M::Controls {
        &self.controls
    }

    /// The flight status now.
    pub fn current_status(&self) -> FlightStatus {
        self.status
    }
}

/// What `Flight` needs from a [`Single`] of any model (a pyclass is not generic).
pub trait AnyFlight: Send + Sync {
    /// The model's name.
    fn model(&self) -> &'static str;
    /// Frames stepped since the start or the last reset.
    fn frame(&self) -> u64;
    /// Frames per second.
    fn fps(&self) -> f64;
    /// The time step, s (widened from `f32` for Bourg).
    fn dt_s(&self) -> f64;
    /// Steps `n` frames with the named actions on each.
    ///
    /// # Errors
    /// An unknown action name (nothing stepped).
    fn step(&mut self, n: u64, actions: &[String]) -> Result<(), String>;
    /// Back to the start, frame 0, the script from its first frame; the
    /// recording and the outputs take the reset.
    ///
    /// # Errors
    /// Writing the recording or an output failed (the reset happened; that
    /// recording or output is closed).
    fn reset(&mut self) -> Result<(), String>;
    /// The state by name.
    fn state(&self) -> Vec<(&'static str, f64)>;
    /// The controls by name.
    fn controls(&self) -> Vec<(&'static str, f64)>;
    /// Sets controls by name (validated).
    ///
    /// # Errors
    /// An unknown name, or a value out of range, naming it.
    fn set_controls(&mut self, values: &[(String, f64)]) -> Result<(), (bool, String)>;
    /// The common view.
    fn view(&self) -> FlightView;
    /// The status.
    fn status(&self) -> FlightStatus;
    /// The model's action names.
    fn action_names(&self) -> &'static [&'static str];
    /// Starts recording to `path` (created or truncated) with `origin` in
    /// the header.
    ///
    /// # Errors
    /// `(is_os_error, message)`: already recording, not at the start, or the
    /// file cannot be created or written.
    fn record_to(&mut self, path: &str, origin: &GeodeticOrigin) -> Result<(), (bool, String)>;
    /// Whether `what` (`record_to`, `csv_to`, `acmi_to`) may write `path`
    /// now: what it refuses before it opens the file (a recording not at
    /// the start, a file the flight already writes), so that a caller can
    /// refuse before waiting for a named pipe's reader.
    ///
    /// # Errors
    /// `(false, message)`, the message of `what`'s refusal.
    fn check_output(&self, what: &str, path: &str) -> Result<(), AttachError>;
    /// Seals and closes the recording; returns its path and frames.
    ///
    /// # Errors
    /// Not recording, or writing the end failed.
    fn stop_recording(&mut self) -> Result<(String, u64), String>;
    /// Where the recording in progress goes.
    fn recording_path(&self) -> Option<&str>;
    /// The watch on Python's signals of the flight's output files.
    fn signal_watch(&self) -> &Arc<SignalWatch>;
    /// An independent flight where this one is: the same frame, state,
    /// controls, status, script (and where it is in it), start and clocks,
    /// without the recording and the outputs (files and sockets are this
    /// flight's). Flown alike, the two give the same bits.
    fn duplicate(&self) -> Box<dyn AnyFlight>;
    /// What [`Self::duplicate`] copies, as bytes ([`restore`] reads them
    /// back): what `pickle` holds of a flight.
    fn pickled(&self) -> Vec<u8>;
    /// Attaches a Tacview ACMI file (`Flight.acmi_to`).
    ///
    /// # Errors
    /// `(is_os_error, message)`.
    fn acmi_to(
        &mut self,
        path: &str,
        origin: &GeodeticOrigin,
        reference_time: Option<&str>,
        title: Option<&str>,
    ) -> Result<(), AttachError>;
    /// Attaches a CSV file (`Flight.csv_to`).
    ///
    /// # Errors
    /// `(is_os_error, message)`.
    fn csv_to(&mut self, path: &str, origin: &GeodeticOrigin) -> Result<(), AttachError>;
    /// Attaches a FlightGear native-FDM link (`Flight.flightgear_to`).
    ///
    /// # Errors
    /// `(is_os_error, message)`.
    fn flightgear_to(&mut self, target: &str, origin: &GeodeticOrigin) -> Result<(), AttachError>;
    /// The FlightGear link's counters so far.
    fn flightgear_report(&self) -> Option<fdm_run::LinkStats>;
    /// Attaches a DIS output (`Flight.dis_to`).
    ///
    /// # Errors
    /// `(is_os_error, message)`.
    #[cfg(feature = "dis")]
    fn dis_to(
        &mut self,
        config: &fdm_run::dis::FlightDis,
        origin: &GeodeticOrigin,
    ) -> Result<(), AttachError>;
    /// The DIS output's report so far.
    #[cfg(feature = "dis")]
    fn dis_report(&self) -> Option<fdm_run::dis::DisReport>;
    /// The attached outputs' labels.
    fn outputs(&self) -> Vec<String>;
    /// Finishes and removes every output.
    ///
    /// # Errors
    /// The first output that failed to finish.
    fn close_outputs(&mut self) -> Result<(), String>;
}

/// `controls` with the named values set, each checked against the model's
/// ranges; `Err((is_type_error, message))`.
pub fn apply_named<M: BindModel>(
    mut controls: M::Controls,
    values: &[(String, f64)],
) -> Result<M::Controls, (bool, String)> {
    for (name, value) in values {
        let Some(index) = M::CONTROL_FIELDS.iter().position(|(n, _, _)| n == name) else {
            let known: Vec<&str> = M::CONTROL_FIELDS.iter().map(|c| c.0).collect();
            return Err((
                true,
                format!(
                    "{name}: not a control of {} (controls: {})",
                    M::NAME,
                    known.join(", ")
                ),
            ));
        };
        let (_, lo, hi) = M::CONTROL_FIELDS[index];
        if !value.is_finite() || !(lo..=hi).contains(value) {
            return Err((false, format!("{name}: {value} is not in {lo}..{hi}")));
        }
        controls = M::with_control(controls, index, *value)
            .map_err(|e| (false, format!("{name}: {e}")))?;
    }
    Ok(controls)
}

impl<M: BindModel> AnyFlight for Single<M> {
    fn model(&self) -> &'static str {
        M::NAME
    }
    fn frame(&self) -> u64 {
        self.frame
    }
    fn fps(&self) -> f64 {
        f64::from(self.fps)
    }
    fn dt_s(&self) -> f64 {
        self.dt.into()
    }
    fn step(&mut self, n: u64, actions: &[String]) -> Result<(), String> {
        let parsed = actions
            .iter()
            .map(|a| {
                M::Action::from_name(a).ok_or_else(|| {
                    format!(
                        "actions: {a:?} is not an action of {} (actions: {})",
                        M::NAME,
                        M::Action::NAMES.join(", ")
                    )
                })
            })
            .collect::<Result<Vec<_>, _>>()?;
        Single::step(self, n, &parsed)
    }
    fn reset(&mut self) -> Result<(), String> {
        (self.controls, self.state) = self.start;
        self.status = FlightStatus::initial(M::height_m(&self.state));
        self.cursor.reset();
        self.frame = 0;
        self.controls_set = false;
        let mut recorded = Ok(());
        if let Some(recorder) = self.recorder.as_mut() {
            let written = recorder.writer.reset();
            recorder
                .writer
                .set_final_state(M::state_fingerprint(&self.state));
            // A failed write stops the recording; the reset itself happened.
            recorded = self.check_written(written);
        }
        let emitted = self.emit(Event::Reset, &[]);
        recorded.and(emitted)
    }
    fn state(&self) -> Vec<(&'static str, f64)> {
        let mut values = vec![0.0; M::STATE_FIELDS.len()];
        M::state_values(&self.state, &mut values);
        M::STATE_FIELDS.iter().copied().zip(values).collect()
    }
    fn controls(&self) -> Vec<(&'static str, f64)> {
        named_values::<M>(&self.controls)
    }
    fn set_controls(&mut self, values: &[(String, f64)]) -> Result<(), (bool, String)> {
        if let Some(recorder) = &self.recorder {
            return Err((
                false,
                format!(
                    "set_controls: controls set by value cannot be recorded (a recording holds \
                     the start and each frame's script actions, as sim-cli's does); recording \
                     to {} goes on unchanged. Use step(actions=[...]) or a script, or \
                     stop_recording() first",
                    recorder.path
                ),
            ));
        }
        self.controls = apply_named::<M>(self.controls, values)?;
        self.controls_set = true;
        Ok(())
    }
    fn view(&self) -> FlightView {
        Single::view(self)
    }
    fn status(&self) -> FlightStatus {
        self.status
    }
    fn action_names(&self) -> &'static [&'static str] {
        M::Action::NAMES
    }
    fn check_output(&self, what: &str, path: &str) -> Result<(), AttachError> {
        if what == "record_to" {
            self.refuse_recording()?;
        }
        self.refuse_clash(what, path)
    }
    fn record_to(&mut self, path: &str, origin: &GeodeticOrigin) -> Result<(), (bool, String)> {
        self.check_output("record_to", path)?;
        let file = File::create(path).map_err(|e| (true, format!("{path}: {e}")))?;
        let start = Start::<M> {
            aircraft: self.aircraft.clone(),
            controls: self.start.0,
            state: self.start.1,
        };
        let file = SyncedFile::watched(SignalWatch::file(&self.watch, file));
        let mut writer = RecordWriter::new(file, self.fps, origin, &start)
            .map_err(|e| (true, format!("{path}: {e}")))?;
        writer.set_final_state(M::state_fingerprint(&self.state));
        self.recorder = Some(Recorder {
            writer,
            path: path.to_owned(),
            frames: 0,
        });
        Ok(())
    }
    fn stop_recording(&mut self) -> Result<(String, u64), String> {
        let Some(mut recorder) = self.recorder.take() else {
            return Err("stop_recording: not recording".to_owned());
        };
        recorder
            .writer
            .finish()
            .map_err(|e| format!("{}: {e}", recorder.path))?;
        let path = std::mem::take(&mut recorder.path);
        Ok((path, recorder.frames))
    }
    fn recording_path(&self) -> Option<&str> {
        self.recorder.as_ref().map(|r| r.path.as_str())
    }
    fn signal_watch(&self) -> &Arc<SignalWatch> {
        &self.watch
    }
    fn duplicate(&self) -> Box<dyn AnyFlight> {
        Box::new(Self {
            aircraft: self.aircraft.clone(),
            start: self.start,
            controls: self.controls,
            state: self.state,
            status: self.status,
            script: self.script.clone(),
            cursor: self.cursor.clone(),
            frame: self.frame,
            flown: self.flown,
            fps: self.fps,
            dt: self.dt,
            controls_set: self.controls_set,
            recorder: None,
            outputs: Outputs::default(),
            frame_actions: Vec::new(),
            watch: Arc::default(),
        })
    }
    fn pickled(&self) -> Vec<u8> {
        let body = Pickled::<M::Controls, M::State> {
            fps: self.fps,
            script: self.script.to_string(),
            start: self.start,
            controls: self.controls,
            state: self.state,
            status: self.status,
            frame: self.frame,
            flown: self.flown,
            controls_set: self.controls_set,
        };
        // Plain data of known size: encoding into a vector cannot fail.
        bincode::serde::encode_to_vec((PICKLE_FORMAT, M::NAME, body), pickle_config())
            .unwrap_or_default()
    }
    fn acmi_to(
        &mut self,
        path: &str,
        origin: &GeodeticOrigin,
        reference_time: Option<&str>,
        title: Option<&str>,
    ) -> Result<(), AttachError> {
        self.refuse_clash("acmi_to", path)?;
        let watch = Arc::clone(&self.watch);
        self.attach_with(|o, start| {
            o.attach_acmi(path, *origin, reference_time, title, &watch, start)
        })
    }
    fn csv_to(&mut self, path: &str, origin: &GeodeticOrigin) -> Result<(), AttachError> {
        self.refuse_clash("csv_to", path)?;
        let watch = Arc::clone(&self.watch);
        self.attach_with(|o, start| o.attach_csv(path, *origin, &watch, start))
    }
    fn flightgear_to(&mut self, target: &str, origin: &GeodeticOrigin) -> Result<(), AttachError> {
        self.attach_with(|o, start| o.attach_flightgear(target, *origin, start))
    }
    fn flightgear_report(&self) -> Option<fdm_run::LinkStats> {
        self.outputs.flightgear_report()
    }
    #[cfg(feature = "dis")]
    fn dis_to(
        &mut self,
        config: &fdm_run::dis::FlightDis,
        origin: &GeodeticOrigin,
    ) -> Result<(), AttachError> {
        self.attach_with(|o, start| o.attach_dis(config, *origin, start))
    }
    #[cfg(feature = "dis")]
    fn dis_report(&self) -> Option<fdm_run::dis::DisReport> {
        self.outputs.dis_report()
    }
    fn outputs(&self) -> Vec<String> {
        self.outputs.labels()
    }
    fn close_outputs(&mut self) -> Result<(), String> {
        self.outputs.close()
    }
}

/// Builds a flight of model `M`.
///
/// # Errors
/// Bad controls, start or script, as Python exceptions.
pub fn new_single<M: BindModel>(
    fps: u32,
    spec: &StartSpec,
    controls: &[(String, f64)],
    script: Option<&str>,
) -> PyResult<Box<dyn AnyFlight>> {
    let given = apply_named::<M>(M::initial_controls(), controls).map_err(to_py)?;
    let (controls, state) = crate::start::start::<M>(spec, M::default_aircraft(), given)
        .map_err(PyValueError::new_err)?;
    let script = match script {
        Some(text) => Script::<M::Action>::parse(text)
            .map_err(|e| PyValueError::new_err(format!("script: {e}")))?,
        None => Script::default(),
    };
    Ok(Box::new(Single::<M>::new(
        M::default_aircraft(),
        controls,
        state,
        script,
        fps,
    )))
}

/// The version of [`Pickled`]'s bytes, their first field: a flight pickled
/// by another version of the package is refused by name, not misread.
const PICKLE_FORMAT: u32 = 1;

/// The bytes' encoding: bincode's standard one (floats as their bits, so
/// the state comes back bit for bit), with a limit that keeps a damaged
/// length field from asking for more memory than any flight needs.
pub(crate) fn pickle_config() -> bincode::config::Configuration<
    bincode::config::LittleEndian,
    bincode::config::Varint,
    bincode::config::Limit<{ 1 << 24 }>,
> {
    bincode::config::standard().with_limit::<{ 1 << 24 }>()
}

/// A flight as `pickle` holds it, after its format and model name: what
/// [`AnyFlight::duplicate`] copies. The aircraft is the model's default,
/// the only one a Python flight has; the script is its text
/// ([`Script`]'s `Display`, which `parse` reads back to an equal script);
/// the script's cursor starts afresh (where it is depends only on the
/// frame and the script).
#[derive(serde::Serialize, serde::Deserialize)]
struct Pickled<C, S> {
    fps: u32,
    script: String,
    start: (C, S),
    controls: C,
    state: S,
    status: FlightStatus,
    frame: u64,
    flown: u64,
    controls_set: bool,
}

/// A flight from the bytes of [`AnyFlight::pickled`].
///
/// # Errors
/// `ValueError` for bytes that are not a flight of this package's format:
/// another format version, an unknown model, damaged bytes, or numbers no
/// flight has (a frame rate out of range, a state or controls that are not
/// finite or out of their ranges).
pub fn restore(data: &[u8]) -> PyResult<Box<dyn AnyFlight>> {
    let refused = |why: String| {
        PyValueError::new_err(format!("Flight: cannot restore a pickled flight: {why}"))
    };
    let (model, body) = pickle_header(data, "flight", PICKLE_FORMAT).map_err(refused)?;
    struct Restore<'a>(&'a [u8]);
    impl crate::models::ModelJob for Restore<'_> {
        type Output = Result<Box<dyn AnyFlight>, String>;
        fn call<M: crate::models::RegisteredModel>(self) -> Self::Output {
            restore_model::<M>(self.0)
        }
    }
    crate::models::with_model(&model, Restore(body))
        .unwrap_or_else(|| Err(format!("`{}` is not a model", Echo::short(&model))))
        .map_err(refused)
}

/// The start of a pickle of this package (a flight's or a fleet's, `what`):
/// its format version, which must be `format`, and its model's name;
/// returns the name and the bytes after it.
///
/// # Errors
/// Bytes that do not start so, or another format version, saying which.
pub(crate) fn pickle_header<'a>(
    data: &'a [u8],
    what: &str,
    format: u32,
) -> Result<(String, &'a [u8]), String> {
    let ((found, model), used): ((u32, String), usize) =
        bincode::serde::decode_from_slice(data, pickle_config())
            .map_err(|e| format!("not a pickled {what} ({e})"))?;
    if found != format {
        return Err(format!(
            "it has format {found}, this package reads format {format}"
        ));
    }
    Ok((model, &data[used..]))
}

/// [`restore`] of model `M`, from the bytes after the model's name.
fn restore_model<M: BindModel>(data: &[u8]) -> Result<Box<dyn AnyFlight>, String> {
    let (p, used): (Pickled<M::Controls, M::State>, usize) =
        bincode::serde::decode_from_slice(data, pickle_config())
            .map_err(|e| format!("damaged ({e})"))?;
    if used != data.len() {
        let more = data.len() - used;
        let plural = if more == 1 { "" } else { "s" };
        return Err(format!("{more} byte{plural} after the flight"));
    }
    if !(1..=fdm_run::MAX_FPS).contains(&p.fps) {
        return Err(format!("fps {} is not in 1..={}", p.fps, fdm_run::MAX_FPS));
    }
    let script = Script::<M::Action>::parse(&p.script).map_err(|e| format!("script: {e}"))?;
    for (what, (controls, state)) in [("start", p.start), ("now", (p.controls, p.state))] {
        if !M::is_finite(&state) {
            return Err(format!("the state ({what}) is not finite"));
        }
        check_controls::<M>(&controls).map_err(|e| format!("the controls ({what}): {e}"))?;
    }
    let mut flight = Single::<M>::new(M::default_aircraft(), p.start.0, p.start.1, script, p.fps);
    flight.controls = p.controls;
    flight.state = p.state;
    flight.status = p.status;
    flight.frame = p.frame;
    flight.flown = p.flown;
    flight.controls_set = p.controls_set;
    Ok(Box::new(flight))
}

/// Checks each of `controls` as `set_controls` would take it: finite, in
/// its range, and one of its settings (Palmer's flaps 0, 20 or 40). For
/// controls read from outside (a pickle), which `M::Controls` alone cannot
/// vouch for.
///
/// # Errors
/// The first control refused, named, and why.
pub(crate) fn check_controls<M: BindModel>(controls: &M::Controls) -> Result<(), String> {
    let named: Vec<(String, f64)> = (named_values::<M>(controls).into_iter())
        .map(|(name, value)| (name.to_owned(), value))
        .collect();
    apply_named::<M>(M::initial_controls(), &named)
        .map(|_| ())
        .map_err(|(_, e)| e)
}

/// `controls` by name, in [`RunModel`]'s `CONTROL_FIELDS` order.
fn named_values<M: BindModel>(controls: &M::Controls) -> Vec<(&'static str, f64)> {
    let mut values = vec![0.0; M::CONTROL_FIELDS.len()];
    M::control_values(controls, &mut values);
    M::CONTROL_FIELDS.iter().map(|c| c.0).zip(values).collect()
}

/// A `(is_type_error, message)` as a Python exception.
pub fn to_py((type_error, message): (bool, String)) -> PyErr {
    if type_error {
        PyTypeError::new_err(message)
    } else {
        PyValueError::new_err(message)
    }
}

/// The common view as `name → value` (units in the names).
pub fn view_dict<'py>(py: Python<'py>, v: &FlightView) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    let items: [(&str, f64); 16] = [
        ("time_s", v.time_s),
        ("x_m", v.position_m.x),
        ("y_m", v.position_m.y),
        ("z_m", v.position_m.z),
        ("vx_mps", v.velocity_mps.x),
        ("vy_mps", v.velocity_mps.y),
        ("vz_mps", v.velocity_mps.z),
        ("roll_deg", v.attitude.roll_deg),
        ("pitch_deg", v.attitude.pitch_deg),
        ("heading_deg", v.attitude.heading_deg),
        ("u_mps", v.velocity_body_mps.x),
        ("v_mps", v.velocity_body_mps.y),
        ("w_mps", v.velocity_body_mps.z),
        ("airspeed_mps", v.airspeed_mps),
        ("alpha_deg", v.alpha_deg),
        ("beta_deg", v.beta_deg),
    ];
    for (k, x) in items {
        d.set_item(k, x)?;
    }
    d.set_item("flaps_norm", v.flaps_norm)?;
    d.set_item("engine_running", v.engine_running)?;
    d.set_item("engine_rpm", v.engine_rpm)?;
    d.set_item("stalling", v.stalling)?;
    Ok(d)
}
