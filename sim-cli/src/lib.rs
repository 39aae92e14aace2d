//! `sim-cli`: fly Palmer's Cessna 172 or Bourg's 6-DoF aircraft from the keyboard
//! into FlightGear, or headless from scripts. The contract is `docs/cli.md`.
//!
//! The binary (`main.rs`) only maps [`run()`]'s result to an exit status; everything
//! else lives in this library so it can be unit-tested. Everything is generic over
//! the model (`models::CliModel`); what differs per model is the run library's
//! (`fdm_run::model`: its adapter modules, and what a front end needs of a model,
//! `fdm_run::model::pilot`), or, for a model outside the library crates (the
//! `glider` feature's), one module under `models`.
//!
//! | module | what |
//! |---|---|
//! | [`args`] | clap definition; the values' parsers and limits are the run library's (`fdm_run::values`) |
//! | `input` | input files (the run library's `fdm_run::input`) refused as usage errors, clashing outputs refused |
//! | `config` | cross-option validation, script loading, the output files created → `config::ModelConfig` (the run library's scenario, the mode, the outputs) |
//! | `models` | the registry (the run library's models, then the CLI's own: the `glider` feature's module) and `models::CliModel`, what the CLI flies: the run library's `PilotModel` (start options, keys, HUD line), `FleetModel` and `StudyModel` |
//! | [`run`](mod@run) | the [`run::Flight`] seam, [`run::headless`] and [`run::interactive`] loops, [`run::fly`] |
//! | `flight` | `flight::ModelFlight`: one aircraft of any model flown by an `fdm_run::Run` with its outputs; `flight::run_model` |
//! | `snapshot`, `report` | the aircraft's state at one instant ([`snapshot::Snapshot`]), the JSON [`report::Report`] and the human summary: the run library's ([`fdm_run::report`]) |
//! | [`csv`] | `--csv`: the run library's CSV output ([`fdm_run::csv::CsvOutput`] of [`fdm_run::csv::FlightRow`]s) and its errors |
//! | `hud`, `keys`, `pacer`, [`terminal`], [`progress`] | interactive and progress plumbing |
//! | `fgfs`, `origin` | `fgfs-command` (the line is `fdm_run::fgfs`'s; `--fg` is parsed by `fgnet::address`), `--origin` |
//! | `fleet` | `sim-cli fleet`: the flags as a fleet run of the run library (`fdm_run::fleet`), progress, the report printed |
//! | `fleet_mp` | `sim-cli fleet --fg-mp`: the flags of a fleet streamed to FlightGear as multiplayer aircraft (`fdm_run::fleet::show`) |
//! | `recording`, `replay` | `--record FILE` flight logs and `sim-cli replay FILE` |
//! | `acmi` | `--acmi FILE`: Tacview ACMI through the run library |
//! | `plot` | `--plot FILE.svg` and `sim-cli plot`: the output file and the CSV read back; the drawing is `fdm_plot`'s |
//! | `study` | `sim-cli study FILE.toml`: Monte Carlo studies (fdm-study: flying, memory check, summary), `--run I`, `study.svg` (drawn by `fdm_plot::study`) |
//! | `dis`, `dis_listen` | `--dis`: DIS Entity State PDUs for one aircraft or a fleet; `sim-cli dis-listen` |
//!
//! Public are only the modules the binary and the tests use ([`args`], [`error`], [`run`](mod@run),
//! [`signals`], [`progress`], [`terminal`], [`csv`]); the domain is the libraries' (`fdm_run`,
//! `fdm_study`, `fdm_plot`, `fdm_dis`).

mod acmi;
pub mod args;
mod config;
pub mod csv;
mod dis;
mod dis_listen;
pub mod error;
mod fgfs;
mod fleet;
mod fleet_mp;
mod flight;
mod hud;
mod input;
mod keys;
mod memory;
mod models;
mod origin;
mod pacer;
mod plot;
pub mod progress;
mod recording;
mod replay;
mod report;
pub mod run;
pub mod signals;
mod snapshot;
mod start;
mod study;
pub mod terminal;

use std::io::Write;

use anyhow::Context as _;

use crate::args::{Cli, Command};
use crate::error::CliError;

/// Executes a parsed command line.
///
/// # Errors
/// `CliError::Usage` for bad input (exit 2), `CliError::Runtime` otherwise (exit 1).
pub fn run(cli: Cli) -> Result<(), CliError> {
    match cli.command {
        Command::Fly(fly) => flight::fly_model(&fly),
        Command::Fleet(args) => fleet::run(&args),
        Command::Replay(args) => replay::run(&args),
        Command::Plot(args) => plot::run_plot(&args.csv, &args.output),
        Command::Study(args) => study::run(&args),
        Command::DisListen(args) => dis_listen::run(&args),
        Command::FgfsCommand(args) => print_line(&fgfs::fgfs_command_line(&args)?),
    }
}

/// Writes `text` and a newline to stdout, turning a closed pipe into an error
/// instead of the panic `println!` would raise.
pub(crate) fn print_line(text: &str) -> Result<(), CliError> {
    print_line_to(&mut std::io::stdout().lock(), text, "stdout")
}

/// Writes a run's report `text` and a newline to stdout, or to stderr when
/// an output of the run writes stdout ([`config::summary_on_stderr`]).
pub(crate) fn print_report(text: &str, on_stderr: bool) -> Result<(), CliError> {
    if on_stderr {
        print_line_to(&mut std::io::stderr().lock(), text, "stderr")
    } else {
        print_line(text)
    }
}

/// Writes `text` and a newline to `out` (named `name` in the error).
fn print_line_to(out: &mut impl Write, text: &str, name: &str) -> Result<(), CliError> {
    writeln!(out, "{text}")
        .and_then(|()| out.flush())
        .with_context(|| format!("writing to {name}"))?;
    Ok(())
}

/// clap's multi-paragraph error text reduced to one line: the error itself plus any
/// `tip:` lines, without the usage block (the message ends by pointing to `--help`).
#[must_use]
pub fn clap_error_line(error: &clap::Error) -> String {
    if error.kind() == clap::error::ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand {
        // clap renders the whole help here; one line is the contract.
        let models = models::ModelKind::ALL.iter().map(|kind| kind.name());
        let names: Vec<&str> = models
            .chain(["fgfs-command", "fleet", "study", "plot"])
            .collect();
        return format!(
            "missing subcommand: {}, replay or dis-listen (see --help)",
            names.join(", ")
        );
    }
    let text = error.render().to_string();
    let mut parts = Vec::new();
    for paragraph in text.split("\n\n") {
        let paragraph = paragraph.trim();
        if paragraph.is_empty()
            || paragraph.starts_with("Usage:")
            || paragraph.starts_with("For more information")
        {
            continue;
        }
        parts.push(error::one_line(paragraph));
    }
    let joined = parts.join("; ");
    let message = joined.strip_prefix("error: ").unwrap_or(&joined);
    format!("{message} (see --help)")
}

#[cfg(test)]
mod tests {
    use super::*;
    use clap::Parser;

    #[test]
    fn clap_errors_become_one_line() {
        let err = Cli::try_parse_from(["sim-cli", "palmer", "--fps", "0"]).unwrap_err();
        assert_eq!(
            clap_error_line(&err),
            "invalid value '0' for '--fps <N>': must be a whole number from 1 to 10000 (see --help)"
        );
        let err = Cli::try_parse_from(["sim-cli", "palmer", "--fp", "3"]).unwrap_err();
        let line = clap_error_line(&err);
        assert!(!line.contains('\n'));
        assert!(
            line.starts_with("unexpected argument '--fp' found; tip:"),
            "{line}"
        );
        let err = Cli::try_parse_from(["sim-cli"]).unwrap_err();
        // The models' subcommands are the registry's (the `glider` feature adds one).
        let models = if cfg!(feature = "glider") {
            "palmer, bourg, glider"
        } else {
            "palmer, bourg"
        };
        assert_eq!(
            clap_error_line(&err),
            format!("missing subcommand: {models}, fgfs-command, fleet, study, plot, replay or dis-listen (see --help)")
        );
    }
}
