//! Stepping through the ECS gives the same bits as calling `fdm-core`
//! directly, for every reference scenario of both models and in both execution
//! modes; and so the ECS also reproduces the original programs' final states
//! exactly.
//!
//! * Palmer: the 4 cases of `reference/palmer.json`, 600 frames at 10 FPS,
//!   all four aircraft in one world.
//! * Bourg: the 5 cases of `reference/bourg.json`, 900 frames at 30 FPS, all
//!   five in one world, driven by their scripts (`Script::<BourgAction>::parse`)
//!   through `ScriptInput`, and again by pushing the same actions as
//!   key presses through `FrameInput`.

use fdm_core::bourg::Bourg;
use fdm_core::palmer::Palmer;
use std::sync::Arc;

use fdm_core::bourg::{
    BourgAction, BourgAircraft, BourgControls, BourgState, DELTA_THRUST_LB, MAX_THRUST_LB,
};
use fdm_core::model::Model;
use fdm_core::palmer::{PalmerAircraft, PalmerState};
use fdm_core::script::ScriptAction;
use fdm_ecs::{Execution, Resources, Simulation};
use fdm_tests::ecs::{
    bourg_bits, bourg_controls_bits, bourg_direct, bourg_reference, palmer_bits, palmer_direct,
    palmer_reference,
};

const MODES: [Execution; 2] = [Execution::Sequential, Execution::Parallel];

#[test]
fn palmer_reference_cases_through_the_ecs_are_bit_identical_to_fdm_core() {
    let (fps, frames, cases) = palmer_reference();
    assert_eq!((fps, frames, cases.len()), (10, 600, 4));
    let aircraft = Arc::new(PalmerAircraft::cessna_172());
    let resources = Resources::new(f64::from(fps)).unwrap();
    assert_eq!(resources.time_step::<Palmer>().to_bits(), 0.1f64.to_bits());

    let direct: Vec<Vec<PalmerState>> = cases
        .iter()
        .map(|case| {
            palmer_direct(
                &aircraft,
                case.controls,
                PalmerState::at_rest(),
                resources.time_step::<Palmer>(),
                frames,
            )
        })
        .collect();

    for mode in MODES {
        let mut sim = Simulation::new(resources.with_execution(mode));
        let entities: Vec<_> = cases
            .iter()
            .map(|case| {
                sim.spawn::<Palmer>(Arc::clone(&aircraft), case.controls, PalmerState::at_rest())
            })
            .collect();
        for frame in 0..frames {
            sim.run_frame();
            for (i, &entity) in entities.iter().enumerate() {
                let got = sim.state::<Palmer>(entity).unwrap();
                let want = &direct[i][usize::try_from(frame).unwrap()];
                assert_eq!(
                    palmer_bits(&got),
                    palmer_bits(want),
                    "{mode:?} {} frame {}",
                    cases[i].name,
                    frame + 1
                );
            }
        }
        for (case, &entity) in cases.iter().zip(&entities) {
            // Against the original C program, exactly (values, not bits: the
            // reference's 0 for y is +0.0, the model's may be -0.0).
            let last = sim.state::<Palmer>(entity).unwrap();
            let want = case.final_state;
            for (got, want) in [
                (last.time_s, want.time_s),
                (last.position_m.x, want.position_m.x),
                (last.position_m.y, want.position_m.y),
                (last.position_m.z, want.position_m.z),
                (last.velocity_mps.x, want.velocity_mps.x),
                (last.velocity_mps.y, want.velocity_mps.y),
                (last.velocity_mps.z, want.velocity_mps.z),
            ] {
                assert!(
                    got == want,
                    "{mode:?} {}: {got:?} vs the original's {want:?}",
                    case.name
                );
            }
            // The controls were given at spawn and never changed.
            assert_eq!(sim.controls::<Palmer>(entity).unwrap(), case.controls);
        }
    }
}

#[test]
fn bourg_reference_scripts_through_the_ecs_are_bit_identical_to_fdm_core() {
    let (fps, frames, cases) = bourg_reference();
    assert_eq!((fps, frames, cases.len()), (30, 900, 5));
    let aircraft = Arc::new(BourgAircraft::bourg_default());
    let resources = Resources::new(f64::from(fps)).unwrap();
    assert_eq!(
        resources.time_step::<Bourg>().to_bits(),
        (1.0f32 / 30.0).to_bits()
    );
    let start = (BourgControls::initial(), BourgState::initial());

    let direct: Vec<_> = cases
        .iter()
        .map(|case| {
            bourg_direct(
                &aircraft,
                &case.script,
                start,
                resources.time_step::<Bourg>(),
                frames,
            )
        })
        .collect();

    for mode in MODES {
        for keyboard in [false, true] {
            let mut sim = Simulation::new(resources.with_execution(mode));
            let entities: Vec<_> = cases
                .iter()
                .map(|case| {
                    let e = sim.spawn::<Bourg>(Arc::clone(&aircraft), start.0, start.1);
                    if !keyboard {
                        sim.set_script(e, Arc::new(case.script.clone())).unwrap();
                    }
                    e
                })
                .collect();
            for frame in 1..=frames {
                if keyboard {
                    for (case, &e) in cases.iter().zip(&entities) {
                        for action in case.script.actions_at(frame) {
                            sim.push_input(e, action).unwrap();
                        }
                    }
                }
                sim.run_frame();
                for (i, &e) in entities.iter().enumerate() {
                    let (want_controls, want_state) =
                        &direct[i][usize::try_from(frame - 1).unwrap()];
                    let what = format!(
                        "{mode:?} {} {} frame {frame}",
                        if keyboard { "keys" } else { "script" },
                        cases[i].name
                    );
                    assert_eq!(
                        bourg_controls_bits(&sim.controls::<Bourg>(e).unwrap()),
                        bourg_controls_bits(want_controls),
                        "{what}"
                    );
                    assert_eq!(
                        bourg_bits(&sim.state::<Bourg>(e).unwrap()),
                        bourg_bits(want_state),
                        "{what}"
                    );
                }
            }
            for (case, &e) in cases.iter().zip(&entities) {
                let s = sim.state::<Bourg>(e).unwrap();
                assert_eq!(
                    s.position_ft.as_slice(),
                    case.final_position_ft,
                    "{mode:?} {}",
                    case.name
                );
                assert_eq!(s.euler_angles_deg().as_slice(), case.final_euler_deg);
                assert_eq!(s.speed_ftps(), case.final_speed_ftps);
            }
        }
    }
}

#[test]
fn bourg_thrust_limits_default_to_the_core_constants_and_are_honoured() {
    let aircraft = BourgAircraft::bourg_default();
    assert_eq!(aircraft.max_thrust_lb, MAX_THRUST_LB);
    assert_eq!(aircraft.delta_thrust_lb, DELTA_THRUST_LB);

    // With the default aircraft the model interface's thrust steps are
    // `BourgControls::apply`'s, bit for bit, from any thrust.
    let thrusts = (0..=64).map(|i| i as f32 * 50.0).chain([
        -1.0,
        0.5,
        99.9,
        2950.25,
        2999.9,
        3000.1,
        1e9,
        f32::NAN,
    ]);
    for thrust in thrusts {
        for &action in BourgAction::ALL {
            let c = BourgControls {
                thrust_lb: thrust,
                ..BourgControls::initial()
            };
            let ecs = Bourg::apply(&aircraft, c, action);
            let core = c.apply(action);
            assert_eq!(
                (ecs.thrust_lb.to_bits(), ecs.rudder_deg.to_bits()),
                (core.thrust_lb.to_bits(), core.rudder_deg.to_bits()),
                "{thrust} {action:?}"
            );
            assert_eq!(
                (
                    ecs.port_aileron,
                    ecs.starboard_aileron,
                    ecs.elevators,
                    ecs.landing_flaps
                ),
                (
                    core.port_aileron,
                    core.starboard_aileron,
                    core.elevators,
                    core.landing_flaps
                )
            );
        }
    }

    // Other limits change what the keys do, through the whole shell.
    let mut limited = BourgAircraft::bourg_default();
    limited.max_thrust_lb = 1200.0;
    limited.delta_thrust_lb = 250.0;
    let mut sim = Simulation::new(Resources::new(30.0).unwrap());
    let e = sim.spawn::<Bourg>(
        Arc::new(limited),
        BourgControls::initial(),
        BourgState::initial(),
    );
    let mut seen = Vec::new();
    for _ in 0..4 {
        sim.push_input(e, BourgAction::ThrustUp).unwrap();
        sim.run_frame();
        seen.push(sim.controls::<Bourg>(e).unwrap().thrust_lb);
    }
    assert_eq!(seen, [750.0, 1000.0, 1200.0, 1200.0]);
    for _ in 0..5 {
        sim.push_input(e, BourgAction::ThrustDown).unwrap();
    }
    sim.run_frame(); // five presses in one frame
    assert_eq!(sim.controls::<Bourg>(e).unwrap().thrust_lb, 0.0);
}
