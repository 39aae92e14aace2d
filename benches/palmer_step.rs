//! One Palmer RK4 step from a representative flying state (banked climb at full
//! power, flaps 20, 150 m up), and the derived flight data.
//!
//! `cargo bench --bench palmer_step -- --warm-up-time 1 --measurement-time 5`

use std::hint::black_box;

use criterion::{criterion_group, criterion_main, Criterion};
use fdm_core::palmer::{step, Flaps, PalmerAircraft, PalmerControls, PalmerState};

fn flying_state() -> (PalmerAircraft, PalmerControls, PalmerState) {
    let cessna = PalmerAircraft::cessna_172();
    let controls = PalmerControls {
        throttle: 1.0,
        alpha_deg: 4.0,
        bank_deg: 5.0,
        flaps: Flaps::Deg20,
        brakes: false,
    };
    // Fly 30 s of the "everything" reference scenario to get a real in-flight state.
    let mut state = PalmerState::at_rest();
    for _ in 0..300 {
        state = step(&cessna, &controls, &state, 0.1);
    }
    assert!(state.position_m.z > 5.0, "not flying: {state:?}");
    (cessna, controls, state)
}

fn bench_step(c: &mut Criterion) {
    let (cessna, controls, state) = flying_state();
    c.bench_function("palmer_step", |b| {
        b.iter(|| {
            step(
                black_box(&cessna),
                black_box(&controls),
                black_box(&state),
                black_box(1.0 / 30.0),
            )
        });
    });
    c.bench_function("palmer_flight_data", |b| {
        b.iter(|| black_box(&state).flight_data());
    });
}

criterion_group!(benches, bench_step);
criterion_main!(benches);
