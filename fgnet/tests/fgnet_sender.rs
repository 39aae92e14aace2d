//! The UDP `Sender` on 127.0.0.1 with ephemeral ports: datagrams arrive as
//! 408 bytes, sending with nobody listening is counted and reported once,
//! and bad addresses give typed errors naming the address.

use std::io::ErrorKind;
use std::net::UdpSocket;
use std::time::Duration;

use fdm_tests::fgnet_fields::assert_bitwise_eq;
use fgnet::{DisplayState, FgNetFdm, SendOutcome, Sender, SenderError, SenderStats};

fn frame(i: u32) -> FgNetFdm {
    let mut fdm = FgNetFdm::from_display(&DisplayState {
        latitude_deg: 37.625 + f64::from(i) * 1e-5,
        longitude_deg: -122.375,
        altitude_m: 100.0 + f64::from(i),
        heading_deg: f64::from(i % 360),
        ..DisplayState::default()
    });
    fdm.cur_time = i;
    fdm
}

#[test]
fn bound_receiver_gets_408_byte_datagrams() {
    let rx = UdpSocket::bind("127.0.0.1:0").unwrap();
    rx.set_read_timeout(Some(Duration::from_secs(5))).unwrap();
    let addr = rx.local_addr().unwrap();
    let mut tx = Sender::connect(&addr.to_string()).unwrap();
    assert_eq!(tx.peer(), addr);
    let local = tx.local_addr().unwrap();

    const N: u32 = 50;
    for i in 0..N {
        let outcome = tx.send(&frame(i));
        assert!(outcome.is_sent(), "frame {i}: {outcome:?}");
    }
    assert_eq!(
        tx.stats(),
        SenderStats {
            sent: u64::from(N),
            failed: 0,
            refused: 0
        }
    );

    let mut buf = [0u8; 2048];
    for i in 0..N {
        let (len, from) = rx.recv_from(&mut buf).expect("datagram arrives");
        assert_eq!(len, 408, "datagram {i} length");
        assert_eq!(from.port(), local.port());
        let got = FgNetFdm::decode(&buf[..len]).expect("decodes");
        assert_bitwise_eq(&got, &frame(i), &format!("datagram {i}"));
    }
}

#[test]
fn nobody_listening_is_counted_and_reported_once() {
    // A port that was just free: bind, note it, close.
    let port = {
        let s = UdpSocket::bind("127.0.0.1:0").unwrap();
        s.local_addr().unwrap().port()
    };
    let mut tx = Sender::connect(&format!("127.0.0.1:{port}")).expect("connect needs no listener");

    const N: u64 = 200;
    let (mut sent, mut first, mut failed) = (0u64, Vec::new(), 0u64);
    for i in 0..N {
        match tx.send(&frame(i as u32)) {
            SendOutcome::Sent => sent += 1,
            SendOutcome::FirstFailure(e) => first.push((i, e)),
            SendOutcome::Failed => failed += 1,
        }
        std::thread::sleep(Duration::from_millis(1));
    }
    let stats = tx.stats();
    eprintln!("nobody listening, {N} frames: {stats:?}");
    assert_eq!(stats.sent + stats.failed, N, "{stats:?}");
    assert_eq!(stats.sent, sent);
    assert_eq!(
        first.len(),
        1,
        "exactly one first-failure report: {first:?}"
    );
    assert_eq!(
        first[0].1.kind(),
        ErrorKind::ConnectionRefused,
        "{:?}",
        first[0]
    );
    assert!(
        first[0].0 >= 1,
        "the first send itself succeeds; its ICMP error shows up later"
    );
    assert_eq!(stats.failed, failed + 1);
    // Linux reports each ICMP port-unreachable once, on the next send, so
    // with nobody listening a large share of the frames fail.
    assert!(stats.failed >= N / 4, "{stats:?}");
    assert_eq!(stats.refused, stats.failed, "{stats:?}");

    // A listener appearing later is served by the same sender.
    let rx = UdpSocket::bind(("127.0.0.1", port)).expect("rebind the port");
    rx.set_read_timeout(Some(Duration::from_secs(5))).unwrap();
    let mut got_one = false;
    for i in 0..10 {
        if tx.send(&frame(1000 + i)).is_sent() {
            got_one = true;
        }
    }
    assert!(got_one);
    let mut buf = [0u8; 1024];
    assert_eq!(rx.recv(&mut buf).unwrap(), 408);
}

#[test]
fn bad_addresses_give_typed_errors_naming_them() {
    for addr in [
        "not an address",
        "127.0.0.1",
        "127.0.0.1:99999",
        ":5500",
        "",
    ] {
        match Sender::connect(addr) {
            Err(e @ SenderError::Resolve { .. }) => {
                let msg = e.to_string();
                assert!(msg.contains(&format!("{addr:?}")), "{msg}");
                assert!(msg.contains("HOST:PORT"), "{msg}");
            }
            other => panic!("{addr:?}: expected a Resolve error, got {other:?}"),
        }
    }
}

#[test]
fn localhost_prefers_ipv4() {
    // FlightGear's native-FDM socket is IPv4 only. Resolved from /etc/hosts.
    let tx = Sender::connect("localhost:5500").expect("localhost resolves");
    assert_eq!(tx.peer(), "127.0.0.1:5500".parse().unwrap());
}
