//! Fleet throughput of the ECS shell against a plain loop over a `Vec`.
//!
//! Per model (Palmer, Bourg) and fleet size (1 000, 100 000 aircraft):
//!
//! * `plain_vec`: `states[i] = step(&aircraft, &controls[i], &states[i], dt)`
//!   over two `Vec`s with one shared `&Aircraft`: the floor the ECS is
//!   measured against;
//! * `ecs_eom_sequential` / `ecs_eom_parallel`: the EquationsOfMotion system
//!   alone, one thread / rayon's pool;
//! * `ecs_frame_sequential` / `ecs_frame_parallel`: a whole frame of the
//!   thesis schedule (FlightControl, EquationsOfMotion, MakePacket, SendPacket)
//!   with no FlightGear links, so nothing is sent.
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
use std::time::{Duration, Instant};

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use fdm_suite::fdm_core::bourg::{self, Aircraft, BourgControls, BourgState};
use fdm_suite::fdm_core::palmer::{self, Flaps, PalmerAircraft, PalmerControls, PalmerState};
use fdm_suite::fdm_ecs::systems::{equations_of_motion_parallel, equations_of_motion_sequential};
use fdm_suite::fdm_ecs::{Execution, Resources, Simulation, World};

const FPS: f64 = 30.0;
/// Frames between resets to the initial states.
const RESET_EVERY: u64 = 300;
const SIZES: [usize; 2] = [1_000, 100_000];

fn palmer_fleet(n: usize) -> Vec<(PalmerControls, PalmerState)> {
    (0..n)
        .map(|i| {
            let controls = PalmerControls {
                throttle: 0.5 + (i % 11) as f64 / 20.0,
                alpha_deg: 2.0 + (i % 5) as f64,
                bank_deg: (i % 21) as f64 - 10.0,
                flaps: [Flaps::Up, Flaps::Deg20][i % 2],
            };
            let state = PalmerState {
                time_s: 0.0,
                position_m: [i as f64 * 10.0, 0.0, 500.0].into(),
                velocity_mps: [45.0 + (i % 10) as f64, 0.0, 0.0].into(),
            };
            (controls, state)
        })
        .collect()
}

fn bourg_fleet(n: usize) -> Vec<(BourgControls, BourgState)> {
    (0..n)
        .map(|i| {
            let mut controls = BourgControls::initial();
            controls.thrust_lb = 500.0 + (i % 21) as f32 * 100.0;
            let mut state = BourgState::initial();
            state.position.y = (i % 1000) as f32 * 20.0;
            (controls, state)
        })
        .collect()
}

/// One model as the bench needs it.
trait Model {
    type Aircraft: Send + Sync + 'static;
    type Controls: Copy;
    type State: Copy + Send + Sync + 'static;
    const NAME: &'static str;
    fn aircraft() -> Self::Aircraft;
    fn fleet(n: usize) -> Vec<(Self::Controls, Self::State)>;
    fn step(
        a: &Self::Aircraft,
        c: &Self::Controls,
        s: &Self::State,
        res: &Resources,
    ) -> Self::State;
    fn spawn(sim: &mut Simulation, a: &Arc<Self::Aircraft>, c: Self::Controls, s: Self::State);
}

struct Palmer;

impl Model for Palmer {
    type Aircraft = PalmerAircraft;
    type Controls = PalmerControls;
    type State = PalmerState;
    const NAME: &'static str = "palmer";

    fn aircraft() -> PalmerAircraft {
        PalmerAircraft::cessna_172()
    }

    fn fleet(n: usize) -> Vec<(PalmerControls, PalmerState)> {
        palmer_fleet(n)
    }

    fn step(
        a: &PalmerAircraft,
        c: &PalmerControls,
        s: &PalmerState,
        res: &Resources,
    ) -> PalmerState {
        palmer::step(a, c, s, res.dt_palmer_s())
    }

    fn spawn(sim: &mut Simulation, a: &Arc<PalmerAircraft>, c: PalmerControls, s: PalmerState) {
        sim.spawn_palmer(Arc::clone(a), c, s, None);
    }
}

struct Bourg;

impl Model for Bourg {
    type Aircraft = Aircraft;
    type Controls = BourgControls;
    type State = BourgState;
    const NAME: &'static str = "bourg";

    fn aircraft() -> Aircraft {
        Aircraft::bourg_default()
    }

    fn fleet(n: usize) -> Vec<(BourgControls, BourgState)> {
        bourg_fleet(n)
    }

    fn step(a: &Aircraft, c: &BourgControls, s: &BourgState, res: &Resources) -> BourgState {
        bourg::step(a, c, s, res.dt_bourg_s())
    }

    fn spawn(sim: &mut Simulation, a: &Arc<Aircraft>, c: BourgControls, s: BourgState) {
        sim.spawn_bourg(Arc::clone(a), c, s, None);
    }
}

/// Times `iters` frames of `frame`, calling `reset` (untimed) every
/// [`RESET_EVERY`] frames.
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

/// Writes the initial states back into the world, in query order.
fn reset_world<S: Copy + Send + Sync + 'static>(world: &mut World, initial: &[S]) {
    for (state, init) in world.query_mut::<&mut S>().into_iter().zip(initial) {
        *state = *init;
    }
}

fn bench_model<M: Model>(c: &mut Criterion) {
    let aircraft = Arc::new(M::aircraft());
    let res = Resources::new(FPS).unwrap();
    for n in SIZES {
        let mut group = c.benchmark_group(format!("{}/{n}", M::NAME));
        group.throughput(Throughput::Elements(n as u64));
        if n >= 100_000 {
            group.sample_size(10);
        }
        let fleet = M::fleet(n);

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
                            *state = M::step(&aircraft, controls, state, &res);
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
                equations_of_motion_sequential as fn(&mut World, &Resources),
                ["ecs_eom_sequential", "ecs_frame_sequential"],
            ),
            (
                Execution::Parallel,
                equations_of_motion_parallel,
                ["ecs_eom_parallel", "ecs_frame_parallel"],
            ),
        ] {
            let mut sim = Simulation::new(res.with_execution(execution));
            for &(controls, state) in &fleet {
                M::spawn(&mut sim, &aircraft, controls, state);
            }
            let initial: Vec<M::State> = sim.world().query::<&M::State>().iter().copied().collect();
            let resources = *sim.resources();
            group.bench_function(BenchmarkId::from_parameter(names[0]), |b| {
                b.iter_custom(|iters| {
                    timed_frames(
                        iters,
                        sim.world_mut(),
                        |world| eom(world, &resources),
                        |world| reset_world(world, &initial),
                    )
                });
            });
            group.bench_function(BenchmarkId::from_parameter(names[1]), |b| {
                b.iter_custom(|iters| {
                    timed_frames(iters, &mut sim, Simulation::run_frame, |sim| {
                        reset_world(sim.world_mut(), &initial)
                    })
                });
            });
        }
        group.finish();
    }
}

criterion_group!(benches, bench_model::<Palmer>, bench_model::<Bourg>);
criterion_main!(benches);
