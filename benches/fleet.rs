//! Fleet throughput, ECS against the object-oriented baseline, at 1, 100,
//! 10 000, 100 000 and 1 000 000 aircraft per model (the question the thesis
//! left "not measured", §6.1).
//!
//! One iteration is one frame of the whole fleet at 30 FPS; criterion reports
//! aircraft-steps per second (`Throughput::Elements(n)`). Per model (group
//! `fleet_palmer`, `fleet_bourg`) and fleet size:
//!
//! * `ecs_seq` / `ecs_par`: fdm-ecs's EquationsOfMotion system
//!   (`equations_of_motion_sequential` / `_parallel`, rayon's global pool,
//!   one thread per core) over a world spawned with `Simulation::spawn_fleet`,
//!   every aircraft a full entity;
//! * `oop_seq` / `oop_par`: the same fleet as a `Vec<Box<dyn Aircraft>>` of
//!   objects that own their data ([`fdm_benches::oop`]), stepped through a
//!   virtual call, in a loop / with rayon's `par_iter_mut`.
//!
//! Both fly the demonstration fleets of the models (`Model::fleet_member`,
//! as `sim-cli fleet` does: distinct controls and states) and end in bit-identical
//! states (`tests/oop_ecs_parity.rs`), so the ECS/OOP ratio at a size is
//! the cost of the layout and the dispatch alone. Every 300 frames the fleet
//! is put back to its initial states outside the timed region, so every
//! variant flies the same 10 s of flight whatever its iteration count.
//!
//! `benches/ecs_fleet.rs` compares the ECS with a plain `Vec` loop and times
//! whole frames (Place included) at 1 000 and 100 000 aircraft.
//!
//! ```text
//! cargo bench --bench fleet                    # everything, 5 to 7 minutes
//! cargo bench --bench fleet -- fleet_palmer/   # one model
//! python3 scripts/fleet_chart.py               # the chart, from target/criterion
//! ```

use std::hint::black_box;
use std::sync::Arc;
use std::time::Duration;

use criterion::{
    criterion_group, criterion_main, BenchmarkId, Criterion, SamplingMode, Throughput,
};
use fdm_benches::oop::{set_world_states, world_states, Fleet};
use fdm_benches::timed_frames;
use fdm_core::bourg::Bourg;
use fdm_core::model::Model;
use fdm_core::palmer::Palmer;
use fdm_ecs::systems::{equations_of_motion_parallel, equations_of_motion_sequential};
use fdm_ecs::{Execution, FleetOutputs, Resources, Simulation};

/// Fleet sizes.
const SIZES: [usize; 5] = [1, 100, 10_000, 100_000, 1_000_000];
/// The fleets' frame rate.
const FPS: f64 = 30.0;

fn bench_model<M: Model>(c: &mut Criterion) {
    for n in SIZES {
        let mut group = c.benchmark_group(format!("fleet_{}", M::NAME));
        group.throughput(Throughput::Elements(n as u64));
        group.warm_up_time(Duration::from_secs(1));
        if n >= 100_000 {
            // 20 to 300 ms a frame: a few frames per sample.
            group.sample_size(10);
            group.sampling_mode(SamplingMode::Flat);
            group.measurement_time(Duration::from_secs(4));
        } else {
            group.sample_size(20);
            group.measurement_time(Duration::from_secs(2));
        }

        // Worlds and fleets are built on first use, so a filtered run
        // (`-- fleet_palmer/ecs_par`) does not build the others.
        for (execution, name) in [
            (Execution::Sequential, "ecs_seq"),
            (Execution::Parallel, "ecs_par"),
        ] {
            let eom = match execution {
                Execution::Sequential => equations_of_motion_sequential::<M>,
                Execution::Parallel => equations_of_motion_parallel::<M>,
            };
            let mut setup: Option<(Simulation, Vec<M::State>)> = None;
            group.bench_function(BenchmarkId::new(name, n), |b| {
                let (sim, initial) = setup.get_or_insert_with(|| {
                    let resources = Resources::new(FPS)
                        .expect("30 frames per second is valid")
                        .with_execution(execution);
                    let mut sim = Simulation::new(resources);
                    sim.spawn_fleet::<M>(
                        &Arc::new(M::default_aircraft()),
                        0..n,
                        FleetOutputs::Placement,
                    );
                    let initial = world_states::<M>(sim.world());
                    (sim, initial)
                });
                let resources: Resources = *sim.resources();
                b.iter_custom(|iters| {
                    timed_frames(
                        iters,
                        sim.world_mut(),
                        |w| eom(black_box(w), &resources),
                        |w| set_world_states::<M>(w, initial),
                    )
                });
            });
        }

        let mut setup: Option<(Fleet, Vec<M::State>)> = None;
        for (parallel, name) in [(false, "oop_seq"), (true, "oop_par")] {
            group.bench_function(BenchmarkId::new(name, n), |b| {
                let (fleet, initial) = setup.get_or_insert_with(|| {
                    let members: Vec<_> = (0..n).map(M::fleet_member).collect();
                    let fleet = Fleet::of::<M>(&M::default_aircraft(), &members);
                    let initial = fleet.states::<M>();
                    (fleet, initial)
                });
                b.iter_custom(|iters| {
                    timed_frames(
                        iters,
                        fleet,
                        |f| {
                            if parallel {
                                black_box(f).step_parallel(FPS);
                            } else {
                                black_box(f).step_sequential(FPS);
                            }
                        },
                        |f| f.set_states::<M>(initial),
                    )
                });
            });
        }
        group.finish();
    }
}

fn bench(c: &mut Criterion) {
    bench_model::<Palmer>(c);
    bench_model::<Bourg>(c);
}

criterion_group!(benches, bench);
criterion_main!(benches);
