//! Property tests of the Palmer model: finite results in the flight envelope,
//! rest stays rest without throttle, non-finite input never panics and is
//! rejected by `try_step`, and key presses keep the controls in range.
//!
//! Case counts are kept small so the suite runs in seconds in debug builds.

use fdm_core::palmer::{
    step, try_step, Flaps, PalmerAction, PalmerAircraft, PalmerControls, PalmerState, StepError,
};
use proptest::prelude::*;

const CESSNA: PalmerAircraft = PalmerAircraft::cessna_172();

fn flaps() -> impl Strategy<Value = Flaps> {
    prop_oneof![Just(Flaps::Up), Just(Flaps::Deg20), Just(Flaps::Deg40)]
}

/// Controls anywhere in the ranges the keys allow.
fn controls() -> impl Strategy<Value = PalmerControls> {
    // Exactly the clamp limits (and Palmer's 16° lift-curve break) as
    // often as any value inside them.
    (
        prop_oneof![Just(0.0), Just(1.0), 0.0..=1.0_f64],
        prop_oneof![Just(-16.0), Just(16.0), Just(20.0), -16.0..=20.0_f64],
        prop_oneof![Just(-20.0), Just(20.0), -20.0..=20.0_f64],
        flaps(),
    )
        .prop_map(|(throttle, alpha_deg, bank_deg, flaps)| PalmerControls {
            throttle,
            alpha_deg,
            bank_deg,
            flaps,
            brakes: false,
        })
}

/// States in the flight envelope: |v| < 100 m/s (each component below
/// 100/sqrt(3)), 0 <= z < 5000 m, anywhere within 100 km horizontally.
fn envelope_state() -> impl Strategy<Value = PalmerState> {
    let v = -57.7..57.7_f64;
    (
        0.0..10_000.0_f64,
        (-1e5..1e5_f64, -1e5..1e5_f64, 0.0..5000.0_f64),
        (v.clone(), v.clone(), v),
    )
        .prop_map(|(time_s, (x, y, z), (vx, vy, vz))| PalmerState {
            time_s,
            position_m: [x, y, z].into(),
            velocity_mps: [vx, vy, vz].into(),
        })
}

/// Time steps in (0, 1] s.
fn dt() -> impl Strategy<Value = f64> {
    prop_oneof![1e-6..=1.0_f64, Just(1.0)]
}

fn non_finite() -> impl Strategy<Value = f64> {
    prop_oneof![Just(f64::NAN), Just(f64::INFINITY), Just(f64::NEG_INFINITY)]
}

fn action() -> impl Strategy<Value = PalmerAction> {
    prop_oneof![
        Just(PalmerAction::ThrottleUp),
        Just(PalmerAction::ThrottleDown),
        Just(PalmerAction::AlphaUp),
        Just(PalmerAction::AlphaDown),
        Just(PalmerAction::BankRight),
        Just(PalmerAction::BankLeft),
        Just(PalmerAction::FlapsDown),
        Just(PalmerAction::FlapsUp),
    ]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(128))]

    #[test]
    fn envelope_steps_are_finite(
        controls in controls(),
        state in envelope_state(),
        dt in dt(),
    ) {
        let next = step(&CESSNA, &controls, &state, dt);
        prop_assert!(next.is_finite(), "{next:?}");
        prop_assert!(next.time_s > state.time_s);
        // The checked step accepts it and returns the very same bits.
        prop_assert_eq!(try_step(&CESSNA, &controls, &state, dt), Ok(next));
        let data = next.flight_data();
        prop_assert!(data.airspeed_mps.is_finite() && data.airspeed_mps >= 0.0);
        prop_assert!((0.0..360.0).contains(&data.heading_deg));
        prop_assert!((0.0..360.0).contains(&data.compass_heading_deg));
        prop_assert!((-90.0..=90.0).contains(&data.climb_angle_deg));
    }

    #[test]
    fn envelope_stays_finite_over_many_steps(
        controls in controls(),
        state in envelope_state(),
        dt in 0.01..=0.1_f64,
    ) {
        let mut s = state;
        for _ in 0..100 {
            s = step(&CESSNA, &controls, &s, dt);
            prop_assert!(s.is_finite(), "{s:?}");
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]

    #[test]
    fn without_throttle_rest_stays_rest(
        alpha_deg in -16.0..=20.0_f64,
        bank_deg in -20.0..=20.0_f64,
        flaps in flaps(),
        dt in dt(),
    ) {
        let controls = PalmerControls { throttle: 0.0, alpha_deg, bank_deg, flaps, brakes: false  };
        let mut s = PalmerState::at_rest();
        for _ in 0..300 {
            s = step(&CESSNA, &controls, &s, dt);
            prop_assert!(s.position_m.z >= 0.0, "{s:?}");
            prop_assert!(s.position_m.iter().all(|&p| p == 0.0), "{s:?}");
            prop_assert!(s.velocity_mps.iter().all(|&v| v == 0.0), "{s:?}");
        }
        prop_assert!(s.time_s > 0.0);
    }

    #[test]
    fn non_finite_state_never_panics_and_is_rejected(
        controls in controls(),
        state in envelope_state(),
        dt in dt(),
        field in 0..7_usize,
        bad in non_finite(),
    ) {
        let mut s = state;
        match field {
            0 => s.time_s = bad,
            1..=3 => s.position_m[field - 1] = bad,
            _ => s.velocity_mps[field - 4] = bad,
        }
        // Unchecked: no panic, and the non-finite value shows in the result.
        let next = step(&CESSNA, &controls, &s, dt);
        prop_assert!(!next.is_finite(), "{next:?}");
        prop_assert_eq!(try_step(&CESSNA, &controls, &s, dt), Err(StepError::NonFiniteState));
    }

    #[test]
    fn non_finite_controls_never_panic_and_are_rejected(
        controls in controls(),
        state in envelope_state(),
        dt in dt(),
        field in 0..3_usize,
        bad in non_finite(),
    ) {
        let mut c = controls;
        match field {
            0 => c.throttle = bad,
            1 => c.alpha_deg = bad,
            _ => c.bank_deg = bad,
        }
        let _unchecked = step(&CESSNA, &c, &state, dt);
        prop_assert_eq!(try_step(&CESSNA, &c, &state, dt), Err(StepError::NonFiniteControls));
    }

    #[test]
    fn bad_time_steps_never_panic_and_are_rejected(
        controls in controls(),
        state in envelope_state(),
        dt in prop_oneof![non_finite(), Just(0.0), Just(-0.0), -10.0..0.0_f64],
    ) {
        let _unchecked = step(&CESSNA, &controls, &state, dt);
        let err = try_step(&CESSNA, &controls, &state, dt).unwrap_err();
        prop_assert!(matches!(err, StepError::InvalidTimeStep { .. }), "{err}");
    }

    #[test]
    fn key_presses_keep_controls_in_range(
        start in controls(),
        actions in proptest::collection::vec(action(), 0..80),
    ) {
        let mut c = start;
        for a in actions {
            c = c.apply(a);
            prop_assert!((0.0..=1.0).contains(&c.throttle), "{c:?}");
            prop_assert!((-16.0..=20.0).contains(&c.alpha_deg), "{c:?}");
            prop_assert!((-20.0..=20.0).contains(&c.bank_deg), "{c:?}");
        }
    }

    #[test]
    fn throttle_from_zero_is_always_an_exact_notch(
        actions in proptest::collection::vec(
            prop_oneof![Just(PalmerAction::ThrottleUp), Just(PalmerAction::ThrottleDown)],
            0..60,
        ),
    ) {
        let mut c = PalmerControls::default();
        let mut notch: i32 = 0;
        for a in actions {
            c = c.apply(a);
            notch = if a == PalmerAction::ThrottleUp { notch + 1 } else { notch - 1 }.clamp(0, 20);
            prop_assert_eq!(c.throttle, f64::from(notch) / 20.0);
        }
    }
}

/// At exactly each clamp limit a further press keeps exactly the limit, and
/// one press back moves exactly one step away from it.
#[test]
fn presses_at_the_limits_stay_exactly_at_the_limits() {
    use fdm_core::palmer::{ALPHA_MAX_DEG, ALPHA_MIN_DEG, BANK_LIMIT_DEG};
    type Get = fn(&PalmerControls) -> f64;
    let cases: [(PalmerControls, PalmerAction, PalmerAction, Get, f64, f64); 6] = [
        (
            PalmerControls {
                throttle: 1.0,
                ..PalmerControls::default()
            },
            PalmerAction::ThrottleUp,
            PalmerAction::ThrottleDown,
            |c| c.throttle,
            1.0,
            0.95,
        ),
        (
            PalmerControls {
                throttle: 0.0,
                ..PalmerControls::default()
            },
            PalmerAction::ThrottleDown,
            PalmerAction::ThrottleUp,
            |c| c.throttle,
            0.0,
            0.05,
        ),
        (
            PalmerControls {
                alpha_deg: ALPHA_MAX_DEG,
                ..PalmerControls::default()
            },
            PalmerAction::AlphaUp,
            PalmerAction::AlphaDown,
            |c| c.alpha_deg,
            20.0,
            19.0,
        ),
        (
            PalmerControls {
                alpha_deg: ALPHA_MIN_DEG,
                ..PalmerControls::default()
            },
            PalmerAction::AlphaDown,
            PalmerAction::AlphaUp,
            |c| c.alpha_deg,
            -16.0,
            -15.0,
        ),
        (
            PalmerControls {
                bank_deg: BANK_LIMIT_DEG,
                ..PalmerControls::default()
            },
            PalmerAction::BankRight,
            PalmerAction::BankLeft,
            |c| c.bank_deg,
            20.0,
            19.0,
        ),
        (
            PalmerControls {
                bank_deg: -BANK_LIMIT_DEG,
                ..PalmerControls::default()
            },
            PalmerAction::BankLeft,
            PalmerAction::BankRight,
            |c| c.bank_deg,
            -20.0,
            -19.0,
        ),
    ];
    for (start, further, back, get, limit, one_back) in cases {
        let pressed = start.apply(further);
        assert_eq!(get(&pressed), limit, "{start:?} + {further:?}");
        assert_eq!(
            get(&pressed.apply(back)),
            one_back,
            "{start:?} + {further:?} + {back:?}"
        );
    }
}
