//! The shared definitions of `fdm_core::model` (the flight view's checks, the
//! flight status and its names, `advance`), tested here against their
//! documentation: the other crates use them, and fdm-core's own tests must
//! catch a change to them (cargo-mutants found that only fdm-ecs and sim-cli
//! did, docs/testing.md).

use fdm_core::model::{advance, FlightStatus, FlightView, LandingState, Model};
use fdm_core::palmer::{Palmer, PalmerControls, PalmerState};
use nalgebra::Vector3;

/// A view whose every number is finite and distinct.
fn view() -> FlightView {
    let aircraft = Palmer::default_aircraft();
    let controls = PalmerControls {
        throttle: 1.0,
        alpha_deg: 4.0,
        ..PalmerControls::default()
    };
    let state = PalmerState {
        time_s: 12.5,
        position_m: Vector3::new(100.0, -20.0, 300.0),
        velocity_mps: Vector3::new(50.0, 3.0, 4.0),
    };
    Palmer::view(&aircraft, &controls, &state)
}

#[test]
fn height_and_climb_rate_are_the_z_components() {
    let v = view();
    assert_eq!(v.height_m(), 300.0);
    assert_eq!(v.climb_rate_mps(), 4.0);
    let mut sinking = v;
    sinking.velocity_mps.z = -7.25;
    assert_eq!(sinking.climb_rate_mps(), -7.25);
}

#[test]
fn a_view_is_finite_only_if_every_number_is() {
    let good = view();
    assert!(good.is_finite());
    // Each number made non-finite alone (NaN, then +∞) makes the view non-finite.
    type Setter = fn(&mut FlightView, f64);
    let fields: [(&str, Setter); 19] = [
        ("time_s", |v, x| v.time_s = x),
        ("position_m.x", |v, x| v.position_m.x = x),
        ("position_m.y", |v, x| v.position_m.y = x),
        ("position_m.z", |v, x| v.position_m.z = x),
        ("velocity_mps.x", |v, x| v.velocity_mps.x = x),
        ("velocity_mps.y", |v, x| v.velocity_mps.y = x),
        ("velocity_mps.z", |v, x| v.velocity_mps.z = x),
        ("velocity_body_mps.x", |v, x| v.velocity_body_mps.x = x),
        ("velocity_body_mps.y", |v, x| v.velocity_body_mps.y = x),
        ("velocity_body_mps.z", |v, x| v.velocity_body_mps.z = x),
        ("roll_deg", |v, x| v.attitude.roll_deg = x),
        ("pitch_deg", |v, x| v.attitude.pitch_deg = x),
        ("heading_deg", |v, x| v.attitude.heading_deg = x),
        ("airspeed_mps", |v, x| v.airspeed_mps = x),
        ("alpha_deg", |v, x| v.alpha_deg = x),
        ("beta_deg", |v, x| v.beta_deg = x),
        ("flaps_norm", |v, x| v.flaps_norm = x),
        ("engine_rpm", |v, x| v.engine_rpm = x),
        ("engine_rpm (again, -inf)", |v, _| {
            v.engine_rpm = f64::NEG_INFINITY
        }),
    ];
    for (name, set) in fields {
        for bad in [f64::NAN, f64::INFINITY] {
            let mut v = good;
            set(&mut v, bad);
            assert!(!v.is_finite(), "{name} = {bad} left the view finite");
        }
    }
    // The booleans do not matter.
    let mut v = good;
    v.engine_running = !v.engine_running;
    v.stalling = !v.stalling;
    assert!(v.is_finite());
}

#[test]
fn the_initial_status_is_on_the_ground_at_or_below_the_plane() {
    assert_eq!(FlightStatus::initial(0.0), FlightStatus::OnGround);
    assert_eq!(FlightStatus::initial(-3.0), FlightStatus::OnGround);
    assert_eq!(FlightStatus::initial(1e-9), FlightStatus::Airborne);
    assert_eq!(FlightStatus::initial(2000.0), FlightStatus::Airborne);
    // Not above the plane: a NaN height starts on the ground.
    assert_eq!(FlightStatus::initial(f64::NAN), FlightStatus::OnGround);
}

/// Every status with its documented finality, HUD label and machine code
/// (docs/cli.md: the JSON report's and the CSV's `status`).
const STATUSES: [(FlightStatus, bool, &str, &str); 6] = [
    (FlightStatus::OnGround, false, "on ground", "on_ground"),
    (FlightStatus::Airborne, false, "flying", "airborne"),
    (
        FlightStatus::Landed(LandingState::Safe),
        false,
        "landed (safe)",
        "landed_safe",
    ),
    (
        FlightStatus::Landed(LandingState::Rough),
        false,
        "landed (rough)",
        "landed_rough",
    ),
    (
        FlightStatus::Landed(LandingState::Crash),
        true,
        "CRASHED",
        "crashed",
    ),
    (FlightStatus::Diverged, true, "DIVERGED", "diverged"),
];

#[test]
fn finality_labels_and_codes_are_the_documented_ones() {
    for (status, is_final, label, code) in STATUSES {
        assert_eq!(status.is_final(), is_final, "{status:?}");
        assert_eq!(status.label(), label, "{status:?}");
        assert_eq!(status.code(), code, "{status:?}");
        // A final status never changes; the others leave the ground above it.
        let after = status.update(50.0, 3.0);
        if is_final {
            assert_eq!(after, status);
        } else {
            assert_eq!(after, FlightStatus::Airborne, "{status:?}");
        }
    }
}

#[test]
fn advance_keeps_a_diverged_aircraft_where_it_was_and_steps_the_others() {
    let aircraft = Palmer::default_aircraft();
    let controls = PalmerControls {
        throttle: 1.0,
        alpha_deg: 4.0,
        ..PalmerControls::default()
    };
    let state = PalmerState {
        position_m: Vector3::new(0.0, 0.0, 500.0),
        velocity_mps: Vector3::new(50.0, 0.0, 0.0),
        ..PalmerState::at_rest()
    };
    let dt = Palmer::time_step(30.0);
    // Diverged: not stepped, the state kept bit for bit.
    let (kept, status) =
        advance::<Palmer>(&aircraft, &controls, FlightStatus::Diverged, &state, dt);
    assert_eq!(status, FlightStatus::Diverged);
    assert_eq!(kept, state);
    // Airborne: exactly the model's step.
    let (stepped, status) =
        advance::<Palmer>(&aircraft, &controls, FlightStatus::Airborne, &state, dt);
    assert_eq!(status, FlightStatus::Airborne);
    assert_eq!(stepped, Palmer::step(&aircraft, &controls, &state, dt));
    assert_ne!(stepped, state);
    // A step that is not finite is not kept: the status becomes Diverged.
    let broken = PalmerControls {
        throttle: f64::NAN,
        ..controls
    };
    let (kept, status) = advance::<Palmer>(&aircraft, &broken, FlightStatus::Airborne, &state, dt);
    assert_eq!(status, FlightStatus::Diverged);
    assert_eq!(kept, state);
}
