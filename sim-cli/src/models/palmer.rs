//! Palmer's Cessna 172 in the CLI: its HUD line, keys and starting controls.

use crossterm::event::KeyCode;
use fdm_core::palmer::{Flaps, Palmer, PalmerAction, PalmerControls};
use fdm_run::model::palmer::brakes_note;

use super::{tenths, Details};
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

/// Palmer's report fields: the run library's.
pub use fdm_run::model::palmer::{PalmerControlsReport, PalmerDetails};

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
