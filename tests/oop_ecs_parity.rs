//! The object-oriented baseline (`fdm_suite::oop`) and the ECS
//! (`fdm_ecs`'s EquationsOfMotion) fly the same fleets to bit-identical
//! states, sequentially and in parallel, so `benches/fleet.rs` compares equal
//! work.

use fdm_suite::fdm_ecs::systems::{equations_of_motion_parallel, equations_of_motion_sequential};
use fdm_suite::fdm_ecs::Execution;
use fdm_suite::oop::{Fleet, FleetState, TimeSteps};
use sim_cli::args::ModelKind;
use sim_cli::fleet::{bourg_fleet, palmer_fleet, spawn_fleet, FLEET_FPS};

const N: usize = 1_000;
const FRAMES: usize = 90;

/// Bit patterns of every number of a state (so -0.0 and 0.0 differ, NaN equals NaN).
fn bits(state: &FleetState) -> Vec<u64> {
    match state {
        FleetState::Palmer(s) => {
            let mut v = vec![s.time_s.to_bits()];
            v.extend(
                s.position_m
                    .iter()
                    .chain(s.velocity_mps.iter())
                    .map(|x| x.to_bits()),
            );
            v
        }
        FleetState::Bourg(s) => {
            let vectors = [
                &s.position,
                &s.velocity,
                &s.velocity_body,
                &s.angular_velocity,
                &s.euler_angles_deg,
            ];
            let mut v: Vec<u64> = vectors
                .iter()
                .flat_map(|v| v.iter())
                .chain(s.orientation.coords.iter())
                .chain(std::iter::once(&s.speed))
                .map(|x| u64::from(x.to_bits()))
                .collect();
            v.push(u64::from(s.stalling));
            v
        }
    }
}

fn check(model: ModelKind) {
    let dt = TimeSteps::at_fps(FLEET_FPS);
    let mut oop = match model {
        ModelKind::Palmer => Fleet::palmer(&palmer_fleet(N)),
        ModelKind::Bourg => Fleet::bourg(&bourg_fleet(N)),
    };
    let mut seq = spawn_fleet(model, N, Execution::Sequential);
    let mut par = spawn_fleet(model, N, Execution::Parallel);
    // The world's query order is the spawn order, the objects' order.
    assert_eq!(FleetState::of_world(seq.world()), oop.states());
    let res = *seq.resources();
    assert_eq!(res.dt_palmer_s(), dt.palmer_s);
    assert_eq!(res.dt_bourg_s(), dt.bourg_s);

    for frame in 0..FRAMES {
        equations_of_motion_sequential(seq.world_mut(), &res);
        equations_of_motion_parallel(par.world_mut(), &res);
        if frame % 2 == 0 {
            oop.step_sequential(&dt);
        } else {
            oop.step_parallel(&dt);
        }
    }
    let oop_states = oop.states();
    assert_eq!(oop_states.len(), N);
    for (name, sim) in [("sequential", &seq), ("parallel", &par)] {
        let ecs = FleetState::of_world(sim.world());
        assert_eq!(ecs.len(), N);
        for (i, (e, o)) in ecs.iter().zip(&oop_states).enumerate() {
            assert_eq!(
                bits(e),
                bits(o),
                "{model:?} {name} aircraft {i}: {e:?} != {o:?}"
            );
        }
    }
    // They really flew, and not all alike.
    let first = &oop_states[0];
    assert!(oop_states.iter().any(|s| bits(s) != bits(first)));
    match first {
        FleetState::Palmer(s) => assert!((s.time_s - 3.0).abs() < 1e-9),
        FleetState::Bourg(s) => assert!(s.speed > 0.0),
    }
}

#[test]
fn palmer_oop_and_ecs_fly_bit_identical_fleets() {
    check(ModelKind::Palmer);
}

#[test]
fn bourg_oop_and_ecs_fly_bit_identical_fleets() {
    check(ModelKind::Bourg);
}
