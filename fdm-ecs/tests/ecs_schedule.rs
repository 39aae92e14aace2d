//! The systems run in the declared order, FlightControl → EquationsOfMotion →
//! FlightStatus → Place (each phase once per model in the world), every
//! frame, and each sees the data the one before it wrote in the same frame:
//! checked by observing the world after every system of a frame. (What the
//! FlightGear output sends from Place's placement is checked in
//! `fdm-run/tests/run_flightgear.rs`.)

use std::sync::Arc;

use fdm_core::bourg::{self, Bourg, BourgAction, BourgAircraft, BourgControls, BourgState};
use fdm_core::model::Model;
use fdm_core::palmer::{self, Palmer, PalmerAction, PalmerAircraft, PalmerControls, PalmerState};
use fdm_core::script::Script;
use fdm_ecs::components::{Attitude, FrameInput, Geodetic};
use fdm_ecs::{Entity, World};
use fdm_ecs::{Resources, Schedule, Simulation};

/// The schedule of a world with a Palmer and a Bourg aircraft, Palmer's
/// first (what `Schedule::thesis` was before fdm-ecs stopped naming models).
fn thesis() -> Schedule {
    Schedule::for_no_model()
        .with_model::<Palmer>()
        .with_model::<Bourg>()
}

fn get<T: fdm_ecs::hecs::Component + Clone>(world: &World, e: Entity) -> T {
    (*world.get::<&T>(e).unwrap()).clone()
}

/// The phases of one frame of the thesis schedule for the two models.
const THESIS_TRACE: [&str; 8] = [
    "FlightControl",
    "FlightControl",
    "EquationsOfMotion",
    "EquationsOfMotion",
    "FlightStatus",
    "FlightStatus",
    "Place",
    "Place",
];

#[test]
fn the_thesis_schedule_declares_each_phase_per_model_in_order() {
    let names: Vec<_> = thesis().systems().iter().map(|s| s.name).collect();
    assert_eq!(names, THESIS_TRACE);
    // Adding a model already there changes nothing.
    assert_eq!(
        thesis().with_model::<Palmer>().systems().len(),
        THESIS_TRACE.len()
    );
    // A schedule without models runs nothing; one model gets one of each phase.
    assert!(Schedule::for_no_model().systems().is_empty());
    let names: Vec<_> = Schedule::for_no_model()
        .with_model::<Bourg>()
        .systems()
        .iter()
        .map(|s| s.name)
        .collect();
    assert_eq!(
        names,
        [
            "FlightControl",
            "EquationsOfMotion",
            "FlightStatus",
            "Place"
        ]
    );
    // The default schedule is the one a new `Simulation` starts from: no
    // model until one is spawned.
    assert!(Schedule::default().systems().is_empty());
}

/// A new `Simulation` has no system; each model's systems join with its
/// first aircraft, so within a phase the models run in the order of their
/// first spawns. That order changes no result (every system of a model
/// queries only that model's aircraft): a Palmer and a Bourg aircraft end
/// with the same bits, statuses and placements whichever is spawned first.
#[test]
fn the_order_the_models_join_in_changes_no_result() {
    let fly = |palmer_first: bool| {
        let mut sim = Simulation::new(Resources::new(30.0).unwrap());
        assert!(sim.schedule().systems().is_empty());
        let spawn_palmer = |sim: &mut Simulation| {
            sim.spawn::<Palmer>(
                Arc::new(PalmerAircraft::cessna_172()),
                PalmerControls::default(),
                PalmerState::initial(),
            )
        };
        let spawn_bourg = |sim: &mut Simulation| {
            sim.spawn::<Bourg>(
                Arc::new(BourgAircraft::bourg_default()),
                BourgControls::initial(),
                BourgState::initial(),
            )
        };
        let (p, b) = if palmer_first {
            let p = spawn_palmer(&mut sim);
            (p, spawn_bourg(&mut sim))
        } else {
            let b = spawn_bourg(&mut sim);
            (spawn_palmer(&mut sim), b)
        };
        let names: Vec<_> = sim.schedule().systems().iter().map(|s| s.name).collect();
        assert_eq!(names, THESIS_TRACE);
        for frame in 0..90 {
            sim.push_input(p, PalmerAction::ThrottleUp).unwrap();
            if frame < 30 {
                sim.push_input(b, BourgAction::PitchUp).unwrap();
            }
            sim.run_frame();
        }
        let palmer = sim.state::<Palmer>(p).unwrap();
        let bourg = sim.state::<Bourg>(b).unwrap();
        (
            format!("{palmer:?} {bourg:?}"),
            [sim.status(p), sim.status(b)],
            format!("{:?} {:?}", sim.geodetic(p), sim.geodetic(b)),
        )
    };
    assert_eq!(fly(true), fly(false));
}

/// Runs frames with an observer that checks, after each system, that exactly
/// the data that system writes has changed and that it was computed from what
/// the previous systems of the same frame wrote.
#[test]
fn each_system_sees_what_the_previous_one_wrote_in_the_same_frame() {
    let res = Resources::new(30.0).unwrap();
    let palmer_aircraft = PalmerAircraft::cessna_172();
    let bourg_aircraft = BourgAircraft::bourg_default();
    let mut sim = Simulation::new(res);
    let p = sim.spawn::<Palmer>(
        Arc::new(palmer_aircraft),
        PalmerControls::default(),
        PalmerState::at_rest(),
    );
    let b = sim.spawn::<Bourg>(
        Arc::new(bourg_aircraft),
        BourgControls::initial(),
        BourgState::initial(),
    );
    // Frames 1-2 pitch up by script, frame 3 rolls left: on frame 3 the
    // elevators must be back to neutral, which only FlightControl's
    // begin-of-frame step does (a FlightControl that skipped it would leave
    // them up and fail the check below).
    sim.set_script(
        b,
        Arc::new(Script::<BourgAction>::parse("1-2 pitch-up\n3-3 roll-left\n").unwrap()),
    )
    .unwrap();

    let origin = sim.resources().origin;

    for frame in 1..=3u64 {
        sim.push_input(p, PalmerAction::ThrottleUp).unwrap();
        sim.push_input(b, BourgAction::ThrustUp).unwrap();

        let world = sim.world();
        let p_controls0: PalmerControls = get(world, p);
        let p_state0: PalmerState = get(world, p);
        let b_controls0: BourgControls = get(world, b);
        let b_state0: BourgState = get(world, b);
        let b_placed0: (Geodetic, Attitude) = (get(world, b), get(world, b));
        let script_action = if frame <= 2 {
            BourgAction::PitchUp
        } else {
            BourgAction::RollLeft
        };

        // After the last system of each phase, every model's part of that
        // phase has run.
        let mut trace = Vec::new();
        sim.run_frame_observed(|name, world| {
            trace.push(name);
            if trace.iter().filter(|n| **n == name).count() < 2 {
                return;
            }
            let p_controls: PalmerControls = get(world, p);
            let p_state: PalmerState = get(world, p);
            let b_controls: BourgControls = get(world, b);
            let b_state: BourgState = get(world, b);
            let b_placed: (Geodetic, Attitude) = (get(world, b), get(world, b));
            match name {
                "FlightControl" => {
                    // Controls updated from this frame's input; nothing else yet.
                    assert_eq!(p_controls, p_controls0.apply(PalmerAction::ThrottleUp));
                    let want = b_controls0
                        .neutralize_surfaces()
                        .apply(script_action)
                        .apply(BourgAction::ThrustUp);
                    assert_eq!(b_controls, want);
                    assert!(world
                        .get::<&FrameInput<PalmerAction>>(p)
                        .unwrap()
                        .is_empty());
                    assert!(world.get::<&FrameInput<BourgAction>>(b).unwrap().is_empty());
                    assert_eq!((p_state, b_state), (p_state0, b_state0));
                    assert_eq!(b_placed, b_placed0);
                }
                "EquationsOfMotion" => {
                    // Stepped with the controls FlightControl just wrote.
                    let dt = 1.0 / 30.0;
                    assert_eq!(
                        p_state,
                        palmer::step(&palmer_aircraft, &p_controls, &p_state0, dt)
                    );
                    assert_eq!(
                        b_state,
                        bourg::step(&bourg_aircraft, &b_controls, &b_state0, 1.0f32 / 30.0)
                    );
                    assert_eq!(b_placed, b_placed0);
                }
                "FlightStatus" => assert_eq!(b_placed, b_placed0),
                "Place" => {
                    // Placed from the state EquationsOfMotion just wrote, as
                    // the FlightGear bridge places it.
                    let view = Bourg::view(&bourg_aircraft, &b_controls, &b_state);
                    let want = fgnet::bridge::display(&view, &origin);
                    assert_eq!(b_placed, (want.geodetic, want.attitude));
                    assert_ne!(b_placed, b_placed0);
                    let view = Palmer::view(&palmer_aircraft, &p_controls, &p_state);
                    let want = fgnet::bridge::display(&view, &origin);
                    assert_eq!(get::<Attitude>(world, p), want.attitude);
                    assert_eq!(get::<Geodetic>(world, p), want.geodetic);
                }
                other => panic!("unexpected system {other}"),
            }
        });
        assert_eq!(trace, THESIS_TRACE);
        assert_eq!(sim.frame(), frame);
    }
}

#[test]
fn frame_counter_numbers_frames_from_one_for_scripts() {
    let mut sim = Simulation::new(Resources::new(30.0).unwrap());
    assert_eq!(sim.frame(), 0);
    let e = sim.spawn::<Bourg>(
        Arc::new(BourgAircraft::bourg_default()),
        BourgControls::initial(),
        BourgState::initial(),
    );
    // A single-frame rule on frame 1 and one on frame 3.
    let script =
        Script::<BourgAction>::parse("1-1 thrust-up\n3-3 thrust-down\n3-3 thrust-down\n").unwrap();
    sim.set_script(e, Arc::new(script)).unwrap();
    let mut thrust = Vec::new();
    for _ in 0..4 {
        sim.run_frame();
        thrust.push(sim.controls::<Bourg>(e).unwrap().thrust_lb);
    }
    assert_eq!(sim.frame(), 4);
    assert_eq!(thrust, [600.0, 600.0, 400.0, 400.0]);
}

#[test]
fn script_actions_come_before_queued_keys() {
    let mut sim = Simulation::new(Resources::new(10.0).unwrap());
    let p = sim.spawn::<Palmer>(
        Arc::new(PalmerAircraft::cessna_172()),
        PalmerControls {
            alpha_deg: 19.0,
            ..PalmerControls::default()
        },
        PalmerState::at_rest(),
    );
    // Script first: 19 +1 (script) = 20, +1 (key) = 20 (limit), -1 (key) = 19.
    // Keys first would give 19 +1 = 20, -1 = 19, +1 (script) = 20.
    sim.set_script(
        p,
        Arc::new(Script::<PalmerAction>::parse("1-1 alpha-up\n").unwrap()),
    )
    .unwrap();
    sim.push_input(p, PalmerAction::AlphaUp).unwrap();
    sim.push_input(p, PalmerAction::AlphaDown).unwrap();
    sim.run_frame();
    assert_eq!(sim.controls::<Palmer>(p).unwrap().alpha_deg, 19.0);
}

/// What a run leaves behind, for comparing schedules.
#[derive(Debug, PartialEq)]
struct Outcome {
    palmer: (
        PalmerControls,
        PalmerState,
        Option<fdm_core::model::FlightStatus>,
        Attitude,
    ),
    bourg: (BourgControls, BourgState, Geodetic),
}

/// Runs 20 frames of a Palmer aircraft landing (1 m up, sinking at 3 m/s,
/// throttle up by key) and a scripted Bourg aircraft (thrust up, pitch up,
/// a roll), with the thesis systems except those
/// named in `skip`, system by system as [`Schedule::run`] does.
fn outcome_without(skip: &[&str]) -> Outcome {
    outcome(Some(skip))
}

/// [`outcome_without`], or with `None` the same run through
/// `Simulation::run_frame`.
fn outcome(skip: Option<&[&str]>) -> Outcome {
    let mut sim = Simulation::new(Resources::new(30.0).unwrap());
    let p = sim.spawn::<Palmer>(
        Arc::new(PalmerAircraft::cessna_172()),
        PalmerControls::default(),
        PalmerState {
            time_s: 0.0,
            position_m: [0.0, 0.0, 1.0].into(),
            velocity_mps: [30.0, 0.0, -3.0].into(),
        },
    );
    let b = sim.spawn::<Bourg>(
        Arc::new(BourgAircraft::bourg_default()),
        BourgControls::initial(),
        BourgState::initial(),
    );
    sim.set_script(
        b,
        Arc::new(
            Script::<BourgAction>::parse("1-3 thrust-up\n1-2 pitch-up\n3-3 roll-left\n").unwrap(),
        ),
    )
    .unwrap();
    let systems: Vec<_> = thesis()
        .systems()
        .iter()
        .filter(|s| !skip.unwrap_or(&[]).contains(&s.name))
        .cloned()
        .collect();
    let mut res = *sim.resources();
    for _ in 0..20 {
        sim.push_input(p, PalmerAction::ThrottleUp).unwrap();
        if skip.is_none() {
            sim.run_frame();
            continue;
        }
        res.frame += 1;
        for system in &systems {
            (system.run)(sim.world_mut(), &res);
        }
    }
    let world = sim.world();
    Outcome {
        palmer: (get(world, p), get(world, p), sim.status(p), get(world, p)),
        bourg: (get(world, b), get(world, b), get(world, b)),
    }
}

/// Skipping any one system of the schedule changes what a run leaves
/// behind (so every system does observable work and the tests above would
/// see it missing), and the full set of systems run one by one is exactly
/// `Simulation::run_frame`.
#[test]
fn skipping_any_system_changes_the_outcome() {
    let full = outcome_without(&[]);
    // The manual loop is the simulation's own frame.
    assert_eq!(outcome(None), full);
    // The run did what the skips are to be seen against: Palmer landed,
    // Bourg's script worked.
    assert!(
        matches!(
            full.palmer.2,
            Some(fdm_core::model::FlightStatus::Landed(_))
        ),
        "{:?}",
        full.palmer.2
    );
    assert_eq!(full.bourg.0.thrust_lb, 800.0);
    for skip in [
        Schedule::FLIGHT_CONTROL,
        Schedule::EQUATIONS_OF_MOTION,
        Schedule::FLIGHT_STATUS,
        Schedule::PLACE,
    ] {
        assert_ne!(outcome_without(&[skip]), full, "without {skip}");
    }
}
