//! Grant Palmer's Cessna 172 point-mass flight model (*Physics for Game
//! Programmers*, 2005, ch. 10), integrated with 4th-order Runge-Kutta in `f64`.
//!
//! Earth frame: x forward ("north"), y left ("west"), z up; metres, seconds.
//!
//! The model is stated operation by operation in the project's
//! `spec/palmer.md`; [`step`] reproduces the original C program's results (with
//! the `std` feature, bit for bit on glibc).
//!
//! * [`PalmerAircraft`]: parameters (Cessna 172 by default), [`PalmerAircraft::validate`].
//! * [`PalmerControls`], [`Flaps`]: throttle, angle of attack, bank, flaps;
//!   [`PalmerControls::apply`] performs one [`PalmerAction`] (key press or script action).
//! * [`PalmerState`]: time, position, velocity; derived [`FlightData`].
//! * [`step`] (RK4, unchecked, NaN propagates), [`try_step`] (checked),
//!   [`derivatives`] (the right-hand side).
//! * [`FlightPhase`], [`LandingState`]: touchdown detection and classification.
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
mod state;

pub use aircraft::{AircraftError, PalmerAircraft};
pub use controls::{
    Flaps, InvalidFlaps, PalmerControls, ALPHA_MAX_DEG, ALPHA_MIN_DEG, ANGLE_STEP_DEG,
    BANK_LIMIT_DEG, THROTTLE_STEP,
};
pub use dynamics::{derivatives, step, try_step, PalmerDerivative, StepError, GRAVITY_MPS2};
pub use landing::{
    landing_state, FlightPhase, LandingState, ROUGH_LANDING_VZ_MPS, SAFE_LANDING_VZ_MPS,
};
pub use state::{compass_from_heading_deg, flight_data, FlightData, PalmerState};

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
}

#[cfg(feature = "alloc")]
impl crate::script::ScriptAction for PalmerAction {
    const ALL: &'static [Self] = &[
        Self::ThrottleUp,
        Self::ThrottleDown,
        Self::AlphaUp,
        Self::AlphaDown,
        Self::BankRight,
        Self::BankLeft,
        Self::FlapsDown,
        Self::FlapsUp,
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
    ];

    fn name(self) -> &'static str {
        Self::NAMES[self as usize]
    }
}
