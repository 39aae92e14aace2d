//! The DIS flags (`--dis HOST:PORT` and its options) of `sim-cli palmer|bourg`
//! and `sim-cli fleet`, turned into the run library's settings
//! ([`fdm_run::dis::DisSettings`], [`FlightDis`]). The output itself, one
//! aircraft's ([`fdm_run::dis::DisOutput`]) and a fleet's
//! ([`fdm_run::dis::FleetDis`]), is the run library's (docs/dis.md).
//!
//! One aircraft is entity `site:application:entity` from `--dis-site`,
//! `--dis-application` and `--dis-entity` (default 1:1:1). Fleet aircraft
//! `i = 0, 1, …` get entity `--dis-entity-base + i`, continuing in the next
//! application past 65 533 ([`fdm_run::dis::fleet_identity`]). Shards of one
//! exercise must not overlap: give each its own `--dis-application` (or site,
//! or entity base).

use std::net::SocketAddr;

use clap::{Args, ValueEnum};
use fdm_dis::{DisVersion, DrAlgorithm, DrThresholds};
use fdm_run::dis::parse_version;
use fdm_run::dis::{parse_callsign, parse_entity, parse_exercise, parse_site_or_application};
use fdm_run::dis::{DisError, DisSettings, FlightDis};
use fdm_run::values::parse_positive as parse_threshold;

use crate::error::CliError;

impl From<DisError> for CliError {
    /// A refused setting is a usage error (`--dis: ...`, exit 2), the socket
    /// a run-time one (exit 1).
    fn from(e: DisError) -> Self {
        match e {
            DisError::Refused(message) => Self::usage(format!("--dis: {message}")),
            DisError::Socket(_) | DisError::World(_) => Self::runtime(e),
        }
    }
}

/// Dead-reckoning algorithm of `--dis-dr`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum DrChoice {
    /// DRM(F,P,W): constant velocity, orientation held.
    Fpw,
    /// DRM(R,P,W): constant velocity, orientation turned at the angular velocity.
    Rpw,
    /// DRM(R,V,W): constant acceleration, orientation turned (the default).
    Rvw,
    /// DRM(F,V,W): constant acceleration, orientation held.
    Fvw,
}

impl DrChoice {
    /// The fdm-dis algorithm.
    #[must_use]
    pub fn algorithm(self) -> DrAlgorithm {
        match self {
            Self::Fpw => DrAlgorithm::Fpw,
            Self::Rpw => DrAlgorithm::Rpw,
            Self::Rvw => DrAlgorithm::Rvw,
            Self::Fvw => DrAlgorithm::Fvw,
        }
    }
}

/// The DIS options every command with `--dis` has.
#[derive(Debug, Clone, Args)]
#[command(next_help_heading = "DIS output")]
pub struct DisArgs {
    /// Publish the aircraft as DIS Entity State PDUs (UDP) to HOST:PORT (DIS's customary port is 3000); a PDU is sent when dead reckoning says receivers are off by more than the thresholds, or on the heartbeat
    #[arg(long = "dis", id = "dis", value_name = "HOST:PORT")]
    pub target: Option<String>,

    /// DIS site number (1..65534)
    #[arg(long = "dis-site", value_name = "N", default_value_t = 1, value_parser = parse_site_or_application, requires = "dis")]
    pub site: u16,

    /// DIS application number (1..65534); shards of one exercise each take their own
    #[arg(long = "dis-application", value_name = "N", default_value_t = 1, value_parser = parse_site_or_application, requires = "dis")]
    pub application: u16,

    /// DIS exercise id (1..255)
    #[arg(long = "dis-exercise", value_name = "N", default_value_t = 1, value_parser = parse_exercise, requires = "dis")]
    pub exercise: u8,

    /// DIS protocol version written: 7 (IEEE 1278.1-2012) or 6 (IEEE 1278.1a-1998)
    #[arg(long = "dis-version", value_name = "6|7", default_value_t = 7, value_parser = parse_version, requires = "dis")]
    pub version: u8,

    /// Dead-reckoning algorithm announced in the PDUs and used to decide when to send
    #[arg(long = "dis-dr", value_enum, default_value_t = DrChoice::Rvw, requires = "dis")]
    pub dr: DrChoice,

    /// Send when the dead-reckoned position is off by more than this, metres
    #[arg(long = "dis-position-threshold", value_name = "M", default_value_t = 1.0, value_parser = parse_threshold, requires = "dis")]
    pub position_threshold_m: f64,

    /// Send when the dead-reckoned orientation is off by more than this, degrees
    #[arg(long = "dis-orientation-threshold", value_name = "DEG", default_value_t = 3.0, value_parser = parse_threshold, requires = "dis")]
    pub orientation_threshold_deg: f64,

    /// Send at least this often, seconds of simulated time (the heartbeat)
    #[arg(long = "dis-heartbeat", value_name = "SECONDS", default_value_t = 5.0, value_parser = parse_threshold, requires = "dis")]
    pub heartbeat_s: f64,

    /// No dead reckoning: send every aircraft's PDU on every frame (to compare traffic)
    #[arg(long = "dis-every-frame", requires = "dis")]
    pub every_frame: bool,
}

impl Default for DisArgs {
    /// No `--dis`, every option at its command-line default.
    fn default() -> Self {
        Self {
            target: None,
            site: 1,
            application: 1,
            exercise: 1,
            version: 7,
            dr: DrChoice::Rvw,
            position_threshold_m: 1.0,
            orientation_threshold_deg: 3.0,
            heartbeat_s: 5.0,
            every_frame: false,
        }
    }
}

/// `sim-cli palmer|bourg`: [`DisArgs`] and the one aircraft's number and callsign.
#[derive(Debug, Clone, Args)]
pub struct FlightDisArgs {
    /// The options every `--dis` command has.
    #[command(flatten)]
    pub common: DisArgs,

    /// DIS entity number of the aircraft (1..65533)
    #[arg(long = "dis-entity", value_name = "N", default_value_t = 1, value_parser = parse_entity, requires = "dis")]
    pub entity: u16,

    /// The aircraft's marking: up to 11 printable ASCII characters [default: C172-N or BRG-N, N the entity number]
    #[arg(long = "dis-callsign", value_name = "TEXT", value_parser = parse_callsign, requires = "dis")]
    pub callsign: Option<String>,
}

/// `sim-cli fleet`: [`DisArgs`] and the first entity number.
#[derive(Debug, Clone, Args)]
pub struct FleetDisArgs {
    /// The options every `--dis` command has.
    #[command(flatten)]
    pub common: DisArgs,

    /// Entity number of the fleet's first aircraft (1..65533); aircraft i is base + i, continuing in the next application past 65533
    #[arg(long = "dis-entity-base", value_name = "N", default_value_t = 1, value_parser = parse_entity, requires = "dis")]
    pub entity_base: u16,
}

impl Default for FlightDisArgs {
    /// No `--dis`, entity 1, the model's callsign.
    fn default() -> Self {
        Self {
            common: DisArgs::default(),
            entity: 1,
            callsign: None,
        }
    }
}

#[cfg(test)]
impl Default for FleetDisArgs {
    /// No `--dis`, entity base 1.
    fn default() -> Self {
        Self {
            common: DisArgs::default(),
            entity_base: 1,
        }
    }
}

impl DisArgs {
    /// The settings, or `None` without `--dis`.
    ///
    /// # Errors
    /// [`CliError::Usage`] when the target does not resolve or has port 0.
    pub fn settings(&self) -> Result<Option<DisSettings>, CliError> {
        let Some(text) = &self.target else {
            return Ok(None);
        };
        let target = resolve_target(text)?;
        Ok(Some(DisSettings {
            target,
            site: self.site,
            application: self.application,
            exercise: self.exercise,
            version: if self.version == 6 {
                DisVersion::V6
            } else {
                DisVersion::V7
            },
            dr: self.dr.algorithm(),
            thresholds: DrThresholds {
                position_m: self.position_threshold_m,
                orientation_deg: self.orientation_threshold_deg,
                heartbeat_s: self.heartbeat_s,
            },
            every_frame: self.every_frame,
        }))
    }
}

/// Resolves `--dis HOST:PORT` ([`fdm_run::dis::resolve_target`]).
///
/// # Errors
/// [`CliError::Usage`] naming the text.
pub fn resolve_target(text: &str) -> Result<SocketAddr, CliError> {
    fdm_run::dis::resolve_target(text).map_err(|e| CliError::usage(format!("--dis {e}")))
}

impl FlightDisArgs {
    /// The validated `--dis` of one aircraft, or `None` without `--dis`.
    ///
    /// # Errors
    /// As [`DisArgs::settings`].
    pub fn resolve(&self) -> Result<Option<FlightDis>, CliError> {
        Ok(self.common.settings()?.map(|settings| FlightDis {
            settings,
            entity: self.entity,
            callsign: self.callsign.clone(),
        }))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `--dis` refuses the unspecified address (IPv4 and IPv6) like `--fg`,
    /// and keeps broadcast and IPv6 receivers, which `--fg` refuses.
    #[test]
    fn dis_targets_refuse_the_unspecified_address_only() {
        for text in ["0.0.0.0:3000", "[::]:3000"] {
            let err = resolve_target(text).unwrap_err();
            assert_eq!(err.exit_code(), 2);
            assert!(err.to_string().contains("unspecified address"), "{err}");
        }
        for text in [
            "255.255.255.255:3000",
            "192.168.1.255:3000",
            "[::1]:3000",
            "127.0.0.1:3000",
        ] {
            assert!(resolve_target(text).is_ok(), "{text}");
        }
    }
}
