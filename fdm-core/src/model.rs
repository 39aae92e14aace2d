//! The model interface: what every flight dynamics model offers the layers
//! above it (the ECS shell, the SIMD fleets, the run library and its outputs,
//! the studies, the CLI, the Python package, the benchmarks).
//!
//! A model is a zero-sized type implementing [`Model`]: [`crate::palmer::Palmer`]
//! and [`crate::bourg::Bourg`] here, any number more outside this crate
//! (`fdm-ecs/examples/third_model.rs` flies a glider written against this
//! trait alone). Everything a shell needs goes through it:
//!
//! * the model's own types: [`Model::Aircraft`] (parameters, shared by every
//!   aircraft of one type), [`Model::State`] (what the step integrates),
//!   [`Model::Controls`] (the pilot's settings) and [`Model::Action`] (one key
//!   press or script action);
//! * one frame: [`Model::begin_frame`] (e.g. Bourg's control surfaces return
//!   to neutral), [`Model::apply`] for each action, then [`Model::step`] (pure,
//!   unchecked, bit-exact) or [`Model::try_step`] (checked, identical bits on
//!   success) with the time step [`Model::time_step`] derives from the frame
//!   rate;
//! * the ground and the start: [`Model::ground_contact`] and
//!   [`Model::at_rest`] (applied by [`settle`]), [`Model::state_at`] and
//!   [`Model::trim`] (starting in the air, `crate::start`);
//! * one read-only [`FlightView`] of the state in a single frame and unit
//!   system (SI, the models' shared earth frame), enough to draw the aircraft,
//!   fill a FlightGear or DIS packet, or print a report; the flight's status
//!   ([`FlightStatus`]) and how it is displayed ([`DisplayStatus`]).
//!
//! The trait has no `self`: a model is a type, not a value, so generic code
//! is monomorphised and a step through the trait is the model's own step,
//! bit for bit (`fdm-ecs/tests/ecs_parity.rs` checks it through the whole shell).
//!
//! ```
//! use fdm_core::model::Model;
//! use fdm_core::palmer::{Palmer, PalmerAction};
//!
//! fn fly<M: Model>(actions: &[M::Action], frames: u32, fps: f64) -> M::State {
//!     let aircraft = M::default_aircraft();
//!     let mut controls = M::initial_controls();
//!     let mut state = M::initial_state();
//!     let dt = M::time_step(fps);
//!     for _ in 0..frames {
//!         controls = M::begin_frame(controls);
//!         for &action in actions {
//!             controls = M::apply(&aircraft, controls, action);
//!         }
//!         state = M::step(&aircraft, &controls, &state, dt);
//!     }
//!     state
//! }
//!
//! let state = fly::<Palmer>(&[PalmerAction::ThrottleUp], 600, 30.0);
//! let view = Palmer::view(&Palmer::default_aircraft(), &Palmer::initial_controls(), &state);
//! assert!(view.airspeed_mps > 10.0 && view.time_s > 19.99);
//! ```

use core::fmt::{Debug, Display};
use core::hash::Hash;

use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

use crate::geodesy::Attitude;
use crate::start::{InitialConditions, StartError, Trimmed};

/// A flight dynamics model. See the [module documentation](self).
///
/// Implementations must keep [`Model::step`] pure (no I/O, no globals, no
/// allocation) and make [`Model::try_step`] return exactly `step`'s bits
/// whenever it succeeds.
pub trait Model: Copy + Debug + Default + Send + Sync + 'static {
    /// Short lower-case name, used as the CLI subcommand and the JSON `model`
    /// field: `"palmer"`, `"bourg"`.
    const NAME: &'static str;
    /// A human title, e.g. `"Palmer Cessna 172"`.
    const TITLE: &'static str;

    /// The parameters of one aircraft type (shared by every aircraft of that
    /// type).
    type Aircraft: Clone + Debug + PartialEq + Send + Sync + 'static;
    /// The integrated state of one aircraft.
    type State: Copy + Debug + PartialEq + Send + Sync + 'static;
    /// The pilot's control settings.
    type Controls: Copy + Debug + PartialEq + Send + Sync + 'static;
    /// One discrete control input: a key press or a script action.
    type Action: ScriptAction + Debug + Eq + Hash + Send + Sync;
    /// The time step's type and unit (seconds): `f64` for Palmer, `f32` for
    /// Bourg, as the original programs.
    type TimeStep: Copy + Debug + PartialEq + Into<f64> + Send + Sync + 'static;
    /// Why [`Model::try_step`] refused.
    type StepError: Copy + Debug + Display + PartialEq + Send + Sync + 'static;

    /// The model's default aircraft (the thesis's).
    fn default_aircraft() -> Self::Aircraft;
    /// The controls at the start of the thesis's runs.
    fn initial_controls() -> Self::Controls;
    /// The state at the start of the thesis's runs.
    fn initial_state() -> Self::State;

    /// Member `index` of a demonstration fleet: controls and a flying state
    /// that vary with the index (so neighbours differ) and place aircraft
    /// apart, for fleets, benchmarks and tests. The default is every member
    /// at [`initial_controls`](Self::initial_controls) and
    /// [`initial_state`](Self::initial_state).
    fn fleet_member(index: usize) -> (Self::Controls, Self::State) {
        let _ = index;
        (Self::initial_controls(), Self::initial_state())
    }

    /// The time step for `fps` frames per second, computed the way the
    /// original program computes it (`1.0 / fps` in the model's float type).
    fn time_step(fps: f64) -> Self::TimeStep;

    /// What happens to the controls at the start of every frame, before the
    /// frame's actions (Bourg: rudder, ailerons and elevators return to
    /// neutral). The default keeps them.
    #[must_use]
    #[inline]
    fn begin_frame(controls: Self::Controls) -> Self::Controls {
        controls
    }

    /// Applies one action to the controls, within the aircraft's limits.
    #[must_use]
    fn apply(
        aircraft: &Self::Aircraft,
        controls: Self::Controls,
        action: Self::Action,
    ) -> Self::Controls;

    /// Advances the state by one time step: pure, unchecked; non-finite inputs
    /// propagate to non-finite outputs.
    #[must_use]
    fn step(
        aircraft: &Self::Aircraft,
        controls: &Self::Controls,
        state: &Self::State,
        dt: Self::TimeStep,
    ) -> Self::State;

    /// [`Model::step`] with its inputs and its result checked; on success the
    /// result is bit-identical to [`Model::step`]'s.
    ///
    /// # Errors
    /// The model's [`Model::StepError`] naming the first problem found.
    fn try_step(
        aircraft: &Self::Aircraft,
        controls: &Self::Controls,
        state: &Self::State,
        dt: Self::TimeStep,
    ) -> Result<Self::State, Self::StepError>;

    /// Whether every number of the state, and of the outputs derived from it
    /// that can overflow on their own (e.g. a speed, the root of a sum of
    /// squares), is finite. [`advance`] calls a state that is not a
    /// divergence.
    fn is_finite(state: &Self::State) -> bool;

    /// Height above the ground plane, m (cheap: what [`FlightStatus`] needs
    /// every frame without a whole [`FlightView`]).
    fn height_m(state: &Self::State) -> f64;

    /// Climb rate, m/s, positive up.
    fn climb_rate_mps(state: &Self::State) -> f64;

    /// The common read-only view of an aircraft (SI units, the shared earth
    /// frame). Computed on demand: nothing in it feeds back into the step.
    fn view(
        aircraft: &Self::Aircraft,
        controls: &Self::Controls,
        state: &Self::State,
    ) -> FlightView;

    /// The ground's reaction to a state that a step left at or below the
    /// ground plane (`height_m(state) <= 0`): the state put back on the
    /// plane (height 0, no downward velocity), with every velocity zero when
    /// `crashed`. Called by [`settle`] only, after the model's own step, so
    /// the step itself (and every reference case) is untouched.
    ///
    /// The default changes nothing: a model without a ground (the workspace's
    /// glider example) keeps its own behaviour.
    #[must_use]
    fn ground_contact(
        aircraft: &Self::Aircraft,
        state: &Self::State,
        crashed: bool,
    ) -> Self::State {
        let _ = (aircraft, crashed);
        *state
    }

    /// A crashed aircraft one frame later: where it was, at rest, its clock
    /// advanced by `dt`. The default is the state unchanged.
    #[must_use]
    fn at_rest(state: &Self::State, dt: Self::TimeStep) -> Self::State {
        let _ = dt;
        *state
    }

    /// The state of an aircraft flying straight, level and wings level at
    /// `conditions` (altitude, true airspeed, true heading), at time 0, in the
    /// attitude the model's own start has (not trimmed: see
    /// [`trim`](Self::trim)).
    ///
    /// # Errors
    /// [`StartError::InvalidConditions`]; the default,
    /// [`StartError::Unsupported`], for models that only start at
    /// [`initial_state`](Self::initial_state).
    fn state_at(
        aircraft: &Self::Aircraft,
        conditions: &InitialConditions,
    ) -> Result<Self::State, StartError> {
        let _ = (aircraft, conditions);
        Err(StartError::Unsupported)
    }

    /// Trim: the controls (starting from `controls`, whose other settings,
    /// e.g. flaps, are kept) and the state for steady, wings-level,
    /// unaccelerated flight at `conditions`.
    ///
    /// # Errors
    /// Why the speed cannot be trimmed ([`StartError`]); the default,
    /// [`StartError::Unsupported`].
    fn trim(
        aircraft: &Self::Aircraft,
        controls: &Self::Controls,
        conditions: &InitialConditions,
    ) -> Result<Trimmed<Self::Controls, Self::State>, StartError> {
        let _ = (aircraft, controls, conditions);
        Err(StartError::Unsupported)
    }
}

/// The equations-of-motion half of a frame with a [`FlightStatus`]: the
/// model's own [`Model::step`], except that a crashed aircraft stays where it
/// is ([`Model::at_rest`]) and a diverged one is not stepped any more. A step
/// whose result is not finite ([`Model::is_finite`]) is not kept: the state
/// stays the last finite one and the status becomes
/// [`FlightStatus::Diverged`], so nothing downstream ever sees a NaN.
#[must_use]
#[inline]
pub fn advance<M: Model>(
    aircraft: &M::Aircraft,
    controls: &M::Controls,
    status: FlightStatus,
    state: &M::State,
    dt: M::TimeStep,
) -> (M::State, FlightStatus) {
    match status {
        FlightStatus::Diverged => (*state, status),
        FlightStatus::Landed(LandingState::Crash) => (M::at_rest(state, dt), status),
        _ => {
            let next = M::step(aircraft, controls, state, dt);
            if M::is_finite(&next) {
                (next, status)
            } else {
                (*state, FlightStatus::Diverged)
            }
        }
    }
}

/// The flight-status half of a frame: the new [`FlightStatus`]
/// ([`FlightStatus::update`]: takeoff, touchdown and its class) and the
/// ground contact ([`Model::ground_contact`]) when the step ended at or below
/// the ground plane. A state that ended above it is returned unchanged, bit
/// for bit; so is one resting exactly on the plane without sinking (Palmer's
/// ground roll from rest: its step already holds it at `z = 0`).
#[must_use]
#[inline]
pub fn settle<M: Model>(
    aircraft: &M::Aircraft,
    status: FlightStatus,
    state: &M::State,
) -> (M::State, FlightStatus) {
    if status.is_final() {
        return (*state, status);
    }
    let height = M::height_m(state);
    let next = status.update(height, M::climb_rate_mps(state));
    if height <= 0.0 {
        let crashed = next == FlightStatus::Landed(LandingState::Crash);
        (M::ground_contact(aircraft, state, crashed), next)
    } else {
        (*state, next)
    }
}

/// One whole frame of one aircraft with its status: [`advance`] then
/// [`settle`] (what the ECS's EquationsOfMotion and FlightStatus systems do
/// in turn). With the status `Airborne` or `OnGround`, above the ground plane
/// the state is [`Model::step`]'s, bit for bit.
///
/// ```
/// use fdm_core::model::{fly, FlightStatus, LandingState, Model};
/// use fdm_core::palmer::{Palmer, PalmerControls, PalmerState};
/// use nalgebra::Vector3;
///
/// // 100 m up, idle, falling at 30 m/s: it crashes and stays there.
/// let aircraft = Palmer::default_aircraft();
/// let controls = PalmerControls::default();
/// let mut state = PalmerState {
///     position_m: Vector3::new(0.0, 0.0, 100.0),
///     velocity_mps: Vector3::new(30.0, 0.0, -30.0),
///     ..PalmerState::at_rest()
/// };
/// let mut status = FlightStatus::initial(100.0);
/// for _ in 0..300 {
///     (state, status) = fly::<Palmer>(&aircraft, &controls, status, &state, 0.1);
///     assert!(state.position_m.z >= 0.0);
/// }
/// assert_eq!(status, FlightStatus::Landed(LandingState::Crash));
/// assert_eq!(state.velocity_mps, Vector3::zeros());
/// ```
#[must_use]
#[inline]
pub fn fly<M: Model>(
    aircraft: &M::Aircraft,
    controls: &M::Controls,
    status: FlightStatus,
    state: &M::State,
    dt: M::TimeStep,
) -> (M::State, FlightStatus) {
    let (next, status) = advance::<M>(aircraft, controls, status, state, dt);
    settle::<M>(aircraft, status, &next)
}

/// A model's control action as scripts and key maps name it; implemented by
/// each model's action enum.
pub trait ScriptAction: Copy + Sized + 'static {
    /// Every action of the model, in a stable order (used for error messages and docs).
    const ALL: &'static [Self];

    /// The script names of [`Self::ALL`], in the same order.
    const NAMES: &'static [&'static str];

    /// The action's name as written in scripts, e.g. `"thrust-up"`.
    fn name(self) -> &'static str;

    /// Looks an action up by its script name.
    fn from_name(name: &str) -> Option<Self> {
        Self::ALL.iter().copied().find(|a| a.name() == name)
    }
}

/// What every model can say about one aircraft, in one frame and one unit
/// system: SI units, the models' shared earth frame (x north, y west, z up,
/// origin on the ground plane; a flat earth the shell places on WGS-84).
///
/// | field | unit, frame |
/// |---|---|
/// | `time_s` | simulated time, s |
/// | `position_m`, `velocity_mps` | earth frame, m, m/s |
/// | `attitude` | roll (right wing down +), pitch (nose up +), heading (clockwise from the earth frame's x axis), degrees |
/// | `velocity_body_mps` | body axes forward, right, down, m/s |
/// | `airspeed_mps` | speed through the air (no wind: the speed), m/s |
/// | `alpha_deg`, `beta_deg` | angle of attack, sideslip, degrees |
/// | `flaps_norm` | flap deflection, 0 (up) to 1 (full) |
/// | `engine_running`, `engine_rpm` | engine state; rpm 0 when the model has none |
/// | `stalling` | whether the model reports a stall |
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct FlightView {
    /// Simulated time, s.
    pub time_s: f64,
    /// Position in the earth frame (x north, y west, z up), m; `z` is the
    /// height above the ground plane.
    pub position_m: Vector3<f64>,
    /// Velocity in the earth frame, m/s.
    pub velocity_mps: Vector3<f64>,
    /// Attitude relative to the earth frame's axes (north, east = −y, down =
    /// −z), degrees.
    pub attitude: Attitude,
    /// Velocity in body axes: forward, right, down, m/s.
    pub velocity_body_mps: Vector3<f64>,
    /// Airspeed, m/s.
    pub airspeed_mps: f64,
    /// Angle of attack, degrees.
    pub alpha_deg: f64,
    /// Sideslip angle, degrees.
    pub beta_deg: f64,
    /// Flap deflection as a fraction of full: 0 up, 1 fully down.
    pub flaps_norm: f64,
    /// Whether the engine runs (throttle or thrust above 0).
    pub engine_running: bool,
    /// Engine (propeller) speed, rev/min; 0 when the model has none.
    pub engine_rpm: f64,
    /// Whether the model reports a stall.
    pub stalling: bool,
}

impl FlightView {
    /// Whether every number of the view is finite.
    #[must_use]
    pub fn is_finite(&self) -> bool {
        let v = |v: &Vector3<f64>| v.iter().all(|x| x.is_finite());
        self.time_s.is_finite()
            && v(&self.position_m)
            && v(&self.velocity_mps)
            && v(&self.velocity_body_mps)
            && self.attitude.roll_deg.is_finite()
            && self.attitude.pitch_deg.is_finite()
            && self.attitude.heading_deg.is_finite()
            && self.airspeed_mps.is_finite()
            && self.alpha_deg.is_finite()
            && self.beta_deg.is_finite()
            && self.flaps_norm.is_finite()
            && self.engine_rpm.is_finite()
    }

    /// Height above the ground plane (`position_m.z`), m.
    #[must_use]
    pub fn height_m(&self) -> f64 {
        self.position_m.z
    }

    /// Climb rate (`velocity_mps.z`), m/s, positive up.
    #[must_use]
    pub fn climb_rate_mps(&self) -> f64 {
        self.velocity_mps.z
    }
}

/// Fastest sink rate (vz, m/s, negative down) still counted as a safe landing:
/// `vz > SAFE_LANDING_VZ_MPS` is safe.
pub const SAFE_LANDING_VZ_MPS: f64 = -2.0;
/// Fastest sink rate (vz, m/s) still counted as a rough landing (rather than a
/// crash): `vz > ROUGH_LANDING_VZ_MPS` is at worst rough.
pub const ROUGH_LANDING_VZ_MPS: f64 = -5.0;

/// How a touchdown went, judged by the vertical speed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum LandingState {
    /// `vz > -2 m/s`.
    Safe,
    /// `-5 m/s < vz <= -2 m/s`.
    Rough,
    /// `vz <= -5 m/s` (or NaN).
    Crash,
}

/// Classifies a touchdown by its vertical speed `vz_mps` (m/s, positive up):
/// `vz > -2` safe, `vz > -5` rough, anything else (including NaN) a crash.
///
/// ```
/// use fdm_core::model::{landing_state, LandingState};
///
/// assert_eq!(landing_state(-1.0), LandingState::Safe);
/// assert_eq!(landing_state(-2.0), LandingState::Rough);
/// assert_eq!(landing_state(-5.0), LandingState::Crash);
/// ```
#[must_use]
#[inline]
pub fn landing_state(vz_mps: f64) -> LandingState {
    if vz_mps > SAFE_LANDING_VZ_MPS {
        LandingState::Safe
    } else if vz_mps > ROUGH_LANDING_VZ_MPS {
        LandingState::Rough
    } else {
        LandingState::Crash
    }
}

/// Where an aircraft is in its flight, tracked from frame to frame by the
/// shell (a component in `fdm-ecs`), the same way for every model: from its
/// height above the ground plane and its climb rate after each step
/// ([`settle`]).
///
/// It starts [`OnGround`](Self::OnGround) (height ≤ 0) or
/// [`Airborne`](Self::Airborne) ([`FlightStatus::initial`]); becomes
/// `Airborne` once the height is above 0; and on the first state at or below
/// the ground plane after that, records the touchdown as
/// [`Landed`](Self::Landed) with its [`landing_state`] of the vertical speed
/// at that state (safe above −2 m/s, rough above −5 m/s, otherwise a crash).
/// After a safe or rough landing it rolls on the ground and can take off
/// again; a crash (`Landed(LandingState::Crash)`) is final: the aircraft stays
/// where it came down, at rest. [`Diverged`](Self::Diverged) is final too:
/// the model's step gave a non-finite state ([`advance`]).
///
/// ```
/// use fdm_core::model::{FlightStatus, LandingState};
///
/// let status = FlightStatus::initial(0.0);
/// assert_eq!(status, FlightStatus::OnGround);
/// let status = status.update(10.0, -1.0);
/// assert_eq!(status, FlightStatus::Airborne);
/// let status = status.update(-0.1, -3.0);
/// assert_eq!(status, FlightStatus::Landed(LandingState::Rough));
/// assert_eq!(status.label(), "landed (rough)");
/// assert_eq!(status.code(), "landed_rough");
/// let crashed = FlightStatus::Airborne.update(-0.1, -9.0);
/// assert_eq!(crashed.code(), "crashed");
/// assert_eq!(crashed.update(5.0, 1.0), crashed); // final
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum FlightStatus {
    /// On the ground, not flown since the start.
    #[default]
    OnGround,
    /// Above the ground plane since the start or the last touchdown.
    Airborne,
    /// Back on the ground; how the touchdown went (a crash is final).
    Landed(LandingState),
    /// The model's step produced a non-finite state (final): the state kept
    /// is the last finite one.
    Diverged,
}

impl FlightStatus {
    /// The status of an aircraft starting at `height_m` above the ground plane.
    #[must_use]
    pub fn initial(height_m: f64) -> Self {
        if height_m > 0.0 {
            Self::Airborne
        } else {
            Self::OnGround
        }
    }

    /// Whether the status can no longer change: crashed or diverged.
    #[must_use]
    pub const fn is_final(self) -> bool {
        matches!(self, Self::Landed(LandingState::Crash) | Self::Diverged)
    }

    /// The status after a step that left the aircraft at `height_m` with climb
    /// rate `climb_rate_mps` (positive up). A non-finite height changes
    /// nothing; a final status ([`is_final`](Self::is_final)) never changes.
    #[must_use]
    pub fn update(self, height_m: f64, climb_rate_mps: f64) -> Self {
        match self {
            Self::Landed(LandingState::Crash) | Self::Diverged => self,
            Self::OnGround | Self::Landed(_) if height_m > 0.0 => Self::Airborne,
            Self::Airborne if height_m <= 0.0 => Self::Landed(landing_state(climb_rate_mps)),
            status => status,
        }
    }

    /// The status as the HUD and the human summary print it.
    #[must_use]
    pub const fn label(self) -> &'static str {
        match self {
            Self::OnGround => "on ground",
            Self::Airborne => "flying",
            Self::Landed(LandingState::Safe) => "landed (safe)",
            Self::Landed(LandingState::Rough) => "landed (rough)",
            Self::Landed(LandingState::Crash) => "CRASHED",
            Self::Diverged => "DIVERGED",
        }
    }

    /// The status as one machine-readable word (the JSON report's `status`,
    /// the CSV's `status` column): `on_ground`, `airborne`, `landed_safe`,
    /// `landed_rough`, `crashed`, `diverged`.
    #[must_use]
    pub const fn code(self) -> &'static str {
        match self {
            Self::OnGround => "on_ground",
            Self::Airborne => "airborne",
            Self::Landed(LandingState::Safe) => "landed_safe",
            Self::Landed(LandingState::Rough) => "landed_rough",
            Self::Landed(LandingState::Crash) => "crashed",
            Self::Diverged => "diverged",
        }
    }
}

/// The status as shown to a person or written to a report: the
/// [`FlightStatus`] and whether the model reports a stall. The one place for
/// the display vocabulary: the HUD's and the plot's labels
/// ([`Self::label`]: `STALL` while stalling in the air), the JSON report's
/// word ([`Self::code`]: `stalling`), and the number of `sim-cli --csv`'s
/// `status` column ([`Self::number`], [`Self::from_number`]). A stall only
/// shows in the air: on the ground or landed, the flight status wins.
///
/// ```
/// use fdm_core::model::{DisplayStatus, FlightStatus};
/// let stall = DisplayStatus::new(FlightStatus::Airborne, true);
/// assert_eq!((stall.label(), stall.code(), stall.number()), ("STALL", "stalling", 6));
/// assert_eq!(DisplayStatus::from_number(6.0), Some(stall));
/// let ground = DisplayStatus::new(FlightStatus::OnGround, true);
/// assert_eq!((ground.label(), ground.code(), ground.number()), ("on ground", "on_ground", 0));
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub struct DisplayStatus {
    /// Where the aircraft is in its flight.
    pub status: FlightStatus,
    /// Whether the model reports a stall.
    pub stalling: bool,
}

impl DisplayStatus {
    /// The labels of [`Self::label`] in the order of the plot's status panel,
    /// bottom to top (without `DIVERGED`: a diverged frame is never shown).
    pub const PANEL_LABELS: [&'static str; 6] = [
        "on ground",
        "flying",
        "STALL",
        "landed (safe)",
        "landed (rough)",
        "CRASHED",
    ];

    /// The status `status` with the model's stall flag `stalling`.
    #[must_use]
    pub const fn new(status: FlightStatus, stalling: bool) -> Self {
        Self { status, stalling }
    }

    /// Whether a stall shows: the model reports one and the aircraft is in
    /// the air.
    #[must_use]
    pub const fn shows_stall(self) -> bool {
        self.stalling && matches!(self.status, FlightStatus::Airborne)
    }

    /// The status as the HUD and the plot show it: [`FlightStatus::label`],
    /// or `STALL` while stalling in the air.
    #[must_use]
    pub const fn label(self) -> &'static str {
        if self.shows_stall() {
            "STALL"
        } else {
            self.status.label()
        }
    }

    /// The status as one word, for the JSON report's `status`:
    /// [`FlightStatus::code`] (`on_ground`, `airborne`, `landed_safe`,
    /// `landed_rough`, `crashed`, `diverged`), or `stalling` while stalling
    /// in the air.
    #[must_use]
    pub const fn code(self) -> &'static str {
        if self.shows_stall() {
            "stalling"
        } else {
            self.status.code()
        }
    }

    /// The status as a number, for the CSV's `status` column (CSV rows hold
    /// numbers only): 0 on ground, 1 airborne, 2 landed safe, 3 landed rough,
    /// 4 crashed, 5 diverged, 6 stalling (in the air).
    #[must_use]
    pub const fn number(self) -> u8 {
        if self.shows_stall() {
            return 6;
        }
        match self.status {
            FlightStatus::OnGround => 0,
            FlightStatus::Airborne => 1,
            FlightStatus::Landed(LandingState::Safe) => 2,
            FlightStatus::Landed(LandingState::Rough) => 3,
            FlightStatus::Landed(LandingState::Crash) => 4,
            FlightStatus::Diverged => 5,
        }
    }

    /// The status of a CSV `status` number ([`Self::number`]); `None` for
    /// any other number.
    #[must_use]
    pub fn from_number(x: f64) -> Option<Self> {
        let status = match x {
            0.0 => FlightStatus::OnGround,
            1.0 | 6.0 => FlightStatus::Airborne,
            2.0 => FlightStatus::Landed(LandingState::Safe),
            3.0 => FlightStatus::Landed(LandingState::Rough),
            4.0 => FlightStatus::Landed(LandingState::Crash),
            5.0 => FlightStatus::Diverged,
            _ => return None,
        };
        Some(Self::new(status, x == 6.0))
    }

    /// The level of [`Self::label`] in the plot's status panel
    /// ([`Self::PANEL_LABELS`]), 0 for a label it does not have
    /// (`DIVERGED`).
    #[must_use]
    pub fn panel_level(self) -> usize {
        let label = self.label();
        Self::PANEL_LABELS
            .iter()
            .position(|&l| l == label)
            .unwrap_or(0)
    }
}

#[cfg(test)]
mod display_status_tests {
    use super::{DisplayStatus, FlightStatus, LandingState};

    /// Every status, with and without a stall, reads back from its CSV
    /// number as it shows (a stall only in the air), and its label is one
    /// of the panel's but for `DIVERGED`.
    #[test]
    fn numbers_round_trip_and_labels_are_the_panels() {
        let statuses = [
            FlightStatus::OnGround,
            FlightStatus::Airborne,
            FlightStatus::Landed(LandingState::Safe),
            FlightStatus::Landed(LandingState::Rough),
            FlightStatus::Landed(LandingState::Crash),
            FlightStatus::Diverged,
        ];
        let mut numbers = [false; 7];
        for status in statuses {
            for stalling in [false, true] {
                let d = DisplayStatus::new(status, stalling);
                let back = DisplayStatus::from_number(f64::from(d.number())).unwrap();
                assert_eq!(back, DisplayStatus::new(status, d.shows_stall()));
                assert_eq!((back.label(), back.code()), (d.label(), d.code()));
                numbers[usize::from(d.number())] = true;
                if status != FlightStatus::Diverged {
                    assert_eq!(DisplayStatus::PANEL_LABELS[d.panel_level()], d.label());
                }
            }
        }
        assert_eq!(numbers, [true; 7]);
        assert_eq!(DisplayStatus::from_number(7.0), None);
        assert_eq!(DisplayStatus::from_number(0.5), None);
    }
}
