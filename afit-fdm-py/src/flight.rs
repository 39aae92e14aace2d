//! One aircraft: `afit_fdm.Flight`.
//!
//! [`Single`] is the engine: the one place that runs a frame (the adapter to
//! switch to the run library when it exists). A frame is the ECS's, as
//! `sim-cli` flies it (docs/cli.md): [`Model::begin_frame`], the script's
//! actions for the frame (frames counted from 1, file order), the actions
//! given to `step`, then [`fdm_core::model::fly`] (the model's step, the
//! ground contact and the flight status). `fdm-ecs/tests/ecs_parity.rs` and
//! `fdm-core/tests/ground_contact.rs` prove that the ECS frame is exactly this;
//! the Python suite compares every frame with `sim-cli --csv`.

use fdm_core::model::{fly, FlightStatus, FlightView, Model, ScriptAction};
use fdm_core::script::{Script, ScriptCursor};
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::models::BindModel;
use crate::start::StartSpec;

/// One aircraft of model `M` with its controls, status, script and clock.
#[derive(Debug)]
pub struct Single<M: Model> {
    aircraft: M::Aircraft,
    start: (M::Controls, M::State),
    controls: M::Controls,
    state: M::State,
    status: FlightStatus,
    script: Script<M::Action>,
    cursor: ScriptCursor,
    frame: u64,
    fps: f64,
    dt: M::TimeStep,
}

impl<M: BindModel> Single<M> {
    fn new(controls: M::Controls, state: M::State, script: Script<M::Action>, fps: f64) -> Self {
        Self {
            aircraft: M::default_aircraft(),
            start: (controls, state),
            controls,
            state,
            status: FlightStatus::initial(M::height_m(&state)),
            script,
            cursor: ScriptCursor::new(),
            frame: 0,
            fps,
            dt: M::time_step(fps),
        }
    }

    /// `n` frames, each with `actions` after the script's.
    fn step(&mut self, n: u64, actions: &[M::Action]) {
        for _ in 0..n {
            self.frame += 1;
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
    }

    fn view(&self) -> FlightView {
        M::view(&self.aircraft, &self.controls, &self.state)
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
    /// Back to the start, frame 0, the script from its first frame.
    fn reset(&mut self);
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
        controls =
            M::set_control(controls, index, *value).map_err(|e| (false, format!("{name}: {e}")))?;
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
        self.fps
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
        Single::step(self, n, &parsed);
        Ok(())
    }
    fn reset(&mut self) {
        (self.controls, self.state) = self.start;
        self.status = FlightStatus::initial(M::height_m(&self.state));
        self.cursor.reset();
        self.frame = 0;
    }
    fn state(&self) -> Vec<(&'static str, f64)> {
        let mut values = vec![0.0; M::STATE_FIELDS.len()];
        M::state_values(&self.state, &mut values);
        M::STATE_FIELDS.iter().copied().zip(values).collect()
    }
    fn controls(&self) -> Vec<(&'static str, f64)> {
        let mut values = vec![0.0; M::CONTROL_FIELDS.len()];
        M::control_values(&self.controls, &mut values);
        M::CONTROL_FIELDS.iter().map(|c| c.0).zip(values).collect()
    }
    fn set_controls(&mut self, values: &[(String, f64)]) -> Result<(), (bool, String)> {
        self.controls = apply_named::<M>(self.controls, values)?;
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
}

/// Builds a flight of model `M`.
///
/// # Errors
/// Bad controls, start or script, as Python exceptions.
pub fn new_single<M: BindModel>(
    fps: f64,
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
    Ok(Box::new(Single::<M>::new(controls, state, script, fps)))
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
