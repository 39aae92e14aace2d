//! David Bourg's 6-DoF rigid-body aircraft (*Physics for Game Developers*,
//! 2002, ch. 7, 11, 12, 15): 8 lifting elements, quaternion attitude,
//! explicit Euler in `f32`, keeping the original C++ operation order.
//!
//! Earth frame: x north, y west, z up; body frame: x forward, y left, z up;
//! feet, slugs, pounds, seconds.

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
}

#[cfg(feature = "alloc")]
impl crate::script::ScriptAction for BourgAction {
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
    ];

    fn name(self) -> &'static str {
        Self::NAMES[self as usize]
    }
}
