//! `sim-cli dis-listen HOST:PORT`: receive DIS datagrams for a while, count
//! them and show every entity's last position (docs/dis.md, docs/cli.md).
//!
//! The listening and the report are the library's ([`fdm_dis::listen`]):
//! a datagram that does not decode (too short, lengths that do not add up,
//! a PDU dis-rs refuses or even panics on) is counted as malformed and
//! skipped; nothing a sender puts on the network stops the listener. Memory
//! is bounded: the socket buffer is one 64 KiB datagram, and the entity
//! table keeps at most `--max-entities` entities (default
//! [`DEFAULT_MAX_ENTITIES`], about 300 bytes each); PDUs of further
//! entities are counted as untracked and not stored. Here are the
//! arguments, the messages and the printing.

use std::net::UdpSocket;

use anyhow::Context as _;
use clap::Args;
use fdm_dis::listen::{ListenError, ListenReport};
use fdm_dis::Listener;

pub use fdm_dis::listen::DEFAULT_MAX_ENTITIES;

use crate::error::CliError;
use crate::input::Echo;
use fdm_run::values::ValueError;

/// Most entities `--max-entities` accepts (some 3 GB of table).
pub const MAX_MAX_ENTITIES: u64 = 10_000_000;

/// Longest `--seconds`: about 11.6 days.
pub const MAX_SECONDS: f64 = 1e6;

/// `sim-cli dis-listen`.
#[derive(Debug, Clone, Args)]
pub struct DisListenArgs {
    /// Address to receive on, e.g. 127.0.0.1:3000 (port 0: any free port, printed on stderr)
    #[arg(value_name = "HOST:PORT")]
    pub address: String,

    /// How long to listen, seconds
    #[arg(long, value_name = "N", default_value_t = 10.0, value_parser = parse_seconds)]
    pub seconds: f64,

    /// Stop as soon as this many distinct entities have been seen (still at most --seconds)
    #[arg(long, value_name = "N", value_parser = parse_entities)]
    pub until_entities: Option<u64>,

    /// Most entities kept in the table; PDUs of further entities are counted, not stored
    #[arg(long, value_name = "N", default_value_t = DEFAULT_MAX_ENTITIES, value_parser = parse_entities)]
    pub max_entities: u64,

    /// Print the result as one JSON object on stdout
    #[arg(long)]
    pub json: bool,
}

fn parse_seconds(text: &str) -> Result<f64, ValueError> {
    fdm_run::values::parse_seconds(text, MAX_SECONDS)
}

fn parse_entities(text: &str) -> Result<u64, ValueError> {
    fdm_run::values::parse_whole(text, 1, MAX_MAX_ENTITIES, "a number of entities")
}

/// A listening error as the CLI reports it: a bad address is a usage error
/// naming it (`dis-listen ADDRESS: not a HOST:PORT address (...)`), the rest
/// run-time errors.
fn cli_error(address: &str, e: ListenError) -> CliError {
    if e.is_bad_address() {
        CliError::usage(format!("dis-listen {}: {e}", Echo::short(address)))
    } else {
        CliError::Runtime(anyhow::Error::new(e))
    }
}

/// Binds `address` ([`fdm_dis::listen::bind`]).
///
/// # Errors
/// [`CliError::Usage`] for an address that does not resolve,
/// [`CliError::Runtime`] when it cannot be bound.
pub fn bind(address: &str) -> Result<UdpSocket, CliError> {
    fdm_dis::listen::bind(address).map_err(|e| cli_error(address, e))
}

/// `sim-cli dis-listen`: bind, say where on stderr, listen until the time,
/// the entity count or a signal (crate::signals: the report of what was
/// received so far is printed), print the report.
///
/// # Errors
/// See [`bind`] and [`fdm_dis::listen::listen`]; writing to stdout can fail too.
pub fn run(args: &DisListenArgs) -> Result<(), CliError> {
    let socket = bind(&args.address)?;
    let local = socket.local_addr().context("reading the bound address")?;
    eprintln!(
        "sim-cli: listening for DIS on {local} for {} s",
        crate::input::show_number(args.seconds)
    );
    let max = usize::try_from(args.max_entities).unwrap_or(usize::MAX);
    let mut listener = Listener::with_max_entities(max);
    let stop = || crate::signals::stop_requested().is_some();
    let seconds = fdm_dis::listen::listen(
        &socket,
        &mut listener,
        args.seconds,
        args.until_entities,
        stop,
    )
    .map_err(|e| cli_error(&args.address, e))?;
    let report = ListenReport::new(local, seconds, &listener);
    let text = if args.json {
        serde_json::to_string(&report).context("encoding the report")?
    } else {
        report.human()
    };
    crate::print_line(&text)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bad_options() {
        assert!(parse_seconds("0").is_err());
        assert!(parse_seconds("nan").is_err());
        assert!(parse_seconds("1e7").is_err());
        assert_eq!(parse_seconds("2.5"), Ok(2.5));
        assert!(parse_entities("0").is_err());
        assert_eq!(parse_entities("2000"), Ok(2000));
        assert_eq!(bind("nonsense").unwrap_err().exit_code(), 2);
        assert!(bind("nonsense")
            .unwrap_err()
            .to_string()
            .starts_with("dis-listen nonsense: not a HOST:PORT address ("));
    }
}
