//! The command line (clap derive). Only syntax and per-value ranges live here;
//! checks that involve several options, files or the terminal are in `crate::config`.
//!
//! Every value parser returns a one-line message so clap's error, which `main`
//! squeezes onto one line, stays readable; clap exits usage errors with status 2.
//! The parsers and their limits are the run library's ([`fdm_run::values`]).
//!
//! `fleet` (many aircraft: throughput, and their DIS, FlightGear multiplayer and
//! ACMI outputs) has its own arguments, [`FleetArgs`], and its own module,
//! `crate::fleet`. The limits (`--fps`, `--frames`) are the run library's
//! ([`fdm_run::MAX_FPS`], [`fdm_run::MAX_FRAMES`]).

use std::path::PathBuf;

use clap::{
    Arg, ArgAction, ArgMatches, Args, CommandFactory, FromArgMatches, Parser, Subcommand, ValueEnum,
};

use crate::dis::{FleetDisArgs, FlightDisArgs};
use crate::origin::{parse_origin, GeodeticOrigin, DEFAULT_ORIGIN};
use fdm_run::model::pilot::{OptionKind, OptionValue, StartOption};
use fdm_run::values::{self, ValueError};
use fdm_run::values::{
    parse_duration, parse_fleet_frames, parse_fleet_size, parse_fps, parse_frames, parse_mp_port,
    parse_threads,
};
use fgnet::address::{parse_fg_listen, parse_fg_target, FgTarget};

/// Highest accepted `--fps` and longest accepted run in frames (`--frames`, or
/// `--duration` × `--fps` rounded): the run library's limits.
pub use fdm_run::{MAX_FPS, MAX_FRAMES};

use fdm_run::acmi::ReferenceTime;

/// The command line as clap derives it, without the models' subcommands
/// (added from the registry by [`Cli`]'s [`CommandFactory`]).
#[derive(Debug, Parser)]
#[command(name = "sim-cli", version)]
struct Spec {
    #[command(subcommand)]
    command: Command,
}

/// `sim-cli`: fly the registry's models (`crate::models`). Its subcommands
/// are the registry's models' (their arguments are [`CommonArgs`] and the
/// model's start options, `PilotModel::START_OPTIONS`, their help
/// `PilotModel::ABOUT`), then
/// [`Command`]'s.
#[derive(Debug)]
pub struct Cli {
    /// What to do.
    pub command: Command,
}

impl CommandFactory for Cli {
    fn command() -> clap::Command {
        let mut command = Spec::command();
        let models = ModelKind::ALL.len();
        let tools: Vec<String> = command
            .get_subcommands()
            .map(|tool| tool.get_name().to_owned())
            .collect();
        for (i, tool) in tools.iter().enumerate() {
            command = command.mut_subcommand(tool, |c| c.display_order(models + i));
        }
        for (i, kind) in ModelKind::ALL.iter().enumerate() {
            command = command.subcommand(kind.with(ModelSubcommand).display_order(i));
        }
        let aircraft = ModelKind::list(|kind| kind.aircraft().to_owned());
        let flies =
            format!("Fly {aircraft} from the keyboard into FlightGear, or headless from scripts");
        command
            .about(flies.clone())
            .long_about(format!(
                "{flies}.\n\nExit status: 0 success, 2 bad usage or bad input file, 1 any other \
                 failure, 3 a replayed recording was cut (the frames before the cut were \
                 replayed), 4 a replay flew another flight than the recorded one (fingerprint \
                 mismatch), 128+N stopped by signal N."
            ))
            .after_help(format!(
                "Run {} for the flight options (frame rate, headless runs, scripts, JSON report, \
                 CSV, FlightGear target, origin).",
                ModelKind::list(|kind| format!("`sim-cli {} --help`", kind.name()))
            ))
    }

    fn command_for_update() -> clap::Command {
        Self::command()
    }
}

/// A model's subcommand (`sim-cli palmer`): the options every model shares
/// ([`CommonArgs`]), then the model's own (its table,
/// `PilotModel::START_OPTIONS`), and its help line.
struct ModelSubcommand;

impl WithModel for ModelSubcommand {
    type Output = clap::Command;

    fn call<M: CliModel>(self) -> clap::Command {
        let command = CommonArgs::augment_args(clap::Command::new(M::NAME));
        M::START_OPTIONS
            .iter()
            .fold(command, |command, option| command.arg(start_arg(option)))
            .about(M::ABOUT)
            .long_about(None)
    }
}

/// A model's start option as a clap argument, as clap's derive made it
/// (the option's long name is its id).
fn start_arg(option: &StartOption) -> Arg {
    let arg = Arg::new(option.long)
        .long(option.long)
        .help(option.help)
        .conflicts_with_all(option.conflicts_with);
    match option.kind {
        OptionKind::Number {
            value_name,
            range,
            default,
        } => arg
            .value_name(value_name)
            .default_value(default)
            .value_parser(move |text: &str| range.parse(text)),
        OptionKind::Choice {
            value_name,
            choices,
            default,
        } => arg
            .value_name(value_name)
            .default_value(default)
            .value_parser(move |text: &str| choices.parse(text)),
        OptionKind::Flag => return arg.action(ArgAction::SetTrue),
    }
    .action(ArgAction::Set)
    .allow_hyphen_values(true)
}

/// The values of a model's start options (`options`, its table) in a
/// subcommand's `matches`, in the table's order.
///
/// # Errors
/// A value not of its option's kind (not the user's mistake).
pub fn start_values(
    matches: &ArgMatches,
    options: &[StartOption],
) -> Result<Vec<OptionValue>, clap::parser::MatchesError> {
    options
        .iter()
        .map(|option| {
            Ok(match option.kind {
                OptionKind::Number { .. } => matches
                    .try_get_one::<f64>(option.long)?
                    .map_or(OptionValue::Absent, |&v| OptionValue::Number(v)),
                OptionKind::Choice { .. } => matches
                    .try_get_one::<&'static str>(option.long)?
                    .map_or(OptionValue::Absent, |&v| OptionValue::Choice(v)),
                OptionKind::Flag => {
                    OptionValue::Flag(matches.try_get_one::<bool>(option.long)? == Some(&true))
                }
            })
        })
        .collect()
}

impl FromArgMatches for Cli {
    fn from_arg_matches(matches: &ArgMatches) -> Result<Self, clap::Error> {
        let command = match matches.subcommand() {
            Some((name, args)) => match ModelKind::named(name) {
                Some(model) => Command::Fly(Fly {
                    model,
                    args: args.clone(),
                }),
                None => Command::from_arg_matches(matches)?,
            },
            None => Command::from_arg_matches(matches)?,
        };
        Ok(Self { command })
    }

    fn update_from_arg_matches(&mut self, matches: &ArgMatches) -> Result<(), clap::Error> {
        *self = Self::from_arg_matches(matches)?;
        Ok(())
    }
}

impl Parser for Cli {}

/// `sim-cli <model> ...`: the model and its subcommand's arguments, parsed
/// (read as [`CommonArgs`] and the model's start options, [`start_values`]).
#[derive(Debug, Clone)]
pub struct Fly {
    /// The model.
    pub model: ModelKind,
    /// Its subcommand's arguments.
    pub args: ArgMatches,
}

/// The subcommands.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// A model's flight: one subcommand per model of the registry.
    #[command(skip)]
    Fly(Fly),
    /// Print the fgfs (FlightGear 2020.3) command line that shows a model flown by sim-cli
    FgfsCommand(FgfsArgs),
    /// Fly a fleet of one model headless through the ECS and report aircraft-steps per second
    Fleet(FleetArgs),
    /// Receive DIS datagrams for a while: count entities, PDUs, bytes, malformed datagrams; show each entity's last position
    DisListen(crate::dis_listen::DisListenArgs),
    /// Replay a flight recorded with --record, headless, to the same bits
    Replay(ReplayArgs),
    /// Draw a CSV written earlier with --csv as an SVG plot (as --plot does for a run)
    Plot(PlotArgs),
    /// Fly a Monte Carlo study (a TOML study file) on the SIMD fleets: runs.csv, summary.json; or one run alone with --run I
    Study(StudyArgs),
}

/// `sim-cli plot`.
#[derive(Debug, Clone, Args)]
pub struct PlotArgs {
    /// A CSV file written by `sim-cli palmer|bourg --csv`
    #[arg(value_name = "FILE.csv")]
    pub csv: PathBuf,

    /// The SVG file to write
    #[arg(short, long, value_name = "FILE.svg")]
    pub output: PathBuf,
}

/// Which model (the registry, `crate::models`).
pub use crate::models::ModelKind;
use crate::models::{CliModel, WithModel};

/// Options both models share (docs/cli.md "Options both models share").
#[derive(Debug, Clone, Args)]
pub struct CommonArgs {
    /// Frames per second, a whole number; each frame advances the model by dt = 1/N seconds
    #[arg(long, value_name = "N", default_value_t = 30, value_parser = parse_fps, allow_hyphen_values = true)]
    pub fps: u32,

    /// No keyboard and no real-time pacing: run as fast as possible, then report
    #[arg(long)]
    pub headless: bool,

    /// Length of a headless run in frames (needs --headless)
    #[arg(long, value_name = "N", conflicts_with = "duration", value_parser = parse_frames, allow_hyphen_values = true)]
    pub frames: Option<u64>,

    /// Length of a headless run in seconds; frames = round(SECONDS × fps) (needs --headless)
    #[arg(long, value_name = "SECONDS", value_parser = parse_duration, allow_hyphen_values = true)]
    pub duration: Option<f64>,

    /// Scripted controls: lines `START-END ACTION`, frames counted from 1, both ends inclusive
    #[arg(long, value_name = "FILE")]
    pub script: Option<PathBuf>,

    /// With --headless: print the final state as one JSON object on stdout
    #[arg(long)]
    pub json: bool,

    /// With --headless: one frame per 1/fps of wall-clock time, as in interactive mode (to replay a script into FlightGear without a terminal)
    #[arg(long)]
    pub realtime: bool,

    /// Write the state as CSV to FILE: a header, the initial state as frame 0, then one row per frame
    #[arg(long, value_name = "FILE")]
    pub csv: Option<PathBuf>,

    /// Draw the flight as an SVG plot in FILE when the run ends: height, airspeed, attitude,
    /// heading and status against time, and the ground track
    #[arg(long, value_name = "FILE")]
    pub plot: Option<PathBuf>,

    /// Send FlightGear native-FDM datagrams (UDP, IPv4) to HOST:PORT every frame
    /// [default: 127.0.0.1:5500 when interactive; headless sends only when given]
    #[arg(long, value_name = "HOST:PORT", value_parser = parse_fg_target)]
    pub fg: Option<FgTarget>,

    /// Geodetic position of the model's earth-frame origin: latitude (deg), longitude (deg), altitude (m),
    /// or a runway: wpafb (the default), phli or bikf (scenery in Debian's FlightGear data), ksfo
    #[arg(long, value_name = "LAT,LON,ALT_M|NAME", default_value = DEFAULT_ORIGIN, value_parser = parse_origin, allow_hyphen_values = true)]
    pub origin: GeodeticOrigin,

    /// Initial conditions and trim (`--altitude-ft`, `--speed-kt`, `--heading-deg`, `--trim`).
    #[command(flatten)]
    pub start: crate::start::StartArgs,

    /// DIS output (`--dis HOST:PORT` and its options, `crate::dis`).
    #[command(flatten)]
    pub dis: FlightDisArgs,

    /// Record the flight to FILE (binary flight log, docs/recording.md) for `sim-cli replay`
    #[arg(long, value_name = "FILE")]
    pub record: Option<PathBuf>,

    /// Tacview ACMI output (`--acmi FILE`, `--acmi-reference-time`).
    #[command(flatten)]
    pub acmi: AcmiArgs,
}

/// `--acmi FILE` and `--acmi-reference-time` (`palmer`, `bourg`, `replay`, `fleet`).
#[derive(Debug, Clone, Default, Args)]
pub struct AcmiArgs {
    /// Write the flight as Tacview ACMI 2.2 to FILE as the frames are flown (zip-compressed when FILE ends in .zip.acmi)
    #[arg(long, value_name = "FILE")]
    pub acmi: Option<PathBuf>,

    /// The ACMI file's ReferenceTime, UTC, e.g. 2024-05-01T12:00:00Z [default: 2000-01-01T00:00:00Z, so that files are reproducible]
    #[arg(long, value_name = "ISO8601", requires = "acmi", value_parser = parse_reference_time)]
    pub acmi_reference_time: Option<ReferenceTime>,
}

/// `--acmi-reference-time`: `YYYY-MM-DDTHH:MM:SS[.fraction]Z`.
pub fn parse_reference_time(text: &str) -> Result<ReferenceTime, String> {
    text.parse()
        .map_err(|e: fdm_run::acmi::ReferenceTimeError| crate::error::one_line(&e.to_string()))
}

/// `sim-cli replay`.
#[derive(Debug, Clone, Args)]
pub struct ReplayArgs {
    /// The recording (written by `sim-cli palmer|bourg --record FILE`)
    #[arg(value_name = "FILE")]
    pub file: PathBuf,

    /// Print the final state as one JSON object on stdout (as a headless --json flight)
    #[arg(long)]
    pub json: bool,

    /// One frame per 1/fps of wall-clock time, as the flight was flown (to watch it in FlightGear with --fg)
    #[arg(long)]
    pub realtime: bool,

    /// Write the state as CSV to FILE, as the recorded flight would (a reset writes a new frame 0)
    #[arg(long, value_name = "FILE")]
    pub csv: Option<PathBuf>,

    /// Draw the replayed flight as an SVG plot in FILE, the same drawing as the recorded run's --plot
    #[arg(long, value_name = "FILE")]
    pub plot: Option<PathBuf>,

    /// Send FlightGear native-FDM datagrams (UDP, IPv4) to HOST:PORT every frame (with
    /// --realtime at the recorded pace; without, as fast as the replay runs)
    #[arg(long, value_name = "HOST:PORT", value_parser = parse_fg_target)]
    pub fg: Option<FgTarget>,

    /// DIS output (`--dis HOST:PORT` and its options, `crate::dis`).
    #[command(flatten)]
    pub dis: FlightDisArgs,

    /// Tacview ACMI output of the replayed flight.
    #[command(flatten)]
    pub acmi: AcmiArgs,
}

/// `sim-cli fgfs-command`.
#[derive(Debug, Clone, Args)]
pub struct FgfsArgs {
    /// The model that will be flown (chooses the aircraft shown and the start position)
    #[arg(value_enum)]
    pub model: ModelKind,

    /// Packet rate FlightGear should poll at; use the --fps you fly with
    #[arg(long, value_name = "N", default_value_t = 30, value_parser = parse_fps, allow_hyphen_values = true)]
    pub fps: u32,

    /// Address FlightGear listens on, as given to sim-cli --fg [default: all interfaces, port 5500]
    #[arg(long, value_name = "HOST:PORT", value_parser = parse_fg_listen)]
    pub fg: Option<FgTarget>,

    /// Geodetic origin as given to sim-cli --origin: LAT,LON,ALT_M or a runway name (wpafb, phli, bikf, ksfo)
    #[arg(long, value_name = "LAT,LON,ALT_M|NAME", default_value = DEFAULT_ORIGIN, value_parser = parse_origin, allow_hyphen_values = true)]
    pub origin: GeodeticOrigin,

    /// The initial conditions that will be flown, as given to sim-cli (FlightGear starts where the aircraft starts).
    #[command(flatten)]
    pub start: crate::start::StartArgs,

    /// FlightGear's view at start (V in FlightGear cycles through them): chase and helicopter show the aircraft from outside
    #[arg(long, value_enum, default_value_t = FgView::Chase)]
    pub view: FgView,

    /// The fgfs program to print (Debian installs it as /usr/games/fgfs, which is not on every PATH)
    #[arg(long, value_name = "PATH", default_value = "fgfs")]
    pub fgfs: String,

    /// Also show a fleet streamed with `sim-cli fleet --fg-mp HOST:PORT`: FlightGear's multiplayer
    /// input listens on PORT (all interfaces; 1..32766, see docs/cli.md)
    #[arg(long, value_name = "PORT", value_parser = parse_mp_port)]
    pub fg_mp: Option<u16>,
}

/// FlightGear 2020.3's built-in views (`/sim/current-view/view-number`);
/// each variant's value (`view as u8`) is the view's index in FlightGear
/// 2020.3's `defaults.xml` view list.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
#[repr(u8)]
pub enum FgView {
    /// From the pilot's seat (view 0).
    Cockpit = 0,
    /// From behind and above, turning with the aircraft's heading only (view 1).
    Helicopter = 1,
    /// From behind, following the aircraft (view 2).
    Chase = 2,
}

/// The frame rate `sim-cli fleet` flies at (and the one "could fly" refers to).
pub const FLEET_FPS: u32 = 30;

/// `sim-cli fleet`.
#[derive(Debug, Clone, Args)]
pub struct FleetArgs {
    /// The model every aircraft of the fleet flies
    #[arg(long, value_enum)]
    pub model: ModelKind,

    /// Number of aircraft (1..=10000000), spread over distinct initial states
    #[arg(long, value_name = "N", value_parser = parse_fleet_size, allow_hyphen_values = true)]
    pub aircraft: u64,

    /// Frames to fly (each aircraft is stepped once per frame, dt = 1/30 s)
    #[arg(long, value_name = "F", value_parser = parse_fleet_frames, allow_hyphen_values = true)]
    pub frames: u64,

    /// Threads of the rayon pool stepping the fleet [default: available cores]
    #[arg(long, value_name = "T", value_parser = parse_threads, allow_hyphen_values = true)]
    pub threads: Option<usize>,

    /// How the fleet is stepped: `lanes`, structure-of-arrays SIMD kernels (fdm-fleet), or `ecs`, one hecs entity per aircraft through EquationsOfMotion
    #[arg(long, value_enum, default_value_t = FleetKernel::Lanes)]
    pub kernel: FleetKernel,

    /// With --kernel lanes: `exact` (every aircraft bit-identical to the model's own step) or `fast` (Palmer only: vectorised pow, within 1e-9 m of exact after 1800 steps)
    #[arg(long, value_enum, default_value_t = FleetPrecision::Exact)]
    pub precision: FleetPrecision,

    /// Print the measurement as one JSON object on stdout
    #[arg(long)]
    pub json: bool,

    /// DIS output (`--dis HOST:PORT` and its options, `crate::dis`).
    #[command(flatten)]
    pub dis: FleetDisArgs,

    /// Tacview ACMI output: every aircraft of the fleet, every frame.
    #[command(flatten)]
    pub acmi: AcmiArgs,

    /// Initial conditions and trim for every aircraft (`--altitude-ft`, `--speed-kt`, `--heading-deg`, `--trim`) instead of the demonstration fleet's varied states.
    #[command(flatten)]
    pub start: crate::start::StartArgs,

    /// Watching the fleet in FlightGear (docs/fleet-in-flightgear.md).
    #[command(flatten)]
    pub show: FleetShowArgs,
}

/// Most fleet aircraft `--fg-mp` streams to FlightGear.
pub const MAX_MP_AIRCRAFT: usize = fdm_run::fleet::show::MAX_STREAMED;

/// `sim-cli fleet` options for watching the fleet in FlightGear through its
/// multiplayer protocol (`crate::fleet_mp`).
#[derive(Debug, Clone, Default, Args)]
pub struct FleetShowArgs {
    /// Stream the fleet to FlightGear's multiplayer input at HOST:PORT (UDP, IPv4), one position
    /// message per aircraft per frame; needs --realtime
    #[arg(long, value_name = "HOST:PORT", value_parser = parse_fg_target)]
    pub fg_mp: Option<FgTarget>,

    /// How many aircraft (the first ones) --fg-mp streams [default: 16]
    #[arg(long, value_name = "N", value_parser = parse_mp_aircraft)]
    pub fg_mp_aircraft: Option<usize>,

    /// Where the fleet starts: demo (the models' spread-out demonstration fleet), rows (pairs
    /// in rows 50 m apart from 50 m north of the model's start: a formation take-off for Palmer)
    /// or v (a V formation led from 50 m north of the model's start)
    #[arg(long, value_enum, default_value_t = FleetPattern::Demo)]
    pub pattern: FleetPattern,

    /// Scripted controls applied to every aircraft (lines `START-END ACTION`), e.g.
    /// examples/scripts/palmer_climb_turn.txt for a formation take-off and turn
    #[arg(long, value_name = "FILE")]
    pub script: Option<PathBuf>,

    /// One frame per 1/30 s of wall-clock time (what FlightGear needs to show the fleet; also paces a fleet published with --dis)
    #[arg(long)]
    pub realtime: bool,

    /// Geodetic origin of the fleet's earth frame: LAT,LON,ALT_M or a runway name (wpafb, phli, bikf, ksfo)
    #[arg(long, value_name = "LAT,LON,ALT_M|NAME", value_parser = parse_origin, allow_hyphen_values = true)]
    pub origin: Option<GeodeticOrigin>,
}

/// Where a watched fleet starts.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, ValueEnum)]
pub enum FleetPattern {
    /// Each model's demonstration fleet (`Model::fleet_member`): distinct flying states.
    #[default]
    Demo,
    /// Pairs 20 m apart abreast, rows 50 m apart, the first 50 m north of the model's start.
    Rows,
    /// A V: the leader 50 m north of the model's start, the others 30 m further back and 30 m
    /// further out per place, alternately left and right.
    V,
}

/// `fleet --fg-mp-aircraft`: 1 to [`MAX_MP_AIRCRAFT`].
pub fn parse_mp_aircraft(text: &str) -> Result<usize, ValueError> {
    values::parse_whole(text, 1, MAX_MP_AIRCRAFT as u64, "a number of aircraft")
}

/// How `sim-cli fleet` steps its aircraft.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum FleetKernel {
    /// Structure-of-arrays SIMD kernels (`fdm-fleet`).
    Lanes,
    /// One ECS entity per aircraft (`fdm-ecs` EquationsOfMotion).
    Ecs,
}

/// `sim-cli fleet --precision`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum FleetPrecision {
    /// Bit-identical to the model's own step.
    Exact,
    /// Faster, within a documented bound of `exact` (Palmer only).
    Fast,
}

impl From<FleetPrecision> for fdm_fleet::Precision {
    /// The run library's precision for `--precision`.
    fn from(precision: FleetPrecision) -> Self {
        match precision {
            FleetPrecision::Exact => Self::Exact,
            FleetPrecision::Fast => Self::Fast,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use fdm_core::palmer::Palmer;
    use fdm_run::model::pilot::PilotModel;

    /// Palmer's own options, read from its table ([`start_values`]).
    struct PalmerArgs {
        throttle: f64,
        alpha: f64,
        bank: f64,
        flaps: u8,
    }

    /// The options of `sim-cli palmer ...`: the shared ones and Palmer's.
    fn palmer(args: &ArgMatches) -> (CommonArgs, PalmerArgs) {
        use OptionValue::{Choice, Flag, Number};
        let values = start_values(args, Palmer::START_OPTIONS).unwrap();
        let [Number(throttle), Number(alpha), Number(bank), Choice(flaps), Flag(_)] = values[..]
        else {
            panic!("not Palmer's options: {values:?}")
        };
        let flaps = flaps.parse().unwrap();
        (
            CommonArgs::from_arg_matches(args).unwrap(),
            PalmerArgs {
                throttle,
                alpha,
                bank,
                flaps,
            },
        )
    }

    /// Palmer's option `--LONG`, from its table.
    fn option(long: &str) -> OptionKind {
        let option = Palmer::START_OPTIONS.iter().find(|o| o.long == long);
        option.unwrap().kind
    }

    /// The value parser of Palmer's number option `--LONG`.
    fn parse_number(long: &str, text: &str) -> Result<f64, ValueError> {
        let OptionKind::Number { range, .. } = option(long) else {
            panic!("--{long} is not a number")
        };
        range.parse(text)
    }

    fn parse_throttle(text: &str) -> Result<f64, ValueError> {
        parse_number("throttle", text)
    }

    fn parse_alpha(text: &str) -> Result<f64, ValueError> {
        parse_number("alpha", text)
    }

    fn parse_bank(text: &str) -> Result<f64, ValueError> {
        parse_number("bank", text)
    }

    fn parse_flaps(text: &str) -> Result<u8, String> {
        let OptionKind::Choice { choices, .. } = option("flaps") else {
            panic!("--flaps is not a choice")
        };
        choices.parse(text).map(|flaps| flaps.parse().unwrap())
    }

    #[test]
    fn clap_definition_is_consistent() {
        Cli::command().debug_assert();
    }

    #[test]
    fn defaults() {
        let cli = Cli::try_parse_from(["sim-cli", "palmer"]).unwrap();
        let Command::Fly(fly) = cli.command else {
            panic!("not palmer")
        };
        let (common, p) = palmer(&fly.args);
        assert_eq!(common.fps, 30);
        assert_eq!(common.origin, GeodeticOrigin::default());
        assert_eq!(common.fg, None);
        assert_eq!((p.throttle, p.alpha, p.bank, p.flaps), (0.0, 0.0, 0.0, 0));
    }

    #[test]
    fn negative_values_are_values() {
        let cli = Cli::try_parse_from([
            "sim-cli",
            "palmer",
            "--alpha",
            "-5",
            "--bank",
            "-20",
            "--origin",
            "-33.9,18.6,0",
        ])
        .unwrap();
        let Command::Fly(fly) = cli.command else {
            panic!("not palmer")
        };
        let (common, p) = palmer(&fly.args);
        assert_eq!((p.alpha, p.bank), (-5.0, -20.0));
        assert_eq!(common.origin.geodetic().lat_deg, -33.9);
    }

    #[test]
    fn value_parsers() {
        assert!(parse_throttle("1.01").is_err());
        assert!(parse_alpha("-16.5").is_err());
        assert_eq!(parse_alpha("20"), Ok(20.0));
        assert!(parse_bank("21").is_err());
        assert!(parse_flaps("10").is_err());
        assert_eq!(parse_flaps("40"), Ok(40));
    }

    #[test]
    fn hyphenated_values_are_values_not_options() {
        for argv in [
            &["--fps", "-inf"][..],
            &["--headless", "--frames", "-inf"][..],
            &["--headless", "--duration", "-inf"][..],
            &["--throttle", "-inf"][..],
            &["--flaps", "-i"][..],
        ] {
            let full = ["sim-cli", "palmer"].iter().chain(argv).copied();
            let err = Cli::try_parse_from(full).unwrap_err();
            assert_eq!(
                err.kind(),
                clap::error::ErrorKind::ValueValidation,
                "{argv:?}"
            );
            let line = crate::clap_error_line(&err);
            assert!(!line.contains("unexpected argument"), "{line}");
        }
    }

    #[test]
    fn out_of_range_numbers_are_echoed_as_given() {
        assert_eq!(
            parse_throttle("1e308").unwrap_err().to_string(),
            "`1e308` is outside 0..1 (fraction of full power)"
        );
    }

    #[test]
    fn frames_and_duration_conflict() {
        let err = Cli::try_parse_from([
            "sim-cli",
            "bourg",
            "--headless",
            "--frames",
            "1",
            "--duration",
            "1",
        ])
        .unwrap_err();
        assert_eq!(err.kind(), clap::error::ErrorKind::ArgumentConflict);
    }
}

/// Default `--memory-limit-mib`: 1 GiB, the study target's budget.
pub const DEFAULT_MEMORY_LIMIT_MIB: u64 = 1024;

/// `sim-cli study`.
#[derive(Debug, Clone, Args)]
pub struct StudyArgs {
    /// The study file (TOML; docs/studies.md)
    #[arg(value_name = "FILE.toml")]
    pub file: PathBuf,

    /// Number of runs, instead of the file's `runs`
    #[arg(long, value_name = "N", value_parser = parse_runs, allow_hyphen_values = true)]
    pub runs: Option<u64>,

    /// Master seed, instead of the file's `seed`
    #[arg(long, value_name = "S")]
    pub seed: Option<u64>,

    /// Directory receiving runs.csv, runs.arrow, summary.json and study.svg (or, with --run, run-I.csv) [default: the study file's directory]
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,

    /// Worker threads [default: available cores]
    #[arg(long, value_name = "T", value_parser = parse_threads, allow_hyphen_values = true)]
    pub threads: Option<usize>,

    /// `exact` (every run bit-identical to the run flown alone) or `fast` (Palmer only: vectorised pow, within 1e-9 m of exact after 1800 steps; not with --run)
    #[arg(long, value_enum, default_value_t = FleetPrecision::Exact)]
    pub precision: FleetPrecision,

    /// Print the summary as JSON on stdout (with --run: the flight's JSON report)
    #[arg(long)]
    pub json: bool,

    /// Refuse to start (exit 2) when the study's estimated memory exceeds this many MiB
    #[arg(long, value_name = "MIB", default_value_t = DEFAULT_MEMORY_LIMIT_MIB)]
    pub memory_limit_mib: u64,

    /// Fly run I alone (0-based) with the outputs of a single flight, bit-identical to run I of the batch
    #[arg(long, value_name = "I")]
    pub run: Option<u64>,

    /// With --run: write the flight as CSV to FILE (as `sim-cli palmer --csv`)
    #[arg(long, value_name = "FILE", requires = "run")]
    pub csv: Option<PathBuf>,

    /// With --run: draw the flight as an SVG plot in FILE
    #[arg(long, value_name = "FILE", requires = "run")]
    pub plot: Option<PathBuf>,

    /// With --run: record the flight to FILE for `sim-cli replay`
    #[arg(long, value_name = "FILE", requires = "run")]
    pub record: Option<PathBuf>,

    /// With --run: send FlightGear native-FDM datagrams to HOST:PORT every frame
    #[arg(long, value_name = "HOST:PORT", value_parser = parse_fg_target, requires = "run")]
    pub fg: Option<FgTarget>,

    /// With --run: Tacview ACMI output of the flight.
    #[command(flatten)]
    pub acmi: AcmiArgs,
}

fn parse_runs(text: &str) -> Result<u64, ValueError> {
    values::parse_whole(text, 1, fdm_study::MAX_RUNS, "a number of runs")
}
