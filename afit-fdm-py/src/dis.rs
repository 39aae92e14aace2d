//! `Flight.dis_to`'s keyword arguments (feature `dis`), checked and turned
//! into the run library's [`FlightDis`]: the same settings, ranges and
//! defaults as `sim-cli --dis` (docs/cli.md, "DIS output and `dis-listen`").
//! Markings, identities and thresholds are checked again by fdm-dis when the
//! output opens.

use std::net::SocketAddr;

use fdm_dis::{DisVersion, DrAlgorithm, DrThresholds};
use fdm_run::dis::{DisSettings, FlightDis, ENTITIES_PER_APPLICATION, MAX_SITE_OR_APPLICATION};
use pyo3::exceptions::PyValueError;
use pyo3::PyResult;

/// `Flight.dis_to`'s arguments as given.
#[derive(Debug)]
pub struct DisArgs<'a> {
    /// `HOST:PORT`.
    pub target: &'a str,
    /// Entity number, 1..=65533.
    pub entity: u16,
    /// Marking, or the model's `CALLSIGN-entity`.
    pub callsign: Option<String>,
    /// Site, 1..=65534.
    pub site: u16,
    /// Application, 1..=65534.
    pub application: u16,
    /// Exercise, 1..=255.
    pub exercise: u8,
    /// 6 or 7.
    pub version: u8,
    /// `fpw`, `rpw`, `rvw` or `fvw`.
    pub dr: &'a str,
    /// Position threshold, m (positive, finite).
    pub position_threshold_m: f64,
    /// Orientation threshold, degrees (positive, finite).
    pub orientation_threshold_deg: f64,
    /// Heartbeat, s (positive, finite).
    pub heartbeat_s: f64,
    /// A PDU every frame.
    pub every_frame: bool,
}

fn refuse(message: String) -> pyo3::PyErr {
    PyValueError::new_err(message)
}

fn in_range(name: &str, value: u64, lo: u64, hi: u64) -> PyResult<()> {
    if (lo..=hi).contains(&value) {
        Ok(())
    } else {
        Err(refuse(format!("{name}: {value} is not in {lo}..={hi}")))
    }
}

/// `HOST:PORT` resolved (its first address), as `sim-cli --dis` resolves
/// it ([`fdm_run::dis::resolve_target`]): port 0 and the unspecified address
/// are refused.
///
/// # Errors
/// `ValueError` naming `target`.
pub fn resolve_target(text: &str) -> PyResult<SocketAddr> {
    fdm_run::dis::resolve_target(text).map_err(|e| refuse(format!("target: {e}")))
}

/// The checked settings of one aircraft's DIS output.
///
/// # Errors
/// `ValueError` naming the argument.
pub fn flight_dis(args: &DisArgs<'_>) -> PyResult<FlightDis> {
    let target = resolve_target(args.target)?;
    let most = u64::from(MAX_SITE_OR_APPLICATION);
    in_range("site", args.site.into(), 1, most)?;
    in_range("application", args.application.into(), 1, most)?;
    in_range("entity", args.entity.into(), 1, ENTITIES_PER_APPLICATION)?;
    in_range("exercise", args.exercise.into(), 1, 255)?;
    in_range("version", args.version.into(), 6, 7)?;
    let dr = match args.dr {
        "fpw" => DrAlgorithm::Fpw,
        "rpw" => DrAlgorithm::Rpw,
        "rvw" => DrAlgorithm::Rvw,
        "fvw" => DrAlgorithm::Fvw,
        other => return Err(refuse(format!("dr: {other:?} is not fpw, rpw, rvw or fvw"))),
    };
    for (name, value) in [
        ("position_threshold_m", args.position_threshold_m),
        ("orientation_threshold_deg", args.orientation_threshold_deg),
        ("heartbeat_s", args.heartbeat_s),
    ] {
        if !(value.is_finite() && value > 0.0) {
            return Err(refuse(format!(
                "{name}: {value} is not a positive finite number"
            )));
        }
    }
    Ok(FlightDis {
        settings: DisSettings {
            target,
            site: args.site,
            application: args.application,
            exercise: args.exercise,
            version: if args.version == 6 {
                DisVersion::V6
            } else {
                DisVersion::V7
            },
            dr,
            thresholds: DrThresholds {
                position_m: args.position_threshold_m,
                orientation_deg: args.orientation_threshold_deg,
                heartbeat_s: args.heartbeat_s,
            },
            every_frame: args.every_frame,
        },
        entity: args.entity,
        callsign: args.callsign.clone(),
    })
}
