//! What a study costs per run, against the bare fleet kernel, in one run.
//!
//! `study_block/study`: one block of 1,024 runs of the study benchmark's file
//! (`examples/studies/palmer_million.toml`: a trimmed start at 300 ft and
//! 70 kt, dispersed speed and heading, a scripted climb, five measures), cut
//! to 10 s (300 frames at 30 Hz), flown by `Study::fly_runs` on one thread:
//! set-up, scripts, the exact fleet kernel and the measure trackers.
//! `study_block/fleet`: the same 1,024 × 300 aircraft-steps of the exact
//! kernel alone (`Fleet::fly_with`), every aircraft from the undispersed
//! start with the climb's controls. The ratio of the two is the study's
//! overhead around the physics (BENCHMARKS.md, "Studies").
//!
//! Run: `cargo bench -p fdm-study --bench study_block -- --warm-up-time 2 --measurement-time 10`.

use std::hint::black_box;

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use fdm_core::model::Model;
use fdm_core::palmer::{Palmer, PalmerAction};
use fdm_fleet::{Fleet, Precision};
use fdm_run::StartOptions;
use fdm_study::{FlyOptions, Study, BLOCK_RUNS};

/// The study benchmark's file, as committed.
const PALMER_MILLION: &str = include_str!("../../examples/studies/palmer_million.toml");
/// Frames flown per run here: 10 s at 30 Hz.
const FRAMES: u64 = 300;

fn bench_block(c: &mut Criterion) {
    let study =
        Study::from_toml_str(&PALMER_MILLION.replace("duration_s = 60.0", "duration_s = 10.0"))
            .expect("the committed study file parses")
            .with_runs(BLOCK_RUNS)
            .expect("1,024 runs");
    assert_eq!(study.frames(), FRAMES);
    let one_thread = FlyOptions {
        threads: 1,
        ..FlyOptions::default()
    };
    // The undispersed start and the climb's controls (the script's first
    // frames: full throttle, alpha up twice).
    let start = StartOptions {
        altitude_ft: Some(300.0),
        speed_kt: Some(70.0),
        trim: true,
        ..StartOptions::default()
    };
    let (start, _) = start
        .start::<Palmer>(Palmer::default_aircraft(), Palmer::initial_controls())
        .expect("the study's start trims");
    let mut controls = start.controls;
    for action in [PalmerAction::ThrottleUp; 10]
        .into_iter()
        .chain([PalmerAction::AlphaUp; 2])
    {
        controls = Palmer::apply(&start.aircraft, controls, action);
    }
    let dt = Palmer::time_step(30.0);

    let mut group = c.benchmark_group("study_block");
    group.sample_size(10);
    group.throughput(Throughput::Elements(BLOCK_RUNS * FRAMES));
    group.bench_function("study", |b| {
        b.iter(|| {
            let table = study.fly_runs(0..BLOCK_RUNS, &one_thread).expect("flies");
            assert_eq!(table.len() as u64, BLOCK_RUNS);
            black_box(table)
        });
    });
    group.bench_function("fleet", |b| {
        b.iter(|| {
            let mut fleet = Fleet::<Palmer>::try_new(start.aircraft).expect("valid aircraft");
            for _ in 0..BLOCK_RUNS {
                fleet.push(start.state, controls);
            }
            for _ in 0..FRAMES {
                fleet
                    .fly_with(dt, Precision::Exact)
                    .expect("exact is available");
            }
            black_box(fleet.state(0))
        });
    });
    group.finish();
}

criterion_group!(benches, bench_block);
criterion_main!(benches);
