//! Touchdown detection and landing classification (from the book's GUI versions).
//!
//! Superseded: every layer above the model (the ECS, the fleets, the run
//! library, the CLI, the Python package) tracks a flight with the model-
//! independent [`crate::model::FlightStatus`] (its `update` from the height
//! and climb rate, the ground contact applied by [`crate::model::settle`]).
//! [`FlightPhase`] is Palmer's original two-phase tracker, kept as the
//! book's GUI versions had it and for callers of the public API; nothing in
//! the workspace uses it. [`LandingState`] and the landing thresholds are
//! the model-wide ones, re-exported.

use serde::{Deserialize, Serialize};

use super::PalmerState;

pub use crate::model::{landing_state, LandingState, ROUGH_LANDING_VZ_MPS, SAFE_LANDING_VZ_MPS};

/// Whether the aircraft is flying, as a small value the caller stores between
/// frames; it has no hidden state. Superseded by
/// [`crate::model::FlightStatus`] (which also knows a crash is final and a
/// diverged step), what the ECS, the fleets and the run library keep per
/// aircraft; see the module docs.
///
/// It starts [`FlightPhase::OnGround`], becomes [`FlightPhase::Airborne`] once
/// the altitude is above 0, and reports a touchdown, once, on the first state
/// with `z < 0` after that (the step alone does not stop the aircraft at the
/// ground plane when it comes down, so `z` dips below 0 on landing; the ground
/// contact, [`crate::model::Model::ground_contact`], is applied after the step
/// by the layers above). After a touchdown it is on the ground again and can
/// take off and land again.
///
/// ```
/// use fdm_core::palmer::{FlightPhase, LandingState, PalmerState};
/// use nalgebra::Vector3;
///
/// let at = |z: f64, vz: f64| PalmerState {
///     position_m: Vector3::new(0.0, 0.0, z),
///     velocity_mps: Vector3::new(40.0, 0.0, vz),
///     ..PalmerState::at_rest()
/// };
/// let phase = FlightPhase::default();
/// let (phase, event) = phase.update(&at(0.0, 0.0));
/// assert_eq!((phase, event), (FlightPhase::OnGround, None));
/// let (phase, event) = phase.update(&at(10.0, -1.0));
/// assert_eq!((phase, event), (FlightPhase::Airborne, None));
/// let (phase, event) = phase.update(&at(-0.1, -3.0));
/// assert_eq!((phase, event), (FlightPhase::OnGround, Some(LandingState::Rough)));
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default, Serialize, Deserialize)]
pub enum FlightPhase {
    /// On the ground (the initial phase, and after each touchdown).
    #[default]
    OnGround,
    /// Has been above the ground plane (`z > 0`) since the last touchdown.
    Airborne,
}

impl FlightPhase {
    /// The phase after `state` (call once per frame, after the step) and, if this
    /// state is a touchdown, how it went ([`landing_state`] of its `vz`).
    ///
    /// A non-finite altitude leaves the phase unchanged and reports nothing.
    #[must_use]
    #[inline]
    pub fn update(self, state: &PalmerState) -> (Self, Option<LandingState>) {
        let z = state.position_m.z;
        match self {
            Self::OnGround if z > 0.0 => (Self::Airborne, None),
            Self::Airborne if z < 0.0 => {
                (Self::OnGround, Some(landing_state(state.velocity_mps.z)))
            }
            phase => (phase, None),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Vector3;

    fn at(z: f64, vz: f64) -> PalmerState {
        PalmerState {
            position_m: Vector3::new(100.0, 0.0, z),
            velocity_mps: Vector3::new(40.0, 0.0, vz),
            ..PalmerState::at_rest()
        }
    }

    #[test]
    fn thresholds() {
        assert_eq!(landing_state(0.5), LandingState::Safe);
        assert_eq!(landing_state(0.0), LandingState::Safe);
        assert_eq!(landing_state(-1.999_999), LandingState::Safe);
        assert_eq!(landing_state(-2.0), LandingState::Rough);
        assert_eq!(landing_state(-4.999_999), LandingState::Rough);
        assert_eq!(landing_state(-5.0), LandingState::Crash);
        assert_eq!(landing_state(-50.0), LandingState::Crash);
        assert_eq!(landing_state(f64::NEG_INFINITY), LandingState::Crash);
        assert_eq!(landing_state(f64::NAN), LandingState::Crash);
    }

    #[test]
    fn no_touchdown_without_flying() {
        let mut phase = FlightPhase::default();
        for z in [0.0, -0.0, -1e-9, 0.0, -3.0] {
            let (next, event) = phase.update(&at(z, -10.0));
            assert_eq!(event, None);
            assert_eq!(next, FlightPhase::OnGround);
            phase = next;
        }
    }

    #[test]
    fn touchdown_reported_once_then_can_fly_again() {
        let flight = [
            (0.0, 0.0, FlightPhase::OnGround, None),
            (0.5, 1.0, FlightPhase::Airborne, None),
            (0.0, -1.0, FlightPhase::Airborne, None),
            (-0.2, -1.5, FlightPhase::OnGround, Some(LandingState::Safe)),
            (-0.3, -1.0, FlightPhase::OnGround, None),
            (2.0, 3.0, FlightPhase::Airborne, None),
            (-0.5, -6.0, FlightPhase::OnGround, Some(LandingState::Crash)),
        ];
        let mut phase = FlightPhase::default();
        for (i, (z, vz, want_phase, want_event)) in flight.into_iter().enumerate() {
            let (next, event) = phase.update(&at(z, vz));
            assert_eq!((next, event), (want_phase, want_event), "sample {i}");
            phase = next;
        }
    }

    #[test]
    fn non_finite_altitude_changes_nothing() {
        for phase in [FlightPhase::OnGround, FlightPhase::Airborne] {
            assert_eq!(phase.update(&at(f64::NAN, -1.0)), (phase, None));
        }
    }
}
