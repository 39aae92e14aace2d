//! What DIS output costs per aircraft and frame in `sim-cli fleet --dis`
//! (`fdm_run::dis`), next to one Palmer step:
//!
//! * `palmer_step`: one RK4 step of a fleet member (the work a frame does anyway);
//! * `place`: the model's view placed in ECEF (`Placement::place`: location,
//!   body-to-ECEF rotation, velocity);
//! * `update_nothing_due`: a whole `Tracker::update` when dead reckoning says
//!   nothing is due (view → placement → rates → ECEF → DR check), the common case;
//! * `update_pdu_due`: the same when a PDU is due every frame
//!   (`--dis-every-frame`): plus building and serialising it with dis-rs;
//! * `udp_send_144`: sending one 144-byte datagram to 127.0.0.1 (a bound
//!   socket that is drained between samples, so the kernel does not drop).
//!
//! `cargo bench -p afit-fdm-cli --bench dis_publish -- --warm-up-time 1 --measurement-time 5`

use std::hint::black_box;
use std::net::UdpSocket;

use criterion::{criterion_group, criterion_main, Criterion};
use fdm_core::geodesy::GeodeticOrigin;
use fdm_core::model::Model;
use fdm_core::palmer::Palmer;
use fdm_dis::{DisVersion, DrThresholds, EntityIdentity, UdpSender};
use fdm_dis::{DrAlgorithm, Placement, Tracker};
use fdm_run::dis::DisSettings;

fn settings(every_frame: bool) -> DisSettings {
    DisSettings {
        target: "127.0.0.1:3000".parse().expect("an address"),
        site: 1,
        application: 1,
        exercise: 1,
        version: DisVersion::V7,
        dr: DrAlgorithm::Rvw,
        thresholds: DrThresholds::default(),
        every_frame,
    }
}

fn tracker(every_frame: bool) -> Tracker {
    let s = settings(every_frame);
    s.tracker::<Palmer>(EntityIdentity::new(1, 1, 1).expect("valid"), "C172-1")
        .expect("valid")
}

fn bench(c: &mut Criterion) {
    let origin = GeodeticOrigin::default();
    let aircraft = Palmer::default_aircraft();
    let (controls, start) = Palmer::fleet_member(3);
    let dt = Palmer::time_step(30.0);
    // Fly 10 s so the aircraft is in its steady turn; keep 2 s of frames.
    let mut state = start;
    for _ in 0..300 {
        state = Palmer::step(&aircraft, &controls, &state, dt);
    }
    let mut views = Vec::new();
    for _ in 0..60 {
        state = Palmer::step(&aircraft, &controls, &state, dt);
        views.push(Palmer::view(&aircraft, &controls, &state));
    }

    c.bench_function("dis/palmer_step", |b| {
        b.iter(|| {
            Palmer::step(
                black_box(&aircraft),
                black_box(&controls),
                black_box(&state),
                dt,
            )
        });
    });
    let placement = Placement::new(origin);
    c.bench_function("dis/place", |b| {
        b.iter(|| black_box(&placement).place(black_box(&views[30])));
    });

    // Nothing due: a steady turn at 10° of bank with DRM(R,V,W) sends about
    // once per 2.5 s; the tracker is reset (a fresh one fed the first frames)
    // whenever a PDU was due, so every timed call is a "nothing due" call
    // except about one in 75.
    c.bench_function("dis/update_nothing_due", |b| {
        let mut t = tracker(false);
        let mut k = 0usize;
        b.iter(|| {
            let due = t
                .update(black_box(&views[k % views.len()]), &placement)
                .map(|d| d.is_some());
            k += 1;
            if k.is_multiple_of(views.len()) {
                t = tracker(false);
            }
            due
        });
    });
    c.bench_function("dis/update_pdu_due", |b| {
        let mut t = tracker(true);
        let mut k = 0usize;
        b.iter(|| {
            let n = t
                .update(black_box(&views[k % views.len()]), &placement)
                .map(|d| d.map_or(0, |d| d.bytes.len()));
            k += 1;
            if k.is_multiple_of(views.len()) {
                t = tracker(true);
            }
            n
        });
    });

    let sink = UdpSocket::bind("127.0.0.1:0").expect("bind");
    sink.set_nonblocking(true).expect("nonblocking");
    let sender = UdpSender::new(sink.local_addr().expect("addr"), false).expect("socket");
    let datagram = [0x5Au8; 144];
    c.bench_function("dis/udp_send_144", |b| {
        b.iter_batched(
            || {
                let mut buf = [0u8; 256];
                while sink.recv_from(&mut buf).is_ok() {}
            },
            |()| {
                for _ in 0..100 {
                    sender.send(black_box(&datagram)).expect("send");
                }
            },
            criterion::BatchSize::PerIteration,
        );
    });
}

criterion_group!(benches, bench);
criterion_main!(benches);
