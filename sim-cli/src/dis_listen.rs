//! `sim-cli dis-listen HOST:PORT`: receive DIS datagrams for a while, count
//! them and show every entity's last position (docs/dis.md, docs/cli.md).
//!
//! The datagrams go through [`fdm_dis::Listener`]: a datagram that does not
//! decode (too short, lengths that do not add up, a PDU dis-rs refuses or
//! even panics on) is counted as malformed and skipped; nothing a sender
//! puts on the network stops the listener. Memory is bounded: the socket
//! buffer is one 64 KiB datagram, and the entity table keeps at most
//! `--max-entities` entities (default [`DEFAULT_MAX_ENTITIES`], about 300
//! bytes each); PDUs of further entities are counted as untracked and not
//! stored.

use std::io::{self, Write};
use std::net::{SocketAddr, ToSocketAddrs, UdpSocket};
use std::time::{Duration, Instant};

use anyhow::Context as _;
use clap::Args;
use fdm_dis::{type_label, EntityRecord, Listener, ListenerStats};
use serde::{Deserialize, Serialize};

use crate::error::CliError;
use crate::input::{show_fixed, Echo};

/// Entities kept by default.
pub const DEFAULT_MAX_ENTITIES: u64 = 100_000;

/// Most entities `--max-entities` accepts (some 3 GB of table).
pub const MAX_MAX_ENTITIES: u64 = 10_000_000;

/// Longest `--seconds`: about 11.6 days.
pub const MAX_SECONDS: f64 = 1e6;

/// Receive buffer asked of the OS, bytes: bursts of PDUs (a fleet's first
/// frame sends one per aircraft at once) wait there while the listener decodes.
pub const RECEIVE_BUFFER_BYTES: usize = 4 << 20;

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

fn parse_seconds(text: &str) -> Result<f64, String> {
    match text.trim().parse::<f64>() {
        Ok(v) if v > 0.0 && v <= MAX_SECONDS => Ok(v),
        _ => Err(format!(
            "`{}` is not a number of seconds in (0, {MAX_SECONDS}]",
            Echo::short(text)
        )),
    }
}

fn parse_entities(text: &str) -> Result<u64, String> {
    match text.trim().parse::<u64>() {
        Ok(v) if (1..=MAX_MAX_ENTITIES).contains(&v) => Ok(v),
        _ => Err(format!(
            "`{}` is not a number of entities in 1..={MAX_MAX_ENTITIES}",
            Echo::short(text)
        )),
    }
}

/// One entity of the report: its last Entity State PDU, converted back to
/// geodetic terms.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct EntityReport {
    /// `site:application:entity`.
    pub id: String,
    /// Site number.
    pub site: u16,
    /// Application number.
    pub application: u16,
    /// Entity number.
    pub entity: u16,
    /// The marking as received (JSON escapes whatever it holds).
    pub marking: String,
    /// `kind.domain.country.category.subcategory.specific.extra`.
    pub entity_type: String,
    /// DIS protocol version of the last PDU.
    pub protocol_version: u8,
    /// Exercise id of the last PDU.
    pub exercise: u8,
    /// Entity State PDUs received for it.
    pub updates: u64,
    /// Latitude, degrees (WGS-84).
    pub lat_deg: f64,
    /// Longitude, degrees.
    pub lon_deg: f64,
    /// Height above the ellipsoid, metres.
    pub alt_m: f64,
    /// Heading, degrees clockwise from true north.
    pub heading_deg: f64,
    /// Pitch, degrees, nose up positive.
    pub pitch_deg: f64,
    /// Roll, degrees, right wing down positive.
    pub roll_deg: f64,
    /// Velocity, local north/east/down, m/s.
    pub velocity_ned_m_s: [f64; 3],
}

impl EntityReport {
    fn new(r: &EntityRecord) -> Self {
        Self {
            id: r.id.to_string(),
            site: r.id.site,
            application: r.id.application,
            entity: r.id.entity,
            marking: r.marking.clone(),
            entity_type: type_label(&r.entity_type),
            protocol_version: r.protocol_version,
            exercise: r.exercise_id,
            updates: r.updates,
            lat_deg: r.position.lat_deg,
            lon_deg: r.position.lon_deg,
            alt_m: r.position.alt_m,
            heading_deg: r.attitude.heading_deg,
            pitch_deg: r.attitude.pitch_deg,
            roll_deg: r.attitude.roll_deg,
            velocity_ned_m_s: r.velocity_ned_m_s.into(),
        }
    }
}

/// What `sim-cli dis-listen` prints (`--json`: this object).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ListenReport {
    /// The address listened on.
    pub address: String,
    /// How long it listened, seconds (wall clock).
    pub seconds: f64,
    /// Datagrams received, good or bad.
    pub datagrams: u64,
    /// Bytes in them.
    pub bytes: u64,
    /// PDUs decoded, all types.
    pub pdus: u64,
    /// Entity State PDUs among them.
    pub entity_state_pdus: u64,
    /// Datagrams that did not decode (counted and skipped).
    pub malformed_datagrams: u64,
    /// … of which made dis-rs panic (caught).
    pub decoder_panics: u64,
    /// Entity State PDUs of entities beyond `max_entities` (counted, not kept).
    pub untracked_entity_pdus: u64,
    /// Distinct entities kept.
    pub entity_count: u64,
    /// The table's bound.
    pub max_entities: u64,
    /// Every kept entity, ordered by id.
    pub entities: Vec<EntityReport>,
}

impl ListenReport {
    /// The report of `listener` after `seconds` on `address`.
    #[must_use]
    pub fn new(address: SocketAddr, seconds: f64, listener: &Listener) -> Self {
        let ListenerStats {
            datagrams,
            bytes,
            pdus,
            entity_state_pdus,
            malformed_datagrams,
            decoder_panics,
            untracked_entity_pdus,
        } = listener.stats();
        Self {
            address: address.to_string(),
            seconds,
            datagrams,
            bytes,
            pdus,
            entity_state_pdus,
            malformed_datagrams,
            decoder_panics,
            untracked_entity_pdus,
            entity_count: listener.entity_count() as u64,
            max_entities: listener.max_entities().map_or(u64::MAX, |m| m as u64),
            entities: listener.entities().map(EntityReport::new).collect(),
        }
    }

    /// The human form: a summary line, then one line per entity.
    #[must_use]
    pub fn human(&self) -> String {
        let mut s = format!(
            "dis-listen {} for {:.1} s: {} datagrams, {} bytes, {} PDUs ({} Entity State), \
             {} malformed, {} entities",
            self.address,
            self.seconds,
            self.datagrams,
            self.bytes,
            self.pdus,
            self.entity_state_pdus,
            self.malformed_datagrams,
            self.entity_count,
        );
        if self.untracked_entity_pdus > 0 {
            s.push_str(&format!(
                " (table full at {}: {} PDUs of further entities not kept)",
                self.max_entities, self.untracked_entity_pdus
            ));
        }
        if !self.entities.is_empty() {
            s.push_str(&format!(
                "\n{:<17} {:<11} {:<19} {:>12} {:>13} {:>9} {:>7} {:>6} {:>7} {:>7}",
                "ENTITY",
                "MARKING",
                "TYPE",
                "LAT",
                "LON",
                "ALT_M",
                "HDG",
                "PITCH",
                "ROLL",
                "UPDATES"
            ));
        }
        for e in &self.entities {
            s.push_str(&format!(
                "\n{:<17} {:<11} {:<19} {:>12} {:>13} {:>9} {:>7} {:>6} {:>7} {:>7}",
                e.id,
                Echo::new(&e.marking, 11).to_string(),
                e.entity_type,
                show_fixed(e.lat_deg, 7),
                show_fixed(e.lon_deg, 7),
                show_fixed(e.alt_m, 1),
                show_fixed(e.heading_deg, 2),
                show_fixed(e.pitch_deg, 2),
                show_fixed(e.roll_deg, 2),
                e.updates
            ));
        }
        s
    }
}

/// Binds `address` (resolved; the first address) with a large receive buffer.
///
/// # Errors
/// [`CliError::Usage`] for an address that does not resolve,
/// [`CliError::Runtime`] when it cannot be bound.
pub fn bind(address: &str) -> Result<UdpSocket, CliError> {
    let shown = Echo::short(address);
    let addr = address
        .to_socket_addrs()
        .map_err(|e| CliError::usage(format!("dis-listen {shown}: not a HOST:PORT address ({e})")))?
        .next()
        .ok_or_else(|| CliError::usage(format!("dis-listen {shown}: resolves to no address")))?;
    let socket = UdpSocket::bind(addr).with_context(|| format!("binding {addr}"))?;
    // Best effort: the OS may cap it (net.core.rmem_max); the listener works
    // with any size, a small one only drops more of a burst.
    #[cfg(unix)]
    let _ = rustix::net::sockopt::set_socket_recv_buffer_size(&socket, RECEIVE_BUFFER_BYTES);
    Ok(socket)
}

/// Receives on `socket` into `listener` until `seconds` have passed or
/// `until_entities` entities are known. Returns the seconds spent.
///
/// # Errors
/// [`CliError::Runtime`] for a socket error other than a timeout.
pub fn listen(
    socket: &UdpSocket,
    listener: &mut Listener,
    seconds: f64,
    until_entities: Option<u64>,
) -> Result<f64, CliError> {
    let start = Instant::now();
    let limit = Duration::from_secs_f64(seconds);
    let mut buf = vec![0u8; 65_536];
    loop {
        if until_entities.is_some_and(|n| listener.entity_count() as u64 >= n) {
            break;
        }
        // Ctrl-C (or any handled signal) ends the listening: the report of
        // what was received so far is printed (crate::signals).
        if crate::signals::stop_requested().is_some() {
            break;
        }
        let elapsed = start.elapsed();
        if elapsed >= limit {
            break;
        }
        let wait = (limit - elapsed).clamp(Duration::from_millis(1), Duration::from_millis(200));
        socket
            .set_read_timeout(Some(wait))
            .context("setting the socket timeout")?;
        match socket.recv_from(&mut buf) {
            // A malformed datagram is counted by the listener and skipped.
            Ok((n, _)) => {
                let _ = listener.ingest(&buf[..n]);
            }
            Err(e)
                if matches!(
                    e.kind(),
                    io::ErrorKind::WouldBlock
                        | io::ErrorKind::TimedOut
                        | io::ErrorKind::Interrupted
                        | io::ErrorKind::ConnectionRefused
                        | io::ErrorKind::ConnectionReset
                ) => {}
            Err(e) => return Err(anyhow::Error::new(e).context("receiving").into()),
        }
    }
    Ok(start.elapsed().as_secs_f64())
}

/// `sim-cli dis-listen`: bind, say where on stderr, listen, print the report.
///
/// # Errors
/// See [`bind`] and [`listen`]; writing to stdout can fail too.
pub fn run(args: &DisListenArgs) -> Result<(), CliError> {
    let socket = bind(&args.address)?;
    let local = socket.local_addr().context("reading the bound address")?;
    eprintln!(
        "sim-cli: listening for DIS on {local} for {} s",
        crate::input::show_number(args.seconds)
    );
    let max = usize::try_from(args.max_entities).unwrap_or(usize::MAX);
    let mut listener = Listener::with_max_entities(max);
    let seconds = listen(&socket, &mut listener, args.seconds, args.until_entities)?;
    let report = ListenReport::new(local, seconds, &listener);
    let text = if args.json {
        serde_json::to_string(&report).context("encoding the report")?
    } else {
        report.human()
    };
    let mut out = io::stdout().lock();
    writeln!(out, "{text}")
        .and_then(|()| out.flush())
        .context("writing to stdout")?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn garbage_is_counted_and_skipped_and_the_report_is_valid_json() {
        let socket = bind("127.0.0.1:0").unwrap();
        let addr = socket.local_addr().unwrap();
        let sender = UdpSocket::bind("127.0.0.1:0").unwrap();
        let mut header = vec![7u8, 1, 1, 1, 0, 0, 0, 0, 0, 144, 0, 0];
        header.resize(144, 0xFF);
        for datagram in [&b""[..], b"\x07", &[0u8; 12], &header] {
            sender.send_to(datagram, addr).unwrap();
        }
        let mut listener = Listener::with_max_entities(10);
        // Four datagrams arrive well within 2 s on loopback; the loop stops on time.
        let secs = listen(&socket, &mut listener, 0.5, None).unwrap();
        assert!(secs >= 0.5);
        let r = ListenReport::new(addr, secs, &listener);
        assert_eq!(r.datagrams, 4);
        assert_eq!(r.malformed_datagrams + r.pdus, 4, "{r:?}");
        assert!(r.malformed_datagrams >= 3, "{r:?}");
        assert_eq!(r.max_entities, 10);
        let json = serde_json::to_string(&r).unwrap();
        let back: ListenReport = serde_json::from_str(&json).unwrap();
        assert_eq!(back.datagrams, 4);
        assert!(r.human().starts_with("dis-listen 127.0.0.1:"));
    }

    /// An entity sent from absurd places (1e308 m up, a latitude of
    /// -1e300 degrees) prints in the short number form, never as 300-digit
    /// numbers; ordinary values keep the table's fixed decimals.
    #[test]
    fn the_table_prints_huge_numbers_short() {
        let entity = EntityReport {
            id: "1:2:3".into(),
            site: 1,
            application: 2,
            entity: 3,
            marking: "X".into(),
            entity_type: "1.2.225.1.0.0.0".into(),
            protocol_version: 7,
            exercise: 1,
            updates: 1,
            lat_deg: -1e300,
            lon_deg: 7.25,
            alt_m: 1e308,
            heading_deg: 90.0,
            pitch_deg: 0.0,
            roll_deg: f64::MAX,
            velocity_ned_m_s: [0.0; 3],
        };
        let report = ListenReport {
            address: "127.0.0.1:3000".into(),
            seconds: 1.0,
            datagrams: 1,
            bytes: 144,
            pdus: 1,
            entity_state_pdus: 1,
            malformed_datagrams: 0,
            decoder_panics: 0,
            untracked_entity_pdus: 0,
            entity_count: 1,
            max_entities: 10,
            entities: vec![entity],
        };
        let human = report.human();
        let row = human.lines().last().unwrap();
        assert!(row.len() < 200, "{row}");
        for cell in ["-1e300", "7.2500000", "1e308", "90.00", "0.00"] {
            assert!(row.split_whitespace().any(|c| c == cell), "{cell}: {row}");
        }
    }

    #[test]
    fn bad_options() {
        assert!(parse_seconds("0").is_err());
        assert!(parse_seconds("nan").is_err());
        assert!(parse_seconds("1e7").is_err());
        assert_eq!(parse_seconds("2.5"), Ok(2.5));
        assert!(parse_entities("0").is_err());
        assert_eq!(parse_entities("2000"), Ok(2000));
        assert_eq!(bind("nonsense").unwrap_err().exit_code(), 2);
    }
}
