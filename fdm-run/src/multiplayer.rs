//! FlightGear multiplayer for a fleet (`sim-cli fleet --fg-mp`,
//! docs/fleet-in-flightgear.md): FlightGear's native-FDM input shows one
//! aircraft, its multiplayer input one `/ai/models/multiplayer[i]` per
//! callsign.
//!
//! * [`MultiplayerFleet`]: aircraft of one model spawned as full entities of
//!   one ECS world (so the Place system computes each one's geodetic
//!   position and attitude every frame), flying one script together;
//!   [`MultiplayerFleet::messages`] makes the position message of each of the
//!   first aircraft ([`fgnet::bridge::multiplayer_position`]: ECEF position
//!   from the placement, orientation from the attitude, body velocity from
//!   the model's view), callsign [`callsign`]`(i)`.
//! * [`MultiplayerSender`]: one UDP socket sending the messages to one
//!   FlightGear, counting sends and failures in a [`LinkStats`] and keeping
//!   the first failure; a failed send never stops the fleet.
//!
//! Errors are typed ([`MultiplayerError`]). Where the aircraft start (the
//! CLI's `--pattern`) and which FlightGear model draws them are the
//! caller's.

use std::io;
use std::net::{SocketAddr, UdpSocket};
use std::sync::Arc;

use fdm_core::geodesy::GeodeticOrigin;
use fdm_core::model::Model;
use fdm_core::script::{Script, ScriptCursor};
use fdm_ecs::{EcsError, Entity, Resources, Simulation};
use fgnet::bridge::{multiplayer_position, MultiplayerIdentity};
use fgnet::{MpEncodeError, MultiplayerPosition, NameError, MP_POSITION_LEN};

use crate::output::LinkStats;

/// Why a multiplayer fleet could not be flown or streamed.
#[derive(Debug, thiserror::Error)]
pub enum MultiplayerError {
    /// The frame rate is not valid for the ECS.
    #[error(transparent)]
    Ecs(#[from] EcsError),
    /// A fleet aircraft has no placement or view (not one of the fleet's
    /// entities of its model; not in practice).
    #[error("a fleet aircraft has no {0}")]
    NotPlaced(&'static str),
    /// The callsign or model path does not fit the message.
    #[error(transparent)]
    Name(#[from] NameError),
    /// The message could not be encoded (the cause is the error's source).
    #[error("encoding a multiplayer message")]
    Encode(#[from] MpEncodeError),
    /// The UDP socket could not be opened (the cause is the error's source).
    #[error("opening the multiplayer socket")]
    Socket(#[source] io::Error),
}

/// The callsign of fleet aircraft `index` (0-based): `SIM001`, `SIM002`, ...
/// (FlightGear takes 1 to 7 characters; 1000 aircraft end at `SIM1000`).
#[must_use]
pub fn callsign(index: usize) -> String {
    format!("SIM{:03}", index + 1)
}

/// Aircraft of model `M`, all full entities of one ECS world (placed every
/// frame), flying one script together.
#[derive(Debug)]
pub struct MultiplayerFleet<M: Model> {
    sim: Simulation,
    entities: Vec<Entity>,
    script: Script<M::Action>,
    cursor: ScriptCursor,
    fps: u32,
}

impl<M: Model> MultiplayerFleet<M> {
    /// One aircraft per start `(controls, state)` (sharing `aircraft`), in
    /// order, at `fps` frames per second with the model frame at `origin`,
    /// to fly `script`.
    ///
    /// # Errors
    /// [`MultiplayerError::Ecs`] for a frame rate of 0.
    pub fn new(
        aircraft: M::Aircraft,
        starts: impl IntoIterator<Item = (M::Controls, M::State)>,
        fps: u32,
        origin: GeodeticOrigin,
        script: Script<M::Action>,
    ) -> Result<Self, MultiplayerError> {
        let resources = Resources::new(f64::from(fps))?.with_origin(origin);
        let mut sim = Simulation::new(resources);
        let aircraft = Arc::new(aircraft);
        let entities = starts
            .into_iter()
            .map(|(controls, state)| sim.spawn::<M>(Arc::clone(&aircraft), controls, state))
            .collect();
        Ok(Self {
            sim,
            entities,
            script,
            cursor: ScriptCursor::new(),
            fps,
        })
    }

    /// The simulation.
    #[must_use]
    pub fn simulation(&self) -> &Simulation {
        &self.sim
    }

    /// The aircraft, in start order.
    #[must_use]
    pub fn entities(&self) -> &[Entity] {
        &self.entities
    }

    /// Flies one frame: the script's actions for it on every aircraft, then
    /// the schedule.
    ///
    /// # Errors
    /// An aircraft lost its input queue (not in practice).
    pub fn step(&mut self) -> Result<(), MultiplayerError> {
        let frame = self.sim.frame() + 1;
        let actions: Vec<M::Action> = self.cursor.actions(&self.script, frame).collect();
        for &entity in &self.entities {
            for &action in &actions {
                self.sim.push_input(entity, action)?;
            }
        }
        self.sim.run_frame();
        Ok(())
    }

    /// The message of one aircraft now: position and attitude as Place
    /// computed them for the last frame, body velocity from the model's view;
    /// the time is the fleet's clock, the lag one frame.
    ///
    /// # Errors
    /// [`MultiplayerError::NotPlaced`] for an entity that is not an aircraft
    /// of the fleet; [`MultiplayerError::Name`] for a callsign or model path
    /// that does not fit.
    pub fn message(
        &self,
        entity: Entity,
        callsign: &str,
        model_path: &str,
    ) -> Result<MultiplayerPosition, MultiplayerError> {
        let geodetic = self
            .sim
            .geodetic(entity)
            .ok_or(MultiplayerError::NotPlaced("geodetic position"))?;
        let attitude = self
            .sim
            .attitude(entity)
            .ok_or(MultiplayerError::NotPlaced("attitude"))?;
        let view = self
            .sim
            .view::<M>(entity)
            .ok_or(MultiplayerError::NotPlaced("view of its model"))?;
        let who = MultiplayerIdentity {
            callsign,
            model_path,
        };
        #[allow(clippy::cast_precision_loss)] // frame counts below 2^53
        let time_s = self.sim.frame() as f64 / f64::from(self.fps);
        let timing = (time_s, 1.0 / f64::from(self.fps));
        Ok(multiplayer_position(
            who, timing, geodetic, attitude, &view,
        )?)
    }

    /// The messages of the first `count` aircraft now, callsigns
    /// [`callsign`]`(0)`, `(1)`, ..., drawn as `model_path` (e.g.
    /// `Aircraft/c172p/Models/c172p.xml`).
    ///
    /// # Errors
    /// As [`Self::message`].
    pub fn messages(
        &self,
        count: usize,
        model_path: &str,
    ) -> Result<Vec<MultiplayerPosition>, MultiplayerError> {
        self.entities
            .iter()
            .take(count)
            .enumerate()
            .map(|(i, &e)| self.message(e, &callsign(i), model_path))
            .collect()
    }
}

/// One UDP socket sending multiplayer messages to one FlightGear, counting
/// sends and failures; the first failure's error is kept.
#[derive(Debug)]
pub struct MultiplayerSender {
    socket: UdpSocket,
    target: SocketAddr,
    buffer: Vec<u8>,
    stats: LinkStats,
    first_failure: Option<io::Error>,
}

impl MultiplayerSender {
    /// A socket on an ephemeral local port sending to `target`.
    ///
    /// # Errors
    /// [`MultiplayerError::Socket`] when the socket cannot be opened.
    pub fn open(target: SocketAddr) -> Result<Self, MultiplayerError> {
        let socket = UdpSocket::bind("0.0.0.0:0").map_err(MultiplayerError::Socket)?;
        Ok(Self {
            socket,
            target,
            buffer: vec![0_u8; MP_POSITION_LEN],
            stats: LinkStats::default(),
            first_failure: None,
        })
    }

    /// Encodes and sends `msg`; a failed send is counted (the first kept),
    /// never an error.
    ///
    /// # Errors
    /// [`MultiplayerError::Encode`] when the message cannot be encoded.
    pub fn send(&mut self, msg: &MultiplayerPosition) -> Result<(), MultiplayerError> {
        let len = msg.encode_into(&mut self.buffer)?;
        match self.socket.send_to(&self.buffer[..len], self.target) {
            Ok(_) => self.stats.sent += 1,
            Err(e) => {
                self.stats.failed += 1;
                self.first_failure.get_or_insert(e);
            }
        }
        Ok(())
    }

    /// Datagrams sent and failed so far.
    #[must_use]
    pub const fn stats(&self) -> LinkStats {
        self.stats
    }

    /// The error of the first failed send, once.
    pub fn take_failure(&mut self) -> Option<io::Error> {
        self.first_failure.take()
    }

    /// Where the messages go.
    #[must_use]
    pub const fn target(&self) -> SocketAddr {
        self.target
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use fdm_core::palmer::Palmer;

    fn fleet(n: usize) -> MultiplayerFleet<Palmer> {
        MultiplayerFleet::new(
            Palmer::default_aircraft(),
            (0..n).map(Palmer::fleet_member),
            30,
            GeodeticOrigin::default(),
            Script::default(),
        )
        .unwrap()
    }

    /// Messages carry the callsigns in order and the fleet's clock; a name
    /// that does not fit is a typed error, not a panic.
    #[test]
    fn messages_name_the_aircraft_and_bad_names_are_errors() {
        let mut fleet = fleet(3);
        for _ in 0..15 {
            fleet.step().unwrap();
        }
        let msgs = fleet.messages(5, "Aircraft/ufo/Models/ufo.xml").unwrap();
        let names: Vec<_> = msgs.iter().map(|m| m.callsign.as_str()).collect();
        assert_eq!(names, ["SIM001", "SIM002", "SIM003"]);
        assert_eq!((msgs[0].time_s, msgs[0].lag_s), (0.5, 1.0 / 30.0));
        let e = fleet.entities()[0];
        assert!(matches!(
            fleet.message(e, "", "Aircraft/ufo/Models/ufo.xml"),
            Err(MultiplayerError::Name(_))
        ));
        assert!(matches!(
            MultiplayerFleet::<Palmer>::new(
                Palmer::default_aircraft(),
                [],
                0,
                GeodeticOrigin::default(),
                Script::default()
            ),
            Err(MultiplayerError::Ecs(_))
        ));
    }

    /// Every send is counted: to a receiver all are sent; to an address the
    /// IPv4 socket cannot reach (an IPv6 one) each fails, the first failure
    /// is kept once, and sending goes on.
    #[test]
    fn sends_and_failures_are_counted_and_the_first_failure_kept_once() {
        let fleet = fleet(1);
        let msg = &fleet.messages(1, "Aircraft/ufo/Models/ufo.xml").unwrap()[0];
        let rx = UdpSocket::bind("127.0.0.1:0").unwrap();
        let mut sender = MultiplayerSender::open(rx.local_addr().unwrap()).unwrap();
        for _ in 0..5 {
            sender.send(msg).unwrap();
        }
        assert_eq!(sender.stats(), LinkStats { sent: 5, failed: 0 });
        assert!(sender.take_failure().is_none());
        let mut buf = [0_u8; 2048];
        let n = rx.recv(&mut buf).unwrap();
        assert_eq!(MultiplayerPosition::decode(&buf[..n]).unwrap(), *msg);

        let v6 = SocketAddr::from((std::net::Ipv6Addr::LOCALHOST, 5000));
        let mut sender = MultiplayerSender::open(v6).unwrap();
        for _ in 0..3 {
            sender.send(msg).unwrap();
        }
        assert_eq!(sender.stats(), LinkStats { sent: 0, failed: 3 });
        assert!(sender.take_failure().is_some());
        assert!(sender.take_failure().is_none());
        assert_eq!(sender.target(), v6);
    }
}
