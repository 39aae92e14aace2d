//! Grant Palmer's Cessna 172 point-mass flight model (*Physics for Game
//! Programmers*, 2005, ch. 10), integrated with 4th-order Runge-Kutta in `f64`.
//!
//! Earth frame: x forward ("north"), y left ("west"), z up; metres, seconds.
//!
//! The model is stated operation by operation in the project's
//! `docs/palmer-model.md`; [`step`] reproduces the original C program's results bit
//! for bit, with or without `std` and on every target (its maths are
//! [`crate::math`]'s: docs/determinism.md).
//!
//! * [`PalmerAircraft`]: parameters (Cessna 172 by default), [`PalmerAircraft::validate`].
//! * [`PalmerControls`], [`Flaps`]: throttle, angle of attack, bank, flaps;
//!   [`PalmerControls::apply`] performs one [`PalmerAction`] (key press or script action).
//! * [`PalmerState`]: time, position, velocity; derived [`FlightData`].
//! * [`step`] (RK4, unchecked, NaN propagates), [`try_step`] (checked),
//!   [`derivatives`] (the right-hand side).
//! * [`FlightPhase`] (the original touchdown tracker, superseded by
//!   [`crate::model::FlightStatus`]), [`LandingState`]: touchdown classification.
//! * [`Palmer`]: the model behind the common [`Model`](crate::model::Model) interface.
//!
//! ```
//! use fdm_core::palmer::{step, PalmerAction, PalmerAircraft, PalmerControls, PalmerState};
//!
//! let cessna = PalmerAircraft::cessna_172();
//! let mut controls = PalmerControls::default();
//! let mut state = PalmerState::at_rest();
//! for frame in 0..900 {
//!     if frame < 20 {
//!         controls = controls.apply(PalmerAction::ThrottleUp); // full power
//!     }
//!     if frame < 5 {
//!         controls = controls.apply(PalmerAction::AlphaUp); // 5 degrees
//!     }
//!     state = step(&cessna, &controls, &state, 1.0 / 30.0);
//! }
//! assert!(state.altitude_m() > 0.0);
//! println!("{:.1} m/s at {:.1} m", state.airspeed_mps(), state.altitude_m());
//! ```

mod aircraft;
mod controls;
mod dynamics;
mod landing;
mod lanes;
mod state;
mod trim;

pub use aircraft::{AircraftError, PalmerAircraft};
pub use controls::{
    Flaps, InvalidFlaps, PalmerControls, ALPHA_MAX_DEG, ALPHA_MIN_DEG, ANGLE_STEP_DEG,
    BANK_LIMIT_DEG, THROTTLE_STEP,
};
pub use dynamics::{
    derivatives, step, try_step, AircraftTerms, ControlTerms, PalmerDerivative, StepError,
    BRAKING_FRICTION_COEFFICIENT, GRAVITY_MPS2,
};
pub use landing::{
    landing_state, FlightPhase, LandingState, ROUGH_LANDING_VZ_MPS, SAFE_LANDING_VZ_MPS,
};
pub use lanes::{PalmerLanes, LANES};
pub use state::{compass_from_heading_deg, flight_data, FlightData, PalmerState};
pub use trim::{state_at, trim};

/// A discrete control input of the Palmer model: one key press (thesis
/// appendix B) or one script action.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum PalmerAction {
    /// Throttle +5 %, up to 100 % (key E).
    ThrottleUp,
    /// Throttle -5 %, down to 0 % (key D).
    ThrottleDown,
    /// Angle of attack +1°, up to 20° (Down arrow).
    AlphaUp,
    /// Angle of attack -1°, down to -16° (Up arrow).
    AlphaDown,
    /// Bank +1° (right), up to 20° (Right arrow).
    BankRight,
    /// Bank -1° (left), down to -20° (Left arrow).
    BankLeft,
    /// Flaps down one notch, 0 → 20 → 40 (key K).
    FlapsDown,
    /// Flaps up to 0 (key L).
    FlapsUp,
    /// Wheel brakes set (key B; our extension, not in the thesis).
    BrakesOn,
    /// Wheel brakes released (key V; our extension, not in the thesis).
    BrakesOff,
}

impl crate::model::ScriptAction for PalmerAction {
    const ALL: &'static [Self] = &[
        Self::ThrottleUp,
        Self::ThrottleDown,
        Self::AlphaUp,
        Self::AlphaDown,
        Self::BankRight,
        Self::BankLeft,
        Self::FlapsDown,
        Self::FlapsUp,
        Self::BrakesOn,
        Self::BrakesOff,
    ];
    const NAMES: &'static [&'static str] = &[
        "throttle-up",
        "throttle-down",
        "alpha-up",
        "alpha-down",
        "bank-right",
        "bank-left",
        "flaps-down",
        "flaps-up",
        "brakes-on",
        "brakes-off",
    ];

    fn name(self) -> &'static str {
        Self::NAMES[self as usize]
    }
}

/// Palmer's Cessna 172 as a [`Model`](crate::model::Model): the types of this
/// module, `dt = 1.0 / fps` in `f64`, controls held between frames.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub struct Palmer;

/// Palmer's full flap deflection, degrees: `flaps_norm` 1.
const FULL_FLAPS_DEG: f64 = 40.0;

impl crate::model::Model for Palmer {
    const NAME: &'static str = "palmer";
    const TITLE: &'static str = "Palmer Cessna 172";

    type Aircraft = PalmerAircraft;
    type State = PalmerState;
    type Controls = PalmerControls;
    type Action = PalmerAction;
    type TimeStep = f64;
    type StepError = StepError;

    fn default_aircraft() -> PalmerAircraft {
        PalmerAircraft::cessna_172()
    }

    fn initial_controls() -> PalmerControls {
        PalmerControls::default()
    }

    fn initial_state() -> PalmerState {
        PalmerState::initial()
    }

    /// Throttle 50..100 % in 11 steps, alpha 2..6°, bank −10..10°, flaps up
    /// or 20°, 45..54 m/s north, 500 m up, spaced 10 m apart along x. No two
    /// neighbours share all their controls.
    fn fleet_member(index: usize) -> (PalmerControls, PalmerState) {
        let controls = PalmerControls {
            throttle: 0.5 + small(index % 11) / 20.0,
            alpha_deg: 2.0 + small(index % 5),
            bank_deg: small(index % 21) - 10.0,
            flaps: [Flaps::Up, Flaps::Deg20][index % 2],
            brakes: false,
        };
        #[allow(clippy::cast_precision_loss)] // exact below 2^53 aircraft
        let x_m = index as f64 * 10.0;
        let state = PalmerState {
            time_s: 0.0,
            position_m: nalgebra::Vector3::new(x_m, 0.0, 500.0),
            velocity_mps: nalgebra::Vector3::new(45.0 + small(index % 10), 0.0, 0.0),
        };
        (controls, state)
    }

    #[inline]
    fn time_step(fps: f64) -> f64 {
        crate::units::dt_f64_s(fps)
    }

    #[inline]
    fn apply(
        _aircraft: &PalmerAircraft,
        controls: PalmerControls,
        action: PalmerAction,
    ) -> PalmerControls {
        controls.apply(action)
    }

    #[inline]
    fn step(
        aircraft: &PalmerAircraft,
        controls: &PalmerControls,
        state: &PalmerState,
        dt: f64,
    ) -> PalmerState {
        step(aircraft, controls, state, dt)
    }

    #[inline]
    fn try_step(
        aircraft: &PalmerAircraft,
        controls: &PalmerControls,
        state: &PalmerState,
        dt: f64,
    ) -> Result<PalmerState, StepError> {
        try_step(aircraft, controls, state, dt)
    }

    /// The state and its airspeed (which overflows first, for speeds above
    /// about 1e154 m/s).
    fn is_finite(state: &PalmerState) -> bool {
        state.is_finite() && state.airspeed_mps().is_finite()
    }

    #[inline]
    fn height_m(state: &PalmerState) -> f64 {
        state.position_m.z
    }

    #[inline]
    fn climb_rate_mps(state: &PalmerState) -> f64 {
        state.velocity_mps.z
    }

    /// A point mass has no attitude state: the attitude is
    /// [`palmer_attitude`](crate::geodesy::palmer_attitude) (wind axes, then
    /// bank, then the angle of attack); body velocity `u = V cos α`,
    /// `w = V sin α`, no sideslip; flaps `degrees / 40`; the engine runs with
    /// the model's propeller speed (`engine_rps · 60` rev/min) while the
    /// throttle is above 0. Palmer's model has no stall.
    fn view(
        aircraft: &PalmerAircraft,
        controls: &PalmerControls,
        state: &PalmerState,
    ) -> crate::model::FlightView {
        use crate::math::{cos, sin};
        let airspeed_mps = state.airspeed_mps();
        let alpha_rad = controls.alpha_deg.to_radians();
        let running = controls.throttle > 0.0;
        crate::model::FlightView {
            time_s: state.time_s,
            position_m: state.position_m,
            velocity_mps: state.velocity_mps,
            attitude: crate::geodesy::palmer_attitude(
                state.velocity_mps,
                controls.alpha_deg,
                controls.bank_deg,
            ),
            velocity_body_mps: nalgebra::Vector3::new(
                airspeed_mps * cos(alpha_rad),
                0.0,
                airspeed_mps * sin(alpha_rad),
            ),
            airspeed_mps,
            alpha_deg: controls.alpha_deg,
            beta_deg: 0.0,
            flaps_norm: controls.flaps.degrees() / FULL_FLAPS_DEG,
            engine_running: running,
            engine_rpm: if running {
                aircraft.engine_rps * 60.0
            } else {
                0.0
            },
            stalling: false,
        }
    }

    /// The contact point is the point mass itself: `z` below 0 becomes 0
    /// and a downward `vz` becomes 0; `vx`, `vy` are kept (the aircraft rolls
    /// on, slowed by drag only, unless the wheel brakes are set: the original
    /// model has no wheel friction, see [`BRAKING_FRICTION_COEFFICIENT`]). A crash
    /// stops it: every velocity 0.
    fn ground_contact(
        _aircraft: &PalmerAircraft,
        state: &PalmerState,
        crashed: bool,
    ) -> PalmerState {
        let mut s = *state;
        if s.position_m.z < 0.0 {
            s.position_m.z = 0.0;
        }
        if s.velocity_mps.z < 0.0 {
            s.velocity_mps.z = 0.0;
        }
        if crashed {
            s.velocity_mps = nalgebra::Vector3::zeros();
        }
        s
    }

    fn state_at(
        _aircraft: &PalmerAircraft,
        conditions: &crate::start::InitialConditions,
    ) -> Result<PalmerState, crate::start::StartError> {
        state_at(conditions)
    }

    fn trim(
        aircraft: &PalmerAircraft,
        controls: &PalmerControls,
        conditions: &crate::start::InitialConditions,
    ) -> Result<crate::start::Trimmed<PalmerControls, PalmerState>, crate::start::StartError> {
        trim(aircraft, controls, conditions)
    }

    fn at_rest(state: &PalmerState, dt: f64) -> PalmerState {
        PalmerState {
            time_s: state.time_s + dt,
            position_m: state.position_m,
            velocity_mps: nalgebra::Vector3::zeros(),
        }
    }
}

/// A small index (below 65536) as `f64`, exactly.
fn small(i: usize) -> f64 {
    f64::from(u16::try_from(i).unwrap_or(u16::MAX))
}
