//! Palmer's Cessna 172 in the CLI: its report fields, keys and starting controls.

use crossterm::event::KeyCode;
use fdm_core::palmer::{Flaps, Palmer, PalmerAction, PalmerAircraft, PalmerControls, PalmerState};
use serde::{Deserialize, Serialize};

use super::{tenths, CliModel, Details};
use crate::args::PalmerArgs;
use crate::config::{prepare_model, start_model, ModelConfig};
use crate::error::CliError;
use crate::keys::{letter, KeyAction};

/// Validates `sim-cli palmer` arguments, reads the script and creates the CSV
/// file; the controls at frame 0 come from `--throttle`, `--alpha`, `--bank`
/// `--flaps` and `--brakes`.
///
/// # Errors
/// [`CliError::Usage`] for anything wrong with the input.
pub fn prepare(args: PalmerArgs) -> Result<ModelConfig<Palmer>, CliError> {
    let flaps = Flaps::from_degrees(args.flaps).ok_or_else(|| {
        CliError::usage(format!(
            "--flaps {}: not a flap setting (0, 20 or 40)",
            args.flaps
        ))
    })?;
    let controls = PalmerControls {
        throttle: args.throttle,
        alpha_deg: args.alpha,
        bank_deg: args.bank,
        flaps,
        brakes: args.brakes,
    };
    let start = start_model::<Palmer>(controls, &args.common.start)?;
    prepare_model(args.common, start)
}

/// Palmer's controls as the model holds them.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct PalmerControlsReport {
    /// Throttle fraction, 0..1.
    pub throttle: f64,
    /// Angle of attack, degrees.
    pub alpha_deg: f64,
    /// Bank, degrees, positive right.
    pub bank_deg: f64,
    /// Flap setting, degrees (0, 20 or 40).
    pub flaps_deg: f64,
    /// Wheel brakes set (our extension); absent from the JSON while off, so
    /// reports without the brakes read as before.
    #[serde(default, skip_serializing_if = "is_off")]
    pub brakes: bool,
}

/// Serde's test for leaving `brakes` out of a report: brakes off.
#[allow(clippy::trivially_copy_pass_by_ref)] // serde passes a reference
fn is_off(brakes: &bool) -> bool {
    !*brakes
}

/// What the summary and the HUD add while the brakes are set.
fn brakes_note(brakes: bool) -> &'static str {
    if brakes {
        "  BRAKES"
    } else {
        ""
    }
}

/// Palmer-only report fields (all `f64` in the model).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct PalmerDetails {
    /// Airspeed, m/s.
    pub airspeed: f64,
    /// Current controls.
    pub controls: PalmerControlsReport,
    /// Climb angle, degrees.
    pub climb_angle_deg: f64,
    /// Climb rate (vz), m/s.
    pub climb_rate: f64,
    /// The model's heading angle, degrees in [0, 360), measured from +x toward +y
    /// (i.e. toward the west; not a compass heading, see `attitude_deg.heading`).
    pub heading_deg: f64,
}

impl Details for PalmerDetails {
    const MODEL: &'static str = "palmer";
    const POSITION_UNIT: &'static str = "m";
    fn summary(&self) -> String {
        format!(
            "airspeed  {:.3} m/s  climb {:.2} deg, {:.3} m/s\n\
             controls  throttle {:.0} %  alpha {} deg  bank {} deg  flaps {} deg{}",
            self.airspeed,
            self.climb_angle_deg,
            self.climb_rate,
            self.controls.throttle * 100.0,
            self.controls.alpha_deg,
            self.controls.bank_deg,
            self.controls.flaps_deg,
            brakes_note(self.controls.brakes),
        )
    }

    fn hud_controls(&self) -> String {
        let c = &self.controls;
        format!(
            "THROTTLE {:3.0} %   ALPHA {:+5.1} deg   BANK {:+5.1} deg   FLAPS {:.0} deg{}",
            c.throttle * 100.0,
            tenths(c.alpha_deg),
            tenths(c.bank_deg),
            c.flaps_deg,
            brakes_note(c.brakes),
        )
    }
}

impl CliModel for Palmer {
    type Details = PalmerDetails;

    fn details(
        _aircraft: &PalmerAircraft,
        controls: &PalmerControls,
        state: &PalmerState,
    ) -> PalmerDetails {
        PalmerDetails {
            airspeed: state.airspeed_mps(),
            controls: PalmerControlsReport {
                throttle: controls.throttle,
                alpha_deg: controls.alpha_deg,
                bank_deg: controls.bank_deg,
                flaps_deg: controls.flaps.degrees(),
                brakes: controls.brakes,
            },
            climb_angle_deg: state.climb_angle_deg(),
            climb_rate: state.climb_rate_mps(),
            heading_deg: state.heading_deg(),
        }
    }
}

impl KeyAction for PalmerAction {
    const KEY_HELP: &'static str =
        "E/D throttle  Down/Up alpha +/-  Left/Right bank  K flaps down  L flaps up  B/V brakes on/off";

    fn from_key(code: KeyCode) -> Option<Self> {
        Some(match (code, letter(code)) {
            (_, Some('e')) => Self::ThrottleUp,
            (_, Some('d')) => Self::ThrottleDown,
            (KeyCode::Down, _) => Self::AlphaUp,
            (KeyCode::Up, _) => Self::AlphaDown,
            (KeyCode::Left, _) => Self::BankLeft,
            (KeyCode::Right, _) => Self::BankRight,
            (_, Some('k')) => Self::FlapsDown,
            (_, Some('l')) => Self::FlapsUp,
            (_, Some('b')) => Self::BrakesOn,
            (_, Some('v')) => Self::BrakesOff,
            _ => return None,
        })
    }
}
