//! What the binding needs to know of each model beyond `fdm_core::model::Model`:
//! its state and controls as named numbers (units in the names), the controls'
//! ranges, and its fleet kernel. One impl per model, and the registry that
//! picks a model by name ([`MODELS`], [`with_model`]): the only file of the
//! crate that names a model; everything else is generic over [`BindModel`].

use fdm_core::bourg::{Bourg, BourgControls, BourgState, Flap, MAX_THRUST_LB};
use fdm_core::model::{FlightStatus, Model};
use fdm_core::palmer::{
    Flaps, Palmer, PalmerControls, PalmerState, ALPHA_MAX_DEG, ALPHA_MIN_DEG, BANK_LIMIT_DEG,
};
use fdm_fleet::{Fleet, FleetError, FleetKernel, FleetPiece, Precision};

use crate::task::{Block, FT_PER_M};

/// A control's name and its accepted range (inclusive; `None` for a set of
/// allowed values checked by [`BindModel::set_control`]).
pub type ControlRange = (&'static str, f64, f64);

/// The models this build knows, by name, in the run library's registry's
/// order (`afit_fdm.MODELS`).
pub const MODELS: [&str; 2] = [Palmer::NAME, Bourg::NAME];

/// Most fields [`BindModel::block_fields`] computes.
pub const MAX_BLOCK_FIELDS: usize = 4;

/// Work done with one model's type, picked by name ([`with_model`]).
pub trait ModelJob {
    /// What the work gives.
    type Output;
    /// Does the work with model `M`.
    fn call<M: BindModel>(self) -> Self::Output;
}

/// Does `job` with the model named `name` (one of [`MODELS`]); `None` for
/// a name that is not a model.
pub fn with_model<J: ModelJob>(name: &str, job: J) -> Option<J::Output> {
    match name {
        n if n == Palmer::NAME => Some(job.call::<Palmer>()),
        n if n == Bourg::NAME => Some(job.call::<Bourg>()),
        _ => None,
    }
}

/// A model as the Python binding exposes it.
pub trait BindModel: fdm_run::csv::CsvModel + FleetKernel {
    /// The model's fleet kernel behind the one adapter the binding uses.
    type Fleet: FleetOps<Self> + Sync;

    /// Controls that cannot be given with `trim=True`, each with what the
    /// trim sets instead (for the error message).
    const TRIM_SETS: &'static [(&'static str, &'static str)];

    /// Names of [`state_values`](Self::state_values), units in the names.
    const STATE_FIELDS: &'static [&'static str];
    /// Names of [`control_values`](Self::control_values), units in the names.
    const CONTROL_FIELDS: &'static [ControlRange];

    /// The state as numbers, in [`STATE_FIELDS`](Self::STATE_FIELDS) order
    /// (`f32` values widened exactly; booleans 0 or 1).
    fn state_values(state: &Self::State, out: &mut [f64]);

    /// `out` becomes the controls as numbers, in
    /// [`CONTROL_FIELDS`](Self::CONTROL_FIELDS) order.
    fn control_values(controls: &Self::Controls, out: &mut [f64]);

    /// `controls` with control `index` (of [`CONTROL_FIELDS`](Self::CONTROL_FIELDS))
    /// set to `value`, which the caller has checked is finite and in range.
    ///
    /// # Errors
    /// A message when the value is in range but not one of the allowed values
    /// (Palmer's flaps: 0, 20 or 40).
    fn set_control(
        controls: Self::Controls,
        index: usize,
        value: f64,
    ) -> Result<Self::Controls, String>;

    /// Actions per aircraft of the Gymnasium tasks (`afit_fdm.gym`).
    const TASK_ACTIONS: usize;
    /// Observed controls per aircraft of the tasks.
    const TASK_CONTROL_OBS: usize;

    /// How many of the last [`STATE_FIELDS`](Self::STATE_FIELDS) (at most
    /// [`MAX_BLOCK_FIELDS`]) a task pass computes a block of aircraft at a
    /// time ([`block_fields`](Self::block_fields): Bourg's speed and three
    /// Euler angles); the others come from
    /// [`state_values_head`](Self::state_values_head).
    const BLOCK_FIELDS: usize = 0;

    /// [`state_values`](Self::state_values) without the last
    /// [`BLOCK_FIELDS`](Self::BLOCK_FIELDS) (which stay as they are).
    #[inline(always)]
    fn state_values_head(state: &Self::State, out: &mut [f64]) {
        Self::state_values(state, out);
    }

    /// The last [`BLOCK_FIELDS`](Self::BLOCK_FIELDS) values of
    /// [`state_values`](Self::state_values) of each of `states`, bit for
    /// bit: `out[field][lane]`.
    #[inline(always)]
    fn block_fields<const N: usize>(
        _states: &[Self::State; N],
        _out: &mut [[f64; N]; MAX_BLOCK_FIELDS],
    ) {
    }

    /// The horizontal speed in the velocity's units times this is the
    /// ground speed in m/s (Palmer 1, Bourg 0.3048).
    const GROUND_MPS_PER_SPEED: f64;

    /// Lane `lane` of `block` becomes what the tasks read of the state
    /// (altitude, climb rate, velocity), from
    /// [`state_values`](Self::state_values).
    fn task_kinematics<const N: usize>(values: &[f64], block: &mut Block<N>, lane: usize);

    /// `out` becomes the observed controls, from
    /// [`control_values`](Self::control_values).
    fn task_control_obs(values: &[f64], out: &mut [f64]);

    /// The controls one aircraft's actions (clipped to -1..1) set, as
    /// `(control index, value)`, in the order the tasks set them; the first
    /// `.1` entries are used.
    fn task_controls(actions: &[f64]) -> ([(usize, f64); 5], usize);

    /// `controls` with the controls one aircraft's actions (clipped to
    /// -1..1, NaN only where a threshold reads it) set: what setting each
    /// of [`task_controls`](Self::task_controls) with
    /// [`set_control`](Self::set_control) gives, without the checks those
    /// values cannot fail.
    fn task_apply(controls: Self::Controls, actions: &[f64]) -> Self::Controls;
}

/// The few fleet operations the binding uses, over `fdm-fleet`'s one
/// generic [`Fleet`].
pub trait FleetOps<M: FleetKernel>: Send + Sized {
    /// An empty fleet of the model's default aircraft.
    ///
    /// # Errors
    /// The kernel's refusal of the aircraft.
    fn empty() -> Result<Self, FleetError>;
    /// Adds an aircraft.
    fn push(&mut self, state: M::State, controls: M::Controls);
    /// Replaces aircraft `index`'s state, controls and status.
    ///
    /// # Errors
    /// Out of range.
    fn set(
        &mut self,
        index: usize,
        state: &M::State,
        controls: M::Controls,
        status: FlightStatus,
    ) -> Result<(), FleetError>;
    /// Replaces aircraft `index`'s controls.
    ///
    /// # Errors
    /// Out of range.
    fn set_controls(&mut self, index: usize, controls: M::Controls) -> Result<(), FleetError>;
    /// Aircraft `index`'s controls.
    fn controls(&self, index: usize) -> Option<M::Controls>;
    /// Aircraft `index`'s state.
    fn state_at(&self, index: usize) -> Option<M::State>;
    /// Aircraft `index`'s status.
    fn status_at(&self, index: usize) -> Option<FlightStatus>;
    /// Every aircraft's controls become `f(index, controls)`, on rayon's
    /// pool when `parallel`.
    fn update_controls(
        &mut self,
        parallel: bool,
        f: impl Fn(usize, M::Controls) -> M::Controls + Sync,
    );
    /// One frame of every aircraft with its status ([`fdm_core::model::fly`]),
    /// on this thread or on rayon's pool.
    ///
    /// # Errors
    /// A precision the kernel does not have ([`Self::check_precision`],
    /// which the constructor already asked).
    fn fly(&mut self, fps: f64, precision: Precision, parallel: bool) -> Result<(), FleetError>;
    /// Every aircraft's state, in order.
    fn for_each_state(&self, f: impl FnMut(usize, &M::State));
    /// Every aircraft's status, in order.
    fn for_each_status(&self, f: impl FnMut(usize, FlightStatus));
    /// Whether the kernel has `precision`.
    ///
    /// # Errors
    /// When it does not.
    fn check_precision(precision: Precision) -> Result<(), FleetError>;
    /// The fleet as runs of `blocks` whole blocks ([`Fleet::pieces_mut`]).
    fn pieces_mut(&mut self, blocks: usize) -> Vec<FleetPiece<'_, M>>;
    /// Aircraft per block.
    fn lanes() -> usize;
    /// The instruction set the kernel dispatched to.
    fn instruction_set(&self) -> &'static str;
}

/// The integer code of a status (the CSV's `status` column of `sim-cli`,
/// without its report-only 6 "stalling").
pub const fn status_code(status: FlightStatus) -> u8 {
    fdm_core::model::DisplayStatus::new(status, false).number()
}

impl BindModel for Palmer {
    type Fleet = Fleet<Palmer>;

    // The trim's throttle and angle of attack replace the given ones.
    const TRIM_SETS: &'static [(&'static str, &'static str)] = &[];

    const STATE_FIELDS: &'static [&'static str] =
        &["time_s", "x_m", "y_m", "z_m", "vx_mps", "vy_mps", "vz_mps"];
    const CONTROL_FIELDS: &'static [ControlRange] = &[
        ("throttle", 0.0, 1.0),
        ("alpha_deg", ALPHA_MIN_DEG, ALPHA_MAX_DEG),
        ("bank_deg", -BANK_LIMIT_DEG, BANK_LIMIT_DEG),
        ("flaps_deg", 0.0, 40.0),
        ("brakes", 0.0, 1.0),
    ];

    fn state_values(s: &PalmerState, out: &mut [f64]) {
        out.copy_from_slice(&[
            s.time_s,
            s.position_m.x,
            s.position_m.y,
            s.position_m.z,
            s.velocity_mps.x,
            s.velocity_mps.y,
            s.velocity_mps.z,
        ]);
    }

    fn control_values(c: &PalmerControls, out: &mut [f64]) {
        out.copy_from_slice(&[
            c.throttle,
            c.alpha_deg,
            c.bank_deg,
            c.flaps.degrees(),
            if c.brakes { 1.0 } else { 0.0 },
        ]);
    }

    fn set_control(
        mut c: PalmerControls,
        index: usize,
        value: f64,
    ) -> Result<PalmerControls, String> {
        match index {
            0 => c.throttle = value,
            1 => c.alpha_deg = value,
            2 => c.bank_deg = value,
            3 => {
                c.flaps = [Flaps::Up, Flaps::Deg20, Flaps::Deg40]
                    .into_iter()
                    .find(|f| f.degrees() == value)
                    .ok_or_else(|| format!("{value} is not 0, 20 or 40"))?;
            }
            _ => {
                c.brakes = match value {
                    1.0 => true,
                    0.0 => false,
                    v => return Err(format!("{v} is not 0 or 1")),
                }
            }
        }
        Ok(c)
    }

    const TASK_ACTIONS: usize = 4;
    const TASK_CONTROL_OBS: usize = 4;

    // `speed * 1.0` is `speed`, bit for bit.
    const GROUND_MPS_PER_SPEED: f64 = 1.0;

    #[inline(always)]
    fn task_kinematics<const N: usize>(v: &[f64], block: &mut Block<N>, lane: usize) {
        block.alt_ft[lane] = v[3] * FT_PER_M;
        block.vz_fps[lane] = v[6] * FT_PER_M;
        block.vx[lane] = v[4];
        block.vy[lane] = v[5];
    }

    fn task_control_obs(c: &[f64], out: &mut [f64]) {
        out.copy_from_slice(&[c[0], c[1] / 20.0, c[2] / 20.0, c[3] / 40.0]);
    }

    fn task_controls(a: &[f64]) -> ([(usize, f64); 5], usize) {
        let [p0, p1, p2, p3] = palmer_controls(a);
        ([p0, p1, p2, p3, (0, 0.0)], 4)
    }

    #[inline]
    fn task_apply(mut c: PalmerControls, a: &[f64]) -> PalmerControls {
        let [(_, throttle), (_, alpha_deg), (_, bank_deg), (_, flaps)] = palmer_controls(a);
        c.throttle = throttle;
        c.alpha_deg = alpha_deg;
        c.bank_deg = bank_deg;
        // `palmer_controls` gives exactly 0, 20 or 40.
        c.flaps = if flaps == 0.0 {
            Flaps::Up
        } else if flaps == 20.0 {
            Flaps::Deg20
        } else {
            Flaps::Deg40
        };
        c
    }
}

/// Bourg's all-or-nothing surfaces from an action: +1 above 1/3, -1 below
/// -1/3, else 0 (NaN too), as `_surface`.
#[must_use]
fn surface(a: f64) -> f64 {
    if a > 1.0 / 3.0 {
        1.0
    } else if a < -1.0 / 3.0 {
        -1.0
    } else {
        0.0
    }
}

/// Palmer's controls from one aircraft's clipped actions: throttle,
/// alpha_deg, bank_deg, flaps_deg (control indices 0..4).
#[must_use]
fn palmer_controls(a: &[f64]) -> [(usize, f64); 4] {
    let flaps = if a[3] < -1.0 / 3.0 {
        0.0
    } else if a[3] <= 1.0 / 3.0 {
        20.0
    } else {
        40.0
    };
    [
        (0, (a[0] + 1.0) * 0.5),
        (1, 2.0 + 18.0 * a[1]),
        (2, 20.0 * a[2]),
        (3, flaps),
    ]
}

/// Bourg's controls from one aircraft's clipped actions: thrust_lb,
/// elevator, aileron, rudder, pitch_trim (control indices 0, 1, 2, 3, 5).
#[must_use]
fn bourg_controls(a: &[f64]) -> [(usize, f64); 5] {
    [
        (0, 1500.0 * (a[0] + 1.0)),
        (1, surface(a[1])),
        (2, surface(a[2])),
        (3, surface(a[3])),
        (5, a[4]),
    ]
}

/// A Bourg surface as a number: −1, 0 or +1.
fn flap_code(f: Flap) -> f64 {
    match f {
        Flap::TrailingEdgeDown => -1.0,
        Flap::Neutral => 0.0,
        Flap::TrailingEdgeUp => 1.0,
    }
}

fn flap_from(value: f64) -> Result<Flap, String> {
    match value {
        -1.0 => Ok(Flap::TrailingEdgeDown),
        0.0 => Ok(Flap::Neutral),
        1.0 => Ok(Flap::TrailingEdgeUp),
        v => Err(format!("{v} is not -1, 0 or 1")),
    }
}

impl BindModel for Bourg {
    type Fleet = Fleet<Bourg>;

    const TRIM_SETS: &'static [(&'static str, &'static str)] = &[("thrust_lb", "the thrust")];

    const STATE_FIELDS: &'static [&'static str] = &[
        "time_s",
        "x_ft",
        "y_ft",
        "z_ft",
        "vx_ftps",
        "vy_ftps",
        "vz_ftps",
        "u_ftps",
        "v_ftps",
        "w_ftps",
        "p_radps",
        "q_radps",
        "r_radps",
        "qw",
        "qx",
        "qy",
        "qz",
        "stalling",
        "speed_ftps",
        "euler_x_deg",
        "euler_y_deg",
        "euler_z_deg",
    ];
    // Surfaces: +1 is the action's direction (`elevator` +1 = pitch-up,
    // `aileron` +1 = roll-right, `rudder` +1 = yaw-right).
    const CONTROL_FIELDS: &'static [ControlRange] = &[
        ("thrust_lb", 0.0, MAX_THRUST_LB as f64),
        ("elevator", -1.0, 1.0),
        ("aileron", -1.0, 1.0),
        ("rudder", -1.0, 1.0),
        ("landing_flaps", 0.0, 1.0),
        ("pitch_trim", -1.0, 1.0),
    ];

    fn state_values(s: &BourgState, out: &mut [f64]) {
        // The state's own fields, then the four derived ones (speed, Euler angles).
        Self::state_values_head(s, out);
        let e = s.euler_angles_deg();
        let w = f64::from;
        out[18..].copy_from_slice(&[w(s.speed_ftps()), w(e.x), w(e.y), w(e.z)]);
    }

    const BLOCK_FIELDS: usize = 4;

    #[inline(always)]
    fn state_values_head(s: &BourgState, out: &mut [f64]) {
        let w = f64::from;
        out[..18].copy_from_slice(&[
            s.time_s,
            w(s.position_ft.x),
            w(s.position_ft.y),
            w(s.position_ft.z),
            w(s.velocity_ftps.x),
            w(s.velocity_ftps.y),
            w(s.velocity_ftps.z),
            w(s.velocity_body_ftps.x),
            w(s.velocity_body_ftps.y),
            w(s.velocity_body_ftps.z),
            w(s.angular_velocity_radps.x),
            w(s.angular_velocity_radps.y),
            w(s.angular_velocity_radps.z),
            w(s.orientation.w),
            w(s.orientation.i),
            w(s.orientation.j),
            w(s.orientation.k),
            if s.stalling { 1.0 } else { 0.0 },
        ]);
    }

    /// The speed of [`BourgState::speed_ftps`] (the same operations, lane
    /// by lane) and the Euler angles of [`BourgState::euler_angles_deg`]
    /// ([`fdm_core::bourg::ops::euler_deg_from_quat_lanes`]), a block at a
    /// time.
    #[inline(always)]
    fn block_fields<const N: usize>(
        states: &[BourgState; N],
        out: &mut [[f64; N]; MAX_BLOCK_FIELDS],
    ) {
        for (o, s) in out[0].iter_mut().zip(states) {
            *o = f64::from(fdm_core::bourg::ops::magnitude(&s.velocity_ftps));
        }
        let q: [_; N] = core::array::from_fn(|l| states[l].orientation);
        let e = fdm_core::bourg::ops::euler_deg_from_quat_lanes(&q);
        for (l, e) in e.iter().enumerate() {
            out[1][l] = f64::from(e.x);
            out[2][l] = f64::from(e.y);
            out[3][l] = f64::from(e.z);
        }
    }

    fn control_values(c: &BourgControls, out: &mut [f64]) {
        let rudder = if c.rudder_deg > 0.0 {
            -1.0
        } else if c.rudder_deg < 0.0 {
            1.0
        } else {
            0.0
        };
        out.copy_from_slice(&[
            f64::from(c.thrust_lb),
            flap_code(c.elevators),
            // roll-right: port trailing edge down (−1): aileron +1. No −0.0
            // for neutral.
            0.0 - flap_code(c.port_aileron),
            rudder,
            if c.landing_flaps { 1.0 } else { 0.0 },
            f64::from(c.pitch_trim),
        ]);
    }

    #[allow(clippy::cast_possible_truncation)] // checked ranges; f32 is the model's type
    fn set_control(
        mut c: BourgControls,
        index: usize,
        value: f64,
    ) -> Result<BourgControls, String> {
        match index {
            0 => c.thrust_lb = value as f32,
            1 => c.elevators = flap_from(value)?,
            2 => {
                c.port_aileron = flap_from(-value)?;
                c.starboard_aileron = flap_from(value)?;
            }
            3 => {
                c.rudder_deg = match value {
                    1.0 => -fdm_core::bourg::RUDDER_DEFLECTION_DEG,
                    -1.0 => fdm_core::bourg::RUDDER_DEFLECTION_DEG,
                    0.0 => 0.0,
                    v => return Err(format!("{v} is not -1, 0 or 1")),
                }
            }
            4 => {
                c.landing_flaps = match value {
                    1.0 => true,
                    0.0 => false,
                    v => return Err(format!("{v} is not 0 or 1")),
                }
            }
            _ => c.pitch_trim = value as f32,
        }
        Ok(c)
    }

    const TASK_ACTIONS: usize = 5;
    const TASK_CONTROL_OBS: usize = 5;

    const GROUND_MPS_PER_SPEED: f64 = 0.3048;

    #[inline(always)]
    fn task_kinematics<const N: usize>(v: &[f64], block: &mut Block<N>, lane: usize) {
        block.alt_ft[lane] = v[3];
        block.vz_fps[lane] = v[6];
        block.vx[lane] = v[4];
        block.vy[lane] = v[5];
    }

    fn task_control_obs(c: &[f64], out: &mut [f64]) {
        out.copy_from_slice(&[c[0] / 3000.0, c[1], c[2], c[3], c[5]]);
    }

    fn task_controls(a: &[f64]) -> ([(usize, f64); 5], usize) {
        (bourg_controls(a), 5)
    }

    #[inline]
    #[allow(clippy::cast_possible_truncation)] // as set_control: f32 is the model's type
    fn task_apply(mut c: BourgControls, a: &[f64]) -> BourgControls {
        let [(_, thrust), (_, elevator), (_, aileron), (_, rudder), (_, trim)] = bourg_controls(a);
        // `surface` gives exactly -1, 0 or +1 (never -0).
        let flap = |v: f64| flap_from(v).unwrap_or(Flap::Neutral);
        c.thrust_lb = thrust as f32;
        c.elevators = flap(elevator);
        c.port_aileron = flap(-aileron);
        c.starboard_aileron = flap(aileron);
        c.rudder_deg = if rudder == 1.0 {
            -fdm_core::bourg::RUDDER_DEFLECTION_DEG
        } else if rudder == -1.0 {
            fdm_core::bourg::RUDDER_DEFLECTION_DEG
        } else {
            0.0
        };
        c.pitch_trim = trim as f32;
        c
    }
}

/// One adapter for every model with a lane instantiation: the fleets are one
/// generic type ([`Fleet`]).
impl<M> FleetOps<M> for Fleet<M>
where
    M: fdm_fleet::FleetKernel,
    M::Controls: Send + Sync,
    Self: Send,
{
    fn empty() -> Result<Self, FleetError> {
        Self::try_new(M::default_aircraft())
    }
    fn push(&mut self, state: M::State, controls: M::Controls) {
        Self::push(self, state, controls);
    }
    fn set(
        &mut self,
        index: usize,
        state: &M::State,
        controls: M::Controls,
        status: FlightStatus,
    ) -> Result<(), FleetError> {
        self.set_state(index, state)?;
        Self::set_controls(self, index, controls)?;
        self.set_status(index, status)
    }
    fn set_controls(&mut self, index: usize, controls: M::Controls) -> Result<(), FleetError> {
        Self::set_controls(self, index, controls)
    }
    fn controls(&self, index: usize) -> Option<M::Controls> {
        Self::controls(self, index)
    }
    fn state_at(&self, index: usize) -> Option<M::State> {
        self.state(index)
    }
    fn status_at(&self, index: usize) -> Option<FlightStatus> {
        self.status(index)
    }
    /// The fleet's own [`Fleet::par_update_controls`] on rayon's pool when
    /// `parallel`, else [`Fleet::update_controls`] (the same fleet either
    /// way).
    fn update_controls(
        &mut self,
        parallel: bool,
        f: impl Fn(usize, M::Controls) -> M::Controls + Sync,
    ) {
        if parallel {
            self.par_update_controls(f);
        } else {
            Self::update_controls(self, f);
        }
    }
    fn fly(&mut self, fps: f64, precision: Precision, parallel: bool) -> Result<(), FleetError> {
        let dt = M::time_step(fps);
        if parallel {
            self.par_fly_with(dt, precision)
        } else {
            self.fly_with(dt, precision)
        }
    }
    fn for_each_state(&self, mut f: impl FnMut(usize, &M::State)) {
        for (i, s) in self.states().enumerate() {
            f(i, &s);
        }
    }
    fn for_each_status(&self, mut f: impl FnMut(usize, FlightStatus)) {
        for (i, s) in self.statuses().enumerate() {
            f(i, s);
        }
    }
    fn check_precision(precision: Precision) -> Result<(), FleetError> {
        Self::check_precision(precision)
    }
    fn pieces_mut(&mut self, blocks: usize) -> Vec<FleetPiece<'_, M>> {
        Self::pieces_mut(self, blocks)
    }
    fn lanes() -> usize {
        <M::Lanes as fdm_core::real::Real>::LANES
    }
    fn instruction_set(&self) -> &'static str {
        Self::instruction_set(self)
    }
}
