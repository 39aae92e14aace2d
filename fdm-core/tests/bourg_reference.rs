//! Equivalence of the `f32` Bourg model with the original C++ program, on the
//! five thesis scenarios of `reference/bourg.json`.
//!
//! Each case runs 900 frames at `dt = 1.0f32 / 30.0`, driven by the case's
//! script through the same parser as `sim-cli` (`Script::<BourgAction>::parse`):
//! every frame the surfaces are neutralised, the frame's actions applied in
//! file order, then the model stepped.
//!
//! Three bars:
//! * the thesis's own bar: 0.01 absolute on x, y, z (ft), roll, pitch up, yaw
//!   (deg) and speed (kt) against the numbers printed in the thesis (6
//!   significant digits, from the original build);
//! * the C++ rebuilt here at full f32 precision (g++, glibc, no FMA): the
//!   final state and 13 checkpoints per case are printed with 9 significant
//!   digits, which round-trip f32 exactly, so the comparison is exact `f32`
//!   equality (0 ulp);
//! * bit-exact early-frame values (frames 1..5 and 50): exact `f32` equality.

use fdm_core::bourg::{step, BourgAction, BourgAircraft, BourgControls, BourgState};
use fdm_core::script::Script;
use serde_json::Value;

const FRAMES: u64 = 900;

fn reference() -> Value {
    let text = fdm_tests::read_reference("bourg.json").expect("reference/bourg.json");
    serde_json::from_str(&text).expect("bourg.json parses")
}

/// States after frames 1..=`frames` (index 0 is frame 1).
fn run(script_lines: &[&str], frames: u64) -> Vec<(BourgControls, BourgState)> {
    let script = Script::<BourgAction>::parse(&script_lines.join("\n")).expect("script parses");
    let aircraft = BourgAircraft::bourg_default();
    let dt = 1.0f32 / 30.0;
    let mut controls = BourgControls::initial();
    let mut state = BourgState::initial();
    let mut out = Vec::with_capacity(usize::try_from(frames).unwrap());
    for frame in 1..=frames {
        controls = controls.neutralize_surfaces();
        for action in script.actions_at(frame) {
            controls = controls.apply(action);
        }
        state = step(&aircraft, &controls, &state, dt);
        out.push((controls, state));
    }
    out
}

fn case_script(case: &Value) -> Vec<&str> {
    case["script"]
        .as_array()
        .unwrap()
        .iter()
        .map(|l| l.as_str().unwrap())
        .collect()
}

fn f32_of(v: &Value) -> f32 {
    // The reference prints f32 values with 9 significant digits: parsing the
    // decimal as f32 recovers the exact value.
    v.as_f64()
        .map(|x| x.to_string())
        .unwrap()
        .parse::<f32>()
        .unwrap()
}

/// The reference's outputs of a state: x, y, z, roll, pitch up, yaw, speed (kt,
/// the C++'s `speed / 1.688f`).
fn outputs(state: &BourgState) -> [f64; 7] {
    [
        f64::from(state.position_ft.x),
        f64::from(state.position_ft.y),
        f64::from(state.position_ft.z),
        f64::from(state.euler_angles_deg().x),
        -f64::from(state.euler_angles_deg().y),
        f64::from(state.euler_angles_deg().z),
        f64::from(state.speed_ftps() / 1.688f32),
    ]
}

const OUTPUT_NAMES: [&str; 7] = ["x", "y", "z", "roll", "pitch_up", "yaw", "speed_kt"];

/// Distance in f32 units in the last place (0 for equal values, also ±0).
fn ulps(a: f32, b: f32) -> u64 {
    fn key(x: f32) -> i64 {
        let bits = i64::from(x.to_bits() as i32);
        if bits < 0 {
            i64::from(i32::MIN) - bits
        } else {
            bits
        }
    }
    key(a).abs_diff(key(b))
}

#[test]
fn thesis_numbers_within_the_thesis_tolerance() {
    let reference = reference();
    let tolerance = reference["thesis_tolerance_abs"].as_f64().unwrap();
    assert_eq!(tolerance, 0.01);
    let mut worst = (0.0f64, String::new());
    for case in reference["cases"].as_array().unwrap() {
        let name = case["name"].as_str().unwrap();
        let states = run(&case_script(case), FRAMES);
        let got = outputs(&states.last().unwrap().1);
        let expected = &case["thesis_expected"];
        let keys = [
            "x_ft",
            "y_ft",
            "z_ft",
            "roll_deg",
            "pitch_up_deg",
            "yaw_deg",
            "speed_kt",
        ];
        for (key, got) in keys.iter().zip(got) {
            let want = expected[key].as_f64().unwrap();
            let err = (got - want).abs();
            if err > worst.0 {
                worst = (err, format!("{name} {key}: got {got}, thesis {want}"));
            }
            assert!(
                err <= tolerance,
                "{name} {key}: got {got}, thesis {want}, error {err} > {tolerance}"
            );
        }
    }
    println!(
        "largest error vs the thesis's printed numbers: {} ({})",
        worst.0, worst.1
    );
}

#[test]
fn early_frames_are_bit_exact() {
    let reference = reference();
    let early = &reference["early_frames_bit_exact"];
    let scenarios: [(&str, &[&str]); 2] = [
        ("no_controls", &[]),
        ("thrust_up_frames_1_to_5", &["1-5 thrust-up"]),
    ];
    let mut checked = 0;
    for (name, script) in scenarios {
        let states = run(script, 50);
        let frames = early[name].as_object().expect(name);
        for (frame, values) in frames {
            let frame: usize = frame.parse().unwrap();
            let state = &states[frame - 1].1;
            for (key, want) in values.as_object().unwrap() {
                let got = match key.as_str() {
                    "x" => state.position_ft.x,
                    "z" => state.position_ft.z,
                    "vx" => state.velocity_ftps.x,
                    other => panic!("unexpected key {other}"),
                };
                let want = want.as_f64().unwrap();
                assert_eq!(
                    f64::from(got).to_bits(),
                    want.to_bits(),
                    "{name} frame {frame} {key}: got {got:?}, C++ {want:?}"
                );
                checked += 1;
            }
        }
    }
    assert_eq!(checked, 19, "every early-frame value was compared");
}

#[test]
fn final_states_match_the_full_precision_cpp_exactly() {
    let reference = reference();
    let mut report = Vec::new();
    let mut worst_ulps = 0;
    for case in reference["cases"].as_array().unwrap() {
        let name = case["name"].as_str().unwrap();
        let (controls, state) = *run(&case_script(case), FRAMES).last().unwrap();
        let cpp = &case["cpp_final_full_precision"];
        let got = [
            state.position_ft.x,
            state.position_ft.y,
            state.position_ft.z,
            state.euler_angles_deg().x,
            state.euler_angles_deg().y,
            state.euler_angles_deg().z,
            state.speed_ftps(),
        ];
        let want: Vec<f32> = cpp["position_ft"]
            .as_array()
            .unwrap()
            .iter()
            .chain(cpp["euler_deg_raw"].as_array().unwrap())
            .chain(core::iter::once(&cpp["speed_ftps"]))
            .map(f32_of)
            .collect();
        let names = ["x", "y", "z", "euler.x", "euler.y", "euler.z", "speed"];
        for ((n, g), w) in names.iter().zip(got).zip(&want) {
            let u = ulps(g, *w);
            worst_ulps = worst_ulps.max(u);
            report.push(format!(
                "{name} {n}: got {g:?}, C++ {w:?}, |err| {:e}, {u} ulp",
                (f64::from(g) - f64::from(*w)).abs()
            ));
        }
        assert_eq!(
            controls.thrust_lb,
            f32_of(&cpp["thrust_lb"]),
            "{name} thrust"
        );
        assert_eq!(
            controls.landing_flaps,
            cpp["flaps"].as_bool().unwrap(),
            "{name} flaps"
        );
        assert_eq!(
            state.stalling,
            cpp["stalling"].as_bool().unwrap(),
            "{name} stalling"
        );
    }
    println!("{}", report.join("\n"));
    println!("largest difference from the full-precision C++ finals: {worst_ulps} ulp");
    assert_eq!(
        worst_ulps,
        0,
        "final states differ from the C++:\n{}",
        report.join("\n")
    );
}

#[test]
fn checkpoints_match_the_full_precision_cpp_exactly() {
    let reference = reference();
    let mut worst = (0u64, 0.0f64, String::new());
    let mut compared = 0;
    for case in reference["cases"].as_array().unwrap() {
        let name = case["name"].as_str().unwrap();
        let states = run(&case_script(case), FRAMES);
        for checkpoint in case["cpp_checkpoints"].as_array().unwrap() {
            let frame = usize::try_from(checkpoint["frame"].as_u64().unwrap()).unwrap();
            let state = &states[frame - 1].1;
            let pos = checkpoint["position_ft"].as_array().unwrap();
            // pitch up is the exact negation of euler.y; speed_kt is the C++'s
            // `speed / 1.688f` in float.
            let got: [f32; 7] = [
                state.position_ft.x,
                state.position_ft.y,
                state.position_ft.z,
                state.euler_angles_deg().x,
                -state.euler_angles_deg().y,
                state.euler_angles_deg().z,
                state.speed_ftps() / 1.688f32,
            ];
            let want = [
                f32_of(&pos[0]),
                f32_of(&pos[1]),
                f32_of(&pos[2]),
                f32_of(&checkpoint["roll_deg"]),
                f32_of(&checkpoint["pitch_up_deg"]),
                f32_of(&checkpoint["yaw_deg"]),
                f32_of(&checkpoint["speed_kt"]),
            ];
            for (i, (g, w)) in got.iter().zip(want).enumerate() {
                let u = ulps(*g, w);
                let abs = (f64::from(*g) - f64::from(w)).abs();
                if u > worst.0 || (u == worst.0 && abs > worst.1) {
                    worst = (
                        u,
                        abs,
                        format!(
                            "{name} frame {frame} {}: got {g:?}, C++ {w:?}",
                            OUTPUT_NAMES[i]
                        ),
                    );
                }
                compared += 1;
            }
        }
    }
    println!(
        "{compared} checkpoint values; largest difference from the C++: {} ulp, {:e} ({})",
        worst.0, worst.1, worst.2
    );
    assert_eq!(compared, 5 * 13 * 7);
    assert_eq!(worst.0, 0, "checkpoint differs: {}", worst.2);
}
