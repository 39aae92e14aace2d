//! David Bourg's 6-DoF rigid-body aircraft (*Physics for Game Developers*,
//! 2002, ch. 7, 11, 12, 15): 8 lifting elements, quaternion attitude,
//! explicit Euler in `f32`, keeping the original C++ operation order.
//!
//! Earth frame: x north, y west, z up; body frame: x forward, y left, z up;
//! feet, slugs, pounds, seconds.
//!
//! # Parts
//!
//! * [`Airframe`]: the eight lifting elements as data (serde), with
//!   [`MassProperties`] derived once and bundled, with the thrust limits,
//!   into a [`BourgAircraft`].
//! * [`BourgControls`]: thrust, rudder, ailerons, elevators, landing flaps;
//!   [`BourgControls::apply`] a [`BourgAction`], and
//!   [`BourgControls::neutralize_surfaces`] at the start of every frame.
//! * [`BourgState`], [`loads`], [`step`] (and the checked [`try_step`]).
//! * [`Bourg`]: the model behind the common [`Model`](crate::model::Model) interface.
//! * [`ops`]: the original's vector, matrix and quaternion operations in its
//!   exact `f32` operation order.
//! * [`airfoil`]: the airfoil and rudder tables, air density and gravity,
//!   and the table look-ups.
//!
//! # Float type
//!
//! Everything is `f32`, the original's `float` (bit-identical to the C++
//! built with g++ and glibc), except where the original widens to `double`
//! ([`ops::quat_from_euler_deg`], [`ops::euler_deg_from_quat`]).
//!
//! Bit-exact with and without `std` and on every target: `sinf`, `asinf`,
//! `atan2`, ... are [`crate::math`]'s pure-Rust functions, which reproduce
//! glibc's results on the reference cases (docs/determinism.md).
//!
//! ```
//! use fdm_core::bourg::{step, BourgAircraft, BourgControls, BourgState};
//!
//! let aircraft = BourgAircraft::bourg_default();
//! let controls = BourgControls::initial();
//! let mut state = BourgState::initial();
//! for _ in 0..50 {
//!     state = step(&aircraft, &controls, &state, 1.0f32 / 30.0);
//! }
//! // Bit-exact with the original C++ (frame 50 of the `no_controls` reference).
//! assert_eq!(state.position_ft.z, 1973.194580078125);
//! ```

pub mod airfoil;
mod airframe;
mod controls;
mod generic;
mod lanes;
mod model;
pub mod ops;
mod trim;

pub use airfoil::{
    airfoil_coefficients, drag_coefficient, lift_coefficient, rudder_coefficients,
    rudder_drag_coefficient, rudder_lift_coefficient,
};
pub use airframe::{
    element_normal, Airframe, AirframeError, BourgAircraft, Element, Flap, MassProperties,
};
pub use airframe::{DELTA_THRUST_LB, MAX_THRUST_LB, RUDDER_DEFLECTION_DEG};
pub use controls::{BourgControls, INITIAL_THRUST_LB, PITCH_TRIM_STEP};
pub use generic::{BourgReal, BourgTerms, BourgVars, Q4};
pub use lanes::{BourgLanes, LANES};
pub use model::{loads, step, try_step, BourgState, Loads, StepError};
/// The nalgebra types of the public API, re-exported so users need not depend
/// on nalgebra themselves.
pub use nalgebra::{Matrix3, Quaternion, Vector3};
pub use trim::{state_at, state_at_attitude, trim};

/// A discrete control input of the Bourg model: one key press (thesis
/// appendix B) or one script action.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum BourgAction {
    /// Thrust +100 lb, up to 3000 lb (key E).
    ThrustUp,
    /// Thrust -100 lb, down to 0 (key D).
    ThrustDown,
    /// Elevators up for this frame (Down arrow).
    PitchUp,
    /// Elevators down for this frame (Up arrow).
    PitchDown,
    /// Ailerons for a left roll this frame (Left arrow).
    RollLeft,
    /// Ailerons for a right roll this frame (Right arrow).
    RollRight,
    /// Rudder +16° this frame (key N).
    YawLeft,
    /// Rudder -16° this frame (key M).
    YawRight,
    /// Landing flaps down, stays down (key K).
    FlapsDown,
    /// Landing flaps up (key L).
    FlapsUp,
    /// Pitch trim +0.01 toward nose up, up to 1 (key T; an extension, see
    /// [`BourgControls::pitch_trim`]).
    TrimNoseUp,
    /// Pitch trim −0.01 toward nose down, down to −1 (key G; an extension).
    TrimNoseDown,
}

impl crate::model::ScriptAction for BourgAction {
    const ALL: &'static [Self] = &[
        Self::ThrustUp,
        Self::ThrustDown,
        Self::PitchUp,
        Self::PitchDown,
        Self::RollLeft,
        Self::RollRight,
        Self::YawLeft,
        Self::YawRight,
        Self::FlapsDown,
        Self::FlapsUp,
        Self::TrimNoseUp,
        Self::TrimNoseDown,
    ];
    const NAMES: &'static [&'static str] = &[
        "thrust-up",
        "thrust-down",
        "pitch-up",
        "pitch-down",
        "roll-left",
        "roll-right",
        "yaw-left",
        "yaw-right",
        "flaps-down",
        "flaps-up",
        "trim-up",
        "trim-down",
    ];

    fn name(self) -> &'static str {
        Self::NAMES[self as usize]
    }
}

/// Bourg's 6-DoF aircraft as a [`Model`](crate::model::Model): the `f32`
/// types of this module, `dt = 1.0f32 / fps as f32`, control surfaces back to
/// neutral at the start of every frame, thrust limits from the aircraft.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub struct Bourg;

impl crate::model::Model for Bourg {
    const NAME: &'static str = "bourg";
    const TITLE: &'static str = "Bourg 6-DoF";

    type Aircraft = BourgAircraft;
    type State = BourgState;
    type Controls = BourgControls;
    type Action = BourgAction;
    type TimeStep = f32;
    type StepError = StepError;

    fn default_aircraft() -> BourgAircraft {
        BourgAircraft::bourg_default()
    }

    fn initial_controls() -> BourgControls {
        BourgControls::initial()
    }

    fn initial_state() -> BourgState {
        BourgState::initial()
    }

    /// Thrust 500..2500 lb in 21 steps, landing flaps down on every third,
    /// flying level north at 60..78 ft/s (body velocity set too, so the very
    /// first frame has its aerodynamic loads) at 2000..2900 ft, spread 20 ft
    /// apart sideways (in rows of 1000).
    fn fleet_member(index: usize) -> (BourgControls, BourgState) {
        let small = |i: usize| f32::from(u16::try_from(i).unwrap_or(u16::MAX));
        let mut controls = BourgControls::initial();
        controls.thrust_lb = 500.0 + small(index % 21) * 100.0;
        controls.landing_flaps = index.is_multiple_of(3);
        let mut state = BourgState::initial();
        state.position_ft.y = small(index % 1000) * 20.0;
        state.position_ft.z = 2000.0 + small(index % 10) * 100.0;
        state.velocity_ftps.x = 60.0 + small(index % 7) * 3.0;
        // Already flying: the body-frame velocity the loads read is the
        // earth-frame one (wings level, heading north). Left at zero, as in
        // `BourgState::initial`, the first frame would have no aerodynamic
        // forces and be much cheaper than the others.
        state.velocity_body_ftps = state.velocity_ftps;
        (controls, state)
    }

    #[inline]
    fn time_step(fps: f64) -> f32 {
        crate::units::dt_f32_s(fps)
    }

    #[inline]
    fn begin_frame(controls: BourgControls) -> BourgControls {
        controls.neutralize_surfaces()
    }

    #[inline]
    fn apply(
        aircraft: &BourgAircraft,
        controls: BourgControls,
        action: BourgAction,
    ) -> BourgControls {
        controls.apply_within(action, aircraft.max_thrust_lb, aircraft.delta_thrust_lb)
    }

    #[inline]
    fn step(
        aircraft: &BourgAircraft,
        controls: &BourgControls,
        state: &BourgState,
        dt: f32,
    ) -> BourgState {
        step(aircraft, controls, state, dt)
    }

    #[inline]
    fn try_step(
        aircraft: &BourgAircraft,
        controls: &BourgControls,
        state: &BourgState,
        dt: f32,
    ) -> Result<BourgState, StepError> {
        try_step(aircraft, controls, state, dt)
    }

    /// The state and its speed (an `f32` magnitude, which overflows for
    /// velocity components above about 1e19 ft/s while they are still finite).
    fn is_finite(state: &BourgState) -> bool {
        state.is_finite() && state.speed_ftps().is_finite()
    }

    #[inline]
    fn height_m(state: &BourgState) -> f64 {
        f64::from(state.position_ft.z) * crate::units::METRES_PER_FOOT
    }

    #[inline]
    fn climb_rate_mps(state: &BourgState) -> f64 {
        f64::from(state.velocity_ftps.z) * crate::units::METRES_PER_FOOT
    }

    /// Feet become metres ([`METRES_PER_FOOT`](crate::units::METRES_PER_FOOT),
    /// after widening to `f64`); the attitude is
    /// [`bourg_attitude`](crate::geodesy::bourg_attitude) of the Euler angles;
    /// alpha is `atan2(w, u)` and sideslip `asin(v / |v|)` of the body
    /// velocity (forward, right, down); flaps 1 when the landing flaps are
    /// down; the engine runs while thrust is above 0 (the model has no engine
    /// speed: rpm 0).
    fn view(
        _aircraft: &BourgAircraft,
        controls: &BourgControls,
        state: &BourgState,
    ) -> crate::model::FlightView {
        use crate::geodesy::{bourg_attitude, ned_from_model};
        use crate::math::{asin, atan2};
        use crate::units::METRES_PER_FOOT;
        let widen = |v: Vector3<f32>| v.map(f64::from);
        // Body frame x forward, y left, z up → forward, right, down.
        let body_ftps = ned_from_model(widen(state.velocity_body_ftps));
        let body_speed_ftps = body_ftps.norm();
        crate::model::FlightView {
            time_s: state.time_s,
            position_m: widen(state.position_ft) * METRES_PER_FOOT,
            velocity_mps: widen(state.velocity_ftps) * METRES_PER_FOOT,
            attitude: bourg_attitude(state.euler_angles_deg()),
            velocity_body_mps: body_ftps * METRES_PER_FOOT,
            airspeed_mps: f64::from(state.speed_ftps()) * METRES_PER_FOOT,
            alpha_deg: atan2(body_ftps.z, body_ftps.x).to_degrees(),
            beta_deg: if body_speed_ftps > 0.0 {
                asin(body_ftps.y / body_speed_ftps).to_degrees()
            } else {
                0.0
            },
            flaps_norm: if controls.landing_flaps { 1.0 } else { 0.0 },
            engine_running: controls.thrust_lb > 0.0,
            engine_rpm: 0.0,
            stalling: state.stalling,
        }
    }

    /// The contact point is the centre of gravity (`position_ft`; the model
    /// has no landing gear): `z` below 0 becomes 0, a downward `vz` becomes
    /// 0, and the body-frame velocity is recomputed from the new earth-frame
    /// one as the step does (`QVRotate(~orientation, velocity)`). Attitude and
    /// rotation are left to the model. A crash stops it: linear and angular
    /// velocities 0.
    fn ground_contact(_aircraft: &BourgAircraft, state: &BourgState, crashed: bool) -> BourgState {
        let mut s = *state;
        if s.position_ft.z < 0.0 {
            s.position_ft.z = 0.0;
        }
        if s.velocity_ftps.z < 0.0 {
            s.velocity_ftps.z = 0.0;
        }
        if crashed {
            s.velocity_ftps = Vector3::zeros();
            s.angular_velocity_radps = Vector3::zeros();
        }
        s.velocity_body_ftps = ops::qv_rotate(&ops::conjugate(&s.orientation), &s.velocity_ftps);
        s
    }

    fn state_at(
        _aircraft: &BourgAircraft,
        conditions: &crate::start::InitialConditions,
    ) -> Result<BourgState, crate::start::StartError> {
        state_at(conditions)
    }

    fn trim(
        aircraft: &BourgAircraft,
        controls: &BourgControls,
        conditions: &crate::start::InitialConditions,
    ) -> Result<crate::start::Trimmed<BourgControls, BourgState>, crate::start::StartError> {
        trim(aircraft, controls, conditions)
    }

    fn at_rest(state: &BourgState, dt: f32) -> BourgState {
        BourgState {
            time_s: state.time_s + f64::from(dt),
            velocity_ftps: Vector3::zeros(),
            velocity_body_ftps: Vector3::zeros(),
            angular_velocity_radps: Vector3::zeros(),
            ..*state
        }
    }
}
