//! The `f64` instantiation of the Bourg model against the `f32` one.
//!
//! Both models share the original's `float` constants and data (the `f64`
//! model widens them exactly), so they differ only in the rounding of the
//! arithmetic: the `f64` model is the C++ with every `float` variable turned
//! into a `double`.

use fdm_core::bourg::{
    step, AircraftOf, BourgAction, BourgControlsOf, BourgFloat, BourgState, BourgState64,
    BourgStateOf,
};
use fdm_core::script::Script;

fn run<F: BourgFloat>(script: &str, frames: u64, dt: F) -> BourgStateOf<F> {
    let script = Script::<BourgAction>::parse(script).unwrap();
    let aircraft = AircraftOf::<F>::bourg_default();
    let mut controls = BourgControlsOf::<F>::initial();
    let mut state = BourgStateOf::<F>::initial();
    for frame in 1..=frames {
        controls = controls.neutralize_surfaces();
        for action in script.actions_at(frame) {
            controls = controls.apply(action);
        }
        state = step(&aircraft, &controls, &state, dt);
    }
    state
}

/// x, y, z (ft), roll, pitch up, yaw (deg), speed (kt).
fn outputs32(s: &BourgState) -> [f64; 7] {
    [
        f64::from(s.position_ft.x),
        f64::from(s.position_ft.y),
        f64::from(s.position_ft.z),
        f64::from(s.euler_angles_deg().x),
        -f64::from(s.euler_angles_deg().y),
        f64::from(s.euler_angles_deg().z),
        f64::from(s.speed_ftps()) / 1.688,
    ]
}

fn outputs64(s: &BourgState64) -> [f64; 7] {
    [
        s.position_ft.x,
        s.position_ft.y,
        s.position_ft.z,
        s.euler_angles_deg().x,
        -s.euler_angles_deg().y,
        s.euler_angles_deg().z,
        s.speed_ftps() / 1.688,
    ]
}

/// No controls, 300 frames (10 s): a gentle glide from (−5000, 0, 2000) ft.
///
/// Expected magnitude: x runs from −5000 to −3969 ft, where an `f32` has an
/// ulp of 4.9e-4 ft (2.4e-4 below 4096), so each `position += velocity * dt`
/// rounds by up to 2.4e-4 ft; 300 such roundings, mostly uncorrelated, add up
/// to about sqrt(300) · 1.4e-4 ≈ 2.4e-3 ft (the velocity's own rounding, a few
/// 1e-6 ft/s per step, contributes less).
/// Attitude and speed come from quantities of order 1 and 100 with relative
/// rounding ~6e-8 per operation: a few 1e-5 degrees and knots after 300 steps.
/// Measured: x 2.1e-3, y 2.0e-5, z 6.6e-4 ft; roll 1.5e-6, pitch 4.3e-5,
/// yaw 2.0e-6 deg; speed 2.5e-5 kt. Asserted: 1e-2 ft and 1e-3 deg/kt, about
/// five times the estimate.
#[test]
fn f32_and_f64_agree_on_a_gentle_glide() {
    let a = outputs32(&run::<f32>("", 300, 1.0f32 / 30.0));
    let b = outputs64(&run::<f64>("", 300, 1.0f64 / 30.0));
    let names = ["x", "y", "z", "roll", "pitch_up", "yaw", "speed_kt"];
    let bounds = [1e-2, 1e-2, 1e-2, 1e-3, 1e-3, 1e-3, 1e-3];
    for i in 0..7 {
        let err = (a[i] - b[i]).abs();
        println!("{}: f32 {} f64 {} |diff| {err:e}", names[i], a[i], b[i]);
        assert!(
            err <= bounds[i],
            "{}: |f32 - f64| = {err} > {}",
            names[i],
            bounds[i]
        );
    }
    // The f64 model really is computed in f64: its x differs from the f32 one
    // by more than two f32 ulps of x at 3969 ft (2 × 2.4e-4 ft).
    assert!((a[0] - b[0]).abs() > 4.9e-4, "x: f64 run equals f32 run");
}

/// A rebuild of the C++ with every float a double still meets 0.01 on four
/// of the five reference cases but misses the pitch case by 0.09 ft
/// (docs/bourg-model.md, "Exactness"). The f64 model reproduces exactly that (measured: largest error
/// 0.0069 on the four cases, pitch case y off by 0.0898 ft).
#[test]
fn f64_model_meets_the_thesis_bar_on_four_cases_and_misses_pitch_by_0_09_ft() {
    let text = fdm_tests::read_reference("bourg.json").unwrap();
    let reference: serde_json::Value = serde_json::from_str(&text).unwrap();
    let keys = [
        "x_ft",
        "y_ft",
        "z_ft",
        "roll_deg",
        "pitch_up_deg",
        "yaw_deg",
        "speed_kt",
    ];
    for case in reference["cases"].as_array().unwrap() {
        let name = case["name"].as_str().unwrap();
        let script: Vec<&str> = case["script"]
            .as_array()
            .unwrap()
            .iter()
            .map(|l| l.as_str().unwrap())
            .collect();
        let got = outputs64(&run::<f64>(&script.join("\n"), 900, 1.0 / 30.0));
        let errors: Vec<f64> = keys
            .iter()
            .zip(got)
            .map(|(k, g)| (g - case["thesis_expected"][k].as_f64().unwrap()).abs())
            .collect();
        println!("{name}: f64 errors vs thesis {errors:.4?}");
        if name == "pitch" {
            let y = errors[1];
            assert!((0.085..0.095).contains(&y), "pitch y error {y}");
            for (k, e) in keys.iter().zip(&errors) {
                if *k != "y_ft" {
                    assert!(*e <= 0.01, "pitch {k}: {e}");
                }
            }
        } else {
            for (k, e) in keys.iter().zip(&errors) {
                assert!(*e <= 0.01, "{name} {k}: {e}");
            }
        }
    }
}
