//! The thesis's figure 13: Palmer against Bourg, 100 frames per iteration at
//! 10, 30, 60 and 100 frames per second (thesis §3.6 and §5.3).
//!
//! As in the thesis, the models are called directly (no ECS): one iteration
//! flies 100 frames from the model's initial state with fixed controls and
//! returns the final state.
//!
//! * Palmer: `dt = 1.0 / fps` (f64), from rest on the runway at full throttle,
//!   alpha 4°, flaps 20 (the take-off roll and, at 10 FPS, the lift-off).
//! * Bourg: `dt = 1.0f32 / fps as f32`, from [`BourgState::initial`] with
//!   [`BourgControls::initial`] (500 lb of thrust, surfaces neutral).
//!
//! Both functions sit in one criterion group with the frame rate as the
//! parameter, so criterion's report for the group
//! (`target/criterion/fig13_100_frames/report/index.html`) draws the thesis's
//! line chart, and the Palmer/Bourg ratio per frame rate comes from one run.
//! The single-step benches are `palmer_step` and `bourg_step`.
//!
//! ```text
//! cargo bench --bench palmer_vs_bourg -- --warm-up-time 1 --measurement-time 5
//! ```

use std::hint::black_box;

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use fdm_core::bourg::{self, BourgAircraft, BourgControls, BourgState};
use fdm_core::palmer::{self, Flaps, PalmerAircraft, PalmerControls, PalmerState};

/// Frames per iteration (the thesis's).
const FRAMES: u32 = 100;
/// The thesis's frame rates.
const FPS: [u32; 4] = [10, 30, 60, 100];

fn palmer_frames(
    aircraft: &PalmerAircraft,
    controls: &PalmerControls,
    dt: f64,
    frames: u32,
) -> PalmerState {
    let mut state = PalmerState::at_rest();
    for _ in 0..frames {
        state = palmer::step(aircraft, controls, &state, dt);
    }
    state
}

fn bourg_frames(
    aircraft: &BourgAircraft,
    controls: &BourgControls,
    dt: f32,
    frames: u32,
) -> BourgState {
    let mut state = BourgState::initial();
    for _ in 0..frames {
        state = bourg::step(aircraft, controls, &state, dt);
    }
    state
}

fn bench(c: &mut Criterion) {
    let cessna = PalmerAircraft::cessna_172();
    let take_off = PalmerControls {
        throttle: 1.0,
        alpha_deg: 4.0,
        bank_deg: 0.0,
        flaps: Flaps::Deg20,
        brakes: false,
    };
    let bourg_aircraft = BourgAircraft::bourg_default();
    let bourg_controls = BourgControls::initial();

    let mut group = c.benchmark_group("fig13_100_frames");
    group.throughput(Throughput::Elements(u64::from(FRAMES)));
    for fps in FPS {
        let dt_palmer = 1.0 / f64::from(fps);
        #[allow(clippy::cast_precision_loss)] // the original's own conversion
        let dt_bourg = 1.0f32 / fps as f32;
        group.bench_with_input(BenchmarkId::new("palmer", fps), &dt_palmer, |b, &dt| {
            b.iter(|| {
                palmer_frames(
                    black_box(&cessna),
                    black_box(&take_off),
                    black_box(dt),
                    FRAMES,
                )
            });
        });
        group.bench_with_input(BenchmarkId::new("bourg", fps), &dt_bourg, |b, &dt| {
            b.iter(|| {
                bourg_frames(
                    black_box(&bourg_aircraft),
                    black_box(&bourg_controls),
                    black_box(dt),
                    FRAMES,
                )
            });
        });
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
