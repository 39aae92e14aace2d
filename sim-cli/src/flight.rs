//! Any [`CliModel`] as a [`Flight`]: one aircraft flown by an
//! [`fdm_run::Run`] (one entity in its own [`fdm_ecs::Simulation`]), with the
//! run's outputs attached: the FlightGear link (`--fg`,
//! [`FlightGearOutput`](fdm_run::flightgear::FlightGearOutput)), DIS (`--dis`), `--csv` (the run library's
//! [`CsvOutput`] of [`FlightRow`]s), `--record`, `--acmi`, `--plot`.
//!
//! A frame is the ECS's: [`Flight::step`] is the run's
//! [`Run::step_frame`](fdm_run::Run::step_frame), which pushes the frame's
//! actions (the script's rules for the frame first, in file order, then the
//! keys pressed) as the entity's frame input, then runs one frame of
//! the thesis schedule: FlightControl (the model's start of frame, e.g. Bourg's
//! surfaces back to neutral, then the actions) → EquationsOfMotion →
//! FlightStatus → Place; then the run hands the frame to its outputs. The frame rate is the simulation's
//! [`Resources`](fdm_ecs::Resources), so dt is the model's own [`Model::time_step`] (docs/cli.md).
//!
//! Geodetic position and attitude in the [`Snapshot`] are the entity's
//! [`Geodetic`] and [`Attitude`] components, which Place fills once per frame
//! and the FlightGear output encodes into the datagram: the report shows
//! exactly what FlightGear was sent.
//!
//! [`Geodetic`]: fdm_ecs::geodesy::Geodetic
//! [`Attitude`]: fdm_ecs::geodesy::Attitude

use anyhow::{anyhow, Context as _};
use fdm_core::model::Model;
use fdm_run::acmi::AcmiOutput;
use fdm_run::csv::{CsvOutput, FlightRow};
use fdm_run::links::{LinkSettings, LinksError};
use fdm_run::{Output, Run, RunError, Scenario};

use clap::{ArgMatches, FromArgMatches};

use crate::args::{start_values, CommonArgs, Fly};
use crate::config::{prepare_model, start_model, ModelConfig, Outputs};
use crate::error::CliError;
use crate::models::{CliModel, WithModel};
use crate::recording::RecordWriter;
use crate::run::{fly, Flight, Links};
use crate::snapshot::Snapshot;

/// One aircraft of model `M`: an [`fdm_run::Run`] (its own simulation and
/// the outputs attached to it), and what the CLI adds around it.
#[derive(Debug)]
pub struct ModelFlight<M: Model> {
    run: Run<M>,
    /// The FlightGear link (`--fg`) and DIS (`--dis`), attached to the run
    /// (which hands them every flown frame); these handles read their
    /// counters and failures.
    links: Links,
}

impl<M: CliModel> ModelFlight<M> {
    /// The model's state now (the start's before the first frame).
    #[must_use]
    pub fn state(&self) -> M::State {
        self.run.state().unwrap_or(self.run.scenario().start.state)
    }

    /// A run of `scenario` (its start, origin, frame rate and script) with
    /// the FlightGear output attached when `links` has a target and the DIS
    /// output with `--dis`.
    ///
    /// # Errors
    /// [`CliError::Usage`] for a frame rate the run refuses,
    /// [`CliError::Runtime`] when the FlightGear socket cannot be opened.
    pub fn new(scenario: Scenario<M>, links: &LinkSettings) -> Result<Self, CliError> {
        let links =
            Links::open::<M>(links, scenario.origin, scenario.fps).map_err(|e| match e {
                LinksError::Dis(e) => CliError::from(e),
                e @ LinksError::FlightGear { .. } => CliError::Runtime(e.into()),
            })?;
        let fps = scenario.fps;
        let mut flight =
            Run::new(scenario).map_err(|e| CliError::usage(format!("--fps {fps}: {e}")))?;
        links.attach_to(&mut flight).map_err(anyhow::Error::from)?;
        Ok(Self { run: flight, links })
    }

    /// [`Self::new`] with the files of `outputs` attached, in this order:
    /// `--csv`, `--record`, `--acmi`, then what `attach` attaches (`sim-cli
    /// study --run I`'s measures), then `--plot` (sampled as the run flies;
    /// written when [`Flight::finish`] completes the outputs, also when the
    /// run stopped early). The run hands them every frame and reset.
    ///
    /// # Errors
    /// As [`Self::new`], an output that fails on frame 0, or `attach`'s.
    pub fn with_outputs(
        scenario: Scenario<M>,
        outputs: Outputs,
        attach: impl FnOnce(&mut Self) -> anyhow::Result<()>,
    ) -> Result<Self, CliError> {
        let Outputs {
            links,
            csv,
            plot,
            record,
            acmi,
        } = outputs;
        let writer = match record {
            Some(record) => Some(
                RecordWriter::new(record.out, scenario.fps, &scenario.origin, &scenario.start)
                    .with_context(|| format!("recording to {}", record.path.display()))?,
            ),
            None => None,
        };
        let mut flight = Self::new(scenario, &links)?;
        if let Some(csv) = csv {
            flight.attach_csv(csv)?;
        }
        if let Some(writer) = writer {
            flight.attach(writer)?;
        }
        if let Some(acmi) = acmi {
            flight.attach(AcmiOutput::<M>::new(acmi))?;
        }
        attach(&mut flight)?;
        if let Some(plot) = plot {
            flight.attach(plot.into_output(M::TITLE))?;
        }
        Ok(flight)
    }

    /// Attaches an output to the run (e.g. `--acmi`).
    ///
    /// # Errors
    /// The output fails on frame 0.
    pub fn attach(&mut self, output: impl Output<M> + 'static) -> anyhow::Result<()> {
        Ok(self.run.attach(output)?)
    }

    /// Attaches `--csv`: a row per frame (frame 0 now and after each
    /// reset), the run library's [`FlightRow`].
    ///
    /// # Errors
    /// Writing the header or the first row failed.
    pub fn attach_csv<W: std::io::Write + 'static>(
        &mut self,
        writer: fdm_run::csv::CsvWriter<W>,
    ) -> anyhow::Result<()> {
        self.attach(CsvOutput::new(
            writer,
            FlightRow::<M>::of as fn(&fdm_run::Frame<'_, M>) -> FlightRow<M>,
        ))
    }
}

impl<M: CliModel> Flight for ModelFlight<M> {
    type Action = M::Action;
    type Details = M::Details;

    const TITLE: &'static str = M::TITLE;

    /// The script's rules for the next frame, then `keys`, and runs the frame; the
    /// run's outputs send it (a failed send is kept by the output, reported
    /// once by the run loop, never per frame).
    ///
    /// A step that diverges (a non-finite state) is an error: the ECS has kept
    /// the last finite state, the outputs sent nothing from the non-finite
    /// one, and the run stops here, before any row, report or HUD is made
    /// from it.
    fn step(&mut self, keys: &[M::Action]) -> anyhow::Result<()> {
        match self.run.step_frame(keys) {
            Ok(()) => {}
            Err(RunError::Diverged { model, dt, .. }) => {
                return Err(anyhow!(
                    "the {model} model diverged (non-finite state) at dt = {dt} s; try a higher --fps"
                ));
            }
            Err(e) => return Err(e.into()),
        }
        Ok(())
    }

    fn reset(&mut self) -> anyhow::Result<()> {
        Ok(self.run.reset()?)
    }

    /// The run's snapshot ([`Run::snapshot`]).
    fn snapshot(&self) -> Snapshot<M::Details> {
        self.run.snapshot()
    }

    fn links(&self) -> Links {
        self.links.clone()
    }

    /// Completes the run's outputs (`--record`, `--acmi`, `--plot`).
    fn finish(&mut self) -> anyhow::Result<()> {
        Ok(self.run.finish()?)
    }
}

/// `sim-cli <model> ...`: the options every model shares and the model's
/// own, as parsed ([`Fly`]), validated into a run ([`ModelConfig`]: the
/// start from the model's controls at frame 0, the script read, the output
/// files created) and flown ([`run_model`]).
///
/// # Errors
/// [`CliError::Usage`] for anything wrong with the input, else as [`run_model`].
pub fn fly_model(fly: &Fly) -> Result<(), CliError> {
    fly.model.with(FlyJob(&fly.args))
}

/// [`fly_model`] for the model's type.
struct FlyJob<'a>(&'a ArgMatches);

impl WithModel for FlyJob<'_> {
    type Output = Result<(), CliError>;

    fn call<M: CliModel>(self) -> Self::Output {
        let parsed = |e: clap::Error| CliError::usage(e.to_string());
        let common = CommonArgs::from_arg_matches(self.0).map_err(parsed)?;
        let own = start_values(self.0, M::START_OPTIONS).map_err(CliError::usage)?;
        let controls = M::start_controls(&own).map_err(CliError::usage)?;
        let start = start_model::<M>(controls, &common.start)?;
        run_model(prepare_model(common, start)?)
    }
}

/// Flies one aircraft of model `M` ([`ModelFlight`]) as configured.
///
/// # Errors
/// As [`ModelFlight::new`] and [`fly`].
pub fn run_model<M: CliModel>(config: ModelConfig<M>) -> Result<(), CliError> {
    run_model_with(config, |_| Ok(()))
}

/// [`run_model`] with `attach` attaching outputs of its own to the flight
/// before frame 0 (after `--record` and `--acmi`): `sim-cli study --run I`'s
/// measures.
///
/// # Errors
/// As [`run_model`], or `attach`'s.
pub fn run_model_with<M: CliModel>(
    config: ModelConfig<M>,
    attach: impl FnOnce(&mut ModelFlight<M>) -> anyhow::Result<()>,
) -> Result<(), CliError> {
    let ModelConfig {
        scenario,
        mode,
        outputs,
    } = config;
    let fps = scenario.fps;
    let fg = outputs.links.fg;
    fly(
        ModelFlight::with_outputs(scenario, outputs, attach)?,
        mode,
        fps,
        fg,
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::hud::status_label;
    use crate::origin::GeodeticOrigin;
    use crate::progress::StderrProgress;
    use crate::run::run_headless;
    use fdm_core::bourg::{self, Bourg, BourgAction, Flap};
    use fdm_core::model::{FlightStatus, LandingState};
    use fdm_core::palmer::{self, Palmer, PalmerAction, PalmerControls};
    use fdm_core::script::Script;
    use fdm_run::Start;
    use fdm_run::{LinkStats, SharedOutput};
    use std::net::{SocketAddrV4, UdpSocket};

    fn new_flight<M: CliModel>(
        fps: u32,
        fg: Option<SocketAddrV4>,
        start: Start<M>,
    ) -> ModelFlight<M> {
        scripted(fps, fg, start, Script::default())
    }

    fn scripted<M: CliModel>(
        fps: u32,
        fg: Option<SocketAddrV4>,
        start: Start<M>,
        script: Script<M::Action>,
    ) -> ModelFlight<M> {
        let scenario = Scenario {
            start,
            origin: GeodeticOrigin::default(),
            fps,
            frames: 0,
            script,
        };
        ModelFlight::new(scenario, &LinkSettings { fg, dis: None }).unwrap()
    }

    fn cruise() -> Start<Palmer> {
        Start {
            controls: PalmerControls {
                throttle: 1.0,
                alpha_deg: 4.0,
                ..PalmerControls::default()
            },
            ..Start::thesis()
        }
    }

    #[test]
    fn palmer_matches_the_core_step_by_step() {
        let mut flight = new_flight(10, None, cruise());
        let aircraft = Palmer::default_aircraft();
        let mut controls = cruise().controls;
        let mut state = Palmer::initial_state();
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
        let p = s.details;
        assert_eq!(p.controls.bank_deg, 20.0);
        assert_eq!(p.controls.flaps_deg, 40.0);
        assert_eq!(p.airspeed, state.airspeed_mps());
        assert_eq!(s.airspeed_mps, state.airspeed_mps());
        assert_eq!(p.heading_deg, state.heading_deg());
    }

    #[test]
    fn palmer_status_follows_the_flight_phase() {
        let mut flight = new_flight(10, None, cruise());
        let status = |f: &ModelFlight<Palmer>| {
            let s = f.snapshot();
            status_label(s.status, s.stalling)
        };
        assert_eq!(status(&flight), "on ground");
        for _ in 0..300 {
            flight.step(&[]).unwrap();
        }
        assert_eq!(status(&flight), "flying");
        // Nose down hard at idle: it comes back to the ground, fast.
        let mut down = vec![PalmerAction::ThrottleDown; 20];
        down.extend([PalmerAction::AlphaDown; 20]);
        flight.step(&down).unwrap();
        let mut frames = 0;
        while flight.snapshot().status == FlightStatus::Airborne && frames < 10_000 {
            flight.step(&[]).unwrap();
            frames += 1;
        }
        assert_eq!(
            flight.snapshot().status,
            FlightStatus::Landed(LandingState::Crash),
            "after {frames} frames"
        );
        assert_eq!(status(&flight), "CRASHED");
        flight.reset().unwrap();
        assert_eq!(status(&flight), "on ground");
        assert_eq!(flight.snapshot().common.position, [0.0; 3]);
    }

    #[test]
    fn palmer_reset_restores_the_initial_controls() {
        let mut flight = new_flight(30, None, cruise());
        flight.step(&[PalmerAction::ThrottleDown]).unwrap();
        flight.reset().unwrap();
        let p = flight.snapshot().details;
        assert_eq!((p.controls.throttle, p.controls.alpha_deg), (1.0, 4.0));
        assert_eq!(flight.snapshot().common.time_s, 0.0);
    }

    /// The scripted stall of `fdm-core/tests/bourg_stall.rs` (thrust cut on
    /// frames 1..5, elevators up from frame 10; the wings pass 24° of attack
    /// when frame 39 starts) shows `STALL` on the HUD's status line from
    /// frame 39 on, and `flying` before.
    #[test]
    fn bourg_stall_shows_on_the_hud() {
        use crate::hud::{render_hud, HudData, LoopStatus};
        let mut flight = new_flight::<Bourg>(30, None, Start::thesis());
        let mut status_line = Vec::new();
        for frame in 1..=40_u64 {
            let mut actions = Vec::new();
            if frame <= 5 {
                actions.push(BourgAction::ThrustDown);
            }
            if frame >= 10 {
                actions.push(BourgAction::PitchUp);
            }
            flight.step(&actions).unwrap();
            let run = LoopStatus {
                frame,
                fps: 30,
                overruns: 0,
                paused: false,
            };
            let hud = HudData::from_snapshot(Bourg::TITLE, &flight.snapshot(), None, None, run, "");
            let lines = render_hud(&hud, 80);
            let roll_line = lines
                .iter()
                .find(|l| l.starts_with("ROLL"))
                .expect("a ROLL line");
            status_line.push(roll_line.clone());
        }
        for (i, line) in status_line.iter().enumerate() {
            let frame = i + 1;
            let want = if frame >= 39 { "STALL" } else { "flying" };
            assert!(line.ends_with(want), "frame {frame}: {line:?}");
        }
    }

    #[test]
    fn bourg_surfaces_are_neutral_at_the_start_of_every_frame() {
        let mut flight = new_flight::<Bourg>(30, None, Start::thesis());
        let controls = |f: &ModelFlight<Bourg>| f.run.controls().unwrap();
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
    fn bourg_matches_the_core_and_keeps_the_models_clock() {
        let mut flight = new_flight::<Bourg>(30, None, Start::thesis());
        let aircraft = Bourg::default_aircraft();
        let mut controls = Bourg::initial_controls();
        let mut state = Bourg::initial_state();
        let dt = 1.0f32 / 30.0;
        let mut clock = 0.0_f64;
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
            state = bourg::step(&aircraft, &controls, &state, dt);
            clock += f64::from(dt);
        }
        let s = flight.snapshot();
        assert_eq!(
            s.common.position,
            <[f64; 3]>::from(state.position_ft.map(f64::from))
        );
        // The model's clock: 60 steps of the f32 time step, summed in f64.
        assert_eq!(s.common.time_s, clock);
        assert!((s.common.time_s - 2.0).abs() < 1e-6);
        let b = s.details;
        assert_eq!(
            b.euler_deg,
            <[f64; 3]>::from(state.euler_angles_deg().map(f64::from))
        );
        assert_eq!(b.speed, f64::from(state.speed_ftps()));
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
        let mut flight = new_flight::<Bourg>(30, Some(addr), Start::thesis());
        for _ in 0..5 {
            flight.step(&[BourgAction::RollRight]).unwrap();
        }
        let links = flight.links();
        assert_eq!(links.fg_stats(), Some(LinkStats { sent: 5, failed: 0 }));
        let packet = links
            .fg
            .as_ref()
            .and_then(|fg| fg.with(|o| o.and_then(|o| o.last_packet().copied())))
            .unwrap();
        let mut buf = [0u8; 512];
        let mut last = Vec::new();
        for _ in 0..5 {
            let n = receiver.recv(&mut buf).unwrap();
            last = buf[..n].to_vec();
        }
        assert_eq!(last, packet.encode());
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
        assert!(links.take_failure().is_none());
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
        let mut flight = new_flight(30, Some(addr), cruise());
        let links = flight.links();
        let mut messages = Vec::new();
        for _ in 0..20 {
            flight.step(&[]).unwrap();
            messages.extend(links.take_failure());
        }
        let stats = links.fg_stats().unwrap();
        assert_eq!(stats.sent + stats.failed, 20);
        assert!(stats.failed > 0, "{stats:?}");
        assert_eq!(messages.len(), 1, "{messages:?}");
        assert!(messages[0].contains(&addr.to_string()), "{}", messages[0]);
    }

    /// A failing link never stops a headless run: the loop takes its first
    /// failure (the output keeps it once) and flies every frame.
    #[test]
    fn a_failing_link_is_never_fatal_in_the_headless_loop() {
        let port = UdpSocket::bind("127.0.0.1:0")
            .unwrap()
            .local_addr()
            .unwrap()
            .port();
        let addr = SocketAddrV4::new(std::net::Ipv4Addr::LOCALHOST, port);
        let mut flight = new_flight(30, Some(addr), cruise());
        let mut progress = StderrProgress::with_enabled(20, false);
        let report = run_headless(&mut flight, 30, 20, false, &mut progress).unwrap();
        assert_eq!(report.frames, 20);
        let links = flight.links();
        assert!(links.fg_stats().unwrap().failed > 0);
        assert!(links.take_failure().is_none(), "taken by the loop");
    }

    /// The actions of every frame flown since the start or the last reset,
    /// as the run hands them to its outputs.
    #[derive(Default)]
    struct Steps(Vec<Vec<PalmerAction>>);

    impl Output<Palmer> for Steps {
        fn frame(
            &mut self,
            frame: &fdm_run::Frame<'_, Palmer>,
        ) -> Result<(), fdm_run::OutputError> {
            match frame.event {
                fdm_run::Event::Step => self.0.push(frame.actions.to_vec()),
                fdm_run::Event::Start | fdm_run::Event::Reset => self.0.clear(),
            }
            Ok(())
        }
    }

    /// A flight's script comes first in every frame, then the keys in the
    /// order pressed, in the headless loop and the interactive session
    /// alike, and starts over on a reset: the run library's
    /// `Run::step_frame`, which the loops' `Flight::step` is (the loops
    /// merged the script themselves before; `run::tests` checks them with a
    /// stand-in flight).
    #[test]
    fn the_script_comes_first_and_starts_over_on_a_reset() {
        use crate::keys::{AppCommand, Input};
        use crate::run::Session;
        use PalmerAction::*;
        let script = |text| Script::parse(text).unwrap();
        let steps_of = |steps: &SharedOutput<Steps>| steps.with(|s| s.unwrap().0.clone());

        let mut flight = scripted(
            10,
            None,
            cruise(),
            script("2-3 throttle-up\n3-3 flaps-down\n5-9 alpha-up\n"),
        );
        let steps = SharedOutput::new(Steps::default());
        flight.attach(steps.clone()).unwrap();
        let mut progress = StderrProgress::with_enabled(4, false);
        let report = run_headless(&mut flight, 10, 4, false, &mut progress).unwrap();
        assert_eq!(
            steps_of(&steps),
            [
                vec![],
                vec![ThrottleUp],
                vec![ThrottleUp, FlapsDown],
                vec![]
            ]
        );
        assert_eq!((report.frames, report.fps), (4, 10));

        let mut flight = scripted(10, None, cruise(), script("1-1 flaps-down\n"));
        let steps = SharedOutput::new(Steps::default());
        flight.attach(steps.clone()).unwrap();
        let mut s = Session::new();
        // Frame 1: script first, then keys in the order pressed.
        for input in [Input::Action(ThrottleUp), Input::Action(ThrottleUp)] {
            s.handle(input, &mut flight).unwrap();
        }
        s.advance(&mut flight).unwrap();
        assert_eq!(steps_of(&steps), [vec![FlapsDown, ThrottleUp, ThrottleUp]]);
        // Paused: no steps, keys ignored.
        s.handle(Input::App(AppCommand::Pause), &mut flight)
            .unwrap();
        s.handle(Input::Action(AlphaUp), &mut flight).unwrap();
        s.advance(&mut flight).unwrap();
        assert_eq!(steps_of(&steps).len(), 1);
        s.handle(Input::App(AppCommand::Pause), &mut flight)
            .unwrap();
        s.advance(&mut flight).unwrap();
        assert_eq!(steps_of(&steps)[1], []);
        // Reset: frame 0, the script starts over.
        s.handle(Input::App(AppCommand::Reset), &mut flight)
            .unwrap();
        s.advance(&mut flight).unwrap();
        assert_eq!(steps_of(&steps), [vec![FlapsDown]]);
        assert_eq!(s.total_frames(), 3);
    }

    /// `--csv` is an output of the run: row 0 when attached, one row per
    /// frame the headless loop flies; the interactive session's reset
    /// writes a new row 0 and the frame numbers start over; paused frames
    /// write nothing.
    #[test]
    fn csv_rows_follow_the_loops_frames_and_resets() {
        use crate::keys::{AppCommand, Input};
        use crate::run::Session;
        use std::sync::{Arc, Mutex};

        /// A writer whose bytes the test reads after the flight finished.
        #[derive(Clone, Default)]
        struct Buffer(Arc<Mutex<Vec<u8>>>);
        impl std::io::Write for Buffer {
            fn write(&mut self, bytes: &[u8]) -> std::io::Result<usize> {
                self.0.lock().unwrap().extend_from_slice(bytes);
                Ok(bytes.len())
            }
            fn flush(&mut self) -> std::io::Result<()> {
                Ok(())
            }
        }
        /// The frame numbers of a Palmer CSV's rows, after its model line
        /// and header.
        fn frames_of(buffer: &Buffer) -> Vec<String> {
            let text = String::from_utf8(buffer.0.lock().unwrap().clone()).unwrap();
            let mut lines = text.lines();
            assert_eq!(lines.next(), Some("# model: palmer"));
            assert!(lines.next().unwrap().starts_with("frame,time_s,"));
            lines
                .map(|l| l.split(',').next().unwrap().to_owned())
                .collect()
        }

        let buffer = Buffer::default();
        let mut flight = new_flight(10, None, cruise());
        flight
            .attach_csv(fdm_run::csv::CsvWriter::new(buffer.clone(), "mem"))
            .unwrap();
        let mut progress = StderrProgress::with_enabled(3, false);
        run_headless(&mut flight, 10, 3, false, &mut progress).unwrap();
        flight.finish().unwrap();
        assert_eq!(frames_of(&buffer), ["0", "1", "2", "3"]);

        let buffer = Buffer::default();
        let mut flight = new_flight(10, None, cruise());
        flight
            .attach_csv(fdm_run::csv::CsvWriter::new(buffer.clone(), "mem"))
            .unwrap();
        let mut session = Session::<PalmerAction>::new();
        session.advance(&mut flight).unwrap();
        session
            .handle(Input::App(AppCommand::Pause), &mut flight)
            .unwrap();
        session.advance(&mut flight).unwrap();
        session
            .handle(Input::App(AppCommand::Pause), &mut flight)
            .unwrap();
        session.advance(&mut flight).unwrap();
        session
            .handle(Input::App(AppCommand::Reset), &mut flight)
            .unwrap();
        session.advance(&mut flight).unwrap();
        flight.finish().unwrap();
        assert_eq!(frames_of(&buffer), ["0", "1", "2", "0", "1"]);
    }

    /// A CSV write that fails while flying (a full disk) stops the run with
    /// a run-time error (exit status 1) naming the frame, the file and the
    /// OS's reason, on one line; the buffered rows are not mistaken for a
    /// success.
    #[test]
    fn a_csv_write_failure_is_a_runtime_error_naming_the_file_and_the_cause() {
        struct Full;
        impl std::io::Write for Full {
            fn write(&mut self, _: &[u8]) -> std::io::Result<usize> {
                Err(std::io::Error::other("disk full"))
            }
            fn flush(&mut self) -> std::io::Result<()> {
                Err(std::io::Error::other("disk full"))
            }
        }
        let mut flight = new_flight(30, None, cruise());
        // The header and row 0 fit in the writer's buffer; a later row or the
        // final flush does not.
        let attached = flight.attach_csv(fdm_run::csv::CsvWriter::new(Full, "out.csv"));
        let mut progress = StderrProgress::with_enabled(100_000, false);
        let flown = attached
            .map_err(CliError::from)
            .and_then(|()| run_headless(&mut flight, 30, 100_000, false, &mut progress).map(drop));
        let err = flown
            .and_then(|()| flight.finish().map_err(CliError::from))
            .unwrap_err();
        assert_eq!(err.exit_code(), 1, "{}", err.one_line());
        let line = err.one_line();
        assert!(
            line.contains("writing CSV file out.csv: disk full"),
            "{line}"
        );
    }
}
