//! One step of the Bourg model from a representative flying state: the
//! thesis "roll" scenario (thrust up on frames 1-5, pitch up 6-246, roll right
//! 247-307) flown to frame 280, in the middle of the roll with the ailerons
//! deflected, banked and turning, all eight elements well above 1 ft/s.
//!
//! Run: `cargo bench --bench bourg_step -- --warm-up-time 1 --measurement-time 5`.

use std::hint::black_box;

use criterion::{criterion_group, criterion_main, Criterion};
use fdm_core::bourg::{step, BourgAction, BourgAircraft, BourgControls, BourgState};
use fdm_core::script::Script;

const DT: f32 = 1.0 / 30.0;

fn flying_state() -> (BourgAircraft, BourgControls, BourgState) {
    let script = Script::<BourgAction>::parse("1-5 thrust-up\n6-246 pitch-up\n247-307 roll-right")
        .expect("script parses");
    let aircraft = BourgAircraft::bourg_default();
    let mut controls = BourgControls::initial();
    let mut state = BourgState::initial();
    for frame in 1..=280 {
        controls = controls.neutralize_surfaces();
        for action in script.actions_at(frame) {
            controls = controls.apply(action);
        }
        state = step(&aircraft, &controls, &state, DT);
    }
    // The next frame's controls: the roll key is still held.
    let controls = controls.neutralize_surfaces().apply(BourgAction::RollRight);
    (aircraft, controls, state)
}

fn bench_step(c: &mut Criterion) {
    let (aircraft, controls, state) = flying_state();
    c.bench_function("bourg_step_f32", |b| {
        b.iter(|| {
            step(
                black_box(&aircraft),
                black_box(&controls),
                black_box(&state),
                black_box(DT),
            )
        });
    });
}

criterion_group!(benches, bench_step);
criterion_main!(benches);
