//! Initial conditions and trim through the model interface
//! ([`Model::state_at`], [`Model::trim`]).
//!
//! Tolerances are the targets, in the CLI's units: a trimmed Palmer
//! holds its altitude within ±10 ft and its airspeed within ±1 kt for five
//! minutes at 30 fps hands off; Bourg within ±100 ft and ±5 kt for 60 s.
//! The placement checks are exact (or 1e-9 relative where a cosine is
//! involved), since they are a few operations.

use fdm_core::bourg::{Bourg, BourgAction};
use fdm_core::model::{fly, FlightStatus, Model};
use fdm_core::palmer::Palmer;
use fdm_core::start::{InitialConditions, StartError, TrimReport};
use fdm_core::units::{KNOTS_PER_MPS, METRES_PER_FOOT};
use proptest::prelude::*;

/// Flies `frames` frames hands off from a trimmed start and returns the
/// largest altitude (ft) and airspeed (kt) deviations.
fn hold<M: Model>(conditions: &InitialConditions, fps: f64, frames: u32) -> (f64, f64) {
    let aircraft = M::default_aircraft();
    let trimmed = M::trim(&aircraft, &M::initial_controls(), conditions).unwrap();
    let (mut state, mut status) = (trimmed.state, FlightStatus::Airborne);
    let dt = M::time_step(fps);
    let (mut dalt, mut dspeed) = (0.0_f64, 0.0_f64);
    for _ in 0..frames {
        let controls = M::begin_frame(trimmed.controls);
        (state, status) = fly::<M>(&aircraft, &controls, status, &state, dt);
        let view = M::view(&aircraft, &controls, &state);
        dalt = dalt.max((view.height_m() - conditions.altitude_m).abs() / METRES_PER_FOOT);
        dspeed = dspeed.max((view.airspeed_mps - conditions.speed_mps).abs() * KNOTS_PER_MPS);
    }
    assert_eq!(status, FlightStatus::Airborne);
    (dalt, dspeed)
}

#[test]
fn palmer_trimmed_at_2000_ft_and_100_kt_holds_for_five_minutes() {
    let ic = InitialConditions::from_feet_knots(2000.0, 100.0, 0.0);
    let (dalt, dspeed) = hold::<Palmer>(&ic, 30.0, 30 * 300);
    assert!(dalt <= 10.0 && dspeed <= 1.0, "{dalt} ft, {dspeed} kt");
}

#[test]
fn palmer_state_at_places_and_points_the_aircraft() {
    let a = Palmer::default_aircraft();
    let at_rest = Palmer::state_at(&a, &InitialConditions::from_feet_knots(0.0, 0.0, 0.0)).unwrap();
    assert_eq!(at_rest, Palmer::initial_state());
    let east =
        Palmer::state_at(&a, &InitialConditions::from_feet_knots(1000.0, 100.0, 90.0)).unwrap();
    assert_eq!(east.position_m.z, 304.8);
    assert!(east.velocity_mps.x.abs() < 1e-9);
    assert!((east.velocity_mps.y + 100.0 / KNOTS_PER_MPS).abs() < 1e-9);
    let view = Palmer::view(&a, &Palmer::initial_controls(), &east);
    assert!(
        (view.attitude.heading_deg - 90.0).abs() < 1e-9,
        "{:?}",
        view.attitude
    );
    for bad in [
        InitialConditions::from_feet_knots(-1.0, 100.0, 0.0),
        InitialConditions::from_feet_knots(1000.0, f64::NAN, 0.0),
        InitialConditions::from_feet_knots(1000.0, 100.0, f64::INFINITY),
    ] {
        assert_eq!(
            Palmer::state_at(&a, &bad),
            Err(StartError::InvalidConditions)
        );
    }
}

#[test]
fn palmer_untrimmable_speeds_are_refused() {
    let a = Palmer::default_aircraft();
    let c = Palmer::initial_controls();
    let slow = InitialConditions::from_feet_knots(2000.0, 30.0, 0.0);
    assert!(matches!(
        Palmer::trim(&a, &c, &slow),
        Err(StartError::BelowStall { .. })
    ));
    let fast = InitialConditions::from_feet_knots(2000.0, 250.0, 0.0);
    assert!(matches!(
        Palmer::trim(&a, &c, &fast),
        Err(StartError::AboveMaxPower { .. })
    ));
}

#[test]
fn bourg_trimmed_at_2000_ft_and_100_kt_holds_for_a_minute() {
    let ic = InitialConditions::from_feet_knots(2000.0, 100.0, 0.0);
    let (dalt, dspeed) = hold::<Bourg>(&ic, 30.0, 30 * 60);
    assert!(dalt <= 100.0 && dspeed <= 5.0, "{dalt} ft, {dspeed} kt");
}

#[test]
fn bourg_state_at_places_and_points_the_aircraft() {
    let a = Bourg::default_aircraft();
    let east =
        Bourg::state_at(&a, &InitialConditions::from_feet_knots(3000.0, 100.0, 90.0)).unwrap();
    assert_eq!(east.position_ft.z, 3000.0);
    assert_eq!(east.position_ft.x, -5000.0);
    let v = 100.0 / KNOTS_PER_MPS / METRES_PER_FOOT;
    // Flying east (−y), nose along the velocity: the body velocity is all forward.
    assert!((f64::from(east.velocity_ftps.y) + v).abs() < 1e-4 * v);
    assert!(
        (f64::from(east.velocity_body_ftps.x) - v).abs() < 1e-4 * v,
        "{east:?}"
    );
    assert!(east.velocity_body_ftps.y.abs() < 1e-3 && east.velocity_body_ftps.z.abs() < 1e-3);
    let view = Bourg::view(&a, &Bourg::initial_controls(), &east);
    assert!(
        (view.attitude.heading_deg - 90.0).abs() < 1e-3,
        "{:?}",
        view.attitude
    );
    assert!(view.attitude.pitch_deg.abs() < 1e-3);
}

/// `bourg::state_at_attitude`, as documented: flying level toward the
/// heading with the nose `pitch_deg` above the horizon, so the view's pitch
/// is `pitch_deg` and, in level flight, so is the angle of attack (the view's
/// alpha, `atan2` of the body velocity's down and forward components), with
/// no sideslip. Within 1e-4°: the attitude is an `f32` quaternion (relative
/// error about 6e-8, i.e. 3e-6° in an angle) and the body velocity an `f32`
/// rotation of it; measured errors are below 4e-6°. And the conditions and
/// the pitch are checked each on its own: invalid conditions are refused at
/// a level nose, a pitch that is not finite in valid conditions.
#[test]
fn bourg_state_at_attitude_raises_the_nose_above_the_level_path() {
    use fdm_core::bourg::state_at_attitude;

    let a = Bourg::default_aircraft();
    let ic = InitialConditions::from_feet_knots(2000.0, 100.0, 30.0);
    for pitch in [5.0f32, -3.0, 12.5] {
        let s = state_at_attitude(&ic, pitch).unwrap();
        assert_eq!(s.velocity_ftps.z, 0.0, "level");
        let view = Bourg::view(&a, &Bourg::initial_controls(), &s);
        let p = f64::from(pitch);
        assert!(
            (view.attitude.pitch_deg - p).abs() < 1e-4,
            "pitch {pitch}: {:?}",
            view.attitude
        );
        assert!((view.attitude.heading_deg - 30.0).abs() < 1e-4);
        assert!(view.attitude.roll_deg.abs() < 1e-4);
        assert!(
            (view.alpha_deg - p).abs() < 1e-4,
            "pitch {pitch}: alpha {}",
            view.alpha_deg
        );
        assert!(view.beta_deg.abs() < 1e-4, "{}", view.beta_deg);
    }

    let invalid = [
        InitialConditions::from_feet_knots(-1.0, 100.0, 0.0),
        InitialConditions::from_feet_knots(2000.0, -1.0, 0.0),
        InitialConditions::from_feet_knots(2000.0, f64::NAN, 0.0),
        InitialConditions::from_feet_knots(2000.0, 100.0, f64::INFINITY),
    ];
    for ic in invalid {
        assert_eq!(
            state_at_attitude(&ic, 0.0),
            Err(StartError::InvalidConditions),
            "{ic:?}"
        );
    }
    for pitch in [f32::NAN, f32::INFINITY, f32::NEG_INFINITY] {
        assert_eq!(
            state_at_attitude(&ic, pitch),
            Err(StartError::InvalidConditions),
            "pitch {pitch}"
        );
    }
}

#[test]
fn bourg_untrimmable_speeds_are_refused() {
    let a = Bourg::default_aircraft();
    let c = Bourg::initial_controls();
    let slow = InitialConditions::from_feet_knots(2000.0, 30.0, 0.0);
    assert!(matches!(
        Bourg::trim(&a, &c, &slow),
        Err(StartError::BelowStall { .. })
    ));
    let fast = InitialConditions::from_feet_knots(2000.0, 250.0, 0.0);
    assert!(matches!(
        Bourg::trim(&a, &c, &fast),
        Err(StartError::AboveMaxPower { .. })
    ));
}

#[test]
fn bourg_pitch_trim_moves_in_steps_and_zero_is_the_original() {
    let a = Bourg::default_aircraft();
    let mut c = Bourg::initial_controls();
    for _ in 0..150 {
        c = Bourg::apply(&a, c, BourgAction::TrimNoseUp);
    }
    assert_eq!(c.pitch_trim, 1.0);
    c = Bourg::begin_frame(c);
    assert_eq!(c.pitch_trim, 1.0, "the trim persists across frames");
    for _ in 0..300 {
        c = Bourg::apply(&a, c, BourgAction::TrimNoseDown);
    }
    assert_eq!(c.pitch_trim, -1.0);
    // Nose-up trim pitches the nose up compared with none.
    let state =
        Bourg::state_at(&a, &InitialConditions::from_feet_knots(2000.0, 100.0, 0.0)).unwrap();
    let pitch_after = |trim: f32| {
        let mut c = Bourg::initial_controls();
        c.pitch_trim = trim;
        let mut s = state;
        for _ in 0..30 {
            s = Bourg::step(&a, &c, &s, 1.0 / 30.0);
        }
        -s.euler_angles_deg().y
    };
    assert!(pitch_after(0.5) > pitch_after(0.0));
    assert!(pitch_after(-0.5) < pitch_after(0.0));
}

/// The speed range searched by the property tests, kt: from below both
/// models' stall to above both models' full-power speed at these altitudes
/// (measured at 2000 ft: Palmer trims from about 53 to 125 kt, Bourg from
/// 59.5 to 143.5 kt, `physics_edges.rs`).
const SPEEDS_KT: core::ops::Range<f64> = 30.0..200.0;

proptest! {
    #![proptest_config(ProptestConfig::with_cases(if cfg!(debug_assertions) { 12 } else { 64 }))]

    /// Every speed Palmer trims, it holds (60 s at 30 fps, ±10 ft, ±1 kt);
    /// every other speed is refused as below the stall or above full power.
    #[test]
    fn palmer_every_trimmable_speed_holds(
        kt in SPEEDS_KT, ft in 500.0..8000.0_f64, hdg in 0.0..360.0_f64,
    ) {
        let ic = InitialConditions::from_feet_knots(ft, kt, hdg);
        match Palmer::trim(&Palmer::default_aircraft(), &Palmer::initial_controls(), &ic) {
            Ok(_) => {
                let (dalt, dspeed) = hold::<Palmer>(&ic, 30.0, 30 * 60);
                prop_assert!(dalt <= 10.0 && dspeed <= 1.0, "{kt} kt: {dalt} ft, {dspeed} kt");
            }
            Err(StartError::BelowStall { .. }) => prop_assert!(kt < 70.0, "{kt}"),
            Err(StartError::AboveMaxPower { .. }) => prop_assert!(kt > 100.0, "{kt}"),
            Err(e) => prop_assert!(false, "{kt} kt: {e}"),
        }
    }

    /// The same for Bourg (30 s at 30 fps, ±100 ft, ±5 kt).
    #[test]
    fn bourg_every_trimmable_speed_holds(
        kt in SPEEDS_KT, ft in 1000.0..8000.0_f64, hdg in 0.0..360.0_f64,
    ) {
        let ic = InitialConditions::from_feet_knots(ft, kt, hdg);
        match Bourg::trim(&Bourg::default_aircraft(), &Bourg::initial_controls(), &ic) {
            Ok(_) => {
                let (dalt, dspeed) = hold::<Bourg>(&ic, 30.0, 30 * 30);
                prop_assert!(dalt <= 100.0 && dspeed <= 5.0, "{kt} kt: {dalt} ft, {dspeed} kt");
            }
            Err(StartError::BelowStall { .. } | StartError::OutOfTrim { .. }) => {
                prop_assert!(kt < 70.0, "{kt}")
            }
            Err(StartError::AboveMaxPower { .. }) => prop_assert!(kt > 120.0, "{kt}"),
            Err(e) => prop_assert!(false, "{kt} kt: {e}"),
        }
    }
}

/// Every refusal is one line for the CLI's `sim-cli: error:` (docs/cli.md,
/// exit status 2), and the trim refusals name the speed asked, in knots.
#[test]
fn start_errors_are_one_line_naming_the_speed_in_knots() {
    let speed_mps = 30.0 / KNOTS_PER_MPS;
    for e in [
        StartError::InvalidConditions,
        StartError::Unsupported,
        StartError::BelowStall { speed_mps },
        StartError::AboveMaxPower { speed_mps },
        StartError::OutOfTrim { speed_mps },
    ] {
        let text = e.to_string();
        assert!(!text.is_empty() && !text.contains('\n'), "{e:?}: {text:?}");
        if !matches!(e, StartError::InvalidConditions | StartError::Unsupported) {
            assert!(text.contains("30.0 kt"), "{e:?}: {text}");
        }
    }
}

/// A trim report reads as docs/cli.md shows it after `sim-cli: palmer
/// trimmed: `: each triple as its name and its value to four decimals, then
/// a space and the unit when there is one, the triples separated by `", "`
/// (docs/cli.md's own example, and a Bourg report whose last value has no
/// unit).
#[test]
fn a_trim_report_reads_as_the_cli_prints_it() {
    let palmer = TrimReport {
        values: [
            ("throttle", 0.6197, ""),
            ("alpha", 2.9679, "deg"),
            ("flaps", 0.0, "deg"),
        ],
    };
    assert_eq!(
        palmer.to_string(),
        "throttle 0.6197, alpha 2.9679 deg, flaps 0.0000 deg"
    );
    let bourg = TrimReport {
        values: [
            ("thrust", 1234.5, "lb"),
            ("pitch", -1.25, "deg"),
            ("elevator trim", 0.125, ""),
        ],
    };
    assert_eq!(
        bourg.to_string(),
        "thrust 1234.5000 lb, pitch -1.2500 deg, elevator trim 0.1250"
    );
}

/// `InitialConditions::velocity_nwu_mps`, as documented: `(V cos h, 0 − V sin
/// h, 0)`, exactly zero with no `−0.0` at zero speed or heading 0 (compared
/// bit for bit: a `−0.0` would be equal as a number). The other quarter
/// headings within 1e-12 m/s (the `f64` cosine of 90° is 6e-17, not 0).
#[test]
fn the_initial_velocity_is_north_west_up_with_no_negative_zeros() {
    let bits = |v: [f64; 3]| v.map(f64::to_bits);
    let zero = bits([0.0; 3]);
    let still = InitialConditions {
        altitude_m: 100.0,
        speed_mps: 0.0,
        heading_deg: 123.0,
    };
    assert_eq!(bits(still.velocity_nwu_mps()), zero);
    let north = InitialConditions {
        speed_mps: 50.0,
        heading_deg: 0.0,
        ..still
    };
    assert_eq!(bits(north.velocity_nwu_mps()), bits([50.0, 0.0, 0.0]));
    for (heading, want) in [
        (90.0, [0.0, -50.0]),
        (180.0, [-50.0, 0.0]),
        (270.0, [0.0, 50.0]),
    ] {
        let v = InitialConditions {
            heading_deg: heading,
            ..north
        }
        .velocity_nwu_mps();
        assert!(
            (v[0] - want[0]).abs() < 1e-12 && (v[1] - want[1]).abs() < 1e-12 && v[2] == 0.0,
            "{heading}: {v:?}"
        );
    }
}

/// Palmer's trim returns only level flight (lift = weight: its doc's first
/// condition, found by bisection on the angle of attack between −16° and the
/// stall angle). An aircraft whose wing still lifts more than its weight at
/// −16° at the speed asked (here a lift coefficient of 3 at zero alpha, 1.4
/// at −16°) has no level attitude in that range, so the speed is refused as
/// too fast, even with power to spare (a hundred times the Cessna's); the
/// same aircraft trims level at a lower speed.
#[test]
fn palmers_trim_refuses_a_speed_where_even_the_lowest_angle_lifts_too_much() {
    let cessna = Palmer::default_aircraft();
    let floaty = fdm_core::palmer::PalmerAircraft {
        cl0: 3.0,
        engine_power_w: cessna.engine_power_w * 100.0,
        ..cessna
    };
    assert!(floaty.validate().is_ok());
    let c = Palmer::initial_controls();
    let fast = InitialConditions::from_feet_knots(2000.0, 150.0, 0.0);
    assert!(matches!(
        Palmer::trim(&floaty, &c, &fast),
        Err(StartError::AboveMaxPower { .. })
    ));
    let slow = InitialConditions::from_feet_knots(2000.0, 40.0, 0.0);
    let trimmed = Palmer::trim(&floaty, &c, &slow).unwrap();
    let az = fdm_core::palmer::derivatives(&floaty, &trimmed.controls, &trimmed.state)
        .acceleration_mps2
        .z;
    assert!(az.abs() < 1e-6, "{az} m/s² at {:?}", trimmed.controls);
}

/// Palmer's trim bisects the angle of attack down to the spacing of `f64`
/// (60 halvings of 36°, `trim`'s `BISECTIONS`) and, as its doc says, returns
/// the `f64` angle nearest level flight: no neighbouring angle has a smaller
/// vertical acceleration, and where several angles side by side give
/// exactly zero, the lowest of them. Checked at 2000 ft for every knot from
/// 55 to 120 (the measured trim range is about 53 to 125 kt, docs/cli.md).
/// Exact comparisons: the property is about which `f64` is returned.
#[test]
fn palmers_trimmed_angle_of_attack_is_the_nearest_f64_to_level_flight() {
    use fdm_core::palmer::{derivatives, PalmerControls};
    let a = Palmer::default_aircraft();
    for kt in 55..=120 {
        let ic = InitialConditions::from_feet_knots(2000.0, f64::from(kt), 0.0);
        let t = Palmer::trim(&a, &Palmer::initial_controls(), &ic).unwrap();
        let az = |alpha_deg: f64| {
            let c = PalmerControls {
                alpha_deg,
                ..t.controls
            };
            derivatives(&a, &c, &t.state).acceleration_mps2.z.abs()
        };
        let alpha = t.controls.alpha_deg;
        let bits = alpha.to_bits();
        let (here, up, down) = (
            az(alpha),
            az(f64::from_bits(bits + 1)),
            az(f64::from_bits(bits - 1)),
        );
        assert!(
            here <= up && here <= down,
            "{kt} kt: |az| {here:e} at {alpha}, {up:e} and {down:e} beside it"
        );
        // Exactly level at two or more neighbouring angles (at 34 of these
        // speeds): the lowest of them.
        assert!(here > 0.0 || down > 0.0, "{kt} kt: level below {alpha} too");
    }
}

/// Palmer's trim at any heading and speed of its range: its doc's two
/// conditions of level flight, the vertical acceleration zero and the
/// horizontal one (along the velocity, "whatever the heading") zero, at the
/// controls it returns, with the same throttle as flying north (the model
/// has no wind and no direction). Within 1e-9 m/s²: the throttle is one division of two
/// accelerations of about 1 m/s² (a rounding of 1e-16), and the headings'
/// sines and cosines add a few more.
#[test]
fn palmers_trim_balances_thrust_and_drag_at_any_heading() {
    use fdm_core::palmer::derivatives;
    let a = Palmer::default_aircraft();
    for (kt, heading) in [
        (55.0, 0.0),
        (60.0, 30.0),
        (70.0, 45.0),
        (90.0, 90.0),
        (100.0, 135.0),
        (110.0, 225.0),
        (120.0, 300.0),
    ] {
        let north = Palmer::trim(
            &a,
            &Palmer::initial_controls(),
            &InitialConditions::from_feet_knots(2000.0, kt, 0.0),
        )
        .unwrap();
        let ic = InitialConditions::from_feet_knots(2000.0, kt, heading);
        let t = Palmer::trim(&a, &Palmer::initial_controls(), &ic).unwrap();
        let acc = derivatives(&a, &t.controls, &t.state).acceleration_mps2;
        let v = t.state.velocity_mps;
        let along = (acc.x * v.x + acc.y * v.y) / ic.speed_mps;
        assert!(
            along.abs() < 1e-9 && acc.z.abs() < 1e-9,
            "{kt} kt, heading {heading}: {acc:?}"
        );
        assert!(
            (t.controls.throttle - north.controls.throttle).abs() < 1e-9,
            "{kt} kt, heading {heading}: {:?}",
            t.controls
        );
    }
}
