//! The two models as [`Flight`]s: one aircraft entity in an [`fdm_ecs::Simulation`],
//! with a [`FlightGearLink`] when the run sends packets.
//!
//! A frame is the ECS's: [`Flight::step`] pushes the frame's actions (the run loop
//! has already put the script's rules for the frame first, in file order, then the
//! keys pressed) as the entity's frame input, then runs one frame of the thesis
//! schedule: FlightControl (for Bourg: rudder, ailerons and elevators back to
//! neutral, then the actions; for Palmer: the actions on the held controls) →
//! EquationsOfMotion → MakePacket → SendPacket. The frame rate is the simulation's
//! [`Resources`], so dt is `1.0 / fps` (Palmer, `f64`) and `1.0f32 / fps as f32`
//! (Bourg), as cli.md states.
//!
//! Geodetic position and attitude in the [`Snapshot`] are the entity's [`Geodetic`]
//! and [`Attitude`] components, which MakePacket fills from the same numbers it
//! encodes into the datagram: the report shows exactly what FlightGear was sent.
//!
//! [`Geodetic`]: fdm_ecs::geodesy::Geodetic
//! [`Attitude`]: fdm_ecs::geodesy::Attitude

use std::net::SocketAddrV4;
use std::sync::Arc;

use anyhow::{anyhow, Context as _};
use fdm_core::bourg::{Aircraft, BourgAction, BourgControls, BourgState};
use fdm_core::palmer::{
    Flaps, FlightPhase, LandingState, PalmerAction, PalmerAircraft, PalmerControls, PalmerState,
};
use fdm_ecs::{Entity, FlightGearLink, Resources, Simulation};

use crate::config::{PalmerInitialControls, RunConfig};
use crate::error::CliError;
use crate::hud::{FlightStatus, LinkStats};
use crate::report::{
    widen, widen3, AttitudeReport, BourgDetails, CommonState, GeodeticReport, ModelDetails,
    PalmerControlsReport, PalmerDetails, Snapshot,
};
use crate::run::Flight;

/// One aircraft in its own simulation, and what the CLI adds around it.
#[derive(Debug)]
struct World {
    sim: Simulation,
    entity: Entity,
    /// The FlightGear target, for the one-time failure message.
    fg: Option<SocketAddrV4>,
    /// The first send failure, as a message, until [`Flight::take_link_failure`].
    link_failure: Option<String>,
}

impl World {
    /// A simulation at the run's frame rate and origin with one aircraft, spawned by
    /// `spawn` with a FlightGear link when the run has a target.
    fn new(
        run: &RunConfig,
        spawn: impl FnOnce(&mut Simulation, Option<FlightGearLink>) -> Entity,
    ) -> Result<Self, CliError> {
        let resources = Resources::new(f64::from(run.fps))
            .map_err(|e| CliError::usage(format!("--fps {}: {e}", run.fps)))?
            .with_origin(run.origin);
        let link = match run.fg {
            Some(addr) => Some(
                FlightGearLink::connect(&addr.to_string())
                    .with_context(|| format!("opening the FlightGear link to {addr}"))?,
            ),
            None => None,
        };
        let mut sim = Simulation::new(resources);
        let entity = spawn(&mut sim, link);
        Ok(Self {
            sim,
            entity,
            fg: run.fg,
            link_failure: None,
        })
    }

    /// Queues `actions` as this frame's key presses, runs the frame, and keeps the
    /// link's first failure (reported once by the run loop, never per frame).
    fn step<A: fdm_ecs::hecs::Component + Copy>(&mut self, actions: &[A]) -> anyhow::Result<()> {
        for &action in actions {
            self.sim.push_input(self.entity, action)?;
        }
        self.sim.run_frame();
        if let Some(error) = self.sim.take_send_failure(self.entity) {
            let target = self
                .fg
                .map_or_else(|| "FlightGear".to_owned(), |a| a.to_string());
            self.link_failure = Some(format!(
                "sending to {target} failed on frame {}: {error}; the run goes on and counts failures",
                self.sim.frame()
            ));
        }
        Ok(())
    }

    fn common(&self, time_s: f64, position: [f64; 3], velocity: [f64; 3]) -> CommonState {
        // Spawn computes both components, so they exist for the entity's lifetime.
        let geodetic = self.sim.geodetic(self.entity).unwrap_or(NAN_GEODETIC);
        let attitude = self.sim.attitude(self.entity).unwrap_or(NAN_ATTITUDE);
        CommonState {
            time_s,
            position,
            velocity,
            geodetic: GeodeticReport {
                lat_deg: geodetic.lat_deg,
                lon_deg: geodetic.lon_deg,
                alt_m: geodetic.alt_m,
            },
            attitude_deg: AttitudeReport {
                roll: attitude.roll_deg,
                pitch: attitude.pitch_deg,
                heading: attitude.heading_deg,
            },
        }
    }

    fn link_stats(&self) -> Option<LinkStats> {
        self.sim.send_stats(self.entity).map(|s| LinkStats {
            sent: s.sent,
            failed: s.failed,
        })
    }
}

/// Never used in practice (the components exist from spawn on); reported as NaN,
/// i.e. JSON `null`, rather than a panic.
const NAN_GEODETIC: fdm_ecs::geodesy::Geodetic = fdm_ecs::geodesy::Geodetic {
    lat_deg: f64::NAN,
    lon_deg: f64::NAN,
    alt_m: f64::NAN,
};
const NAN_ATTITUDE: fdm_ecs::geodesy::Attitude = fdm_ecs::geodesy::Attitude {
    roll_deg: f64::NAN,
    pitch_deg: f64::NAN,
    heading_deg: f64::NAN,
};

/// Palmer's Cessna 172 in the ECS.
#[derive(Debug)]
pub struct PalmerFlight {
    world: World,
    initial: PalmerControls,
    phase: FlightPhase,
    landing: Option<LandingState>,
}

impl PalmerFlight {
    /// A Cessna at rest on the runway at the run's origin, with the controls of
    /// `--throttle/--alpha/--bank/--flaps`.
    ///
    /// # Errors
    /// [`CliError::Usage`] for a flap setting other than 0, 20 or 40 (the argument
    /// parser already rejects those), [`CliError::Runtime`] when the FlightGear
    /// socket cannot be opened.
    pub fn new(run: &RunConfig, controls: PalmerInitialControls) -> Result<Self, CliError> {
        let flaps = Flaps::from_degrees(controls.flaps_deg).ok_or_else(|| {
            CliError::usage(format!(
                "--flaps {}: not a flap setting (0, 20 or 40)",
                controls.flaps_deg
            ))
        })?;
        let initial = PalmerControls {
            throttle: controls.throttle,
            alpha_deg: controls.alpha_deg,
            bank_deg: controls.bank_deg,
            flaps,
        };
        let world = World::new(run, |sim, link| {
            sim.spawn_palmer(
                Arc::new(PalmerAircraft::cessna_172()),
                initial,
                PalmerState::at_rest(),
                link,
            )
        })?;
        Ok(Self {
            world,
            initial,
            phase: FlightPhase::default(),
            landing: None,
        })
    }

    /// The model's state now.
    fn state(&self) -> anyhow::Result<PalmerState> {
        self.world
            .sim
            .palmer_state(self.world.entity)
            .ok_or_else(|| anyhow!("the Palmer aircraft is gone from the simulation"))
    }
}

impl Flight for PalmerFlight {
    type Action = PalmerAction;

    fn step(&mut self, actions: &[PalmerAction]) -> anyhow::Result<()> {
        self.world.step(actions)?;
        let (phase, touchdown) = self.phase.update(&self.state()?);
        self.phase = phase;
        if phase == FlightPhase::Airborne {
            self.landing = None;
        }
        if touchdown.is_some() {
            self.landing = touchdown;
        }
        Ok(())
    }

    fn reset(&mut self) -> anyhow::Result<()> {
        self.world
            .sim
            .reset_palmer(self.world.entity, self.initial, PalmerState::at_rest())?;
        self.phase = FlightPhase::default();
        self.landing = None;
        Ok(())
    }

    fn snapshot(&self) -> Snapshot {
        let sim = &self.world.sim;
        let entity = self.world.entity;
        let state = sim.palmer_state(entity).unwrap_or(PalmerState {
            time_s: f64::NAN,
            ..PalmerState::at_rest()
        });
        let controls = sim.palmer_controls(entity).unwrap_or(self.initial);
        Snapshot {
            common: self.world.common(
                state.time_s,
                state.position_m.into(),
                state.velocity_mps.into(),
            ),
            details: ModelDetails::Palmer(PalmerDetails {
                airspeed: state.airspeed_mps(),
                controls: PalmerControlsReport {
                    throttle: controls.throttle,
                    alpha_deg: controls.alpha_deg,
                    bank_deg: controls.bank_deg,
                    flaps_deg: controls.flaps.degrees(),
                },
                climb_angle_deg: state.climb_angle_deg(),
                climb_rate: state.climb_rate_mps(),
                heading_deg: state.heading_deg(),
            }),
        }
    }

    fn status(&self) -> FlightStatus {
        match (self.phase, self.landing) {
            (FlightPhase::Airborne, _) => FlightStatus::Flying,
            (FlightPhase::OnGround, None) => FlightStatus::OnGround,
            (FlightPhase::OnGround, Some(LandingState::Safe)) => FlightStatus::SafeLanding,
            (FlightPhase::OnGround, Some(LandingState::Rough)) => FlightStatus::RoughLanding,
            (FlightPhase::OnGround, Some(LandingState::Crash)) => FlightStatus::Crashed,
        }
    }

    fn link_stats(&self) -> Option<LinkStats> {
        self.world.link_stats()
    }

    fn take_link_failure(&mut self) -> Option<String> {
        self.world.link_failure.take()
    }
}

/// Bourg's 6-DoF aircraft in the ECS.
#[derive(Debug)]
pub struct BourgFlight {
    world: World,
    fps: u32,
    /// Frames since the start or the last reset (the model keeps no clock).
    frames: u64,
}

impl BourgFlight {
    /// The aircraft at Bourg's initial conditions: model position (−5000, 0, 2000) ft
    /// (5000 ft south of the origin, 2000 ft up), 60 ft/s north, thrust 500 lb.
    ///
    /// # Errors
    /// [`CliError::Runtime`] when the FlightGear socket cannot be opened.
    pub fn new(run: &RunConfig) -> Result<Self, CliError> {
        let world = World::new(run, |sim, link| {
            sim.spawn_bourg(
                Arc::new(Aircraft::bourg_default()),
                BourgControls::initial(),
                BourgState::initial(),
                link,
            )
        })?;
        Ok(Self {
            world,
            fps: run.fps,
            frames: 0,
        })
    }
}

impl Flight for BourgFlight {
    type Action = BourgAction;

    fn step(&mut self, actions: &[BourgAction]) -> anyhow::Result<()> {
        self.world.step(actions)?;
        self.frames += 1;
        Ok(())
    }

    fn reset(&mut self) -> anyhow::Result<()> {
        self.world.sim.reset_bourg(
            self.world.entity,
            BourgControls::initial(),
            BourgState::initial(),
        )?;
        self.frames = 0;
        Ok(())
    }

    /// Bourg's model has no clock: `time_s` is frames / fps.
    #[allow(clippy::cast_precision_loss)] // exact below 2^53 frames
    fn snapshot(&self) -> Snapshot {
        let sim = &self.world.sim;
        let entity = self.world.entity;
        let state = sim.bourg_state(entity).unwrap_or_else(BourgState::initial);
        let controls = sim
            .bourg_controls(entity)
            .unwrap_or_else(BourgControls::initial);
        Snapshot {
            common: self.world.common(
                self.frames as f64 / f64::from(self.fps),
                widen3(state.position.into()),
                widen3(state.velocity.into()),
            ),
            details: ModelDetails::Bourg(BourgDetails {
                speed: widen(state.speed),
                euler_deg: widen3(state.euler_angles_deg.into()),
                thrust_lb: widen(controls.thrust_lb),
                flaps: controls.landing_flaps,
                stalling: state.stalling,
            }),
        }
    }

    fn status(&self) -> FlightStatus {
        match self.world.sim.bourg_state(self.world.entity) {
            Some(state) if state.stalling => FlightStatus::Stalling,
            _ => FlightStatus::Flying,
        }
    }

    fn link_stats(&self) -> Option<LinkStats> {
        self.world.link_stats()
    }

    fn take_link_failure(&mut self) -> Option<String> {
        self.world.link_failure.take()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::config::Mode;
    use crate::origin::GeodeticOrigin;
    use fdm_core::bourg::Flap;
    use fdm_core::palmer;
    use std::net::UdpSocket;

    fn run(fps: u32, fg: Option<SocketAddrV4>) -> RunConfig {
        RunConfig {
            fps,
            mode: Mode::Headless {
                frames: 0,
                json: false,
            },
            csv: None,
            fg,
            origin: GeodeticOrigin::default(),
        }
    }

    const CRUISE: PalmerInitialControls = PalmerInitialControls {
        throttle: 1.0,
        alpha_deg: 4.0,
        bank_deg: 0.0,
        flaps_deg: 0,
    };

    #[test]
    fn palmer_matches_the_core_step_by_step() {
        let mut flight = PalmerFlight::new(&run(10, None), CRUISE).unwrap();
        let aircraft = PalmerAircraft::cessna_172();
        let mut controls = PalmerControls {
            throttle: 1.0,
            alpha_deg: 4.0,
            ..PalmerControls::default()
        };
        let mut state = PalmerState::at_rest();
        let keys = [
            vec![],
            vec![PalmerAction::BankRight, PalmerAction::BankRight],
            vec![PalmerAction::FlapsDown],
            vec![],
        ];
        for actions in keys.iter().cycle().take(40) {
            flight.step(actions).unwrap();
            for &a in actions {
                controls = controls.apply(a);
            }
            state = palmer::step(&aircraft, &controls, &state, 0.1);
        }
        let s = flight.snapshot();
        assert_eq!(s.common.position, <[f64; 3]>::from(state.position_m));
        assert_eq!(s.common.velocity, <[f64; 3]>::from(state.velocity_mps));
        assert_eq!(s.common.time_s, state.time_s);
        let ModelDetails::Palmer(p) = s.details else {
            panic!("not palmer")
        };
        assert_eq!(p.controls.bank_deg, 20.0);
        assert_eq!(p.controls.flaps_deg, 40.0);
        assert_eq!(p.airspeed, state.airspeed_mps());
        assert_eq!(p.heading_deg, state.heading_deg());
    }

    #[test]
    fn palmer_status_follows_the_flight_phase() {
        let mut flight = PalmerFlight::new(&run(10, None), CRUISE).unwrap();
        assert_eq!(flight.status(), FlightStatus::OnGround);
        for _ in 0..300 {
            flight.step(&[]).unwrap();
        }
        assert_eq!(flight.status(), FlightStatus::Flying);
        // Nose down hard at idle: it comes back to the ground, fast.
        let mut down = vec![PalmerAction::ThrottleDown; 20];
        down.extend([PalmerAction::AlphaDown; 20]);
        flight.step(&down).unwrap();
        let mut frames = 0;
        while flight.status() == FlightStatus::Flying && frames < 10_000 {
            flight.step(&[]).unwrap();
            frames += 1;
        }
        assert_eq!(
            flight.status(),
            FlightStatus::Crashed,
            "after {frames} frames"
        );
        flight.reset().unwrap();
        assert_eq!(flight.status(), FlightStatus::OnGround);
        assert_eq!(flight.snapshot().common.position, [0.0; 3]);
    }

    #[test]
    fn palmer_reset_restores_the_initial_controls() {
        let mut flight = PalmerFlight::new(&run(30, None), CRUISE).unwrap();
        flight.step(&[PalmerAction::ThrottleDown]).unwrap();
        flight.reset().unwrap();
        let ModelDetails::Palmer(p) = flight.snapshot().details else {
            panic!("not palmer")
        };
        assert_eq!((p.controls.throttle, p.controls.alpha_deg), (1.0, 4.0));
        assert_eq!(flight.snapshot().common.time_s, 0.0);
    }

    #[test]
    fn bourg_surfaces_are_neutral_at_the_start_of_every_frame() {
        let mut flight = BourgFlight::new(&run(30, None)).unwrap();
        let controls = |f: &BourgFlight| f.world.sim.bourg_controls(f.world.entity).unwrap();
        flight
            .step(&[
                BourgAction::PitchUp,
                BourgAction::RollLeft,
                BourgAction::YawRight,
                BourgAction::ThrustUp,
                BourgAction::FlapsDown,
            ])
            .unwrap();
        let c = controls(&flight);
        assert_ne!(c.elevators, Flap::Neutral);
        assert_ne!(c.port_aileron, Flap::Neutral);
        assert_ne!(c.rudder_deg, 0.0);
        flight.step(&[]).unwrap();
        let c = controls(&flight);
        assert_eq!(
            (
                c.elevators,
                c.port_aileron,
                c.starboard_aileron,
                c.rudder_deg
            ),
            (Flap::Neutral, Flap::Neutral, Flap::Neutral, 0.0)
        );
        // Thrust and flaps keep their state.
        assert_eq!((c.thrust_lb, c.landing_flaps), (600.0, true));
    }

    #[test]
    fn bourg_matches_the_core_and_counts_time_in_frames() {
        let mut flight = BourgFlight::new(&run(30, None)).unwrap();
        let aircraft = Aircraft::bourg_default();
        let mut controls = BourgControls::initial();
        let mut state = BourgState::initial();
        for frame in 1..=60_u32 {
            let actions: &[BourgAction] = if frame % 3 == 0 {
                &[BourgAction::PitchUp, BourgAction::ThrustUp]
            } else {
                &[]
            };
            flight.step(actions).unwrap();
            controls = controls.neutralize_surfaces();
            for &a in actions {
                controls = controls.apply(a);
            }
            state = fdm_core::bourg::step(&aircraft, &controls, &state, 1.0f32 / 30.0);
        }
        let s = flight.snapshot();
        assert_eq!(s.common.position, widen3(state.position.into()));
        assert_eq!(s.common.time_s, 2.0);
        let ModelDetails::Bourg(b) = s.details else {
            panic!("not bourg")
        };
        assert_eq!(b.euler_deg, widen3(state.euler_angles_deg.into()));
        assert_eq!(b.speed, widen(state.speed));
        assert_eq!(b.thrust_lb, 2500.0);
        flight.reset().unwrap();
        assert_eq!(flight.snapshot().common.time_s, 0.0);
        assert_eq!(flight.snapshot().common.position, [-5000.0, 0.0, 2000.0]);
    }

    #[test]
    fn snapshot_geodesy_is_what_the_packet_carries() {
        let receiver = UdpSocket::bind("127.0.0.1:0").unwrap();
        let std::net::SocketAddr::V4(addr) = receiver.local_addr().unwrap() else {
            panic!("not IPv4")
        };
        let mut flight = BourgFlight::new(&run(30, Some(addr))).unwrap();
        for _ in 0..5 {
            flight.step(&[BourgAction::RollRight]).unwrap();
        }
        assert_eq!(flight.link_stats(), Some(LinkStats { sent: 5, failed: 0 }));
        let packet = flight.world.sim.packet(flight.world.entity).unwrap();
        let s = flight.snapshot();
        assert_eq!(packet.latitude, s.common.geodetic.lat_deg.to_radians());
        assert_eq!(packet.longitude, s.common.geodetic.lon_deg.to_radians());
        assert_eq!(packet.altitude, s.common.geodetic.alt_m);
        assert_eq!(packet.phi, s.common.attitude_deg.roll.to_radians() as f32);
        assert_eq!(
            packet.theta,
            s.common.attitude_deg.pitch.to_radians() as f32
        );
        assert_eq!(
            packet.psi,
            s.common.attitude_deg.heading.to_radians() as f32
        );
        assert!(flight.take_link_failure().is_none());
    }

    #[test]
    fn a_failing_link_is_reported_once_and_counted() {
        // Bind and drop a socket: its port is (almost surely) closed afterwards, so
        // the kernel answers with ICMP port unreachable.
        let port = UdpSocket::bind("127.0.0.1:0")
            .unwrap()
            .local_addr()
            .unwrap()
            .port();
        let addr = SocketAddrV4::new(std::net::Ipv4Addr::LOCALHOST, port);
        let mut flight = PalmerFlight::new(&run(30, Some(addr)), CRUISE).unwrap();
        let mut messages = Vec::new();
        for _ in 0..20 {
            flight.step(&[]).unwrap();
            messages.extend(flight.take_link_failure());
        }
        let stats = flight.link_stats().unwrap();
        assert_eq!(stats.sent + stats.failed, 20);
        assert!(stats.failed > 0, "{stats:?}");
        assert_eq!(messages.len(), 1, "{messages:?}");
        assert!(messages[0].contains(&addr.to_string()), "{}", messages[0]);
    }
}
