//! Criterion benchmarks of the FGNetFDM v24 encoders and decoders: the
//! `to_be_bytes` path (`encode`, `decode`) against the serde +
//! bincode 2 path (`encode_bincode`, `decode_bincode`), one datagram each.
//!
//! Run: `cargo bench --bench fgnet_encode -- --warm-up-time 1 --measurement-time 5`

use std::hint::black_box;

use criterion::{criterion_group, criterion_main, Criterion};
use fgnet::{DisplayState, EngineState, FgNetFdm, DATAGRAM_LEN};

fn sample() -> FgNetFdm {
    let mut fdm = FgNetFdm::from_display(&DisplayState {
        latitude_deg: 37.625,
        longitude_deg: -122.375,
        altitude_m: 100.0,
        roll_deg: 14.3,
        pitch_deg: -7.1,
        heading_deg: 85.9,
        airspeed_kt: 90.0,
        climb_rate_fps: 8.0,
        v_north_fps: 150.0,
        engine_state: EngineState::Running,
        engine_rpm: 2400.0,
        flaps_norm: 0.5,
        ..DisplayState::default()
    });
    fdm.num_tanks = 2;
    fdm.fuel_quantity = [20.0, 19.5, 0.0, 0.0];
    fdm.num_wheels = 3;
    fdm.gear_pos = [1.0; 3];
    fdm
}

fn bench(c: &mut Criterion) {
    let fdm = sample();
    let bytes = fdm.encode();

    let mut g = c.benchmark_group("fgnet_encode");
    g.bench_function("encode_to_be_bytes", |b| {
        b.iter(|| black_box(black_box(&fdm).encode()))
    });
    g.bench_function("encode_into_to_be_bytes", |b| {
        let mut out = [0u8; DATAGRAM_LEN];
        b.iter(|| {
            black_box(&fdm).encode_into(&mut out);
            black_box(&out);
        })
    });
    g.bench_function("encode_bincode", |b| {
        b.iter(|| black_box(black_box(&fdm).encode_bincode()))
    });
    g.finish();

    let mut g = c.benchmark_group("fgnet_decode");
    g.bench_function("decode_from_be_bytes", |b| {
        b.iter(|| black_box(FgNetFdm::decode(black_box(&bytes[..]))))
    });
    g.bench_function("decode_bincode", |b| {
        b.iter(|| black_box(FgNetFdm::decode_bincode(black_box(&bytes[..]))))
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
