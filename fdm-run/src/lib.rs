//! A flight as a library: a [`Scenario`] becomes a [`Run`] that another
//! program drives frame by frame ([`Run::step_frame`]) or to the end
//! ([`Run::run_to_end`]), headless or paced in real time, with [`Output`]s
//! attached; record and replay ([`recording`], [`mod@replay`]); Tacview ACMI ([`acmi`]).
//!
//! `sim-cli` flies its single aircraft and its fleets through this crate; the Python
//! bindings and study runners are meant to build on it the same way.
//!
//! ```
//! use fdm_core::palmer::{Palmer, PalmerAction};
//! use fdm_core::script::Script;
//! use fdm_run::recording::{RecordWriter, Recording, Replayed};
//! use fdm_run::{Run, Scenario, Start};
//!
//! // A scripted take-off, recorded in memory as it flies.
//! let script = Script::parse("1-20 throttle-up\n1-5 alpha-up\n")?;
//! let scenario = Scenario::<Palmer>::new(Start::thesis(), 30, 300)?.with_script(script);
//! let mut run = Run::new(scenario.clone())?;
//! let writer = RecordWriter::new(Vec::new(), 30, &scenario.origin, &scenario.start)?;
//! let shared = fdm_run::SharedOutput::new(writer);
//! run.attach(shared.clone())?;
//! run.run_to_end()?;
//! run.finish()?;
//! let bytes = shared.take().map(|w| w.into_inner()).unwrap_or_default();
//!
//! // The replay is bit-identical.
//! let recording = Recording::<Palmer>::parse(&bytes)?;
//! let mut replay = Run::new(Scenario::new(recording.start.clone(), recording.fps, 0)?)?;
//! for event in recording.events() {
//!     match event? {
//!         Replayed::Frames { count, actions } => {
//!             for _ in 0..count {
//!                 replay.step_actions(&actions)?;
//!             }
//!         }
//!         Replayed::Reset => replay.reset()?,
//!     }
//! }
//! assert_eq!(replay.state()?, run.state()?);
//! # let _ = PalmerAction::ThrottleUp;
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! | module | what |
//! |---|---|
//! | [`scenario`] | [`Scenario`], [`Start`] and where it is ([`StartOptions`]: altitude, speed, heading, trim), the run limits ([`MAX_FPS`], [`MAX_FRAMES`]) |
//! | [`mod@run`] | [`Run`]: the run loop over one `fdm_ecs::Simulation` |
//! | [`output`] | [`Output`], [`Frame`], [`Placement`], [`LinkStats`]: outputs as plugins |
//! | [`fgfs`] | the FlightGear command line that shows a run ([`fgfs::command_line`]: aircraft, start preset, view, multiplayer input) |
//! | [`flightgear`] | the FlightGear native-FDM link ([`flightgear::FlightGearOutput`]) |
//! | [`links`] | handles to a run's network outputs ([`links::Links`]: the FlightGear link's counters, DIS's report, their first failures) |
//! | [`multiplayer`] | FlightGear multiplayer for a fleet ([`multiplayer::MultiplayerFleet`], [`multiplayer::MultiplayerSender`]) |
//! | [`origin`] | where the earth-frame origin is: `LAT,LON,ALT_M` or a named runway ([`origin::parse_origin`], [`origin::NAMED_ORIGINS`]) |
//! | [`replay`] | a recording replayed on a run ([`replay::replay`], real-time or not, stoppable) and checked against its fingerprint ([`replay::check_fingerprint`]) |
//! | [`recording`] | the binary flight log (`--record`, `sim-cli replay`; docs/recording.md) |
//! | [`acmi`] | Tacview ACMI 2.2 ([`acmi::AcmiWriter`], [`acmi::AcmiOutput`]) |
//! | `dis` (feature `dis`) | DIS Entity State output: `dis::DisOutput` (one aircraft), `dis::FleetDis` (fleets), `dis::DisReport` |
//! | [`csv`] | per-frame CSV rows ([`csv::CsvWriter`], [`csv::CsvRecord`]), [`csv::CsvOutput`], and the flight CSV's row ([`csv::FlightRow`]) |
//! | [`fleet`] | fleet runs: [`fleet::FleetScenario`] → [`fleet::FleetRun`] (ECS or lanes kernel, [`fleet::FleetOutput`] plugins such as ACMI, DIS, [`fleet::FleetReport`]), a fleet watched in FlightGear ([`fleet::show`]) |
//! | [`input`] | input files read safely (a regular file or a pipe, bounded: [`input::read_text`], [`input::InputError`]), the same-file check ([`input::clash`]), paths and numbers shown in messages |
//! | [`outfile`] | output files locked against a second writer ([`outfile::create_locked`]), watched while a write waits ([`outfile::WatchedFile`]) |
//! | [`values`] | settings read from text (the options of `sim-cli`): frame rate, frames, durations, fleet sizes, start conditions, ports, each checked against its range ([`values::ValueError`]) |
//! | [`memory`] | how much memory this process can still allocate, and the fleet's memory check |
//! | [`model`] | [`RunModel`] (with each model's FlightGear aircraft, ACMI name, callsign, DIS type), [`FleetModel`] and the model registry ([`model::MODELS`], [`model::with_model`]); what a front end flying a model by hand needs of it ([`model::pilot`]); its state and controls as named columns ([`model::ColumnModel`]) and what a learning agent's tasks need of it ([`model::AgentModel`]); one adapter module per model ([`model::palmer`], [`model::bourg`]) |
//! | [`report`] | what a run reports at its end: [`Report`] (JSON and a human summary) from a [`Snapshot`] ([`Run::snapshot`]), each model's own fields ([`ReportModel`]) |
//! | [`pacer`] | [`pacer::FramePacer`]: real-time pacing |

pub mod acmi;
pub mod csv;
#[cfg(feature = "dis")]
pub mod dis;
pub mod fgfs;
pub mod fleet;
pub mod flightgear;
pub mod flushable;
pub mod input;
pub mod links;
pub mod memory;
pub mod model;
pub mod multiplayer;
pub mod origin;
pub mod outfile;
pub mod output;
pub mod pacer;
pub mod recording;
pub mod replay;
pub mod report;
pub mod run;
pub mod scenario;
mod shared;
pub mod values;

pub use model::{FleetModel, NamedInputs, RegisteredModel, RunModel};
pub use output::{Event, Frame, LinkStats, Output, OutputError, Placement};
pub use report::{Report, ReportModel, Snapshot};
pub use run::{End, Run, RunError};
pub use scenario::{
    Scenario, ScenarioError, Start, StartOptions, StartRefused, MAX_FPS, MAX_FRAMES,
};
pub use shared::SharedOutput;
