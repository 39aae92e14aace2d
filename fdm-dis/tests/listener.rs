//! The listener: counts, entities, geodetic read-back, and malformed input
//! (counted and skipped, never a panic).
//!
//! Read-back tolerances: the location is an `f64` on the wire, so latitude
//! and longitude come back to the geodesy's round trip (< 1e-9°) and the
//! height to < 1e-6 m; the angles are `f32` on the wire, so heading, pitch
//! and roll come back within 1e-4° for |pitch| ≤ 60° (see
//! `tests/frames.rs` for the bound); velocities are `f32`: within 1e-4 m/s
//! for speeds up to a few hundred m/s (half an f32 ulp at 256 is 1.5e-5,
//! three components).

use std::net::UdpSocket;
use std::time::Duration;

use fdm_dis::geodesy::{Attitude, Geodetic};
use fdm_dis::{
    decode_datagram, AircraftKind, AircraftState, DecodeError, DisVersion, DrThresholds,
    EntityConfig, EntityIdentity, EntityPublisher, Listener, Marking, UdpSender,
};
use nalgebra::Vector3;
use proptest::prelude::*;

fn state(t: f64, lat: f64, lon: f64, heading: f64) -> AircraftState {
    AircraftState::new(
        t,
        Geodetic {
            lat_deg: lat,
            lon_deg: lon,
            alt_m: 900.0 + t,
        },
        Attitude {
            heading_deg: heading,
            pitch_deg: 4.0,
            roll_deg: 12.0,
        },
        Vector3::new(40.0, 20.0, -1.5),
    )
}

fn publisher(entity: u16, kind: AircraftKind, marking: &str, v: DisVersion) -> EntityPublisher {
    let mut c = EntityConfig::new(
        EntityIdentity::new(1, 2, entity).unwrap(),
        kind,
        Marking::new(marking).unwrap(),
    );
    c.version = v;
    EntityPublisher::new(c, DrThresholds::default()).unwrap()
}

fn one_pdu(p: &mut EntityPublisher, s: &AircraftState) -> Vec<u8> {
    // A fresh publisher always sends its first state.
    p.update(s).unwrap().expect("first PDU").bytes.to_vec()
}

fn assert_close(rec: &fdm_dis::EntityRecord, s: &AircraftState) {
    assert!((rec.position.lat_deg - s.position.lat_deg).abs() < 1e-9);
    assert!((rec.position.lon_deg - s.position.lon_deg).abs() < 1e-9);
    assert!((rec.position.alt_m - s.position.alt_m).abs() < 1e-6);
    let d = |a: f64, b: f64| ((a - b + 180.0).rem_euclid(360.0) - 180.0).abs();
    assert!(d(rec.attitude.heading_deg, s.attitude.heading_deg) < 1e-4);
    assert!((rec.attitude.pitch_deg - s.attitude.pitch_deg).abs() < 1e-4);
    assert!(d(rec.attitude.roll_deg, s.attitude.roll_deg) < 1e-4);
    assert!((rec.velocity_ned_m_s - s.velocity_ned_m_s).norm() < 1e-4);
}

#[test]
fn counts_entities_and_reads_back_geodetic() {
    let mut cessna = publisher(
        1,
        AircraftKind::CESSNA_172_SKYHAWK,
        "CESSNA1",
        DisVersion::V7,
    );
    let mut bourg = publisher(
        2,
        AircraftKind::SMALL_CIVIL_FIXED_WING,
        "BOURG2",
        DisVersion::V6,
    );
    let s1 = state(0.0, 39.8, -84.0, 10.0);
    let s2 = state(0.0, -33.9, 151.2, 200.0);
    let d1 = one_pdu(&mut cessna, &s1);
    let d2 = one_pdu(&mut bourg, &s2);

    let mut l = Listener::new();
    assert_eq!(l.ingest(&d1), Ok(1));
    assert_eq!(l.ingest(&d2), Ok(1));
    // Two PDUs in one datagram (same entities again, later states).
    let s1b = state(7.0, 39.801, -84.002, 15.0);
    let s2b = state(7.0, -33.899, 151.201, 205.0);
    let mut both = cessna
        .update(&s1b)
        .unwrap()
        .expect("heartbeat")
        .bytes
        .to_vec();
    both.extend_from_slice(bourg.update(&s2b).unwrap().expect("heartbeat").bytes);
    assert_eq!(l.ingest(&both), Ok(2));

    let st = l.stats();
    assert_eq!(st.datagrams, 3);
    assert_eq!(st.bytes, 144 * 4);
    assert_eq!((st.pdus, st.entity_state_pdus), (4, 4));
    assert_eq!((st.malformed_datagrams, st.decoder_panics), (0, 0));
    assert_eq!(l.entity_count(), 2);

    let r1 = l.entity(&EntityIdentity::new(1, 2, 1).unwrap()).unwrap();
    assert_eq!(
        (r1.updates, r1.protocol_version, r1.marking.as_str()),
        (2, 7, "CESSNA1")
    );
    assert_eq!(
        r1.entity_type,
        AircraftKind::CESSNA_172_SKYHAWK.entity_type()
    );
    assert!(r1.marking_is_ascii);
    assert_close(r1, &s1b);
    let r2 = l.entity(&EntityIdentity::new(1, 2, 2).unwrap()).unwrap();
    assert_eq!(
        (r2.updates, r2.protocol_version, r2.marking.as_str()),
        (2, 6, "BOURG2")
    );
    assert_eq!(
        r2.entity_type,
        AircraftKind::SMALL_CIVIL_FIXED_WING.entity_type()
    );
    assert_close(r2, &s2b);
    let ids: Vec<_> = l.entities().map(|r| r.id.entity).collect();
    assert_eq!(ids, [1, 2]);
}

#[test]
fn a_bounded_listener_keeps_its_first_entities_and_counts_the_rest() {
    let mut l = Listener::with_max_entities(2);
    assert_eq!(l.max_entities(), Some(2));
    let s = state(0.0, 39.8, -84.0, 10.0);
    for entity in 1..=5 {
        let mut p = publisher(
            entity,
            AircraftKind::CESSNA_172_SKYHAWK,
            "C172",
            DisVersion::V7,
        );
        assert_eq!(l.ingest(&one_pdu(&mut p, &s)), Ok(1));
    }
    // Entity 1 again: it is kept, so it is updated.
    let mut p = publisher(1, AircraftKind::CESSNA_172_SKYHAWK, "C172", DisVersion::V7);
    l.ingest(&one_pdu(&mut p, &state(1.0, 39.9, -84.0, 10.0)))
        .unwrap();
    let ids: Vec<_> = l.entities().map(|r| r.id.entity).collect();
    assert_eq!(ids, [1, 2]);
    let st = l.stats();
    assert_eq!((st.pdus, st.entity_state_pdus), (6, 6));
    assert_eq!(st.untracked_entity_pdus, 3);
    let r1 = l.entity(&EntityIdentity::new(1, 2, 1).unwrap()).unwrap();
    assert_eq!(r1.updates, 2);
    assert!((r1.position.lat_deg - 39.9).abs() < 1e-9);
    assert_eq!(Listener::new().max_entities(), None);
}

#[test]
fn malformed_datagrams_are_counted_and_skipped() {
    let mut p = publisher(9, AircraftKind::CESSNA_172_SKYHAWK, "X", DisVersion::V7);
    let good = one_pdu(&mut p, &state(0.0, 10.0, 10.0, 0.0));
    let mut l = Listener::new();

    let mut bad_cases: Vec<(Vec<u8>, &str)> = vec![
        (vec![], "empty"),
        (good[..11].to_vec(), "shorter than a header"),
        (good[..100].to_vec(), "truncated body"),
        (vec![0xFF; 200], "garbage"),
    ];
    let mut zero_len = good.clone();
    zero_len[8..10].copy_from_slice(&0u16.to_be_bytes());
    bad_cases.push((zero_len, "length 0"));
    let mut long_len = good.clone();
    long_len[8..10].copy_from_slice(&200u16.to_be_bytes());
    bad_cases.push((long_len, "length beyond the datagram"));
    let mut trailing = good.clone();
    trailing.extend_from_slice(&[1, 2, 3]);
    bad_cases.push((trailing, "3 trailing bytes"));
    let mut short_body = good.clone();
    short_body[8..10].copy_from_slice(&100u16.to_be_bytes());
    bad_cases.push((short_body, "declared length cuts the body"));

    for (i, (d, what)) in bad_cases.iter().enumerate() {
        let r = l.ingest(d);
        assert!(r.is_err(), "{what}: {r:?}");
        assert_eq!(l.stats().malformed_datagrams, i as u64 + 1, "{what}");
    }
    assert!(matches!(
        decode_datagram(&good[..11]),
        Err(DecodeError::ShortHeader { .. })
    ));
    assert!(matches!(
        decode_datagram(&bad_cases[4].0),
        Err(DecodeError::BadLength { declared: 0, .. })
    ));
    // Nothing from a bad datagram was applied; a good one still works.
    assert_eq!((l.stats().pdus, l.entity_count()), (0, 0));
    assert_eq!(l.ingest(&good), Ok(1));
    assert_eq!(l.entity_count(), 1);
    assert_eq!(l.stats().decoder_panics, 0);
}

/// `DecodeError`'s cases at their limits, as documented: fewer bytes left
/// than a header (12) is `ShortHeader`, exactly a header's worth is not; a
/// declared length below a header or beyond what is left is `BadLength`,
/// exactly a header or exactly what is left is not (the piece goes to
/// dis-rs). Each error names the offset of its piece in the datagram: here
/// the second piece, after a good 144-byte PDU.
#[test]
fn decode_errors_at_their_limits_name_the_pieces_offset() {
    let mut p = publisher(
        4,
        AircraftKind::CESSNA_172_SKYHAWK,
        "LIMITS",
        DisVersion::V7,
    );
    let good = one_pdu(&mut p, &state(0.0, 20.0, 30.0, 45.0));
    assert_eq!(good.len(), 144);
    let after_good = |tail: &[u8]| {
        let mut d = good.clone();
        d.extend_from_slice(tail);
        decode_datagram(&d)
    };
    // The good PDU's header with another declared length.
    let header = |declared: u16| {
        let mut h = good[..12].to_vec();
        h[8..10].copy_from_slice(&declared.to_be_bytes());
        h
    };

    assert_eq!(
        after_good(&good[..11]),
        Err(DecodeError::ShortHeader {
            offset: 144,
            left: 11
        })
    );
    // Twelve bytes left are a header: its length is read and checked.
    assert_eq!(
        after_good(&header(13)),
        Err(DecodeError::BadLength {
            offset: 144,
            declared: 13,
            left: 12
        })
    );
    let mut short = header(11);
    short.extend_from_slice(&[0; 20]);
    assert_eq!(
        after_good(&short),
        Err(DecodeError::BadLength {
            offset: 144,
            declared: 11,
            left: 32
        })
    );
    // A declared length of exactly a header is within the limits: the
    // piece is dis-rs's to parse (a header alone is no Entity State PDU).
    let r = after_good(&header(12));
    assert!(
        matches!(r, Ok(_) | Err(DecodeError::Parse { offset: 144, .. })),
        "{r:?}"
    );
    // Exactly what is left, and one byte beyond.
    assert_eq!(after_good(&good).map(|p| p.len()), Ok(2));
    let mut beyond = good.clone();
    beyond[8..10].copy_from_slice(&145u16.to_be_bytes());
    assert_eq!(
        after_good(&beyond),
        Err(DecodeError::BadLength {
            offset: 144,
            declared: 145,
            left: 144
        })
    );
    // A piece that dis-rs rejects (an Entity State PDU cut to 100 bytes,
    // its declared length too) names its offset too.
    let mut cut = good[..100].to_vec();
    cut[8..10].copy_from_slice(&100u16.to_be_bytes());
    let r = after_good(&cut);
    assert!(
        matches!(r, Err(DecodeError::Parse { offset: 144, .. })),
        "{r:?}"
    );
}

#[test]
fn over_udp_loopback() {
    const RATE_DEG_S: f64 = 1.7;
    let rx = UdpSocket::bind("127.0.0.1:0").unwrap();
    rx.set_read_timeout(Some(Duration::from_secs(5))).unwrap();
    let tx = UdpSender::new(rx.local_addr().unwrap(), false).unwrap();
    let mut pubs: Vec<EntityPublisher> = (1..=3)
        .map(|i| {
            publisher(
                i,
                AircraftKind::CESSNA_172_SKYHAWK,
                &format!("N{i}"),
                DisVersion::V7,
            )
        })
        .collect();
    let mut sent = 0;
    let mut last = Vec::new();
    for k in 0..=40 {
        let t = f64::from(k) * 0.25;
        last.clear();
        for (i, p) in pubs.iter_mut().enumerate() {
            // Each aircraft turns at a different rate so they send at different times.
            // Held in place (zero velocity, fixed height) so that only the
            // turning decides when PDUs are due.
            let mut s = state(t, 40.0 + i as f64, -80.0, RATE_DEG_S * t * (i as f64 + 1.0));
            s.velocity_ned_m_s = Vector3::zeros();
            s.position.alt_m = 900.0;
            if let Some(due) = p.update(&s).unwrap() {
                tx.send(due.bytes).unwrap();
                sent += 1;
            }
            last.push(s);
        }
    }
    let mut l = Listener::new();
    let mut buf = [0u8; 2048];
    for _ in 0..sent {
        let n = rx.recv(&mut buf).expect("datagram on loopback");
        l.ingest(&buf[..n]).unwrap();
    }
    assert_eq!(l.stats().pdus, sent);
    assert_eq!(l.entity_count(), 3);
    let total: u64 = pubs.iter().map(|p| p.counts().sent).sum();
    assert_eq!(total, sent);
    // Turning 0.425°, 0.85° and 1.275° per 0.25 s frame (no multiple of 3°
    // falls on a frame), each sends on the first frame past 3°: every
    // floor(3 / step) + 1 frames, over frames 0..=40.
    let expected: u64 = (1..=3)
        .map(|i| {
            let step_deg = RATE_DEG_S * 0.25 * f64::from(i);
            let every = (3.0 / step_deg).floor() as u64 + 1;
            1 + 40 / every
        })
        .sum();
    assert_eq!(sent, expected);
    println!("3 aircraft, 41 frames: {sent} PDUs over loopback");
}

/// dis-rs 0.14 panics on a Signal PDU whose encoding class is "application
/// specific data" (or "database index") but whose data is shorter than the 4
/// (8) bytes it then slices (`signal/parser.rs`, `parse_encoding_scheme`);
/// found by the cargo-fuzz target. The listener catches it, counts it and
/// stays usable.
#[test]
fn dis_rs_signal_pdu_panic_is_caught() {
    // Hand-made: DIS 7 header (version 7, exercise 1, type 26 Signal, family
    // 4, timestamp 0, length 32, status/padding 0), then radio reference
    // entity 1:1:1, radio 1, encoding scheme 0x8000 (class 2, application
    // specific), TDL type 0, sample rate 0, data length 0 bits, 0 samples.
    let mut signal = vec![7u8, 1, 26, 4, 0, 0, 0, 0, 0, 32, 0, 0];
    signal.extend_from_slice(&[
        0, 1, 0, 1, 0, 1, 0, 1, 0x80, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0,
    ]);
    assert_eq!(signal.len(), 32);
    // As the fuzzer found it (a protocol version 12 Signal PDU, 44 bytes,
    // then 17 more).
    let found: [u8; 61] = [
        0x0c, 0x00, 0x1a, 0xff, 0x00, 0xf3, 0x00, 0xf7, 0x00, 0x2c, 0x00, 0x00, 0x00, 0x00, 0xa7,
        0xa7, 0xa7, 0xa7, 0xa7, 0xa7, 0xa7, 0xa7, 0xa7, 0xa7, 0xa7, 0xa7, 0xa7, 0x00, 0x00, 0x00,
        0x00, 0x00, 0xff, 0xff, 0xff, 0xff, 0xff, 0xff, 0xff, 0x02, 0x26, 0x00, 0xfa, 0x00, 0x00,
        0x00, 0x00, 0x00, 0x00, 0x0c, 0x00, 0x0c, 0x01, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x0c,
        0x00,
    ];
    let mut l = Listener::new();
    for (i, d) in [&signal[..], &found[..]].into_iter().enumerate() {
        assert_eq!(
            l.ingest(d),
            Err(DecodeError::DecoderPanic { offset: 0 }),
            "input {i}"
        );
        assert_eq!(l.stats().decoder_panics, i as u64 + 1);
        assert_eq!(l.stats().malformed_datagrams, i as u64 + 1);
    }
    // Still usable.
    let mut p = publisher(3, AircraftKind::CESSNA_172_SKYHAWK, "AFTER", DisVersion::V7);
    assert_eq!(
        l.ingest(&one_pdu(&mut p, &state(0.0, 1.0, 2.0, 3.0))),
        Ok(1)
    );
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(2000))]

    /// Arbitrary bytes: never a panic, and the counts add up.
    #[test]
    fn random_bytes_never_panic(d in proptest::collection::vec(any::<u8>(), 0..400)) {
        let mut l = Listener::new();
        let r = l.ingest(&d);
        let s = l.stats();
        prop_assert_eq!(s.datagrams, 1);
        prop_assert_eq!(s.malformed_datagrams, u64::from(r.is_err()));
        // dis-rs panics on some inputs (see above); those are caught and
        // counted as malformed too.
        prop_assert!(s.decoder_panics <= s.malformed_datagrams);
    }

    /// A valid PDU with random bytes overwritten: never a panic.
    #[test]
    fn mutated_pdus_never_panic(
        edits in proptest::collection::vec((0usize..144, any::<u8>()), 1..8),
        cut in 0usize..=144,
    ) {
        let mut p = publisher(5, AircraftKind::SMALL_CIVIL_FIXED_WING, "FUZZ", DisVersion::V7);
        let mut d = one_pdu(&mut p, &state(1.0, 45.0, 7.0, 90.0));
        for (i, b) in edits {
            d[i] = b;
        }
        d.truncate(cut);
        let mut l = Listener::new();
        let r = l.ingest(&d);
        let s = l.stats();
        prop_assert_eq!(s.malformed_datagrams, u64::from(r.is_err()));
        prop_assert!(s.decoder_panics <= s.malformed_datagrams);
    }
}
