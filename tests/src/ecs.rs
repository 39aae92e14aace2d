//! Shared by the `ecs_*` integration tests: the reference scenarios, direct
//! `fdm-core` runs to compare against, and bitwise views of states.

use fdm_core::bourg::{self, BourgAction, BourgAircraft, BourgControls, BourgState};
use fdm_core::palmer::{self, Flaps, PalmerAircraft, PalmerControls, PalmerState};
use fdm_core::script::Script;
use serde_json::Value;

/// Every bit of a Palmer state.
pub fn palmer_bits(s: &PalmerState) -> [u64; 7] {
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

/// Every bit of a Bourg state (the `stalling` flag as 0/1 at the end).
pub fn bourg_bits(s: &BourgState) -> Vec<u32> {
    let mut bits = Vec::with_capacity(20);
    for v in [
        &s.position_ft,
        &s.velocity_ftps,
        &s.velocity_body_ftps,
        &s.angular_velocity_radps,
        &s.euler_angles_deg(),
    ] {
        bits.extend(v.iter().map(|x| x.to_bits()));
    }
    bits.extend(s.orientation.coords.iter().map(|x| x.to_bits()));
    bits.push(s.speed_ftps().to_bits());
    bits.push(u32::from(s.stalling));
    bits
}

/// Every bit of a model state, as `u64`s (so `-0.0` and `0.0` differ and a
/// NaN equals itself): the one bit view the generic tests compare.
pub trait StateBits {
    /// The state's numbers as bit patterns, in a fixed order.
    fn state_bits(&self) -> Vec<u64>;
}

impl StateBits for PalmerState {
    fn state_bits(&self) -> Vec<u64> {
        palmer_bits(self).to_vec()
    }
}

impl StateBits for BourgState {
    /// [`bourg_bits`] plus the clock.
    fn state_bits(&self) -> Vec<u64> {
        let mut bits: Vec<u64> = bourg_bits(self).into_iter().map(u64::from).collect();
        bits.push(self.time_s.to_bits());
        bits
    }
}

/// Every bit of Bourg controls.
pub fn bourg_controls_bits(c: &BourgControls) -> (u32, u32, [i8; 3], bool) {
    (
        c.thrust_lb.to_bits(),
        c.rudder_deg.to_bits(),
        [
            c.port_aileron.code(),
            c.starboard_aileron.code(),
            c.elevators.code(),
        ],
        c.landing_flaps,
    )
}

/// One Palmer scenario of `reference/palmer.json`.
pub struct PalmerCase {
    /// The scenario's name in the reference file.
    pub name: String,
    /// The controls the scenario flies with (held for the whole run).
    pub controls: PalmerControls,
    /// Final state of the original C program: time, position, velocity
    /// (serde_json with `float_roundtrip` reads the decimals exactly).
    pub final_state: PalmerState,
}

fn f64s(v: &Value) -> Vec<f64> {
    v.as_array()
        .expect("array")
        .iter()
        .map(|x| x.as_f64().expect("number"))
        .collect()
}

/// `reference/palmer.json`: (fps, frames, cases).
pub fn palmer_reference() -> (u32, u64, Vec<PalmerCase>) {
    let text = crate::read_reference("palmer.json").expect("reference/palmer.json");
    let doc: Value = serde_json::from_str(&text).expect("palmer.json parses");
    let cases = doc["cases"]
        .as_array()
        .expect("cases")
        .iter()
        .map(|case| {
            let c = &case["controls"];
            let flaps = u8::try_from(c["flaps"].as_u64().expect("flaps")).expect("flaps fits");
            let fin = &case["final"];
            let (p, v) = (f64s(&fin["position"]), f64s(&fin["velocity"]));
            PalmerCase {
                name: case["name"].as_str().expect("name").to_owned(),
                controls: PalmerControls {
                    throttle: c["throttle"].as_f64().expect("throttle"),
                    alpha_deg: c["alpha"].as_f64().expect("alpha"),
                    bank_deg: c["bank"].as_f64().expect("bank"),
                    flaps: Flaps::from_degrees(flaps).expect("0, 20 or 40"),
                    brakes: false,
                },
                final_state: PalmerState {
                    time_s: fin["time_s"].as_f64().expect("time_s"),
                    position_m: [p[0], p[1], p[2]].into(),
                    velocity_mps: [v[0], v[1], v[2]].into(),
                },
            }
        })
        .collect();
    (
        u32::try_from(doc["fps"].as_u64().expect("fps")).expect("fps fits"),
        doc["frames"].as_u64().expect("frames"),
        cases,
    )
}

/// One Bourg scenario of `reference/bourg.json`.
pub struct BourgCase {
    /// The scenario's name in the reference file.
    pub name: String,
    /// The scenario's key presses as a script.
    pub script: Script<BourgAction>,
    /// The C++ build's final position, ft (exact f32 values).
    pub final_position_ft: [f32; 3],
    /// The C++ build's final raw Euler angles, degrees (exact f32 values).
    pub final_euler_deg: [f32; 3],
    /// The C++ build's final speed, ft/s (exact f32 value).
    pub final_speed_ftps: f32,
}

/// A reference number printed with 9 significant digits: exactly one f32.
fn f32_of(v: &Value) -> f32 {
    v.as_f64()
        .expect("number")
        .to_string()
        .parse()
        .expect("f32")
}

fn f32x3(v: &Value) -> [f32; 3] {
    let a = v.as_array().expect("array");
    [f32_of(&a[0]), f32_of(&a[1]), f32_of(&a[2])]
}

/// `reference/bourg.json`: (fps, frames, cases), scripts parsed with
/// `Script::<BourgAction>::parse` as `sim-cli` does.
pub fn bourg_reference() -> (u32, u64, Vec<BourgCase>) {
    let text = crate::read_reference("bourg.json").expect("reference/bourg.json");
    let doc: Value = serde_json::from_str(&text).expect("bourg.json parses");
    let cases = doc["cases"]
        .as_array()
        .expect("cases")
        .iter()
        .map(|case| {
            let lines: Vec<&str> = case["script"]
                .as_array()
                .expect("script")
                .iter()
                .map(|l| l.as_str().expect("line"))
                .collect();
            let fin = &case["cpp_final_full_precision"];
            BourgCase {
                name: case["name"].as_str().expect("name").to_owned(),
                script: Script::parse(&lines.join("\n")).expect("script parses"),
                final_position_ft: f32x3(&fin["position_ft"]),
                final_euler_deg: f32x3(&fin["euler_deg_raw"]),
                final_speed_ftps: f32_of(&fin["speed_ftps"]),
            }
        })
        .collect();
    (
        u32::try_from(doc["fps"].as_u64().expect("fps")).expect("fps fits"),
        doc["frames"].as_u64().expect("frames"),
        cases,
    )
}

/// Palmer flown directly with `fdm-core`: the states after frames 1..=frames.
pub fn palmer_direct(
    aircraft: &PalmerAircraft,
    controls: PalmerControls,
    start: PalmerState,
    dt_s: f64,
    frames: u64,
) -> Vec<PalmerState> {
    let mut state = start;
    (0..frames)
        .map(|_| {
            state = palmer::step(aircraft, &controls, &state, dt_s);
            state
        })
        .collect()
}

/// Bourg flown directly with `fdm-core` as the original's loop does
/// (neutralise, apply the frame's script actions, step): the controls and
/// states after frames 1..=frames.
pub fn bourg_direct(
    aircraft: &BourgAircraft,
    script: &Script<BourgAction>,
    start: (BourgControls, BourgState),
    dt_s: f32,
    frames: u64,
) -> Vec<(BourgControls, BourgState)> {
    let (mut controls, mut state) = start;
    (1..=frames)
        .map(|frame| {
            controls = controls.neutralize_surfaces();
            for action in script.actions_at(frame) {
                controls = controls.apply(action);
            }
            state = bourg::step(aircraft, &controls, &state, dt_s);
            (controls, state)
        })
        .collect()
}
