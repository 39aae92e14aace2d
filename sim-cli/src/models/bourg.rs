//! Bourg's 6-DoF aircraft in the CLI: its HUD line, keys and starting controls.

use crossterm::event::KeyCode;
use fdm_core::bourg::{Bourg, BourgAction};
use fdm_core::model::Model;

use super::Details;
use crate::args::BourgArgs;
use crate::config::{prepare_model, start_model, ModelConfig};
use crate::error::CliError;
use crate::keys::{letter, KeyAction};

/// Validates `sim-cli bourg` arguments, reads the script and creates the CSV
/// file; the thrust at frame 0 comes from `--thrust-lb`.
///
/// # Errors
/// [`CliError::Usage`] for anything wrong with the input.
pub fn prepare(args: BourgArgs) -> Result<ModelConfig<Bourg>, CliError> {
    let mut controls = Bourg::initial_controls();
    if let Some(thrust_lb) = args.thrust_lb {
        // In 0..3000 (clap checked): exact enough in f32 for any typed value.
        #[allow(clippy::cast_possible_truncation)]
        {
            controls.thrust_lb = thrust_lb as f32;
        }
    }
    let start = start_model::<Bourg>(controls, &args.common.start)?;
    prepare_model(args.common, start)
}

/// Bourg's report fields and its aircraft as a recording stores it: the
/// run library's.
pub use fdm_run::model::bourg::{BourgAircraftRecord, BourgDetails};

impl Details for BourgDetails {
    fn hud_controls(&self) -> String {
        format!(
            "THRUST {:4.0} lb   FLAPS {}   TRIM {:+.2}",
            self.thrust_lb,
            if self.flaps { "down" } else { "up" },
            self.pitch_trim
        )
    }
}

impl KeyAction for BourgAction {
    const KEY_HELP: &'static str =
        "E/D thrust  Down/Up pitch up/down  T/G trim nose up/down  Left/Right roll  N/M yaw  K/L flaps down/up";

    fn from_key(code: KeyCode) -> Option<Self> {
        Some(match (code, letter(code)) {
            (_, Some('e')) => Self::ThrustUp,
            (_, Some('d')) => Self::ThrustDown,
            (KeyCode::Down, _) => Self::PitchUp,
            (KeyCode::Up, _) => Self::PitchDown,
            (KeyCode::Left, _) => Self::RollLeft,
            (KeyCode::Right, _) => Self::RollRight,
            (_, Some('n')) => Self::YawLeft,
            (_, Some('m')) => Self::YawRight,
            (_, Some('k')) => Self::FlapsDown,
            (_, Some('l')) => Self::FlapsUp,
            (_, Some('t')) => Self::TrimNoseUp,
            (_, Some('g')) => Self::TrimNoseDown,
            _ => return None,
        })
    }
}
