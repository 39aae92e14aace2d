//! Fleet throughput of the ECS shell against a plain loop over a `Vec`.
//!
//! Per model (Palmer, Bourg) and fleet size (1 000, 100 000 aircraft):
//!
//! * `plain_vec`: `states[i] = M::step(&aircraft, &controls[i], &states[i], dt)`
//!   over two `Vec`s with one shared aircraft: the floor the ECS is measured
//!   against;
//! * `ecs_eom_sequential` / `ecs_eom_parallel`: the EquationsOfMotion system
//!   alone, one thread / rayon's pool;
//! * `ecs_frame_sequential` / `ecs_frame_parallel`: a whole frame of the
//!   thesis schedule (FlightControl, EquationsOfMotion, FlightStatus,
//!   Place). Until issue 22 the frame also built every aircraft's FlightGear
//!   datagram (MakePacket) and ran SendPacket; the datagram is an output of
//!   the run library now, so frames measured before and after that change
//!   are not comparable.
//!
//! One iteration is one frame of the whole fleet; the throughput is in
//! aircraft-steps per second. Every 300 frames the fleet is put back to its
//! initial states, outside the timed region, so every variant flies the same
//! stretch of flight whatever the iteration count.
//!
//! ```text
//! cargo bench --bench ecs_fleet -- --warm-up-time 1 --measurement-time 5
//! ```

use std::hint::black_box;
use std::sync::Arc;

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use fdm_benches::oop::{set_world_states, world_states};
use fdm_benches::timed_frames;
use fdm_core::bourg::Bourg;
use fdm_core::model::Model;
use fdm_core::palmer::Palmer;
use fdm_ecs::systems::{equations_of_motion_parallel, equations_of_motion_sequential};
use fdm_ecs::{Execution, FleetOutputs, Resources, Simulation, World};

const FPS: f64 = 30.0;
const SIZES: [usize; 2] = [1_000, 100_000];

fn bench_model<M: Model>(c: &mut Criterion) {
    let aircraft = Arc::new(M::default_aircraft());
    let res = Resources::new(FPS).unwrap();
    let dt = res.time_step::<M>();
    for n in SIZES {
        let mut group = c.benchmark_group(format!("{}/{n}", M::NAME));
        group.throughput(Throughput::Elements(n as u64));
        if n >= 100_000 {
            group.sample_size(10);
        }
        let fleet: Vec<_> = (0..n).map(M::fleet_member).collect();
        let controls: Vec<_> = fleet.iter().map(|(c, _)| *c).collect();
        let initial: Vec<_> = fleet.iter().map(|(_, s)| *s).collect();
        let mut states = initial.clone();
        group.bench_function(BenchmarkId::from_parameter("plain_vec"), |b| {
            b.iter_custom(|iters| {
                timed_frames(
                    iters,
                    &mut states,
                    |states| {
                        for (state, controls) in states.iter_mut().zip(&controls) {
                            *state = M::step(&aircraft, controls, state, dt);
                        }
                        black_box(states);
                    },
                    |states| states.copy_from_slice(&initial),
                )
            });
        });
        for (execution, eom, names) in [
            (
                Execution::Sequential,
                equations_of_motion_sequential::<M> as fn(&mut World, &Resources),
                ["ecs_eom_sequential", "ecs_frame_sequential"],
            ),
            (
                Execution::Parallel,
                equations_of_motion_parallel::<M>,
                ["ecs_eom_parallel", "ecs_frame_parallel"],
            ),
        ] {
            let mut sim = Simulation::new(res.with_execution(execution));
            sim.spawn_fleet::<M>(&aircraft, 0..n, FleetOutputs::Placement);
            let initial = world_states::<M>(sim.world());
            let resources = *sim.resources();
            group.bench_function(BenchmarkId::from_parameter(names[0]), |b| {
                b.iter_custom(|iters| {
                    timed_frames(
                        iters,
                        sim.world_mut(),
                        |world| eom(world, &resources),
                        |world| set_world_states::<M>(world, &initial),
                    )
                });
            });
            group.bench_function(BenchmarkId::from_parameter(names[1]), |b| {
                b.iter_custom(|iters| {
                    timed_frames(iters, &mut sim, Simulation::run_frame, |sim| {
                        set_world_states::<M>(sim.world_mut(), &initial);
                    })
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
