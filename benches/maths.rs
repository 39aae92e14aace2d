//! The deterministic maths of `fdm_core::math` against the C library's, in one
//! run (so the ratio is measured under one load): 1,024 × `pow(x, 5.25)`
//! (Palmer's pressure ratio, `x` a temperature ratio in `[0.5, 1.1)`) and
//! 1,024 × `asinf(x)` (Bourg's element angles, `x` in `[-1, 1)`), each as
//! `fdm_core::math`'s and as `f64::powf` / `f32::asin` (glibc's `pow` and
//! `asinf` on Linux). The two give the same bits on these inputs (asserted
//! before timing, so the comparison is like for like).
//!
//! Run: `cargo bench -p fdm-benches --bench maths -- --warm-up-time 1 --measurement-time 5`.

use std::hint::black_box;

use criterion::{criterion_group, criterion_main, Criterion};

/// `n` evenly spread values from `low` (inclusive) to `high` (exclusive).
fn spread(n: u32, low: f64, high: f64) -> Vec<f64> {
    (0..n)
        .map(|i| low + (high - low) * f64::from(i) / f64::from(n))
        .collect()
}

fn bench_maths(c: &mut Criterion) {
    let temperature_ratios = spread(1024, 0.5, 1.1);
    #[allow(clippy::cast_possible_truncation)] // f32 inputs, as Bourg's step gives them
    let sines: Vec<f32> = spread(1024, -1.0, 1.0).iter().map(|&x| x as f32).collect();
    for &x in &temperature_ratios {
        assert_eq!(
            fdm_core::math::pow(x, 5.25).to_bits(),
            x.powf(5.25).to_bits()
        );
    }
    for &x in &sines {
        assert_eq!(fdm_core::math::asinf(x).to_bits(), x.asin().to_bits());
    }
    let mut group = c.benchmark_group("maths");
    group.bench_function("pow_x_5.25/fdm_core", |b| {
        b.iter(|| {
            for &x in black_box(&temperature_ratios) {
                black_box(fdm_core::math::pow(x, black_box(5.25)));
            }
        });
    });
    group.bench_function("pow_x_5.25/libc", |b| {
        b.iter(|| {
            for &x in black_box(&temperature_ratios) {
                black_box(x.powf(black_box(5.25)));
            }
        });
    });
    // Latency: each call's argument depends on the previous result (as in
    // a step, where every RK4 stage's pressure needs the last stage's
    // altitude); `acc * 1e-300` adds nothing but the dependency.
    group.bench_function("pow_x_5.25_chained/fdm_core", |b| {
        b.iter(|| {
            let mut acc = 0.0;
            for &x in black_box(&temperature_ratios) {
                acc = fdm_core::math::pow(x + acc * 1e-300, 5.25);
            }
            acc
        });
    });
    group.bench_function("pow_x_5.25_chained/libc", |b| {
        b.iter(|| {
            let mut acc = 0.0_f64;
            for &x in black_box(&temperature_ratios) {
                acc = (x + acc * 1e-300).powf(5.25);
            }
            acc
        });
    });
    group.bench_function("asinf/fdm_core", |b| {
        b.iter(|| {
            for &x in black_box(&sines) {
                black_box(fdm_core::math::asinf(x));
            }
        });
    });
    group.bench_function("asinf/libc", |b| {
        b.iter(|| {
            for &x in black_box(&sines) {
                black_box(x.asin());
            }
        });
    });
    group.finish();
}

criterion_group!(benches, bench_maths);
criterion_main!(benches);
