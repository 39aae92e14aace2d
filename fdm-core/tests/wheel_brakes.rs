//! The wheel brakes, our extension of Palmer's model (docs/palmer-model.md
//! "Wheel brakes"): without them an idle landing rolls on for ever (the
//! original has no wheel friction); with them it stops within a realistic
//! distance and stays stopped; off, or in the air, they change no bit.
//!
//! Tolerances: the distances are measured values checked against bands (the
//! documented numbers, rounded outward by about 1 m); every other comparison
//! is exact (bits or `==`), because the brakes either act or leave the step's
//! operations untouched.

use fdm_core::model::{fly, FlightStatus, LandingState, Model};
use fdm_core::palmer::{
    derivatives, step, Flaps, Palmer, PalmerAction, PalmerControls, PalmerState,
    BRAKING_FRICTION_COEFFICIENT, GRAVITY_MPS2,
};
use fdm_core::script::Script;
use nalgebra::Vector3;

const DT_S: f64 = 0.1;

/// The braked roll-out measured below (346.87 m, 15.3 s from a 37.47 m/s
/// touchdown; docs/palmer-model.md quotes them), rounded outward.
const DISTANCE_LOW_M: f64 = 346.0;
const DISTANCE_HIGH_M: f64 = 348.0;
const TIME_LOW_S: f64 = 15.2;
const TIME_HIGH_S: f64 = 15.4;

/// The approach of `ground_contact.rs`: 30 m up at 45 m/s, 30 % power, 4°
/// angle of attack, until the touchdown; then idle (and the brakes, if
/// `brakes`) for `rollout_s` seconds. Returns the touchdown state, the final
/// state and the first state whose ground speed is below 0.01 m/s, if any.
fn land_and_roll(brakes: bool, rollout_s: f64) -> (PalmerState, PalmerState, Option<PalmerState>) {
    let aircraft = Palmer::default_aircraft();
    let mut controls = PalmerControls {
        throttle: 0.3,
        alpha_deg: 4.0,
        bank_deg: 0.0,
        flaps: Flaps::Up,
        brakes: false,
    };
    let mut state = PalmerState {
        position_m: Vector3::new(0.0, 0.0, 30.0),
        velocity_mps: Vector3::new(45.0, 0.0, 0.0),
        ..PalmerState::at_rest()
    };
    let mut status = FlightStatus::initial(30.0);
    while !matches!(status, FlightStatus::Landed(_)) {
        (state, status) = fly::<Palmer>(&aircraft, &controls, status, &state, DT_S);
        assert!(state.time_s < 120.0, "no touchdown: {state:?}");
    }
    assert_eq!(status, FlightStatus::Landed(LandingState::Safe));
    let touchdown = state;
    controls.throttle = 0.0;
    controls.brakes = brakes;
    let mut stopped = None;
    while state.time_s < touchdown.time_s + rollout_s {
        (state, status) = fly::<Palmer>(&aircraft, &controls, status, &state, DT_S);
        assert_eq!(state.position_m.z, 0.0, "{state:?}");
        if stopped.is_none() && state.velocity_mps.xy().norm() < 0.01 {
            stopped = Some(state);
        }
    }
    (touchdown, state, stopped)
}

#[test]
fn without_brakes_an_idle_landing_rolls_on_for_ever() {
    // The original model's behaviour, kept: 15 minutes after the touchdown
    // the aircraft still rolls at more than 1 m/s (about 2.4 kt), kilometres on.
    let (touchdown, end, stopped) = land_and_roll(false, 900.0);
    let speed_mps = end.velocity_mps.xy().norm();
    let distance_m = end.position_m.x - touchdown.position_m.x;
    println!(
        "free roll: touchdown {touchdown:?}\n 15 min later {speed_mps} m/s, {distance_m} m on"
    );
    assert!(stopped.is_none());
    assert!(speed_mps > 1.0, "{speed_mps}");
    assert!(distance_m > 4000.0, "{distance_m}");
}

#[test]
fn a_braked_landing_stops_within_a_realistic_distance_and_stays() {
    let (touchdown, end, stopped) = land_and_roll(true, 120.0);
    let stopped = stopped.expect("the brakes stop the aircraft");
    let distance_m = stopped.position_m.x - touchdown.position_m.x;
    let time_s = stopped.time_s - touchdown.time_s;
    println!(
        "braked roll: touchdown at {} m/s, stopped {distance_m} m and {time_s} s later",
        touchdown.velocity_mps.x
    );
    // Never backwards, no sideways drift, and at rest it stays.
    assert!(end.position_m.x >= stopped.position_m.x);
    assert_eq!(end.position_m.y, 0.0);
    assert!(end.position_m.x - stopped.position_m.x < 0.01, "{end:?}");
    assert!(
        end.velocity_mps.x >= 0.0 && end.velocity_mps.x < 0.01,
        "{end:?}"
    );
    assert!(
        (DISTANCE_LOW_M..=DISTANCE_HIGH_M).contains(&distance_m),
        "{distance_m}"
    );
    assert!((TIME_LOW_S..=TIME_HIGH_S).contains(&time_s), "{time_s}");
}

#[test]
fn at_rest_the_brakes_hold_the_aircraft_against_full_power_and_release() {
    let aircraft = Palmer::default_aircraft();
    let braked = PalmerControls {
        throttle: 1.0,
        brakes: true,
        ..PalmerControls::default()
    };
    // Full power pushes with about 2.6 m/s², the brakes hold up to
    // 0.4 * 9.81 = 3.9 m/s²: nothing moves, exactly.
    const { assert!(BRAKING_FRICTION_COEFFICIENT * -GRAVITY_MPS2 > 3.9) };
    let d = derivatives(&aircraft, &braked, &PalmerState::at_rest());
    assert_eq!(d.acceleration_mps2, Vector3::zeros());
    let mut state = PalmerState::at_rest();
    for _ in 0..100 {
        state = step(&aircraft, &braked, &state, DT_S);
    }
    assert_eq!(state.position_m, Vector3::zeros());
    assert_eq!(state.velocity_mps, Vector3::zeros());
    // Released: the take-off roll starts.
    let released = braked.apply(PalmerAction::BrakesOff);
    assert!(!released.brakes);
    state = step(&aircraft, &released, &state, DT_S);
    assert!(state.velocity_mps.x > 0.25, "{state:?}");
}

#[test]
fn in_the_air_the_brakes_change_no_bit() {
    let aircraft = Palmer::default_aircraft();
    let free = PalmerControls {
        throttle: 0.6,
        alpha_deg: 3.0,
        bank_deg: -4.0,
        flaps: Flaps::Deg20,
        brakes: false,
    };
    let braked = free.apply(PalmerAction::BrakesOn);
    assert!(braked.brakes);
    // Through ground effect down to 0.5 m above the ground, never on it.
    for z_m in [500.0, 4.0, 0.5] {
        let start = PalmerState {
            position_m: Vector3::new(10.0, 20.0, z_m),
            velocity_mps: Vector3::new(40.0, -5.0, 1.0),
            ..PalmerState::at_rest()
        };
        let (mut a, mut b) = (start, start);
        for _ in 0..5 {
            a = step(&aircraft, &free, &a, DT_S);
            b = step(&aircraft, &braked, &b, DT_S);
            assert!(a.position_m.z > 0.0);
        }
        assert_eq!(
            a.position_m.map(f64::to_bits),
            b.position_m.map(f64::to_bits)
        );
        assert_eq!(
            a.velocity_mps.map(f64::to_bits),
            b.velocity_mps.map(f64::to_bits)
        );
    }
}

#[test]
fn brakes_are_a_script_action_and_absent_from_the_json_while_off() {
    let script = Script::<PalmerAction>::parse("3-3 brakes-on\n7-7 brakes-off\n").unwrap();
    let mut c = PalmerControls::default();
    let mut history = Vec::new();
    for frame in 1..=8_u64 {
        for action in script.actions_at(frame) {
            c = c.apply(action);
        }
        history.push(c.brakes);
    }
    assert_eq!(
        history,
        [false, false, true, true, true, true, false, false]
    );
    let off = PalmerControls::default();
    let json = serde_json::to_string(&off).unwrap();
    assert_eq!(
        json,
        r#"{"throttle":0.0,"alpha_deg":0.0,"bank_deg":0.0,"flaps":0}"#
    );
    assert_eq!(serde_json::from_str::<PalmerControls>(&json).unwrap(), off);
    let on = off.apply(PalmerAction::BrakesOn);
    let json = serde_json::to_string(&on).unwrap();
    assert_eq!(
        json,
        r#"{"throttle":0.0,"alpha_deg":0.0,"bank_deg":0.0,"flaps":0,"brakes":true}"#
    );
    assert_eq!(serde_json::from_str::<PalmerControls>(&json).unwrap(), on);
}

#[test]
fn a_braked_roll_is_the_same_in_every_direction() {
    // With the wings level, every force of steps 10 to 12 turns with the
    // horizontal velocity (thrust and drag along it, the friction against
    // it, through `cosT` and `sinT`), so a braked roll along any heading is
    // the roll along x turned: the same speed at every step, the same
    // distance, no sideways drift, and it stops as that one does (never
    // backwards). Some thrust is kept (30 %: less than the brakes hold) so
    // that the horizontal force the friction is limited by near the stop is
    // large. Tolerance 1e-9 m/s and 1e-9 m: turning the velocity rounds its
    // components (about 1e-15 relative, 20 m/s over 150 steps), far below
    // that; the friction limit seeing another force along the travel is
    // off by its size over a stage (0.1 s / 1114 kg per newton, over 1e-6).
    let aircraft = Palmer::default_aircraft();
    let controls = PalmerControls {
        throttle: 0.3,
        brakes: true,
        ..PalmerControls::default()
    };
    let roll = |heading_deg: f64| {
        let (sin, cos) = heading_deg.to_radians().sin_cos();
        let mut state = PalmerState {
            velocity_mps: Vector3::new(20.0 * cos, 20.0 * sin, 0.0),
            ..PalmerState::at_rest()
        };
        (0..150)
            .map(|_| {
                state = step(&aircraft, &controls, &state, DT_S);
                assert_eq!(state.position_m.z, 0.0, "{heading_deg}: {state:?}");
                let along = state.velocity_mps.x * cos + state.velocity_mps.y * sin;
                let across = state.velocity_mps.y * cos - state.velocity_mps.x * sin;
                let distance = state.position_m.x * cos + state.position_m.y * sin;
                (along, across, distance)
            })
            .collect::<Vec<_>>()
    };
    let straight = roll(0.0);
    // The roll along x stops (below 0.01 m/s) within the 15 s.
    assert!(
        straight.last().unwrap().0.abs() < 0.01,
        "{:?}",
        straight.last()
    );
    assert!(straight.iter().all(|&(along, _, _)| along >= 0.0));
    for heading_deg in [30.0, 90.0, 135.0, 200.0, 300.0] {
        for (n, (turned, along_x)) in roll(heading_deg).iter().zip(&straight).enumerate() {
            let (speed, across, distance) = *turned;
            assert!(
                (speed - along_x.0).abs() < 1e-9
                    && across.abs() < 1e-9
                    && (distance - along_x.2).abs() < 1e-9,
                "heading {heading_deg}°, step {}: {turned:?} against {along_x:?} along x",
                n + 1
            );
        }
    }
}
