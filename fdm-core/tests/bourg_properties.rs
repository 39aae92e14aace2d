//! Property tests of the `f32` Bourg model.
//!
//! * Finite in, finite out: any reasonable flying state and controls step to a
//!   finite state.
//! * The attitude quaternion stays a unit quaternion (within 1e-5) over 10 000
//!   steps (333 s) of random control sequences.
//! * Non-finite inputs never panic. What they do: `step` propagates them (a NaN
//!   or infinity in a field the dynamics read, i.e. position, velocity,
//!   velocity_body, angular_velocity, orientation, thrust or dt, gives a state
//!   with a non-finite field; `speed` and `euler_angles_deg` are outputs only and
//!   are not read), and `try_step` refuses them with a typed `StepError`.
//!
//! Case counts are kept small so the suite runs in a few seconds in debug
//! builds (a debug step takes ~10 µs).

use fdm_core::bourg::ops::{conjugate, quat_from_euler_deg, quat_magnitude, qv_rotate};
use fdm_core::bourg::{
    step, try_step, BourgAction, BourgAircraft, BourgControls, BourgState, Flap, StepError,
    Vector3, MAX_THRUST_LB,
};
use fdm_core::script::ScriptAction;
use proptest::prelude::*;

fn vec3(range: core::ops::Range<f32>) -> impl Strategy<Value = Vector3<f32>> {
    (range.clone(), range.clone(), range).prop_map(|(x, y, z)| Vector3::new(x, y, z))
}

fn flap() -> impl Strategy<Value = Flap> {
    prop::sample::select(vec![
        Flap::TrailingEdgeDown,
        Flap::Neutral,
        Flap::TrailingEdgeUp,
    ])
}

/// A flying state: any attitude, up to 300 ft/s in any direction, up to
/// 2 rad/s about each axis, velocity_body consistent with the attitude.
fn flying_state() -> impl Strategy<Value = BourgState> {
    (
        vec3(-20_000.0..20_000.0),
        vec3(-300.0..300.0),
        vec3(-2.0..2.0),
        vec3(-180.0..180.0),
        any::<bool>(),
    )
        .prop_map(|(position, velocity, angular_velocity, euler, stalling)| {
            let orientation = quat_from_euler_deg(&euler);
            BourgState {
                time_s: 0.0,
                position_ft: position,
                velocity_ftps: velocity,
                velocity_body_ftps: qv_rotate(&conjugate(&orientation), &velocity),
                angular_velocity_radps: angular_velocity,
                orientation,
                stalling,
            }
        })
}

fn controls() -> impl Strategy<Value = BourgControls> {
    (
        0.0f32..=MAX_THRUST_LB,
        prop::sample::select(vec![-16.0f32, 0.0, 16.0]),
        flap(),
        flap(),
        flap(),
        any::<bool>(),
    )
        .prop_map(
            |(thrust_lb, rudder_deg, port_aileron, starboard_aileron, elevators, landing_flaps)| {
                BourgControls {
                    thrust_lb,
                    rudder_deg,
                    port_aileron,
                    starboard_aileron,
                    elevators,
                    landing_flaps,
                    pitch_trim: 0.0,
                }
            },
        )
}

fn dt() -> impl Strategy<Value = f32> {
    prop::sample::select(vec![1.0f32 / 10.0, 1.0 / 30.0, 1.0 / 60.0, 1.0 / 100.0])
}

/// Replaces one component of a dynamic input field by `value` (`component`
/// 0..4; vectors use it modulo 3); returns the field's name.
fn poison(state: &mut BourgState, which: usize, component: usize, value: f32) -> &'static str {
    match which {
        0 => {
            state.position_ft[component % 3] = value;
            "position_ft"
        }
        1 => {
            state.velocity_ftps[component % 3] = value;
            "velocity_ftps"
        }
        2 => {
            state.velocity_body_ftps[component % 3] = value;
            "velocity_body_ftps"
        }
        3 => {
            state.angular_velocity_radps[component % 3] = value;
            "angular_velocity_radps"
        }
        _ => {
            state.orientation.coords[component] = value;
            "orientation"
        }
    }
}

fn non_finite() -> impl Strategy<Value = f32> {
    prop::sample::select(vec![f32::NAN, f32::INFINITY, f32::NEG_INFINITY])
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    #[test]
    fn finite_in_finite_out(state in flying_state(), controls in controls(), dt in dt()) {
        let aircraft = BourgAircraft::bourg_default();
        let next = step(&aircraft, &controls, &state, dt);
        prop_assert!(next.is_finite(), "{next:?}");
        // try_step agrees bit for bit when it accepts.
        let checked = try_step(&aircraft, &controls, &state, dt);
        prop_assert_eq!(checked, Ok(next));
    }

    #[test]
    fn non_finite_state_never_panics_and_propagates(
        state in flying_state(),
        controls in controls(),
        which in 0usize..5,
        component in 0usize..4,
        value in non_finite(),
    ) {
        let aircraft = BourgAircraft::bourg_default();
        let mut state = state;
        let field = poison(&mut state, which, component, value);
        let next = step(&aircraft, &controls, &state, 1.0 / 30.0);
        prop_assert!(!next.is_finite(), "{field} = {value} vanished: {next:?}");
        prop_assert_eq!(
            try_step(&aircraft, &controls, &state, 1.0 / 30.0),
            Err(StepError::NonFiniteState { field })
        );
    }

    #[test]
    fn output_only_fields_are_not_read(
        state in flying_state(),
        controls in controls(),
        time_s in -1.0e9f64..1.0e9,
    ) {
        // `stalling` is an output of the step and `time_s` only its clock: the
        // dynamics read neither.
        let aircraft = BourgAircraft::bourg_default();
        let dt = 1.0f32 / 30.0;
        let clean = step(&aircraft, &controls, &state, dt);
        let mut dirty = state;
        dirty.stalling = !state.stalling;
        dirty.time_s = time_s;
        let next = step(&aircraft, &controls, &dirty, dt);
        prop_assert_eq!(next.time_s, time_s + f64::from(dt));
        prop_assert_eq!(BourgState { time_s: clean.time_s, ..next }, clean);
    }

    #[test]
    fn non_finite_controls_and_dt_never_panic(
        state in flying_state(),
        controls in controls(),
        value in non_finite(),
        bad_dt in prop::sample::select(vec![f32::NAN, f32::INFINITY, 0.0, -1.0 / 30.0]),
    ) {
        let aircraft = BourgAircraft::bourg_default();
        let thrust = BourgControls { thrust_lb: value, ..controls };
        prop_assert!(!step(&aircraft, &thrust, &state, 1.0 / 30.0).is_finite());
        prop_assert_eq!(
            try_step(&aircraft, &thrust, &state, 1.0 / 30.0),
            Err(StepError::NonFiniteControls)
        );
        let rudder = BourgControls { rudder_deg: value, ..controls };
        let _ = step(&aircraft, &rudder, &state, 1.0 / 30.0);
        prop_assert_eq!(
            try_step(&aircraft, &rudder, &state, 1.0 / 30.0),
            Err(StepError::NonFiniteControls)
        );
        let _ = step(&aircraft, &controls, &state, bad_dt);
        prop_assert_eq!(
            try_step(&aircraft, &controls, &state, bad_dt),
            Err(StepError::InvalidTimeStep)
        );
    }
}

proptest! {
    // 10 000 debug steps take ~0.1 s; 12 sequences keep the test at a few seconds.
    #![proptest_config(ProptestConfig::with_cases(12))]

    /// Random control sequences: up to 12 segments of 1..2000 frames, each
    /// holding a random set of keys (bit i of the mask = action i, applied every
    /// frame of the segment in `BourgAction::ALL` order), repeated until 10 000
    /// frames.
    #[test]
    fn quaternion_stays_unit_over_10_000_steps(
        segments in prop::collection::vec((1u32..2000, 0u16..1024), 1..12),
    ) {
        let aircraft = BourgAircraft::bourg_default();
        let mut controls = BourgControls::initial();
        let mut state = BourgState::initial();
        let dt = 1.0f32 / 30.0;
        let mut frames = 0u32;
        let mut worst = 0.0f32;
        'outer: loop {
            for &(length, keys) in &segments {
                for _ in 0..length {
                    if frames == 10_000 {
                        break 'outer;
                    }
                    controls = controls.neutralize_surfaces();
                    for (bit, action) in BourgAction::ALL.iter().enumerate() {
                        if keys & (1 << bit) != 0 {
                            controls = controls.apply(*action);
                        }
                    }
                    state = step(&aircraft, &controls, &state, dt);
                    frames += 1;
                    prop_assert!(state.is_finite(), "frame {frames}: {state:?}");
                    let error = (quat_magnitude(&state.orientation) - 1.0).abs();
                    worst = worst.max(error);
                    prop_assert!(error <= 1e-5, "frame {frames}: |q| - 1 = {error}");
                }
            }
        }
        println!("10 000 frames: max ||q| - 1| = {worst:e}, final speed {} ft/s", state.speed_ftps());
        prop_assert_eq!(frames, 10_000);
        prop_assert!(worst <= 1e-5);
    }
}

/// Thrust stays within 0..=3000 lb whatever the key presses.
#[test]
fn thrust_is_clamped() {
    let mut controls = BourgControls::initial();
    for _ in 0..40 {
        controls = controls.apply(BourgAction::ThrustUp);
    }
    assert_eq!(controls.thrust_lb, 3000.0);
    for _ in 0..40 {
        controls = controls.apply(BourgAction::ThrustDown);
    }
    assert_eq!(controls.thrust_lb, 0.0);
}

/// Every `StepError` says what was refused in one line, naming the field
/// where it has one (the project's rule for errors: a clear message, never
/// an empty one).
#[test]
fn step_errors_are_one_line_naming_what_was_refused() {
    for (error, must_name) in [
        (
            StepError::NonFiniteState {
                field: "angular_velocity",
            },
            "angular_velocity",
        ),
        (StepError::NonFiniteControls, "control"),
        (StepError::InvalidTimeStep, "time step"),
        (
            StepError::NonFiniteResult {
                field: "velocity_body",
            },
            "velocity_body",
        ),
    ] {
        let message = error.to_string();
        assert!(
            message.contains(must_name) && message.contains("finite"),
            "{error:?}: {message:?}"
        );
        assert!(!message.contains('\n'), "{error:?}: {message:?}");
    }
}
