//! `sim-cli fleet ... --fg-mp HOST:PORT --realtime`: a fleet to watch in
//! FlightGear (docs/fleet-in-flightgear.md): the flags and the wiring.
//!
//! The fleet and its messages are the run library's
//! ([`fdm_run::multiplayer`]): a [`MultiplayerFleet`] at [`FLEET_FPS`] (each
//! aircraft a full entity, placed every frame), flown with the same scripted
//! actions for every aircraft, and the first `--fg-mp-aircraft` aircraft
//! (default [`DEFAULT_MP_AIRCRAFT`]) sent to FlightGear every frame as
//! multiplayer position messages through a [`MultiplayerSender`]: callsign
//! [`callsign`]`(i)`, model [`CliModel::FG_MP_MODEL`].
//!
//! Where the aircraft start is [`FleetPattern`]: the models' demonstration
//! fleet, pairs along a runway ahead of the viewer (a formation take-off for Palmer's Cessnas
//! with `--script examples/scripts/palmer_climb_turn.txt`), or a V.

use std::net::{SocketAddr, SocketAddrV4};
use std::time::Instant;

use anyhow::Context as _;
use fdm_core::geodesy::GeodeticOrigin;
use fdm_core::script::Script;
pub use fdm_run::multiplayer::callsign;
use fdm_run::multiplayer::{MultiplayerFleet, MultiplayerSender};
use serde::Serialize;

use crate::args::{FleetArgs, FleetPattern, FLEET_FPS};
use crate::config::load_script;
use crate::error::CliError;
use crate::models::{CliModel, WithModel};
use crate::pacer::FramePacer;

/// `--fg-mp-aircraft` when not given.
pub const DEFAULT_MP_AIRCRAFT: usize = 16;

/// Rows pattern: metres between the two aircraft of a row (10 m either side of
/// the runway's centre line) and between rows.
pub const ROW_SPAN_M: f64 = 20.0;
/// Rows pattern: metres from one row to the next, northwards.
pub const ROW_SPACING_M: f64 = 50.0;
/// V pattern: metres back and out per place in the V.
pub const V_STEP_M: f64 = 30.0;
/// Rows and V patterns: metres north of the model's start where the first
/// aircraft starts, leaving the start itself to the viewer's own aircraft
/// (`fgfs-command` puts FlightGear's aircraft there), whose chase view then
/// looks north at the fleet.
pub const PATTERN_AHEAD_M: f64 = 50.0;

/// Controls and state of aircraft `index` of a fleet of model `M` started in
/// `pattern`.
#[must_use]
pub fn start_of<M: CliModel>(pattern: FleetPattern, index: usize) -> (M::Controls, M::State) {
    let (controls, state) = (M::initial_controls(), M::initial_state());
    #[allow(clippy::cast_precision_loss)] // indices up to 10 million
    let i = index as f64;
    match pattern {
        FleetPattern::Demo => M::fleet_member(index),
        FleetPattern::Rows => {
            let row = (i / 2.0).floor();
            // Even indices on the left (west, +y), odd on the right.
            let west = if index.is_multiple_of(2) { 0.5 } else { -0.5 } * ROW_SPAN_M;
            (
                controls,
                M::offset_state(&state, PATTERN_AHEAD_M + row * ROW_SPACING_M, west, 0.0),
            )
        }
        FleetPattern::V => {
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

/// What a watched fleet did (`--json`).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ShowReport {
    /// `"palmer"` or `"bourg"`.
    pub model: &'static str,
    /// Aircraft flown.
    pub aircraft: u64,
    /// Aircraft streamed to FlightGear.
    pub streamed: usize,
    /// Frames flown.
    pub frames: u64,
    /// Datagrams sent / that the OS refused.
    pub sent: u64,
    /// Datagrams whose send failed.
    pub failed: u64,
    /// Frames that missed their real-time deadline.
    pub overruns: u64,
}

/// `n` aircraft of model `M` in `pattern` around `origin`, to fly `script`
/// at [`FLEET_FPS`].
///
/// # Errors
/// Not in practice ([`FLEET_FPS`] is a valid frame rate).
pub fn fleet<M: CliModel>(
    n: usize,
    pattern: FleetPattern,
    origin: GeodeticOrigin,
    script: Script<M::Action>,
) -> anyhow::Result<MultiplayerFleet<M>> {
    let starts = (0..n).map(|i| start_of::<M>(pattern, i));
    Ok(MultiplayerFleet::new(
        M::default_aircraft(),
        starts,
        FLEET_FPS,
        origin,
        script,
    )?)
}

/// Flies and streams the fleet `args` describe: `frames` frames, one
/// position message per streamed aircraft per frame to `target`, paced at
/// 1/30 s per frame.
///
/// # Errors
/// A usage error for a fleet too large to watch or a bad script; a runtime
/// error if the socket cannot be opened.
pub fn show<M: CliModel>(args: &FleetArgs, target: SocketAddrV4) -> Result<ShowReport, CliError> {
    let n = usize::try_from(args.aircraft).unwrap_or(usize::MAX);
    if n > MAX_WATCHED_FLEET {
        return Err(CliError::usage(format!(
            "--fg-mp flies at most {MAX_WATCHED_FLEET} aircraft in real time (got --aircraft {n})"
        )));
    }
    let script = match &args.show.script {
        Some(path) => load_script(path)?,
        None => Script::default(),
    };
    let streamed = args
        .show
        .fg_mp_aircraft
        .unwrap_or(DEFAULT_MP_AIRCRAFT)
        .min(n);
    let origin = args.show.origin.unwrap_or_default();
    let mut show = fleet::<M>(n, args.show.pattern, origin, script)?;
    let mut sender =
        MultiplayerSender::open(SocketAddr::V4(target)).map_err(anyhow::Error::from)?;
    let mut pacer = FramePacer::new(FramePacer::period_for(FLEET_FPS), Instant::now());
    for _ in 0..args.frames {
        show.step().map_err(anyhow::Error::from)?;
        for msg in show
            .messages(streamed, M::FG_MP_MODEL)
            .map_err(anyhow::Error::from)?
        {
            sender.send(&msg).map_err(anyhow::Error::from)?;
        }
        let sleep = pacer.finish_frame(Instant::now());
        if !sleep.is_zero() {
            std::thread::sleep(sleep);
        }
    }
    let stats = sender.stats();
    if let Some(e) = sender.take_failure() {
        eprintln!(
            "sim-cli: warning: sending to {target} failed ({}); {} datagrams failed",
            crate::error::one_line(&e.to_string()),
            stats.failed
        );
    }
    Ok(ShowReport {
        model: M::NAME,
        aircraft: args.aircraft,
        streamed,
        frames: args.frames,
        sent: stats.sent,
        failed: stats.failed,
        overruns: pacer.overruns(),
    })
}

/// `sim-cli fleet` with `--fg-mp`: flies and streams the fleet, and returns
/// the text to print (the report as JSON with `--json`, else a summary line).
/// `None` without `--fg-mp` (then `fleet` measures throughput).
///
/// # Errors
/// [`CliError::Usage`] for `--fg-mp` without `--realtime`, watching options
/// without `--fg-mp`, or a target that does not resolve; as [`show`] otherwise.
pub fn run_show(args: &FleetArgs) -> Result<Option<String>, CliError> {
    let show_args = &args.show;
    let Some(target) = &show_args.fg_mp else {
        for (given, name) in [
            (show_args.fg_mp_aircraft.is_some(), "--fg-mp-aircraft"),
            (show_args.pattern != FleetPattern::Demo, "--pattern"),
            (show_args.script.is_some(), "--script"),
            // --realtime also paces a fleet published with --dis.
            (
                show_args.realtime && args.dis.common.target.is_none(),
                "--realtime",
            ),
            (show_args.origin.is_some(), "--origin"),
        ] {
            if given {
                return Err(CliError::usage(format!("fleet {name} needs --fg-mp")));
            }
        }
        return Ok(None);
    };
    if args.dis.common.target.is_some() {
        return Err(CliError::usage(
            "fleet --dis and --fg-mp cannot be used together (publish over DIS or stream to \
             FlightGear, one at a time)",
        ));
    }
    if !show_args.realtime {
        return Err(CliError::usage(
            "fleet --fg-mp needs --realtime (FlightGear shows multiplayer aircraft in real time)",
        ));
    }
    let target = target
        .resolve()
        .map_err(|e| CliError::usage(e.to_string()))?;
    let report = args.model.with(ShowJob { args, target })?;
    Ok(Some(if args.json {
        serde_json::to_string(&report).context("encoding the report")?
    } else {
        format!(
            "{} fleet: {} aircraft, {} streamed to {target} as multiplayer aircraft SIM001..{}, \
             {} frames, {} datagrams sent, {} failed, {} overruns",
            report.model,
            report.aircraft,
            report.streamed,
            callsign(report.streamed.saturating_sub(1)),
            report.frames,
            report.sent,
            report.failed,
            report.overruns
        )
    }))
}

/// Largest fleet `--fg-mp` flies (every aircraft is a full entity stepped in
/// real time on one thread).
pub const MAX_WATCHED_FLEET: usize = 10_000;

/// [`show`] for the model the arguments name.
pub struct ShowJob<'a> {
    /// The arguments.
    pub args: &'a FleetArgs,
    /// Where FlightGear listens.
    pub target: SocketAddrV4,
}

impl WithModel for ShowJob<'_> {
    type Output = Result<ShowReport, CliError>;

    fn call<M: CliModel>(self) -> Self::Output {
        show::<M>(self.args, self.target)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::args::{Cli, Command, ModelKind};
    use clap::Parser;
    use fdm_core::bourg::Bourg;
    use fdm_core::model::Model;
    use fdm_core::palmer::Palmer;
    use fgnet::MultiplayerPosition;
    use std::net::UdpSocket;
    use std::time::Duration;

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
        assert_eq!(xyz(FleetPattern::Rows, 0), [50.0, 10.0, 0.0]);
        assert_eq!(xyz(FleetPattern::Rows, 1), [50.0, -10.0, 0.0]);
        assert_eq!(xyz(FleetPattern::Rows, 5), [150.0, -10.0, 0.0]);
        // V: leader 50 m north of the start, then 30 m back and out per place, left then right.
        assert_eq!(xyz(FleetPattern::V, 0), [50.0, 0.0, 0.0]);
        assert_eq!(xyz(FleetPattern::V, 1), [20.0, 30.0, 0.0]);
        assert_eq!(xyz(FleetPattern::V, 2), [20.0, -30.0, 0.0]);
        assert_eq!(xyz(FleetPattern::V, 3), [-10.0, 60.0, 0.0]);
        assert_eq!(
            start_of::<Palmer>(FleetPattern::Demo, 7),
            Palmer::fleet_member(7)
        );
        // Bourg in feet, f32: 20 m north and 30 m west of its start.
        let b = start_of::<Bourg>(FleetPattern::V, 1).1.position_ft;
        assert_eq!(b.x, -5000.0 + (20.0 / 0.3048) as f32);
        assert_eq!(b.y, (30.0 / 0.3048) as f32);
    }

    /// The messages carry what the simulation computed: position within
    /// 1e-6 degrees (tolerance: the ECEF round trip is exact to nanometres; the
    /// orientation goes through f32 on the wire, a few 1e-6 degrees).
    #[test]
    fn messages_carry_the_fleets_positions_and_attitudes() {
        let origin = crate::origin::parse_origin("phli").unwrap();
        let script = Script::parse("1-20 thrust-up\n1-60 pitch-up\n").unwrap();
        let mut show = fleet::<Bourg>(6, FleetPattern::V, origin, script).unwrap();
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

    /// End to end on loopback: `fleet --fg-mp` sends one datagram per streamed
    /// aircraft per frame, at the real-time pace.
    #[test]
    fn fleet_streams_positions_at_real_time_pace() {
        let rx = UdpSocket::bind("127.0.0.1:0").unwrap();
        rx.set_read_timeout(Some(Duration::from_secs(5))).unwrap();
        let port = rx.local_addr().unwrap().port();
        let target = format!("127.0.0.1:{port}");
        let cli = Cli::try_parse_from([
            "sim-cli",
            "fleet",
            "--model",
            "palmer",
            "--aircraft",
            "5",
            "--frames",
            "15",
            "--fg-mp",
            &target,
            "--fg-mp-aircraft",
            "3",
            "--pattern",
            "rows",
            "--realtime",
        ])
        .unwrap();
        let Command::Fleet(args) = cli.command else {
            panic!("not fleet")
        };
        let start = Instant::now();
        let report = ModelKind::Palmer
            .with(ShowJob {
                args: &args,
                target: args.show.fg_mp.as_ref().unwrap().resolve().unwrap(),
            })
            .unwrap();
        // 15 frames at 30 fps: half a second, less one period.
        assert!(
            start.elapsed() >= Duration::from_millis(460),
            "{:?}",
            start.elapsed()
        );
        assert_eq!((report.sent, report.failed, report.streamed), (45, 0, 3));
        let mut seen = std::collections::BTreeMap::new();
        let mut buf = [0_u8; 2048];
        for _ in 0..45 {
            let n = rx.recv(&mut buf).unwrap();
            let msg = MultiplayerPosition::decode(&buf[..n]).unwrap();
            assert_eq!(msg.model_path, "Aircraft/c172p/Models/c172p.xml");
            *seen.entry(msg.callsign).or_insert(0) += 1;
        }
        assert_eq!(
            seen.into_iter().collect::<Vec<_>>(),
            [
                ("SIM001".to_owned(), 15),
                ("SIM002".to_owned(), 15),
                ("SIM003".to_owned(), 15)
            ]
        );
    }
}
