//! The `Simulation` builder API as `sim-cli` uses it: errors for entities of
//! the wrong model or gone, reset, accessors before the first frame.

use fdm_core::bourg::Bourg;
use fdm_core::palmer::Palmer;
use std::sync::Arc;

use fdm_core::bourg::{BourgAction, BourgAircraft, BourgControls, BourgState};
use fdm_core::model::Model;
use fdm_core::palmer::{PalmerAction, PalmerAircraft, PalmerControls, PalmerState};
use fdm_core::script::Script;
use fdm_ecs::components::FrameInput;
use fdm_ecs::{EcsError, Resources, Simulation};

fn palmer_and_bourg(sim: &mut Simulation) -> (fdm_ecs::Entity, fdm_ecs::Entity) {
    let p = sim.spawn::<Palmer>(
        Arc::new(PalmerAircraft::cessna_172()),
        PalmerControls {
            throttle: 1.0,
            alpha_deg: 4.0,
            ..PalmerControls::default()
        },
        PalmerState::at_rest(),
    );
    let b = sim.spawn::<Bourg>(
        Arc::new(BourgAircraft::bourg_default()),
        BourgControls::initial(),
        BourgState::initial(),
    );
    (p, b)
}

#[test]
fn invalid_frame_rates_are_rejected_and_time_steps_follow_fps() {
    for fps in [0.0, -30.0, f64::NAN, f64::INFINITY] {
        assert!(matches!(
            Resources::new(fps),
            Err(EcsError::InvalidFps { .. })
        ));
    }
    // Whole rates: the original C++'s `1.0f / N` for Bourg, `1.0 / N` for Palmer.
    for n in [1_u32, 10, 30, 60, 144, 1000] {
        let res = Resources::new(f64::from(n)).unwrap();
        assert_eq!(res.fps(), f64::from(n));
        assert_eq!(
            res.time_step::<Palmer>().to_bits(),
            (1.0 / f64::from(n)).to_bits()
        );
        assert_eq!(
            res.time_step::<Bourg>().to_bits(),
            (1.0f32 / n as f32).to_bits()
        );
    }
    // Any other rate as docs/cli.md writes it.
    for fps in [29.97, 0.5, 12.5] {
        let res = Resources::new(fps).unwrap();
        assert_eq!(res.time_step::<Palmer>(), 1.0 / fps);
        assert_eq!(res.time_step::<Bourg>(), 1.0f32 / fps as f32);
    }
}

#[test]
fn operations_on_the_wrong_model_or_a_gone_entity_are_errors() {
    let mut sim = Simulation::new(Resources::new(30.0).unwrap());
    let (p, b) = palmer_and_bourg(&mut sim);
    let missing_bourg_input = EcsError::missing::<FrameInput<BourgAction>>();
    assert_eq!(
        sim.push_input(p, BourgAction::ThrustUp),
        Err(missing_bourg_input)
    );
    assert_eq!(
        sim.push_input(b, PalmerAction::ThrottleUp),
        Err(EcsError::missing::<FrameInput<PalmerAction>>())
    );
    let script = Arc::new(Script::<BourgAction>::parse("1-1 thrust-up\n").unwrap());
    assert_eq!(
        sim.set_script(p, Arc::clone(&script)),
        Err(missing_bourg_input)
    );
    assert!(matches!(
        sim.reset::<Palmer>(b, PalmerControls::default(), PalmerState::at_rest()),
        Err(EcsError::MissingComponent { .. })
    ));
    assert!(matches!(
        sim.reset::<Bourg>(p, BourgControls::initial(), BourgState::initial()),
        Err(EcsError::MissingComponent { .. })
    ));
    assert!(sim.state::<Palmer>(b).is_none() && sim.state::<Bourg>(p).is_none());

    sim.despawn(b).unwrap();
    assert_eq!(sim.despawn(b), Err(EcsError::NoSuchEntity));
    assert_eq!(
        sim.push_input(b, BourgAction::ThrustUp),
        Err(EcsError::NoSuchEntity)
    );
    assert_eq!(sim.set_script(b, script), Err(EcsError::NoSuchEntity));
    assert_eq!(
        sim.reset::<Bourg>(b, BourgControls::initial(), BourgState::initial()),
        Err(EcsError::NoSuchEntity)
    );
    assert!(sim.state::<Bourg>(b).is_none() && sim.geodetic(b).is_none());
    // The survivor still flies.
    sim.run_frame();
    assert!(sim.state::<Palmer>(p).unwrap().time_s > 0.0);
}

#[test]
fn display_components_are_valid_from_spawn_on() {
    let mut sim = Simulation::new(Resources::new(30.0).unwrap());
    let (p, b) = palmer_and_bourg(&mut sim);
    let origin = sim.resources().origin;
    let view = Palmer::view(
        &PalmerAircraft::cessna_172(),
        &sim.controls::<Palmer>(p).unwrap(),
        &PalmerState::at_rest(),
    );
    assert_eq!(sim.view::<Palmer>(p), Some(view));
    // The placement is what the FlightGear bridge computes, bit for bit.
    let want = fgnet::bridge::display(&view, &origin);
    assert_eq!(sim.geodetic(p), Some(want.geodetic));
    let here = want.geodetic; // at the origin, to the round trip's nanometres
    let there = origin.geodetic();
    assert!(
        (here.lat_deg - there.lat_deg).abs() < 1e-12 && (here.alt_m - there.alt_m).abs() < 1e-6
    );
    assert_eq!(sim.attitude(p), Some(want.attitude));
    let view = Bourg::view(
        &BourgAircraft::bourg_default(),
        &BourgControls::initial(),
        &BourgState::initial(),
    );
    let want = fgnet::bridge::display(&view, &origin);
    assert_eq!(sim.geodetic(b), Some(want.geodetic));
    assert_eq!(sim.attitude(b), Some(want.attitude));
}

#[test]
fn reset_puts_an_aircraft_back_as_if_just_spawned() {
    let mut sim = Simulation::new(Resources::new(30.0).unwrap());
    let (p, b) = palmer_and_bourg(&mut sim);
    let mut fresh = Simulation::new(Resources::new(30.0).unwrap());
    let (fp, fb) = palmer_and_bourg(&mut fresh);

    sim.run_frames(90);
    sim.push_input(p, PalmerAction::BankLeft).unwrap();
    sim.push_input(b, BourgAction::RollLeft).unwrap();
    let palmer_controls = fresh.controls::<Palmer>(fp).unwrap();
    sim.reset::<Palmer>(p, palmer_controls, PalmerState::at_rest())
        .unwrap();
    sim.reset::<Bourg>(b, BourgControls::initial(), BourgState::initial())
        .unwrap();
    // Immediately: state, controls and display as at spawn.
    assert_eq!(sim.state::<Palmer>(p), fresh.state::<Palmer>(fp));
    assert_eq!(sim.attitude(p), fresh.attitude(fp));
    assert_eq!(sim.geodetic(b), fresh.geodetic(fb));
    assert_eq!(sim.attitude(b), fresh.attitude(fb));
    // The queued keys were dropped: the next frame flies like a fresh one's
    // first.
    sim.run_frame();
    fresh.run_frame();
    assert_eq!(sim.state::<Palmer>(p), fresh.state::<Palmer>(fp));
    assert_eq!(sim.controls::<Palmer>(p), fresh.controls::<Palmer>(fp));
    assert_eq!(sim.state::<Bourg>(b), fresh.state::<Bourg>(fb));
    assert_eq!(sim.attitude(b), fresh.attitude(fb));
}
