//! DIS output (feature `dis`): every aircraft of a run becomes a DIS entity
//! publishing Entity State PDUs through [`fdm_dis`] (docs/dis.md).
//!
//! * [`DisOutput`]: one aircraft, an [`Output`] of a [`Run`](crate::Run)
//!   (`sim-cli palmer|bourg --dis`);
//! * [`FleetDis`]: a whole fleet, flown in one ECS world
//!   ([`FleetDis::attach`], [`FleetDis::publish`]) or by a lanes kernel
//!   ([`FleetDis::for_lanes`]; [`FleetDis::fly_and_publish_lanes`] flies a
//!   frame and publishes each piece of the fleet right after its step,
//!   [`FleetDis::publish_lanes`] publishes a frame already flown)
//!   (`sim-cli fleet --dis`);
//! * [`DisSettings`]: what every entity of a run shares (target, site,
//!   application, exercise, version, dead reckoning), and [`DisReport`], the
//!   counters of the JSON report.
//!
//! Everything here is generic over the model: an aircraft is seen through the
//! model interface's [`FlightView`], placed in ECEF from the run's
//! [`GeodeticOrigin`] as the FlightGear bridge places it
//! ([`fdm_dis::Placement`]), and the only per-model facts are the registry's
//! [`RunModel::DIS_KIND`] (the entity type, a value) and
//! [`RunModel::CALLSIGN`] (the start of the markings). Placing, rates from
//! consecutive frames, dead reckoning and counting the sends are fdm-dis's
//! ([`fdm_dis::tracker`]).
//!
//! # Entity numbers and callsigns
//!
//! One aircraft is entity `site:application:entity`. Fleet aircraft
//! `i = 0, 1, …` get entity `entity_base + i`; DIS allows 65 533 entity
//! numbers per application, so past 65 533 the numbering goes on at entity 1
//! of the next application ([`fleet_identity`]): a fleet of 100 000 from
//! 1:1:1 ends at 1:2:34 467. Callsigns are the model's prefix and the
//! aircraft's number, `C172-1`, `BRG-17` ([`callsign`]).
//!
//! # Why the run library depends on fdm-dis, and not the other way
//!
//! fdm-dis is the protocol: PDUs, frames, dead reckoning, a listener; it
//! knows no run, no ECS world and no model (it is fuzzed and benchmarked on
//! its own). The run library is where a frame ([`Frame`]) and a world exist,
//! so the output that joins the two lives here, behind the optional `dis`
//! feature (dis-rs needs Rust 1.91; builds without DIS, such as the Python
//! package, keep the workspace's 1.89).

use std::net::{SocketAddr, ToSocketAddrs};
use std::time::Instant;

use fdm_core::geodesy::GeodeticOrigin;
use fdm_core::model::{FlightStatus, FlightView, Model};
use fdm_dis::{
    AircraftKind, DisOutputError, DisVersion, DrAlgorithm, DrThresholds, EntityConfig,
    EntityIdentity, FleetPublisher, Marking, Placement, Tally, Tracker, UdpSender,
};
use fdm_ecs::components::Params;
use fdm_ecs::{Entity, World};
use serde::{Deserialize, Serialize};

use crate::output::{Event, Frame, Output, OutputError};
use crate::values::{parse_whole, ValueError};
use crate::{FleetModel, RunModel};

/// Entity numbers DIS allows in one application (1 to 0xFFFD).
pub const ENTITIES_PER_APPLICATION: u64 = 0xFFFD;

/// Largest site or application number (0xFFFF means "all").
pub const MAX_SITE_OR_APPLICATION: u16 = 0xFFFE;

/// A site or application number (`--dis-site`, `--dis-application`): 1 to
/// [`MAX_SITE_OR_APPLICATION`].
///
/// # Errors
/// [`ValueError::NotWhole`].
pub fn parse_site_or_application(text: &str) -> Result<u16, ValueError> {
    parse_whole(text, 1, u64::from(MAX_SITE_OR_APPLICATION), "a DIS number")
}

/// An entity number (`--dis-entity`, `--dis-entity-base`): 1 to
/// [`ENTITIES_PER_APPLICATION`].
///
/// # Errors
/// [`ValueError::NotWhole`].
pub fn parse_entity(text: &str) -> Result<u16, ValueError> {
    parse_whole(text, 1, ENTITIES_PER_APPLICATION, "a DIS entity number")
}

/// An exercise id (`--dis-exercise`): 1 to 255.
///
/// # Errors
/// [`ValueError::NotWhole`].
pub fn parse_exercise(text: &str) -> Result<u8, ValueError> {
    parse_whole(text, 1, 255, "a DIS exercise id")
}

/// A protocol version (`--dis-version`): 6 or 7.
///
/// # Errors
/// [`ValueError::NotWhole`].
pub fn parse_version(text: &str) -> Result<u8, ValueError> {
    parse_whole(text, 6, 7, "a DIS version")
}

/// A marking (`--dis-callsign`): what [`Marking::new`] accepts (at most 11
/// printable ASCII characters).
///
/// # Errors
/// [`ValueError::NotMarking`].
pub fn parse_callsign(text: &str) -> Result<String, ValueError> {
    Marking::new(text)
        .map(|m| m.as_str().to_owned())
        .map_err(|_| ValueError::NotMarking {
            text: fdm_core::script::Echo::short(text).to_string(),
        })
}

/// Why a DIS target `HOST:PORT` was refused ([`resolve_target`]). The
/// text is quoted through [`fdm_core::script::Echo`] (control characters
/// escaped, long text cut), so each message is one line.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum DisTargetError {
    /// Not `HOST:PORT`, or the host does not resolve.
    #[error("{text}: not a HOST:PORT address ({message})")]
    NotAnAddress {
        /// The text as given.
        text: String,
        /// The resolver's error.
        message: String,
    },
    /// The host resolves to no address at all.
    #[error("{text}: resolves to no address")]
    NoAddress {
        /// The text as given.
        text: String,
    },
    /// Port 0 names no receiver.
    #[error("{text}: port 0")]
    PortZero {
        /// The text as given.
        text: String,
    },
    /// 0.0.0.0 or `::` names no host.
    #[error("{text}: the unspecified address (no host); give a receiver's address, or a broadcast address such as 255.255.255.255")]
    Unspecified {
        /// The text as given.
        text: String,
    },
}

/// Resolves a DIS target `HOST:PORT` (`sim-cli --dis`, Python's
/// `Flight.dis_to`) to the first address it names. Unlike FlightGear's
/// target (`fgnet::address`), broadcast (DIS exercises are often broadcast
/// on a LAN) and IPv6 (DIS receivers need not be IPv4) are allowed; port 0
/// and the unspecified address, which name no receiver, are not.
///
/// ```
/// use fdm_run::dis::{resolve_target, DisTargetError};
///
/// assert_eq!(resolve_target("127.0.0.1:3000")?.port(), 3000);
/// assert!(resolve_target("255.255.255.255:3000").is_ok());
/// assert!(matches!(resolve_target("0.0.0.0:3000"), Err(DisTargetError::Unspecified { .. })));
/// assert!(matches!(resolve_target("127.0.0.1:0"), Err(DisTargetError::PortZero { .. })));
/// # Ok::<(), DisTargetError>(())
/// ```
///
/// # Errors
/// [`DisTargetError`], naming the text.
pub fn resolve_target(text: &str) -> Result<SocketAddr, DisTargetError> {
    let shown = || fdm_core::script::Echo::short(text).to_string();
    let addr = text
        .to_socket_addrs()
        .map_err(|e| DisTargetError::NotAnAddress {
            text: shown(),
            message: e.to_string(),
        })?
        .next()
        .ok_or_else(|| DisTargetError::NoAddress { text: shown() })?;
    if addr.port() == 0 {
        return Err(DisTargetError::PortZero { text: shown() });
    }
    if addr.ip().is_unspecified() {
        return Err(DisTargetError::Unspecified { text: shown() });
    }
    Ok(addr)
}

/// Why DIS output could not start.
#[derive(Debug, thiserror::Error)]
pub enum DisError {
    /// A setting fdm-dis refuses (an identity, marking or threshold), or a
    /// fleet that needs more entity numbers than DIS has; the message is one
    /// line.
    #[error("{0}")]
    Refused(String),
    /// The UDP socket could not be made.
    #[error("opening the DIS socket: {0}")]
    Socket(#[source] DisOutputError),
    /// A fleet's world lost an aircraft while the trackers were given out.
    #[error("fleet aircraft vanished: {0}")]
    World(String),
}

/// What every entity of a run shares.
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
    pub dr: DrAlgorithm,
    /// When to send.
    pub thresholds: DrThresholds,
    /// Send every frame instead (no dead reckoning).
    pub every_frame: bool,
}

impl DisSettings {
    /// The thresholds the publishers run with: the configured ones, or with
    /// [`Self::every_frame`] a heartbeat so short that every frame is due.
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

    /// The configuration of one entity of type `kind`.
    ///
    /// # Errors
    /// [`DisError::Refused`] for a marking fdm-dis refuses.
    pub fn entity_config(
        &self,
        kind: AircraftKind,
        id: EntityIdentity,
        marking: &str,
    ) -> Result<EntityConfig, DisError> {
        let marking = Marking::new(marking).map_err(refused)?;
        let mut config = EntityConfig::new(id, kind, marking);
        config.exercise_id = self.exercise;
        config.dr_algorithm = self.dr;
        config.version = self.version;
        Ok(config)
    }

    /// A [`Tracker`] for entity `id` of model `M` marked `marking`, with the
    /// [effective thresholds](Self::effective_thresholds).
    ///
    /// # Errors
    /// [`DisError::Refused`] for a marking or thresholds fdm-dis refuses.
    pub fn tracker<M: RunModel>(
        &self,
        id: EntityIdentity,
        marking: &str,
    ) -> Result<Tracker, DisError> {
        Tracker::new(
            self.entity_config(M::DIS_KIND, id, marking)?,
            self.effective_thresholds(),
        )
        .map_err(refused)
    }
}

// By value: the `map_err` adaptor hands the error over.
#[allow(clippy::needless_pass_by_value)]
fn refused(e: DisOutputError) -> DisError {
    DisError::Refused(e.to_string())
}

/// The identity of fleet aircraft `index` (0-based): entity `base + index`
/// in `application`, continuing at entity 1 of the next application past
/// [`ENTITIES_PER_APPLICATION`].
///
/// # Errors
/// [`DisError::Refused`] when the numbering runs past application 65534.
pub fn fleet_identity(
    site: u16,
    application: u16,
    entity_base: u16,
    index: u64,
) -> Result<EntityIdentity, DisError> {
    let k = u64::from(entity_base.max(1) - 1) + index;
    let app = u64::from(application) + k / ENTITIES_PER_APPLICATION;
    let entity = 1 + k % ENTITIES_PER_APPLICATION;
    let (Ok(app), Ok(entity)) = (u16::try_from(app), u16::try_from(entity)) else {
        return Err(too_many(site, application, entity_base, index));
    };
    EntityIdentity::new(site, app, entity)
        .map_err(|_| too_many(site, application, entity_base, index))
}

fn too_many(site: u16, application: u16, entity_base: u16, index: u64) -> DisError {
    DisError::Refused(format!(
        "aircraft {} would need an application number above {MAX_SITE_OR_APPLICATION} \
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

/// The entity type of a model as DIS writes it,
/// `kind.domain.country.category.subcategory.specific.extra`.
#[must_use]
pub fn entity_type_label(kind: AircraftKind) -> String {
    fdm_dis::type_label(&kind.entity_type())
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
    /// The heartbeat (with every frame sent: every frame after the first).
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

/// The JSON report's `dis` object: what a run's DIS output sent.
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
    /// Whether every frame was sent (no dead reckoning).
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
    /// reckoning, encoding, sending), separately from the steps. For a
    /// lanes fleet, whose pieces are published right after their steps,
    /// the share of the frames' wall clock that the threads spent
    /// publishing ([`Self::publish_thread_seconds`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub publish_seconds: Option<f64>,
    /// Lanes fleets, whose pieces are each published right after their
    /// step: seconds the pool's threads spent stepping, summed over the
    /// threads (each piece's step timed on its thread). The frames' wall
    /// clock is split between `seconds` and [`Self::publish_seconds`] in
    /// proportion to this and [`Self::publish_thread_seconds`].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub step_thread_seconds: Option<f64>,
    /// Lanes fleets: seconds the pool's threads spent publishing (reading
    /// each piece's states after its step, screening, placing, encoding,
    /// sending), summed over the threads.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub publish_thread_seconds: Option<f64>,
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
    /// Opens the socket (with `SO_BROADCAST` for an IPv4 broadcast target).
    ///
    /// # Errors
    /// [`DisError::Socket`] when the socket cannot be made.
    pub fn open(settings: DisSettings) -> Result<Self, DisError> {
        // A broadcast address needs SO_BROADCAST; unicast does not mind it.
        let broadcast = matches!(settings.target, SocketAddr::V4(a) if a.ip().is_broadcast() || a.ip().octets()[3] == 255);
        let sender = UdpSender::new(settings.target, broadcast).map_err(DisError::Socket)?;
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

    /// The first send failure, once.
    pub fn take_failure(&mut self) -> Option<String> {
        self.tally.first_failure.take()
    }

    /// The report for `entities` entities from `first` to `last` over
    /// `frames` frames at `fps`.
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
            step_thread_seconds: None,
            publish_thread_seconds: None,
        }
    }
}

/// One aircraft's DIS identity in a single flight: the shared settings, its
/// entity number and marking.
#[derive(Debug, Clone, PartialEq)]
pub struct FlightDis {
    /// The shared settings.
    pub settings: DisSettings,
    /// The aircraft's entity number (in `settings`' site and application).
    pub entity: u16,
    /// Its marking, if not the model's default (`CALLSIGN-entity`).
    pub callsign: Option<String>,
}

/// One aircraft's DIS output, an [`Output`] of its run: after every flown
/// frame (not at the start or a reset, nor for a diverged step) the aircraft
/// is placed, dead-reckoned and, when due, sent.
///
/// Keep a handle through [`crate::SharedOutput`] to read
/// [`DisOutput::report`] and [`DisOutput::take_failure`] while it flies.
#[derive(Debug)]
pub struct DisOutput {
    link: DisLink,
    tracker: Tracker,
    placement: Placement,
    fps: u32,
    frames: u64,
}

impl DisOutput {
    /// The socket and the publisher of one aircraft of model `M` flown at
    /// `fps` from `origin`.
    ///
    /// # Errors
    /// [`DisError::Refused`] for a bad identity or marking,
    /// [`DisError::Socket`] when the socket cannot be made.
    pub fn open<M: RunModel>(
        config: &FlightDis,
        origin: GeodeticOrigin,
        fps: u32,
    ) -> Result<Self, DisError> {
        let s = &config.settings;
        let id = EntityIdentity::new(s.site, s.application, config.entity).map_err(refused)?;
        let marking = config
            .callsign
            .clone()
            .unwrap_or_else(|| callsign(M::CALLSIGN, u64::from(config.entity)));
        let tracker = s.tracker::<M>(id, &marking)?;
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

    /// The first send failure, once (sends are counted, never fatal).
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

impl<M: Model> Output<M> for DisOutput {
    /// Publishes [`Event::Step`] frames whose step did not diverge; a failed
    /// send is counted (and kept for [`DisOutput::take_failure`]), never an
    /// error.
    fn frame(&mut self, frame: &Frame<'_, M>) -> Result<(), OutputError> {
        if frame.event == Event::Step && frame.status != FlightStatus::Diverged {
            self.publish(frame.view);
        }
        Ok(())
    }
}

/// Model `M`'s [`FleetModel::dis_rough_lanes`] as the fleet screen's
/// [`fdm_dis::RoughFrames`]: always inlined, so that a model's lanes
/// (Palmer's) are compiled into the screen's loop with its instruction set
/// (a closure or the function passed by name was called out of line, in the
/// baseline instruction set).
struct ModelRough<M>(core::marker::PhantomData<M>);

impl<M: FleetModel> fdm_dis::RoughFrames<M::State> for ModelRough<M> {
    #[inline(always)]
    fn rough_lanes(
        &mut self,
        first: usize,
        states: &[Option<M::State>],
        out: &mut fdm_dis::RoughLanes,
    ) {
        M::dis_rough_lanes(first, states, out);
    }
}

/// A fleet's DIS output: a [`Tracker`] per aircraft (an ECS component of
/// each aircraft's entity, or for a lanes kernel a [`FleetPublisher`] beside
/// the fleet's arrays), one socket.
#[derive(Debug)]
pub struct FleetDis {
    link: DisLink,
    entities: u64,
    first: EntityIdentity,
    last: EntityIdentity,
    frames: u64,
    seconds: f64,
    /// Fused frames ([`FleetDis::fly_and_publish_lanes`]): seconds the
    /// pool's threads spent stepping and publishing, summed over the pieces.
    step_thread_seconds: f64,
    publish_thread_seconds: f64,
    /// The lanes kernel's trackers, aircraft `i` at index `i` (empty for ECS fleets).
    lanes: FleetPublisher,
}

impl FleetDis {
    fn open(settings: &DisSettings, entity_base: u16, n: u64) -> Result<Self, DisError> {
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
            step_thread_seconds: 0.0,
            publish_thread_seconds: 0.0,
            lanes: FleetPublisher::default(),
        })
    }

    /// The tracker of fleet aircraft `i` of model `M`.
    fn tracker<M: RunModel>(
        settings: &DisSettings,
        entity_base: u16,
        i: u64,
    ) -> Result<Tracker, DisError> {
        let id = fleet_identity(settings.site, settings.application, entity_base, i)?;
        let number = u64::from(entity_base) + i;
        settings.tracker::<M>(id, &callsign(M::CALLSIGN, number))
    }

    /// Gives every aircraft of model `M` in `world` (in spawn order) its
    /// identity, callsign and [`Tracker`] (a component of its entity), and
    /// opens the socket.
    ///
    /// # Errors
    /// [`DisError::Refused`] when the fleet needs entity numbers past
    /// application 65534; [`DisError::Socket`] for the socket.
    pub fn attach<M: RunModel>(
        world: &mut World,
        settings: &DisSettings,
        entity_base: u16,
    ) -> Result<Self, DisError> {
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
                .map_err(|e| DisError::World(e.to_string()))?;
        }
        Ok(dis)
    }

    /// Trackers for `n` aircraft of model `M` flown by a lanes kernel, and
    /// the socket.
    ///
    /// # Errors
    /// As [`FleetDis::attach`].
    pub fn for_lanes<M: RunModel>(
        settings: &DisSettings,
        entity_base: u16,
        n: usize,
    ) -> Result<Self, DisError> {
        let mut dis = Self::open(settings, entity_base, n as u64)?;
        dis.lanes = FleetPublisher::new(
            (0..n as u64)
                .map(|i| Self::tracker::<M>(settings, entity_base, i))
                .collect::<Result<_, _>>()?,
        );
        Ok(dis)
    }

    /// Publishes one frame of a lanes-kernel fleet: aircraft `i`'s state is
    /// `state(i)` (`None`: not this frame), its controls those of
    /// [`Model::fleet_member`]`(i)` (the kernel's demonstration fleet). On
    /// the current rayon pool, sending as it goes, screened
    /// ([`FleetPublisher::publish_screened`]): the model's
    /// [`FleetModel::dis_rough`] frames decide which aircraft certainly have
    /// nothing due, and only the others get their full view; the PDUs are
    /// those of [`FleetPublisher::publish`] bit for bit. `last` keeps each
    /// aircraft's last state between frames: the same buffer every frame,
    /// empty at first.
    pub fn publish_lanes<M: FleetModel>(
        &mut self,
        last: &mut Vec<Option<M::State>>,
        state: impl Fn(usize) -> Option<M::State> + Sync,
        origin: &GeodeticOrigin,
    ) {
        let start = Instant::now();
        self.frames += 1;
        let placement = Placement::new(*origin);
        let aircraft = M::default_aircraft();
        let tally = self.lanes.publish_screened(
            &self.link.sender,
            &placement,
            last,
            state,
            |first, states, out| M::dis_rough(first, states, out),
            |i, s| {
                let (controls, _) = M::fleet_member(i);
                M::view(&aircraft, &controls, s)
            },
        );
        self.link.tally.merge(tally);
        self.seconds += start.elapsed().as_secs_f64();
    }

    /// Flies one frame of a lanes-kernel fleet and publishes it, each piece
    /// of the fleet right after its step: the fleet is cut into pieces of
    /// [`fdm_dis::FLEET_BATCH`] aircraft (whole blocks,
    /// [`fdm_fleet::LaneFleet::par_fly_then`]), and each piece, on the thread
    /// of the current rayon pool that has just flown it and while its
    /// aircraft are in that core's cache, is published as
    /// [`FleetDis::publish_lanes`] publishes it
    /// ([`fdm_dis::ScreenedPiece::publish_lanes`], the model's rough frames
    /// made eight at a time by [`FleetModel::dis_rough_lanes`] and screened
    /// as they are made): the same PDUs, bytes, counts and per-aircraft
    /// order of datagrams. A
    /// diverged aircraft is not sent.
    ///
    /// Returns the wall-clock seconds of the frame's steps; the rest of the
    /// frame's wall clock is added to the publishing time. The two are one
    /// pass on every thread, so the frame's wall clock is split between
    /// them in proportion to the time the pool's threads spent in each
    /// (each piece's step timed apart from its publishing, summed over the
    /// pieces); those sums are reported too
    /// ([`DisReport::step_thread_seconds`],
    /// [`DisReport::publish_thread_seconds`]).
    ///
    /// # Errors
    /// The kernel's (a precision it lacks; nothing is flown or sent then).
    pub fn fly_and_publish_lanes<M: FleetModel>(
        &mut self,
        fleet: &mut M::Lanes,
        fps: f64,
        precision: fdm_fleet::Precision,
        last: &mut Vec<Option<M::State>>,
        origin: &GeodeticOrigin,
    ) -> Result<f64, fdm_fleet::FleetError> {
        use fdm_fleet::LaneFleet as _;
        let start = Instant::now();
        let placement = Placement::new(*origin);
        let aircraft = M::default_aircraft();
        let per = M::Lanes::piece_aircraft(fdm_dis::FLEET_BATCH);
        let pieces = self.lanes.screened_pieces(&placement, last, per);
        let sender = &self.link.sender;
        let done = fleet.par_fly_then(fps, precision, per, pieces, |mut piece, flown| {
            for (s, status) in flown.states.iter_mut().zip(flown.statuses) {
                if *status == FlightStatus::Diverged {
                    *s = None;
                }
            }
            let tally = piece.publish_lanes(
                sender,
                flown.states,
                ModelRough::<M>(core::marker::PhantomData),
                |i, s| {
                    let (controls, _) = M::fleet_member(i);
                    M::view(&aircraft, &controls, s)
                },
            );
            (
                tally,
                flown.fly_seconds,
                flown.flown_at.elapsed().as_secs_f64(),
            )
        })?;
        let wall = start.elapsed().as_secs_f64();
        self.frames += 1;
        let (mut step, mut publish) = (0.0, 0.0);
        for (tally, fly_s, publish_s) in done {
            self.link.tally.merge(tally);
            step += fly_s;
            publish += publish_s;
        }
        self.step_thread_seconds += step;
        self.publish_thread_seconds += publish;
        let step_share = if step + publish > 0.0 {
            wall * step / (step + publish)
        } else {
            wall
        };
        self.seconds += wall - step_share;
        Ok(step_share)
    }

    /// Publishes one frame of every aircraft of model `M` in `world` with a
    /// [`Tracker`]: on this thread, or with `parallel` on the current rayon
    /// pool in batches of [`fdm_ecs::systems::PARALLEL_BATCH`] aircraft, each
    /// batch sending through the shared socket as it goes (a UDP socket
    /// sends whole datagrams from any thread). Datagrams of one frame are
    /// then in no particular order; each aircraft's own stay in order.
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

    /// The first send failure, once.
    pub fn take_failure(&mut self) -> Option<String> {
        self.link.take_failure()
    }

    /// The report at `fps`, with the time spent publishing.
    #[must_use]
    pub fn report(&self, fps: u32) -> DisReport {
        let mut r = self
            .link
            .report(self.entities, (self.first, self.last), self.frames, fps);
        r.publish_seconds = Some(self.seconds);
        if self.step_thread_seconds + self.publish_thread_seconds > 0.0 {
            r.step_thread_seconds = Some(self.step_thread_seconds);
            r.publish_thread_seconds = Some(self.publish_thread_seconds);
        }
        r
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{Run, Scenario, SharedOutput, Start};
    use fdm_core::bourg::Bourg;
    use fdm_core::geodesy::ned_from_model;
    use fdm_core::palmer::Palmer;
    use fdm_core::script::Script;
    use fdm_dis::Listener;
    use nalgebra::Vector3;
    use std::net::UdpSocket;
    use std::time::Duration;

    fn settings(target: SocketAddr, every_frame: bool) -> DisSettings {
        DisSettings {
            target,
            site: 1,
            application: 1,
            exercise: 1,
            version: DisVersion::V7,
            dr: DrAlgorithm::Rvw,
            thresholds: DrThresholds::default(),
            every_frame,
        }
    }

    /// Each DIS number's parser at the ends of its documented range and
    /// just past them, with the message a command line shows.
    #[test]
    fn dis_numbers_at_the_ends_of_their_ranges() {
        let refused = |parsed: Result<u16, ValueError>| parsed.unwrap_err().to_string();
        assert_eq!(parse_site_or_application("1"), Ok(1));
        assert_eq!(parse_site_or_application("65534"), Ok(0xFFFE));
        for text in ["0", "65535"] {
            let message = refused(parse_site_or_application(text));
            assert!(
                message.contains("a DIS number") && message.contains("1..=65534"),
                "{message}"
            );
        }
        assert_eq!(parse_entity("1"), Ok(1));
        assert_eq!(parse_entity("65533"), Ok(0xFFFD));
        for text in ["0", "65534"] {
            let message = refused(parse_entity(text));
            assert!(
                message.contains("a DIS entity number") && message.contains("1..=65533"),
                "{message}"
            );
        }
        assert_eq!(parse_exercise("1"), Ok(1));
        assert_eq!(parse_exercise("255"), Ok(255));
        assert!(parse_exercise("0")
            .unwrap_err()
            .to_string()
            .contains("a DIS exercise id"));
        assert!(parse_exercise("256").is_err());
        assert_eq!(parse_version("6"), Ok(6));
        assert_eq!(parse_version("7"), Ok(7));
        for text in ["5", "8"] {
            let message = parse_version(text).unwrap_err().to_string();
            assert!(message.contains("a DIS version"), "{message}");
        }
    }

    /// A marking is kept as given when DIS can carry it (at most 11
    /// printable ASCII characters), refused otherwise, the text shown on
    /// one line.
    #[test]
    fn callsigns_are_kept_or_refused() {
        assert_eq!(parse_callsign("VIPER-1").as_deref(), Ok("VIPER-1"));
        assert_eq!(parse_callsign("ABCDEFGHIJK").as_deref(), Ok("ABCDEFGHIJK"));
        for text in ["ABCDEFGHIJKL", "CAFÉ", "TAB\tBED"] {
            let Err(ValueError::NotMarking { text: shown }) = parse_callsign(text) else {
                panic!("{text:?} accepted");
            };
            assert!(!shown.contains('\t'), "{shown}");
        }
    }

    /// A DIS target is the first address its text names; port 0 and the
    /// unspecified address name no receiver and are refused, by kind.
    #[test]
    fn targets_need_a_port_and_a_host() {
        assert_eq!(
            resolve_target("127.0.0.1:3000"),
            Ok("127.0.0.1:3000".parse().unwrap())
        );
        assert_eq!(
            resolve_target("[::1]:3000"),
            Ok("[::1]:3000".parse().unwrap())
        );
        assert!(resolve_target("255.255.255.255:3000").is_ok());
        assert!(matches!(
            resolve_target("127.0.0.1:0"),
            Err(DisTargetError::PortZero { .. })
        ));
        assert!(matches!(
            resolve_target("0.0.0.0:3000"),
            Err(DisTargetError::Unspecified { .. })
        ));
        assert!(matches!(
            resolve_target("[::]:3000"),
            Err(DisTargetError::Unspecified { .. })
        ));
        assert!(matches!(
            resolve_target("127.0.0.1"),
            Err(DisTargetError::NotAnAddress { .. })
        ));
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

    /// The registry's entity types are the ones docs/dis.md documents.
    #[test]
    fn entity_types_are_the_documented_ones() {
        assert_eq!(
            entity_type_label(<Palmer as RunModel>::DIS_KIND),
            "1.2.225.85.11.1.0"
        );
        assert_eq!(
            entity_type_label(<Bourg as RunModel>::DIS_KIND),
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
        let mut tracker = settings("127.0.0.1:3000".parse().unwrap(), false)
            .tracker::<Palmer>(EntityIdentity::new(1, 1, 1).unwrap(), "T")
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

    /// Receives every datagram waiting on `socket` (it has a short read
    /// timeout) into `listener`; returns how many.
    fn drain(socket: &UdpSocket, listener: &mut Listener) -> usize {
        let mut buf = [0u8; 2048];
        let mut n = 0;
        while let Ok(len) = socket.recv(&mut buf) {
            listener.ingest(&buf[..len]).unwrap();
            n += 1;
        }
        n
    }

    /// A run with a [`DisOutput`] attached sends, over a real UDP socket,
    /// the PDUs a [`Tracker`] fed the same views makes: the same count,
    /// decoded by fdm-dis's listener (the interop approach of
    /// `fdm-dis/tests/listener.rs`, proven against Open-DIS there) to the
    /// aircraft's entity id, marking, type and last position. With every
    /// frame due, 60 frames are 60 PDUs of 144 bytes; the decoded latitude
    /// and longitude of the last are the last frame's placement to 1e-7°
    /// (the PDU carries ECEF in `f64`: the round trip is good to nanometres)
    /// and the height to 1 mm.
    #[test]
    fn the_output_sends_what_a_tracker_makes_and_a_listener_decodes_it() {
        let socket = UdpSocket::bind("127.0.0.1:0").unwrap();
        socket
            .set_read_timeout(Some(Duration::from_millis(200)))
            .unwrap();
        let target = socket.local_addr().unwrap();
        let config = FlightDis {
            settings: settings(target, true),
            entity: 7,
            callsign: None,
        };
        let script = Script::parse("1-20 throttle-up\n1-5 alpha-up\n").unwrap();
        let scenario = Scenario::<Palmer>::new(Start::thesis(), 30, 60)
            .unwrap()
            .with_script(script);
        let origin = scenario.origin;
        let mut run = Run::new(scenario).unwrap();
        let dis = SharedOutput::new(DisOutput::open::<Palmer>(&config, origin, 30).unwrap());
        run.attach(dis.clone()).unwrap();
        // The same views through a tracker of the same configuration.
        let mut tracker = config
            .settings
            .tracker::<Palmer>(EntityIdentity::new(1, 1, 7).unwrap(), "C172-7")
            .unwrap();
        let placement = Placement::new(origin);
        let mut due = 0;
        let mut last = None;
        let mut listener = Listener::new();
        let mut received = 0;
        for _ in 0..60 {
            run.step_frame(&[]).unwrap();
            let view = run.view();
            if tracker.update(&view, &placement).unwrap().is_some() {
                due += 1;
            }
            last = Some(fgnet::bridge::display(&view, &origin).geodetic);
            received += drain(&socket, &mut listener);
        }
        run.finish().unwrap();
        received += drain(&socket, &mut listener);
        let report = dis.with(|o| o.map(|o| o.report())).unwrap();
        assert_eq!(due, 60);
        assert_eq!((report.pdus, report.bytes), (60, 60 * 144));
        assert_eq!((report.frames, report.entities), (60, 1));
        assert_eq!(report.first_entity, "1:1:7");
        assert_eq!(report.reasons.first, 1);
        assert_eq!(received, 60);
        assert_eq!(listener.entity_count(), 1);
        let record = listener.entities().next().unwrap();
        assert_eq!(record.id.to_string(), "1:1:7");
        assert_eq!(record.marking, "C172-7");
        assert_eq!(
            record.entity_type,
            AircraftKind::CESSNA_172_SKYHAWK.entity_type()
        );
        let last = last.unwrap();
        assert!((record.position.lat_deg - last.lat_deg).abs() < 1e-7);
        assert!((record.position.lon_deg - last.lon_deg).abs() < 1e-7);
        assert!((record.position.alt_m - last.alt_m).abs() < 1e-3);
        assert!(dis.with(|o| o.and_then(DisOutput::take_failure)).is_none());
    }

    /// A reset is not a frame: nothing is sent for it, and the first frame
    /// after it is sent as a first PDU again (the model's clock went back
    /// behind the last PDU's; every frame is due here, so the last PDU is the
    /// last frame's).
    #[test]
    fn a_reset_sends_nothing_and_restarts_the_entity() {
        let socket = UdpSocket::bind("127.0.0.1:0").unwrap();
        let config = FlightDis {
            settings: settings(socket.local_addr().unwrap(), true),
            entity: 1,
            callsign: Some("ONE".to_owned()),
        };
        let scenario = Scenario::<Bourg>::new(Start::thesis(), 30, 0).unwrap();
        let origin = scenario.origin;
        let mut run = Run::new(scenario).unwrap();
        let dis = SharedOutput::new(DisOutput::open::<Bourg>(&config, origin, 30).unwrap());
        run.attach(dis.clone()).unwrap();
        let report = || dis.with(|o| o.map(|o| o.report())).unwrap();
        assert_eq!(report().frames, 0);
        run.step_frame(&[]).unwrap();
        run.step_frame(&[]).unwrap();
        run.reset().unwrap();
        let counts = || {
            let r = report();
            (r.frames, r.pdus, r.reasons.first, r.reasons.heartbeat)
        };
        assert_eq!(counts(), (2, 2, 1, 1));
        run.step_frame(&[]).unwrap();
        assert_eq!(counts(), (3, 3, 2, 1));
        assert_eq!(report().dr_algorithm, "DRM(R,V,W)");
    }

    /// The report's rates are per simulated second (frames over the frame
    /// rate), none for a run of no frame; the protocol version is the one
    /// written; the summary line says what was sent, where and why.
    #[test]
    fn the_report_gives_rates_per_simulated_second_and_a_summary() {
        let socket = UdpSocket::bind("127.0.0.1:0").unwrap();
        let target = socket.local_addr().unwrap();
        for (version, every_frame) in [(DisVersion::V7, true), (DisVersion::V6, false)] {
            let config = FlightDis {
                settings: DisSettings {
                    version,
                    ..settings(target, every_frame)
                },
                entity: 3,
                callsign: None,
            };
            let scenario = Scenario::<Palmer>::new(Start::thesis(), 20, 50).unwrap();
            let origin = scenario.origin;
            let mut run = Run::new(scenario).unwrap();
            let dis = SharedOutput::new(DisOutput::open::<Palmer>(&config, origin, 20).unwrap());
            run.attach(dis.clone()).unwrap();
            let report = || dis.with(|o| o.map(|o| o.report())).unwrap();
            let none = report();
            assert_eq!((none.frames, none.sim_seconds), (0, 0.0));
            assert_eq!((none.pdus_per_sim_s, none.bytes_per_sim_s), (None, None));
            run.run_to_end().unwrap();
            let r = report();
            assert_eq!(r.protocol_version, if every_frame { 7 } else { 6 });
            assert_eq!((r.frames, r.sim_seconds), (50, 2.5));
            #[allow(clippy::cast_precision_loss)] // small counts
            let (pdus, bytes) = (r.pdus as f64, r.bytes as f64);
            assert_eq!(r.pdus_per_sim_s, Some(pdus / 2.5));
            assert_eq!(r.bytes_per_sim_s, Some(bytes / 2.5));
            let reasons = &r.reasons;
            assert_eq!(
                reasons.first + reasons.position + reasons.orientation + reasons.heartbeat,
                r.pdus
            );
            let when = if every_frame {
                "every frame".to_owned()
            } else {
                r.dr_algorithm.clone()
            };
            assert_eq!(
                r.summary(),
                format!(
                    "dis  {} PDUs ({} bytes) to {target} for 1 entity, 0 failed; {when} \
                     (first 1, position {}, orientation {}, heartbeat {})",
                    r.pdus, r.bytes, reasons.position, reasons.orientation, reasons.heartbeat
                )
            );
            if every_frame {
                assert_eq!((r.pdus, r.bytes), (50, 50 * 144));
            } else {
                assert!(r.pdus < 50, "{}", r.pdus);
            }
        }
    }
}
