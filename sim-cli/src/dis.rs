//! DIS output (`--dis HOST:PORT`) for `sim-cli palmer|bourg` and `sim-cli
//! fleet`: every aircraft becomes a DIS entity publishing Entity State PDUs
//! through [`fdm_dis`] (docs/dis.md).
//!
//! Everything here is generic over the model: an aircraft is seen through the
//! model interface's [`FlightView`], placed on WGS-84 with the run's
//! [`GeodeticOrigin`] as the FlightGear bridge places it
//! ([`fgnet::bridge::display`]: the same position and attitude, computed
//! straight into ECEF, [`Placement`]), and the only per-model facts are
//! [`CliModel::DIS_KIND`] (the entity type) and [`CliModel::DIS_CALLSIGN`]
//! (the start of the markings).
//!
//! # Placement, rates, what is due
//!
//! Placing an aircraft in ECEF, deriving its rates from consecutive frames,
//! deciding what is due and counting the sends are fdm-dis's
//! ([`fdm_dis::tracker`]); a lanes-kernel fleet is published by its
//! [`FleetPublisher`] on all threads, making the DIS angles, rates and PDU
//! only for the aircraft that are due.
//!
//! # Entity numbers and callsigns
//!
//! One aircraft is entity `site:application:entity` from `--dis-site`,
//! `--dis-application` and `--dis-entity` (default 1:1:1). Fleet aircraft
//! `i = 0, 1, …` get entity `--dis-entity-base + i`; DIS allows 65 533 entity
//! numbers per application, so past 65 533 the numbering goes on at entity 1
//! of the next application ([`fleet_identity`]): a fleet of 100 000 from
//! 1:1:1 ends at 1:2:34 467. Shards of one exercise must not overlap: give
//! each its own `--dis-application` (or site, or entity base). Callsigns are
//! the model's prefix and the aircraft's number, `C172-1`, `BRG-17`
//! ([`callsign`]).

use std::net::{SocketAddr, ToSocketAddrs};
use std::time::Instant;

use clap::{Args, ValueEnum};
use fdm_core::geodesy::GeodeticOrigin;
use fdm_core::model::{FlightView, Model};
use fdm_dis::{
    AircraftKind, DisVersion, DrAlgorithm, DrThresholds, EntityConfig, EntityIdentity,
    FleetPublisher, Marking, UdpSender,
};
use fdm_ecs::components::Params;
use fdm_ecs::{Entity, World};
use serde::{Deserialize, Serialize};

use crate::error::CliError;
use crate::input::Echo;
use crate::models::CliModel;

/// Entity numbers DIS allows in one application (1 to 0xFFFD).
pub const ENTITIES_PER_APPLICATION: u64 = 0xFFFD;

/// Largest site or application number (0xFFFF means "all").
pub const MAX_SITE_OR_APPLICATION: u16 = 0xFFFE;

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

    /// The standard's name, e.g. `"DRM(R,V,W)"`.
    #[must_use]
    pub fn label(self) -> &'static str {
        match self {
            Self::Fpw => "DRM(F,P,W)",
            Self::Rpw => "DRM(R,P,W)",
            Self::Rvw => "DRM(R,V,W)",
            Self::Fvw => "DRM(F,V,W)",
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

fn parse_number<T: TryFrom<u64>>(text: &str, lo: u64, hi: u64, what: &str) -> Result<T, String> {
    text.trim()
        .parse::<u64>()
        .ok()
        .filter(|v| (lo..=hi).contains(v))
        .and_then(|v| T::try_from(v).ok())
        .ok_or_else(|| format!("`{}` is not a {what} in {lo}..={hi}", Echo::short(text)))
}

/// `--dis-site`, `--dis-application`: 1 to 65534.
pub fn parse_site_or_application(text: &str) -> Result<u16, String> {
    parse_number(text, 1, u64::from(MAX_SITE_OR_APPLICATION), "DIS number")
}

/// `--dis-entity`, `--dis-entity-base`: 1 to 65533.
pub fn parse_entity(text: &str) -> Result<u16, String> {
    parse_number(text, 1, ENTITIES_PER_APPLICATION, "DIS entity number")
}

/// `--dis-exercise`: 1 to 255.
pub fn parse_exercise(text: &str) -> Result<u8, String> {
    parse_number(text, 1, 255, "DIS exercise id")
}

/// `--dis-version`: 6 or 7.
pub fn parse_version(text: &str) -> Result<u8, String> {
    parse_number(text, 6, 7, "DIS version")
}

/// Thresholds and heartbeat: positive, finite.
pub fn parse_threshold(text: &str) -> Result<f64, String> {
    match text.trim().parse::<f64>() {
        Ok(v) if v.is_finite() && v > 0.0 => Ok(v),
        _ => Err(format!(
            "`{}` is not a positive finite number",
            Echo::short(text)
        )),
    }
}

/// `--dis-callsign`: what [`Marking::new`] accepts (at most 11 printable ASCII characters).
pub fn parse_callsign(text: &str) -> Result<String, String> {
    Marking::new(text)
        .map(|m| m.as_str().to_owned())
        .map_err(|_| {
            format!(
                "`{}` is not a DIS marking (at most 11 printable ASCII characters)",
                Echo::short(text)
            )
        })
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

impl Default for FleetDisArgs {
    /// No `--dis`, entity base 1.
    fn default() -> Self {
        Self {
            common: DisArgs::default(),
            entity_base: 1,
        }
    }
}

/// Validated `--dis` settings shared by every aircraft of a run.
#[derive(Debug, Clone, PartialEq)]
pub struct DisSettings {
    /// Where the PDUs go.
    pub target: SocketAddr,
    /// Site number.
    pub site: u16,
    /// (First) application number.
    pub application: u16,
    /// Exercise id.
    pub exercise: u8,
    /// Protocol version written.
    pub version: DisVersion,
    /// Dead-reckoning algorithm.
    pub dr: DrChoice,
    /// When to send.
    pub thresholds: DrThresholds,
    /// Send every frame instead (no dead reckoning).
    pub every_frame: bool,
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
            dr: self.dr,
            thresholds: DrThresholds {
                position_m: self.position_threshold_m,
                orientation_deg: self.orientation_threshold_deg,
                heartbeat_s: self.heartbeat_s,
            },
            every_frame: self.every_frame,
        }))
    }
}

/// Resolves `HOST:PORT` (the first address it resolves to).
///
/// # Errors
/// [`CliError::Usage`] naming the text.
pub fn resolve_target(text: &str) -> Result<SocketAddr, CliError> {
    let shown = Echo::short(text);
    let addr = text
        .to_socket_addrs()
        .map_err(|e| CliError::usage(format!("--dis {shown}: not a HOST:PORT address ({e})")))?
        .next()
        .ok_or_else(|| CliError::usage(format!("--dis {shown}: resolves to no address")))?;
    if addr.port() == 0 {
        return Err(CliError::usage(format!("--dis {shown}: port 0")));
    }
    // As for --fg: the unspecified address names no receiver. Unlike --fg,
    // broadcast (DIS exercises are often broadcast on a LAN) and IPv6 (DIS
    // receivers need not be IPv4, unlike FlightGear's native-FDM socket) are
    // allowed.
    if addr.ip().is_unspecified() {
        return Err(CliError::usage(format!(
            "--dis {shown}: the unspecified address (no host); give a receiver's address, \
             or a broadcast address such as 255.255.255.255"
        )));
    }
    Ok(addr)
}

impl DisSettings {
    /// The thresholds the publishers run with: the configured ones, or with
    /// `--dis-every-frame` a heartbeat so short that every frame is due.
    #[must_use]
    pub fn effective_thresholds(&self) -> DrThresholds {
        if self.every_frame {
            DrThresholds {
                heartbeat_s: f64::MIN_POSITIVE,
                ..self.thresholds
            }
        } else {
            self.thresholds
        }
    }

    /// The configuration of one entity of model `M`.
    ///
    /// # Errors
    /// [`CliError::Usage`] for a marking fdm-dis refuses.
    pub fn entity_config<M: CliModel>(
        &self,
        id: EntityIdentity,
        marking: &str,
    ) -> Result<EntityConfig, CliError> {
        let marking = Marking::new(marking).map_err(|e| CliError::usage(format!("--dis: {e}")))?;
        let mut config = EntityConfig::new(id, M::DIS_KIND, marking);
        config.exercise_id = self.exercise;
        config.dr_algorithm = self.dr.algorithm();
        config.version = self.version;
        Ok(config)
    }
}

/// The identity of fleet aircraft `index` (0-based): entity `base + index`
/// in `application`, continuing at entity 1 of the next application past
/// [`ENTITIES_PER_APPLICATION`].
///
/// # Errors
/// [`CliError::Usage`] when the numbering runs past application 65534.
pub fn fleet_identity(
    site: u16,
    application: u16,
    entity_base: u16,
    index: u64,
) -> Result<EntityIdentity, CliError> {
    let k = u64::from(entity_base.max(1) - 1) + index;
    let app = u64::from(application) + k / ENTITIES_PER_APPLICATION;
    let entity = 1 + k % ENTITIES_PER_APPLICATION;
    let (Ok(app), Ok(entity)) = (u16::try_from(app), u16::try_from(entity)) else {
        return Err(too_many(site, application, entity_base, index));
    };
    EntityIdentity::new(site, app, entity)
        .map_err(|_| too_many(site, application, entity_base, index))
}

fn too_many(site: u16, application: u16, entity_base: u16, index: u64) -> CliError {
    CliError::usage(format!(
        "--dis: aircraft {} would need an application number above {MAX_SITE_OR_APPLICATION} \
         (entities {site}:{application}:{entity_base} onwards, {ENTITIES_PER_APPLICATION} per application)",
        index + 1
    ))
}

/// The marking of aircraft number `n`: `PREFIX-n`, or `PREFIXn`, or `n`,
/// the first that fits in 11 characters (a `u64` below 10¹¹ always fits).
#[must_use]
pub fn callsign(prefix: &str, n: u64) -> String {
    let with_dash = format!("{prefix}-{n}");
    if with_dash.len() <= 11 {
        return with_dash;
    }
    let joined = format!("{prefix}{n}");
    if joined.len() <= 11 {
        return joined;
    }
    let digits = n.to_string();
    digits[digits.len().saturating_sub(11)..].to_owned()
}

/// The placement, rates and counts of DIS output live in fdm-dis
/// ([`fdm_dis::tracker`]); re-exported here where the commands use them.
pub use fdm_dis::{rotation_vector, Placement, Tally, Tracker};

/// A [`Tracker`] for `config`, with fdm-dis's refusal as a usage error.
///
/// # Errors
/// [`CliError::Usage`] for thresholds fdm-dis refuses.
pub fn tracker(config: EntityConfig, thresholds: DrThresholds) -> Result<Tracker, CliError> {
    Tracker::new(config, thresholds).map_err(|e| CliError::usage(format!("--dis: {e}")))
}

/// The JSON report's `dis.reasons`: why the PDUs were sent.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct ReasonCounts {
    /// The first PDU of an entity, or the first after a reset.
    pub first: u64,
    /// The dead-reckoned position was off by more than the threshold.
    pub position: u64,
    /// The dead-reckoned orientation was off by more than the threshold.
    pub orientation: u64,
    /// The heartbeat (with `--dis-every-frame`: every frame after the first).
    pub heartbeat: u64,
}

impl From<fdm_dis::ReasonCounts> for ReasonCounts {
    fn from(r: fdm_dis::ReasonCounts) -> Self {
        Self {
            first: r.first,
            position: r.position,
            orientation: r.orientation,
            heartbeat: r.heartbeat,
        }
    }
}

/// The JSON report's `dis.thresholds`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ThresholdReport {
    /// Position threshold, metres.
    pub position_m: f64,
    /// Orientation threshold, degrees.
    pub orientation_deg: f64,
    /// Heartbeat, seconds.
    pub heartbeat_s: f64,
}

/// The JSON report's `dis` object (`sim-cli palmer|bourg --headless --json`
/// and `sim-cli fleet --json` with `--dis`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct DisReport {
    /// Where the PDUs went.
    pub target: String,
    /// DIS protocol version written (6 or 7).
    pub protocol_version: u8,
    /// Exercise id.
    pub exercise: u8,
    /// Dead-reckoning algorithm, e.g. `"DRM(R,V,W)"`.
    pub dr_algorithm: String,
    /// Whether every frame was sent (`--dis-every-frame`: no dead reckoning).
    pub every_frame: bool,
    /// The thresholds (as configured; ignored with `every_frame`).
    pub thresholds: ThresholdReport,
    /// Entities published.
    pub entities: u64,
    /// The first entity id, `site:application:entity`.
    pub first_entity: String,
    /// The last entity id.
    pub last_entity: String,
    /// Frames published (each a dead-reckoning check of every entity).
    pub frames: u64,
    /// Simulated seconds those frames cover (frames / fps).
    pub sim_seconds: f64,
    /// PDUs sent (handed to the OS), one per datagram.
    pub pdus: u64,
    /// Bytes in those datagrams (UDP payload).
    pub bytes: u64,
    /// Sends that failed (counted, never fatal).
    pub failed: u64,
    /// Frames of an aircraft that could not be sent at all (a non-finite state).
    pub invalid: u64,
    /// Why the PDUs were due.
    pub reasons: ReasonCounts,
    /// `pdus / sim_seconds` (`null` for a run of 0 frames).
    pub pdus_per_sim_s: Option<f64>,
    /// `bytes / sim_seconds`.
    pub bytes_per_sim_s: Option<f64>,
    /// Fleets: wall-clock seconds spent in DIS output (placing, dead
    /// reckoning, encoding, sending), separately from the steps.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub publish_seconds: Option<f64>,
}

impl DisReport {
    /// The summary line of the human report.
    #[must_use]
    pub fn summary(&self) -> String {
        format!(
            "dis  {} PDUs ({} bytes) to {} for {} entit{}, {} failed; {} (first {}, position {}, orientation {}, heartbeat {})",
            self.pdus,
            self.bytes,
            self.target,
            self.entities,
            if self.entities == 1 { "y" } else { "ies" },
            self.failed,
            if self.every_frame { "every frame" } else { self.dr_algorithm.as_str() },
            self.reasons.first,
            self.reasons.position,
            self.reasons.orientation,
            self.reasons.heartbeat,
        )
    }
}

/// The socket and the counts shared by all entities of a run.
#[derive(Debug)]
pub struct DisLink {
    settings: DisSettings,
    sender: UdpSender,
    tally: Tally,
}

impl DisLink {
    /// Opens the socket.
    ///
    /// # Errors
    /// [`CliError::Runtime`] when the socket cannot be made.
    pub fn open(settings: DisSettings) -> Result<Self, CliError> {
        // A broadcast address needs SO_BROADCAST; unicast does not mind it.
        let broadcast = matches!(settings.target, SocketAddr::V4(a) if a.ip().is_broadcast() || a.ip().octets()[3] == 255);
        let sender = UdpSender::new(settings.target, broadcast)
            .map_err(|e| CliError::runtime(format!("opening the DIS socket: {e}")))?;
        Ok(Self {
            settings,
            sender,
            tally: Tally::default(),
        })
    }

    /// The settings.
    #[must_use]
    pub fn settings(&self) -> &DisSettings {
        &self.settings
    }

    /// The first failure, once.
    pub fn take_failure(&mut self) -> Option<String> {
        self.tally.first_failure.take()
    }

    /// The report for `entities` entities from `first` to `last` over `frames` frames at `fps`.
    #[must_use]
    pub fn report(
        &self,
        entities: u64,
        (first, last): (EntityIdentity, EntityIdentity),
        frames: u64,
        fps: u32,
    ) -> DisReport {
        #[allow(clippy::cast_precision_loss)] // counts far below 2^53
        let sim_seconds = frames as f64 / f64::from(fps);
        #[allow(clippy::cast_precision_loss)]
        let per_s = |n: u64| (sim_seconds > 0.0).then(|| n as f64 / sim_seconds);
        let s = &self.settings;
        DisReport {
            target: s.target.to_string(),
            protocol_version: if s.version == DisVersion::V6 { 6 } else { 7 },
            exercise: s.exercise,
            dr_algorithm: s.dr.label().to_owned(),
            every_frame: s.every_frame,
            thresholds: ThresholdReport {
                position_m: s.thresholds.position_m,
                orientation_deg: s.thresholds.orientation_deg,
                heartbeat_s: s.thresholds.heartbeat_s,
            },
            entities,
            first_entity: first.to_string(),
            last_entity: last.to_string(),
            frames,
            sim_seconds,
            pdus: self.tally.pdus,
            bytes: self.tally.bytes,
            failed: self.tally.failed,
            invalid: self.tally.invalid,
            reasons: ReasonCounts::from(self.tally.reasons),
            pdus_per_sim_s: per_s(self.tally.pdus),
            bytes_per_sim_s: per_s(self.tally.bytes),
            publish_seconds: None,
        }
    }
}

/// `--dis` for one aircraft (`sim-cli palmer|bourg`), as configured.
#[derive(Debug, Clone, PartialEq)]
pub struct FlightDis {
    /// The shared settings.
    pub settings: DisSettings,
    /// The aircraft's entity number.
    pub entity: u16,
    /// Its marking, if not the default.
    pub callsign: Option<String>,
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

/// One aircraft's DIS output in a `sim-cli palmer|bourg` run.
#[derive(Debug)]
pub struct DisOutput {
    link: DisLink,
    tracker: Tracker,
    placement: Placement,
    fps: u32,
    frames: u64,
}

impl DisOutput {
    /// The socket and the publisher of one aircraft of model `M`.
    ///
    /// # Errors
    /// [`CliError::Usage`] for a bad identity or marking,
    /// [`CliError::Runtime`] when the socket cannot be made.
    pub fn open<M: CliModel>(
        config: &FlightDis,
        origin: GeodeticOrigin,
        fps: u32,
    ) -> Result<Self, CliError> {
        let s = &config.settings;
        let id = EntityIdentity::new(s.site, s.application, config.entity)
            .map_err(|e| CliError::usage(format!("--dis: {e}")))?;
        let marking = config
            .callsign
            .clone()
            .unwrap_or_else(|| callsign(M::DIS_CALLSIGN, u64::from(config.entity)));
        let tracker = tracker(
            s.entity_config::<M>(id, &marking)?,
            s.effective_thresholds(),
        )?;
        Ok(Self {
            link: DisLink::open(s.clone())?,
            tracker,
            placement: Placement::new(origin),
            fps,
            frames: 0,
        })
    }

    /// Publishes one frame of the aircraft seen through `view`.
    pub fn publish(&mut self, view: &FlightView) {
        self.frames += 1;
        let link = &mut self.link;
        link.tally
            .publish(&link.sender, self.tracker.update(view, &self.placement));
    }

    /// The first failure, once.
    pub fn take_failure(&mut self) -> Option<String> {
        self.link.take_failure()
    }

    /// The report so far.
    #[must_use]
    pub fn report(&self) -> DisReport {
        let id = self.tracker.config().id;
        self.link.report(1, (id, id), self.frames, self.fps)
    }
}

/// `--dis` for a fleet: a [`Tracker`] per aircraft (an ECS component of each
/// aircraft's entity, or for the lanes kernel a vector beside the fleet's
/// arrays), one socket.
#[derive(Debug)]
pub struct FleetDis {
    link: DisLink,
    entities: u64,
    first: EntityIdentity,
    last: EntityIdentity,
    frames: u64,
    seconds: f64,
    /// The lanes kernel's trackers, aircraft `i` at index `i` (empty for ECS fleets).
    lanes: FleetPublisher,
}

impl FleetDis {
    fn open(settings: &DisSettings, entity_base: u16, n: u64) -> Result<Self, CliError> {
        Ok(Self {
            link: DisLink::open(settings.clone())?,
            entities: n,
            first: fleet_identity(settings.site, settings.application, entity_base, 0)?,
            last: fleet_identity(
                settings.site,
                settings.application,
                entity_base,
                n.saturating_sub(1),
            )?,
            frames: 0,
            seconds: 0.0,
            lanes: FleetPublisher::default(),
        })
    }

    /// The tracker of fleet aircraft `i` of model `M`.
    fn tracker<M: CliModel>(
        settings: &DisSettings,
        entity_base: u16,
        i: u64,
    ) -> Result<Tracker, CliError> {
        let id = fleet_identity(settings.site, settings.application, entity_base, i)?;
        let number = u64::from(entity_base) + i;
        tracker(
            settings.entity_config::<M>(id, &callsign(M::DIS_CALLSIGN, number))?,
            settings.effective_thresholds(),
        )
    }

    /// Gives every aircraft of model `M` in `world` (in spawn order) its
    /// identity, callsign and [`Tracker`], and opens the socket.
    ///
    /// # Errors
    /// [`CliError::Usage`] when the fleet needs entity numbers past
    /// application 65534; [`CliError::Runtime`] for the socket.
    pub fn attach<M: CliModel>(
        world: &mut World,
        settings: &DisSettings,
        entity_base: u16,
    ) -> Result<Self, CliError> {
        let mut aircraft: Vec<Entity> = world
            .query::<(Entity, &Params<M>)>()
            .iter()
            .map(|(e, _)| e)
            .collect();
        aircraft.sort_by_key(|e| e.id());
        let dis = Self::open(settings, entity_base, aircraft.len() as u64)?;
        for (i, entity) in (0u64..).zip(aircraft) {
            let tracker = Self::tracker::<M>(settings, entity_base, i)?;
            world
                .insert_one(entity, tracker)
                .map_err(|e| CliError::runtime(format!("fleet aircraft vanished: {e}")))?;
        }
        Ok(dis)
    }

    /// Trackers for `n` aircraft of model `M` flown by the lanes kernel
    /// (its demonstration fleet: aircraft `i` flies with the controls of
    /// [`Model::fleet_member`]`(i)`), and the socket.
    ///
    /// # Errors
    /// As [`FleetDis::attach`].
    pub fn for_lanes<M: CliModel>(
        settings: &DisSettings,
        entity_base: u16,
        n: usize,
    ) -> Result<Self, CliError> {
        let mut dis = Self::open(settings, entity_base, n as u64)?;
        dis.lanes = FleetPublisher::new(
            (0..n as u64)
                .map(|i| Self::tracker::<M>(settings, entity_base, i))
                .collect::<Result<_, _>>()?,
        );
        Ok(dis)
    }

    /// Publishes one frame of a lanes-kernel fleet: aircraft `i`'s state is
    /// `state(i)`, its controls those of [`Model::fleet_member`]`(i)`. On
    /// the current rayon pool ([`FleetPublisher::publish`]), sending as it
    /// goes.
    pub fn publish_lanes<M: Model>(
        &mut self,
        state: impl Fn(usize) -> Option<M::State> + Sync,
        origin: &GeodeticOrigin,
    ) {
        let start = Instant::now();
        self.frames += 1;
        let placement = Placement::new(*origin);
        let aircraft = M::default_aircraft();
        let tally = self.lanes.publish(&self.link.sender, &placement, |i| {
            let s = state(i)?;
            let (controls, _) = M::fleet_member(i);
            Some(M::view(&aircraft, &controls, &s))
        });
        self.link.tally.merge(tally);
        self.seconds += start.elapsed().as_secs_f64();
    }

    /// Publishes one frame of every aircraft of model `M` with a [`Tracker`]:
    /// on this thread, or with `parallel` on the current rayon pool in
    /// batches of [`fdm_ecs::systems::PARALLEL_BATCH`] aircraft, each batch
    /// sending through the shared socket as it goes (a UDP socket sends
    /// whole datagrams from any thread). Datagrams of one frame are then in
    /// no particular order; each aircraft's own stay in order.
    pub fn publish<M: Model>(
        &mut self,
        world: &mut World,
        origin: &GeodeticOrigin,
        parallel: bool,
    ) {
        use rayon::iter::{ParallelBridge as _, ParallelIterator as _};
        let start = Instant::now();
        let placement = Placement::new(*origin);
        let placement = &placement;
        self.frames += 1;
        let query = world.query_mut::<(&Params<M>, &M::Controls, &M::State, &mut Tracker)>();
        let sender = &self.link.sender;
        let one = |tally: &mut Tally,
                   (params, controls, state, tracker): (
            &Params<M>,
            &M::Controls,
            &M::State,
            &mut Tracker,
        )| {
            let view = M::view(&params.0, controls, state);
            tally.publish(sender, tracker.update(&view, placement));
        };
        if parallel {
            let tally = query
                .into_iter_batched(fdm_ecs::systems::PARALLEL_BATCH)
                .par_bridge()
                .map(|batch| {
                    let mut tally = Tally::default();
                    batch.for_each(|item| one(&mut tally, item));
                    tally
                })
                .reduce(Tally::default, |mut a, b| {
                    a.merge(b);
                    a
                });
            self.link.tally.merge(tally);
        } else {
            let mut tally = Tally::default();
            query.into_iter().for_each(|item| one(&mut tally, item));
            self.link.tally.merge(tally);
        }
        self.seconds += start.elapsed().as_secs_f64();
    }

    /// The first failure, once.
    pub fn take_failure(&mut self) -> Option<String> {
        self.link.take_failure()
    }

    /// The report, with the time spent publishing.
    #[must_use]
    pub fn report(&self, fps: u32) -> DisReport {
        let mut r = self
            .link
            .report(self.entities, (self.first, self.last), self.frames, fps);
        r.publish_seconds = Some(self.seconds);
        r
    }
}

/// The entity type of a model as DIS writes it, `kind.domain.country.category.subcategory.specific.extra`.
#[must_use]
pub fn entity_type_label(kind: AircraftKind) -> String {
    type_label(&kind.entity_type())
}

/// `kind.domain.country.category.subcategory.specific.extra` of a DIS entity type.
#[must_use]
pub fn type_label(t: &fdm_dis::dis_rs::model::EntityType) -> String {
    format!(
        "{}.{}.{}.{}.{}.{}.{}",
        u8::from(t.kind),
        u8::from(t.domain),
        u16::from(t.country),
        t.category,
        t.subcategory,
        t.specific,
        t.extra
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use fdm_core::geodesy::ned_from_model;
    use fdm_core::palmer::Palmer;
    use nalgebra::Vector3;

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

    #[test]
    fn fleet_numbering_spills_into_the_next_application() {
        let id = |base, i| fleet_identity(1, 1, base, i).unwrap().to_string();
        assert_eq!(id(1, 0), "1:1:1");
        assert_eq!(id(1, 65_532), "1:1:65533");
        assert_eq!(id(1, 65_533), "1:2:1");
        assert_eq!(id(1, 99_999), "1:2:34467");
        assert_eq!(id(1001, 0), "1:1:1001");
        assert_eq!(id(65_533, 1), "1:2:1");
        assert!(fleet_identity(1, 0xFFFE, 1, 65_533).is_err());
        assert!(fleet_identity(1, 0xFFFE, 1, 65_532).is_ok());
    }

    #[test]
    fn callsigns_always_fit() {
        assert_eq!(callsign("C172", 1), "C172-1");
        assert_eq!(callsign("C172", 100_000), "C172-100000");
        assert_eq!(callsign("C172", 1_000_000), "C1721000000");
        assert_eq!(callsign("C172", 10_000_000), "10000000");
        assert_eq!(callsign("BRG", 10_000_000), "BRG10000000");
        for n in [1, 99, 123_456_789, u64::MAX] {
            assert!(Marking::new(&callsign("C172", n)).is_ok(), "{n}");
        }
    }

    #[test]
    fn entity_types_are_the_documented_ones() {
        assert_eq!(
            entity_type_label(<Palmer as CliModel>::DIS_KIND),
            "1.2.225.85.11.1.0"
        );
        assert_eq!(
            entity_type_label(<fdm_core::bourg::Bourg as CliModel>::DIS_KIND),
            "1.2.0.85.0.0.0"
        );
    }

    /// The direct placement and the bridge's geodetic one, turned into
    /// ECEF the way fdm-dis does for an `AircraftState`, agree to rounding:
    /// 1e-6 m in position (the closed-form geodetic round trip is good to
    /// nanometres; 12 km from the origin here), 1e-12 in each rotation matrix
    /// element, 1e-9 m/s in velocity.
    #[test]
    fn placement_is_the_flightgear_bridges() {
        let origin = GeodeticOrigin::default();
        let placement = Placement::new(origin);
        for i in [0, 7, 1_234] {
            let (controls, mut state) = Palmer::fleet_member(i);
            for _ in 0..300 {
                state = Palmer::step(&Palmer::default_aircraft(), &controls, &state, 1.0 / 30.0);
            }
            let view = Palmer::view(&Palmer::default_aircraft(), &controls, &state);
            let direct = placement.place(&view);
            let d = fgnet::bridge::display(&view, &origin);
            let mut via = fdm_dis::AircraftState::new(
                view.time_s,
                d.geodetic,
                d.attitude,
                origin.model_ned_to_local_ned_at(&d.geodetic) * ned_from_model(view.velocity_mps),
            );
            via.acceleration_ned_m_s2 = Some(Vector3::zeros());
            let via = via.to_ecef().unwrap();
            assert!((direct.location_m - via.location_m).norm() < 1e-6, "{i}");
            assert!(
                (direct.body_to_ecef - via.body_to_ecef).amax() < 1e-12,
                "{i}"
            );
            assert!(
                (direct.velocity_m_s - via.velocity_m_s).norm() < 1e-9,
                "{i}"
            );
        }
    }

    /// A steady turn: the derived rates are the turn's. At 20° of bank and
    /// 50 m/s the turn rate is g·tan(20°)/V = 0.0714 rad/s about the
    /// vertical. The placement keeps the model's flat frame fixed to the
    /// origin's tangent plane, so relative to ECEF the body turns at exactly
    /// the model's rate, and the log of a rotation at a constant rate over
    /// 1/60 s is exact up to rounding: 1e-6 relative. The backward
    /// difference of the velocity is V·2·sin(ωΔt/2)/Δt, within 1e-7 of the
    /// centripetal V·ω = 3.57 m/s²; 1e-3 m/s² leaves room for rounding.
    #[test]
    fn rates_of_a_steady_turn() {
        let origin = GeodeticOrigin::default();
        let omega = 9.806_65 * 20f64.to_radians().tan() / 50.0;
        let view_at = |t: f64| {
            let heading = omega * t;
            let mut v = Palmer::view(
                &Palmer::default_aircraft(),
                &Palmer::initial_controls(),
                &Palmer::initial_state(),
            );
            v.time_s = t;
            // Earth frame: x north, y west; heading clockwise from x.
            v.position_m = Vector3::new(
                50.0 / omega * heading.sin(),
                -(50.0 / omega) * (1.0 - heading.cos()),
                500.0,
            );
            v.velocity_mps = Vector3::new(50.0 * heading.cos(), -50.0 * heading.sin(), 0.0);
            v.attitude = fdm_core::geodesy::Attitude {
                heading_deg: heading.to_degrees(),
                pitch_deg: 0.0,
                roll_deg: 20.0,
            };
            v
        };
        let mut tracker = tracker(
            DisSettings {
                target: "127.0.0.1:3000".parse().unwrap(),
                site: 1,
                application: 1,
                exercise: 1,
                version: DisVersion::V7,
                dr: DrChoice::Rvw,
                thresholds: DrThresholds::default(),
                every_frame: false,
            }
            .entity_config::<Palmer>(EntityIdentity::new(1, 1, 1).unwrap(), "T")
            .unwrap(),
            DrThresholds::default(),
        )
        .unwrap();
        let placement = Placement::new(origin);
        let first = tracker.with_rates(placement.place(&view_at(0.0)));
        assert_eq!(first.angular_velocity_body_rad_s, Vector3::zeros());
        let s = tracker.with_rates(placement.place(&view_at(1.0 / 60.0)));
        let w = s.angular_velocity_body_rad_s;
        // Yaw at ω about the vertical, seen in body axes banked 20°: q = ω sin φ, r = ω cos φ.
        let (sin_phi, cos_phi) = 20f64.to_radians().sin_cos();
        assert!((w - Vector3::new(0.0, omega * sin_phi, omega * cos_phi)).norm() < 1e-6 * omega);
        let a = placement.model_ned_to_ecef().transpose() * s.acceleration_m_s2;
        assert!((a.norm() - 50.0 * omega).abs() < 1e-3, "{a}");
        assert!(a[2].abs() < 1e-3, "{a}");
    }
}
