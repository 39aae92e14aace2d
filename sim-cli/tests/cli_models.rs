//! The model modules' record and placement functions through the public
//! `RunModel` (record) and `FleetModel` (placement) traits (found by mutation
//! testing, docs/testing.md): a recorded
//! aircraft comes back as it was, bad thrust limits are refused naming the
//! field, and `offset_state` moves a state by the given metres, converted to
//! the model's own unit (Bourg: feet, 1 ft = 0.3048 m exactly).

use fdm_core::bourg::{Bourg, BourgAircraft, BourgState};
use fdm_core::model::Model;
use fdm_core::palmer::{Palmer, PalmerAircraft, PalmerState};
use fdm_run::FleetModel;
use fdm_run::RunModel;

fn bourg_aircraft() -> BourgAircraft {
    let mut aircraft = Bourg::default_aircraft();
    aircraft.max_thrust_lb = 4321.5;
    aircraft.delta_thrust_lb = 12.25;
    aircraft
}

#[test]
fn a_recorded_bourg_aircraft_comes_back_as_it_was() {
    let aircraft = bourg_aircraft();
    assert_ne!(aircraft, Bourg::default_aircraft());
    let back = Bourg::aircraft_from_record(Bourg::aircraft_record(&aircraft)).unwrap();
    assert_eq!(back, aircraft);
}

#[test]
fn a_recorded_palmer_aircraft_comes_back_as_it_was() {
    let default = Palmer::default_aircraft();
    let palmer = PalmerAircraft {
        wing_area_m2: default.wing_area_m2 * 1.25,
        cdp: default.cdp * 1.5,
        ..default
    };
    assert_ne!(palmer, PalmerAircraft::default());
    assert_eq!(Palmer::aircraft_record(&palmer), palmer);
    let back = Palmer::aircraft_from_record(Palmer::aircraft_record(&palmer)).unwrap();
    assert_eq!(back, palmer);
}

#[test]
fn thrust_limits_must_be_finite_and_not_negative() {
    for (field, value) in [
        ("max_thrust_lb", -1.0f32),
        ("max_thrust_lb", f32::INFINITY),
        ("max_thrust_lb", f32::NAN),
        ("delta_thrust_lb", -0.5),
        ("delta_thrust_lb", f32::INFINITY),
    ] {
        let mut record = Bourg::aircraft_record(&bourg_aircraft());
        if field == "max_thrust_lb" {
            record.max_thrust_lb = value;
        } else {
            record.delta_thrust_lb = value;
        }
        let err = Bourg::aircraft_from_record(record).unwrap_err();
        assert!(err.contains(field), "{field} {value}: {err}");
    }
    // Zero is a valid limit.
    let mut record = Bourg::aircraft_record(&bourg_aircraft());
    record.max_thrust_lb = 0.0;
    record.delta_thrust_lb = 0.0;
    assert!(Bourg::aircraft_from_record(record).is_ok());
}

#[test]
fn offset_state_moves_by_metres_in_the_models_unit() {
    let mut state: BourgState = Bourg::initial_state();
    state.position_ft.x = 100.0;
    state.position_ft.y = -20.0;
    state.position_ft.z = 500.0;
    let moved = Bourg::offset_state(&state, 30.48, -60.96, 91.44);
    // 30.48 m = 100 ft, -60.96 m = -200 ft, 91.44 m = 300 ft.
    assert!((moved.position_ft.x - 200.0).abs() < 1e-3, "{moved:?}");
    assert!((moved.position_ft.y + 220.0).abs() < 1e-3, "{moved:?}");
    assert!((moved.position_ft.z - 800.0).abs() < 1e-3, "{moved:?}");
    assert_eq!(moved.velocity_ftps, state.velocity_ftps);
    assert_eq!(moved.orientation, state.orientation);
}

#[test]
fn palmer_offset_state_moves_by_metres() {
    let mut state: PalmerState = Palmer::initial_state();
    state.position_m.x = 100.0;
    state.position_m.y = -20.0;
    state.position_m.z = 500.0;
    let moved = Palmer::offset_state(&state, 30.0, -60.0, 90.0);
    assert_eq!(
        [moved.position_m.x, moved.position_m.y, moved.position_m.z],
        [130.0, -80.0, 590.0]
    );
    assert_eq!(moved.velocity_mps, state.velocity_mps);
    assert_eq!(moved.time_s, state.time_s);
}
