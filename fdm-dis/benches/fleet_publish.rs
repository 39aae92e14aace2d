//! One frame of a fleet's DIS output ([`FleetPublisher::publish`]) at
//! 100 000 Palmer aircraft, next to one frame of their steps:
//!
//! * `dis_fleet/step_100000`: one RK4 step of every aircraft, scalar, on
//!   the rayon pool (for scale; `sim-cli fleet`'s SIMD kernel is faster);
//! * `dis_fleet/publish_100000`: placing, rating and dead-reckoning every
//!   aircraft and sending the PDUs that are due (about 2 % per frame in a
//!   turning fleet at the default thresholds) to a socket on 127.0.0.1
//!   that reads nothing (the kernel drops what overflows its buffer; the
//!   `sendto` is paid either way).
//!
//! The fleet is flown 10 s first so the frames timed are ordinary ones (not
//! the first PDU of every aircraft). Each timed frame is a new frame: the
//! fleet is stepped, untimed, before it.
//!
//! `cargo bench -p fdm-dis --bench fleet_publish -- --warm-up-time 1 --measurement-time 10`

use std::hint::black_box;
use std::net::UdpSocket;

use criterion::{criterion_group, criterion_main, BatchSize, Criterion};
use fdm_core::geodesy::GeodeticOrigin;
use fdm_core::model::Model;
use fdm_core::palmer::{Palmer, PalmerControls, PalmerState};
use fdm_dis::{
    AircraftKind, DrThresholds, EntityConfig, EntityIdentity, FleetPublisher, Marking, Placement,
    Tracker, UdpSender,
};
use rayon::prelude::*;

const AIRCRAFT: usize = 100_000;
const DT_S: f64 = 1.0 / 30.0;

fn fleet() -> (Vec<PalmerControls>, Vec<PalmerState>) {
    (0..AIRCRAFT).map(Palmer::fleet_member).unzip()
}

fn step(
    aircraft: &<Palmer as Model>::Aircraft,
    controls: &[PalmerControls],
    states: &mut [PalmerState],
) {
    states
        .par_iter_mut()
        .zip(controls.par_iter())
        .for_each(|(s, c)| *s = Palmer::step(aircraft, c, s, DT_S));
}

fn bench(c: &mut Criterion) {
    let aircraft = Palmer::default_aircraft();
    let (controls, mut states) = fleet();
    let sink = UdpSocket::bind("127.0.0.1:0").expect("a local socket");
    let sender = UdpSender::new(sink.local_addr().expect("an address"), false).expect("a socket");
    let placement = Placement::new(GeodeticOrigin::default());
    let mut publisher = FleetPublisher::new(
        (0..AIRCRAFT)
            .map(|i| {
                let id = EntityIdentity::new(1, 1 + (i / 65_533) as u16, 1 + (i % 65_533) as u16)
                    .expect("valid");
                let config = EntityConfig::new(
                    id,
                    AircraftKind::CESSNA_172_SKYHAWK,
                    Marking::new("C172").expect("valid"),
                );
                Tracker::new(config, DrThresholds::default()).expect("valid")
            })
            .collect(),
    );
    let mut publish = |states: &[PalmerState]| {
        publisher.publish(&sender, &placement, |i| {
            Some(Palmer::view(&aircraft, &controls[i], &states[i]))
        })
    };
    for _ in 0..300 {
        step(&aircraft, &controls, &mut states);
        publish(&states);
    }
    let mut group = c.benchmark_group("dis_fleet");
    group.sample_size(20);
    group.bench_function("step_100000", |b| {
        b.iter(|| step(black_box(&aircraft), &controls, &mut states));
    });
    // The setup steps the fleet, the routine publishes it: both need the states.
    let states = std::cell::RefCell::new(states);
    group.bench_function("publish_100000", |b| {
        b.iter_batched_ref(
            || step(&aircraft, &controls, &mut states.borrow_mut()),
            |()| black_box(publish(&states.borrow())),
            BatchSize::PerIteration,
        );
    });
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
