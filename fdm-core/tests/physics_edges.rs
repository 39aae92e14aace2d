//! The physics at its documented edges, for both models and in both unit
//! systems (Palmer in metres, Bourg in feet), through the model interface
//! (`fdm_core::model::{fly, advance, settle}`, `Model::trim`):
//!
//! * a crashed Bourg stops turning as well as moving (docs/bourg-model.md,
//!   "The ground": after a crash the linear *and angular* velocities are
//!   zero), and keeps its attitude afterwards;
//! * after a ground contact Bourg's body-frame velocity is the earth-frame
//!   velocity the contact clamped, rotated into the body (checked with an
//!   independent `f64` rotation);
//! * the touchdown classes at their thresholds exactly: −2 m/s and −5 m/s
//!   for Palmer (the adjacent `f64` values on both sides), and the same
//!   thresholds in feet for Bourg (the adjacent `f32` ft/s values on both
//!   sides of −2/0.3048 and −5/0.3048 ft/s), plus a rough landing at
//!   2.4 m/s flown through a real step of each model;
//! * divergence at its threshold: a state is finite only when its speed is,
//!   the largest speed component whose square still fits the float type on
//!   one side and the next value on the other; a step that leaves Bourg with
//!   finite components but an infinite `f32` speed is a divergence;
//! * Palmer's trim levels the wings whatever bank the caller had, and its
//!   speed limits are where the documented limits bind (throttle 1, the
//!   stall angle); Bourg's thrust limit binds to one `f32` ulp;
//! * a deterministic sweep of Bourg's trim at 0.5 kt steps: the trimmable
//!   speeds are one interval (59.5 to 143.5 kt at 2000 ft, docs/cli.md;
//!   the bottom is where the elevator trim reaches its limit, the top where
//!   the thrust does), each holds, each refusal has the right reason.
//!
//! Each test was checked against the bug it is named for: the bug was planted
//! in a local copy (crash without zeroing the angular velocity; the contact
//! without recomputing the body velocity; Bourg's climb rate left in ft/s;
//! Palmer's trim keeping the caller's bank; Bourg's trim stopped after 6
//! Newton iterations; Bourg's `is_finite` looking at the position only), the
//! test failed, and the plant was reverted (docs/testing.md).

use fdm_core::bourg::{Bourg, BourgState, Quaternion};
use fdm_core::model::{advance, fly, settle, FlightStatus, LandingState, Model};
use fdm_core::palmer::{Flaps, Palmer, PalmerControls, PalmerState};
use fdm_core::start::{InitialConditions, StartError};
use fdm_core::units::{KNOTS_PER_MPS, METRES_PER_FOOT};
use nalgebra::{UnitQuaternion, Vector3};

/// A Bourg orientation (body → earth) from roll, pitch and yaw in degrees,
/// built with nalgebra in `f64` (not with the model's own conversion).
fn bourg_orientation(roll_deg: f64, pitch_deg: f64, yaw_deg: f64) -> Quaternion<f32> {
    let q = UnitQuaternion::from_euler_angles(
        roll_deg.to_radians(),
        pitch_deg.to_radians(),
        yaw_deg.to_radians(),
    );
    let c = q.quaternion().coords;
    Quaternion::new(c.w as f32, c.x as f32, c.y as f32, c.z as f32)
}

/// A Bourg state `z_ft` above the plane with the given earth velocity and
/// rotation, its body velocity consistent with the attitude.
fn bourg_at(z_ft: f32, velocity_ftps: Vector3<f32>, omega_radps: Vector3<f32>) -> BourgState {
    let orientation = bourg_orientation(12.0, -4.0, 25.0);
    BourgState {
        position_ft: Vector3::new(100.0, -40.0, z_ft),
        velocity_ftps,
        velocity_body_ftps: earth_to_body(&orientation, &velocity_ftps),
        angular_velocity_radps: omega_radps,
        orientation,
        ..BourgState::initial()
    }
}

/// `v_earth` in the body frame of `q` (body → earth), in `f64`.
fn earth_to_body(q: &Quaternion<f32>, v_earth: &Vector3<f32>) -> Vector3<f32> {
    let u = unit64(q);
    u.inverse_transform_vector(&v_earth.map(f64::from))
        .map(|c| c as f32)
}

fn unit64(q: &Quaternion<f32>) -> UnitQuaternion<f64> {
    UnitQuaternion::from_quaternion(nalgebra::Quaternion::new(
        f64::from(q.coords.w),
        f64::from(q.coords.x),
        f64::from(q.coords.y),
        f64::from(q.coords.z),
    ))
}

/// The largest difference between the earth velocity and the body velocity
/// rotated back to the earth frame, ft/s.
fn body_earth_mismatch_ftps(s: &BourgState) -> f64 {
    let earth = unit64(&s.orientation).transform_vector(&s.velocity_body_ftps.map(f64::from));
    (earth - s.velocity_ftps.map(f64::from)).amax()
}

fn palmer_at(z_m: f64, vz_mps: f64) -> PalmerState {
    PalmerState {
        position_m: Vector3::new(10.0, 5.0, z_m),
        velocity_mps: Vector3::new(40.0, 0.0, vz_mps),
        ..PalmerState::at_rest()
    }
}

#[test]
fn a_crashed_bourg_stops_turning_and_keeps_its_attitude() {
    let aircraft = Bourg::default_aircraft();
    let controls = Bourg::initial_controls();
    let dt = Bourg::time_step(30.0);
    // Half a foot up, spinning about all three axes, sinking at 60 ft/s
    // (18 m/s): the next step ends below the plane, a crash.
    let omega = Vector3::new(0.8, -0.5, 0.3);
    let state = bourg_at(0.5, Vector3::new(90.0, 10.0, -60.0), omega);
    let (crashed, status) = fly::<Bourg>(&aircraft, &controls, FlightStatus::Airborne, &state, dt);
    assert_eq!(status, FlightStatus::Landed(LandingState::Crash));
    assert_eq!(
        crashed.angular_velocity_radps,
        Vector3::zeros(),
        "{crashed:?}"
    );
    assert_eq!(crashed.velocity_ftps, Vector3::zeros());
    assert_eq!(crashed.velocity_body_ftps, Vector3::zeros());
    assert_eq!(crashed.position_ft.z, 0.0);
    // Afterwards it stays exactly where and as it came down, whatever the
    // controls; only its clock runs.
    let mut full = controls;
    full.thrust_lb = 3000.0;
    let (mut s, mut st) = (crashed, status);
    for frame in 1..=90 {
        (s, st) = fly::<Bourg>(&aircraft, &full, st, &s, dt);
        assert_eq!(st, status);
        assert_eq!(s.angular_velocity_radps, Vector3::zeros(), "frame {frame}");
        assert_eq!(s.velocity_ftps, Vector3::zeros(), "frame {frame}");
        assert_eq!(s.orientation, crashed.orientation, "frame {frame}");
        assert_eq!(s.position_ft, crashed.position_ft, "frame {frame}");
    }
    assert!(s.time_s > crashed.time_s + 2.9);
}

#[test]
fn after_a_ground_contact_bourgs_body_velocity_is_its_earth_velocity() {
    let aircraft = Bourg::default_aircraft();
    let controls = Bourg::initial_controls();
    let dt = Bourg::time_step(30.0);
    // Banked, pitched and yawed, touching down safe (−1 m/s) and rough
    // (−3 m/s): the contact removes the downward velocity, which changes all
    // three body components.
    for (vz_ftps, class) in [(-3.28, LandingState::Safe), (-9.84, LandingState::Rough)] {
        let state = bourg_at(
            0.05,
            Vector3::new(110.0, -15.0, vz_ftps),
            Vector3::new(0.1, 0.05, -0.02),
        );
        assert!(body_earth_mismatch_ftps(&state) < 1e-3);
        let (next, status) = fly::<Bourg>(&aircraft, &controls, FlightStatus::Airborne, &state, dt);
        assert_eq!(status, FlightStatus::Landed(class), "{vz_ftps}");
        assert_eq!(next.position_ft.z, 0.0);
        assert_eq!(next.velocity_ftps.z, 0.0, "a downward vz is removed");
        // f32 rounding of a rotation of a ~110 ft/s vector: a few 1e-5 ft/s.
        let mismatch = body_earth_mismatch_ftps(&next);
        assert!(mismatch < 1e-3, "{vz_ftps} ft/s: {mismatch} ft/s\n{next:?}");
        // Rolling on: every later frame on the ground is consistent too.
        let (mut s, mut st) = (next, status);
        for frame in 0..60 {
            (s, st) = fly::<Bourg>(&aircraft, &controls, st, &s, dt);
            let mismatch = body_earth_mismatch_ftps(&s);
            assert!(mismatch < 1e-3, "frame {frame}: {mismatch}\n{s:?}");
        }
    }
}

/// `(state at or below the plane, expected class)` for a touchdown from
/// `Airborne`, classified by `settle` (the contact half of a frame).
fn palmer_touchdown(vz_mps: f64) -> FlightStatus {
    let a = Palmer::default_aircraft();
    settle::<Palmer>(&a, FlightStatus::Airborne, &palmer_at(-0.01, vz_mps)).1
}

fn bourg_touchdown(vz_ftps: f32) -> FlightStatus {
    let a = Bourg::default_aircraft();
    let state = bourg_at(-0.01, Vector3::new(100.0, 0.0, vz_ftps), Vector3::zeros());
    settle::<Bourg>(&a, FlightStatus::Airborne, &state).1
}

#[test]
fn palmer_touchdowns_land_at_each_threshold_in_metres() {
    use LandingState::{Crash, Rough, Safe};
    // docs/palmer-model.md: vz > −2 m/s safe, vz > −5 m/s rough, else crash.
    for (vz, class) in [
        (0.0, Safe),
        (-1.0, Safe),
        ((-2.0_f64).next_up(), Safe),
        (-2.0, Rough),
        (-2.4, Rough),
        ((-5.0_f64).next_up(), Rough),
        (-5.0, Crash),
        (-30.0, Crash),
        (f64::NAN, Crash),
    ] {
        assert_eq!(
            palmer_touchdown(vz),
            FlightStatus::Landed(class),
            "{vz} m/s"
        );
    }
    // Exactly on the plane is a touchdown; the smallest height above it is not.
    let a = Palmer::default_aircraft();
    let on = settle::<Palmer>(&a, FlightStatus::Airborne, &palmer_at(0.0, -1.0)).1;
    assert_eq!(on, FlightStatus::Landed(Safe));
    let above = settle::<Palmer>(
        &a,
        FlightStatus::Airborne,
        &palmer_at(f64::MIN_POSITIVE, -9.0),
    )
    .1;
    assert_eq!(above, FlightStatus::Airborne);
}

/// The `f32` values just above and at-or-below `limit_mps` converted to ft/s
/// (the two neighbours of the conversion `limit / 0.3048`).
fn f32_around_ftps(limit_mps: f64) -> (f32, f32) {
    let exact = limit_mps / METRES_PER_FOOT;
    let mut below = exact as f32;
    while f64::from(below) * METRES_PER_FOOT > limit_mps {
        below = below.next_down();
    }
    while f64::from(below.next_up()) * METRES_PER_FOOT <= limit_mps {
        below = below.next_up();
    }
    let above = below.next_up();
    // Both are within one f32 ulp of the exact threshold, and their products
    // with 0.3048 are far from −2 and −5 compared with f64 rounding.
    let ulp = f64::from(f32::EPSILON) * exact.abs();
    assert!((f64::from(above) - exact).abs() <= ulp && (f64::from(below) - exact).abs() <= ulp);
    (above, below)
}

#[test]
fn bourg_touchdowns_land_at_each_threshold_in_feet() {
    use LandingState::{Crash, Rough, Safe};
    // docs/bourg-model.md: safe above −2 m/s (−6.56 ft/s), rough above
    // −5 m/s (−16.4 ft/s), otherwise a crash.
    let (safe_edge, rough_edge) = f32_around_ftps(-2.0);
    let (rough_top, crash_edge) = f32_around_ftps(-5.0);
    assert!(safe_edge > -6.562 && safe_edge < -6.561, "{safe_edge}");
    assert!(crash_edge > -16.405 && crash_edge < -16.404, "{crash_edge}");
    for (vz, class) in [
        (0.0, Safe),
        (-3.0, Safe),
        (safe_edge, Safe),
        (rough_edge, Rough),
        // 2.4 m/s: rough in metres; a crash if feet were read as metres.
        ((-2.4 / METRES_PER_FOOT) as f32, Rough),
        (-6.0, Safe),
        (-16.0, Rough),
        (rough_top, Rough),
        (crash_edge, Crash),
        (-40.0, Crash),
        (f32::NAN, Crash),
    ] {
        assert_eq!(
            bourg_touchdown(vz),
            FlightStatus::Landed(class),
            "{vz} ft/s"
        );
    }
}

#[test]
fn a_rough_landing_at_2_4_mps_is_rough_through_a_whole_frame() {
    // Each model sinking at 2.4 m/s, a few centimetres above the plane: one
    // frame's gravity adds at most 0.33 m/s at 30 fps, still rough.
    let vz_mps = -2.4;
    let a = Palmer::default_aircraft();
    let c = PalmerControls {
        throttle: 0.3,
        alpha_deg: 4.0,
        ..PalmerControls::default()
    };
    let (s, st) = fly::<Palmer>(
        &a,
        &c,
        FlightStatus::Airborne,
        &palmer_at(0.02, vz_mps),
        1.0 / 30.0,
    );
    assert_eq!(st, FlightStatus::Landed(LandingState::Rough), "{s:?}");
    assert_eq!((s.position_m.z, s.velocity_mps.z), (0.0, 0.0));

    let a = Bourg::default_aircraft();
    let vz_ftps = (vz_mps / METRES_PER_FOOT) as f32;
    let state = bourg_at(0.05, Vector3::new(100.0, 0.0, vz_ftps), Vector3::zeros());
    let (s, st) = fly::<Bourg>(
        &a,
        &Bourg::initial_controls(),
        FlightStatus::Airborne,
        &state,
        Bourg::time_step(30.0),
    );
    assert_eq!(st, FlightStatus::Landed(LandingState::Rough), "{s:?}");
    assert_eq!((s.position_ft.z, s.velocity_ftps.z), (0.0, 0.0));
}

#[test]
fn a_state_is_finite_exactly_while_its_speed_is() {
    // Palmer, f64: the largest component whose square is finite, then the next.
    let mut edge = f64::MAX.sqrt();
    while (edge.next_up() * edge.next_up()).is_finite() {
        edge = edge.next_up();
    }
    while !(edge * edge).is_finite() {
        edge = edge.next_down();
    }
    let palmer = |vx: f64, vy: f64| PalmerState {
        velocity_mps: Vector3::new(vx, vy, 0.0),
        ..palmer_at(1000.0, 0.0)
    };
    assert!(Palmer::is_finite(&palmer(edge, 0.0)));
    assert!(!Palmer::is_finite(&palmer(edge.next_up(), 0.0)));
    // Each component's square fits, their sum does not.
    let half = edge * 0.75;
    assert!(!Palmer::is_finite(&palmer(half, half)));

    // Bourg, f32: the square is taken in f32. A product of two f32 is exact in
    // f64, so rounding it to f32 is the f32 product: the edge computed there.
    let fits = |v: f32| ((f64::from(v) * f64::from(v)) as f32).is_finite();
    let mut edge = f32::MAX.sqrt();
    while fits(edge.next_up()) {
        edge = edge.next_up();
    }
    while !fits(edge) {
        edge = edge.next_down();
    }
    assert!(edge > 1.8e19 && edge < 1.9e19, "{edge}");
    let bourg = |vx: f32, vy: f32| BourgState {
        velocity_ftps: Vector3::new(vx, vy, 0.0),
        ..BourgState::initial()
    };
    assert!(Bourg::is_finite(&bourg(edge, 0.0)));
    assert!(!Bourg::is_finite(&bourg(edge.next_up(), 0.0)));
    assert!(!Bourg::is_finite(&bourg(-edge.next_up(), 0.0)));
    let half = edge * 0.75;
    assert!(!Bourg::is_finite(&bourg(half, half)));
}

#[test]
fn a_bourg_step_to_an_infinite_speed_is_a_divergence() {
    let aircraft = Bourg::default_aircraft();
    let controls = Bourg::initial_controls();
    let dt = Bourg::time_step(30.0);
    // Every component finite, and stays finite through the step (no body
    // velocity, so no aerodynamic load; the position moves by v·dt), but
    // |v| overflows f32: the documented divergence.
    let state = BourgState {
        velocity_ftps: Vector3::new(1.5e19, 1.5e19, 0.0),
        ..BourgState::initial()
    };
    let next = Bourg::step(&aircraft, &controls, &state, dt);
    assert!(next.is_finite(), "every field finite: {next:?}");
    assert!(next.speed_ftps().is_infinite());
    let (kept, status) = advance::<Bourg>(&aircraft, &controls, FlightStatus::Airborne, &state, dt);
    assert_eq!(status, FlightStatus::Diverged);
    assert_eq!(kept, state, "the last state is kept");
    let (_, status) = fly::<Bourg>(&aircraft, &controls, FlightStatus::Airborne, &state, dt);
    assert_eq!(status, FlightStatus::Diverged);
    // Nothing that is not diverged shows an infinite airspeed: one component
    // at the edge of the f32 square is still a finite speed.
    let at_edge = BourgState {
        velocity_ftps: Vector3::new(1.8e19, 0.0, 0.0),
        ..BourgState::initial()
    };
    let (s, status) = advance::<Bourg>(&aircraft, &controls, FlightStatus::Airborne, &at_edge, dt);
    if status != FlightStatus::Diverged {
        assert!(Bourg::view(&aircraft, &controls, &s).is_finite(), "{s:?}");
    }
}

#[test]
fn palmers_trim_levels_the_wings_whatever_the_callers_bank() {
    let a = Palmer::default_aircraft();
    let ic = InitialConditions::from_feet_knots(3000.0, 90.0, 40.0);
    for bank_deg in [-20.0, -7.0, 0.0, 13.0, 20.0] {
        let mut c = PalmerControls {
            bank_deg,
            flaps: Flaps::Deg20,
            ..PalmerControls::default()
        };
        c.throttle = 0.9;
        let trimmed = Palmer::trim(&a, &c, &ic).expect("90 kt trims");
        assert_eq!(trimmed.controls.bank_deg, 0.0, "bank {bank_deg}");
        assert_eq!(trimmed.controls.flaps, Flaps::Deg20, "flaps are kept");
        // Wings level: 60 s hands off, the heading does not move.
        let (mut s, mut st) = (trimmed.state, FlightStatus::Airborne);
        let h0 = Palmer::view(&a, &trimmed.controls, &s).attitude.heading_deg;
        for _ in 0..1800 {
            (s, st) = fly::<Palmer>(&a, &trimmed.controls, st, &s, 1.0 / 30.0);
        }
        let h1 = Palmer::view(&a, &trimmed.controls, &s).attitude.heading_deg;
        assert!(
            (h1 - h0).abs() < 1e-6,
            "bank {bank_deg}: heading {h0} -> {h1}"
        );
    }
}

/// Bisects the speed (kt) between a trimmable `ok` and a refused `bad`
/// until they are 1e-6 kt apart; returns the last trimmable speed, its trim
/// and the refusal just beyond it.
fn trim_edge<M: Model>(
    altitude_ft: f64,
    mut ok: f64,
    mut bad: f64,
) -> (
    f64,
    fdm_core::start::Trimmed<M::Controls, M::State>,
    StartError,
) {
    let a = M::default_aircraft();
    let c = M::initial_controls();
    let trim = |kt: f64| {
        M::trim(
            &a,
            &c,
            &InitialConditions::from_feet_knots(altitude_ft, kt, 0.0),
        )
    };
    let Err(mut refusal) = trim(bad) else {
        panic!("{bad} kt trims")
    };
    while (bad - ok).abs() > 1e-6 {
        let mid = 0.5 * (ok + bad);
        match trim(mid) {
            Ok(_) => ok = mid,
            Err(e) => {
                refusal = e;
                bad = mid;
            }
        }
    }
    let Ok(trimmed) = trim(ok) else {
        panic!("{ok} kt does not trim")
    };
    (ok, trimmed, refusal)
}

#[test]
fn palmers_trim_limits_are_full_throttle_and_the_stall_angle() {
    let aircraft = Palmer::default_aircraft();
    // docs/cli.md: at 2000 ft Palmer trims from about 53 to 125 kt.
    let (top, at_top, why) = trim_edge::<Palmer>(2000.0, 100.0, 200.0);
    assert!(matches!(why, StartError::AboveMaxPower { .. }), "{why}");
    assert!((120.0..130.0).contains(&top), "{top}");
    assert!(
        at_top.controls.throttle <= 1.0 && at_top.controls.throttle > 0.9999,
        "{:?}",
        at_top.controls
    );
    let (bottom, at_bottom, why) = trim_edge::<Palmer>(2000.0, 100.0, 20.0);
    assert!(matches!(why, StartError::BelowStall { .. }), "{why}");
    assert!((48.0..58.0).contains(&bottom), "{bottom}");
    let stall = aircraft.alpha_cl_max_deg;
    assert!(
        at_bottom.controls.alpha_deg < stall && at_bottom.controls.alpha_deg > stall - 1e-3,
        "{} vs {stall}",
        at_bottom.controls.alpha_deg
    );
    // The refusals carry the speed asked (m/s).
    let slow = InitialConditions::from_feet_knots(2000.0, bottom - 0.01, 0.0);
    match Palmer::trim(&aircraft, &Palmer::initial_controls(), &slow) {
        Err(StartError::BelowStall { speed_mps }) => assert_eq!(speed_mps, slow.speed_mps),
        other => panic!("{other:?}"),
    }
}

#[test]
fn bourgs_trim_limits_are_full_thrust_and_the_elevator_trims_range() {
    // Measured at 2000 ft: 59.5 to 143.5 kt at 0.5 kt steps (docs/cli.md).
    // The top is where the thrust reaches 3000 lb; the bottom where the
    // elevator trim reaches +1 (the model's range, bourg-model.md), before
    // the wing stalls.
    let (top, at_top, why) = trim_edge::<Bourg>(2000.0, 100.0, 200.0);
    assert!(matches!(why, StartError::AboveMaxPower { .. }), "{why}");
    assert!((143.5..144.0).contains(&top), "{top}");
    let thrust = at_top.controls.thrust_lb;
    assert!(thrust <= 3000.0 && thrust > 2999.0, "{thrust}");
    let (bottom, at_bottom, why) = trim_edge::<Bourg>(2000.0, 100.0, 20.0);
    assert!(matches!(why, StartError::OutOfTrim { .. }), "{why}");
    assert!((59.0..59.5).contains(&bottom), "{bottom}");
    let trim = at_bottom.controls.pitch_trim;
    assert!(trim <= 1.0 && trim > 0.999, "{trim}");
}

#[test]
fn bourgs_thrust_limit_binds_to_one_f32_ulp() {
    let ic = InitialConditions::from_feet_knots(2000.0, 120.0, 0.0);
    let controls = Bourg::initial_controls();
    let mut aircraft = Bourg::default_aircraft();
    let thrust = Bourg::trim(&aircraft, &controls, &ic)
        .unwrap()
        .controls
        .thrust_lb;
    assert!(thrust > 500.0 && thrust < 3000.0, "{thrust}");
    aircraft.max_thrust_lb = thrust.next_up();
    let ok = Bourg::trim(&aircraft, &controls, &ic).expect("at the limit");
    assert_eq!(ok.controls.thrust_lb, thrust);
    aircraft.max_thrust_lb = thrust.next_down().next_down();
    assert!(matches!(
        Bourg::trim(&aircraft, &controls, &ic),
        Err(StartError::AboveMaxPower { .. })
    ));
}

/// Flies a trimmed start 30 s hands off; the largest altitude (ft) and
/// airspeed (kt) deviations.
fn bourg_hold(ic: &InitialConditions) -> (f64, f64) {
    let a = Bourg::default_aircraft();
    let t = Bourg::trim(&a, &Bourg::initial_controls(), ic).unwrap();
    let (mut s, mut st) = (t.state, FlightStatus::Airborne);
    let dt = Bourg::time_step(30.0);
    let (mut dalt, mut dspeed) = (0.0_f64, 0.0_f64);
    for _ in 0..900 {
        let c = Bourg::begin_frame(t.controls);
        (s, st) = fly::<Bourg>(&a, &c, st, &s, dt);
        let v = Bourg::view(&a, &c, &s);
        dalt = dalt.max((v.height_m() - ic.altitude_m).abs() / METRES_PER_FOOT);
        dspeed = dspeed.max((v.airspeed_mps - ic.speed_mps).abs() * KNOTS_PER_MPS);
    }
    assert_eq!(st, FlightStatus::Airborne);
    (dalt, dspeed)
}

/// Every speed from 30 to 200 kt at 0.5 kt steps (the property test in
/// `start_trim.rs` samples this range at random; a sweep cannot miss a gap
/// of a few knots). At 2000 ft the trimmable speeds are one interval whose
/// ends are the documented ones (59.5 and 143.5 kt); each holds (±100 ft,
/// ±5 kt for 30 s, the property test's bounds); below it every refusal is
/// the stall or the trim range, above it full power.
#[test]
fn bourgs_trim_sweep_at_half_knot_steps_is_one_interval() {
    let a = Bourg::default_aircraft();
    let c = Bourg::initial_controls();
    let speeds: Vec<f64> = (60..=400).map(|i| f64::from(i) * 0.5).collect();
    let results: Vec<_> = speeds
        .iter()
        .map(|&kt| Bourg::trim(&a, &c, &InitialConditions::from_feet_knots(2000.0, kt, 0.0)))
        .collect();
    let trimmed: Vec<usize> = (0..speeds.len()).filter(|&i| results[i].is_ok()).collect();
    let (first, last) = (trimmed[0], *trimmed.last().unwrap());
    assert_eq!(
        trimmed.len(),
        last - first + 1,
        "a gap in the trimmable speeds: {:?}",
        trimmed.iter().map(|&i| speeds[i]).collect::<Vec<_>>()
    );
    assert_eq!((speeds[first], speeds[last]), (59.5, 143.5));
    for (i, r) in results.iter().enumerate() {
        let kt = speeds[i];
        match r {
            Ok(_) => {
                let (dalt, dspeed) =
                    bourg_hold(&InitialConditions::from_feet_knots(2000.0, kt, 0.0));
                assert!(
                    dalt <= 100.0 && dspeed <= 5.0,
                    "{kt} kt: {dalt} ft, {dspeed} kt"
                );
            }
            Err(StartError::BelowStall { .. } | StartError::OutOfTrim { .. }) => {
                assert!(i < first, "{kt} kt: {r:?}");
            }
            Err(StartError::AboveMaxPower { .. }) => assert!(i > last, "{kt} kt: {r:?}"),
            Err(e) => panic!("{kt} kt: {e}"),
        }
    }
}

/// The same at other altitudes, without the hold: one interval, with its
/// ends moving as the thrust and lift do (the model's air density is the
/// same at every altitude, docs/bourg-model.md, so the interval does not
/// move at all).
#[test]
fn bourgs_trim_interval_is_the_same_at_every_altitude() {
    let a = Bourg::default_aircraft();
    let c = Bourg::initial_controls();
    let interval = |ft: f64| {
        let ok: Vec<f64> = (60..=400)
            .map(|i| f64::from(i) * 0.5)
            .filter(|&kt| {
                Bourg::trim(&a, &c, &InitialConditions::from_feet_knots(ft, kt, 0.0)).is_ok()
            })
            .collect();
        let n = ok.len();
        assert_eq!(
            ok[n - 1] - ok[0],
            (n - 1) as f64 * 0.5,
            "{ft} ft: a gap in {ok:?}"
        );
        (ok[0], ok[n - 1])
    };
    let at_2000 = interval(2000.0);
    for ft in [500.0, 8000.0, 30000.0] {
        assert_eq!(interval(ft), at_2000, "{ft} ft");
    }
}
