//! A UDP sender of datagrams to FlightGear's `--native-fdm=socket,in,...,udp`.

use std::io;
use std::net::{Ipv4Addr, Ipv6Addr, SocketAddr, ToSocketAddrs, UdpSocket};

use thiserror::Error;

use crate::fdm::{FgNetFdm, DATAGRAM_LEN};

/// Why [`Sender::connect`] could not set up a sender. Every variant names the
/// address string it was given.
#[derive(Debug, Error)]
pub enum SenderError {
    /// The address is not `HOST:PORT`, or the host name did not resolve.
    #[error("cannot resolve FlightGear address {addr:?} (expected HOST:PORT, e.g. 127.0.0.1:5500): {source}")]
    Resolve {
        /// The address as given.
        addr: String,
        /// The resolver's error.
        source: io::Error,
    },
    /// The host name resolved to no address at all.
    #[error("FlightGear address {addr:?} resolved to no socket address")]
    NoAddress {
        /// The address as given.
        addr: String,
    },
    /// Creating, binding, connecting or configuring the local UDP socket failed.
    #[error("cannot open a UDP socket to FlightGear at {addr:?} ({resolved}): {source}")]
    Socket {
        /// The address as given.
        addr: String,
        /// The socket address it resolved to.
        resolved: SocketAddr,
        /// The operating system's error.
        source: io::Error,
    },
}

/// Counters of a [`Sender`] since it was created.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct SenderStats {
    /// Datagrams the operating system accepted in full. UDP gives no
    /// delivery guarantee: this does not mean FlightGear received them.
    pub sent: u64,
    /// Datagrams that were not sent (any error, a would-block on a full
    /// socket buffer, or a short write).
    pub failed: u64,
    /// The subset of `failed` that were `ECONNREFUSED`, i.e. an earlier
    /// datagram drew an ICMP port-unreachable: nobody listens at the address.
    pub refused: u64,
}

/// What happened to one datagram passed to [`Sender::send`].
///
/// Only the first failure in the sender's life carries the error; later
/// failures are only counted (see [`Sender::stats`]), so a simulation that
/// logs [`SendOutcome::FirstFailure`] logs once, not once per frame.
#[derive(Debug)]
pub enum SendOutcome {
    /// The whole 408-byte datagram was handed to the operating system.
    Sent,
    /// The first datagram this sender failed to send, with the error
    /// (`ConnectionRefused` when nobody listens on the port).
    FirstFailure(io::Error),
    /// A later datagram failed; the failure is counted in [`Sender::stats`].
    Failed,
}

impl SendOutcome {
    /// Whether the datagram was handed to the operating system.
    pub const fn is_sent(&self) -> bool {
        matches!(self, Self::Sent)
    }
}

/// Sends [`FgNetFdm`] datagrams over UDP to one `HOST:PORT`, e.g. FlightGear
/// started with `--native-fdm=socket,in,30,127.0.0.1,5500,udp`.
///
/// The socket is bound to an ephemeral local port and *connected* to the
/// target, so only one address is used and the kernel reports an ICMP
/// port-unreachable back as `ECONNREFUSED`. On Linux such an error is returned
/// by the send *after* the datagram that drew it and then cleared, so with
/// nobody listening roughly every other send fails. The socket is
/// non-blocking, so a full send buffer drops the datagram (counted as failed)
/// instead of stalling the simulation. [`send`](Self::send) never panics and
/// never returns an error that would stop the simulation: it returns a
/// [`SendOutcome`] and counts in [`stats`](Self::stats).
///
/// ```
/// use fgnet::{FgNetFdm, SendOutcome, Sender};
///
/// let receiver = std::net::UdpSocket::bind("127.0.0.1:0").unwrap();
/// let mut sender = Sender::connect(&receiver.local_addr().unwrap().to_string()).unwrap();
/// assert!(sender.send(&FgNetFdm::new()).is_sent());
///
/// let mut buf = [0u8; 1024];
/// let (len, _) = receiver.recv_from(&mut buf).unwrap();
/// assert_eq!(len, 408);
/// assert_eq!(sender.stats().sent, 1);
/// ```
#[derive(Debug)]
pub struct Sender {
    socket: UdpSocket,
    peer: SocketAddr,
    buf: [u8; DATAGRAM_LEN],
    stats: SenderStats,
    reported_failure: bool,
}

impl Sender {
    /// Opens a UDP socket that sends to `addr` (`"HOST:PORT"`, e.g.
    /// `"127.0.0.1:5500"` or `"localhost:5500"`).
    ///
    /// If the host resolves to several addresses the first IPv4 one is used,
    /// because FlightGear's native-FDM socket is IPv4 only; an IPv6 address
    /// is used only when there is no IPv4 one. Nothing is sent, so this
    /// succeeds whether or not anybody listens.
    ///
    /// # Errors
    /// [`SenderError`] naming `addr` when it cannot be parsed or resolved,
    /// resolves to nothing, or the local socket cannot be set up.
    pub fn connect(addr: &str) -> Result<Self, SenderError> {
        let resolved: Vec<SocketAddr> = addr
            .to_socket_addrs()
            .map_err(|source| SenderError::Resolve {
                addr: addr.to_owned(),
                source,
            })?
            .collect();
        let peer = resolved
            .iter()
            .find(|a| a.is_ipv4())
            .or_else(|| resolved.first())
            .copied()
            .ok_or_else(|| SenderError::NoAddress {
                addr: addr.to_owned(),
            })?;
        let socket_err = |source| SenderError::Socket {
            addr: addr.to_owned(),
            resolved: peer,
            source,
        };
        let local: SocketAddr = if peer.is_ipv4() {
            (Ipv4Addr::UNSPECIFIED, 0).into()
        } else {
            (Ipv6Addr::UNSPECIFIED, 0).into()
        };
        let socket = UdpSocket::bind(local).map_err(socket_err)?;
        socket.connect(peer).map_err(socket_err)?;
        socket.set_nonblocking(true).map_err(socket_err)?;
        Ok(Self {
            socket,
            peer,
            buf: [0; DATAGRAM_LEN],
            stats: SenderStats::default(),
            reported_failure: false,
        })
    }

    /// Encodes `fdm` (counts clamped, see [`FgNetFdm::encode`]) and sends it
    /// as one 408-byte datagram.
    ///
    /// Returns [`SendOutcome::FirstFailure`] with the error for the first
    /// datagram that fails in this sender's life and [`SendOutcome::Failed`]
    /// for every later one; all are counted in [`stats`](Self::stats).
    pub fn send(&mut self, fdm: &FgNetFdm) -> SendOutcome {
        fdm.encode_into(&mut self.buf);
        let error = match self.socket.send(&self.buf) {
            Ok(DATAGRAM_LEN) => {
                self.stats.sent += 1;
                return SendOutcome::Sent;
            }
            Ok(n) => io::Error::new(
                io::ErrorKind::WriteZero,
                format!("short UDP write: {n} of {DATAGRAM_LEN} bytes"),
            ),
            Err(e) => e,
        };
        self.stats.failed += 1;
        if error.kind() == io::ErrorKind::ConnectionRefused {
            self.stats.refused += 1;
        }
        if self.reported_failure {
            SendOutcome::Failed
        } else {
            self.reported_failure = true;
            SendOutcome::FirstFailure(error)
        }
    }

    /// Counts of sent and failed datagrams so far.
    pub const fn stats(&self) -> SenderStats {
        self.stats
    }

    /// The socket address datagrams go to.
    pub const fn peer(&self) -> SocketAddr {
        self.peer
    }

    /// The local address of the sending socket.
    ///
    /// # Errors
    /// The operating system's error, if it cannot report the address.
    pub fn local_addr(&self) -> io::Result<SocketAddr> {
        self.socket.local_addr()
    }
}
