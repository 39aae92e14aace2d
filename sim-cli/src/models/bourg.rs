//! Bourg's 6-DoF aircraft in the CLI: its report fields and keys.

use crossterm::event::KeyCode;
use fdm_core::bourg::{Bourg, BourgAction, BourgAircraft, BourgControls, BourgState};
use fdm_core::model::Model;
use serde::{Deserialize, Serialize};

use super::{CliModel, Details};
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

/// Bourg-only report fields. The model is `f32`; every float here is the
/// model's `f32` widened exactly with `f64::from`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct BourgDetails {
    /// Speed |velocity|, ft/s.
    pub speed: f64,
    /// Euler angles [x roll, y pitch (positive nose-down), z yaw] in degrees, exactly as
    /// `MakeEulerAnglesFromQ` computes them.
    pub euler_deg: [f64; 3],
    /// Thrust, lb.
    pub thrust_lb: f64,
    /// Landing flaps down.
    pub flaps: bool,
    /// Any wing element past its stall angle on the last step.
    pub stalling: bool,
    /// The persistent pitch trim, −1..=1 (an extension of the model; 0
    /// unless trimmed or moved with T/G). Absent in older reports.
    #[serde(default)]
    pub pitch_trim: f64,
}

impl Details for BourgDetails {
    const MODEL: &'static str = "bourg";
    const POSITION_UNIT: &'static str = "ft";
    /// `flaps` and `stalling` are written as 0 or 1.
    fn summary(&self) -> String {
        format!(
            "speed     {:.3} ft/s  thrust {} lb  flaps {}  stalling {}  pitch trim {:.3}",
            self.speed,
            self.thrust_lb,
            if self.flaps { "down" } else { "up" },
            if self.stalling { "yes" } else { "no" },
            self.pitch_trim,
        )
    }

    fn hud_controls(&self) -> String {
        format!(
            "THRUST {:4.0} lb   FLAPS {}   TRIM {:+.2}",
            self.thrust_lb,
            if self.flaps { "down" } else { "up" },
            self.pitch_trim
        )
    }
}

impl CliModel for Bourg {
    type Details = BourgDetails;

    fn details(
        _aircraft: &BourgAircraft,
        controls: &BourgControls,
        state: &BourgState,
    ) -> BourgDetails {
        BourgDetails {
            speed: f64::from(state.speed_ftps()),
            euler_deg: state.euler_angles_deg().map(f64::from).into(),
            thrust_lb: f64::from(controls.thrust_lb),
            flaps: controls.landing_flaps,
            stalling: state.stalling,
            pitch_trim: f64::from(controls.pitch_trim),
        }
    }
}

/// Bourg's aircraft as a recording stores it (the run library's).
pub use fdm_run::model::BourgAircraftRecord;

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
