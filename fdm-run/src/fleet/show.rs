//! A fleet to watch in FlightGear (`sim-cli fleet --fg-mp HOST:PORT
//! --realtime`, docs/fleet-in-flightgear.md): a [`ShowScenario`] becomes a
//! [`FleetShow`], driven frame by frame or to the end.
//!
//! The fleet is a [`MultiplayerFleet`] (each aircraft a full entity of one ECS
//! world, placed every frame) flying one script together; after every frame
//! the first [`ShowScenario::streamed`] aircraft are sent to FlightGear as
//! multiplayer position messages through a [`MultiplayerSender`] (callsign
//! [`callsign`](crate::multiplayer::callsign)`(i)`, model [`FleetModel::FG_MP_MODEL`]), and the frame is
//! paced at 1/fps s of wall-clock time.
//!
//! Where the aircraft start is a [`StartPattern`] ([`start_of`]): the models'
//! demonstration fleet, pairs along a runway ahead of the viewer (a formation
//! take-off for Palmer's Cessnas with
//! `examples/scripts/palmer_climb_turn.txt`), or a V.

use std::io;
use std::net::SocketAddr;
use std::time::Instant;

use fdm_core::geodesy::GeodeticOrigin;
use fdm_core::script::Script;
use serde::Serialize;

use super::FleetError;
use crate::model::FleetModel;
use crate::multiplayer::{MultiplayerError, MultiplayerFleet, MultiplayerSender};
use crate::pacer::FramePacer;

/// Aircraft streamed when the caller does not say.
pub const DEFAULT_MP_AIRCRAFT: usize = 16;

/// Largest fleet a show flies (every aircraft is a full entity stepped in
/// real time on one thread).
pub const MAX_WATCHED_FLEET: usize = 10_000;

/// Rows pattern: metres between the two aircraft of a row (10 m either side of
/// the runway's centre line).
pub const ROW_SPAN_M: f64 = 20.0;
/// Rows pattern: metres from one row to the next, northwards.
pub const ROW_SPACING_M: f64 = 50.0;
/// V pattern: metres back and out per place in the V.
pub const V_STEP_M: f64 = 30.0;
/// Rows and V patterns: metres north of the model's start where the first
/// aircraft starts, leaving the start itself to the viewer's own aircraft
/// (`sim-cli fgfs-command` puts FlightGear's aircraft there), whose chase
/// view then looks north at the fleet.
pub const PATTERN_AHEAD_M: f64 = 50.0;

/// Where a watched fleet's aircraft start.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum StartPattern {
    /// Each model's demonstration fleet
    /// ([`Model::fleet_member`](fdm_core::model::Model::fleet_member)): distinct
    /// flying states.
    #[default]
    Demo,
    /// Pairs abreast ([`ROW_SPAN_M`]) in rows [`ROW_SPACING_M`] apart
    /// northwards, from [`PATTERN_AHEAD_M`] north of the model's start.
    Rows,
    /// A V: a leader [`PATTERN_AHEAD_M`] north of the model's start, then
    /// [`V_STEP_M`] back and out per place, left then right.
    V,
}

/// Controls and state of aircraft `index` of a fleet of model `M` started in
/// `pattern`.
#[must_use]
pub fn start_of<M: FleetModel>(pattern: StartPattern, index: usize) -> (M::Controls, M::State) {
    let (controls, state) = (M::initial_controls(), M::initial_state());
    #[allow(clippy::cast_precision_loss)] // indices up to 10 million
    let i = index as f64;
    match pattern {
        StartPattern::Demo => M::fleet_member(index),
        StartPattern::Rows => {
            let row = (i / 2.0).floor();
            // Even indices on the left (west, +y), odd on the right.
            let west = if index.is_multiple_of(2) { 0.5 } else { -0.5 } * ROW_SPAN_M;
            (
                controls,
                M::offset_state(&state, PATTERN_AHEAD_M + row * ROW_SPACING_M, west, 0.0),
            )
        }
        StartPattern::V => {
            let place = ((i + 1.0) / 2.0).floor();
            let side = if index.is_multiple_of(2) { -1.0 } else { 1.0 };
            (
                controls,
                M::offset_state(
                    &state,
                    PATTERN_AHEAD_M - place * V_STEP_M,
                    side * place * V_STEP_M,
                    0.0,
                ),
            )
        }
    }
}

/// `n` aircraft of model `M` in `pattern` around `origin`, to fly `script`
/// at `fps` frames per second.
///
/// # Errors
/// [`MultiplayerError::Ecs`] for a frame rate the ECS refuses.
pub fn multiplayer_fleet<M: FleetModel>(
    n: usize,
    pattern: StartPattern,
    origin: GeodeticOrigin,
    script: Script<M::Action>,
    fps: u32,
) -> Result<MultiplayerFleet<M>, MultiplayerError> {
    let starts = (0..n).map(|i| start_of::<M>(pattern, i));
    MultiplayerFleet::new(M::default_aircraft(), starts, fps, origin, script)
}

/// What a watched fleet flies.
#[derive(Debug, Clone, PartialEq)]
pub struct ShowScenario<A> {
    /// Aircraft flown (at most [`MAX_WATCHED_FLEET`]).
    pub aircraft: u64,
    /// Aircraft streamed to FlightGear: the first this many (at most
    /// `aircraft`).
    pub streamed: usize,
    /// Where they start.
    pub pattern: StartPattern,
    /// Where the fleet's earth frame is on WGS-84.
    pub origin: GeodeticOrigin,
    /// The actions every aircraft flies.
    pub script: Script<A>,
    /// Frames [`FleetShow::run_to_end`] flies.
    pub frames: u64,
    /// Frames per second (wall-clock pace).
    pub fps: u32,
}

/// `aircraft` as a watched fleet's size (checked again by
/// [`FleetShow::new`]; callers that load a script first check it before).
///
/// # Errors
/// [`FleetError::TooManyToWatch`] above [`MAX_WATCHED_FLEET`].
pub fn watched_size(aircraft: u64) -> Result<usize, FleetError> {
    usize::try_from(aircraft)
        .ok()
        .filter(|&n| n <= MAX_WATCHED_FLEET)
        .ok_or(FleetError::TooManyToWatch {
            aircraft,
            max: MAX_WATCHED_FLEET,
        })
}

/// What a watched fleet did (`sim-cli fleet --fg-mp --json`).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ShowReport {
    /// The model's name, e.g. `"palmer"`.
    pub model: &'static str,
    /// Aircraft flown.
    pub aircraft: u64,
    /// Aircraft streamed to FlightGear.
    pub streamed: usize,
    /// Frames flown.
    pub frames: u64,
    /// Datagrams sent (handed to the OS).
    pub sent: u64,
    /// Datagrams whose send failed.
    pub failed: u64,
    /// Frames that missed their real-time deadline.
    pub overruns: u64,
}

impl ShowReport {
    /// The human-readable summary (`sim-cli fleet --fg-mp` without
    /// `--json`): one line, the fleet streamed to `target` with the
    /// multiplayer callsigns it used.
    #[must_use]
    pub fn summary(&self, target: SocketAddr) -> String {
        format!(
            "{} fleet: {} aircraft, {} streamed to {target} as multiplayer aircraft SIM001..{}, \
             {} frames, {} datagrams sent, {} failed, {} overruns",
            self.model,
            self.aircraft,
            self.streamed,
            crate::multiplayer::callsign(self.streamed.saturating_sub(1)),
            self.frames,
            self.sent,
            self.failed,
            self.overruns
        )
    }
}

/// A watched fleet of model `M` flying and streaming.
#[derive(Debug)]
pub struct FleetShow<M: FleetModel> {
    fleet: MultiplayerFleet<M>,
    sender: MultiplayerSender,
    pacer: FramePacer,
    aircraft: u64,
    streamed: usize,
    frames: u64,
    flown: u64,
}

impl<M: FleetModel> FleetShow<M> {
    /// Spawns the fleet and opens the socket to FlightGear at `target`; the
    /// real-time clock starts now.
    ///
    /// # Errors
    /// [`FleetError::TooManyToWatch`], or [`FleetError::Multiplayer`] for a
    /// frame rate of 0 or a socket that cannot be opened.
    pub fn new(scenario: ShowScenario<M::Action>, target: SocketAddr) -> Result<Self, FleetError> {
        let n = watched_size(scenario.aircraft)?;
        let streamed = scenario.streamed.min(n);
        let fleet = multiplayer_fleet::<M>(
            n,
            scenario.pattern,
            scenario.origin,
            scenario.script,
            scenario.fps,
        )?;
        let sender = MultiplayerSender::open(target)?;
        let pacer = FramePacer::new(FramePacer::period_for(scenario.fps), Instant::now());
        Ok(Self {
            fleet,
            sender,
            pacer,
            aircraft: scenario.aircraft,
            streamed,
            frames: scenario.frames,
            flown: 0,
        })
    }

    /// Flies one frame, sends the streamed aircraft's messages and waits for
    /// the frame's end.
    ///
    /// # Errors
    /// [`FleetError::Multiplayer`] when a message cannot be made (a failed
    /// send is counted, never an error).
    pub fn step_frame(&mut self) -> Result<(), FleetError> {
        self.fleet.step()?;
        for msg in self.fleet.messages(self.streamed, M::FG_MP_MODEL)? {
            self.sender.send(&msg)?;
        }
        self.flown += 1;
        self.pacer.pace();
        Ok(())
    }

    /// Flies the frames left of [`ShowScenario::frames`].
    ///
    /// # Errors
    /// As [`Self::step_frame`].
    pub fn run_to_end(&mut self) -> Result<(), FleetError> {
        while self.flown < self.frames {
            self.step_frame()?;
        }
        Ok(())
    }

    /// The fleet.
    #[must_use]
    pub fn fleet(&self) -> &MultiplayerFleet<M> {
        &self.fleet
    }

    /// The error of the first failed send, once.
    pub fn take_failure(&mut self) -> Option<io::Error> {
        self.sender.take_failure()
    }

    /// What the show did so far.
    #[must_use]
    pub fn report(&self) -> ShowReport {
        let stats = self.sender.stats();
        ShowReport {
            model: M::NAME,
            aircraft: self.aircraft,
            streamed: self.streamed,
            frames: self.flown,
            sent: stats.sent,
            failed: stats.failed,
            overruns: self.pacer.overruns(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::multiplayer::callsign;
    use fdm_core::bourg::Bourg;
    use fdm_core::model::Model;
    use fdm_core::palmer::Palmer;
    use fgnet::MultiplayerPosition;

    #[test]
    fn callsigns_fit_flightgear() {
        assert_eq!(callsign(0), "SIM001");
        assert_eq!(callsign(999), "SIM1000");
        for i in [0, 15, 999] {
            assert!(MultiplayerPosition::new(&callsign(i), Palmer::FG_MP_MODEL).is_ok());
            assert!(MultiplayerPosition::new(&callsign(i), Bourg::FG_MP_MODEL).is_ok());
        }
    }

    #[test]
    fn patterns_place_aircraft_as_documented() {
        let p = |pattern, i| start_of::<Palmer>(pattern, i).1.position_m;
        // Rows: pairs 20 m abreast, rows 50 m apart from 50 m north of the start.
        let xyz = |pattern, i| <[f64; 3]>::from(p(pattern, i));
        assert_eq!(xyz(StartPattern::Rows, 0), [50.0, 10.0, 0.0]);
        assert_eq!(xyz(StartPattern::Rows, 1), [50.0, -10.0, 0.0]);
        assert_eq!(xyz(StartPattern::Rows, 5), [150.0, -10.0, 0.0]);
        // V: leader 50 m north of the start, then 30 m back and out per place, left then right.
        assert_eq!(xyz(StartPattern::V, 0), [50.0, 0.0, 0.0]);
        assert_eq!(xyz(StartPattern::V, 1), [20.0, 30.0, 0.0]);
        assert_eq!(xyz(StartPattern::V, 2), [20.0, -30.0, 0.0]);
        assert_eq!(xyz(StartPattern::V, 3), [-10.0, 60.0, 0.0]);
        assert_eq!(
            start_of::<Palmer>(StartPattern::Demo, 7),
            Palmer::fleet_member(7)
        );
        // Bourg in feet, f32: 20 m north and 30 m west of its start.
        let b = start_of::<Bourg>(StartPattern::V, 1).1.position_ft;
        assert_eq!(b.x, -5000.0 + (20.0 / 0.3048) as f32);
        assert_eq!(b.y, (30.0 / 0.3048) as f32);
    }

    /// The messages carry what the simulation computed: position within
    /// 1e-6 degrees (tolerance: the ECEF round trip is exact to nanometres; the
    /// orientation goes through f32 on the wire, a few 1e-6 degrees).
    #[test]
    fn messages_carry_the_fleets_positions_and_attitudes() {
        // PHLI, Lihue (sim-cli's `--origin phli`).
        let origin = GeodeticOrigin::new(21.963792, -159.335883, 26.94).unwrap();
        let script = Script::parse("1-20 thrust-up\n1-60 pitch-up\n").unwrap();
        let mut show = multiplayer_fleet::<Bourg>(6, StartPattern::V, origin, script, 30).unwrap();
        for _ in 0..45 {
            show.step().unwrap();
        }
        let msgs = show.messages(4, Bourg::FG_MP_MODEL).unwrap();
        assert_eq!(msgs.len(), 4);
        for (i, msg) in msgs.iter().enumerate() {
            let e = show.entities()[i];
            let here = show.simulation().geodetic(e).unwrap();
            let att = show.simulation().attitude(e).unwrap();
            let bytes = msg.encode().unwrap();
            let back = MultiplayerPosition::decode(&bytes).unwrap();
            assert_eq!(back.callsign, callsign(i));
            assert_eq!(back.model_path, "Aircraft/ufo/Models/ufo.xml");
            let g = fdm_core::geodesy::ecef_to_geodetic(back.position_ecef_m.into());
            assert!((g.lat_deg - here.lat_deg).abs() < 1e-6, "{g:?} {here:?}");
            assert!((g.lon_deg - here.lon_deg).abs() < 1e-6, "{g:?} {here:?}");
            assert!((g.alt_m - here.alt_m).abs() < 1e-6, "{g:?} {here:?}");
            let read = back.attitude(here.lat_deg, here.lon_deg);
            let d = |a: f64, b: f64| ((a - b + 540.0).rem_euclid(360.0) - 180.0).abs();
            assert!(
                d(read.heading_deg, att.heading_deg) < 1e-4,
                "{read:?} {att:?}"
            );
            assert!(d(read.pitch_deg, att.pitch_deg) < 1e-4, "{read:?} {att:?}");
            assert!(d(read.roll_deg, att.roll_deg) < 1e-4, "{read:?} {att:?}");
            assert!((back.time_s - 1.5).abs() < 1e-12);
        }
        // The V flies as one: same script, same dynamics, same offsets.
        let lead = show
            .simulation()
            .state::<Bourg>(show.entities()[0])
            .unwrap();
        let wing = show
            .simulation()
            .state::<Bourg>(show.entities()[1])
            .unwrap();
        assert_eq!(lead.velocity_ftps, wing.velocity_ftps);
    }

    /// A show too large to fly in real time is a typed error, before
    /// anything is spawned.
    #[test]
    fn shows_too_large_are_refused() {
        assert_eq!(watched_size(10_000).unwrap(), 10_000);
        assert!(matches!(
            watched_size(10_001),
            Err(FleetError::TooManyToWatch {
                aircraft: 10_001,
                max: MAX_WATCHED_FLEET
            })
        ));
    }
}
