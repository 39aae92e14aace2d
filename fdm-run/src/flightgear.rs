//! The FlightGear native-FDM link as an output of a run: every flown frame,
//! one FGNetFDM v24 datagram (408 bytes, `fgnet`) to one FlightGear started
//! with `--fdm=null --native-fdm=socket,in,FPS,HOST,PORT,udp`
//! (docs/fgnetfdm.md).
//!
//! [`FlightGearOutput`] is what the thesis's MakePacket and SendPacket
//! systems did inside the ECS: the datagram is made from the frame's
//! [`FlightView`] and the [`Placement`] the ECS computed once for every
//! output (`fgnet::bridge::packet_at`, the same bytes as
//! `fgnet::bridge::display`), and sent through a connected
//! [`fgnet::Sender`]. It sends on [`Event::Step`] only (attaching and
//! resetting send nothing, as before), and nothing for a diverged frame: no
//! datagram ever carries a NaN or an infinity.
//!
//! # Why here, and why the output owns its socket
//!
//! `fgnet` is the wire format (datagram, sender, bridge): it knows no run.
//! The output that joins a run's [`Frame`] to it lives in the run library,
//! like DIS's (`fdm_run::dis`, feature `dis`), so the ECS core (`fdm-ecs`) no longer
//! depends on `fgnet` and the run loop does not change for it. No feature
//! gates it: `fgnet` needs nothing beyond the workspace's Rust 1.89 and the
//! run library already placed aircraft with it.
//!
//! The sender's socket is *connected*: it reports "connection refused"
//! (FlightGear not listening) for its own target, which a socket shared by
//! many targets could not attribute; it closes when the output is dropped.
//!
//! ```
//! use fdm_core::palmer::Palmer;
//! use fdm_run::flightgear::FlightGearOutput;
//! use fdm_run::{Run, Scenario, SharedOutput, Start};
//!
//! # let fg = std::net::UdpSocket::bind("127.0.0.1:0")?;
//! # let addr = fg.local_addr()?.to_string();
//! let scenario = Scenario::<Palmer>::new(Start::thesis(), 30, 3)?;
//! let link = SharedOutput::new(FlightGearOutput::connect(&addr, scenario.origin)?);
//! let mut run = Run::new(scenario)?;
//! run.attach(link.clone())?;
//! run.run_to_end()?;
//! let stats = link.with(|o| o.map(|o| o.stats())).unwrap();
//! assert_eq!((stats.sent, stats.failed), (3, 0));
//! # let mut buf = [0u8; 512];
//! # assert_eq!(fg.recv(&mut buf)?, 408);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

use std::io;

use fdm_core::geodesy::GeodeticOrigin;
use fdm_core::model::{FlightStatus, FlightView, Model};
use fgnet::{FgNetFdm, SendOutcome, Sender, SenderError};

use crate::output::{Event, Frame, LinkStats, Output, OutputError, Placement};

/// One aircraft's FlightGear native-FDM link: an [`Output`] sending one
/// datagram per flown frame, counting sends and failures ([`Self::stats`])
/// and keeping the first failure for the caller to report once
/// ([`Self::take_failure`]). A failed send never stops the run.
#[derive(Debug)]
pub struct FlightGearOutput {
    sender: Sender,
    origin: GeodeticOrigin,
    packet: Option<FgNetFdm>,
    first_failure: Option<String>,
}

impl FlightGearOutput {
    /// Opens a UDP socket sending to `addr` (`"HOST:PORT"`, e.g.
    /// `"127.0.0.1:5500"`; see [`Sender::connect`]) for a run whose model
    /// frame sits at `origin` (the run's [`Scenario::origin`](crate::Scenario)).
    /// Nothing is sent yet, so this succeeds whether or not FlightGear
    /// listens.
    ///
    /// # Errors
    /// [`SenderError`] when the address does not resolve or the socket
    /// cannot be set up.
    pub fn connect(addr: &str, origin: GeodeticOrigin) -> Result<Self, SenderError> {
        Sender::connect(addr).map(|sender| Self::new(sender, origin))
    }

    /// An output sending through an existing `sender`.
    #[must_use]
    pub const fn new(sender: Sender, origin: GeodeticOrigin) -> Self {
        Self {
            sender,
            origin,
            packet: None,
            first_failure: None,
        }
    }

    /// The datagram of `view` placed at `placement` (what
    /// [`Output::frame`] sends): `fgnet::bridge::packet_at`.
    #[must_use]
    pub fn packet(view: &FlightView, origin: &GeodeticOrigin, placement: &Placement) -> FgNetFdm {
        fgnet::bridge::packet_at(view, origin, placement.geodetic, placement.attitude)
    }

    /// Datagrams sent and failed so far.
    #[must_use]
    pub fn stats(&self) -> LinkStats {
        let stats = self.sender.stats();
        LinkStats {
            sent: stats.sent,
            failed: stats.failed,
        }
    }

    /// The first failed send as a one-line message (target, frame, error),
    /// once: later calls return `None`, later failures are only counted.
    pub fn take_failure(&mut self) -> Option<String> {
        self.first_failure.take()
    }

    /// The last datagram sent or attempted (`None` before the first flown
    /// frame).
    #[must_use]
    pub const fn last_packet(&self) -> Option<&FgNetFdm> {
        self.packet.as_ref()
    }

    /// The sender.
    #[must_use]
    pub const fn sender(&self) -> &Sender {
        &self.sender
    }

    /// The message for the first failure, on frame `flown` of the run.
    fn failure_message(&self, flown: u64, error: &io::Error) -> String {
        format!(
            "sending to {} failed on frame {flown}: {error}; the run goes on and counts failures",
            self.sender.peer()
        )
    }
}

impl<M: Model> Output<M> for FlightGearOutput {
    /// Sends the frame's datagram on [`Event::Step`] unless the aircraft
    /// diverged; a failed send is counted (the first kept for
    /// [`FlightGearOutput::take_failure`]), never an error.
    fn frame(&mut self, frame: &Frame<'_, M>) -> Result<(), OutputError> {
        if frame.event != Event::Step || frame.status == FlightStatus::Diverged {
            return Ok(());
        }
        let packet = Self::packet(frame.view, &self.origin, frame.placement);
        if let SendOutcome::FirstFailure(error) = self.sender.send(&packet) {
            self.first_failure = Some(self.failure_message(frame.flown, &error));
        }
        self.packet = Some(packet);
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{Run, Scenario, SharedOutput, Start};
    use fdm_core::palmer::Palmer;

    /// Each flown frame's datagram, as FlightGear receives it, is the
    /// frame's `fgnet::bridge::display` packet (the run's own view and
    /// origin, placed again from scratch), and `last_packet` is the last one
    /// sent; none is sent at the start or a reset.
    #[test]
    fn each_flown_frame_sends_the_display_packet_of_its_view() {
        let fg = std::net::UdpSocket::bind("127.0.0.1:0").unwrap();
        fg.set_read_timeout(Some(std::time::Duration::from_secs(5)))
            .unwrap();
        let scenario = Scenario::<Palmer>::new(Start::thesis(), 30, 3).unwrap();
        let origin = scenario.origin;
        let link = SharedOutput::new(
            FlightGearOutput::connect(&fg.local_addr().unwrap().to_string(), origin).unwrap(),
        );
        let mut run = Run::new(scenario).unwrap();
        run.attach(link.clone()).unwrap();
        assert!(link.with(|o| o.unwrap().last_packet().is_none()));
        let mut buf = [0_u8; 512];
        for flown in 1..=4 {
            if flown == 3 {
                run.reset().unwrap();
            }
            run.step_frame(&[]).unwrap();
            let n = fg.recv(&mut buf).unwrap();
            let got = FgNetFdm::decode(&buf[..n]).unwrap();
            let want = fgnet::bridge::display(&run.view(), &origin).packet;
            assert_eq!(got.encode(), want.encode(), "frame {flown}");
            let last = link.with(|o| o.unwrap().last_packet().copied()).unwrap();
            assert_eq!(last.encode(), want.encode(), "frame {flown}");
            assert_eq!(
                FlightGearOutput::packet(&run.view(), &origin, &run.placement()).encode(),
                want.encode()
            );
        }
        // Four flown frames, four datagrams: the reset sent none.
        fg.set_nonblocking(true).unwrap();
        assert!(fg.recv(&mut buf).is_err());
        let stats = link.with(|o| o.unwrap().stats());
        assert_eq!((stats.sent, stats.failed), (4, 0));
    }
}
