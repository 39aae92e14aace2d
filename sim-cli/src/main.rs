//! `sim-cli`: fly Palmer's Cessna 172 or Bourg's 6-DoF aircraft (see the library docs).
//!
//! This file only maps outcomes to exit statuses (docs/cli.md): 0 success, 2 bad usage or
//! input, 1 anything else, always with at most one `sim-cli: error: ...` line on
//! stderr and never a panic message or backtrace for user errors. A run ended by
//! SIGTERM, SIGHUP, SIGINT or SIGQUIT exits with 128 + the signal number after
//! the run has finished its outputs and restored the terminal (`sim_cli::signals`).

use std::panic::{self, AssertUnwindSafe};
use std::process::ExitCode;

use clap::error::ErrorKind;
use clap::Parser;
use sim_cli::args::Cli;

fn main() -> ExitCode {
    sim_cli::terminal::install_panic_hook();
    // The hook has already restored the terminal and printed one line; a panic is
    // a bug, which the contract files under "any other failure".
    panic::catch_unwind(AssertUnwindSafe(real_main)).unwrap_or(ExitCode::from(1))
}

fn real_main() -> ExitCode {
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) if matches!(e.kind(), ErrorKind::DisplayHelp | ErrorKind::DisplayVersion) => {
            // Help and version go to stdout with status 0.
            return match e.print() {
                Ok(()) => ExitCode::SUCCESS,
                Err(_) => ExitCode::from(1),
            };
        }
        Err(e) => {
            eprintln!("sim-cli: error: {}", sim_cli::clap_error_line(&e));
            return ExitCode::from(2);
        }
    };
    // A stdout that is /dev/null (even opened read-write, as Python's
    // `subprocess.DEVNULL`, Node's `stdio: 'ignore'` and systemd's `StandardOutput=null`
    // hand it over, or put in place by the runtime for a closed descriptor 1) is the
    // caller's decision to discard it: the run goes on normally (docs/cli.md).
    // SIGTERM/SIGHUP/SIGINT/SIGQUIT: the run stops at the next frame, finishes its
    // outputs and restores the terminal; exit 128+N (below).
    if let Err(e) = sim_cli::signals::install() {
        eprintln!("sim-cli: warning: cannot watch for signals ({e}); a signal will not restore the terminal");
    }
    let outcome = sim_cli::run(cli);
    if let Err(e) = &outcome {
        eprintln!("sim-cli: error: {}", e.one_line());
    }
    // A signal ended the run early; its outputs are finished (the loops stop at
    // the next frame): the status says how it ended, as a shell would.
    if let Some(signal) = sim_cli::signals::stop_requested() {
        eprintln!(
            "{}sim-cli: stopped by {}",
            sim_cli::progress::line_start(),
            sim_cli::signals::signal_name(signal)
        );
        return ExitCode::from(u8::try_from(sim_cli::signals::exit_status(signal)).unwrap_or(1));
    }
    match outcome {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => ExitCode::from(e.exit_code()),
    }
}
