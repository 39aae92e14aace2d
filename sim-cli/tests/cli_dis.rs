//! `--dis` through the binary: `sim-cli palmer|bourg --headless --dis` and
//! `sim-cli fleet --dis` send Entity State PDUs over UDP on 127.0.0.1 that
//! fdm-dis's listener decodes, and the JSON report's `dis` object counts
//! exactly what arrived. Loopback only.

mod support;

use std::net::UdpSocket;
use std::time::Duration;

use fdm_dis::{AircraftKind, EntityIdentity, Listener};
use support::{num, report, sim, text};

/// Binds a receiver on 127.0.0.1 with a 4 MiB buffer request (a fleet's
/// first frame is a burst of one PDU per aircraft).
fn receiver() -> (UdpSocket, String) {
    let socket = UdpSocket::bind("127.0.0.1:0").unwrap();
    rustix::net::sockopt::set_socket_recv_buffer_size(&socket, 4 << 20).unwrap();
    socket
        .set_read_timeout(Some(Duration::from_millis(300)))
        .unwrap();
    let addr = socket.local_addr().unwrap().to_string();
    (socket, addr)
}

/// Every datagram waiting on `socket` (until 300 ms pass without one).
fn drain(socket: &UdpSocket) -> Listener {
    let mut listener = Listener::new();
    let mut buf = [0u8; 2048];
    while let Ok((n, _)) = socket.recv_from(&mut buf) {
        listener.ingest(&buf[..n]).expect("a well-formed PDU");
    }
    listener
}

/// The geodetic report's position, within what the PDU's f64 ECEF location
/// and the closed-form ECEF → geodetic conversion keep: 1e-9° and 1e-6 m
/// (the conversion is accurate to nanometres); attitude within 1e-4° (f32
/// angles on the wire, |pitch| small here).
#[test]
fn palmer_headless_publishes_what_the_report_counts() {
    let (socket, addr) = receiver();
    let r = report(&[
        "palmer",
        "--headless",
        "--duration",
        "60",
        "--throttle",
        "1",
        "--alpha",
        "4",
        "--bank",
        "10",
        "--json",
        "--dis",
        &addr,
        "--dis-site",
        "12",
        "--dis-application",
        "34",
        "--dis-entity",
        "56",
    ]);
    let listener = drain(&socket);
    let dis = &r["dis"];
    let pdus = dis["pdus"].as_u64().unwrap();
    assert_eq!(listener.stats().entity_state_pdus, pdus);
    assert_eq!(listener.stats().bytes, dis["bytes"].as_u64().unwrap());
    assert_eq!(dis["bytes"].as_u64().unwrap(), 144 * pdus);
    assert_eq!(dis["first_entity"], "12:34:56");
    assert_eq!(dis["frames"].as_u64().unwrap(), 1800);
    assert_eq!(num(&dis["sim_seconds"]), 60.0);
    let reasons = &dis["reasons"];
    let sum: u64 = ["first", "position", "orientation", "heartbeat"]
        .iter()
        .map(|k| reasons[k].as_u64().unwrap())
        .sum();
    assert_eq!(sum, pdus);
    assert_eq!(reasons["first"], 1);
    // A 10° turn for a minute is a manoeuvre: more than the heartbeats alone,
    // far fewer than the 1800 frames.
    assert!((13..200).contains(&pdus), "{pdus}");

    let id = EntityIdentity::new(12, 34, 56).unwrap();
    let e = listener.entity(&id).expect("the aircraft");
    assert_eq!(listener.entity_count(), 1);
    assert_eq!(e.marking, "C172-56");
    assert_eq!(
        e.entity_type,
        AircraftKind::CESSNA_172_SKYHAWK.entity_type()
    );
    assert_eq!(e.protocol_version, 7);
    // The last PDU is at most 5 s old, so the aircraft is near (not at) the
    // report's final position: within 5 s × 60 m/s.
    let g = &r["geodetic"];
    let dlat_m = (e.position.lat_deg - num(&g["lat_deg"])) * 111_000.0;
    let dlon_m = (e.position.lon_deg - num(&g["lon_deg"])) * 85_000.0;
    assert!(dlat_m.hypot(dlon_m) < 300.0, "{dlat_m} {dlon_m}");
}

/// Every frame sent, DIS 6, Bourg: one PDU per frame, the Bourg entity type,
/// and the last PDU is the final frame, so its decoded position and attitude
/// are the report's (tolerances as above).
#[test]
fn bourg_every_frame_dis6_ends_on_the_reports_state() {
    let (socket, addr) = receiver();
    let r = report(&[
        "bourg",
        "--headless",
        "--frames",
        "90",
        "--json",
        "--dis",
        &addr,
        "--dis-version",
        "6",
        "--dis-every-frame",
        "--dis-callsign",
        "UFO 7",
    ]);
    let listener = drain(&socket);
    assert_eq!(r["dis"]["pdus"], 90);
    assert_eq!(r["dis"]["every_frame"], true);
    assert_eq!(listener.stats().entity_state_pdus, 90);
    let e = listener
        .entity(&EntityIdentity::new(1, 1, 1).unwrap())
        .unwrap();
    assert_eq!(e.protocol_version, 6);
    assert_eq!(e.marking, "UFO 7");
    assert_eq!(
        e.entity_type,
        AircraftKind::SMALL_CIVIL_FIXED_WING.entity_type()
    );
    let g = &r["geodetic"];
    assert!((e.position.lat_deg - num(&g["lat_deg"])).abs() < 1e-9);
    assert!((e.position.lon_deg - num(&g["lon_deg"])).abs() < 1e-9);
    assert!((e.position.alt_m - num(&g["alt_m"])).abs() < 1e-6);
    let a = &r["attitude_deg"];
    let d = |x: f64, y: f64| ((x - y + 180.0).rem_euclid(360.0) - 180.0).abs();
    assert!(d(e.attitude.heading_deg, num(&a["heading"])) < 1e-4);
    assert!((e.attitude.pitch_deg - num(&a["pitch"])).abs() < 1e-4);
    assert!(d(e.attitude.roll_deg, num(&a["roll"])) < 1e-4);
}

/// Both fleet kernels publish every aircraft with its own number; the lanes
/// kernel (exact) is bit-identical to the ECS one, so the dead reckoning
/// decides alike and both send exactly the same number of PDUs.
#[test]
fn fleet_publishes_every_aircraft_with_its_own_number() {
    let mut pdus = Vec::new();
    for kernel in ["lanes", "ecs"] {
        let (socket, addr) = receiver();
        let out = sim(&[
            "fleet",
            "--model",
            "palmer",
            "--kernel",
            kernel,
            "--aircraft",
            "300",
            "--frames",
            "30",
            "--threads",
            "2",
            "--json",
            "--dis",
            &addr,
            "--dis-application",
            "9",
            "--dis-entity-base",
            "65500",
        ]);
        assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
        let r: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
        let listener = drain(&socket);
        let dis = &r["dis"];
        assert_eq!(dis["entities"], 300);
        // 65500..=65533 in application 9, then 1..=266 in application 10.
        assert_eq!(dis["first_entity"], "1:9:65500");
        assert_eq!(dis["last_entity"], "1:10:266");
        assert_eq!(
            listener.stats().entity_state_pdus,
            dis["pdus"].as_u64().unwrap(),
            "{kernel}"
        );
        assert_eq!(listener.entity_count(), 300, "{kernel}");
        assert!(num(&dis["publish_seconds"]) > 0.0);
        let last = listener
            .entity(&EntityIdentity::new(1, 10, 266).unwrap())
            .unwrap();
        assert_eq!(last.marking, "C172-65799");
        pdus.push(dis["pdus"].as_u64().unwrap());
    }
    assert_eq!(pdus[0], pdus[1]);
}

#[test]
fn dis_options_need_dis_and_bad_values_are_usage_errors() {
    for args in [
        &["palmer", "--headless", "--frames", "1", "--dis-site", "2"][..],
        &[
            "fleet",
            "--model",
            "bourg",
            "--aircraft",
            "1",
            "--frames",
            "1",
            "--dis-entity-base",
            "5",
        ][..],
        &[
            "palmer",
            "--headless",
            "--frames",
            "1",
            "--dis",
            "127.0.0.1:3000",
            "--dis-site",
            "0",
        ][..],
        &[
            "palmer",
            "--headless",
            "--frames",
            "1",
            "--dis",
            "127.0.0.1:3000",
            "--dis-version",
            "5",
        ][..],
        &[
            "palmer",
            "--headless",
            "--frames",
            "1",
            "--dis",
            "127.0.0.1:3000",
            "--dis-callsign",
            "TWELVE CHARS",
        ][..],
        &[
            "palmer",
            "--headless",
            "--frames",
            "1",
            "--dis",
            "127.0.0.1:0",
        ][..],
        &["palmer", "--headless", "--frames", "1", "--dis", "no port"][..],
        &[
            "bourg",
            "--headless",
            "--frames",
            "1",
            "--dis",
            "127.0.0.1:3000",
            "--dis-heartbeat",
            "0",
        ][..],
        &[
            "fleet",
            "--model",
            "palmer",
            "--aircraft",
            "70000",
            "--frames",
            "1",
            "--dis",
            "127.0.0.1:3000",
            "--dis-application",
            "65534",
        ][..],
    ] {
        let out = sim(args);
        let err = text(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {err}");
        assert_eq!(err.lines().count(), 1, "{args:?}: {err}");
        assert!(err.starts_with("sim-cli: error: "), "{err}");
    }
}

/// `sim-cli dis-listen` on 127.0.0.1, port chosen by the OS (read from its
/// stderr line); returns the child and the port.
fn start_listener(extra: &[&str]) -> (std::process::Child, String) {
    use std::io::{BufRead, BufReader};
    use std::process::{Command, Stdio};
    let mut child = Command::new(env!("CARGO_BIN_EXE_sim-cli"))
        .args(["dis-listen", "127.0.0.1:0", "--json"])
        .args(extra)
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("start dis-listen");
    let mut line = String::new();
    BufReader::new(child.stderr.as_mut().unwrap())
        .read_line(&mut line)
        .unwrap();
    // "sim-cli: listening for DIS on 127.0.0.1:PORT for N s"
    let addr = line
        .split_whitespace()
        .find(|w| w.starts_with("127.0.0.1:"))
        .unwrap_or_else(|| panic!("no address in {line:?}"))
        .to_owned();
    (child, addr)
}

/// Two shards of 1,000 Palmer aircraft each, in two processes with their own
/// application numbers, publish to one loopback address; `dis-listen` sees all
/// 2,000 entities, each with its shard's numbering and callsign, at a
/// plausible place: the demonstration fleet starts 500 m above the default
/// origin (39.8264°, -84.0483°, 251 m), aircraft i at 10·i m north, and flies
/// 1 s at 45-55 m/s, so every aircraft is within 0.2° of the origin and
/// between 650 and 850 m high.
#[test]
fn two_fleet_shards_are_seen_as_2000_entities() {
    let (listener, addr) = start_listener(&["--seconds", "60", "--until-entities", "2000"]);
    let shard = |application: &str| {
        std::process::Command::new(env!("CARGO_BIN_EXE_sim-cli"))
            .args([
                "fleet",
                "--model",
                "palmer",
                "--aircraft",
                "1000",
                "--frames",
                "30",
                "--threads",
                "1",
                "--json",
                "--dis",
                &addr,
                "--dis-application",
                application,
            ])
            .stdin(std::process::Stdio::null())
            .output()
            .expect("run a shard")
    };
    let (a, b) = std::thread::scope(|s| {
        let a = s.spawn(|| shard("1"));
        let b = s.spawn(|| shard("2"));
        (a.join().unwrap(), b.join().unwrap())
    });
    for out in [&a, &b] {
        assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    }
    let out = listener.wait_with_output().unwrap();
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    let r: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(r["entity_count"], 2000, "{}", r["entity_count"]);
    assert_eq!(r["malformed_datagrams"], 0);
    let entities = r["entities"].as_array().unwrap();
    let mut per_application = [0u32; 3];
    for e in entities {
        let app = e["application"].as_u64().unwrap() as usize;
        per_application[app] += 1;
        assert_eq!(e["site"], 1);
        assert_eq!(e["entity_type"], "1.2.225.85.11.1.0");
        assert_eq!(
            e["marking"].as_str().unwrap(),
            format!("C172-{}", e["entity"])
        );
        let (lat, lon, alt) = (num(&e["lat_deg"]), num(&e["lon_deg"]), num(&e["alt_m"]));
        assert!((lat - 39.8264).abs() < 0.2, "{e}");
        assert!((lon + 84.0483).abs() < 0.2, "{e}");
        assert!((650.0..850.0).contains(&alt), "{e}");
    }
    assert_eq!(per_application, [0, 1000, 1000]);
    // Both shards' reports count what they sent; the listener may have
    // stopped (2,000 entities seen) before the last PDUs of the run.
    let sent: u64 = [&a, &b]
        .iter()
        .map(|o| {
            let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
            v["dis"]["pdus"].as_u64().unwrap()
        })
        .sum();
    assert!(r["entity_state_pdus"].as_u64().unwrap() <= sent);
}

/// Garbage on the listener's port is counted as malformed, never fatal.
#[test]
fn dis_listen_counts_malformed_datagrams() {
    let (listener, addr) = start_listener(&["--seconds", "1.5"]);
    let sender = UdpSocket::bind("127.0.0.1:0").unwrap();
    for datagram in [
        &b"hello"[..],
        &[0xFF; 12],
        &[7, 1, 1, 1, 0, 0, 0, 0, 0, 200, 0, 0],
    ] {
        sender.send_to(datagram, &addr).unwrap();
    }
    let out = listener.wait_with_output().unwrap();
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    let r: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(r["datagrams"], 3);
    assert_eq!(r["malformed_datagrams"], 3);
    assert_eq!(r["entity_count"], 0);
}

/// Every datagram waiting on `socket`, in order (until 300 ms pass without one).
fn datagrams(socket: &UdpSocket) -> Vec<Vec<u8>> {
    let mut out = Vec::new();
    let mut buf = [0u8; 2048];
    while let Ok((n, _)) = socket.recv_from(&mut buf) {
        out.push(buf[..n].to_vec());
    }
    out
}

/// `sim-cli replay --dis` publishes what the recorded flight published: the
/// replay is bit-identical, the dead reckoning decides alike, and the PDU
/// timestamps are simulation time, so the datagrams are byte for byte the same.
#[test]
fn replay_publishes_the_same_pdus_as_the_recorded_flight() {
    let dir = support::scratch("dis-replay");
    let recording = dir.join("flight.rec");
    let rec = recording.to_str().unwrap();
    let (first, first_addr) = receiver();
    let flown = report(&[
        "palmer",
        "--headless",
        "--frames",
        "900",
        "--throttle",
        "1",
        "--alpha",
        "5",
        "--bank",
        "-12",
        "--json",
        "--record",
        rec,
        "--dis",
        &first_addr,
        "--dis-entity",
        "42",
    ]);
    let flown_pdus = datagrams(&first);
    let (second, second_addr) = receiver();
    let replayed = report(&[
        "replay",
        rec,
        "--json",
        "--dis",
        &second_addr,
        "--dis-entity",
        "42",
    ]);
    let replayed_pdus = datagrams(&second);
    // Everything but the destination port.
    let without_target = |r: &serde_json::Value| {
        let mut d = r["dis"].clone();
        d.as_object_mut().unwrap().remove("target");
        d
    };
    assert_eq!(without_target(&flown), without_target(&replayed));
    assert!(flown_pdus.len() > 1);
    assert_eq!(
        flown_pdus.len() as u64,
        flown["dis"]["pdus"].as_u64().unwrap()
    );
    assert_eq!(flown_pdus, replayed_pdus);
}
