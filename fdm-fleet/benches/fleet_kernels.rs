//! Aircraft-steps per second of fleets: the scalar step in a loop over an array
//! of (state, controls) against `Fleet<Palmer>` in `exact` and `fast` precision
//! (group `palmer_fleet`) and against `Fleet<Bourg>` (group `bourg_fleet`, 1/30 s
//! steps), at 1,000 / 100,000 / 1,000,000 aircraft, on 1 and 2 threads.
//!
//! Every benchmark steps the whole fleet once per iteration (throughput in
//! aircraft-steps), and every iteration flies the same stretch of the
//! members' flights: the first [`WINDOW_S`] seconds, from a copy of the
//! starting fleet taken anew (untimed) at the end of each stretch. (Before,
//! the fleets kept flying from one iteration to the next, so a benchmark
//! timed whatever part of the flights its number of iterations reached, and
//! a Bourg step costs more later in the flights: a faster kernel, given more
//! iterations, timed later and dearer states.) One thread runs without rayon
//! (`step` and a plain loop); two threads run the rayon versions
//! (`par_step`, `par_iter_mut`) inside a 2-thread pool.
//!
//! ```sh
//! cargo bench -p fdm-fleet --bench fleet_kernels -- --warm-up-time 1 --measurement-time 3
//! ```
//!
//! Group `divider`: this CPU's throughput of the two operations that bound
//! the kernels (BENCHMARKS.md, "Distance to the divider"): 1,024
//! independent `f64` and `f32` divisions and square roots a pass, in the
//! widest vectors the CPU has (the fleets' own dispatch, [`pulp::Arch`]),
//! throughput in lane-operations. With the kernels' counts of divisions and
//! square roots per aircraft-step, they give each kernel's floor:
//!
//! ```sh
//! cargo bench -p fdm-fleet --bench fleet_kernels -- 'divider|/1t/1000$' --warm-up-time 1 --measurement-time 3
//! ```

use std::hint::black_box;
use std::time::{Duration, Instant};

use criterion::{criterion_group, criterion_main, Bencher, BenchmarkId, Criterion, Throughput};
use fdm_core::bourg::{self, Bourg, BourgAction, BourgAircraft, BourgControls, BourgState};
use fdm_core::palmer::{step, Flaps, Palmer, PalmerAircraft, PalmerControls, PalmerState};
use fdm_fleet::{Fleet, Precision};
use pulp::{Arch, Simd, WithSimd};
use rayon::prelude::*;

const CESSNA: PalmerAircraft = PalmerAircraft::cessna_172();
const DT: f64 = 0.1;
/// The stretch of the members' flights every benchmark times, seconds.
const WINDOW_S: f64 = 30.0;

/// Times `step`, one call per iteration, on `start`'s copy flying the first
/// `window` steps of its flights, again and again: the copy is taken anew,
/// outside the timing, after every `window` steps. So each timed step is a
/// step of that stretch, whatever the number of iterations criterion picks.
fn time_stretch<F: Clone>(
    b: &mut Bencher<'_>,
    start: &F,
    window: u64,
    mut step: impl FnMut(&mut F),
) {
    b.iter_custom(|iters| {
        let mut fleet = start.clone();
        let mut timed = Duration::ZERO;
        for i in 0..iters {
            if i > 0 && i % window == 0 {
                fleet = start.clone();
            }
            let begin = Instant::now();
            step(&mut fleet);
            timed += begin.elapsed();
        }
        black_box(&fleet);
        timed
    });
}

/// A deterministic mix of take-off rolls from rest (on the ground, with ground
/// effect) and climbing aircraft at 50 to 2,000 m, every one with its own
/// controls.
fn members(n: usize) -> Vec<(PalmerState, PalmerControls)> {
    let mut seed = 0x5EED_u64;
    let mut unit = move || {
        seed = seed.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = seed;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        #[allow(clippy::cast_precision_loss)] // 53 random bits, exact
        let u = ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64;
        u
    };
    (0..n)
        .map(|i| {
            let controls = PalmerControls {
                throttle: 0.5 + 0.5 * unit(),
                alpha_deg: 2.0 + 6.0 * unit(),
                bank_deg: -10.0 + 20.0 * unit(),
                flaps: [Flaps::Up, Flaps::Deg20][i % 2],
                brakes: false,
            };
            let mut state = PalmerState::at_rest();
            if i % 4 != 0 {
                state.position_m.z = 50.0 + 1950.0 * unit();
                state.velocity_mps.x = 30.0 + 20.0 * unit();
                state.velocity_mps.y = -10.0 + 20.0 * unit();
            }
            (state, controls)
        })
        .collect()
}

fn pools() -> Vec<(usize, rayon::ThreadPool)> {
    [1, 2]
        .into_iter()
        .map(|t| {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(t)
                .build()
                .expect("thread pool");
            (t, pool)
        })
        .collect()
}

/// Bourg aircraft from the reference start, each with its own thrust and
/// surfaces (held), so they spread over climbs, dives and turns.
fn bourg_members(n: usize) -> Vec<(BourgState, BourgControls)> {
    let actions = [
        BourgAction::PitchUp,
        BourgAction::PitchDown,
        BourgAction::RollLeft,
        BourgAction::RollRight,
        BourgAction::FlapsDown,
    ];
    (0..n)
        .map(|i| {
            let mut c = BourgControls::initial();
            for _ in 0..(i % 10) {
                c = c.apply(BourgAction::ThrustUp);
            }
            (BourgState::initial(), c.apply(actions[i % actions.len()]))
        })
        .collect()
}

fn bench_bourg(c: &mut Criterion) {
    const DT_BOURG: f32 = 1.0 / 30.0;
    let aircraft = BourgAircraft::bourg_default();
    let pools = pools();
    let mut group = c.benchmark_group("bourg_fleet");
    group.sample_size(10);
    #[allow(clippy::cast_possible_truncation, clippy::cast_sign_loss)] // 900
    let bourg_window = (WINDOW_S * f64::from(DT_BOURG.recip())).round() as u64;
    for n in [1_000, 100_000, 1_000_000] {
        let members = bourg_members(n);
        group.throughput(Throughput::Elements(n as u64));
        for (threads, pool) in &pools {
            let threads = *threads;
            let id = |what: &str| BenchmarkId::new(format!("{what}/{threads}t"), n);
            let window = bourg_window;
            group.bench_function(id("scalar"), |b| {
                if threads == 1 {
                    time_stretch(b, &members, window, |scalar| {
                        for (s, c) in scalar {
                            *s = bourg::step(&aircraft, c, s, DT_BOURG);
                        }
                    });
                } else {
                    time_stretch(b, &members, window, |scalar| {
                        pool.install(|| {
                            scalar.par_iter_mut().with_min_len(256).for_each(|(s, c)| {
                                *s = bourg::step(&aircraft, c, s, DT_BOURG);
                            });
                        });
                    });
                }
            });
            let mut fleet = Fleet::<Bourg>::new(aircraft).expect("fleet");
            for (s, c) in &members {
                fleet.push(*s, *c);
            }
            group.bench_function(id("exact"), |b| {
                if threads == 1 {
                    time_stretch(b, &fleet, window, |f| f.step(DT_BOURG));
                } else {
                    time_stretch(b, &fleet, window, |f| pool.install(|| f.par_step(DT_BOURG)));
                }
            });
        }
    }
    group.finish();
}

fn bench(c: &mut Criterion) {
    let pools = pools();
    let mut group = c.benchmark_group("palmer_fleet");
    group.sample_size(10);
    for n in [1_000, 100_000, 1_000_000] {
        let members = members(n);
        group.throughput(Throughput::Elements(n as u64));
        for (threads, pool) in &pools {
            let threads = *threads;
            let id = |what: &str| BenchmarkId::new(format!("{what}/{threads}t"), n);

            #[allow(clippy::cast_possible_truncation, clippy::cast_sign_loss)] // 300
            let window = (WINDOW_S / DT).round() as u64;
            group.bench_function(id("scalar"), |b| {
                if threads == 1 {
                    time_stretch(b, &members, window, |scalar| {
                        for (s, c) in scalar {
                            *s = step(&CESSNA, c, s, DT);
                        }
                    });
                } else {
                    time_stretch(b, &members, window, |scalar| {
                        pool.install(|| {
                            scalar.par_iter_mut().with_min_len(256).for_each(|(s, c)| {
                                *s = step(&CESSNA, c, s, DT);
                            });
                        });
                    });
                }
            });

            for precision in [Precision::Exact, Precision::Fast] {
                let fleet =
                    Fleet::<Palmer>::from_states(CESSNA, members.iter().copied()).expect("fleet");
                // The stretch stays finite (a fleet of NaN would time
                // another path).
                let mut end = fleet.clone();
                for _ in 0..window {
                    end.step_with(DT, precision).expect("precision");
                }
                let finite = end.states().filter(PalmerState::is_finite).count();
                assert_eq!(finite, n, "a benchmark fleet went non-finite");
                group.bench_function(id(precision.name()), |b| {
                    if threads == 1 {
                        time_stretch(b, &fleet, window, |f| {
                            f.step_with(DT, precision).expect("precision");
                        });
                    } else {
                        time_stretch(b, &fleet, window, |f| {
                            pool.install(|| f.par_step_with(DT, precision))
                                .expect("precision");
                        });
                    }
                });
            }
        }
    }
    group.finish();
}

/// Lane-operations a pass of the `divider` group.
const DIVIDER_LANES: usize = 1024;

/// `out[i] = op(a[i], b[i])` for every `i`, compiled for the instruction set
/// [`Arch::dispatch`] picks, so the loop is vectorised as wide as the CPU
/// allows; every element independent (throughput, not latency).
struct LaneOps<'a, T, F> {
    a: &'a [T],
    b: &'a [T],
    out: &'a mut [T],
    op: F,
}

impl<T: Copy, F: Fn(T, T) -> T> WithSimd for LaneOps<'_, T, F> {
    type Output = ();

    #[inline(always)]
    fn with_simd<S: Simd>(self, _simd: S) {
        for ((o, &a), &b) in self.out.iter_mut().zip(self.a).zip(self.b) {
            *o = (self.op)(a, b);
        }
    }
}

/// Benchmark `name`: one [`LaneOps`] pass of `op` over `a` and `b`
/// (monomorphised per `op`, so the operation is inlined into the vector loop).
fn lane_ops<T: Copy + Default, F: Fn(T, T) -> T + Copy>(
    group: &mut criterion::BenchmarkGroup<'_, criterion::measurement::WallTime>,
    arch: Arch,
    name: &str,
    a: &[T],
    b: &[T],
    op: F,
) {
    let mut out = vec![T::default(); a.len()];
    group.bench_function(name, |bench| {
        bench.iter(|| {
            arch.dispatch(LaneOps {
                a: black_box(a),
                b: black_box(b),
                out: &mut out,
                op,
            });
            black_box(&out);
        });
    });
}

fn bench_divider(c: &mut Criterion) {
    let arch = Arch::new();
    #[allow(clippy::cast_precision_loss)] // small integers, exact
    let a: Vec<f64> = (0..DIVIDER_LANES).map(|i| 1.0 + i as f64 / 7.0).collect();
    #[allow(clippy::cast_precision_loss)] // small integers, exact
    let b: Vec<f64> = (0..DIVIDER_LANES).map(|i| 3.0 + i as f64 / 5.0).collect();
    #[allow(clippy::cast_possible_truncation)] // f32 operands, as Bourg's
    let (a32, b32): (Vec<f32>, Vec<f32>) = (
        a.iter().map(|&x| x as f32).collect(),
        b.iter().map(|&x| x as f32).collect(),
    );
    let mut group = c.benchmark_group("divider");
    group.throughput(Throughput::Elements(DIVIDER_LANES as u64));
    lane_ops(&mut group, arch, "f64_div", &a, &b, |x: f64, y: f64| x / y);
    lane_ops(&mut group, arch, "f64_sqrt", &a, &b, |x: f64, _: f64| {
        x.sqrt()
    });
    lane_ops(&mut group, arch, "f32_div", &a32, &b32, |x: f32, y: f32| {
        x / y
    });
    lane_ops(
        &mut group,
        arch,
        "f32_sqrt",
        &a32,
        &b32,
        |x: f32, _: f32| x.sqrt(),
    );
    group.finish();
}

criterion_group!(benches, bench, bench_bourg, bench_divider);
criterion_main!(benches);
