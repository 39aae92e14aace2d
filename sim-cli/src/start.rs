//! Starting in the air (docs/cli.md "Initial conditions and trim"):
//! `--altitude-ft`, `--speed-kt`, `--heading-deg` and `--trim`
//! ([`StartArgs`], shared by `palmer`, `bourg` and `fgfs-command`), turned
//! into a model's start (`crate::config::start_model`, from
//! [`StartArgs::options`]) through the library's
//! [`Model::state_at`](fdm_core::model::Model::state_at) and [`Model::trim`](fdm_core::model::Model::trim).
//!
//! Without any of them the start is exactly the thesis's
//! ([`Model::initial_state`](fdm_core::model::Model::initial_state)). With some of them, the missing ones come from
//! that start (Palmer: 0 ft, 0 kt, north; Bourg: 2000 ft, 60 ft/s, north).

use clap::Args;

use crate::error::CliError;
use crate::input::Echo;
use fdm_run::{StartOptions, StartRefused};

use fdm_run::values::{parse_altitude_ft, parse_heading_deg, parse_speed_kt};

/// Initial-condition options.
#[derive(Debug, Clone, Copy, Default, PartialEq, Args)]
pub struct StartArgs {
    /// Start this many feet above the origin (0..100000), flying level [default: the model's start]
    #[arg(long, value_name = "FT", value_parser = parse_altitude_ft, allow_hyphen_values = true)]
    pub altitude_ft: Option<f64>,

    /// Start at this true airspeed, knots (0..1000) [default: the model's start]
    #[arg(long, value_name = "KT", value_parser = parse_speed_kt, allow_hyphen_values = true)]
    pub speed_kt: Option<f64>,

    /// Start on this true heading, degrees clockwise from north [default: 0, north]
    #[arg(long, value_name = "DEG", value_parser = parse_heading_deg, allow_hyphen_values = true)]
    pub heading_deg: Option<f64>,

    /// Start trimmed for steady level flight at the initial altitude and speed (sets Palmer's throttle and angle of attack, Bourg's thrust, pitch and pitch trim); prints what it found on stderr
    #[arg(long)]
    pub trim: bool,
}

impl StartArgs {
    /// Whether the start is the thesis's (no option given).
    #[must_use]
    pub fn is_thesis(&self) -> bool {
        *self == Self::default()
    }

    /// The options as the run library takes them.
    #[must_use]
    pub fn options(&self) -> StartOptions {
        StartOptions {
            altitude_ft: self.altitude_ft,
            speed_kt: self.speed_kt,
            heading_deg: self.heading_deg,
            trim: self.trim,
        }
    }
}

/// Why a start was refused, as a usage error (exit 2) naming the option.
#[must_use]
pub fn refused(refused: StartRefused) -> CliError {
    CliError::usage(match refused {
        StartRefused::TrimOnGround => {
            "--trim: cannot trim on the ground; give --altitude-ft above 0".to_owned()
        }
        StartRefused::Trim(e) => format!("--trim: {e}"),
        StartRefused::Conditions(e) => format!("initial conditions: {e}"),
        StartRefused::OutOfRange { name, value, .. } => format!(
            "--{}: `{}` is out of range",
            name.replace('_', "-"),
            Echo::short(&value.to_string())
        ),
    })
}
