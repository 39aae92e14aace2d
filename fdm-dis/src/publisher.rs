//! One aircraft's DIS output: its configuration, its dead-reckoning model and
//! a reusable encode buffer, behind one call per frame; and a UDP sender.

use std::net::{SocketAddr, ToSocketAddrs, UdpSocket};
use std::sync::atomic::{AtomicBool, Ordering};

use bytes::BytesMut;

use crate::dead_reckoning::{DeadReckoner, DrThresholds, SendReason};
use crate::entity::{
    encode_entity_state, rewrite_entity_state, EntityConfig, WireState, ENTITY_STATE_PDU_LEN,
};
use crate::error::DisOutputError;
use crate::frames::{AircraftState, EcefState};

/// Counts kept by an [`EntityPublisher`].
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct PublisherCounts {
    /// Frames given to [`EntityPublisher::update`].
    pub frames: u64,
    /// PDUs produced, all reasons.
    pub sent: u64,
    /// … of which the first one or after a clock reset.
    pub first_or_reset: u64,
    /// … because the position error passed its threshold.
    pub position: u64,
    /// … because the orientation error passed its threshold.
    pub orientation: u64,
    /// … because the heartbeat was due.
    pub heartbeat: u64,
}

/// A PDU that is due, borrowed from the publisher's buffer.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Due<'a> {
    /// Why it is due.
    pub reason: SendReason,
    /// The encoded Entity State PDU, ready for one UDP datagram.
    pub bytes: &'a [u8],
}

/// One aircraft's DIS Entity State output.
///
/// A shell calls [`EntityPublisher::update`] once per frame with the
/// aircraft's state; when it returns bytes, it sends them (for example with
/// [`UdpSender`]). One publisher per aircraft: each keeps its own
/// dead-reckoning model.
#[derive(Debug, Clone)]
pub struct EntityPublisher {
    config: EntityConfig,
    reckoner: DeadReckoner,
    buf: BytesMut,
    /// `buf` holds a PDU [`encode_entity_state`] wrote for `config`: the
    /// next one is that PDU rewritten ([`rewrite_entity_state`]).
    encoded: bool,
    counts: PublisherCounts,
}

impl EntityPublisher {
    /// A publisher that has sent nothing yet.
    ///
    /// # Errors
    /// As [`DrThresholds::validate`].
    pub fn new(config: EntityConfig, thresholds: DrThresholds) -> Result<Self, DisOutputError> {
        let reckoner = DeadReckoner::new(config.dr_algorithm, thresholds)?;
        Ok(Self {
            config,
            reckoner,
            buf: BytesMut::with_capacity(ENTITY_STATE_PDU_LEN),
            encoded: false,
            counts: PublisherCounts::default(),
        })
    }

    /// The configuration.
    #[must_use]
    pub fn config(&self) -> &EntityConfig {
        &self.config
    }

    /// The dead-reckoning model (what receivers last got, the thresholds).
    #[must_use]
    pub fn reckoner(&self) -> &DeadReckoner {
        &self.reckoner
    }

    /// The counts so far.
    #[must_use]
    pub fn counts(&self) -> PublisherCounts {
        self.counts
    }

    /// Takes this frame's state; returns the PDU to send if one is due
    /// (and then assumes it is sent: receivers extrapolate from it from now
    /// on).
    ///
    /// # Errors
    /// An invalid state ([`AircraftState::validate`]) or an encoding failure;
    /// the model is unchanged then.
    pub fn update(&mut self, state: &AircraftState) -> Result<Option<Due<'_>>, DisOutputError> {
        let ecef = state.to_ecef()?;
        self.update_ecef(&ecef)
    }

    /// Reads a few fields spread over the publisher's memory and a byte of
    /// each cache line of its PDU buffer, mixed (see `Tracker::warm`).
    pub(crate) fn warm(&self) -> u64 {
        let r = &self.reckoner;
        let sent = r
            .last_sent()
            .map_or(0, |w| w.time_s.to_bits() ^ w.location_m.z.to_bits());
        let m = r.last_sent_body_to_ecef();
        let buf = [0, 64, 128].map(|k| u64::from(self.buf.get(k).copied().unwrap_or(0)));
        sent ^ m[(0, 0)].to_bits()
            ^ m[(2, 2)].to_bits()
            ^ r.thresholds().position_m.to_bits()
            ^ self.counts.frames
            ^ buf[0]
            ^ (buf[1] << 8)
            ^ (buf[2] << 16)
    }

    /// Counts a frame that [`DeadReckoner::check_at`](crate::DeadReckoner::check_at)
    /// found nothing due for (what [`EntityPublisher::update_ecef`] counts
    /// for such a frame).
    pub(crate) fn count_quiet_frame(&mut self) {
        self.count_quiet_frames(1);
    }

    /// Counts `n` such frames at once (the fleet screen's).
    pub(crate) fn count_quiet_frames(&mut self, n: u64) {
        self.counts.frames += n;
    }

    /// [`EntityPublisher::update`] for a state already in ECEF.
    ///
    /// # Errors
    /// A non-finite state ([`EcefState::validate`]) or an encoding failure;
    /// the model is unchanged then.
    pub fn update_ecef(&mut self, ecef: &EcefState) -> Result<Option<Due<'_>>, DisOutputError> {
        ecef.validate()?;
        let ecef = *ecef;
        self.counts.frames += 1;
        let Some(reason) = self.reckoner.check(&ecef) else {
            return Ok(None);
        };
        let wire = WireState::new(&ecef, self.config.dr_algorithm);
        // The first PDU through dis-rs; the next ones rewrite its bytes
        // (the configuration does not change, so neither does the rest).
        let pdu: Option<&mut [u8; ENTITY_STATE_PDU_LEN]> = if self.encoded {
            (&mut self.buf[..]).try_into().ok()
        } else {
            None
        };
        let n = if let Some(pdu) = pdu {
            rewrite_entity_state(pdu, &wire);
            ENTITY_STATE_PDU_LEN
        } else {
            let n = encode_entity_state(&self.config, &wire, &mut self.buf)?;
            self.encoded = n == ENTITY_STATE_PDU_LEN && self.buf.len() == n;
            n
        };
        self.reckoner.record_sent(wire);
        self.counts.sent += 1;
        match reason {
            SendReason::First | SendReason::ClockReset => self.counts.first_or_reset += 1,
            SendReason::PositionError => self.counts.position += 1,
            SendReason::OrientationError => self.counts.orientation += 1,
            SendReason::Heartbeat => self.counts.heartbeat += 1,
        }
        Ok(Some(Due {
            reason,
            bytes: &self.buf[..n],
        }))
    }
}

/// A UDP socket that sends datagrams to one address (unicast or broadcast;
/// the tests use 127.0.0.1 only).
///
/// A fleet's due datagrams of one size go out several to a system call
/// where the OS can split them (`UdpSender::send_segments`: UDP generic
/// segmentation offload on Linux); the receivers get the same datagrams.
#[derive(Debug)]
pub struct UdpSender {
    socket: UdpSocket,
    target: SocketAddr,
    /// Whether [`UdpSender::send_segments`] still tries the OS's
    /// segmentation (cleared the first time the OS refuses it).
    segmenting: AtomicBool,
}

/// The most datagrams the OS is asked to split one buffer into: Linux's
/// `UDP_MAX_SEGMENTS` (64 since 4.18, when UDP segmentation came).
pub(crate) const MAX_SEGMENTS: usize = 64;

/// The most bytes of one segmented buffer: a UDP payload's limit over IPv4
/// (65,507) rounded down.
const MAX_SEGMENTED_BYTES: usize = 65_000;

/// How many datagrams of `len` bytes one call of
/// [`UdpSender::send_segments`] may carry (at least 1).
pub(crate) fn segments_for(len: usize) -> usize {
    MAX_SEGMENTED_BYTES
        .checked_div(len)
        .map_or(1, |n| n.clamp(1, MAX_SEGMENTS))
}

impl UdpSender {
    /// Binds an ephemeral local port and aims at `target` (DIS's customary
    /// port is 3000). Broadcast is enabled when `broadcast` is true.
    ///
    /// # Errors
    /// [`DisOutputError::Io`] if the address does not resolve or the socket
    /// cannot be made.
    pub fn new(target: impl ToSocketAddrs, broadcast: bool) -> Result<Self, DisOutputError> {
        let io = |e: std::io::Error| DisOutputError::Io(e.to_string());
        let target = target
            .to_socket_addrs()
            .map_err(io)?
            .next()
            .ok_or_else(|| DisOutputError::Io("address resolves to nothing".into()))?;
        // A loopback target gets a loopback source: nothing is opened on
        // other interfaces then.
        let local: SocketAddr = match (target.is_ipv4(), target.ip().is_loopback()) {
            (true, true) => (std::net::Ipv4Addr::LOCALHOST, 0).into(),
            (true, false) => (std::net::Ipv4Addr::UNSPECIFIED, 0).into(),
            (false, true) => (std::net::Ipv6Addr::LOCALHOST, 0).into(),
            (false, false) => (std::net::Ipv6Addr::UNSPECIFIED, 0).into(),
        };
        let socket = UdpSocket::bind(local).map_err(io)?;
        socket.set_broadcast(broadcast).map_err(io)?;
        Ok(Self {
            socket,
            target,
            segmenting: AtomicBool::new(cfg!(target_os = "linux")),
        })
    }

    /// The destination.
    #[must_use]
    pub fn target(&self) -> SocketAddr {
        self.target
    }

    /// Sends one datagram.
    ///
    /// # Errors
    /// [`DisOutputError::Io`] from the socket.
    pub fn send(&self, datagram: &[u8]) -> Result<usize, DisOutputError> {
        self.socket
            .send_to(datagram, self.target)
            .map_err(|e| DisOutputError::Io(e.to_string()))
    }

    /// A sender whose every send fails: an IPv4 loopback socket aimed at an
    /// IPv6 address (the tests' failing sends; nothing leaves the host).
    #[cfg(test)]
    pub(crate) fn failing() -> Self {
        Self {
            socket: UdpSocket::bind("127.0.0.1:0").unwrap(),
            target: "[::1]:9".parse().unwrap(),
            segmenting: AtomicBool::new(true),
        }
    }

    /// Stops [`UdpSender::send_segments`] from trying the OS's segmentation
    /// (the tests' way to the one-by-one path on Linux).
    #[cfg(test)]
    pub(crate) fn stop_segmenting(&self) {
        self.segmenting.store(false, Ordering::Relaxed);
    }

    /// Sends `datagrams`, consecutive datagrams of `len` bytes each (at most
    /// [`segments_for`]`(len)` of them, the last possibly shorter), in one
    /// system call that the OS splits into those datagrams (Linux's UDP
    /// generic segmentation offload, `UDP_SEGMENT`): the receivers get the
    /// same datagrams, in order, as from one [`UdpSender::send`] each,
    /// for a fraction of the kernel's work per datagram (one socket lookup,
    /// route and copy for all of them).
    ///
    /// Returns the bytes sent, or `None` when it sent nothing: the OS has no
    /// such segmentation (not Linux, a kernel before 4.18, a device that
    /// refuses it: then it is not tried again on this sender), or the send
    /// failed. The caller then sends them one by one, which also reports
    /// each datagram's own error.
    pub(crate) fn send_segments(&self, datagrams: &[u8], len: usize) -> Option<usize> {
        if !self.segmenting.load(Ordering::Relaxed) || len == 0 || datagrams.len() <= len {
            return None;
        }
        let segment = u16::try_from(len).ok()?;
        match segmented::send(&self.socket, self.target, datagrams, segment) {
            Ok(n) => Some(n),
            Err(e) => {
                if segmented::unsupported(&e) {
                    self.segmenting.store(false, Ordering::Relaxed);
                }
                None
            }
        }
    }
}

/// Due datagrams of one size queued to go to the OS together
/// ([`UdpSender::send_segments`]), for a fleet's frame: up to
/// [`segments_for`] of them, sent when the queue is full, when a datagram of
/// another size comes, or at [`DatagramQueue::flush`]. Each datagram's
/// result goes to the caller's `sent` (the bytes sent, or the error of its
/// own send when the OS could not take them together), in order.
#[derive(Debug, Clone, Default)]
pub(crate) struct DatagramQueue {
    /// The queued datagrams, end to end.
    bytes: Vec<u8>,
    /// Each one's length.
    len: usize,
    /// How many.
    count: usize,
}

impl DatagramQueue {
    /// Whether nothing is queued.
    pub(crate) const fn is_empty(&self) -> bool {
        self.count == 0
    }

    /// Queues `datagram` (first sending what is queued if its size
    /// differs), and sends the queue if that fills it.
    pub(crate) fn push(
        &mut self,
        sender: &UdpSender,
        datagram: &[u8],
        mut sent: impl FnMut(Result<usize, DisOutputError>),
    ) {
        if self.count > 0 && self.len != datagram.len() {
            self.flush(sender, &mut sent);
        }
        self.len = datagram.len();
        self.bytes.extend_from_slice(datagram);
        self.count += 1;
        if self.count >= segments_for(self.len) {
            self.flush(sender, &mut sent);
        }
    }

    /// Sends what is queued: in one call where the OS segments it, else one
    /// datagram at a time.
    pub(crate) fn flush(
        &mut self,
        sender: &UdpSender,
        mut sent: impl FnMut(Result<usize, DisOutputError>),
    ) {
        if self.count == 0 {
            return;
        }
        let together = sender.send_segments(&self.bytes, self.len).is_some();
        for datagram in self.bytes.chunks(self.len) {
            sent(if together {
                Ok(datagram.len())
            } else {
                sender.send(datagram)
            });
        }
        // The buffer is kept for the next datagrams.
        self.bytes.clear();
        self.len = 0;
        self.count = 0;
    }
}

/// UDP segmentation offload: one `sendmsg` with a `UDP_SEGMENT` control
/// message (Linux 4.18 and later), through nix's safe wrappers.
#[cfg(target_os = "linux")]
mod segmented {
    use std::io::IoSlice;
    use std::net::{SocketAddr, UdpSocket};
    use std::os::fd::AsRawFd;

    use nix::errno::Errno;
    use nix::sys::socket::{sendmsg, ControlMessage, MsgFlags, SockaddrStorage};

    /// Sends `buf` to `to` as datagrams of `segment` bytes.
    pub(super) fn send(
        socket: &UdpSocket,
        to: SocketAddr,
        buf: &[u8],
        segment: u16,
    ) -> Result<usize, Errno> {
        let to = SockaddrStorage::from(to);
        sendmsg(
            socket.as_raw_fd(),
            &[IoSlice::new(buf)],
            &[ControlMessage::UdpGsoSegments(&segment)],
            MsgFlags::empty(),
            Some(&to),
        )
    }

    /// Whether `e` says the OS or the device cannot segment (rather than
    /// that the datagrams could not be sent).
    pub(super) fn unsupported(e: &Errno) -> bool {
        matches!(
            e,
            Errno::EINVAL | Errno::ENOPROTOOPT | Errno::EOPNOTSUPP | Errno::EIO
        )
    }
}

/// No UDP segmentation offload off Linux: every datagram is its own send.
#[cfg(not(target_os = "linux"))]
mod segmented {
    use std::net::{SocketAddr, UdpSocket};

    /// Never sends (the caller sends one datagram at a time).
    pub(super) fn send(
        _socket: &UdpSocket,
        _to: SocketAddr,
        _buf: &[u8],
        _segment: u16,
    ) -> Result<usize, std::io::Error> {
        Err(std::io::ErrorKind::Unsupported.into())
    }

    /// Always (nothing to try again).
    pub(super) fn unsupported(_e: &std::io::Error) -> bool {
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A publisher's PDUs are [`encode_entity_state`]'s of what it sent,
    /// byte for byte, from the first (through dis-rs) to the last
    /// (rewritten from the one before): an aircraft turning and climbing
    /// with every frame due (thresholds of 1 µm and 1e-6°), the clock going back once
    /// (a reset: first PDU again) and a state that cannot be sent between,
    /// under each dead-reckoning model and both DIS versions.
    #[test]
    fn every_pdu_is_the_encoders() {
        use crate::entity::{AircraftKind, DisVersion, DrAlgorithm, EntityIdentity, Marking};
        use fdm_core::geodesy::{Attitude, Geodetic};
        use nalgebra::Vector3;
        let mut checked = 0;
        for (alg, version) in [
            (DrAlgorithm::Fpw, DisVersion::V6),
            (DrAlgorithm::Rpw, DisVersion::V7),
            (DrAlgorithm::Rvw, DisVersion::V7),
            (DrAlgorithm::Fvw, DisVersion::V6),
        ] {
            let mut config = EntityConfig::new(
                EntityIdentity::new(3, 9, 77).unwrap(),
                AircraftKind::CESSNA_172_SKYHAWK,
                Marking::new("DIS144").unwrap(),
            );
            config.dr_algorithm = alg;
            config.version = version;
            config.exercise_id = 9;
            let thresholds = DrThresholds {
                position_m: 1e-6,
                orientation_deg: 1e-6,
                heartbeat_s: 5.0,
            };
            let mut publisher = EntityPublisher::new(config.clone(), thresholds).unwrap();
            for frame in 0..120_u32 {
                let f = f64::from(frame);
                let time = if frame < 60 { 3590.0 + f } else { f - 60.0 };
                let mut state = AircraftState::new(
                    time,
                    Geodetic {
                        lat_deg: 39.8 + 1e-4 * f,
                        lon_deg: -84.0 - 2e-4 * f,
                        alt_m: 500.0 + 3.0 * f,
                    },
                    Attitude {
                        heading_deg: 7.0 * f,
                        pitch_deg: 5.0 - 0.1 * f,
                        roll_deg: 30.0 * (0.1 * f).sin(),
                    },
                    Vector3::new(40.0 + f, -3.0 * f, -1.0),
                );
                state.angular_velocity_body_rad_s = Some(Vector3::new(0.01 * f, -0.02, 0.1));
                state.acceleration_ned_m_s2 = Some(Vector3::new(0.5, -0.25 * f, 0.125));
                if frame == 30 {
                    state.velocity_ned_m_s.x = f64::NAN;
                    assert!(publisher.update(&state).is_err());
                    continue;
                }
                let bytes = publisher.update(&state).unwrap().unwrap().bytes.to_vec();
                let wire = *publisher.reckoner().last_sent().unwrap();
                let mut want = BytesMut::new();
                encode_entity_state(&config, &wire, &mut want).unwrap();
                assert_eq!(bytes, &want[..], "{alg:?} {version:?} frame {frame}");
                checked += 1;
            }
        }
        assert_eq!(checked, 4 * 119);
    }

    /// The queue holds a run of datagrams of one size until 64 fill it (then
    /// they go together), sends the run before a datagram of another size,
    /// and sends what it holds at `flush`: every datagram reaches the
    /// receiver once, in order, each result reported once.
    #[test]
    fn the_queue_holds_a_run_of_one_size_until_it_is_full() {
        let rx = UdpSocket::bind("127.0.0.1:0").unwrap();
        rx.set_read_timeout(Some(std::time::Duration::from_secs(5)))
            .unwrap();
        let sender = UdpSender::new(rx.local_addr().unwrap(), false).unwrap();
        let datagram = |k: usize, len: usize| vec![k as u8; len];
        let mut queue = DatagramQueue::default();
        let mut sent = Vec::new();
        let mut expected = Vec::new();
        let mut push = |queue: &mut DatagramQueue, sent: &mut Vec<usize>, d: Vec<u8>| {
            queue.push(&sender, &d, |r| sent.push(r.unwrap()));
            expected.push(d);
        };
        for k in 0..63 {
            push(&mut queue, &mut sent, datagram(k, 144));
        }
        assert_eq!((queue.count, queue.len, sent.len()), (63, 144, 0));
        assert!(!queue.is_empty());
        push(&mut queue, &mut sent, datagram(63, 144));
        assert_eq!((queue.count, sent.len()), (0, 64));
        assert!(queue.is_empty());
        push(&mut queue, &mut sent, datagram(64, 144));
        push(&mut queue, &mut sent, datagram(65, 144));
        assert_eq!((queue.count, sent.len()), (2, 64));
        push(&mut queue, &mut sent, datagram(66, 100));
        assert_eq!((queue.count, queue.len, sent.len()), (1, 100, 66));
        queue.flush(&sender, |r| sent.push(r.unwrap()));
        queue.flush(&sender, |r| sent.push(r.unwrap()));
        assert_eq!((queue.count, queue.len, sent.len()), (0, 0, 67));
        let lens: Vec<usize> = expected.iter().map(Vec::len).collect();
        assert_eq!(sent, lens);
        let mut buf = [0_u8; 256];
        for d in &expected {
            let n = rx.recv(&mut buf).unwrap();
            assert_eq!(&buf[..n], &d[..]);
        }
    }
}
