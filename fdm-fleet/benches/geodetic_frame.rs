//! Whole frames of a fleet that is placed on the Earth every frame (what
//! FlightGear multiplayer and DIS outputs need): every aircraft flown one
//! frame with its flight status and its WGS-84 geodetic position computed,
//! at 100,000 aircraft, on 1 and 2 threads (group `geodetic_frame`).
//!
//! * `per_aircraft`: the per-aircraft path, a `Vec` of (state, status,
//!   controls) and for each aircraft `fdm_core::model::fly` then
//!   `GeodeticOrigin::model_to_geodetic` of its position (the model's view
//!   position, computed directly); rayon `par_iter_mut` on 2 threads;
//! * `lanes_exact` / `lanes_fast` (Palmer) / `lanes` (Bourg): the fleet's
//!   `fly` / `par_fly` (bit-identical to `fly` per aircraft in `exact`), its
//!   `positions_m`, then `BatchGeodesy::geodetic_into` /
//!   `par_geodetic_into` (bit-identical to `model_to_geodetic`).
//!
//! Throughput is in aircraft-frames; the fleets keep flying from one
//! iteration to the next (the demonstration fleets, `Model::fleet_member`).
//!
//! ```sh
//! cargo bench -p fdm-fleet --bench geodetic_frame -- --warm-up-time 1 --measurement-time 5
//! ```

use std::hint::black_box;

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use fdm_core::bourg::{Bourg, BourgState, Vector3};
use fdm_core::geodesy::{Geodetic, GeodeticOrigin, METRES_PER_FOOT};
use fdm_core::model::{fly, FlightStatus, Model};
use fdm_core::palmer::{Palmer, PalmerState};
use fdm_fleet::geodesy::BatchGeodesy;
use fdm_fleet::{Fleet, LaneFleet, Precision};
use rayon::prelude::*;

const N: usize = 100_000;
const FPS: f64 = 30.0;

/// One aircraft of the per-aircraft path.
struct Member<M: Model> {
    controls: M::Controls,
    state: M::State,
    status: FlightStatus,
    geodetic: Geodetic,
}

fn members<M: Model>(n: usize) -> Vec<Member<M>> {
    (0..n)
        .map(|i| {
            let (controls, state) = M::fleet_member(i);
            Member {
                controls,
                state,
                status: FlightStatus::initial(M::height_m(&state)),
                geodetic: GeodeticOrigin::WRIGHT_PATTERSON,
            }
        })
        .collect()
}

/// One frame of one aircraft on the per-aircraft path.
#[inline]
fn frame<M: Model>(
    aircraft: &M::Aircraft,
    origin: &GeodeticOrigin,
    position_m: fn(&M::State) -> Vector3<f64>,
    m: &mut Member<M>,
) {
    (m.state, m.status) = fly::<M>(aircraft, &m.controls, m.status, &m.state, M::time_step(FPS));
    m.geodetic = origin.model_to_geodetic(position_m(&m.state));
}

fn palmer_position(s: &PalmerState) -> Vector3<f64> {
    s.position_m
}

fn bourg_position(s: &BourgState) -> Vector3<f64> {
    s.position_ft.map(f64::from) * METRES_PER_FOOT
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

/// The per-aircraft path and the lanes path(s) of model `F::Model`.
fn bench_model<F: LaneFleet>(
    c: &mut Criterion,
    position_m: fn(&<F::Model as Model>::State) -> Vector3<f64>,
    precisions: &[(&str, Precision)],
) {
    let origin = GeodeticOrigin::from_geodetic(GeodeticOrigin::WRIGHT_PATTERSON).expect("origin");
    let batch = BatchGeodesy::new(origin);
    let aircraft = F::Model::default_aircraft();
    let mut group = c.benchmark_group("geodetic_frame");
    group.sample_size(10);
    group.throughput(Throughput::Elements(N as u64));
    for (threads, pool) in &pools() {
        let threads = *threads;
        let id = |what: &str| BenchmarkId::new(format!("{}/{what}/{threads}t", F::Model::NAME), N);
        let mut scalar = members::<F::Model>(N);
        group.bench_function(id("per_aircraft"), |b| {
            if threads == 1 {
                b.iter(|| {
                    for m in &mut scalar {
                        frame(&aircraft, &origin, position_m, m);
                    }
                });
            } else {
                b.iter(|| {
                    pool.install(|| {
                        scalar
                            .par_iter_mut()
                            .with_min_len(256)
                            .for_each(|m| frame(&aircraft, &origin, position_m, m));
                    });
                });
            }
        });
        black_box(&scalar);
        for &(name, precision) in precisions {
            let mut fleet = F::demonstration(N).expect("fleet");
            let (mut positions, mut geodetic) = (Vec::new(), Vec::new());
            group.bench_function(id(name), |b| {
                b.iter(|| {
                    pool.install(|| {
                        fleet.par_fly(FPS, precision).expect("precision");
                        fleet.positions_m(&mut positions);
                        if threads == 1 {
                            batch.geodetic_into(&positions, &mut geodetic);
                        } else {
                            batch.par_geodetic_into(&positions, &mut geodetic);
                        }
                    });
                });
            });
            black_box(&geodetic);
        }
    }
    group.finish();
}

fn bench(c: &mut Criterion) {
    bench_model::<Fleet<Palmer>>(
        c,
        palmer_position,
        &[
            ("lanes_exact", Precision::Exact),
            ("lanes_fast", Precision::Fast),
        ],
    );
    bench_model::<Fleet<Bourg>>(c, bourg_position, &[("lanes", Precision::Exact)]);
}

criterion_group!(benches, bench);
criterion_main!(benches);
