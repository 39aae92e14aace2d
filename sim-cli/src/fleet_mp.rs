//! `sim-cli fleet ... --fg-mp HOST:PORT --realtime`: a fleet of any size to
//! watch in FlightGear (docs/fleet-in-flightgear.md): the flags, checked and
//! turned into the run library's [`ShowScenario`] ([`fdm_run::fleet::show`]:
//! the fleet on the lanes kernel, its start patterns, the multiplayer
//! messages and their pacing), and the line printed. The first
//! `--fg-mp-aircraft` aircraft (default [`DEFAULT_MP_AIRCRAFT`]) are
//! streamed, callsigns `fdm_run::multiplayer::callsign(i)`.

use std::net::{SocketAddr, SocketAddrV4};

use anyhow::Context as _;
use fdm_run::fleet::show::{watched_size, FleetShow, ShowScenario, StartPattern};
pub use fdm_run::fleet::show::{ShowReport, DEFAULT_MP_AIRCRAFT};

use crate::args::{FleetArgs, FleetKernel, FleetPattern, FLEET_FPS};
use crate::config::load_script;
use crate::error::CliError;
use crate::models::{CliModel, WithModel};

/// Flies and streams the fleet `args` describe: `frames` frames, one
/// position message per streamed aircraft per frame to `target`, paced at
/// 1/30 s per frame.
///
/// # Errors
/// A usage error for a fleet that does not fit in memory, a precision the
/// model's kernel has not or a bad script; a runtime error if the thread
/// pool or the socket cannot be made.
pub fn show<M: CliModel>(args: &FleetArgs, target: SocketAddrV4) -> Result<ShowReport, CliError> {
    watched_size::<M>(args.aircraft)?;
    let script = args.show.script.as_deref().map(load_script).transpose()?;
    let scenario = ShowScenario {
        aircraft: args.aircraft,
        streamed: args.show.fg_mp_aircraft.unwrap_or(DEFAULT_MP_AIRCRAFT),
        pattern: match args.show.pattern {
            FleetPattern::Demo => StartPattern::Demo,
            FleetPattern::Rows => StartPattern::Rows,
            FleetPattern::V => StartPattern::V,
        },
        origin: args.show.origin.unwrap_or_default(),
        script: script.unwrap_or_default(),
        frames: args.frames,
        fps: FLEET_FPS,
        threads: args.threads,
        precision: args.precision.into(),
    };
    let mut show = FleetShow::<M>::new(scenario, SocketAddr::V4(target))?;
    show.run_to_end()?;
    let report = show.report();
    if let Some(e) = show.take_failure() {
        eprintln!(
            "sim-cli: warning: sending to {target} failed ({}); {} datagrams failed",
            crate::error::one_line(&e.to_string()),
            report.failed
        );
    }
    Ok(report)
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
    if args.kernel == FleetKernel::Ecs {
        return Err(CliError::usage(
            "fleet --fg-mp flies the lanes kernel (--kernel ecs is for measuring the ECS)",
        ));
    }
    if !args.start.is_thesis() {
        return Err(CliError::usage(
            "fleet --fg-mp starts the aircraft in a --pattern (--altitude-ft, --speed-kt, \
             --heading-deg and --trim are for measuring with --kernel ecs)",
        ));
    }
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
    let target = target.resolve()?;
    let report = args.model.with(ShowJob { args, target })?;
    Ok(Some(if args.json {
        serde_json::to_string(&report).context("encoding the report")?
    } else {
        report.summary(SocketAddr::V4(target))
    }))
}

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
    use fgnet::MultiplayerPosition;
    use std::net::UdpSocket;
    use std::time::{Duration, Instant};

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
        let report = ModelKind::named("palmer")
            .unwrap()
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

    fn fleet_args(extra: &[&str]) -> FleetArgs {
        let mut argv = vec!["sim-cli", "fleet", "--model", "bourg", "--frames", "3"];
        argv.extend_from_slice(extra);
        let Command::Fleet(args) = Cli::try_parse_from(argv).unwrap().command else {
            panic!("not fleet")
        };
        args
    }

    /// A fleet larger than the old ECS show's 10,000 flies on the lanes
    /// kernel on the threads asked for and streams only the aircraft asked
    /// for: 3 frames of 20,000 Bourg aircraft on 2 threads, 2 streamed, 6
    /// datagrams.
    #[test]
    fn a_fleet_of_any_size_streams_the_aircraft_asked_for() {
        let rx = UdpSocket::bind("127.0.0.1:0").unwrap();
        rx.set_read_timeout(Some(Duration::from_secs(5))).unwrap();
        let target = format!("127.0.0.1:{}", rx.local_addr().unwrap().port());
        let args = fleet_args(&[
            "--aircraft",
            "20000",
            "--threads",
            "2",
            "--fg-mp",
            &target,
            "--fg-mp-aircraft",
            "2",
            "--realtime",
            "--json",
        ]);
        let text = run_show(&args).unwrap().unwrap();
        let report: serde_json::Value = serde_json::from_str(&text).unwrap();
        assert_eq!(report["aircraft"], 20_000);
        assert_eq!(report["streamed"], 2);
        assert_eq!(report["sent"], 6);
        let mut buf = [0_u8; 2048];
        for _ in 0..6 {
            let n = rx.recv(&mut buf).unwrap();
            let msg = MultiplayerPosition::decode(&buf[..n]).unwrap();
            assert!(["SIM001", "SIM002"].contains(&msg.callsign.as_str()));
        }
    }

    /// What a watched fleet cannot do is a usage error naming the flag,
    /// before anything flies: the ECS kernel, initial conditions meant for
    /// it, a precision Bourg's kernel has not.
    #[test]
    fn options_a_watched_fleet_cannot_honour_are_refused() {
        let base = ["--fg-mp", "127.0.0.1:5000", "--realtime", "--aircraft"];
        for (extra, says) in [
            (&["3", "--kernel", "ecs"][..], "--kernel ecs"),
            (&["3", "--altitude-ft", "3000"][..], "--altitude-ft"),
            (&["3", "--precision", "fast"][..], "fast"),
        ] {
            let mut argv = base.to_vec();
            argv.extend_from_slice(extra);
            let args = fleet_args(&argv);
            let err = match run_show(&args) {
                Err(e) => e,
                Ok(_) => panic!("{extra:?} was accepted"),
            };
            let text = err.to_string();
            assert!(matches!(err, CliError::Usage(_)), "{extra:?}: {text}");
            assert!(text.contains(says), "{extra:?}: {text}");
        }
    }
}
