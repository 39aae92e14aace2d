//! Grant Palmer's Cessna 172 point-mass flight model (*Physics for Game
//! Programmers*, 2005, ch. 10), integrated with 4th-order Runge-Kutta in `f64`.
//!
//! Earth frame: x forward ("north"), y left ("west"), z up; metres, seconds.

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
