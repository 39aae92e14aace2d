//! fdm-core without `std` (the build an embedded target gets), run on the
//! host: its maths (`fdm_core::math`, pure Rust in every build) give the
//! reference cases the original programs' bits, exactly as the `std` build
//! does (fdm-core's own tests).
//!
//! 1. The functions the reference cases depend on give x86-64 glibc 2.36's
//!    bits: `pow` and `asinf` on sweeps of inputs (compared with `std`'s,
//!    which is glibc, when the host is x86-64 glibc), `sqrt`/`sqrtf` and
//!    `fma` everywhere (correctly rounded); the functions taken from the
//!    `libm` crate are that crate's.
//! 2. Palmer's four cases and Bourg's five: every final value bit-identical to
//!    the original programs' (Bourg's `pitch` case too, which drifted 0.0935 ft
//!    when this build used the `libm` crate's `asinf`, `sinf` and `cosf`).

use fdm_core::bourg::{step as bourg_step, BourgAction, BourgAircraft, BourgControls, BourgState};
use fdm_core::math;
use fdm_core::palmer::{step as palmer_step, Flaps, PalmerAircraft, PalmerControls, PalmerState};
use fdm_core::script::Script;
use serde_json::Value;

/// SplitMix64: reproducible inputs in `[lo, hi)`.
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

/// True where `std`'s maths are x86-64 glibc's, the platform the reference
/// bits come from.
const GLIBC_X86_64: bool = cfg!(all(
    target_arch = "x86_64",
    target_os = "linux",
    target_env = "gnu"
));

#[test]
fn pow_and_asinf_are_glibcs_and_the_rest_are_the_libm_crates() {
    let n = 200_000;
    let xs = inputs(n, 0.5, 1.05);
    let ys = inputs(n + 1, -20.0, 20.0);
    for (&x, &y) in xs.iter().zip(&ys[1..]) {
        if GLIBC_X86_64 {
            assert_eq!(
                math::pow(x, 5.25).to_bits(),
                x.powf(5.25).to_bits(),
                "pow({x:e}, 5.25)"
            );
            let x = x * 80.0;
            assert_eq!(
                math::pow(x, y).to_bits(),
                x.powf(y).to_bits(),
                "pow({x:e}, {y:e})"
            );
        }
        assert_eq!(math::sqrt(x).to_bits(), x.sqrt().to_bits());
        assert_eq!(math::fma(x, y, -x).to_bits(), x.mul_add(y, -x).to_bits());
    }
    for x in inputs(n, -1.0, 1.0) {
        let x = x as f32;
        if GLIBC_X86_64 {
            assert_eq!(math::asinf(x).to_bits(), x.asin().to_bits(), "asinf({x:e})");
        }
        assert_eq!(math::sqrtf(x.abs()).to_bits(), x.abs().sqrt().to_bits());
    }
    type F1 = (&'static str, fn(f64) -> f64, fn(f64) -> f64);
    let one: [F1; 7] = [
        ("sin", math::sin, libm::sin),
        ("cos", math::cos, libm::cos),
        ("atan", math::atan, libm::atan),
        ("asin", |x| math::asin(x / 4.0), |x| libm::asin(x / 4.0)),
        ("cbrt", math::cbrt, libm::cbrt),
        (
            "sinf",
            |x| f64::from(math::sinf(x as f32)),
            |x| f64::from(libm::sin(f64::from(x as f32)) as f32),
        ),
        (
            "cosf",
            |x| f64::from(math::cosf(x as f32)),
            |x| f64::from(libm::cos(f64::from(x as f32)) as f32),
        ),
    ];
    for (name, ours, theirs) in one {
        for x in inputs(20_000, -4.0, 4.0) {
            assert_eq!(ours(x).to_bits(), theirs(x).to_bits(), "{name}({x:e})");
        }
    }
    for (&x, &y) in xs.iter().zip(&ys[1..]).take(20_000) {
        assert_eq!(
            math::atan2(y, x - 0.8).to_bits(),
            libm::atan2(y, x - 0.8).to_bits()
        );
        assert_eq!(math::hypot(y, x).to_bits(), libm::hypot(y, x).to_bits());
    }
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
/// original C program's final states (printed with 17 digits: exact f64):
/// all 28 values equal.
#[test]
fn palmer_reference_cases_are_bit_exact_without_std() {
    let doc = reference("palmer.json");
    let frames = doc["frames"].as_u64().unwrap();
    let dt = num(&doc["dt"]);
    let cessna = PalmerAircraft::cessna_172();
    let mut compared = 0;
    for case in doc["cases"].as_array().unwrap() {
        let name = case["name"].as_str().unwrap();
        let c = &case["controls"];
        let controls = PalmerControls {
            throttle: num(&c["throttle"]),
            alpha_deg: num(&c["alpha"]),
            bank_deg: num(&c["bank"]),
            flaps: Flaps::try_from(c["flaps"].as_u64().unwrap() as u8).unwrap(),
            // Our extension; off, the step is the original's.
            brakes: false,
        };
        let mut state = PalmerState::at_rest();
        for _ in 0..frames {
            state = palmer_step(&cessna, &controls, &state, dt);
        }
        let fin = &case["final"];
        let mut pairs: Vec<(String, f64, f64)> = (0..3)
            .map(|i| {
                (
                    format!("position[{i}]"),
                    state.position_m[i],
                    num(&fin["position"][i]),
                )
            })
            .collect();
        pairs.extend((0..3).map(|i| {
            (
                format!("velocity[{i}]"),
                state.velocity_mps[i],
                num(&fin["velocity"][i]),
            )
        }));
        pairs.push((
            "airspeed".to_owned(),
            state.airspeed_mps(),
            num(&fin["airspeed"]),
        ));
        for (what, got, want) in pairs {
            // `==`: the reference's 0 for y is +0.0, the model's may be -0.0.
            assert!(got == want, "{name} {what}: {got:?}, C {want:?}");
            compared += 1;
        }
    }
    assert_eq!(compared, 28);
}

/// Bourg's five cases (900 Euler steps in f32) against the original C++
/// (full-precision finals: exact f32): all 35 values bit-identical, the
/// `pitch` case included.
#[test]
fn bourg_reference_cases_are_bit_exact_without_std() {
    let doc = reference("bourg.json");
    let aircraft = BourgAircraft::bourg_default();
    let dt = 1.0f32 / 30.0;
    let mut compared = 0;
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
        for (i, (g, w)) in got.iter().zip(&want).enumerate() {
            assert_eq!(g.to_bits(), w.to_bits(), "{name} #{i}: {g:?}, C++ {w:?}");
            compared += 1;
        }
    }
    assert_eq!(compared, 35);
}
