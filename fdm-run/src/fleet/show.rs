//! A fleet to watch in FlightGear (`sim-cli fleet --fg-mp HOST:PORT
//! --realtime`, docs/fleet-in-flightgear.md): a [`ShowScenario`] becomes a
//! [`FleetShow`], driven frame by frame or to the end.
//!
//! The fleet is the model's structure-of-arrays kernel
//! ([`FleetModel::Lanes`]) on a rayon pool, so a show flies a fleet of any
//! size that fits in memory, every aircraft flying one script together.
//! FlightGear takes far fewer multiplayer aircraft than that: after every
//! frame only the first [`ShowScenario::streamed`] aircraft (at most
//! [`MAX_STREAMED`]) are placed on WGS-84 ([`Placement::of`], on the pool's
//! threads) and sent as multiplayer position messages through a
//! [`MultiplayerSender`] (callsign [`callsign`]`(i)`,
//! model [`FleetModel::FG_MP_MODEL`]); the rest fly unplaced. The frame is
//! then paced at 1/fps s of wall-clock time. In [`Precision::Exact`] the
//! messages are byte for byte those of the same aircraft as full ECS
//! entities ([`MultiplayerFleet`], [`multiplayer_fleet`]; tested).
//!
//! Where the aircraft start is a [`StartPattern`] ([`start_of`]): the models'
//! demonstration fleet, pairs along a runway ahead of the viewer (a formation
//! take-off for Palmer's Cessnas with
//! `examples/scripts/palmer_climb_turn.txt`), or a V.

use std::io;
use std::net::SocketAddr;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Instant;

use fdm_core::geodesy::GeodeticOrigin;
use fdm_core::model::{FlightStatus, FlightView};
use fdm_core::script::{Script, ScriptCursor};
use fdm_fleet::{LaneFleet, Precision};
use fgnet::bridge::{multiplayer_position, MultiplayerIdentity};
use fgnet::MultiplayerPosition;
use rayon::prelude::*;
use serde::Serialize;

use super::FleetError;
use crate::model::FleetModel;
use crate::multiplayer::{callsign, MultiplayerError, MultiplayerFleet, MultiplayerSender};
use crate::output::Placement;
use crate::pacer::FramePacer;

/// Aircraft streamed when the caller does not say.
pub const DEFAULT_MP_AIRCRAFT: usize = 16;

/// Most aircraft a show streams: FlightGear draws every multiplayer
/// aircraft it is sent as an AI model with its own property tree, and 1000
/// callsigns end at `SIM1000`, the longest that fits its 7 characters.
pub const MAX_STREAMED: usize = 1000;

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
    /// Aircraft flown (at least 1; as many as fit in memory).
    pub aircraft: u64,
    /// Aircraft streamed to FlightGear: the first this many (at most
    /// `aircraft` and [`MAX_STREAMED`]).
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
    /// Threads of the rayon pool flying the fleet and placing the streamed
    /// aircraft; `None`: one per available core.
    pub threads: Option<usize>,
    /// The kernel's precision ([`Precision::Exact`]: each aircraft as
    /// [`fdm_core::model::fly`] leaves it).
    pub precision: Precision,
}

/// `aircraft` as a watched fleet of model `M`'s size, if this machine can
/// hold it (checked again by [`FleetShow::new`]; callers that load a script
/// first check it before).
///
/// # Errors
/// [`FleetError::NoAircraft`] for 0, [`FleetError::TooMany`] above the
/// address space, [`FleetError::Memory`] for a fleet that does not fit in
/// the memory this process can allocate ([`crate::memory::check_fleet`]).
pub fn watched_size<M: FleetModel>(aircraft: u64) -> Result<usize, FleetError> {
    if aircraft == 0 {
        return Err(FleetError::NoAircraft);
    }
    let n = usize::try_from(aircraft).map_err(|_| FleetError::TooMany(aircraft))?;
    crate::memory::check_fleet(
        M::NAME,
        aircraft,
        M::Lanes::bytes_per_aircraft() as u64,
        crate::memory::available_bytes(),
    )?;
    Ok(n)
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
    /// Seconds spent flying the frames (the controls and the kernel).
    pub fly_seconds: f64,
    /// Seconds spent placing, encoding and sending the streamed aircraft.
    pub stream_seconds: f64,
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
pub struct FleetShow<M: FleetModel> {
    fleet: M::Lanes,
    precision: Precision,
    pool: rayon::ThreadPool,
    origin: GeodeticOrigin,
    script: Script<M::Action>,
    cursor: ScriptCursor,
    /// Whether the next frame's [`Model::begin_frame`] may change a
    /// control: true until a frame without actions changed none (then, with
    /// no actions, every later frame would leave them as they are).
    controls_may_change: bool,
    /// Each streamed aircraft's last placement and view whose numbers are
    /// all finite: what it is shown at once it diverges (`None`: never
    /// placed, not sent).
    shown: Vec<Option<(Placement, FlightView)>>,
    sender: MultiplayerSender,
    pacer: FramePacer,
    aircraft: u64,
    frames: u64,
    fps: u32,
    flown: u64,
    fly_seconds: f64,
    stream_seconds: f64,
}

impl<M: FleetModel> std::fmt::Debug for FleetShow<M> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("FleetShow")
            .field("model", &M::NAME)
            .field("aircraft", &self.aircraft)
            .field("streamed", &self.shown.len())
            .field("flown", &self.flown)
            .finish_non_exhaustive()
    }
}

impl<M: FleetModel> FleetShow<M> {
    /// Spawns the fleet, builds its thread pool and opens the socket to
    /// FlightGear at `target`; the real-time clock starts now.
    ///
    /// # Errors
    /// As [`watched_size`]; [`FleetError::Fps`] for a frame rate of 0,
    /// [`FleetError::NoThreads`], [`FleetError::ThreadPool`],
    /// [`FleetError::Precision`] for a precision the model's kernel has not,
    /// [`FleetError::Kernel`] for an aircraft it cannot fly, or
    /// [`FleetError::Multiplayer`] for a socket that cannot be opened.
    pub fn new(scenario: ShowScenario<M::Action>, target: SocketAddr) -> Result<Self, FleetError> {
        let n = watched_size::<M>(scenario.aircraft)?;
        // The ECS's check of the frame rate, as the ECS fleet had it.
        fdm_ecs::Resources::new(f64::from(scenario.fps))?;
        M::Lanes::check_precision(scenario.precision).map_err(FleetError::Precision)?;
        let pool = super::thread_pool(super::threads_or_cores(scenario.threads)?)?;
        let (pattern, origin) = (scenario.pattern, scenario.origin);
        let fleet = pool
            .install(|| {
                M::Lanes::from_starts(
                    M::default_aircraft(),
                    (0..n).map(|i| start_of::<M>(pattern, i)),
                )
            })
            .map_err(FleetError::Kernel)?;
        let streamed = scenario.streamed.min(n).min(MAX_STREAMED);
        let shown = (0..streamed)
            .map(|i| placed::<M>(&fleet, i, &origin))
            .collect();
        let sender = MultiplayerSender::open(target)?;
        let pacer = FramePacer::new(FramePacer::period_for(scenario.fps), Instant::now());
        Ok(Self {
            fleet,
            precision: scenario.precision,
            pool,
            origin,
            script: scenario.script,
            cursor: ScriptCursor::new(),
            controls_may_change: true,
            shown,
            sender,
            pacer,
            aircraft: scenario.aircraft,
            frames: scenario.frames,
            fps: scenario.fps,
            flown: 0,
            fly_seconds: 0.0,
            stream_seconds: 0.0,
        })
    }

    /// Flies one frame (the script's actions for it on every aircraft, then
    /// the kernel), sends the streamed aircraft's messages and waits for the
    /// frame's end.
    ///
    /// # Errors
    /// [`FleetError::Kernel`] if the kernel fails; [`FleetError::Multiplayer`]
    /// when a message cannot be made (a failed send is counted, never an
    /// error).
    pub fn step_frame(&mut self) -> Result<(), FleetError> {
        let start = Instant::now();
        self.fly()?;
        let flown = Instant::now();
        for msg in self.messages()? {
            self.sender.send(&msg)?;
        }
        self.fly_seconds += (flown - start).as_secs_f64();
        self.stream_seconds += flown.elapsed().as_secs_f64();
        self.pacer.pace();
        Ok(())
    }

    /// The frame's controls (as the ECS's FlightControl system sets them:
    /// [`Model::begin_frame`], then each action of the script's frame) and
    /// the frame itself, on the pool.
    fn fly(&mut self) -> Result<(), FleetError> {
        let frame = self.flown + 1;
        let actions: Vec<M::Action> = self.cursor.actions(&self.script, frame).collect();
        let fleet = &mut self.fleet;
        let (precision, fps) = (self.precision, f64::from(self.fps));
        if !actions.is_empty() || self.controls_may_change {
            let aircraft = fleet.aircraft().clone();
            let changed = AtomicBool::new(false);
            self.pool.install(|| {
                fleet.par_update_controls(|_, controls| {
                    let begun = M::begin_frame(controls);
                    if begun != controls {
                        changed.store(true, Ordering::Relaxed);
                    }
                    actions
                        .iter()
                        .fold(begun, |c, &action| M::apply(&aircraft, c, action))
                });
            });
            self.controls_may_change = !actions.is_empty() || changed.into_inner();
        }
        self.pool
            .install(|| fleet.par_fly(fps, precision))
            .map_err(FleetError::Kernel)?;
        self.flown = frame;
        Ok(())
    }

    /// The streamed aircraft's messages now (placed on the pool's threads),
    /// callsigns [`callsign`]`(0)`, `(1)`, ...: position and attitude from
    /// [`Placement::of`] the model's view, body velocity from the view; the
    /// time is the fleet's clock, the lag one frame. A diverged aircraft,
    /// or one whose placement is not finite, is shown where it last was (and
    /// not at all if it never had a finite placement: no message carries a
    /// NaN or an infinity).
    ///
    /// # Errors
    /// [`MultiplayerError::Name`] for the model's path if it does not fit the
    /// message.
    pub fn messages(&mut self) -> Result<Vec<MultiplayerPosition>, FleetError> {
        let (fleet, origin) = (&self.fleet, &self.origin);
        #[allow(clippy::cast_precision_loss)] // frame counts below 2^53
        let time_s = self.flown as f64 / f64::from(self.fps);
        let timing = (time_s, 1.0 / f64::from(self.fps));
        let shown = &mut self.shown;
        let messages = self.pool.install(|| {
            shown
                .par_iter_mut()
                .enumerate()
                .filter_map(|(i, last)| {
                    if let Some(now) = placed::<M>(fleet, i, origin) {
                        *last = Some(now);
                    }
                    let (placement, view) = last.as_ref()?;
                    let who = MultiplayerIdentity {
                        callsign: &callsign(i),
                        model_path: M::FG_MP_MODEL,
                    };
                    Some(multiplayer_position(
                        who,
                        timing,
                        placement.geodetic,
                        placement.attitude,
                        view,
                    ))
                })
                .collect::<Result<Vec<_>, _>>()
        });
        Ok(messages.map_err(MultiplayerError::Name)?)
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
    pub fn fleet(&self) -> &M::Lanes {
        &self.fleet
    }

    /// Frames flown so far.
    #[must_use]
    pub fn flown(&self) -> u64 {
        self.flown
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
            streamed: self.shown.len(),
            frames: self.flown,
            sent: stats.sent,
            failed: stats.failed,
            overruns: self.pacer.overruns(),
            fly_seconds: self.fly_seconds,
            stream_seconds: self.stream_seconds,
        }
    }
}

/// Aircraft `index`'s placement and view now, `None` when it has diverged
/// or any of their numbers is not finite (the rule of the ECS's Place
/// system, `fdm_ecs::systems::place`).
fn placed<M: FleetModel>(
    fleet: &M::Lanes,
    index: usize,
    origin: &GeodeticOrigin,
) -> Option<(Placement, FlightView)> {
    if fleet.status(index)? == FlightStatus::Diverged {
        return None;
    }
    let view = M::view(
        fleet.aircraft(),
        &fleet.controls(index)?,
        &fleet.state(index)?,
    );
    Some((Placement::of_finite(&view, origin)?, view))
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

    /// A loopback socket for a show to send to.
    fn receiver() -> (std::net::UdpSocket, SocketAddr) {
        let socket = std::net::UdpSocket::bind("127.0.0.1:0").unwrap();
        let addr = socket.local_addr().unwrap();
        (socket, addr)
    }

    fn scenario<M: FleetModel>(
        aircraft: u64,
        streamed: usize,
        pattern: StartPattern,
        script: &str,
    ) -> ShowScenario<M::Action> {
        ShowScenario {
            aircraft,
            streamed,
            pattern,
            // PHLI, Lihue (sim-cli's `--origin phli`).
            origin: GeodeticOrigin::new(21.963792, -159.335883, 26.94).unwrap(),
            script: Script::parse(script).unwrap(),
            frames: 90,
            fps: 30,
            threads: Some(2),
            precision: Precision::Exact,
        }
    }

    /// The lanes show sends, byte for byte, what the same aircraft send as
    /// full ECS entities (the Place system's placement, the FlightControl
    /// system's controls): every streamed aircraft, every frame, for each
    /// pattern, with scripts that start and stop actions (Bourg's surfaces
    /// return to neutral at every frame's start) and 21 aircraft (two whole
    /// blocks of 8 and a partial one).
    #[test]
    fn the_lanes_show_sends_the_ecs_fleets_messages_byte_for_byte() {
        fn check<M: FleetModel>(script: &str, frames: u64) {
            let (_socket, addr) = receiver();
            for pattern in [StartPattern::Demo, StartPattern::Rows, StartPattern::V] {
                let scenario = scenario::<M>(21, 21, pattern, script);
                let mut ecs = multiplayer_fleet::<M>(
                    21,
                    pattern,
                    scenario.origin,
                    scenario.script.clone(),
                    30,
                )
                .unwrap();
                let mut show = FleetShow::<M>::new(scenario, addr).unwrap();
                for frame in 1..=frames {
                    ecs.step().unwrap();
                    show.fly().unwrap();
                    let want: Vec<_> = ecs
                        .messages(21, M::FG_MP_MODEL)
                        .unwrap()
                        .iter()
                        .map(|m| m.encode().unwrap())
                        .collect();
                    let got: Vec<_> = show
                        .messages()
                        .unwrap()
                        .iter()
                        .map(|m| m.encode().unwrap())
                        .collect();
                    assert_eq!(got.len(), want.len());
                    let differs = (0..want.len()).find(|&k| got[k] != want[k]);
                    assert_eq!(
                        differs,
                        None,
                        "{} {pattern:?} frame {frame}: this aircraft's message differs",
                        M::NAME
                    );
                }
            }
        }
        check::<Bourg>(
            "1-20 thrust-up\n5-40 pitch-up\n41-50 roll-right\n61-70 yaw-left\n",
            90,
        );
        check::<Palmer>(
            "1-20 throttle-up\n1-5 alpha-up\n31-45 bank-right\n61-75 bank-left\n",
            90,
        );
    }

    /// A show flies the whole fleet and streams only the first aircraft:
    /// 2,000 aircraft (beyond the 1,000 FlightGear callsigns), 3 frames, 5
    /// streamed: 15 datagrams arrive on loopback, each a position message
    /// of one of the 5 callsigns, and every aircraft flew (the last one's
    /// clock moved).
    #[test]
    fn a_show_flies_every_aircraft_and_streams_the_first() {
        let (socket, addr) = receiver();
        socket
            .set_read_timeout(Some(std::time::Duration::from_secs(5)))
            .unwrap();
        let mut scenario = scenario::<Palmer>(2_000, 5, StartPattern::Demo, "1-3 throttle-up\n");
        scenario.frames = 3;
        let before = Palmer::fleet_member(1_999).1;
        let mut show = FleetShow::<Palmer>::new(scenario, addr).unwrap();
        show.run_to_end().unwrap();
        let report = show.report();
        assert_eq!(
            (report.aircraft, report.streamed, report.frames, report.sent),
            (2_000, 5, 3, 15)
        );
        let mut seen = Vec::new();
        let mut buf = [0_u8; 2048];
        for _ in 0..15 {
            let len = socket.recv(&mut buf).unwrap();
            let msg = MultiplayerPosition::decode(&buf[..len]).unwrap();
            seen.push(msg.callsign);
        }
        seen.sort();
        seen.dedup();
        assert_eq!(seen, (0..5).map(callsign).collect::<Vec<_>>());
        let last = show.fleet().state(1_999).unwrap();
        assert!(last.time_s > before.time_s, "{last:?}");
        assert_eq!(show.fleet().len(), 2_000);
    }

    /// Streamed aircraft are capped at what FlightGear's callsigns allow,
    /// and an empty fleet or a frame rate of 0 is a typed error before
    /// anything is sent.
    #[test]
    fn shows_check_their_scenario() {
        let (_socket, addr) = receiver();
        let show = FleetShow::<Palmer>::new(
            scenario::<Palmer>(1_500, 5_000, StartPattern::Rows, ""),
            addr,
        )
        .unwrap();
        assert_eq!(show.report().streamed, MAX_STREAMED);
        let show =
            FleetShow::<Palmer>::new(scenario::<Palmer>(3, 16, StartPattern::Rows, ""), addr)
                .unwrap();
        assert_eq!(show.report().streamed, 3);
        assert!(matches!(
            FleetShow::<Bourg>::new(scenario::<Bourg>(0, 1, StartPattern::V, ""), addr),
            Err(FleetError::NoAircraft)
        ));
        let mut zero_fps = scenario::<Bourg>(1, 1, StartPattern::V, "");
        zero_fps.fps = 0;
        assert!(matches!(
            FleetShow::<Bourg>::new(zero_fps, addr),
            Err(FleetError::Fps(_))
        ));
        let mut no_threads = scenario::<Bourg>(1, 1, StartPattern::V, "");
        no_threads.threads = Some(0);
        assert!(matches!(
            FleetShow::<Bourg>::new(no_threads, addr),
            Err(FleetError::NoThreads)
        ));
        assert!(matches!(
            watched_size::<Palmer>(u64::MAX),
            Err(FleetError::TooMany(_) | FleetError::Memory(_))
        ));
    }

    /// What is not shown: a diverged aircraft, and a finite state whose
    /// placement is not (a position of 1.7e308 m); their messages keep the
    /// last placement ([`FleetShow::messages`]).
    #[test]
    fn diverged_and_unplaceable_aircraft_are_not_placed() {
        let origin = GeodeticOrigin::default();
        let (controls, state) = Palmer::fleet_member(0);
        // Finite, but no geodetic position exists for it.
        let mut far = state;
        (far.position_m.x, far.position_m.z) = (1.7e308, 1.7e308);
        let mut fleet = <Palmer as FleetModel>::Lanes::from_starts(
            Palmer::default_aircraft(),
            [(controls, state), (controls, far), (controls, state)],
        )
        .unwrap();
        fleet.set_status(2, FlightStatus::Diverged).unwrap();
        let view = Palmer::view(&Palmer::default_aircraft(), &controls, &state);
        assert_eq!(
            placed::<Palmer>(&fleet, 0, &origin),
            Some((Placement::of(&view, &origin), view))
        );
        assert_eq!(placed::<Palmer>(&fleet, 1, &origin), None);
        assert_eq!(placed::<Palmer>(&fleet, 2, &origin), None);
        assert_eq!(placed::<Palmer>(&fleet, 3, &origin), None);
    }
}
