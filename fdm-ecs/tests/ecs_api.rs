//! Parts of the public API the simulation tests do not reach (found by
//! mutation testing, docs/testing.md), each checked against its documented
//! contract: `Params` compares the aircraft data it shares, not the sharing,
//! and its debug form names the model and shows that data; `FrameInput` keeps
//! the pushed actions in order until drained; `Resources::with_execution`
//! sets the mode (both modes give the same results, so only the field shows
//! it); `Schedule` knows its models, `push` appends a system that then runs
//! last and `insert_after` puts one right after the last system of a name;
//! a spawned aircraft's status is valid before the first frame; the
//! simulation's debug form counts its entities; `spawn_fleet` spawns the
//! model's fleet members in order; `aircraft` gives back the shared
//! parameters, for that model only; the sequential and parallel
//! EquationsOfMotion systems step as `fdm_core::model::advance` does; and
//! Place marks diverged a finite state with a finite view that has no
//! geodetic position.

use std::sync::Arc;

use fdm_core::bourg::Bourg;
use fdm_core::model::Model;
use fdm_core::model::{advance, FlightStatus};
use fdm_core::palmer::{Palmer, PalmerAircraft, PalmerControls, PalmerState};
use fdm_ecs::components::{FrameInput, Params};
use fdm_ecs::{Execution, FleetOutputs, Resources, Schedule, Simulation, System, World};
use nalgebra::Vector3;

/// The schedule of a world with a Palmer and a Bourg aircraft, Palmer's
/// first (what `Schedule::thesis` was before fdm-ecs stopped naming models).
fn thesis() -> Schedule {
    Schedule::for_no_model()
        .with_model::<Palmer>()
        .with_model::<Bourg>()
}

#[test]
fn params_are_equal_when_their_aircraft_data_are() {
    let aircraft = Palmer::default_aircraft();
    let a = Params::<Palmer>::new(Arc::new(aircraft));
    // Another allocation of the same data, and a clone sharing the first.
    let b = Params::<Palmer>::new(Arc::new(aircraft));
    assert!(!Arc::ptr_eq(&a.0, &b.0));
    assert!(a == b);
    assert!(a == a.clone());
    let heavier = PalmerAircraft {
        wing_area_m2: aircraft.wing_area_m2 * 2.0,
        ..aircraft
    };
    let c = Params::<Palmer>::new(Arc::new(heavier));
    assert!(a != c);
    assert!(!(a == c));
}

#[test]
fn params_debug_names_the_model_and_shows_the_aircraft() {
    let palmer = Params::<Palmer>::new(Arc::new(Palmer::default_aircraft()));
    let text = format!("{palmer:?}");
    assert!(text.starts_with("Params(\"palmer\", "), "{text}");
    assert!(
        text.contains(&format!("{:?}", Palmer::default_aircraft())),
        "{text}"
    );
    let bourg = Params::<Bourg>::new(Arc::new(Bourg::default_aircraft()));
    let text = format!("{bourg:?}");
    assert!(text.starts_with("Params(\"bourg\", "), "{text}");
}

#[test]
fn frame_input_keeps_actions_in_order_until_drained() {
    let mut input = FrameInput::new();
    assert!(input.is_empty());
    assert_eq!(input.actions(), &[] as &[char]);
    input.push('e');
    input.push('d');
    input.push('e');
    assert!(!input.is_empty());
    assert_eq!(input.actions(), &['e', 'd', 'e']);
    assert_eq!(input.drain().collect::<Vec<_>>(), ['e', 'd', 'e']);
    assert!(input.is_empty());
    assert_eq!(input.actions(), &[] as &[char]);
}

#[test]
fn with_execution_sets_the_mode() {
    let res = Resources::new(30.0).unwrap();
    assert_eq!(res.execution, Execution::Sequential);
    let par = res.with_execution(Execution::Parallel);
    assert_eq!(par.execution, Execution::Parallel);
    assert_eq!(par.with_execution(Execution::Sequential), res);
}

#[test]
fn schedule_knows_its_models() {
    let none = Schedule::for_no_model();
    assert!(!none.has_model::<Palmer>() && !none.has_model::<Bourg>());
    let palmer = Schedule::for_no_model().with_model::<Palmer>();
    assert!(palmer.has_model::<Palmer>() && !palmer.has_model::<Bourg>());
    let thesis = thesis();
    assert!(thesis.has_model::<Palmer>() && thesis.has_model::<Bourg>());
}

/// A system that counts the frames it ran in, through the world.
fn count_frames(world: &mut World, _: &Resources) {
    for counter in world.query_mut::<&mut u64>() {
        *counter += 1;
    }
}

#[test]
fn pushed_system_runs_last() {
    let mut schedule = thesis();
    let before = schedule.systems().len();
    schedule.push(System {
        name: "Counter",
        run: count_frames,
    });
    assert_eq!(schedule.systems().len(), before + 1);
    assert_eq!(schedule.systems().last().unwrap().name, "Counter");
    let mut world = World::new();
    let counter = world.spawn((0u64,));
    let mut res = Resources::new(30.0).unwrap();
    let mut order = Vec::new();
    schedule.run_observed(&mut world, &mut res, |name, _| order.push(name));
    schedule.run(&mut world, &mut res);
    assert_eq!(order.last(), Some(&"Counter"));
    assert_eq!(*world.get::<&u64>(counter).unwrap(), 2);
}

#[test]
fn insert_after_goes_after_the_last_system_of_that_name() {
    let mut schedule = thesis();
    let names = |s: &Schedule| s.systems().iter().map(|s| s.name).collect::<Vec<_>>();
    let before = names(&schedule);
    // FlightStatus appears once per model; the new system follows the last.
    let last = before.iter().rposition(|n| *n == "FlightStatus").unwrap();
    assert!(before[..last].contains(&"FlightStatus"));
    let counter = System {
        name: "Counter",
        run: count_frames,
    };
    assert!(schedule.insert_after("FlightStatus", counter));
    let mut expected = before.clone();
    expected.insert(last + 1, "Counter");
    assert_eq!(names(&schedule), expected);
    assert!(!schedule.insert_after("NoSuchSystem", counter));
    assert_eq!(names(&schedule), expected);
}

#[test]
fn a_spawned_aircraft_has_its_status_before_the_first_frame() {
    let mut sim = Simulation::new(Resources::new(30.0).unwrap());
    let aircraft = Arc::new(Palmer::default_aircraft());
    let controls = PalmerControls::default();
    let at = |z: f64| PalmerState {
        position_m: Vector3::new(0.0, 0.0, z),
        ..PalmerState::at_rest()
    };
    let flying = sim.spawn::<Palmer>(Arc::clone(&aircraft), controls, at(300.0));
    let parked = sim.spawn::<Palmer>(Arc::clone(&aircraft), controls, at(0.0));
    let broken = sim.spawn::<Palmer>(Arc::clone(&aircraft), controls, at(f64::NAN));
    assert_eq!(sim.frame(), 0);
    assert_eq!(sim.status(flying), Some(FlightStatus::Airborne));
    assert_eq!(sim.status(parked), Some(FlightStatus::OnGround));
    assert_eq!(sim.status(broken), Some(FlightStatus::Diverged));
    let text = format!("{sim:?}");
    assert!(text.starts_with("Simulation {"), "{text}");
    assert!(text.contains("entities: 3"), "{text}");
}

#[test]
fn spawn_fleet_spawns_the_members_in_order() {
    for outputs in [FleetOutputs::None, FleetOutputs::Placement] {
        let mut sim = Simulation::new(Resources::new(30.0).unwrap());
        let aircraft = Arc::new(Palmer::default_aircraft());
        sim.spawn_fleet::<Palmer>(&aircraft, 3..8, outputs);
        assert_eq!(sim.world().len(), 5);
        let mut query = sim.world().query::<(&PalmerState, &PalmerControls)>();
        let got: Vec<(PalmerState, PalmerControls)> = query.iter().map(|(s, c)| (*s, *c)).collect();
        let expected: Vec<(PalmerState, PalmerControls)> = (3..8)
            .map(|i| {
                let (c, s) = Palmer::fleet_member(i);
                (s, c)
            })
            .collect();
        assert_eq!(got, expected, "{outputs:?}");
    }
}

#[test]
fn aircraft_gives_back_the_shared_parameters() {
    let mut sim = Simulation::new(Resources::new(30.0).unwrap());
    let aircraft = Arc::new(Palmer::default_aircraft());
    let e = sim.spawn::<Palmer>(
        Arc::clone(&aircraft),
        PalmerControls::default(),
        PalmerState::at_rest(),
    );
    let shared = sim.aircraft::<Palmer>(e).unwrap();
    assert!(Arc::ptr_eq(&shared, &aircraft));
    assert!(sim.aircraft::<Bourg>(e).is_none());
}

/// A simulation of two Palmer fleet members whose schedule is only `system`
/// (set through `schedule_mut`).
fn with_only(system: System) -> Simulation {
    let mut sim = Simulation::new(Resources::new(30.0).unwrap());
    sim.spawn_fleet::<Palmer>(
        &Arc::new(Palmer::default_aircraft()),
        0..2,
        FleetOutputs::Placement,
    );
    *sim.schedule_mut() = Schedule::new(vec![system]);
    assert_eq!(sim.schedule().systems().len(), 1);
    sim
}

#[test]
fn both_equations_of_motion_variants_step_like_advance() {
    use fdm_ecs::systems::{equations_of_motion_parallel, equations_of_motion_sequential};
    let aircraft = Palmer::default_aircraft();
    let dt = Palmer::time_step(30.0);
    for run in [
        equations_of_motion_sequential::<Palmer>,
        equations_of_motion_parallel::<Palmer>,
    ] {
        let mut sim = with_only(System {
            name: "EquationsOfMotion",
            run,
        });
        sim.run_frame();
        let mut query = sim.world().query::<&PalmerState>();
        let got: Vec<PalmerState> = query.iter().copied().collect();
        let expected: Vec<PalmerState> = (0..2)
            .map(|i| {
                let (controls, state) = Palmer::fleet_member(i);
                advance::<Palmer>(&aircraft, &controls, FlightStatus::Airborne, &state, dt).0
            })
            .collect();
        assert_eq!(got, expected);
        assert_ne!(got[0], Palmer::fleet_member(0).1, "not stepped");
    }
}

/// A position of 1.7e308 m is finite, and so is the view, but no geodetic
/// position exists for it: Place must mark it diverged (so no output is
/// handed a placement made from it).
#[test]
fn place_marks_an_unplaceable_state_diverged() {
    use fdm_ecs::systems::place;
    let mut sim = with_only(System {
        name: "Place",
        run: place::<Palmer>,
    });
    let aircraft = Palmer::default_aircraft();
    let controls = PalmerControls::default();
    let far = PalmerState {
        position_m: Vector3::new(1.7e308, 0.0, 1.7e308),
        velocity_mps: Vector3::new(45.0, 0.0, 0.0),
        ..PalmerState::at_rest()
    };
    let view = Palmer::view(&aircraft, &controls, &far);
    assert!(Palmer::is_finite(&far) && view.is_finite());
    let placed = fgnet::bridge::display(&view, &sim.resources().origin);
    assert!(
        !(placed.geodetic.lat_deg.is_finite()
            && placed.geodetic.lon_deg.is_finite()
            && placed.geodetic.alt_m.is_finite())
    );
    let e = sim.spawn::<Palmer>(Arc::new(aircraft), controls, far);
    let at_spawn = sim.geodetic(e).unwrap().lat_deg.to_bits();
    // `spawn` added Palmer's systems back: Place alone again.
    *sim.schedule_mut() = Schedule::new(vec![System {
        name: "Place",
        run: place::<Palmer>,
    }]);
    sim.run_frame();
    assert_eq!(sim.status(e), Some(FlightStatus::Diverged));
    assert_eq!(sim.geodetic(e).unwrap().lat_deg.to_bits(), at_spawn);
}
