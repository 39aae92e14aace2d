//! Palmer's Cessna 172 in the CLI: its HUD line, keys and starting controls.

use crossterm::event::KeyCode;
use fdm_core::palmer::{Flaps, PalmerAction, PalmerControls};
use fdm_run::model::palmer::brakes_note;

use super::{tenths, CliModel, Details};
use crate::error::CliError;
use crate::input::Echo;
use fdm_run::values::{parse_in_range, ValueError};
use crate::keys::{letter, KeyAction};

/// Palmer's Cessna 172, as the registry names it.
pub use fdm_core::palmer::Palmer;

/// `sim-cli palmer`'s own options (after the options every model shares).
#[derive(Debug, Clone, clap::Args)]
pub struct PalmerArgs {
    /// Throttle at frame 0, as a fraction of full power (0..1)
    #[arg(long, value_name = "FRACTION", default_value_t = 0.0, value_parser = parse_throttle, allow_hyphen_values = true)]
    pub throttle: f64,

    /// Angle of attack at frame 0, degrees (-16..20)
    #[arg(long, value_name = "DEG", default_value_t = 0.0, value_parser = parse_alpha, allow_hyphen_values = true)]
    pub alpha: f64,

    /// Bank angle at frame 0, degrees, positive banks right (-20..20)
    #[arg(long, value_name = "DEG", default_value_t = 0.0, value_parser = parse_bank, allow_hyphen_values = true)]
    pub bank: f64,

    /// Flap setting at frame 0, degrees (0, 20 or 40)
    #[arg(long, value_name = "0|20|40", default_value_t = 0, value_parser = parse_flaps, allow_hyphen_values = true)]
    pub flaps: u8,

    /// Wheel brakes set at frame 0 (our extension; keys B/V, script actions
    /// brakes-on/brakes-off)
    #[arg(long)]
    pub brakes: bool,
}

impl CliModel for Palmer {
    const AIRCRAFT: &'static str = "Palmer's Cessna 172";
    const ABOUT: &'static str = "Fly Grant Palmer's Cessna 172 (point mass, RK4, f64; metres, m/s)";
    type Args = PalmerArgs;

    /// `--throttle`, `--alpha`, `--bank`, `--flaps` and `--brakes`.
    fn controls(args: &PalmerArgs) -> Result<PalmerControls, CliError> {
        let flaps = Flaps::from_degrees(args.flaps).ok_or_else(|| {
            CliError::usage(format!(
                "--flaps {}: not a flap setting (0, 20 or 40)",
                args.flaps
            ))
        })?;
        Ok(PalmerControls {
            throttle: args.throttle,
            alpha_deg: args.alpha,
            bank_deg: args.bank,
            flaps,
            brakes: args.brakes,
        })
    }
}

/// `--throttle`: fraction in 0..1.
pub fn parse_throttle(text: &str) -> Result<f64, ValueError> {
    parse_in_range(text, 0.0, 1.0, " (fraction of full power)")
}

/// `--alpha`: degrees in -16..20, the range the alpha keys clamp to (the
/// model's [`ALPHA_MIN_DEG`](fdm_core::palmer::ALPHA_MIN_DEG)..[`ALPHA_MAX_DEG`](fdm_core::palmer::ALPHA_MAX_DEG)).
pub fn parse_alpha(text: &str) -> Result<f64, ValueError> {
    use fdm_core::palmer::{ALPHA_MAX_DEG, ALPHA_MIN_DEG};
    parse_in_range(text, ALPHA_MIN_DEG, ALPHA_MAX_DEG, " degrees")
}

/// `--bank`: degrees in -20..20, the range the bank keys clamp to (the
/// model's [`BANK_LIMIT_DEG`](fdm_core::palmer::BANK_LIMIT_DEG) either side).
pub fn parse_bank(text: &str) -> Result<f64, ValueError> {
    use fdm_core::palmer::BANK_LIMIT_DEG;
    parse_in_range(text, -BANK_LIMIT_DEG, BANK_LIMIT_DEG, " degrees")
}

/// `--flaps`: exactly 0, 20 or 40 degrees, the model's three notches.
pub fn parse_flaps(text: &str) -> Result<u8, String> {
    match text.trim() {
        "0" => Ok(0),
        "20" => Ok(20),
        "40" => Ok(40),
        _ => Err(format!(
            "`{}` is not a flap setting (0, 20 or 40)",
            Echo::short(text)
        )),
    }
}


/// Palmer's report fields: the run library's.
pub use fdm_run::model::palmer::PalmerDetails;
/// Palmer's controls in its report fields (the HUD's tests make some).
#[cfg(test)]
pub use fdm_run::model::palmer::PalmerControlsReport;

impl Details for PalmerDetails {
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
