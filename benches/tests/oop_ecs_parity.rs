//! The object-oriented baseline (`fdm_benches::oop`) and the ECS
//! (`fdm_ecs`'s EquationsOfMotion) fly the same fleets to bit-identical
//! states, sequentially and in parallel, so the `fleet` benchmark compares
//! equal work. Both go through the same [`Model`] interface.

use std::sync::Arc;

use fdm_benches::oop::{world_states, Fleet};
use fdm_core::bourg::Bourg;
use fdm_core::model::Model;
use fdm_core::palmer::Palmer;
use fdm_ecs::systems::{equations_of_motion_parallel, equations_of_motion_sequential};
use fdm_ecs::{Execution, FleetOutputs, Resources, Simulation};
use fdm_tests::ecs::StateBits;

const N: usize = 1_000;
const FRAMES: usize = 90;
const FPS: f64 = 30.0;

fn fleet_world<M: Model>(execution: Execution) -> Simulation {
    let resources = Resources::new(FPS).unwrap().with_execution(execution);
    let mut sim = Simulation::new(resources);
    sim.spawn_fleet::<M>(&Arc::new(M::default_aircraft()), 0..N, FleetOutputs::None);
    sim
}

fn check<M: Model>() -> Vec<M::State>
where
    M::State: StateBits,
{
    let members: Vec<_> = (0..N).map(M::fleet_member).collect();
    let mut oop = Fleet::of::<M>(&M::default_aircraft(), &members);
    let mut seq = fleet_world::<M>(Execution::Sequential);
    let mut par = fleet_world::<M>(Execution::Parallel);
    // The world's query order is the spawn order, the objects' order.
    assert_eq!(world_states::<M>(seq.world()), oop.states::<M>());
    let res = *seq.resources();

    for frame in 0..FRAMES {
        equations_of_motion_sequential::<M>(seq.world_mut(), &res);
        equations_of_motion_parallel::<M>(par.world_mut(), &res);
        if frame % 2 == 0 {
            oop.step_sequential(FPS);
        } else {
            oop.step_parallel(FPS);
        }
    }
    let oop_states = oop.states::<M>();
    assert_eq!(oop_states.len(), N);
    for (name, sim) in [("sequential", &seq), ("parallel", &par)] {
        let ecs = world_states::<M>(sim.world());
        assert_eq!(ecs.len(), N);
        for (i, (e, o)) in ecs.iter().zip(&oop_states).enumerate() {
            assert_eq!(
                e.state_bits(),
                o.state_bits(),
                "{} {name} aircraft {i}: {e:?} != {o:?}",
                M::NAME
            );
        }
    }
    // They really flew, and not all alike.
    let first = oop_states[0].state_bits();
    assert!(oop_states.iter().any(|s| s.state_bits() != first));
    assert_ne!(oop_states[0], members[0].1);
    oop_states
}

#[test]
fn palmer_oop_and_ecs_fly_bit_identical_fleets() {
    let states = check::<Palmer>();
    assert!((states[0].time_s - 3.0).abs() < 1e-9);
}

#[test]
fn bourg_oop_and_ecs_fly_bit_identical_fleets() {
    let states = check::<Bourg>();
    assert!(states[0].speed_ftps() > 0.0);
    assert!((states[0].time_s - 3.0).abs() < 1e-6);
}
