//! Pilot controls of the Palmer model: throttle, angle of attack, bank, flaps
//! (thesis appendix B), the wheel brakes (our extension, docs/palmer-model.md
//! "Wheel brakes"), and the key-press / script steps that change them.

use core::fmt;

use serde::{Deserialize, Deserializer, Serialize, Serializer};

use super::PalmerAction;

/// Lowest angle of attack the keys reach, degrees.
pub const ALPHA_MIN_DEG: f64 = -16.0;
/// Highest angle of attack the keys reach, degrees.
pub const ALPHA_MAX_DEG: f64 = 20.0;
/// Largest bank (either side) the keys reach, degrees.
pub const BANK_LIMIT_DEG: f64 = 20.0;
/// Throttle change per key press (fraction of full power; 5 %).
pub const THROTTLE_STEP: f64 = 0.05;
/// Angle of attack and bank change per key press, degrees.
pub const ANGLE_STEP_DEG: f64 = 1.0;

/// Number of throttle notches between 0 and full power (`1 / THROTTLE_STEP`).
const THROTTLE_NOTCHES: f64 = 20.0;
/// How close (in notches) a throttle value must be to a notch to count as on it.
const NOTCH_TOLERANCE: f64 = 1e-9;

/// Flap setting: up, 20° or 40°.
///
/// Serialized as the plain number of degrees (`0`, `20` or `40`), the way
/// docs/palmer-model.md, the reference file and `sim-cli --flaps` write it; any other number is
/// a deserialization error.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default, Serialize, Deserialize)]
#[serde(into = "u8", try_from = "u8")]
pub enum Flaps {
    /// Flaps retracted (0°).
    #[default]
    Up,
    /// Flaps at 20° (lift coefficient +0.25).
    Deg20,
    /// Flaps at 40° (lift coefficient +0.5).
    Deg40,
}

impl Flaps {
    /// The deflection in degrees: 0, 20 or 40.
    #[must_use]
    #[inline]
    pub const fn degrees(self) -> f64 {
        match self {
            Self::Up => 0.0,
            Self::Deg20 => 20.0,
            Self::Deg40 => 40.0,
        }
    }

    /// One notch further down: 0° → 20° → 40°; 40° stays 40° (key K).
    #[must_use]
    #[inline]
    pub const fn lower(self) -> Self {
        match self {
            Self::Up => Self::Deg20,
            Self::Deg20 | Self::Deg40 => Self::Deg40,
        }
    }

    /// The setting for a whole number of degrees (0, 20 or 40), `None` otherwise.
    #[must_use]
    pub const fn from_degrees(degrees: u8) -> Option<Self> {
        match degrees {
            0 => Some(Self::Up),
            20 => Some(Self::Deg20),
            40 => Some(Self::Deg40),
            _ => None,
        }
    }
}

impl From<Flaps> for u8 {
    fn from(flaps: Flaps) -> Self {
        match flaps {
            Flaps::Up => 0,
            Flaps::Deg20 => 20,
            Flaps::Deg40 => 40,
        }
    }
}

/// A flap angle other than 0, 20 or 40 degrees.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct InvalidFlaps(
    /// The rejected number of degrees.
    pub u8,
);

impl fmt::Display for InvalidFlaps {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "flaps must be 0, 20 or 40 degrees, got {}", self.0)
    }
}

impl core::error::Error for InvalidFlaps {}

impl TryFrom<u8> for Flaps {
    type Error = InvalidFlaps;

    fn try_from(degrees: u8) -> Result<Self, Self::Error> {
        Self::from_degrees(degrees).ok_or(InvalidFlaps(degrees))
    }
}

/// The pilot's controls. They hold their values between key presses (the Palmer
/// simulator does not reset them every frame).
///
/// [`Default`] is throttle 0, alpha 0°, bank 0°, flaps up, brakes off.
///
/// Serialized as the original's four fields while the brakes are off, so
/// files and recordings written before the brakes existed read back
/// unchanged and the same controls write the same bytes: readable formats
/// (JSON) add `"brakes": true` only while they are set; compact binary
/// formats (a recording's bincode header) carry them in the flaps byte's top
/// bit (`0x80`), which an older reader refuses as a flap setting.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct PalmerControls {
    /// Throttle, fraction of full power, 0..=1.
    pub throttle: f64,
    /// Angle of attack, degrees (the keys keep it in -16..=20).
    pub alpha_deg: f64,
    /// Bank angle, degrees; positive banks right and turns toward negative y
    /// (the keys keep it in -20..=20).
    pub bank_deg: f64,
    /// Flap setting.
    pub flaps: Flaps,
    /// Wheel brakes set (our extension; the original model has no wheel
    /// friction). While the aircraft is on the ground they brake it with
    /// the friction coefficient
    /// [`BRAKING_FRICTION_COEFFICIENT`](super::BRAKING_FRICTION_COEFFICIENT);
    /// in the air they do nothing. Off, the step is the original model's, bit
    /// for bit. Absent from the serialized form while off, so controls written
    /// before the brakes existed read back unchanged and write the same text.
    pub brakes: bool,
}

/// [`PalmerControls`] as readable formats (JSON) write it.
#[derive(Serialize, Deserialize)]
#[serde(rename = "PalmerControls")]
struct ReadableControls {
    throttle: f64,
    alpha_deg: f64,
    bank_deg: f64,
    flaps: Flaps,
    #[serde(default, skip_serializing_if = "is_off")]
    brakes: bool,
}

/// [`PalmerControls`] as compact binary formats write it: the brakes in the
/// flaps byte's [`BRAKES_BIT`], the other fields as before the brakes existed.
#[derive(Serialize, Deserialize)]
#[serde(rename = "PalmerControls")]
struct CompactControls {
    throttle: f64,
    alpha_deg: f64,
    bank_deg: f64,
    flaps: u8,
}

/// The bit of [`CompactControls::flaps`] that holds the brakes (no flap
/// setting, 0, 20 or 40, has it).
const BRAKES_BIT: u8 = 0x80;

impl Serialize for PalmerControls {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        if serializer.is_human_readable() {
            ReadableControls {
                throttle: self.throttle,
                alpha_deg: self.alpha_deg,
                bank_deg: self.bank_deg,
                flaps: self.flaps,
                brakes: self.brakes,
            }
            .serialize(serializer)
        } else {
            let brakes = if self.brakes { BRAKES_BIT } else { 0 };
            CompactControls {
                throttle: self.throttle,
                alpha_deg: self.alpha_deg,
                bank_deg: self.bank_deg,
                flaps: u8::from(self.flaps) | brakes,
            }
            .serialize(serializer)
        }
    }
}

impl<'de> Deserialize<'de> for PalmerControls {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        if deserializer.is_human_readable() {
            let c = ReadableControls::deserialize(deserializer)?;
            Ok(Self {
                throttle: c.throttle,
                alpha_deg: c.alpha_deg,
                bank_deg: c.bank_deg,
                flaps: c.flaps,
                brakes: c.brakes,
            })
        } else {
            let c = CompactControls::deserialize(deserializer)?;
            let flaps = Flaps::try_from(c.flaps & !BRAKES_BIT).map_err(serde::de::Error::custom)?;
            Ok(Self {
                throttle: c.throttle,
                alpha_deg: c.alpha_deg,
                bank_deg: c.bank_deg,
                flaps,
                brakes: c.flaps & BRAKES_BIT != 0,
            })
        }
    }
}

/// Serde's test for leaving `brakes` out: brakes off.
#[allow(clippy::trivially_copy_pass_by_ref)] // serde passes a reference
fn is_off(brakes: &bool) -> bool {
    !*brakes
}

impl PalmerControls {
    /// Applies one key press or script action and clamps into range:
    ///
    /// * throttle ±5 % within 0..=1 (see below for the exact values),
    /// * angle of attack ±1° within -16..=20°,
    /// * bank ±1° within -20..=20°,
    /// * flaps one notch down (0 → 20 → 40, 40 stays) or back up to 0,
    /// * brakes set or released.
    ///
    /// The result is clamped into the range after the step, so a value set
    /// outside the range by other means (e.g. `--alpha 25`) comes back to the
    /// nearest limit on the next press of either direction.
    ///
    /// **Throttle values are exact notches.** Adding `0.05` repeatedly in f64
    /// drifts: three presses would give `0.15000000000000002`, ten
    /// `0.49999999999999994`, twenty `1.0000000000000002` (clamped to 1). When
    /// the throttle sits on a 5 % notch (within 1e-9 of `k / 20`), a press moves
    /// it to exactly `(k ± 1) as f64 / 20.0`, the same f64 as the decimal
    /// literal (`0.15`, `0.5`, `1.0`), so a key-press run and a run started with
    /// `--throttle 0.15` fly identical bits. A throttle set off the grid (say
    /// `0.33`) moves by plain f64 `± 0.05` instead, keeping its offset.
    /// Non-finite values stay non-finite (NaN in, NaN out; never a panic).
    ///
    /// ```
    /// use fdm_core::palmer::{PalmerAction, PalmerControls};
    ///
    /// let mut c = PalmerControls::default();
    /// for _ in 0..3 {
    ///     c = c.apply(PalmerAction::ThrottleUp);
    /// }
    /// assert_eq!(c.throttle, 0.15);
    /// for _ in 0..30 {
    ///     c = c.apply(PalmerAction::ThrottleUp);
    /// }
    /// assert_eq!(c.throttle, 1.0);
    /// ```
    #[must_use]
    #[inline]
    pub fn apply(self, action: PalmerAction) -> Self {
        let mut c = self;
        match action {
            PalmerAction::ThrottleUp => c.throttle = step_throttle(c.throttle, 1.0),
            PalmerAction::ThrottleDown => c.throttle = step_throttle(c.throttle, -1.0),
            PalmerAction::AlphaUp => {
                c.alpha_deg = (c.alpha_deg + ANGLE_STEP_DEG).clamp(ALPHA_MIN_DEG, ALPHA_MAX_DEG);
            }
            PalmerAction::AlphaDown => {
                c.alpha_deg = (c.alpha_deg - ANGLE_STEP_DEG).clamp(ALPHA_MIN_DEG, ALPHA_MAX_DEG);
            }
            PalmerAction::BankRight => {
                c.bank_deg = (c.bank_deg + ANGLE_STEP_DEG).clamp(-BANK_LIMIT_DEG, BANK_LIMIT_DEG);
            }
            PalmerAction::BankLeft => {
                c.bank_deg = (c.bank_deg - ANGLE_STEP_DEG).clamp(-BANK_LIMIT_DEG, BANK_LIMIT_DEG);
            }
            PalmerAction::FlapsDown => c.flaps = c.flaps.lower(),
            PalmerAction::FlapsUp => c.flaps = Flaps::Up,
            PalmerAction::BrakesOn => c.brakes = true,
            PalmerAction::BrakesOff => c.brakes = false,
        }
        c
    }

    /// Whether throttle, angle of attack and bank are all finite.
    #[must_use]
    #[inline]
    pub fn is_finite(&self) -> bool {
        self.throttle.is_finite() && self.alpha_deg.is_finite() && self.bank_deg.is_finite()
    }
}

/// One throttle press of `direction` (+1 or -1) notches; see [`PalmerControls::apply`].
#[inline]
fn step_throttle(throttle: f64, direction: f64) -> f64 {
    let notches = throttle * THROTTLE_NOTCHES;
    // `round` is exact; libm's and the platform's agree, so no facade is needed.
    let notch = libm::round(notches);
    let next = if libm::fabs(notches - notch) <= NOTCH_TOLERANCE {
        (notch + direction) / THROTTLE_NOTCHES
    } else {
        throttle + direction * THROTTLE_STEP
    };
    // NaN compares false everywhere and passes through `clamp` unchanged.
    next.clamp(0.0, 1.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn press(c: PalmerControls, action: PalmerAction, times: usize) -> PalmerControls {
        (0..times).fold(c, |c, _| c.apply(action))
    }

    #[test]
    fn default_is_all_zero_flaps_up() {
        let c = PalmerControls::default();
        assert_eq!(
            c,
            PalmerControls {
                throttle: 0.0,
                alpha_deg: 0.0,
                bank_deg: 0.0,
                flaps: Flaps::Up,
                brakes: false,
            }
        );
    }

    #[test]
    fn throttle_presses_land_on_exact_notches() {
        let mut c = PalmerControls::default();
        for k in 1..=20_u32 {
            c = c.apply(PalmerAction::ThrottleUp);
            assert_eq!(c.throttle, f64::from(k) / 20.0, "after {k} presses");
        }
        assert_eq!(c.throttle, 1.0);
        assert_eq!(c.apply(PalmerAction::ThrottleUp).throttle, 1.0);
        // Literals agree with notches (0.35 is the f64 nearest 35/100).
        assert_eq!(
            press(PalmerControls::default(), PalmerAction::ThrottleUp, 7).throttle,
            0.35
        );
        for k in (0..20_u32).rev() {
            c = c.apply(PalmerAction::ThrottleDown);
            assert_eq!(c.throttle, f64::from(k) / 20.0, "down to notch {k}");
        }
        assert_eq!(c.throttle, 0.0);
        assert_eq!(c.apply(PalmerAction::ThrottleDown).throttle, 0.0);
    }

    #[test]
    fn off_grid_throttle_keeps_its_offset_and_clamps() {
        let c = PalmerControls {
            throttle: 0.33,
            ..PalmerControls::default()
        };
        assert_eq!(c.apply(PalmerAction::ThrottleUp).throttle, 0.33 + 0.05);
        assert_eq!(c.apply(PalmerAction::ThrottleDown).throttle, 0.33 - 0.05);
        assert_eq!(press(c, PalmerAction::ThrottleUp, 100).throttle, 1.0);
        assert_eq!(press(c, PalmerAction::ThrottleDown, 100).throttle, 0.0);
        // Set out of range by other means: back to the limit on any press.
        let high = PalmerControls { throttle: 1.7, ..c };
        assert_eq!(high.apply(PalmerAction::ThrottleDown).throttle, 1.0);
    }

    #[test]
    fn alpha_and_bank_step_one_degree_and_clamp() {
        let c = PalmerControls::default();
        assert_eq!(c.apply(PalmerAction::AlphaUp).alpha_deg, 1.0);
        assert_eq!(c.apply(PalmerAction::AlphaDown).alpha_deg, -1.0);
        assert_eq!(press(c, PalmerAction::AlphaUp, 50).alpha_deg, 20.0);
        assert_eq!(press(c, PalmerAction::AlphaDown, 50).alpha_deg, -16.0);
        assert_eq!(c.apply(PalmerAction::BankRight).bank_deg, 1.0);
        assert_eq!(c.apply(PalmerAction::BankLeft).bank_deg, -1.0);
        assert_eq!(press(c, PalmerAction::BankRight, 50).bank_deg, 20.0);
        assert_eq!(press(c, PalmerAction::BankLeft, 50).bank_deg, -20.0);
        // Other controls untouched.
        let busy = PalmerControls {
            throttle: 0.5,
            alpha_deg: 4.0,
            bank_deg: -3.0,
            flaps: Flaps::Deg20,
            brakes: false,
        };
        let after = busy.apply(PalmerAction::AlphaUp);
        assert_eq!(
            after,
            PalmerControls {
                alpha_deg: 5.0,
                ..busy
            }
        );
    }

    #[test]
    fn flap_notches() {
        assert_eq!(Flaps::Up.lower(), Flaps::Deg20);
        assert_eq!(Flaps::Deg20.lower(), Flaps::Deg40);
        assert_eq!(Flaps::Deg40.lower(), Flaps::Deg40);
        assert_eq!(Flaps::Up.degrees(), 0.0);
        assert_eq!(Flaps::Deg20.degrees(), 20.0);
        assert_eq!(Flaps::Deg40.degrees(), 40.0);
        let c = PalmerControls::default();
        assert_eq!(press(c, PalmerAction::FlapsDown, 1).flaps, Flaps::Deg20);
        assert_eq!(press(c, PalmerAction::FlapsDown, 2).flaps, Flaps::Deg40);
        assert_eq!(press(c, PalmerAction::FlapsDown, 5).flaps, Flaps::Deg40);
        let down = press(c, PalmerAction::FlapsDown, 2);
        assert_eq!(down.apply(PalmerAction::FlapsUp).flaps, Flaps::Up);
        assert_eq!(c.apply(PalmerAction::FlapsUp).flaps, Flaps::Up);
    }

    #[test]
    fn flaps_from_degrees() {
        assert_eq!(Flaps::from_degrees(0), Some(Flaps::Up));
        assert_eq!(Flaps::from_degrees(20), Some(Flaps::Deg20));
        assert_eq!(Flaps::from_degrees(40), Some(Flaps::Deg40));
        assert_eq!(Flaps::from_degrees(10), None);
        assert_eq!(Flaps::try_from(30), Err(InvalidFlaps(30)));
        assert_eq!(
            InvalidFlaps(30).to_string(),
            "flaps must be 0, 20 or 40 degrees, got 30"
        );
        for flaps in [Flaps::Up, Flaps::Deg20, Flaps::Deg40] {
            assert_eq!(Flaps::try_from(u8::from(flaps)), Ok(flaps));
        }
    }

    #[test]
    fn controls_serde_uses_flap_degrees() {
        let c = PalmerControls {
            throttle: 1.0,
            alpha_deg: 4.0,
            bank_deg: 5.0,
            flaps: Flaps::Deg20,
            brakes: false,
        };
        let json = serde_json::to_string(&c).unwrap();
        assert_eq!(
            json,
            r#"{"throttle":1.0,"alpha_deg":4.0,"bank_deg":5.0,"flaps":20}"#
        );
        assert_eq!(serde_json::from_str::<PalmerControls>(&json).unwrap(), c);
        let bad = r#"{"throttle":1.0,"alpha_deg":4.0,"bank_deg":5.0,"flaps":25}"#;
        let err = serde_json::from_str::<PalmerControls>(bad).unwrap_err();
        assert!(err.to_string().contains("0, 20 or 40"), "{err}");
    }

    /// The brakes' serialised forms, as the type's doc gives them: JSON adds
    /// `"brakes": true` only while they are set (and reads them back); a
    /// compact binary format (bincode, as a recording's header: standard
    /// config, so the `f64`s are 8 bytes each and the flaps one byte) writes
    /// the flap degrees with the top bit (0x80) set for the brakes, reads
    /// both back for every flap setting, and refuses a flaps byte whose
    /// low bits are no flap setting, with the top bit set or not.
    #[test]
    fn the_brakes_serialise_as_documented() {
        let on = PalmerControls {
            throttle: 0.5,
            alpha_deg: -2.0,
            bank_deg: 3.0,
            flaps: Flaps::Deg40,
            brakes: true,
        };
        let json = serde_json::to_string(&on).unwrap();
        assert_eq!(
            json,
            r#"{"throttle":0.5,"alpha_deg":-2.0,"bank_deg":3.0,"flaps":40,"brakes":true}"#
        );
        assert_eq!(serde_json::from_str::<PalmerControls>(&json).unwrap(), on);

        let config = bincode::config::standard();
        for flaps in [Flaps::Up, Flaps::Deg20, Flaps::Deg40] {
            for brakes in [false, true] {
                let c = PalmerControls {
                    flaps,
                    brakes,
                    ..on
                };
                let bytes = bincode::serde::encode_to_vec(c, config).unwrap();
                let flaps_byte = u8::from(flaps) | if brakes { 0x80 } else { 0 };
                assert_eq!(bytes.len(), 25, "{c:?}");
                assert_eq!(bytes[24], flaps_byte, "{c:?}");
                let (back, _): (PalmerControls, usize) =
                    bincode::serde::decode_from_slice(&bytes, config).unwrap();
                assert_eq!(back, c);
            }
        }
        let mut bytes = bincode::serde::encode_to_vec(on, config).unwrap();
        for bad in [0x80 | 25, 25, 0x40 | 20, 0x7f] {
            bytes[24] = bad;
            let decoded = bincode::serde::decode_from_slice::<PalmerControls, _>(&bytes, config);
            assert!(decoded.is_err(), "flaps byte {bad:#x}: {decoded:?}");
        }
    }

    #[test]
    fn non_finite_controls_do_not_panic() {
        let c = PalmerControls {
            throttle: f64::NAN,
            alpha_deg: f64::INFINITY,
            bank_deg: f64::NEG_INFINITY,
            flaps: Flaps::Up,
            brakes: false,
        };
        assert!(!c.is_finite());
        assert!(c.apply(PalmerAction::ThrottleUp).throttle.is_nan());
        assert!(c.apply(PalmerAction::ThrottleDown).throttle.is_nan());
        // Infinite angles clamp to the limits.
        assert_eq!(c.apply(PalmerAction::AlphaDown).alpha_deg, 20.0);
        assert_eq!(c.apply(PalmerAction::BankRight).bank_deg, -20.0);
        assert!(PalmerControls::default().is_finite());
    }

    #[cfg(feature = "alloc")]
    #[test]
    fn script_applied_frame_by_frame() {
        use crate::script::Script;

        let text = "\
# take off: full power in 20 frames, 4 degrees of alpha, one notch of flaps
1-20 throttle-up
3-6 alpha-up
5-5 flaps-down
8-12 bank-right
10-11 bank-left   # net +3
13-13 flaps-down
14-14 flaps-up
15-40 alpha-down
";
        let script = Script::<PalmerAction>::parse(text).unwrap();
        let mut c = PalmerControls::default();
        let mut history = [c; 41];
        for frame in 1..=40_u64 {
            for action in script.actions_at(frame) {
                c = c.apply(action);
            }
            history[usize::try_from(frame).unwrap()] = c;
        }
        let at = |frame: usize| history[frame];
        assert_eq!(at(1).throttle, 0.05);
        assert_eq!(at(2).alpha_deg, 0.0);
        assert_eq!(at(6).alpha_deg, 4.0);
        assert_eq!(at(4).flaps, Flaps::Up);
        assert_eq!(at(5).flaps, Flaps::Deg20);
        assert_eq!(at(9).bank_deg, 2.0);
        assert_eq!(at(10).bank_deg, 2.0);
        assert_eq!(at(12).bank_deg, 3.0);
        assert_eq!(at(13).flaps, Flaps::Deg40);
        assert_eq!(at(14).flaps, Flaps::Up);
        assert_eq!(
            at(20),
            PalmerControls {
                throttle: 1.0,
                alpha_deg: -2.0,
                bank_deg: 3.0,
                flaps: Flaps::Up,
                brakes: false,
            }
        );
        assert_eq!(at(40).alpha_deg, -16.0);
        assert_eq!(at(40).throttle, 1.0);
    }
}
