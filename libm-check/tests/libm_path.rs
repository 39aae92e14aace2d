//! fdm-core without `std`: its maths go through the pure-Rust `libm` crate
//! instead of the platform's (glibc's) libm. Run on the host:
//!
//! 1. the proof that this build really uses that path: every function of
//!    `fdm_core::math` returns the `libm` crate's bits on a sweep of inputs,
//!    and for some inputs those bits differ from glibc's (through `std`), so
//!    the facade cannot be calling `std`. The same sweep checks that each
//!    facade function is the function its name says (within 1 ulp of `std`'s),
//!    so a swapped mapping fails;
//! 2. the reference cases (`reference/palmer.json`, `reference/bourg.json`)
//!    under these maths, with measured tolerances (below): glibc's results
//!    are bit-exact with the original programs (fdm-core's own tests), the
//!    libm ones are not, and this says by how much.

use fdm_core::bourg::{step as bourg_step, BourgAction, BourgAircraft, BourgControls, BourgState};
use fdm_core::math;
use fdm_core::palmer::{step as palmer_step, Flaps, PalmerAircraft, PalmerControls, PalmerState};
use fdm_core::script::Script;
use serde_json::Value;

/// Distance in units in the last place between two finite f64 of one sign
/// (what the sweep needs).
fn ulps64(a: f64, b: f64) -> u64 {
    if a == b {
        return 0;
    }
    (a.to_bits() as i64).abs_diff(b.to_bits() as i64)
}

fn ulps32(a: f32, b: f32) -> u64 {
    if a == b {
        return 0;
    }
    u64::from((a.to_bits() as i32).abs_diff(b.to_bits() as i32))
}

/// SplitMix64: reproducible inputs.
fn inputs(n: usize, lo: f64, hi: f64) -> Vec<f64> {
    let mut s = 0x5eed_u64;
    (0..n)
        .map(|_| {
            s = s.wrapping_add(0x9e37_79b9_7f4a_7c15);
            let mut z = s;
            z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
            z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
            z ^= z >> 31;
            lo + (hi - lo) * ((z >> 11) as f64 / (1u64 << 53) as f64)
        })
        .collect()
}

#[test]
fn the_facade_is_the_libm_crate_and_each_function_is_itself() {
    type F1 = (
        &'static str,
        fn(f64) -> f64,
        fn(f64) -> f64,
        fn(f64) -> f64,
        f64,
        f64,
    );
    let one: [F1; 7] = [
        ("sqrt", math::sqrt, libm::sqrt, f64::sqrt, 0.0, 1e4),
        ("sin", math::sin, libm::sin, f64::sin, -10.0, 10.0),
        ("cos", math::cos, libm::cos, f64::cos, -10.0, 10.0),
        ("atan", math::atan, libm::atan, f64::atan, -50.0, 50.0),
        ("asin", math::asin, libm::asin, f64::asin, -1.0, 1.0),
        ("cbrt", math::cbrt, libm::cbrt, f64::cbrt, -1e3, 1e3),
        ("square", math::square, |x| x * x, |x| x.powi(2), -1e3, 1e3),
    ];
    type F2 = (
        &'static str,
        fn(f64, f64) -> f64,
        fn(f64, f64) -> f64,
        fn(f64, f64) -> f64,
    );
    let two: [F2; 3] = [
        ("pow", math::pow, libm::pow, f64::powf),
        ("atan2", math::atan2, libm::atan2, f64::atan2),
        ("hypot", math::hypot, libm::hypot, f64::hypot),
    ];
    type G1 = (
        &'static str,
        fn(f32) -> f32,
        fn(f32) -> f32,
        fn(f32) -> f32,
        f64,
        f64,
    );
    let single: [G1; 4] = [
        ("sqrtf", math::sqrtf, libm::sqrtf, f32::sqrt, 0.0, 1e4),
        ("sinf", math::sinf, libm::sinf, f32::sin, -10.0, 10.0),
        ("cosf", math::cosf, libm::cosf, f32::cos, -10.0, 10.0),
        ("asinf", math::asinf, libm::asinf, f32::asin, -1.0, 1.0),
    ];
    let n = 20_000;
    let mut differs_from_std = Vec::new();
    for (name, facade, crate_fn, std_fn, lo, hi) in one {
        let mut d = 0;
        for x in inputs(n, lo, hi) {
            let got = facade(x);
            assert_eq!(
                got.to_bits(),
                crate_fn(x).to_bits(),
                "{name}({x:e}): not libm's"
            );
            assert!(
                ulps64(got, std_fn(x)) <= 1,
                "{name}({x:e}) = {got:e}, std {:e}",
                std_fn(x)
            );
            d += usize::from(got.to_bits() != std_fn(x).to_bits());
        }
        differs_from_std.push((name, d));
    }
    let xs = inputs(n, -50.0, 50.0);
    let ys = inputs(n + 1, -50.0, 50.0);
    for (name, facade, crate_fn, std_fn) in two {
        let mut d = 0;
        for (&x, &y) in xs.iter().zip(&ys[1..]) {
            // pow: positive bases, moderate exponents (the model's use: 5.25).
            let (x, y) = if name == "pow" {
                (x.abs() + 0.5, y / 10.0)
            } else {
                (x, y)
            };
            let got = facade(x, y);
            assert_eq!(
                got.to_bits(),
                crate_fn(x, y).to_bits(),
                "{name}({x:e}, {y:e})"
            );
            assert!(
                ulps64(got, std_fn(x, y)) <= 1,
                "{name}({x:e}, {y:e}) = {got:e}, std {:e}",
                std_fn(x, y)
            );
            d += usize::from(got.to_bits() != std_fn(x, y).to_bits());
        }
        differs_from_std.push((name, d));
    }
    for (name, facade, crate_fn, std_fn, lo, hi) in single {
        let mut d = 0;
        for x in inputs(n, lo, hi) {
            let x = x as f32;
            let got = facade(x);
            assert_eq!(
                got.to_bits(),
                crate_fn(x).to_bits(),
                "{name}({x:e}): not libm's"
            );
            assert!(
                ulps32(got, std_fn(x)) <= 1,
                "{name}({x:e}) = {got:e}, std {:e}",
                std_fn(x)
            );
            d += usize::from(got.to_bits() != std_fn(x).to_bits());
        }
        differs_from_std.push((name, d));
    }
    {
        let mut d = 0;
        for (&x, &y) in xs.iter().zip(&ys[1..]) {
            let (x, y) = (x as f32, y as f32);
            let got = math::atan2f(x, y);
            assert_eq!(
                got.to_bits(),
                libm::atan2f(x, y).to_bits(),
                "atan2f({x:e}, {y:e})"
            );
            assert!(ulps32(got, x.atan2(y)) <= 1, "atan2f({x:e}, {y:e})");
            d += usize::from(got.to_bits() != x.atan2(y).to_bits());
        }
        differs_from_std.push(("atan2f", d));
    }
    eprintln!("inputs (of {n}) where the facade's bits differ from std's: {differs_from_std:?}");
    // The proof that this is not std's maths: some results differ from it.
    let total: usize = differs_from_std.iter().map(|(_, d)| d).sum();
    assert!(
        total > 0,
        "the facade gave std's bits everywhere: is `std` on?"
    );
}

// ------------------------------------------------------------ reference cases

fn reference(name: &str) -> Value {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../reference")
        .join(name);
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    // float_roundtrip: every decimal read correctly rounded.
    serde_json::from_str(&text).unwrap()
}

fn num(v: &Value) -> f64 {
    v.as_f64().unwrap_or_else(|| panic!("not a number: {v}"))
}

/// Palmer's four cases (600 RK4 steps of 0.1 s from rest) against the
/// original C program's final states (printed with 17 digits: exact f64).
/// Measured under libm: 4 of the 28 values differ from the C program's, by
/// at most 2.3e-13 (one ulp of 1428.7 m, case `everything`); tolerance
/// [`PALMER_TOLERANCE`].
#[test]
fn palmer_reference_cases_under_libm() {
    let doc = reference("palmer.json");
    let frames = doc["frames"].as_u64().unwrap();
    let dt = num(&doc["dt"]);
    let cessna = PalmerAircraft::cessna_172();
    let mut worst = (0.0_f64, String::new());
    let mut not_exact = 0;
    for case in doc["cases"].as_array().unwrap() {
        let name = case["name"].as_str().unwrap();
        let c = &case["controls"];
        let controls = PalmerControls {
            throttle: num(&c["throttle"]),
            alpha_deg: num(&c["alpha"]),
            bank_deg: num(&c["bank"]),
            flaps: Flaps::try_from(c["flaps"].as_u64().unwrap() as u8).unwrap(),
        };
        let mut state = PalmerState::at_rest();
        for _ in 0..frames {
            state = palmer_step(&cessna, &controls, &state, dt);
        }
        let fin = &case["final"];
        let pairs = (0..3)
            .map(|i| {
                (
                    format!("position[{i}]"),
                    state.position_m[i],
                    num(&fin["position"][i]),
                )
            })
            .chain((0..3).map(|i| {
                (
                    format!("velocity[{i}]"),
                    state.velocity_mps[i],
                    num(&fin["velocity"][i]),
                )
            }))
            .chain([(
                "airspeed".to_owned(),
                state.airspeed_mps(),
                num(&fin["airspeed"]),
            )]);
        for (what, got, want) in pairs {
            let e = (got - want).abs();
            not_exact += usize::from(got.to_bits() != want.to_bits());
            if e >= worst.0 {
                worst = (e, format!("{name} {what}: libm {got:?}, C {want:?}"));
            }
        }
    }
    eprintln!(
        "palmer under libm: largest difference {:e} ({}); {not_exact} of 28 values not bit-exact",
        worst.0, worst.1
    );
    assert!(
        worst.0 <= PALMER_TOLERANCE,
        "{:e} > {PALMER_TOLERANCE:e}: {}",
        worst.0,
        worst.1
    );
}

/// Bourg's five cases (900 Euler steps in f32) against the original C++
/// (full-precision finals: exact f32) and the thesis's printed numbers.
#[test]
fn bourg_reference_cases_under_libm() {
    let doc = reference("bourg.json");
    let aircraft = BourgAircraft::bourg_default();
    let dt = 1.0f32 / 30.0;
    let mut not_exact = 0;
    let mut report = Vec::new();
    for case in doc["cases"].as_array().unwrap() {
        let name = case["name"].as_str().unwrap();
        let lines: Vec<&str> = case["script"]
            .as_array()
            .unwrap()
            .iter()
            .map(|l| l.as_str().unwrap())
            .collect();
        let script = Script::<BourgAction>::parse(&lines.join("\n")).unwrap();
        let mut controls = BourgControls::initial();
        let mut state = BourgState::initial();
        for frame in 1..=900 {
            controls = controls.neutralize_surfaces();
            for a in script.actions_at(frame) {
                controls = controls.apply(a);
            }
            state = bourg_step(&aircraft, &controls, &state, dt);
        }
        let cpp = &case["cpp_final_full_precision"];
        let e = state.euler_angles_deg();
        let got = [
            state.position_ft.x,
            state.position_ft.y,
            state.position_ft.z,
            e.x,
            e.y,
            e.z,
            state.speed_ftps(),
        ];
        let want: Vec<f32> = cpp["position_ft"]
            .as_array()
            .unwrap()
            .iter()
            .chain(cpp["euler_deg_raw"].as_array().unwrap())
            .chain([&cpp["speed_ftps"]])
            .map(|v| num(v) as f32)
            .collect();
        let mut worst = 0.0_f64;
        for (g, w) in got.iter().zip(&want) {
            not_exact += usize::from(g.to_bits() != w.to_bits());
            worst = worst.max((f64::from(*g) - f64::from(*w)).abs());
        }
        report.push((name.to_owned(), worst));
    }
    eprintln!("bourg under libm, largest |difference| from the C++ per case: {report:?}; {not_exact} of 35 values not bit-exact");
    for (name, worst) in &report {
        let tol = if name == "pitch" {
            BOURG_PITCH_TOLERANCE
        } else {
            BOURG_TOLERANCE
        };
        assert!(*worst <= tol, "{name}: {worst:e} > {tol:e}");
    }
    // Under glibc these 35 values are bit-exact (fdm-core/tests/bourg_reference.rs);
    // under libm some are not: a second sign that this is the libm path.
    assert!(not_exact > 0);
}

/// Palmer under libm, absolute (m, m/s): measured 2.3e-13 (one ulp); the
/// RK4 steps are smooth, so last-bit differences in `sin`/`cos`/`pow` stay
/// last-bit. Ten ulps of the largest value, still 1e5 times below the
/// thesis's own bar (1e-6).
const PALMER_TOLERANCE: f64 = 1e-11;
/// Bourg under libm, absolute (ft, degrees, ft/s), cases `no_controls`,
/// `roll`, `yaw`, `flaps`: measured 8.1e-5, 1.13e-3, 2.4e-4, 6.6e-4
/// (26 of the 35 final values are not bit-exact: `sinf`, `asinf`, `atan2`
/// differ in the last bit for some inputs and 900 Euler steps carry it).
/// Within the thesis's bar of 0.01; tolerance about twice the worst.
const BOURG_TOLERANCE: f64 = 2.5e-3;
/// Bourg's `pitch` case (elevators held up for 900 frames: a sensitive
/// trajectory) under libm: measured 0.0935 ft (y). This **misses** the
/// thesis's 0.01 bar, as docs/bourg-model.md says; the tolerance bounds the
/// measured drift with about 50 % margin.
const BOURG_PITCH_TOLERANCE: f64 = 0.15;
