//! The optimised `palmer::step` against an oracle: the RK4 of docs/palmer-model.md written
//! plainly (one right-hand side per stage, the atmosphere's `pow` inside it,
//! every coefficient recomputed per stage), as the model was before its
//! per-step invariants were hoisted and its `pow` calls reordered. Every
//! result must be bit-identical, NaN for NaN, on random states on the ground,
//! in ground effect, in flight, and with non-finite inputs.
//!
//! The reference scenarios (`palmer_reference.rs`) pin the model to the
//! original C; this test pins the optimisations to the plain form on inputs
//! the scenarios never reach.

use std::f64::consts::PI;

use fdm_core::math;
use fdm_core::palmer::{step, Flaps, PalmerAircraft, PalmerControls, PalmerState};
use proptest::prelude::*;

const G: f64 = -9.81;

/// The `rhs(` of docs/palmer-model.md: `rhs(q, delta_q, ds, q_scale)`, steps 1-13, in its operation order.
fn rhs(
    a: &PalmerAircraft,
    c: &PalmerControls,
    q: &[f64; 6],
    dq: &[f64; 6],
    ds: f64,
    s: f64,
) -> [f64; 6] {
    let new_q: [f64; 6] = std::array::from_fn(|i| q[i] + s * dq[i]);
    let (vx, vy, vz, z) = (new_q[0], new_q[2], new_q[4], new_q[5]);
    let bank = c.bank_deg * PI / 180.0;
    let vh = (vx * vx + vy * vy).sqrt();
    let vtotal = (vx * vx + vy * vy + vz * vz).sqrt();
    let temperature = 288.15 - 0.0065 * z;
    let grp = 1.0 - 0.0065 * z / 288.15;
    let pressure = 101_325.0 * math::pow(grp, 5.25);
    let density = 0.00348 * pressure / temperature;
    let omega = density / 1.225;
    let factor = (omega - 0.12) / 0.88;
    let advance_ratio = vtotal / (a.engine_rps * a.prop_diameter_m);
    let thrust = c.throttle
        * factor
        * a.engine_power_w
        * (a.prop_a + a.prop_b * advance_ratio * advance_ratio)
        / (a.engine_rps * a.prop_diameter_m);
    let mut cl = if c.alpha_deg < a.alpha_cl_max_deg {
        a.cl_slope0_per_deg * c.alpha_deg + a.cl0
    } else {
        a.cl_slope1_per_deg * c.alpha_deg + a.cl1
    };
    match c.flaps {
        Flaps::Up => {}
        Flaps::Deg20 => cl += 0.25,
        Flaps::Deg40 => cl += 0.5,
    }
    if z < 5.0 {
        cl += 0.25;
    }
    let lift = 0.5 * cl * density * vtotal * vtotal * a.wing_area_m2;
    let aspect_ratio = a.wing_span_m * a.wing_span_m / a.wing_area_m2;
    let cd = a.cdp + cl * cl / (PI * aspect_ratio * a.eff);
    let drag = 0.5 * cd * density * vtotal * vtotal * a.wing_area_m2;
    let (cos_w, sin_w) = (math::cos(bank), math::sin(bank));
    let (cos_p, sin_p) = if vtotal == 0.0 {
        (1.0, 0.0)
    } else {
        (vh / vtotal, vz / vtotal)
    };
    let (cos_t, sin_t) = if vh == 0.0 {
        (1.0, 0.0)
    } else {
        (vx / vh, vy / vh)
    };
    let fx = cos_t * cos_p * (thrust - drag) + (sin_t * sin_w - cos_t * sin_p * cos_w) * lift;
    let fy = sin_t * cos_p * (thrust - drag) + (-cos_t * sin_w - sin_t * sin_p * cos_w) * lift;
    let mut fz = sin_p * (thrust - drag) + cos_p * cos_w * lift;
    fz += a.mass_kg * G;
    if z <= 0.0 && fz <= 0.0 {
        fz = 0.0;
    }
    let m = a.mass_kg;
    [
        ds * (fx / m),
        ds * vx,
        ds * (fy / m),
        ds * vy,
        ds * (fz / m),
        ds * vz,
    ]
}

fn oracle_step(a: &PalmerAircraft, c: &PalmerControls, st: &PalmerState, ds: f64) -> PalmerState {
    let (p, v) = (&st.position_m, &st.velocity_mps);
    let q = [v.x, p.x, v.y, p.y, v.z, p.z];
    let dq1 = rhs(a, c, &q, &q, ds, 0.0);
    let dq2 = rhs(a, c, &q, &dq1, ds, 0.5);
    let dq3 = rhs(a, c, &q, &dq2, ds, 0.5);
    let dq4 = rhs(a, c, &q, &dq3, ds, 1.0);
    let n: [f64; 6] =
        std::array::from_fn(|j| q[j] + (dq1[j] + 2.0 * dq2[j] + 2.0 * dq3[j] + dq4[j]) / 6.0);
    PalmerState {
        time_s: st.time_s + ds,
        position_m: [n[1], n[3], n[5]].into(),
        velocity_mps: [n[0], n[2], n[4]].into(),
    }
}

fn bits(s: &PalmerState) -> [u64; 7] {
    let (p, v) = (&s.position_m, &s.velocity_mps);
    [s.time_s, p.x, p.y, p.z, v.x, v.y, v.z].map(f64::to_bits)
}

/// Equal bits, or both NaN in the same places (NaN payloads may differ).
fn same(a: &PalmerState, b: &PalmerState) -> bool {
    let (x, y) = (bits(a), bits(b));
    x.iter()
        .zip(&y)
        .all(|(&p, &q)| p == q || (f64::from_bits(p).is_nan() && f64::from_bits(q).is_nan()))
}

fn flaps() -> impl Strategy<Value = Flaps> {
    prop_oneof![Just(Flaps::Up), Just(Flaps::Deg20), Just(Flaps::Deg40)]
}

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

/// Altitudes on the ground, around the 5 m ground-effect edge, and in flight.
fn altitude() -> impl Strategy<Value = f64> {
    prop_oneof![
        Just(0.0),
        -1.0..0.0_f64,
        0.0..10.0_f64,
        4.99..5.01_f64,
        // Exactly the ground-effect edge (`z < 5.0`: no ground effect at
        // 5.0 itself) and the double just below it; with vz = 0 every RK4
        // stage is at that height too.
        Just(5.0),
        Just(f64::from_bits(5.0_f64.to_bits() - 1)),
        0.0..8000.0_f64
    ]
}

fn state() -> impl Strategy<Value = PalmerState> {
    let v = prop_oneof![Just(0.0), -80.0..80.0_f64];
    (
        0.0..1e4_f64,
        -1e5..1e5_f64,
        -1e5..1e5_f64,
        altitude(),
        v.clone(),
        v.clone(),
        v,
    )
        .prop_map(|(t, x, y, z, vx, vy, vz)| PalmerState {
            time_s: t,
            position_m: [x, y, z].into(),
            velocity_mps: [vx, vy, vz].into(),
        })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(2000))]

    #[test]
    fn step_is_the_plain_rk4_bit_for_bit(c in controls(), s in state(), dt in prop_oneof![Just(1.0 / 30.0), 1e-4..1.0_f64]) {
        let cessna = PalmerAircraft::cessna_172();
        let (mut a, mut b) = (s, s);
        for _ in 0..5 {
            a = step(&cessna, &c, &a, dt);
            b = oracle_step(&cessna, &c, &b, dt);
            prop_assert!(same(&a, &b), "{a:?} != {b:?}");
        }
    }

    #[test]
    fn non_finite_inputs_propagate_alike(
        c in controls(), s in state(), field in 0..10_usize,
        bad in prop_oneof![Just(f64::NAN), Just(f64::INFINITY), Just(f64::NEG_INFINITY)],
    ) {
        let (mut c, mut s) = (c, s);
        match field {
            0 => s.position_m.x = bad,
            1 => s.position_m.y = bad,
            2 => s.position_m.z = bad,
            3 => s.velocity_mps.x = bad,
            4 => s.velocity_mps.y = bad,
            5 => s.velocity_mps.z = bad,
            6 => s.time_s = bad,
            7 => c.throttle = bad,
            8 => c.alpha_deg = bad,
            _ => c.bank_deg = bad,
        }
        let cessna = PalmerAircraft::cessna_172();
        let (a, b) = (step(&cessna, &c, &s, 0.1), oracle_step(&cessna, &c, &s, 0.1));
        prop_assert!(same(&a, &b), "{a:?} != {b:?}");
    }
}

#[test]
fn long_flights_match() {
    let cessna = PalmerAircraft::cessna_172();
    let c = PalmerControls {
        throttle: 1.0,
        alpha_deg: 4.0,
        bank_deg: 3.0,
        flaps: Flaps::Deg20,
        brakes: false,
    };
    let (mut a, mut b) = (PalmerState::at_rest(), PalmerState::at_rest());
    for _ in 0..20_000 {
        a = step(&cessna, &c, &a, 1.0 / 30.0);
        b = oracle_step(&cessna, &c, &b, 1.0 / 30.0);
        assert!(same(&a, &b), "{a:?} != {b:?}");
    }
    assert!(a.position_m.z > 100.0);
}

/// The ground-effect edge exactly: at z = 5.0 with no vertical speed (every
/// RK4 stage at 5.0) the step is the oracle's (`z < 5.0`: no ground effect at
/// 5.0), one ulp below too; and the right-hand side itself (no stages) has
/// ground effect (+0.25 on CL: more lift, more upward acceleration) one ulp
/// below 5 m and none at 5 m, where it equals the value at 6 m.
#[test]
fn ground_effect_starts_strictly_below_five_metres() {
    use fdm_core::palmer::derivatives;
    let cessna = PalmerAircraft::cessna_172();
    let c = PalmerControls {
        throttle: 1.0,
        alpha_deg: 4.0,
        bank_deg: 0.0,
        flaps: Flaps::Up,
        brakes: false,
    };
    let at = |z: f64| PalmerState {
        time_s: 0.0,
        position_m: [0.0, 0.0, z].into(),
        velocity_mps: [40.0, 0.0, 0.0].into(),
    };
    let below = f64::from_bits(5.0_f64.to_bits() - 1);
    for z in [5.0, below] {
        let (a, b) = (
            step(&cessna, &c, &at(z), 0.01),
            oracle_step(&cessna, &c, &at(z), 0.01),
        );
        assert!(same(&a, &b), "z = {z}: {a:?} != {b:?}");
    }
    let az = |z: f64| derivatives(&cessna, &c, &at(z)).acceleration_mps2.z;
    // Air density differs by ~1e-7 relative between 5 and 6 m; the ground
    // effect changes the lift by ~50 %.
    assert!(
        (az(5.0) - az(6.0)).abs() < 1e-3,
        "{} vs {}",
        az(5.0),
        az(6.0)
    );
    assert!(az(below) > az(5.0) + 1.0, "{} vs {}", az(below), az(5.0));
}
