//! Bourg's 6-DoF aircraft in the CLI: its HUD line, keys and starting controls.

use crossterm::event::KeyCode;
use fdm_core::bourg::{BourgAction, BourgControls};
use fdm_core::model::Model;

use super::{CliModel, Details};
use crate::error::CliError;
use fdm_run::values::{parse_in_range, ValueError};
use crate::keys::{letter, KeyAction};

/// Bourg's 6-DoF aircraft, as the registry names it.
pub use fdm_core::bourg::Bourg;

/// `sim-cli bourg`'s own options (after the options every model shares).
#[derive(Debug, Clone, clap::Args)]
pub struct BourgArgs {
    /// Thrust at frame 0, lb (0..3000) [default: 500, the model's start]
    #[arg(long, value_name = "LB", value_parser = parse_thrust_lb, allow_hyphen_values = true, conflicts_with = "trim")]
    pub thrust_lb: Option<f64>,
}

impl CliModel for Bourg {
    const AIRCRAFT: &'static str = "Bourg's 6-DoF aircraft";
    const ABOUT: &'static str = "Fly David Bourg's 6-DoF aircraft (rigid body, Euler, f32; feet, ft/s, lb)";
    type Args = BourgArgs;

    /// The model's start, with `--thrust-lb`.
    fn controls(args: &BourgArgs) -> Result<BourgControls, CliError> {
        let mut controls = Bourg::initial_controls();
        if let Some(thrust_lb) = args.thrust_lb {
            // In 0..3000 (clap checked): exact enough in f32 for any typed value.
            #[allow(clippy::cast_possible_truncation)]
            {
                controls.thrust_lb = thrust_lb as f32;
            }
        }
        Ok(controls)
    }
}

/// `--thrust-lb`: pounds in 0..3000, Bourg's thrust range (the model's
/// [`MAX_THRUST_LB`](fdm_core::bourg::MAX_THRUST_LB)).
pub fn parse_thrust_lb(text: &str) -> Result<f64, ValueError> {
    parse_in_range(text, 0.0, f64::from(fdm_core::bourg::MAX_THRUST_LB), " lb")
}

/// Bourg's report fields: the run library's.
pub use fdm_run::model::bourg::BourgDetails;

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
