//! Cost of the DIS output per aircraft and frame:
//!
//! * `frames/to_ecef`: geodetic/NED state → ECEF location, DIS Euler angles,
//!   ECEF velocity;
//! * `encode/entity_state_pdu`: building the dis-rs Entity State PDU and
//!   serialising it into a reused buffer (144 bytes);
//! * `dead_reckoning/check`: one sender-side check (extrapolate the last
//!   PDU with DRM(R,V,W), position and orientation errors, thresholds);
//! * `publisher/update_no_send` and `publisher/update_send`: the whole
//!   per-frame call when nothing is due and when a PDU is due;
//! * `listener/ingest`: decoding one datagram and updating the entity.
//!
//! Run: `cargo bench -p fdm-dis --bench dis_encode`.

use std::hint::black_box;

use bytes::BytesMut;
use criterion::{criterion_group, criterion_main, Criterion};
use fdm_dis::geodesy::{Attitude, Geodetic};
use fdm_dis::{
    encode_entity_state, AircraftKind, AircraftState, DeadReckoner, DrAlgorithm, DrThresholds,
    EntityConfig, EntityIdentity, EntityPublisher, Listener, Marking, WireState,
};
use nalgebra::Vector3;

fn state(t: f64) -> AircraftState {
    let mut s = AircraftState::new(
        t,
        Geodetic {
            lat_deg: 39.8264,
            lon_deg: -84.0483,
            alt_m: 1500.0,
        },
        Attitude {
            heading_deg: 280.0,
            pitch_deg: 3.0,
            roll_deg: 15.0,
        },
        Vector3::new(10.0, -58.0, -1.0),
    );
    s.angular_velocity_body_rad_s = Some(Vector3::new(0.0, 0.01, 0.05));
    s.acceleration_ned_m_s2 = Some(Vector3::new(0.2, 0.1, 0.0));
    s
}

fn config() -> EntityConfig {
    EntityConfig::new(
        EntityIdentity::new(1, 1, 1).unwrap(),
        AircraftKind::CESSNA_172_SKYHAWK,
        Marking::new("N172SP").unwrap(),
    )
}

fn benches(c: &mut Criterion) {
    let s = state(10.0);
    c.bench_function("frames/to_ecef", |b| {
        b.iter(|| black_box(black_box(&s).to_ecef().unwrap()));
    });

    let cfg = config();
    let e = s.to_ecef().unwrap();
    let wire = WireState::new(&e, cfg.dr_algorithm);
    let mut buf = BytesMut::with_capacity(fdm_dis::ENTITY_STATE_PDU_LEN);
    c.bench_function("encode/entity_state_pdu", |b| {
        b.iter(|| encode_entity_state(black_box(&cfg), black_box(&wire), &mut buf).unwrap());
    });

    let mut r = DeadReckoner::new(DrAlgorithm::Rvw, DrThresholds::default()).unwrap();
    r.record_sent(wire);
    let later = state(10.5).to_ecef().unwrap();
    c.bench_function("dead_reckoning/check", |b| {
        b.iter(|| black_box(r.check(black_box(&later))));
    });

    // Nothing due: the state of the last PDU again (elapsed 0): the whole
    // conversion and check, no encoding.
    let mut p = EntityPublisher::new(cfg.clone(), DrThresholds::default()).unwrap();
    let quiet = state(0.0);
    p.update(&quiet).unwrap();
    c.bench_function("publisher/update_no_send", |b| {
        b.iter(|| black_box(p.update(black_box(&quiet)).unwrap().is_some()));
    });

    // Always due: alternate the heading by 10°.
    let mut p = EntityPublisher::new(cfg.clone(), DrThresholds::default()).unwrap();
    let mut a = state(0.0);
    let mut k = 0u32;
    c.bench_function("publisher/update_send", |b| {
        b.iter(|| {
            k += 1;
            a.attitude.heading_deg = if k.is_multiple_of(2) { 280.0 } else { 290.0 };
            black_box(p.update(black_box(&a)).unwrap().map(|d| d.bytes.len()))
        });
    });

    let mut enc = BytesMut::new();
    let n = encode_entity_state(&cfg, &wire, &mut enc).unwrap();
    let datagram = enc[..n].to_vec();
    let mut l = Listener::new();
    c.bench_function("listener/ingest", |b| {
        b.iter(|| l.ingest(black_box(&datagram)).unwrap());
    });
}

criterion_group!(dis, benches);
criterion_main!(dis);
