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
use fdm_core::start::{InitialConditions, StartError};
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
