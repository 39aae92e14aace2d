//! Listening on a UDP socket for a while: bind ([`bind`]), receive into a
//! [`Listener`] until a time or an entity count is reached ([`listen`]), and
//! summarise what arrived ([`ListenReport`]: JSON through serde, or a
//! human table). What `sim-cli dis-listen` does (docs/dis.md, docs/cli.md).
//!
//! Memory is bounded when the listener is ([`Listener::with_max_entities`]):
//! the receive buffer is one 64 KiB datagram; nothing a sender puts on the
//! network stops the listening (a datagram that does not decode is counted
//! as malformed and skipped).

use std::io;
use std::net::{SocketAddr, ToSocketAddrs, UdpSocket};
use std::time::{Duration, Instant};

use fdm_core::script::Echo;
use serde::{Deserialize, Serialize};
use thiserror::Error;

use crate::entity::type_label;
use crate::listener::{EntityRecord, Listener, ListenerStats};

/// Entities a listener keeps by default (`sim-cli dis-listen
/// --max-entities`), about 300 bytes each.
pub const DEFAULT_MAX_ENTITIES: u64 = 100_000;

/// Receive buffer asked of the OS, bytes: bursts of PDUs (a fleet's first
/// frame sends one per aircraft at once) wait there while the listener decodes.
pub const RECEIVE_BUFFER_BYTES: usize = 4 << 20;

/// Largest datagram received whole, bytes (a UDP datagram's limit).
pub const DATAGRAM_BUFFER_BYTES: usize = 65_536;

/// Why listening could not start or went on failing.
#[derive(Debug, Error)]
pub enum ListenError {
    /// The address did not parse or resolve.
    #[error("not a HOST:PORT address ({0})")]
    NotAnAddress(io::Error),
    /// The address resolved to nothing.
    #[error("resolves to no address")]
    NoAddress,
    /// The socket could not be bound.
    #[error("binding {address}")]
    Bind {
        /// The resolved address.
        address: SocketAddr,
        /// What the OS said.
        #[source]
        source: io::Error,
    },
    /// The bound socket's address could not be read.
    #[error("reading the bound address")]
    LocalAddress(#[source] io::Error),
    /// The receive timeout could not be set.
    #[error("setting the socket timeout")]
    Timeout(#[source] io::Error),
    /// Receiving failed with an error other than a timeout.
    #[error("receiving")]
    Receive(#[source] io::Error),
}

impl ListenError {
    /// Whether the address itself was refused (the caller's input), rather
    /// than the OS failing on a good one.
    #[must_use]
    pub fn is_bad_address(&self) -> bool {
        matches!(self, Self::NotAnAddress(_) | Self::NoAddress)
    }
}

/// Binds `address` (`HOST:PORT`, resolved; the first address) with a large
/// receive buffer ([`RECEIVE_BUFFER_BYTES`], best effort: the OS may cap it).
///
/// # Errors
/// [`ListenError::NotAnAddress`] or [`ListenError::NoAddress`] for an
/// address that does not resolve, [`ListenError::Bind`] when it cannot be
/// bound.
pub fn bind(address: &str) -> Result<UdpSocket, ListenError> {
    let address = address
        .to_socket_addrs()
        .map_err(ListenError::NotAnAddress)?
        .next()
        .ok_or(ListenError::NoAddress)?;
    let socket =
        UdpSocket::bind(address).map_err(|source| ListenError::Bind { address, source })?;
    // Best effort: the OS may cap it (net.core.rmem_max); the listener works
    // with any size, a small one only drops more of a burst.
    #[cfg(unix)]
    let _ = rustix::net::sockopt::set_socket_recv_buffer_size(&socket, RECEIVE_BUFFER_BYTES);
    Ok(socket)
}

/// Receives on `socket` into `listener` until `seconds` have passed,
/// `until_entities` entities are known, or `stop()` says so (checked at
/// least every 200 ms; e.g. a signal handler's flag). Returns the seconds
/// spent. A datagram that does not decode is counted by the listener and
/// skipped; a refused or reset connection (ICMP from an earlier send on the
/// socket) is ignored.
///
/// # Errors
/// [`ListenError::Timeout`] or [`ListenError::Receive`] for a socket error
/// other than a timeout.
pub fn listen(
    socket: &UdpSocket,
    listener: &mut Listener,
    seconds: f64,
    until_entities: Option<u64>,
    stop: impl FnMut() -> bool,
) -> Result<f64, ListenError> {
    listen_from(socket, listener, seconds, until_entities, stop)
}

/// Where [`listen`] receives datagrams: a UDP socket, or in the tests a
/// source whose receive fails as a socket rarely can on demand.
trait DatagramSource {
    /// Waits at most `wait` in the next [`Self::receive`].
    fn set_wait(&self, wait: Duration) -> io::Result<()>;
    /// One datagram into `buf`: its length.
    fn receive(&self, buf: &mut [u8]) -> io::Result<usize>;
}

impl DatagramSource for UdpSocket {
    fn set_wait(&self, wait: Duration) -> io::Result<()> {
        self.set_read_timeout(Some(wait))
    }

    fn receive(&self, buf: &mut [u8]) -> io::Result<usize> {
        self.recv_from(buf).map(|(n, _)| n)
    }
}

/// [`listen`] on any [`DatagramSource`].
fn listen_from(
    source: &impl DatagramSource,
    listener: &mut Listener,
    seconds: f64,
    until_entities: Option<u64>,
    mut stop: impl FnMut() -> bool,
) -> Result<f64, ListenError> {
    let start = Instant::now();
    let limit = Duration::try_from_secs_f64(seconds).unwrap_or(Duration::ZERO);
    let mut buf = vec![0u8; DATAGRAM_BUFFER_BYTES];
    loop {
        if until_entities.is_some_and(|n| listener.entity_count() as u64 >= n) {
            break;
        }
        if stop() {
            break;
        }
        let elapsed = start.elapsed();
        if elapsed >= limit {
            break;
        }
        let wait = (limit - elapsed).clamp(Duration::from_millis(1), Duration::from_millis(200));
        source.set_wait(wait).map_err(ListenError::Timeout)?;
        match source.receive(&mut buf) {
            // A malformed datagram is counted by the listener and skipped.
            Ok(n) => {
                let _ = listener.ingest(&buf[..n]);
            }
            Err(e) if goes_on_after(e.kind()) => {}
            Err(e) => return Err(ListenError::Receive(e)),
        }
    }
    Ok(start.elapsed().as_secs_f64())
}

/// Whether [`listen`] goes on after a receive that failed with `kind`: the
/// read timeout ran out (`WouldBlock` or `TimedOut`, by platform), a signal
/// interrupted the call, or the socket got an ICMP refusal or reset for an
/// earlier send. Anything else is the socket failing: listening stops.
fn goes_on_after(kind: io::ErrorKind) -> bool {
    matches!(
        kind,
        io::ErrorKind::WouldBlock
            | io::ErrorKind::TimedOut
            | io::ErrorKind::Interrupted
            | io::ErrorKind::ConnectionRefused
            | io::ErrorKind::ConnectionReset
    )
}

/// One entity of a [`ListenReport`]: its last Entity State PDU, converted
/// back to geodetic terms.
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
    /// The report of one entity the listener keeps.
    #[must_use]
    pub fn new(r: &EntityRecord) -> Self {
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

/// What a listening session received: the counts and every kept entity
/// (`sim-cli dis-listen` prints it; `--json`: this object).
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
    /// The table's bound (`u64::MAX` when unbounded).
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

    /// The human form: a summary line (which says, when the entity table
    /// was full, its size and how many PDUs of further entities were not
    /// kept), then, if any entity arrived, a header line and a table of one
    /// line per entity (markings escaped and cut to 11 characters; numbers
    /// with fixed decimals, or in the short scientific form when that would
    /// exceed 24 characters).
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
                fixed(e.lat_deg, 7),
                fixed(e.lon_deg, 7),
                fixed(e.alt_m, 1),
                fixed(e.heading_deg, 2),
                fixed(e.pitch_deg, 2),
                fixed(e.roll_deg, 2),
                e.updates
            ));
        }
        s
    }
}

/// `value` with `decimals` decimals, as in a table column, unless that is
/// longer than 24 characters: then scientific notation (`1e308`, not 309
/// digits).
fn fixed(value: f64, decimals: usize) -> String {
    let fixed = format!("{value:.decimals$}");
    if fixed.len() <= 24 {
        fixed
    } else {
        format!("{value:e}")
    }
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
        let secs = listen(&socket, &mut listener, 0.5, None, || false).unwrap();
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

    /// The summary line alone without entities; with them, a header line
    /// and one line each; the full table's note only when PDUs of further
    /// entities were not kept.
    #[test]
    fn the_human_form_has_a_table_only_with_entities_and_a_note_only_when_full() {
        let entity = EntityReport {
            id: "1:2:3".into(),
            site: 1,
            application: 2,
            entity: 3,
            marking: "N172".into(),
            entity_type: "1.2.225.85.11.1.0".into(),
            protocol_version: 7,
            exercise: 1,
            updates: 4,
            lat_deg: 39.8,
            lon_deg: -84.0,
            alt_m: 300.0,
            heading_deg: 90.0,
            pitch_deg: 1.0,
            roll_deg: -2.0,
            velocity_ned_m_s: [50.0, 0.0, 0.0],
        };
        let empty = ListenReport {
            address: "127.0.0.1:3000".into(),
            seconds: 2.0,
            datagrams: 0,
            bytes: 0,
            pdus: 0,
            entity_state_pdus: 0,
            malformed_datagrams: 0,
            decoder_panics: 0,
            untracked_entity_pdus: 0,
            entity_count: 0,
            max_entities: 1,
            entities: vec![],
        };
        let human = empty.human();
        assert_eq!(human.lines().count(), 1, "{human}");
        assert!(!human.contains("table full"), "{human}");

        let two = ListenReport {
            entities: vec![entity.clone(), entity],
            entity_count: 2,
            max_entities: 2,
            ..empty.clone()
        };
        let human = two.human();
        let lines: Vec<&str> = human.lines().collect();
        assert_eq!(lines.len(), 4, "{human}");
        assert!(lines[1].starts_with("ENTITY"), "{human}");
        assert!(lines[2].starts_with("1:2:3") && lines[3].starts_with("1:2:3"));
        assert!(!human.contains("table full"), "{human}");

        let full = ListenReport {
            untracked_entity_pdus: 5,
            ..two
        };
        let human = full.human();
        assert_eq!(human.lines().count(), 4, "{human}");
        assert!(
            human
                .lines()
                .next()
                .unwrap()
                .ends_with(" (table full at 2: 5 PDUs of further entities not kept)"),
            "{human}"
        );
    }

    #[test]
    fn fixed_falls_back_to_the_short_form() {
        assert_eq!(fixed(1.5, 2), "1.50");
        assert_eq!(fixed(-1e308, 1), "-1e308");
        assert_eq!(fixed(f64::MAX, 7), format!("{:e}", f64::MAX));
    }

    #[test]
    fn a_bad_address_is_the_callers() {
        let err = bind("nonsense").unwrap_err();
        assert!(err.is_bad_address(), "{err:?}");
        assert!(err.to_string().starts_with("not a HOST:PORT address ("));
    }

    /// An address that resolves but cannot be bound (a port already taken)
    /// is not the caller's address mistake: `is_bad_address` is false for
    /// the OS's refusals, true only for addresses that do not resolve.
    #[test]
    fn a_taken_port_is_not_a_bad_address() {
        let taken = bind("127.0.0.1:0").unwrap();
        let err = bind(&taken.local_addr().unwrap().to_string()).unwrap_err();
        assert!(matches!(err, ListenError::Bind { .. }), "{err:?}");
        assert!(!err.is_bad_address(), "{err:?}");
        assert!(ListenError::NoAddress.is_bad_address());
        for other in [
            ListenError::LocalAddress(io::Error::other("x")),
            ListenError::Timeout(io::Error::other("x")),
            ListenError::Receive(io::Error::other("x")),
        ] {
            assert!(!other.is_bad_address(), "{other:?}");
        }
    }

    /// The receive errors listening goes on after (a timeout, a signal, an
    /// ICMP refusal or reset for an earlier send) and some it stops on.
    #[test]
    fn listening_goes_on_only_after_timeouts_signals_and_icmp() {
        use io::ErrorKind as K;
        for kind in [
            K::WouldBlock,
            K::TimedOut,
            K::Interrupted,
            K::ConnectionRefused,
            K::ConnectionReset,
        ] {
            assert!(goes_on_after(kind), "{kind:?}");
        }
        for kind in [
            K::PermissionDenied,
            K::InvalidInput,
            K::NotConnected,
            K::OutOfMemory,
            K::Other,
        ] {
            assert!(!goes_on_after(kind), "{kind:?}");
        }
    }

    /// A receive that fails with an error other than a timeout, a signal or
    /// an ICMP refusal or reset ends the listening with that error at once
    /// (not after the time is up); one that fails with those goes on.
    #[test]
    fn a_failing_socket_ends_the_listening_with_its_error() {
        use std::cell::Cell;
        struct Failing {
            kind: io::ErrorKind,
            receives: Cell<u32>,
        }
        impl DatagramSource for Failing {
            fn set_wait(&self, _: Duration) -> io::Result<()> {
                Ok(())
            }
            fn receive(&self, _: &mut [u8]) -> io::Result<usize> {
                self.receives.set(self.receives.get() + 1);
                std::thread::sleep(Duration::from_millis(1));
                Err(io::Error::new(self.kind, "planted"))
            }
        }
        let failing = Failing {
            kind: io::ErrorKind::PermissionDenied,
            receives: Cell::new(0),
        };
        let mut listener = Listener::new();
        let err = listen_from(&failing, &mut listener, 10.0, None, || false).unwrap_err();
        assert!(
            matches!(&err, ListenError::Receive(e) if e.kind() == io::ErrorKind::PermissionDenied),
            "{err:?}"
        );
        assert_eq!(failing.receives.get(), 1);

        let refused = Failing {
            kind: io::ErrorKind::ConnectionRefused,
            receives: Cell::new(0),
        };
        let secs = listen_from(&refused, &mut listener, 0.05, None, || false).unwrap();
        assert!(secs >= 0.05 && refused.receives.get() > 1, "{secs}");
    }

    /// Listening for `seconds` with nothing arriving returns when they have
    /// passed, not a whole wait later: the last wait is cut to what is
    /// left (0.25 s is one 200 ms wait and one of about 50 ms; a last wait
    /// of a full 200 ms would end near 0.4 s). Bounded on both sides, with
    /// room for a loaded machine's late wake-ups.
    #[test]
    fn listening_ends_when_the_time_is_up() {
        let socket = bind("127.0.0.1:0").unwrap();
        let mut listener = Listener::new();
        let secs = listen(&socket, &mut listener, 0.25, None, || false).unwrap();
        assert!((0.25..0.36).contains(&secs), "{secs}");
    }

    #[test]
    fn stop_ends_the_listening_at_once() {
        let socket = bind("127.0.0.1:0").unwrap();
        let mut listener = Listener::new();
        let secs = listen(&socket, &mut listener, 100.0, None, || true).unwrap();
        assert!(secs < 1.0, "{secs}");
    }
}
