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
//!   one thread per core) over a world spawned with `Simulation::spawn_*`,
//!   every aircraft a full entity;
//! * `oop_seq` / `oop_par`: the same fleet as a `Vec<Box<dyn Aircraft>>` of
//!   objects that own their data ([`fdm_suite::oop`]), stepped through a
//!   virtual call, in a loop / with rayon's `par_iter_mut`.
//!
//! Both fly the fleets of `sim-cli fleet` (`sim_cli::fleet::palmer_fleet`,
//! `bourg_fleet`: distinct controls and states) and end in bit-identical
//! states (`tests/oop_ecs_parity.rs`), so the ECS/OOP ratio at a size is
//! the cost of the layout and the dispatch alone. Every 300 frames the fleet
//! is put back to its initial states outside the timed region, so every
//! variant flies the same 10 s of flight whatever its iteration count.
//!
//! `benches/ecs_fleet.rs` compares the ECS with a plain `Vec` loop and times
//! whole frames (MakePacket included) at 1 000 and 100 000 aircraft.
//!
//! ```text
//! cargo bench --bench fleet                    # everything, 5 to 7 minutes
//! cargo bench --bench fleet -- fleet_palmer/   # one model
//! python3 scripts/fleet_chart.py               # the chart, from target/criterion
//! ```

use std::hint::black_box;
use std::time::{Duration, Instant};

use criterion::{
    criterion_group, criterion_main, BenchmarkId, Criterion, SamplingMode, Throughput,
};
use fdm_suite::fdm_ecs::systems::{equations_of_motion_parallel, equations_of_motion_sequential};
use fdm_suite::fdm_ecs::{Execution, Resources, Simulation};
use fdm_suite::oop::{Fleet, FleetState, TimeSteps};
use sim_cli::args::ModelKind;
use sim_cli::fleet::{bourg_fleet, palmer_fleet, spawn_fleet, FLEET_FPS};

/// Fleet sizes.
const SIZES: [usize; 5] = [1, 100, 10_000, 100_000, 1_000_000];
/// Frames between resets to the initial states.
const RESET_EVERY: u64 = 300;

/// Times `iters` frames of `frame`, calling `reset` (untimed) every
/// [`RESET_EVERY`] frames, starting with a reset.
fn timed_frames<T>(
    iters: u64,
    target: &mut T,
    mut frame: impl FnMut(&mut T),
    mut reset: impl FnMut(&mut T),
) -> Duration {
    let mut total = Duration::ZERO;
    for i in 0..iters {
        if i % RESET_EVERY == 0 {
            reset(target);
        }
        let start = Instant::now();
        frame(target);
        total += start.elapsed();
    }
    total
}

/// Writes `initial` back into the objects, in order.
fn reset_fleet(fleet: &mut Fleet, initial: &[FleetState]) {
    for (object, init) in fleet.aircraft_mut().iter_mut().zip(initial) {
        object.set_state(*init);
    }
}

fn bench_model(c: &mut Criterion, model: ModelKind) {
    let dt = TimeSteps::at_fps(FLEET_FPS);
    for n in SIZES {
        let mut group = c.benchmark_group(format!("fleet_{}", model.name()));
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
                Execution::Sequential => equations_of_motion_sequential,
                Execution::Parallel => equations_of_motion_parallel,
            };
            let mut setup: Option<(Simulation, Vec<FleetState>)> = None;
            group.bench_function(BenchmarkId::new(name, n), |b| {
                let (sim, initial) = setup.get_or_insert_with(|| {
                    let sim = spawn_fleet(model, n, execution);
                    let initial = FleetState::of_world(sim.world());
                    (sim, initial)
                });
                let resources: Resources = *sim.resources();
                b.iter_custom(|iters| {
                    timed_frames(
                        iters,
                        sim.world_mut(),
                        |w| eom(black_box(w), &resources),
                        |w| FleetState::write_to_world(w, initial),
                    )
                });
            });
        }

        let mut setup: Option<(Fleet, Vec<FleetState>)> = None;
        for (parallel, name) in [(false, "oop_seq"), (true, "oop_par")] {
            group.bench_function(BenchmarkId::new(name, n), |b| {
                let (fleet, initial) = setup.get_or_insert_with(|| {
                    let fleet = match model {
                        ModelKind::Palmer => Fleet::palmer(&palmer_fleet(n)),
                        ModelKind::Bourg => Fleet::bourg(&bourg_fleet(n)),
                    };
                    let initial = fleet.states();
                    (fleet, initial)
                });
                b.iter_custom(|iters| {
                    timed_frames(
                        iters,
                        fleet,
                        |f| {
                            if parallel {
                                black_box(f).step_parallel(&dt);
                            } else {
                                black_box(f).step_sequential(&dt);
                            }
                        },
                        |f| reset_fleet(f, initial),
                    )
                });
            });
        }
        group.finish();
    }
}

fn bench(c: &mut Criterion) {
    bench_model(c, ModelKind::Palmer);
    bench_model(c, ModelKind::Bourg);
}

criterion_group!(benches, bench);
criterion_main!(benches);
