//! SendPacket: an entity with a FlightGear link sends exactly one 408-byte
//! datagram per frame, the packet MakePacket built that frame; an entity
//! without a link sends nothing; send failures are counted, reported once, and
//! do not stop the simulation.

use fdm_core::bourg::Bourg;
use fdm_core::palmer::Palmer;
use std::io::ErrorKind;
use std::net::UdpSocket;
use std::sync::Arc;
use std::time::Duration;

use fdm_core::bourg::{BourgAircraft, BourgControls, BourgState};
use fdm_core::palmer::{PalmerAircraft, PalmerControls, PalmerState};
use fdm_ecs::{FlightGearLink, Resources, Simulation};
use fgnet::{FgNetFdm, DATAGRAM_LEN};

fn receiver() -> (UdpSocket, String) {
    let socket = UdpSocket::bind("127.0.0.1:0").unwrap();
    socket
        .set_read_timeout(Some(Duration::from_secs(5)))
        .unwrap();
    let addr = socket.local_addr().unwrap().to_string();
    (socket, addr)
}

/// Receives one datagram, asserting it has the FGNetFDM size.
fn recv_packet(socket: &UdpSocket) -> FgNetFdm {
    let mut buf = [0u8; 2048];
    let len = socket.recv(&mut buf).unwrap();
    assert_eq!(len, DATAGRAM_LEN);
    FgNetFdm::decode(&buf[..len]).unwrap()
}

/// Asserts nothing more is waiting on the socket.
fn assert_drained(socket: &UdpSocket) {
    socket.set_nonblocking(true).unwrap();
    let mut buf = [0u8; 2048];
    let err = socket.recv(&mut buf).unwrap_err();
    assert_eq!(
        err.kind(),
        ErrorKind::WouldBlock,
        "an extra datagram arrived"
    );
    socket.set_nonblocking(false).unwrap();
}

#[test]
fn linked_entities_send_one_datagram_per_frame_and_unlinked_ones_nothing() {
    let (fg_palmer, palmer_addr) = receiver();
    let (fg_bourg, bourg_addr) = receiver();
    let mut sim = Simulation::new(Resources::new(30.0).unwrap());
    let cessna = Arc::new(PalmerAircraft::cessna_172());
    let controls = PalmerControls {
        throttle: 1.0,
        alpha_deg: 4.0,
        ..PalmerControls::default()
    };
    let linked = sim.spawn::<Palmer>(
        Arc::clone(&cessna),
        controls,
        PalmerState::at_rest(),
        Some(FlightGearLink::connect(&palmer_addr).unwrap()),
    );
    let unlinked = sim.spawn::<Palmer>(cessna, controls, PalmerState::at_rest(), None);
    let bourg = sim.spawn::<Bourg>(
        Arc::new(BourgAircraft::bourg_default()),
        BourgControls::initial(),
        BourgState::initial(),
        Some(FlightGearLink::connect(&bourg_addr).unwrap()),
    );

    let frames = 20;
    for frame in 1..=frames {
        sim.run_frame();
        let got = recv_packet(&fg_palmer);
        assert_eq!(got, sim.packet(linked).unwrap(), "frame {frame}");
        assert_eq!(recv_packet(&fg_bourg), sim.packet(bourg).unwrap());
        // The unlinked twin flies the same and has a packet, but nothing of it
        // reaches either socket.
        assert_eq!(sim.packet(unlinked), sim.packet(linked));
        assert_drained(&fg_palmer);
        assert_drained(&fg_bourg);
    }
    assert_eq!(sim.send_stats(linked).unwrap().sent, frames);
    assert_eq!(sim.send_stats(linked).unwrap().failed, 0);
    assert_eq!(sim.send_stats(bourg).unwrap().sent, frames);
    assert!(sim.send_stats(unlinked).is_none());
    assert!(sim.take_send_failure(linked).is_none());
}

#[test]
fn send_failures_are_counted_reported_once_and_do_not_stop_the_run() {
    // A port nobody listens on: bind, note the port, close.
    let addr = {
        let (socket, addr) = receiver();
        drop(socket);
        addr
    };
    let mut sim = Simulation::new(Resources::new(30.0).unwrap());
    let e = sim.spawn::<Palmer>(
        Arc::new(PalmerAircraft::cessna_172()),
        PalmerControls::default(),
        PalmerState::at_rest(),
        Some(FlightGearLink::connect(&addr).unwrap()),
    );
    let frames = 10;
    sim.run_frames(frames);
    assert_eq!(sim.frame(), frames);
    let stats = sim.send_stats(e).unwrap();
    assert_eq!(stats.sent + stats.failed, frames);
    // Linux reports the ICMP port-unreachable of one datagram on the next send.
    assert!(stats.failed >= 1, "{stats:?}");
    let first = sim.take_send_failure(e).expect("first failure kept");
    assert_eq!(first.kind(), ErrorKind::ConnectionRefused);
    assert!(sim.take_send_failure(e).is_none(), "reported once");
    sim.run_frames(4);
    assert!(
        sim.take_send_failure(e).is_none(),
        "later failures only counted"
    );
    assert_eq!(
        sim.send_stats(e).unwrap().failed + sim.send_stats(e).unwrap().sent,
        14
    );
}
