//! The ground and divergence through the ECS: EquationsOfMotion and
//! FlightStatus (`fdm_core::model::{advance, settle}`) keep every aircraft at
//! or above the ground plane, hold a crashed one at rest, and stop stepping
//! and placing a diverged one (its state and placement stay the last finite
//! ones; the run library's outputs send nothing for it:
//! `fdm-run/tests/run_flightgear.rs`).
//! Exact comparisons only: the ECS runs the same pure functions.

use std::sync::Arc;

use fdm_core::model::{fly, FlightStatus, LandingState, Model};
use fdm_core::palmer::{Palmer, PalmerControls, PalmerState};
use fdm_ecs::{Resources, Simulation};
use nalgebra::Vector3;

fn falling() -> PalmerState {
    PalmerState {
        position_m: Vector3::new(0.0, 0.0, 30.0),
        velocity_mps: Vector3::new(45.0, 0.0, 0.0),
        ..PalmerState::at_rest()
    }
}

#[test]
fn the_ecs_flies_what_fly_flies_and_holds_a_crash() {
    let mut sim = Simulation::new(Resources::new(10.0).unwrap());
    let aircraft = Arc::new(Palmer::default_aircraft());
    let controls = PalmerControls::default();
    let e = sim.spawn::<Palmer>(Arc::clone(&aircraft), controls, falling());
    let (mut state, mut status) = (falling(), FlightStatus::Airborne);
    for frame in 0..400 {
        sim.run_frame();
        (state, status) = fly::<Palmer>(&aircraft, &controls, status, &state, 0.1);
        assert_eq!(sim.state::<Palmer>(e), Some(state), "frame {frame}");
        assert_eq!(sim.status(e), Some(status), "frame {frame}");
        assert!(state.position_m.z >= 0.0);
    }
    assert_eq!(status, FlightStatus::Landed(LandingState::Crash));
    assert_eq!(state.velocity_mps, Vector3::zeros());
    assert_eq!(sim.diverged_count(), 0);
}

#[test]
fn a_diverged_aircraft_is_counted_and_placed_no_more() {
    let mut sim = Simulation::new(Resources::new(10.0).unwrap());
    let aircraft = Arc::new(Palmer::default_aircraft());
    let controls = PalmerControls::default();
    let fine = sim.spawn::<Palmer>(Arc::clone(&aircraft), controls, falling());
    // Huge but finite (and so is its view): its first step overflows.
    let huge = PalmerState {
        velocity_mps: Vector3::new(1e150, 0.0, 0.0),
        ..falling()
    };
    let bad = sim.spawn::<Palmer>(Arc::clone(&aircraft), controls, huge);
    let placed_before = (sim.geodetic(bad).unwrap(), sim.attitude(bad).unwrap());
    for _ in 0..5 {
        sim.run_frame();
    }
    assert_eq!(sim.status(bad), Some(FlightStatus::Diverged));
    assert_eq!(sim.state::<Palmer>(bad), Some(huge));
    assert_eq!(
        (sim.geodetic(bad).unwrap(), sim.attitude(bad).unwrap()),
        placed_before
    );
    assert!(fdm_core::model::FlightView::is_finite(&Palmer::view(
        &aircraft, &controls, &huge
    )));
    assert_eq!(sim.diverged_count(), 1);
    assert_eq!(sim.status(fine), Some(FlightStatus::Airborne));
    assert!(Palmer::is_finite(&sim.state::<Palmer>(fine).unwrap()));
}

#[test]
fn a_state_too_far_out_to_be_placed_is_diverged() {
    let mut sim = Simulation::new(Resources::new(10.0).unwrap());
    let aircraft = Arc::new(Palmer::default_aircraft());
    let controls = PalmerControls::default();
    // Finite, and its step is finite, but no geodetic position exists for it.
    let far = PalmerState {
        position_m: Vector3::new(1.7e308, 0.0, 1.7e308),
        ..falling()
    };
    let e = sim.spawn::<Palmer>(Arc::clone(&aircraft), controls, far);
    let placed_before = (sim.geodetic(e).unwrap(), sim.attitude(e).unwrap());
    sim.run_frame();
    assert!(Palmer::is_finite(&sim.state::<Palmer>(e).unwrap()));
    assert_eq!(sim.status(e), Some(FlightStatus::Diverged));
    // Bitwise: the placement at spawn is NaN already (no geodetic position
    // exists for it), and it was not rewritten.
    let (g, a) = (sim.geodetic(e).unwrap(), sim.attitude(e).unwrap());
    assert_eq!(g.lat_deg.to_bits(), placed_before.0.lat_deg.to_bits());
    assert_eq!(
        a.heading_deg.to_bits(),
        placed_before.1.heading_deg.to_bits()
    );
}
