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

/// Bourg's `Model::view`, from its documentation: feet become metres
/// (`METRES_PER_FOOT` after widening to `f64`); the body velocity (x forward,
/// y left, z up) becomes forward, right, down; alpha is `atan2(w, u)` and
/// sideslip `asin(v / |v|)` of it (0 at rest); flaps 1 with the landing flaps
/// down; the engine runs while thrust is above 0; rpm 0. Exact: the same
/// widening and operations as documented (the maths are fdm-core's own
/// `atan2`/`asin`, which the page names as the model's).
#[test]
fn bourgs_view_converts_and_derives_as_documented() {
    use fdm_core::bourg::{Bourg, BourgControls, BourgState};
    use fdm_core::math::{asin, atan2};
    use fdm_core::units::METRES_PER_FOOT;

    let aircraft = Bourg::default_aircraft();
    let mut controls = BourgControls::initial();
    controls.landing_flaps = true;
    controls.thrust_lb = 0.0;
    let mut state = BourgState::initial();
    state.time_s = 3.25;
    state.position_ft = Vector3::new(-4000.0, 12.5, 1500.0);
    state.velocity_ftps = Vector3::new(80.0, -6.0, -3.5);
    // Forward 80, left 6 (so right -6), up 3.5 (so down -3.5).
    state.velocity_body_ftps = Vector3::new(80.0, 6.0, 3.5);
    let v = Bourg::view(&aircraft, &controls, &state);

    let ft = |x: f32| f64::from(x) * METRES_PER_FOOT;
    assert_eq!(v.time_s, 3.25);
    assert_eq!(
        v.position_m,
        Vector3::new(ft(-4000.0), ft(12.5), ft(1500.0))
    );
    assert_eq!(v.velocity_mps, Vector3::new(ft(80.0), ft(-6.0), ft(-3.5)));
    assert_eq!(
        v.velocity_body_mps,
        Vector3::new(ft(80.0), ft(-6.0), ft(-3.5)),
        "forward, right, down"
    );
    let speed_ftps = (80.0f32 * 80.0 + 6.0 * 6.0 + 3.5 * 3.5).sqrt();
    assert_eq!(v.airspeed_mps, ft(state.speed_ftps()));
    assert!((v.airspeed_mps - ft(speed_ftps)).abs() < 1e-5);
    assert_eq!(v.alpha_deg, atan2(-3.5f64, 80.0).to_degrees());
    let body_speed = (80.0f64 * 80.0 + 36.0 + 3.5 * 3.5).sqrt();
    assert_eq!(v.beta_deg, asin(-6.0 / body_speed).to_degrees());
    assert!(v.beta_deg < -4.0 && v.beta_deg > -4.5, "{}", v.beta_deg);
    assert_eq!(
        (v.flaps_norm, v.engine_running, v.engine_rpm),
        (1.0, false, 0.0)
    );
    assert_eq!(Bourg::height_m(&state), ft(1500.0));
    assert_eq!(Bourg::climb_rate_mps(&state), ft(-3.5));

    // At rest in the body frame: no sideslip (not NaN); thrust runs the engine.
    controls.thrust_lb = 0.5;
    controls.landing_flaps = false;
    state.velocity_body_ftps = Vector3::zeros();
    let v = Bourg::view(&aircraft, &controls, &state);
    assert_eq!(v.beta_deg.to_bits(), 0.0f64.to_bits());
    assert_eq!((v.flaps_norm, v.engine_running), (0.0, true));
}

/// Bourg's `Model::fleet_member(i)`, as documented: thrust 500..2500 lb in
/// 21 steps (`500 + (i mod 21)·100`), landing flaps down on every third,
/// flying north at `60 + (i mod 7)·3` ft/s (the body velocity the same) at
/// `2000 + (i mod 10)·100` ft, `(i mod 1000)·20` ft sideways; the rest as
/// the initial controls and state. And the trait's `try_step` is the model's
/// (same bits on success, the same refusal).
#[test]
fn bourgs_fleet_members_and_checked_step_are_as_documented() {
    use fdm_core::bourg::{Bourg, BourgControls, BourgState};

    for i in [
        0usize, 1, 2, 3, 7, 20, 21, 22, 999, 1000, 1234, 20_999, 1_000_003,
    ] {
        let (controls, state) = Bourg::fleet_member(i);
        let want_thrust = 500.0 + (i % 21) as f32 * 100.0;
        assert_eq!(controls.thrust_lb, want_thrust, "member {i}");
        assert_eq!(controls.landing_flaps, i % 3 == 0, "member {i}");
        let rest = BourgControls {
            thrust_lb: controls.thrust_lb,
            landing_flaps: controls.landing_flaps,
            ..BourgControls::initial()
        };
        assert_eq!(controls, rest, "member {i}");
        let speed = 60.0 + (i % 7) as f32 * 3.0;
        assert_eq!(
            state.position_ft,
            Vector3::new(
                -5000.0,
                (i % 1000) as f32 * 20.0,
                2000.0 + (i % 10) as f32 * 100.0
            ),
            "member {i}"
        );
        assert_eq!(
            state.velocity_ftps,
            Vector3::new(speed, 0.0, 0.0),
            "member {i}"
        );
        assert_eq!(state.velocity_body_ftps, state.velocity_ftps, "member {i}");
        let initial = BourgState::initial();
        assert_eq!(
            (
                state.orientation,
                state.angular_velocity_radps,
                state.time_s
            ),
            (
                initial.orientation,
                initial.angular_velocity_radps,
                initial.time_s
            ),
            "member {i}"
        );
    }

    let aircraft = Bourg::default_aircraft();
    let (controls, mut state) = Bourg::fleet_member(5);
    let dt = Bourg::time_step(30.0);
    for _ in 0..60 {
        let checked = <Bourg as Model>::try_step(&aircraft, &controls, &state, dt).unwrap();
        let plain = <Bourg as Model>::step(&aircraft, &controls, &state, dt);
        assert_eq!(format!("{checked:?}"), format!("{plain:?}"));
        assert_ne!(checked, state);
        state = checked;
    }
    let mut broken = state;
    broken.velocity_ftps.x = f32::NAN;
    assert!(<Bourg as Model>::try_step(&aircraft, &controls, &broken, dt).is_err());
}

/// Bourg's `Model::at_rest`, as `Model::at_rest` documents it: a crashed
/// aircraft one frame later is where it was (position and attitude, the
/// stall flag too), at rest (every velocity zero: earth and body frames and
/// the rotation, so it does not keep spinning), its clock advanced by `dt`
/// (`time_s + f64::from(dt)`). `advance` applies it to a crashed aircraft
/// whatever the controls. From a state that still moves and spins in every
/// axis, so that each velocity is seen to be zeroed on its own. Exact: zeros
/// and copies, and the clock's one documented addition.
#[test]
fn a_crashed_bourg_aircraft_rests_where_it_was_with_its_clock_advanced() {
    use fdm_core::bourg::ops::quat_from_euler_deg;
    use fdm_core::bourg::{Bourg, BourgControls, BourgState};

    let mut state = BourgState::initial();
    state.time_s = 41.5;
    state.position_ft = Vector3::new(-1234.5, 67.25, 0.0);
    state.velocity_ftps = Vector3::new(55.0, -4.5, 2.25);
    state.velocity_body_ftps = Vector3::new(54.0, 6.5, -3.75);
    state.angular_velocity_radps = Vector3::new(0.5, -0.25, 0.125);
    state.orientation = quat_from_euler_deg(&Vector3::new(12.0, -7.0, 135.0));
    state.stalling = true;
    let dt = Bourg::time_step(30.0);

    let rest = Bourg::at_rest(&state, dt);
    assert_eq!(rest.time_s, 41.5 + f64::from(dt));
    assert_eq!(rest.velocity_ftps, Vector3::zeros(), "earth-frame velocity");
    assert_eq!(rest.velocity_body_ftps, Vector3::zeros(), "body velocity");
    assert_eq!(
        rest.angular_velocity_radps,
        Vector3::zeros(),
        "rotation: a crashed aircraft does not keep spinning"
    );
    assert_eq!(rest.position_ft, state.position_ft);
    assert_eq!(rest.orientation, state.orientation);
    assert!(rest.stalling);

    let aircraft = Bourg::default_aircraft();
    let crash = FlightStatus::Landed(LandingState::Crash);
    let full = BourgControls {
        thrust_lb: 3000.0,
        ..BourgControls::initial()
    };
    let (next, status) = advance::<Bourg>(&aircraft, &full, crash, &state, dt);
    assert_eq!(status, crash);
    assert_eq!(next, rest);
    // And it stays there, frame after frame, only its clock moving.
    let (later, _) = advance::<Bourg>(&aircraft, &full, crash, &next, dt);
    assert_eq!(later.time_s, next.time_s + f64::from(dt));
    assert_eq!(
        (later.position_ft, later.orientation, later.velocity_ftps),
        (rest.position_ft, rest.orientation, Vector3::zeros())
    );
}

/// Palmer's `Model::view`, from its documentation (`fdm_core::palmer`): a
/// point mass has no attitude state, so the attitude is
/// `geodesy::palmer_attitude` of the velocity, alpha and bank; the body
/// velocity is `u = V cos α`, `w = V sin α`, no sideslip; flaps
/// `degrees / 40`; the engine runs at the model's propeller speed
/// (`engine_rps · 60` rev/min) while the throttle is above 0, and not at 0;
/// no stall. Exact: the documented operations on the same numbers, with
/// fdm-core's own `sqrt`, `cos` and `sin` (the model's maths).
#[test]
fn palmers_view_derives_as_documented() {
    use fdm_core::geodesy::palmer_attitude;
    use fdm_core::math::{cos, sin, sqrt};
    use fdm_core::palmer::Flaps;

    let aircraft = Palmer::default_aircraft();
    let controls = PalmerControls {
        throttle: 0.35,
        alpha_deg: 6.0,
        bank_deg: -12.0,
        flaps: Flaps::Deg20,
        brakes: false,
    };
    let state = PalmerState {
        time_s: 7.25,
        position_m: Vector3::new(120.0, -35.5, 640.0),
        velocity_mps: Vector3::new(48.0, -5.0, 2.5),
    };
    let v = Palmer::view(&aircraft, &controls, &state);
    let speed = sqrt(48.0 * 48.0 + 5.0 * 5.0 + 2.5 * 2.5);
    assert_eq!(v.airspeed_mps, speed);
    assert_eq!(
        (v.time_s, v.position_m, v.velocity_mps),
        (7.25, state.position_m, state.velocity_mps)
    );
    let alpha = 6.0f64.to_radians();
    assert_eq!(
        v.velocity_body_mps,
        Vector3::new(speed * cos(alpha), 0.0, speed * sin(alpha))
    );
    assert_eq!(v.attitude, palmer_attitude(state.velocity_mps, 6.0, -12.0));
    assert_eq!((v.alpha_deg, v.beta_deg), (6.0, 0.0));
    assert_eq!(v.flaps_norm, 0.5);
    assert_eq!(v.engine_rpm, aircraft.engine_rps * 60.0);
    assert!(
        v.engine_running && v.engine_rpm > 1000.0,
        "{}",
        v.engine_rpm
    );
    assert!(!v.stalling);
    assert!(v.is_finite());

    // Idle (throttle exactly 0): the engine does not run; full flaps are 1.
    let idle = PalmerControls {
        throttle: 0.0,
        flaps: Flaps::Deg40,
        ..controls
    };
    let v = Palmer::view(&aircraft, &idle, &state);
    assert_eq!(
        (v.engine_running, v.engine_rpm, v.flaps_norm),
        (false, 0.0, 1.0)
    );
    // Any throttle above 0 runs it; flaps up are 0.
    let least = PalmerControls {
        throttle: f64::from_bits(1),
        flaps: Flaps::Up,
        ..controls
    };
    let v = Palmer::view(&aircraft, &least, &state);
    assert_eq!(
        (v.engine_running, v.engine_rpm, v.flaps_norm),
        (true, aircraft.engine_rps * 60.0, 0.0)
    );
    assert_eq!(Palmer::height_m(&state), 640.0);
    assert_eq!(Palmer::climb_rate_mps(&state), 2.5);
}

/// Palmer's `Model::fleet_member(i)`, as documented: throttle 50..100 % in
/// 11 steps (5 % each), alpha 2..6° and bank −10..10° in whole degrees, flaps
/// up or 20°, 45..54 m/s north, 500 m up, spaced 10 m apart along x (the
/// first at the origin), no brakes, time 0; and no two neighbours share all
/// their controls. Over the first 2310 members (every combination of the
/// steps' periods) each step of each control is taken. Exact: sums and
/// products of small whole numbers and of 0.05-multiples as `f64` computes
/// them (`0.5 + k / 20`).
#[test]
fn palmers_fleet_members_are_as_documented() {
    use fdm_core::palmer::Flaps;
    use std::collections::BTreeSet;

    let (mut throttles, mut alphas, mut banks, mut speeds) = (
        BTreeSet::new(),
        BTreeSet::new(),
        BTreeSet::new(),
        BTreeSet::new(),
    );
    let mut flaps = BTreeSet::new();
    let mut previous: Option<PalmerControls> = None;
    for i in 0..2310usize {
        let (controls, state) = Palmer::fleet_member(i);
        let k = (0..=10)
            .find(|&k| controls.throttle == 0.5 + f64::from(k) / 20.0)
            .unwrap_or_else(|| panic!("member {i}: throttle {}", controls.throttle));
        throttles.insert(k);
        assert!(
            controls.alpha_deg == controls.alpha_deg.round()
                && (2.0..=6.0).contains(&controls.alpha_deg),
            "member {i}: alpha {}",
            controls.alpha_deg
        );
        alphas.insert(controls.alpha_deg as i64);
        assert!(
            controls.bank_deg == controls.bank_deg.round()
                && (-10.0..=10.0).contains(&controls.bank_deg),
            "member {i}: bank {}",
            controls.bank_deg
        );
        banks.insert(controls.bank_deg as i64);
        assert!(
            matches!(controls.flaps, Flaps::Up | Flaps::Deg20),
            "member {i}"
        );
        flaps.insert(controls.flaps.degrees() as i64);
        assert!(!controls.brakes, "member {i}");
        assert_eq!(state.time_s, 0.0, "member {i}");
        assert_eq!(
            state.position_m,
            Vector3::new(10.0 * i as f64, 0.0, 500.0),
            "member {i}"
        );
        let speed = state.velocity_mps.x;
        assert!(
            speed == speed.round() && (45.0..=54.0).contains(&speed),
            "member {i}: speed {speed}"
        );
        assert_eq!(state.velocity_mps, Vector3::new(speed, 0.0, 0.0));
        speeds.insert(speed as i64);
        if let Some(before) = previous {
            assert_ne!(controls, before, "members {} and {i}", i - 1);
        }
        previous = Some(controls);
    }
    assert_eq!(throttles, (0..=10).collect());
    assert_eq!(alphas, (2..=6).collect());
    assert_eq!(banks, (-10..=10).collect());
    assert_eq!(speeds, (45..=54).collect());
    assert_eq!(flaps, [0, 20].into_iter().collect());
    // Far members too: within the same ranges, 10 m apart.
    for i in [65_535usize, 65_536, 1_000_003] {
        let (controls, state) = Palmer::fleet_member(i);
        assert!((0.5..=1.0).contains(&controls.throttle), "member {i}");
        assert!((2.0..=6.0).contains(&controls.alpha_deg), "member {i}");
        assert!((-10.0..=10.0).contains(&controls.bank_deg), "member {i}");
        assert!((45.0..=54.0).contains(&state.velocity_mps.x), "member {i}");
        assert_eq!(state.position_m.x, 10.0 * i as f64, "member {i}");
    }
}

/// Palmer's `Model::at_rest`, `ground_contact`, `time_step` and `apply`, as
/// documented: a crashed aircraft one frame later is where it was, every
/// velocity 0, its clock advanced by `dt`; the contact point is the point
/// mass (a height below 0 becomes 0, a downward `vz` becomes 0, `vx` and
/// `vy` are kept; a crash stops it); `dt = 1.0 / fps` in `f64`
/// (docs/cli.md); the checked step is `step` on valid input; `apply` is the
/// controls' own. Exact: copies, zeros, the clock's one addition and the
/// same step.
#[test]
fn palmer_rests_touches_the_ground_and_steps_as_documented() {
    use fdm_core::palmer::PalmerAction;

    let dt = Palmer::time_step(30.0);
    assert_eq!(dt, 1.0 / 30.0);
    assert_eq!(Palmer::time_step(8.0), 0.125);
    let state = PalmerState {
        time_s: 41.5,
        position_m: Vector3::new(-1234.5, 67.25, 0.0),
        velocity_mps: Vector3::new(55.0, -4.5, 2.25),
    };
    let rest = Palmer::at_rest(&state, dt);
    assert_eq!(rest.time_s, 41.5 + dt);
    assert_eq!(rest.position_m, state.position_m);
    assert_eq!(rest.velocity_mps, Vector3::zeros());

    let aircraft = Palmer::default_aircraft();
    let below = PalmerState {
        position_m: Vector3::new(300.0, -20.0, -0.75),
        velocity_mps: Vector3::new(40.0, 3.0, -2.5),
        ..state
    };
    let on = Palmer::ground_contact(&aircraft, &below, false);
    assert_eq!(on.time_s, below.time_s);
    assert_eq!(on.position_m, Vector3::new(300.0, -20.0, 0.0));
    assert_eq!(on.velocity_mps, Vector3::new(40.0, 3.0, 0.0));
    let crashed = Palmer::ground_contact(&aircraft, &below, true);
    assert_eq!(crashed.position_m, Vector3::new(300.0, -20.0, 0.0));
    assert_eq!(crashed.velocity_mps, Vector3::zeros());
    // Above the ground and climbing: untouched.
    let above = PalmerState {
        position_m: Vector3::new(300.0, -20.0, 0.5),
        velocity_mps: Vector3::new(40.0, 3.0, 1.5),
        ..state
    };
    assert_eq!(Palmer::ground_contact(&aircraft, &above, false), above);

    // The checked step is the model's: the same bits as `step` on valid
    // input (docs/palmer-model.md), a refusal for a non-finite state.
    let (member, mut flying) = Palmer::fleet_member(3);
    for _ in 0..30 {
        let checked = <Palmer as Model>::try_step(&aircraft, &member, &flying, dt).unwrap();
        assert_eq!(checked, Palmer::step(&aircraft, &member, &flying, dt));
        assert_ne!(checked, flying);
        flying = checked;
    }
    let broken = PalmerState {
        velocity_mps: Vector3::new(f64::NAN, 0.0, 0.0),
        ..flying
    };
    assert!(<Palmer as Model>::try_step(&aircraft, &member, &broken, dt).is_err());

    let controls = PalmerControls::default();
    for action in [PalmerAction::ThrottleUp, PalmerAction::BankLeft] {
        assert_eq!(
            Palmer::apply(&aircraft, controls, action),
            controls.apply(action)
        );
        assert_ne!(Palmer::apply(&aircraft, controls, action), controls);
    }
}
