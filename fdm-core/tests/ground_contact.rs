//! Ground contact and flight status through the model interface
//! (`fdm_core::model::{fly, advance, settle}`), for both models:
//!
//! * every reference case of both models, flown through [`fly`], is bit for
//!   bit the model's own step at every frame (so the reference tests, which
//!   check the bare step against the original programs, hold for `fly` too);
//! * an aircraft never goes below the ground plane; a crash stays at rest; a
//!   landing rolls out and can take off again; a divergence keeps the last
//!   finite state.
//!
//! Tolerances: none. Every comparison is exact (bits, or `>= 0.0`), because the
//! ground contact is an exact clamp applied after the model's step.

use fdm_core::bourg::{Bourg, BourgAction, BourgControls, BourgState};
use fdm_core::model::{fly, FlightStatus, LandingState, Model};
use fdm_core::palmer::{Flaps, Palmer, PalmerAction, PalmerControls, PalmerState};
use fdm_core::script::Script;
use nalgebra::Vector3;
use serde_json::Value;

fn palmer_bits(s: &PalmerState) -> [u64; 7] {
    [
        s.time_s.to_bits(),
        s.position_m.x.to_bits(),
        s.position_m.y.to_bits(),
        s.position_m.z.to_bits(),
        s.velocity_mps.x.to_bits(),
        s.velocity_mps.y.to_bits(),
        s.velocity_mps.z.to_bits(),
    ]
}

fn bourg_bits(s: &BourgState) -> Vec<u64> {
    let mut out = vec![s.time_s.to_bits(), u64::from(s.stalling)];
    for v in [
        s.position_ft,
        s.velocity_ftps,
        s.velocity_body_ftps,
        s.angular_velocity_radps,
    ] {
        out.extend(v.iter().map(|x| u64::from(x.to_bits())));
    }
    out.extend(s.orientation.coords.iter().map(|x| u64::from(x.to_bits())));
    out
}

fn reference(name: &str) -> Value {
    let text = fdm_tests::read_reference(name).expect("reference file");
    serde_json::from_str(&text).expect("reference parses")
}

#[test]
fn palmer_reference_cases_through_fly_are_the_bare_step_bit_for_bit() {
    let doc = reference("palmer.json");
    let frames = doc["frames"].as_u64().expect("frames");
    let dt = doc["dt"].as_f64().expect("dt");
    let aircraft = Palmer::default_aircraft();
    let cases = doc["cases"].as_array().expect("cases");
    assert_eq!(cases.len(), 4);
    for case in cases {
        let c = &case["controls"];
        let controls = PalmerControls {
            throttle: c["throttle"].as_f64().unwrap(),
            alpha_deg: c["alpha"].as_f64().unwrap(),
            bank_deg: c["bank"].as_f64().unwrap(),
            flaps: Flaps::try_from(u8::try_from(c["flaps"].as_u64().unwrap()).unwrap()).unwrap(),
            brakes: false,
        };
        let (mut bare, mut flown) = (Palmer::initial_state(), Palmer::initial_state());
        let mut status = FlightStatus::initial(0.0);
        for frame in 1..=frames {
            bare = Palmer::step(&aircraft, &controls, &bare, dt);
            (flown, status) = fly::<Palmer>(&aircraft, &controls, status, &flown, dt);
            assert_eq!(
                palmer_bits(&flown),
                palmer_bits(&bare),
                "{} frame {frame}",
                case["name"]
            );
        }
        // The ground roll from rest, then the climb.
        assert_eq!(status, FlightStatus::Airborne, "{}", case["name"]);
    }
}

#[test]
fn bourg_reference_cases_through_fly_are_the_bare_step_bit_for_bit() {
    let doc = reference("bourg.json");
    let frames = doc["frames"].as_u64().expect("frames");
    let aircraft = Bourg::default_aircraft();
    let dt = Bourg::time_step(30.0);
    let cases = doc["cases"].as_array().expect("cases");
    assert_eq!(cases.len(), 5);
    for case in cases {
        let lines: Vec<&str> = case["script"]
            .as_array()
            .unwrap()
            .iter()
            .map(|l| l.as_str().unwrap())
            .collect();
        let script = Script::<BourgAction>::parse(&lines.join("\n")).unwrap();
        let mut controls = BourgControls::initial();
        let (mut bare, mut flown) = (Bourg::initial_state(), Bourg::initial_state());
        let mut status = FlightStatus::initial(Bourg::height_m(&flown));
        for frame in 1..=frames {
            controls = Bourg::begin_frame(controls);
            for action in script.actions_at(frame) {
                controls = Bourg::apply(&aircraft, controls, action);
            }
            bare = Bourg::step(&aircraft, &controls, &bare, dt);
            (flown, status) = fly::<Bourg>(&aircraft, &controls, status, &flown, dt);
            assert_eq!(
                bourg_bits(&flown),
                bourg_bits(&bare),
                "{} frame {frame}",
                case["name"]
            );
        }
        assert_eq!(status, FlightStatus::Airborne, "{}", case["name"]);
    }
}

fn palmer_at(z: f64, vx: f64, vz: f64) -> PalmerState {
    PalmerState {
        position_m: Vector3::new(0.0, 0.0, z),
        velocity_mps: Vector3::new(vx, 0.0, vz),
        ..PalmerState::at_rest()
    }
}

#[test]
fn palmer_crash_stays_on_the_ground_at_rest() {
    let aircraft = Palmer::default_aircraft();
    // Idle, nose level, 30 m up at 45 m/s: it comes down hard.
    let mut controls = PalmerControls::default();
    let mut state = palmer_at(30.0, 45.0, 0.0);
    let mut status = FlightStatus::initial(30.0);
    let mut crashed_at = None;
    for frame in 0..3000 {
        if frame == 500 {
            // Full power after the crash changes nothing.
            controls = controls.apply(PalmerAction::ThrottleUp);
            controls.throttle = 1.0;
        }
        (state, status) = fly::<Palmer>(&aircraft, &controls, status, &state, 0.1);
        assert!(state.position_m.z >= 0.0, "frame {frame}: {state:?}");
        if status == FlightStatus::Landed(LandingState::Crash) && crashed_at.is_none() {
            crashed_at = Some(state.position_m);
        }
    }
    assert_eq!(status, FlightStatus::Landed(LandingState::Crash));
    assert_eq!(Some(state.position_m), crashed_at);
    assert_eq!(state.velocity_mps, Vector3::zeros());
    assert_eq!(state.position_m.z, 0.0);
    // The clock goes on.
    assert!((state.time_s - 300.0).abs() < 1e-9, "{}", state.time_s);
}

#[test]
fn palmer_lands_rolls_out_and_takes_off_again() {
    let aircraft = Palmer::default_aircraft();
    // A shallow approach at 30 % power, 4° angle of attack.
    let approach = PalmerControls {
        throttle: 0.3,
        alpha_deg: 4.0,
        bank_deg: 0.0,
        flaps: Flaps::Up,
        brakes: false,
    };
    let mut state = palmer_at(30.0, 45.0, 0.0);
    let mut status = FlightStatus::initial(30.0);
    let mut landed = None;
    for frame in 0..1200 {
        (state, status) = fly::<Palmer>(&aircraft, &approach, status, &state, 0.1);
        assert!(state.position_m.z >= 0.0, "frame {frame}");
        if let FlightStatus::Landed(how) = status {
            landed.get_or_insert(how);
        }
    }
    assert_eq!(landed, Some(LandingState::Safe));
    assert_eq!(status, FlightStatus::Landed(LandingState::Safe));
    // Rolling on the runway, not floating above it, and not stopped.
    assert_eq!(state.position_m.z, 0.0);
    assert_eq!(state.velocity_mps.z, 0.0);
    assert!(state.velocity_mps.x > 10.0, "{state:?}");
    // Full power, 10°: airborne again.
    let takeoff = PalmerControls {
        throttle: 1.0,
        alpha_deg: 10.0,
        ..approach
    };
    for _ in 0..600 {
        (state, status) = fly::<Palmer>(&aircraft, &takeoff, status, &state, 0.1);
    }
    assert_eq!(status, FlightStatus::Airborne);
    assert!(state.position_m.z > 50.0, "{state:?}");
}

#[test]
fn bourg_without_input_comes_down_and_stays_down() {
    let aircraft = Bourg::default_aircraft();
    let controls = Bourg::initial_controls();
    let mut state = Bourg::initial_state();
    let mut status = FlightStatus::initial(Bourg::height_m(&state));
    let dt = Bourg::time_step(30.0);
    for frame in 0..(30 * 3600) {
        (state, status) = fly::<Bourg>(&aircraft, &controls, status, &state, dt);
        assert!(state.position_ft.z >= 0.0, "frame {frame}: {state:?}");
        assert!(state.is_finite(), "frame {frame}");
    }
    assert_eq!(status, FlightStatus::Landed(LandingState::Crash));
    assert_eq!(state.velocity_ftps, Vector3::zeros());
    assert_eq!(state.position_ft.z, 0.0);
}

#[test]
fn bourg_on_the_ground_holds_and_can_leave_it() {
    let aircraft = Bourg::default_aircraft();
    // On the plane, wings level, 160 ft/s north, full thrust, flaps down.
    let mut controls = Bourg::initial_controls();
    controls.thrust_lb = 3000.0;
    controls.landing_flaps = true;
    let mut state = Bourg::initial_state();
    state.position_ft.z = 0.0;
    state.velocity_ftps = Vector3::new(160.0, 0.0, 0.0);
    state.velocity_body_ftps = state.velocity_ftps;
    let mut status = FlightStatus::initial(0.0);
    let dt = Bourg::time_step(30.0);
    let mut highest = 0.0_f32;
    for _ in 0..300 {
        (state, status) = fly::<Bourg>(&aircraft, &controls, status, &state, dt);
        assert!(state.position_ft.z >= 0.0);
        highest = highest.max(state.position_ft.z);
    }
    assert!(highest > 0.0, "never left the ground: {state:?}");
}

#[test]
fn a_diverging_step_keeps_the_last_finite_state() {
    let aircraft = Palmer::default_aircraft();
    let controls = PalmerControls::default();
    // Huge but finite: the step overflows.
    let state = PalmerState {
        velocity_mps: Vector3::new(1e200, 0.0, 0.0),
        ..palmer_at(100.0, 0.0, 0.0)
    };
    let (next, status) = fly::<Palmer>(&aircraft, &controls, FlightStatus::Airborne, &state, 0.1);
    assert_eq!(status, FlightStatus::Diverged);
    assert_eq!(palmer_bits(&next), palmer_bits(&state));
    // Final: not stepped any more.
    let (again, status) = fly::<Palmer>(&aircraft, &controls, status, &next, 0.1);
    assert_eq!(
        (palmer_bits(&again), status),
        (palmer_bits(&state), FlightStatus::Diverged)
    );
}

#[test]
fn touchdown_classes_follow_the_documented_thresholds() {
    let aircraft = Palmer::default_aircraft();
    let controls = PalmerControls::default();
    for (vz, want) in [
        (-1.0, LandingState::Safe),
        (-3.0, LandingState::Rough),
        (-7.0, LandingState::Crash),
    ] {
        // Just above the plane, sinking at `vz`: the next step ends below it.
        let state = palmer_at(0.01, 40.0, vz);
        let (next, status) =
            fly::<Palmer>(&aircraft, &controls, FlightStatus::Airborne, &state, 0.1);
        let FlightStatus::Landed(how) = status else {
            panic!("{vz}: {status:?}")
        };
        assert_eq!(how, want, "vz {vz}");
        assert_eq!(next.position_m.z, 0.0);
        assert!(next.velocity_mps.z >= 0.0);
        assert_eq!(next.velocity_mps.x == 0.0, want == LandingState::Crash);
    }
}

#[test]
fn palmer_bare_step_flies_through_the_ground_and_comes_back_up_where_fly_crashes() {
    // The crash above (idle, nose level, 30 m up at 45 m/s) through the bare
    // step: the original model has no ground, so it sinks through z = 0 and,
    // as it gains speed below, its lift brings it back above the plane, where
    // `fly` has it crash and stay put (docs/palmer-model.md).
    let aircraft = Palmer::default_aircraft();
    let controls = PalmerControls::default();
    let mut bare = palmer_at(30.0, 45.0, 0.0);
    let (mut below_at, mut lowest_m, mut back_at) = (None, 0.0_f64, None);
    for _ in 0..600 {
        bare = Palmer::step(&aircraft, &controls, &bare, 0.1);
        let z = bare.position_m.z;
        if z < 0.0 {
            below_at.get_or_insert(bare.time_s);
            lowest_m = lowest_m.min(z);
        } else if below_at.is_some() && back_at.is_none() {
            back_at = Some(bare.time_s);
        }
    }
    let (below_at, back_at) = (below_at.expect("through z = 0"), back_at.expect("back up"));
    println!(
        "bare step: below z = 0 at {below_at} s, {lowest_m} m deep, back above at {back_at} s"
    );
    assert!(lowest_m < -1.0, "{lowest_m}");
    assert!(back_at > below_at);
    let mut flown = palmer_at(30.0, 45.0, 0.0);
    let mut status = FlightStatus::initial(30.0);
    for _ in 0..600 {
        (flown, status) = fly::<Palmer>(&aircraft, &controls, status, &flown, 0.1);
        assert!(flown.position_m.z >= 0.0);
    }
    assert_eq!(status, FlightStatus::Landed(LandingState::Crash));
    assert_eq!(flown.position_m.z, 0.0);
}
